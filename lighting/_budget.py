"""The work and memory budget: requests estimate their peak memory and are refused above it, before allocating.

The command line's ``--memory-budget`` sets it (:func:`set_memory_budget`); every allocation-heavy entry point
calls :func:`check_budget` with its estimate.  The names are also importable from :mod:`lighting._numeric`.
"""

from __future__ import annotations

from ._numeric import check_count

__all__ = ["DEFAULT_MEMORY_BUDGET", "BudgetError", "memory_budget", "set_memory_budget", "check_budget"]

#: Default budget for one allocation-heavy request (an image, a sample set, a mesh), in bytes.
DEFAULT_MEMORY_BUDGET = 2 * 1024**3
_memory_budget = [DEFAULT_MEMORY_BUDGET]


def memory_budget() -> int:
    """The memory budget in force, in bytes (2 GiB unless :func:`set_memory_budget` raised it).

    Returns
    -------
    int
        The budget in bytes.
    """
    return _memory_budget[0]


def set_memory_budget(nbytes: int) -> int:
    """Set the memory budget (bytes); returns the previous one.  The command line's ``--memory-budget``.

    Parameters
    ----------
    nbytes : int
        The new budget in bytes, an integer >= 1.

    Returns
    -------
    int
        The budget in force before the call, in bytes.

    Raises
    ------
    ValueError
        For ``nbytes < 1`` (``ArgumentTypeError`` for a value that is not an integer).
    """
    previous = _memory_budget[0]
    _memory_budget[0] = check_count("memory budget", nbytes, 1)
    return previous


def _bytes(n: float) -> str:
    for unit, size in (("GiB", 1024**3), ("MiB", 1024**2), ("KiB", 1024)):
        if n >= size:
            return f"{n / size:.1f} {unit}"
    return f"{int(n)} bytes"


class BudgetError(ValueError):
    """A request whose estimated memory is over the budget (a ValueError, so callers catch it as bad input)."""


def check_budget(name: str, estimate_bytes: float, *, what: str = "", budget: int | None = None) -> None:
    """Refuse a request whose estimated memory exceeds the budget, naming ``name`` and the estimate.

    Call it *before* allocating, with an estimate of the peak bytes the request needs.

    Parameters
    ----------
    name : str
        What the request is, for the error message (the arguments that set its size).
    estimate_bytes : float
        The estimated peak memory in bytes; NaN is refused like an estimate over the budget.
    what : str, optional
        A detail shown in parentheses after the estimate (``"1000 shading points"``).
    budget : int or None, optional
        The limit in bytes; ``None`` (default): :func:`memory_budget`.

    Raises
    ------
    BudgetError
        Where ``estimate_bytes`` is not <= the limit.
    """
    limit = memory_budget() if budget is None else budget
    if not estimate_bytes <= limit:  # also refuses NaN estimates
        detail = f" ({what})" if what else ""
        raise BudgetError(
            f"{name} needs about {_bytes(float(estimate_bytes))}{detail}, over the memory budget of "
            f"{_bytes(limit)}; reduce it or raise the budget (--memory-budget)"
        )

"""Words in messages: a count with its noun in the right number (``1 light``, ``2 lights``)."""

from __future__ import annotations

__all__ = ["plural"]

#: Nouns whose plural is not the noun with ``s``.
_IRREGULAR = {"entry": "entries", "index": "indices", "vertex": "vertices", "process": "processes"}


def plural(count: int, noun: str, plural_form: str | None = None) -> str:
    """``count`` and ``noun``, the noun plural unless the count is one: ``"1 light"``, ``"2 lights"``, ``"0 lights"``.

    Parameters
    ----------
    count : int
        How many.
    noun : str
        The noun in the singular.
    plural_form : str, optional
        The plural, when it is not ``noun + "s"`` and not one of the few irregular nouns known here.

    Returns
    -------
    str
        ``f"{count} {noun}"`` in the right number.

    Examples
    --------
    >>> plural(1, "light"), plural(2, "light"), plural(0, "object"), plural(3, "entry")
    ('1 light', '2 lights', '0 objects', '3 entries')
    >>> plural(2, "dtype"), plural(1, "part"), plural(4, "datum", "data")
    ('2 dtypes', '1 part', '4 data')
    """
    if count == 1:
        return f"{count} {noun}"
    return f"{count} {plural_form or _IRREGULAR.get(noun, noun + 's')}"

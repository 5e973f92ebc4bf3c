"""Argument checks for the engine's public entry points (constructors, loaders, public functions).

Every boundary checks its arguments once through these helpers, so that every illegal argument gets the
same kind of answer: ValueError (:class:`ArgumentTypeError`, also a TypeError, for a wrong type) whose
message names the parameter, the value given (abbreviated, :func:`lighting._text.quote`) and what is
allowed.  Inner code trusts what a boundary has checked.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from ._text import quote
from .numerics import working_dtype

__all__ = [
    "ArgumentTypeError",
    "real_array",
    "check_vectors",
    "check_count",
    "check_bool",
    "check_range",
    "check_finite",
    "check_color",
    "check_positive",
    "check_nonnegative",
    "check_choice",
    "check_float_dtype",
]


class ArgumentTypeError(TypeError, ValueError):
    """A wrong type for an argument: a TypeError, and a ValueError too, so that callers that catch bad
    input as ValueError (the command line, scene loading) catch it as well."""


def _is_text(value) -> bool:
    """Strings and bytes, alone or inside an array: NumPy would parse them as numbers."""
    if isinstance(value, (str, bytes, bytearray)):
        return True
    if isinstance(value, np.ndarray):
        return value.dtype.kind in "SUO" and any(isinstance(x, (str, bytes)) for x in value.flat)
    if isinstance(value, (list, tuple)):
        return any(_is_text(x) for x in value)
    return False


def real_array(name: str, value, *, allowed: str = "finite real numbers", dtype=None) -> np.ndarray:
    """``value`` as a real float array; TypeError for text, complex, None or objects; ValueError for NaN/inf.

    ``dtype=None`` keeps a NumPy float input's dtype (float64 otherwise), as the dtype policy asks.

    Parameters
    ----------
    name : str
        The parameter's name, for the error message.
    value : array_like
        Real numbers (integer or float), any shape.  Booleans, complex numbers, text, None, dicts,
        sets and objects are refused.
    allowed : str, optional
        What the error message says is allowed.
    dtype : dtype or type, optional
        The result's dtype; ``None``: :func:`working_dtype` of ``value`` (float32 for a float32 or
        float16 array, float64 otherwise).

    Returns
    -------
    ndarray
        ``value`` in that dtype, same shape (0-d for a scalar), every entry finite; no copy when it
        already has the dtype.

    Raises
    ------
    ArgumentTypeError
        For a refused type.
    ValueError
        For NaN or infinite entries, also those that overflow ``dtype`` on conversion.
    """
    if value is None or _is_text(value) or isinstance(value, (dict, set)):
        raise ArgumentTypeError(f"{name} must be {allowed}; got {type(value).__name__} {quote(value)}")
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"{name} must be {allowed}; got {type(value).__name__} {quote(value)}") from None
    if arr.dtype.kind == "b" or arr.dtype.kind not in "fiu":
        raise ArgumentTypeError(f"{name} must be {allowed}; got {arr.dtype} {quote(value)}")
    dt = dtype if dtype is not None else working_dtype(arr)
    with np.errstate(over="ignore"):
        out = arr.astype(dt, copy=False)
    if not np.all(np.isfinite(out)):
        raise ValueError(f"{name} must be {allowed} (finite in {np.dtype(dt).name}); got {quote(value)}")
    return out


def check_vectors(name: str, value, *, dtype=None, nonzero: bool = False) -> np.ndarray:
    """Directions or points of shape ``(..., 3)``: real, finite, and (``nonzero``) of non-zero length.

    Parameters
    ----------
    name : str
        The parameter's name, for the error message.
    value : array_like, shape (..., 3)
        Real vectors, as :func:`real_array` accepts them.
    dtype : dtype or type, optional
        As :func:`real_array` (``None``: the float dtype of ``value``).
    nonzero : bool, optional
        Refuse any vector whose entries are all 0.

    Returns
    -------
    ndarray, shape (..., 3)
        ``value`` in that dtype, every entry finite.

    Raises
    ------
    ValueError
        For a last axis other than 3, a zero vector when ``nonzero``, or what :func:`real_array`
        refuses (``ArgumentTypeError`` for a wrong type).
    """
    allowed = "finite real vectors of shape (..., 3)" + (" and non-zero length" if nonzero else "")
    arr = real_array(name, value, allowed=allowed, dtype=dtype)
    if arr.shape[-1:] != (3,):
        raise ValueError(f"{name} must be {allowed}; got shape {arr.shape}: {quote(value)}")
    if nonzero and arr.size:
        big = np.max(np.abs(arr), axis=-1)
        if np.any(big == 0):
            raise ValueError(f"{name} must be {allowed}; got a zero vector: {quote(value)}")
    return arr


def check_count(name: str, value, lo: int = 1, hi: int | None = None) -> int:
    """An integer in ``[lo, hi]`` (a bool, a float or text is refused with TypeError).

    Parameters
    ----------
    name : str
        The parameter's name, for the error message.
    value : int
        A Python or NumPy integer.
    lo : int, optional
        The smallest allowed value (default 1).
    hi : int or None, optional
        The largest allowed value; ``None`` (default): no upper bound.

    Returns
    -------
    int
        ``value`` as a Python ``int``.

    Raises
    ------
    ArgumentTypeError
        For a value that is not an integer.
    ValueError
        For an integer outside ``[lo, hi]``.
    """
    allowed = f"an integer >= {lo}" if hi is None else f"an integer in [{lo}, {hi}]"
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Integral, np.integer)):
        raise ArgumentTypeError(f"{name} must be {allowed}; got {type(value).__name__} {quote(value)}")
    v = int(value)
    if v < lo or (hi is not None and v > hi):
        raise ValueError(f"{name} must be {allowed}; got {quote(v)}")
    return v


def check_bool(name: str, value) -> bool:
    """A real bool (``True``/``False`` or a NumPy bool), not a number or a string.

    Parameters
    ----------
    name : str
        The parameter's name, for the error message.
    value : bool
        ``True``, ``False`` or a NumPy bool.

    Returns
    -------
    bool
        ``value`` as a Python ``bool``.

    Raises
    ------
    ArgumentTypeError
        For anything else (``0``, ``1``, ``"yes"`` …).
    """
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise ArgumentTypeError(f"{name} must be True or False; got {type(value).__name__} {quote(value)}")


def check_range(name: str, value, lo: float | None = None, hi: float | None = None, *,
                lo_open: bool = False, hi_open: bool = False) -> float:
    """A finite real scalar inside ``[lo, hi]`` (ends open where asked).

    Parameters
    ----------
    name : str
        The parameter's name, for the error message.
    value : float
        A real Python or NumPy number (or a 0-d array); booleans and text are refused.
    lo, hi : float or None, optional
        The ends of the range; ``None`` (default): unbounded on that side.
    lo_open, hi_open : bool, optional
        Exclude ``lo`` (``hi``) itself.

    Returns
    -------
    float
        ``value`` as a Python ``float``.

    Raises
    ------
    ArgumentTypeError
        For a value that is not a real scalar.
    ValueError
        For NaN, infinities or a value outside the range.
    """
    parts = []
    if lo is not None:
        parts.append(f"{'>' if lo_open else '>='} {lo:g}")
    if hi is not None:
        parts.append(f"{'<' if hi_open else '<='} {hi:g}")
    allowed = "a finite number" + (" " + " and ".join(parts) if parts else "")
    v = _scalar(name, value, allowed)
    if lo is not None and (v < lo or (lo_open and v == lo)):
        raise ValueError(f"{name} must be {allowed}; got {quote(v)}")
    if hi is not None and (v > hi or (hi_open and v == hi)):
        raise ValueError(f"{name} must be {allowed}; got {quote(v)}")
    return v


def check_finite(name: str, value, *, shape_hint: str = "a finite number") -> np.ndarray:
    """Convert ``value`` to a float64 array and require it to be finite.

    Parameters
    ----------
    name : str
        The parameter's name, for the error message.
    value : array_like
        Real numbers (integer or float), any shape; booleans, complex numbers, text and None are refused.
    shape_hint : str, optional
        What the error message says is allowed.

    Returns
    -------
    ndarray
        A float64 copy of ``value``, same shape (0-d for a scalar).

    Raises
    ------
    ArgumentTypeError
        For a refused type.
    ValueError
        For NaN or infinite entries.
    """
    if value is None or _is_text(value):
        raise ArgumentTypeError(f"{name} must be {shape_hint}; got {type(value).__name__} {quote(value)}")
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError):
        raw = None
    # Complex values would lose their imaginary part silently, booleans would count as 0 and 1.
    if raw is None or raw.dtype.kind not in "fiu":
        raise ArgumentTypeError(f"{name} must be {shape_hint}; got {type(value).__name__} {quote(value)}")
    with np.errstate(over="ignore"):
        arr = raw.astype(np.float64)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be {shape_hint} (finite); got {quote(value)}")
    return arr


def check_color(name: str, value, *, allow_negative: bool = False) -> np.ndarray:
    """An RGB coefficient: a scalar or an RGB triple, finite and (usually) >= 0.

    Returns a float64 array of shape (3,).

    Parameters
    ----------
    name : str
        The parameter's name, for the error message.
    value : float or array_like, shape (3,)
        A scalar (the same in every channel) or an RGB triple of real numbers.
    allow_negative : bool, optional
        Accept entries < 0 (default False).

    Returns
    -------
    ndarray, shape (3,)
        float64; a scalar ``value`` repeated in the three channels.

    Raises
    ------
    ValueError
        For another shape, NaN, infinities or (unless ``allow_negative``) a negative entry
        (``ArgumentTypeError`` for a wrong type).
    """
    allowed = "a finite scalar or RGB triple" + ("" if allow_negative else " with every entry >= 0")
    arr = check_finite(name, value, shape_hint=allowed)
    if arr.ndim == 0:
        arr = np.full(3, float(arr))
    elif arr.shape != (3,):
        raise ValueError(f"{name} must be {allowed}; got shape {arr.shape}: {quote(value)}")
    if not allow_negative and np.any(arr < 0):
        raise ValueError(f"{name} must be {allowed}; got {quote(value)}")
    return arr.astype(np.float64)


def _scalar(name, value, allowed):
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Real, np.floating, np.integer)):
        arr = None if value is None or _is_text(value) else np.asarray(value)
        if arr is None or arr.ndim != 0 or arr.dtype.kind not in "fiu":
            raise ArgumentTypeError(f"{name} must be {allowed}; got {type(value).__name__} {quote(value)}")
        value = arr.item()
    try:
        value = float(value)
    except OverflowError:  # a Python int beyond the float range
        raise ValueError(f"{name} must be {allowed}; got {quote(value)}") from None
    if math.isnan(value) or math.isinf(value):
        raise ValueError(f"{name} must be {allowed}; got {quote(value)}")
    return value


def check_positive(name: str, value) -> float:
    """A finite scalar > 0.

    Parameters
    ----------
    name : str
        The parameter's name, for the error message.
    value : float
        A real Python or NumPy number (or a 0-d array); booleans and text are refused.

    Returns
    -------
    float
        ``value`` as a Python ``float``.

    Raises
    ------
    ValueError
        For NaN, infinities or a value <= 0 (``ArgumentTypeError`` for a wrong type).
    """
    allowed = "a finite number > 0"
    v = _scalar(name, value, allowed)
    if not v > 0:
        raise ValueError(f"{name} must be {allowed}; got {v!r}")
    return v


def check_nonnegative(name: str, value) -> float:
    """A finite scalar >= 0.

    Parameters
    ----------
    name : str
        The parameter's name, for the error message.
    value : float
        A real Python or NumPy number (or a 0-d array); booleans and text are refused.

    Returns
    -------
    float
        ``value`` as a Python ``float``.

    Raises
    ------
    ValueError
        For NaN, infinities or a value < 0 (``ArgumentTypeError`` for a wrong type).
    """
    allowed = "a finite number >= 0"
    v = _scalar(name, value, allowed)
    if not v >= 0:
        raise ValueError(f"{name} must be {allowed}; got {v!r}")
    return v


def check_choice(name: str, value, choices) -> str:
    """One of a fixed set of names (case-insensitive, '_' and '-' alike).

    Parameters
    ----------
    name : str
        The parameter's name, for the error message.
    value : str
        The name given; surrounding blanks are ignored.
    choices : iterable of str
        The allowed names; only lower-case ones without ``_`` can match.

    Returns
    -------
    str
        The entry of ``choices`` that ``value`` names.

    Raises
    ------
    ArgumentTypeError
        For a value that is not a string.
    ValueError
        For a string that names none of ``choices``.
    """
    if isinstance(value, str):
        key = value.strip().lower().replace("_", "-")
        for c in choices:
            if key == c:
                return c
    allowed = ", ".join(repr(c) for c in choices)
    if not isinstance(value, str):
        raise ArgumentTypeError(f"{name} must be one of {allowed}; got {type(value).__name__} {quote(value)}")
    raise ValueError(f"{name} must be one of {allowed}; got {quote(value)}")


def check_float_dtype(dtype, name: str = "dtype") -> np.dtype:
    """``dtype`` as ``np.dtype(float32)`` or ``np.dtype(float64)``; anything else (None included) is refused.

    Callers that accept ``None`` ("the inputs decide") test for it before calling.

    Parameters
    ----------
    dtype : dtype, type or str
        Anything ``np.dtype`` reads as float32 or float64 (``np.float32``, ``"float64"``, ``float`` …).
    name : str, optional
        The parameter's name, for the error message (default ``"dtype"``).

    Returns
    -------
    numpy.dtype
        ``np.dtype(np.float32)`` or ``np.dtype(np.float64)``.

    Raises
    ------
    ArgumentTypeError
        For any other dtype (float16, integers …), None, or a value that is not a dtype.

    Examples
    --------
    >>> check_float_dtype("float32")
    dtype('float32')
    """
    try:
        dt = None if dtype is None else np.dtype(dtype)  # np.dtype(None) would be float64
    except (TypeError, ValueError):
        dt = None
    if dt is None or dt not in (np.dtype(np.float32), np.dtype(np.float64)):
        raise ArgumentTypeError(f"{name} must be float32 or float64; got {quote(dtype)}")
    return dt

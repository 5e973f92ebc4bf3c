"""Numerical plumbing shared by the engine: dtype policy, safe arithmetic, validation.

Dtype policy (conventions.md): every public function keeps the float dtype of its
array inputs.  NumPy arrays of float32/float64 decide the working dtype; Python
scalars, lists and tuples are "weak" and adopt it.  With no float array among the
inputs the result is float64.

"Finite in, finite out": where a formula's true value exceeds the largest finite
number of the working type (a point light at distance 0, a mirror-like lobe seen
exactly at grazing incidence) the engine saturates at that largest finite value
instead of returning ``inf``; no NumPy floating-point warning is raised.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

__all__ = [
    "working_dtype",
    "as_float",
    "safe_div",
    "saturate_to",
    "check_color",
    "check_positive",
    "check_nonnegative",
    "check_finite",
    "check_choice",
    "check_vectors",
    "check_count",
    "check_bool",
    "check_range",
    "real_array",
    "abbreviate",
    "check_budget",
    "memory_budget",
    "set_memory_budget",
    "BudgetError",
    "ArgumentTypeError",
    "cos_sin",
    "cos_sin_deg",
    "check_float_dtype",
]


def _array_float_dtype(x):
    if isinstance(x, (np.ndarray, np.generic)):
        kind = x.dtype.kind
        if kind == "f":
            return np.float32 if x.dtype.itemsize <= 4 else np.float64
        return np.float64
    return None


def working_dtype(*inputs) -> type:
    """The float dtype a computation on ``inputs`` returns.

    float32 if every NumPy float input is float32 (or smaller); float64 if any
    NumPy input is float64 or an integer array; float64 if there is no NumPy
    input at all (Python scalars and tuples are weak, as NEP 50 treats them).

    Parameters
    ----------
    *inputs
        Any values.  Only NumPy arrays and NumPy scalars count: float16/float32 ones ask for
        float32, every other dtype (float64, integer, bool) for float64.

    Returns
    -------
    type
        ``np.float32`` or ``np.float64`` (the scalar type, not a ``np.dtype``).
    """
    found = [d for d in (_array_float_dtype(x) for x in inputs) if d is not None]
    if not found:
        return np.float64
    return np.float64 if any(d is np.float64 for d in found) else np.float32


def as_float(x, dtype) -> np.ndarray:
    """``x`` as an ndarray of ``dtype`` (no copy when it already is one).

    Parameters
    ----------
    x : array_like
        The values, any shape.
    dtype : dtype or type
        The target dtype (in the engine ``np.float32`` or ``np.float64``).

    Returns
    -------
    ndarray
        ``x`` in ``dtype``, same shape (0-d for a scalar).
    """
    return np.asarray(x, dtype=dtype)


def saturate_to(x, dtype) -> np.ndarray:
    """``x`` cast to ``dtype``, values above its largest finite number clamped to it (no overflow warning).

    Parameters
    ----------
    x : array_like
        The values, usually float64 and >= 0: only the upper end is clamped.
    dtype : dtype or type
        The target float dtype.

    Returns
    -------
    ndarray
        ``x`` in ``dtype``, same shape (a NumPy scalar for a scalar ``x``); ``inf`` and every value above
        ``np.finfo(dtype).max`` become that maximum, NaN stays NaN.
    """
    return np.minimum(x, float(np.finfo(dtype).max)).astype(dtype)


def log1p(x) -> np.ndarray:
    """``log(1 + x)`` for ``x >= -1``, accurate to a few ulp, through the vectorized ``log``.

    NumPy's own ``log1p`` has no SIMD loop (several times slower than ``log``;
    docs/numerics.md), and per-pixel lobes take one per sample and light.  This is
    the correction of Goldberg ("What every computer scientist should know about
    floating-point arithmetic", 1991, Theorem 4): with ``y = fl(1 + x)``,
    ``log1p(x) = log(y) · x / (y − 1)`` (and ``x`` where ``y == 1``).  ``y − 1`` is
    exact, so the ratio restores the digits of ``x`` that rounding ``1 + x``
    dropped; measured against float64 ``log1p`` the
    relative error stays below 6 ulp (NumPy's: 1.3).
    """
    x = np.asarray(x)
    return log_corrected(1 + x, x)


def log_corrected(y, x) -> np.ndarray:
    """``log(y)`` with Goldberg's correction: ``log1p(x)`` where ``y`` is ``fl(1 + x)``.

    Returns ``log(y) · x / (y − 1)``, and ``x`` where ``y == 1``.  Where ``x`` is
    exactly ``y − 1`` the ratio is 1 and the result is plain ``log(y)``, so a
    caller may mix rows of both kinds (the Blinn–Phong lobe takes ``log(n·h)``
    far from its peak, ``log1p(−(1 − n·h))`` near it, in one pass).
    """
    shape = np.broadcast_shapes(np.shape(y), np.shape(x))
    y = np.atleast_1d(y)  # the in-place passes below need an array
    z = y - 1
    zero = z == 0
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.log(y)
        z += zero
        r *= x / z
    r += x * zero
    return r.reshape(shape)


def _exponent_in(dtype, exponent: float):
    """A lobe exponent ``e >= 0`` as a scalar of ``dtype``, kept inside the type's positive range.

    Rounding ``e`` to float32 would turn ``e = 1e-300`` into 0, so ``0^e`` (a half vector on
    the horizon, ``l = −v``) became ``0^0``: ``exp(0 · log 0) = exp(0 · −∞)`` is NaN.  And
    ``e = 1e39`` would become ``inf``, which makes ``1^e`` NaN the same way.  So a positive
    ``e`` is rounded up to the smallest subnormal and down to the largest finite number of
    the type.  Neither changes a single lobe value: ``x^e`` for every ``x`` in ``(0, 1]`` of
    the type rounds to 1 for all ``e`` below the first (``|e log x| < 1e-42``), and to 0 or
    exactly 1 for all ``e`` above the second (``log x <= −6e-8`` for ``x < 1``).

    >>> [float(_exponent_in(np.float32, e)) for e in (0.0, 1e-300, 1e300)]
    [0.0, 1.401298464324817e-45, 3.4028234663852886e+38]
    """
    if exponent == 0:
        return dtype(0)
    info = np.finfo(dtype)
    return dtype(min(max(float(exponent), float(info.smallest_subnormal)), float(info.max)))



def safe_div(num, den, *, zero_where_den_le0: bool = True) -> np.ndarray:
    """``num / den`` without warnings; saturates at the dtype's largest finite value.

    Where ``den <= 0`` (or ``den == 0`` when ``zero_where_den_le0`` is False) the
    result is 0: every caller uses this for quantities that are masked to zero
    there (a BRDF below the horizon, a light at zero distance contributing with a
    zero-length direction).

    Parameters
    ----------
    num, den : array_like
        Numerator and denominator, broadcasting together.
    zero_where_den_le0 : bool, optional
        True (default): the result is 0 where ``den <= 0``; False: only where ``den == 0``.

    Returns
    -------
    ndarray
        The quotient, of the broadcast shape (a NumPy scalar for scalar arguments), in the float dtype
        NumPy gives ``np.asarray(num) / np.asarray(den)`` (float64 for integers; a Python float is
        float64 here, so it does not adopt a float32 partner's dtype).  NaN becomes 0 and ``±inf``
        becomes ``±np.finfo(dtype).max``.
    """
    num = np.asarray(num)
    den = np.asarray(den)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        q = num / den
    dt = q.dtype if q.dtype.kind == "f" else np.float64
    big = np.finfo(dt).max
    mask = den > 0 if zero_where_den_le0 else den != 0
    q = np.where(mask, q, 0)
    q = np.nan_to_num(q, nan=0.0, posinf=big, neginf=-big)
    return q.astype(dt, copy=False)


# --------------------------------------------------------------------------- validation
# Every public function checks its arguments once, at the boundary, through these helpers, so that
# every illegal argument gets the same kind of answer: ValueError (TypeError for a wrong type) whose
# message names the parameter, the value given (abbreviated) and what is allowed.

#: Longest rendering of a user's value inside an error message.
MAX_VALUE_CHARS = 80


def abbreviate(text: str, limit: int = MAX_VALUE_CHARS) -> str:
    """``text`` cut to ``limit`` characters, with the number of characters left out.

    Parameters
    ----------
    text : str
        The text (any other value is converted with ``str``).
    limit : int, optional
        The longest text kept whole (default :data:`MAX_VALUE_CHARS`, 80).

    Returns
    -------
    str
        ``text`` itself if it has at most ``limit`` characters; else its first ``max(limit // 2, 1)``
        characters followed by ``…(+N chars)``, ``N`` the number left out.

    Examples
    --------
    >>> abbreviate("x" * 200, 20)
    'xxxxxxxxxx…(+190 chars)'
    """
    text = str(text)
    if len(text) <= limit:
        return text
    keep = max(limit // 2, 1)
    return f"{text[:keep]}…(+{len(text) - keep} chars)"


def _fmt(value) -> str:
    """A short rendering of a user's value for an error message (never more than ``MAX_VALUE_CHARS``)."""
    try:
        if isinstance(value, (str, bytes)):
            return abbreviate(repr(value))
        arr = np.asarray(value)
        if arr.dtype.kind in "fiucb" and arr.ndim > 0:
            # One line whatever the shape: messages are one line.
            text = np.array2string(arr, separator=", ", threshold=8, edgeitems=2, max_line_width=10**6)
            text = " ".join(text.split())
        elif arr.dtype.kind in "fiucb":
            text = repr(arr.item())
        else:
            text = repr(value)
    except Exception:  # repr of exotic objects
        try:
            text = repr(value)
        except Exception:
            text = f"<{type(value).__name__}>"
    return abbreviate(text)


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
        raise ArgumentTypeError(f"{name} must be {allowed}; got {type(value).__name__} {_fmt(value)}")
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"{name} must be {allowed}; got {type(value).__name__} {_fmt(value)}") from None
    if arr.dtype.kind == "b" or arr.dtype.kind not in "fiu":
        raise ArgumentTypeError(f"{name} must be {allowed}; got {arr.dtype} {_fmt(value)}")
    dt = dtype if dtype is not None else working_dtype(arr)
    with np.errstate(over="ignore"):
        out = arr.astype(dt, copy=False)
    if not np.all(np.isfinite(out)):
        raise ValueError(f"{name} must be {allowed} (finite in {np.dtype(dt).name}); got {_fmt(value)}")
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
        raise ValueError(f"{name} must be {allowed}; got shape {arr.shape}: {_fmt(value)}")
    if nonzero and arr.size:
        big = np.max(np.abs(arr), axis=-1)
        if np.any(big == 0):
            raise ValueError(f"{name} must be {allowed}; got a zero vector: {_fmt(value)}")
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
        raise ArgumentTypeError(f"{name} must be {allowed}; got {type(value).__name__} {_fmt(value)}")
    v = int(value)
    if v < lo or (hi is not None and v > hi):
        raise ValueError(f"{name} must be {allowed}; got {_fmt(v)}")
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
    raise ArgumentTypeError(f"{name} must be True or False; got {type(value).__name__} {_fmt(value)}")


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
        raise ValueError(f"{name} must be {allowed}; got {_fmt(v)}")
    if hi is not None and (v > hi or (hi_open and v == hi)):
        raise ValueError(f"{name} must be {allowed}; got {_fmt(v)}")
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
        raise ArgumentTypeError(f"{name} must be {shape_hint}; got {type(value).__name__} {_fmt(value)}")
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError):
        raw = None
    # Complex values would lose their imaginary part silently, booleans would count as 0 and 1.
    if raw is None or raw.dtype.kind not in "fiu":
        raise ArgumentTypeError(f"{name} must be {shape_hint}; got {type(value).__name__} {_fmt(value)}")
    with np.errstate(over="ignore"):
        arr = raw.astype(np.float64)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be {shape_hint} (finite); got {_fmt(value)}")
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
        raise ValueError(f"{name} must be {allowed}; got shape {arr.shape}: {_fmt(value)}")
    if not allow_negative and np.any(arr < 0):
        raise ValueError(f"{name} must be {allowed}; got {_fmt(value)}")
    return arr.astype(np.float64)


def _scalar(name, value, allowed):
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Real, np.floating, np.integer)):
        arr = None if value is None or _is_text(value) else np.asarray(value)
        if arr is None or arr.ndim != 0 or arr.dtype.kind not in "fiu":
            raise ArgumentTypeError(f"{name} must be {allowed}; got {type(value).__name__} {_fmt(value)}")
        value = arr.item()
    try:
        value = float(value)
    except OverflowError:  # a Python int beyond the float range
        raise ValueError(f"{name} must be {allowed}; got {_fmt(value)}") from None
    if math.isnan(value) or math.isinf(value):
        raise ValueError(f"{name} must be {allowed}; got {_fmt(value)}")
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
        raise ArgumentTypeError(f"{name} must be one of {allowed}; got {type(value).__name__} {_fmt(value)}")
    raise ValueError(f"{name} must be one of {allowed}; got {_fmt(value)}")


# --------------------------------------------------------------------------- exact angles
# cos(radians(90)) is 6.1e-17, not 0: a direction built from "90 degrees" would sit a hair above the
# horizon, and a lobe seen there is lit.  Every direction or cosine the engine builds from an angle goes
# through these two helpers, which are exact wherever the angle is a multiple of a right angle.
def cos_sin(theta):
    """``(cos θ, sin θ)`` for angles in radians, exactly 0 and ±1 at the floats nearest to ``kπ/2``.

    Elsewhere the values are NumPy's.  Keeps the float dtype of ``theta`` (float64 for Python numbers).

    Parameters
    ----------
    theta : float or array_like
        Angles in radians, any shape (integers are converted to float64).

    Returns
    -------
    c, s : ndarray
        ``cos θ`` and ``sin θ``, each of ``theta``'s shape and float dtype.

    Examples
    --------
    >>> import math
    >>> cos_sin(math.pi / 2)
    (array(0.), array(1.))
    """
    t = np.asarray(theta)
    if t.dtype.kind != "f":
        t = t.astype(np.float64)
    quarter = t.dtype.type(math.pi / 2)
    with np.errstate(invalid="ignore", over="ignore"):
        k = np.rint(t / quarter)
        exact = (k * quarter == t) & np.isfinite(t)
    c, s = np.cos(t), np.sin(t)
    if np.any(exact):
        km = np.where(exact, k, 0).astype(np.int64) % 4
        c = np.where(exact, np.array([1, 0, -1, 0], dtype=t.dtype)[km], c).astype(t.dtype, copy=False)
        s = np.where(exact, np.array([0, 1, 0, -1], dtype=t.dtype)[km], s).astype(t.dtype, copy=False)
    return c, s


def cos_sin_deg(deg):
    """``(cos, sin)`` of an angle in degrees, exactly 0 and ±1 at multiples of 90°.

    Parameters
    ----------
    deg : float or array_like
        Angles in degrees, any shape (integers are converted to float64).

    Returns
    -------
    c, s : ndarray
        The cosine and the sine, each of ``deg``'s shape and float dtype (float64 for Python numbers).

    Examples
    --------
    >>> cos_sin_deg(90.0)
    (array(0.), array(1.))
    >>> cos_sin_deg(-180.0)
    (array(-1.), array(0.))
    """
    d = np.asarray(deg)
    if d.dtype.kind != "f":
        d = d.astype(np.float64)
    with np.errstate(invalid="ignore"):
        d = np.fmod(d, 360.0)  # exact, so 450° is exactly 90°
        exact = np.fmod(d, 90.0) == 0
    c, s = np.cos(np.radians(d)), np.sin(np.radians(d))
    if np.any(exact):
        km = (np.where(exact, d, 0) // 90).astype(np.int64) % 4
        c = np.where(exact, np.array([1, 0, -1, 0], dtype=d.dtype)[km], c).astype(d.dtype, copy=False)
        s = np.where(exact, np.array([0, 1, 0, -1], dtype=d.dtype)[km], s).astype(d.dtype, copy=False)
    return c, s


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
        raise ArgumentTypeError(f"{name} must be float32 or float64; got {_fmt(dtype)}")
    return dt


# The memory budget lives in lighting/_budget.py; its names stay importable from here, where every module
# takes its argument checks.
from ._budget import BudgetError, check_budget, memory_budget, set_memory_budget  # noqa: E402

"""Float arithmetic shared by the engine: the dtype policy, saturation, safe division and exact angles.

Dtype policy (conventions.md): every public function keeps the float dtype of its
array inputs.  NumPy arrays of float32/float64 decide the working dtype; Python
scalars, lists and tuples are "weak" and adopt it.  With no float array among the
inputs the result is float64.

"Finite in, finite out": where a formula's true value exceeds the largest finite
number of the working type (a point light at distance 0, a mirror-like lobe seen
exactly at grazing incidence) the engine saturates at that largest finite value
instead of returning ``inf``; no NumPy floating-point warning is raised.

cos(radians(90)) is 6.1e-17, not 0: a direction built from "90 degrees" would sit a hair above the
horizon, and a lobe seen there is lit.  Every direction or cosine the engine builds from an angle goes
through :func:`cos_sin` or :func:`cos_sin_deg`, which are exact wherever the angle is a multiple of a right angle.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "working_dtype",
    "as_float",
    "saturate_to",
    "log1p",
    "log_corrected",
    "safe_div",
    "cos_sin",
    "cos_sin_deg",
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


def saturate_to(x, dtype, *, overwrite: bool = False) -> np.ndarray:
    """``x`` cast to ``dtype``, values above its largest finite number clamped to it (no overflow warning).

    Parameters
    ----------
    x : array_like
        The values, usually float64 and >= 0: only the upper end is clamped.
    dtype : dtype or type
        The target float dtype.
    overwrite : bool, optional
        Clamp ``x`` itself, a float array the caller owns (a fresh product), instead of a copy of it.

    Returns
    -------
    ndarray
        ``x`` in ``dtype``, same shape (a NumPy scalar for a scalar ``x``); ``inf`` and every value above
        ``np.finfo(dtype).max`` become that maximum, NaN stays NaN.
    """
    top = float(np.finfo(dtype).max)
    if overwrite:
        return np.minimum(x, top, out=x).astype(dtype, copy=False)
    return np.minimum(x, top).astype(dtype, copy=False)  # np.minimum made the copy


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
    mask = den > 0 if zero_where_den_le0 else den != 0
    if isinstance(q, np.ndarray) and q.ndim and q.dtype.kind == "f":
        # The quotient is a fresh float array: saturated and zeroed in place, the numbers the general form below
        # gives (np.clip keeps NaN and −0; NaN and the masked entries are then set to +0).
        big = np.finfo(q.dtype).max
        keep = mask & ~np.isnan(q)
        np.clip(q, -big, big, out=q)
        np.copyto(q, 0, where=~keep)
        return q
    dt = q.dtype if q.dtype.kind == "f" else np.float64
    big = np.finfo(dt).max
    q = np.where(mask, q, 0)
    q = np.nan_to_num(q, nan=0.0, posinf=big, neginf=-big)
    return q.astype(dt, copy=False)


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

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
    """
    found = [d for d in (_array_float_dtype(x) for x in inputs) if d is not None]
    if not found:
        return np.float64
    return np.float64 if any(d is np.float64 for d in found) else np.float32


def as_float(x, dtype) -> np.ndarray:
    """``x`` as an ndarray of ``dtype`` (no copy when it already is one)."""
    return np.asarray(x, dtype=dtype)


def saturate_to(x, dtype) -> np.ndarray:
    """``x`` cast to ``dtype``, values above its largest finite number clamped to it (no overflow warning)."""
    return np.minimum(x, float(np.finfo(dtype).max)).astype(dtype)


def log1p(x) -> np.ndarray:
    """``log(1 + x)`` for ``x >= -1``, accurate to a few ulp, through the vectorized ``log``.

    NumPy's own ``log1p`` has no SIMD loop (measured 4.4 ms against 0.9 ms for
    ``log`` on 465,000 float32 values here), and per-pixel lobes take one per
    sample and light.  This is the correction of Goldberg ("What every computer
    scientist should know about floating-point arithmetic", 1991, Theorem 4):
    with ``y = fl(1 + x)``, ``log1p(x) = log(y) · x / (y − 1)`` (and ``x`` where
    ``y == 1``).  ``y − 1`` is exact, so the ratio restores the digits of ``x``
    that rounding ``1 + x`` dropped; measured against float64 ``log1p`` the
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


def safe_div(num, den, *, zero_where_den_le0: bool = True) -> np.ndarray:
    """``num / den`` without warnings; saturates at the dtype's largest finite value.

    Where ``den <= 0`` (or ``den == 0`` when ``zero_where_den_le0`` is False) the
    result is 0: every caller uses this for quantities that are masked to zero
    there (a BRDF below the horizon, a light at zero distance contributing with a
    zero-length direction).
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
def _fmt(value) -> str:
    try:
        arr = np.asarray(value)
        if arr.ndim == 0:
            return repr(arr.item())
        return np.array2string(arr, separator=", ", threshold=8)
    except Exception:  # pragma: no cover - repr of exotic objects
        return repr(value)


def check_finite(name: str, value, *, shape_hint: str = "a finite number") -> np.ndarray:
    """Convert ``value`` to a float64 array and require it to be finite."""
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be {shape_hint}; got {value!r}") from None
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be {shape_hint} (finite); got {_fmt(value)}")
    return arr


def check_color(name: str, value, *, allow_negative: bool = False) -> np.ndarray:
    """An RGB coefficient: a scalar or an RGB triple, finite and (usually) >= 0.

    Returns a float64 array of shape (3,).
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
    if isinstance(value, bool) or not isinstance(value, (numbers.Real, np.floating, np.integer)):
        arr = np.asarray(value) if not isinstance(value, str) else None
        if arr is None or arr.ndim != 0 or arr.dtype.kind not in "fiu":
            raise ValueError(f"{name} must be {allowed}; got {value!r}")
        value = arr.item()
    value = float(value)
    if math.isnan(value) or math.isinf(value):
        raise ValueError(f"{name} must be {allowed}; got {value!r}")
    return value


def check_positive(name: str, value) -> float:
    """A finite scalar > 0."""
    allowed = "a finite number > 0"
    v = _scalar(name, value, allowed)
    if not v > 0:
        raise ValueError(f"{name} must be {allowed}; got {v!r}")
    return v


def check_nonnegative(name: str, value) -> float:
    """A finite scalar >= 0."""
    allowed = "a finite number >= 0"
    v = _scalar(name, value, allowed)
    if not v >= 0:
        raise ValueError(f"{name} must be {allowed}; got {v!r}")
    return v


def check_choice(name: str, value, choices) -> str:
    """One of a fixed set of names (case-insensitive, '_' and '-' alike)."""
    if isinstance(value, str):
        key = value.strip().lower().replace("_", "-")
        for c in choices:
            if key == c:
                return c
    raise ValueError(f"{name} must be one of {', '.join(repr(c) for c in choices)}; got {value!r}")

"""Small vector toolkit used everywhere in the engine.

All functions take arrays of shape ``(..., 3)`` (or anything that broadcasts to
it, including Python tuples), broadcast over the leading axes and keep the float
dtype of their array inputs (see :mod:`lighting.numerics`).

Names follow the slides: ``n`` the unit normal, ``l`` the unit vector toward the
light, ``v`` toward the viewer, ``h = (l + v) / |l + v|``,
``R_l = 2 n (n·l) - l``.
"""

from __future__ import annotations

import numpy as np

from ._text import quote
from ._validate import check_float_dtype, check_vectors, real_array
from .numerics import cos_sin, cos_sin_deg, safe_div, working_dtype

__all__ = [
    "dot",
    "cross",
    "length",
    "normalize",
    "reflect",
    "halfway",
    "one_minus_cos_between",
    "orthonormal_basis",
    "spherical_direction",
    "direction_from_elevation",
    "to_local",
    "from_local",
]


_ALLOWED = "finite real vectors of shape (..., 3)"


def _vec(x, dtype=None, name="a", *, finite=True) -> np.ndarray:
    """``x`` as vectors of shape ``(..., 3)`` in ``dtype``, checked at the public boundary.

    Text, complex numbers, objects and NaN/inf are refused with an error naming ``name``: a
    NaN vector would otherwise come back as a silent 0 (``normalize``) or spread NaN.  With
    ``finite=False`` a float array's finiteness is left to the caller (``normalize`` tests it
    only where its fast path fails, so the engine's hot loops pay nothing for the check).
    """
    dt = working_dtype(x) if dtype is None else dtype
    if finite or not (isinstance(x, np.ndarray) and x.dtype.kind == "f"):
        return check_vectors(name, x, dtype=dt)
    a = x.astype(dt, copy=False)
    if a.shape[-1:] != (3,):
        raise ValueError(f"{name} must be {_ALLOWED}; got shape {a.shape}: {quote(x)}")
    return a


def _refuse_nonfinite(name, a) -> None:
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be {_ALLOWED} (finite in {a.dtype.name}); got {quote(a)}")


def dot(a, b) -> np.ndarray:
    """Dot product over the last axis: shape ``(...)``.

    Parameters
    ----------
    a, b : array_like, shape (..., 3)
        Finite real vectors, broadcasting together.

    Returns
    -------
    ndarray, shape (...)
        ``a·b`` over the broadcast leading axes (a NumPy scalar for two single vectors), in the float
        dtype of the inputs.

    Examples
    --------
    >>> float(dot((1.0, 2.0, 3.0), (4.0, 5.0, 6.0)))
    32.0
    """
    dt = working_dtype(a, b)
    return _dot(_vec(a, dt, "a"), _vec(b, dt, "b"))


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """:func:`dot` of checked arrays, component by component: each vector's value is the same whatever vectors are
    computed with it (a matrix product groups rows, and a row's bits would depend on its place among them)."""
    if a.shape == b.shape and a.ndim > 1:
        # The same products and sums: the products formed in one pass over the contiguous arrays, instead of three
        # passes over strided columns (where a vector broadcasts, that one pass would loop three elements at a time).
        p = a * b
        out = np.add(p[..., 0], p[..., 1])
        out += p[..., 2]
        return out
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]


def cross(a, b) -> np.ndarray:
    """Cross product ``a × b``, shape ``(..., 3)``.

    Parameters
    ----------
    a, b : array_like, shape (..., 3)
        Finite real vectors, broadcasting together.

    Returns
    -------
    ndarray, shape (..., 3)
        ``a × b`` over the broadcast leading axes, in the float dtype of the inputs.
    """
    dt = working_dtype(a, b)
    a, b = _vec(a, dt, "a"), _vec(b, dt, "b")
    return np.stack(
        [
            a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
            a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
            a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0],
        ],
        axis=-1,
    )


def _scaled(a: np.ndarray):
    """``a / max|a_i|`` and ``max|a_i|``: the scaled vector has entries in [-1, 1].

    Scaling first is what keeps ``|a|`` free of overflow (components ~1e20 in
    float32) and underflow (components ~1e-30 in float32).
    """
    m = np.max(np.abs(a), axis=-1, keepdims=True)
    s = safe_div(a, m)  # 0 for the zero vector
    return s.astype(a.dtype, copy=False), m


def length(a) -> np.ndarray:
    """Euclidean length over the last axis, computed without overflow or underflow.

    Parameters
    ----------
    a : array_like, shape (..., 3)
        Finite real vectors.

    Returns
    -------
    ndarray, shape (...)
        ``|a|`` >= 0 (a NumPy scalar for a single vector), in the float dtype of ``a``.
    """
    a = _vec(a, name="a")
    s, m = _scaled(a)
    return m[..., 0] * np.sqrt(dot(s, s))


def normalize(a) -> np.ndarray:
    """Unit vector along ``a``; the zero vector maps to the zero vector.

    Uses the direct ``a / |a|`` where ``|a|²`` is safely representable and a
    scaled form elsewhere, so tiny (1e-30 in float32) and huge (1e20 in float32)
    vectors normalize correctly.  No warning is raised for zero vectors.

    Parameters
    ----------
    a : array_like, shape (..., 3)
        Finite real vectors (NaN and infinities are refused).

    Returns
    -------
    ndarray, shape (..., 3)
        Unit vectors (zero vectors for zero ``a``), in the float dtype of ``a``.

    Examples
    --------
    >>> normalize((3.0, 0.0, 4.0)).tolist()
    [0.6, 0.0, 0.8]
    >>> normalize((0.0, 0.0, 0.0)).tolist()
    [0.0, 0.0, 0.0]
    """
    return _normalize(a, "a")


def _normalize(a, name):
    a = _vec(a, name=name, finite=False)
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        len2 = _dot(a, a)
    fast = _direct_path(len2, a.dtype)
    if np.all(fast):
        return _divide_components(a, np.sqrt(len2))  # a / np.sqrt(len2)[..., None]
    _refuse_nonfinite(name, a)  # NaN and inf never take the fast path: checked here, at no cost above
    # The path is chosen per vector, never per batch: a vector's unit vector (and so the
    # bit-exact symmetry of a mirror pair l, R_l) must not depend on its neighbours.
    flat, ok = a.reshape(-1, 3), fast.reshape(-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = flat / np.sqrt(np.where(ok, len2.reshape(-1), 1))[:, None]
    s, _ = _scaled(flat[~ok])
    len_s = np.sqrt(s[..., 0] * s[..., 0] + s[..., 1] * s[..., 1] + s[..., 2] * s[..., 2])
    out[~ok] = safe_div(s, len_s[..., None])
    return out.astype(a.dtype, copy=False).reshape(a.shape)


def _direct_path(len2, dtype) -> np.ndarray:
    """Where :func:`normalize` divides a vector by its length directly: the squared length ``len2`` comfortably
    inside the normal range of ``dtype`` (elsewhere it scales the vector first)."""
    fi = np.finfo(dtype)
    return (len2 > float(fi.tiny) * 1e4) & (len2 < float(fi.max) * 1e-4)


def _add_vectors(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a + b`` for vectors ``(..., 3)`` of one float dtype: the same sums, bit for bit, a fresh C-contiguous array.

    Where the shapes differ the sum is formed one component at a time: a broadcast over the last axis of
    length 3 runs NumPy's inner loop three elements at a time.
    """
    if a.shape == b.shape:
        return a + b
    out = np.empty(np.broadcast_shapes(a.shape, b.shape), dtype=np.result_type(a, b))
    for k in range(3):
        np.add(a[..., k], b[..., k], out=out[..., k])
    return out


def _divide_components(a: np.ndarray, d: np.ndarray) -> np.ndarray:
    """``a / d[..., None]`` for vectors ``a`` ``(..., 3)`` and divisors ``d`` ``(...)`` of one float dtype.

    The same quotients, bit for bit, computed one component at a time: the broadcast over the axis of
    length 3 runs NumPy's inner loop three elements at a time, several times slower on long arrays.
    """
    out = np.empty(a.shape, dtype=np.result_type(a, d))
    for k in range(3):
        np.divide(a[..., k], d, out=out[..., k])
    return out


def reflect(d, n) -> np.ndarray:
    """Mirror ``d`` about ``n``: ``2 n (n·d) - d`` (the slides' ``R_l`` for ``d = l``).

    Parameters
    ----------
    d : array_like, shape (..., 3)
        The direction to mirror (finite, real).
    n : array_like, shape (..., 3)
        The unit normal; it is not normalized here.  Broadcasts with ``d``.

    Returns
    -------
    ndarray, shape (..., 3)
        The mirrored direction (of the length of ``d`` for a unit ``n``), in the float dtype of the inputs.
    """
    dt = working_dtype(d, n)
    d, n = _vec(d, dt, "d"), _vec(n, dt, "n")
    return 2 * n * dot(n, d)[..., None] - d


def halfway(l, v) -> np.ndarray:  # noqa: E741 - the slides' name
    """Halfway vector ``h = (l + v) / |l + v|``.

    Where ``l = -v`` exactly the sum is the zero vector and so is the result:
    then every ``n·h`` is 0, which is the right limit for the shading models
    (one of ``l``, ``v`` is then at or below the horizon, where every BRDF is 0).

    Parameters
    ----------
    l, v : array_like, shape (..., 3)
        Unit directions toward the light and toward the viewer (finite, real), broadcasting together;
        only their sum is normalized.

    Returns
    -------
    ndarray, shape (..., 3)
        Unit vectors (the zero vector where ``l + v = 0``), in the float dtype of the inputs.

    Examples
    --------
    >>> halfway((1.0, 0.0, 0.0), (0.0, 1.0, 0.0)).round(6).tolist()
    [0.707107, 0.707107, 0.0]
    >>> halfway((1.0, 0.0, 0.0), (-1.0, 0.0, 0.0)).tolist()
    [0.0, 0.0, 0.0]
    """
    dt = working_dtype(l, v)
    return normalize(_vec(l, dt, "l") + _vec(v, dt, "v"))


def one_minus_cos_between(a, b) -> np.ndarray:
    r"""``1 − cos ψ`` of the angle ``ψ`` between unit vectors ``a`` and ``b``, as ``|a − b|² / 2``.

        1 − a·b = |a − b|² / 2        (for |a| = |b| = 1)

    Near ``ψ = 0`` (a mirror direction, the peak of a sharp lobe) ``1 − a·b`` cancels:
    it keeps only the digits of ``a·b`` left after the leading 1, where ``|a − b|²``
    keeps those of the components.  The result is clipped to ``[0, 2]``.

    Parameters
    ----------
    a, b : array_like, shape (..., 3)
        Unit vectors (finite), broadcasting together.

    Returns
    -------
    ndarray, shape (...)
        ``1 − cos ψ`` in ``[0, 2]``, in the float dtype of the inputs.

    Examples
    --------
    >>> float(one_minus_cos_between((1.0, 0.0, 0.0), (0.0, 1.0, 0.0)))
    1.0
    """
    dt = working_dtype(a, b)
    return _one_minus_cos_between(_vec(a, dt, "a"), _vec(b, dt, "b"))


def _one_minus_cos_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """:func:`one_minus_cos_between` on arrays already checked (the shading and sampling paths)."""
    d = a - b
    return np.clip(0.5 * (d[..., 0] * d[..., 0] + d[..., 1] * d[..., 1] + d[..., 2] * d[..., 2]), 0, 2)


def orthonormal_basis(n):
    """Two unit tangents ``(t, b)`` with ``(t, b, n)`` a right-handed orthonormal frame.

    Branch-free construction of Duff et al., "Building an Orthonormal Basis,
    Revisited" (JCGT 2017); continuous except across ``n_z = 0`` sign flips.

    Parameters
    ----------
    n : array_like, shape (..., 3)
        Normals (finite, real); normalized here.  A zero ``n`` gives ``t = x``, ``b = y``.

    Returns
    -------
    t, b : ndarray, shape (..., 3)
        The two tangents, in the float dtype of ``n``.
    """
    n = _normalize(n, "n")
    sign = np.where(n[..., 2] >= 0, 1.0, -1.0).astype(n.dtype)
    a = -1.0 / (sign + n[..., 2])
    b = n[..., 0] * n[..., 1] * a
    t = np.stack([1.0 + sign * n[..., 0] ** 2 * a, sign * b, -sign * n[..., 0]], axis=-1)
    bt = np.stack([b, sign + n[..., 1] ** 2 * a, -n[..., 1]], axis=-1)
    return t.astype(n.dtype, copy=False), bt.astype(n.dtype, copy=False)


def spherical_direction(theta, phi, dtype=None) -> np.ndarray:
    """Unit vector at polar angle ``theta`` (from +z) and azimuth ``phi`` (from +x toward +y).

    Built through :func:`lighting.numerics.cos_sin`, so ``theta = π/2`` lies exactly on the horizon
    (``z = 0``, not ``cos(π/2) = 6.1e-17``) and ``phi = π/2`` exactly on the ``y`` axis: every view that
    builds a direction from angles agrees on which side of the horizon it is.

    Parameters
    ----------
    theta, phi : float or array_like
        Polar angle and azimuth in radians: finite real numbers, broadcasting together.
    dtype : dtype, type, str or None, optional
        The result's dtype, float32 or float64; ``None`` (default): the float dtype of ``theta`` and
        ``phi`` (float64 for Python numbers).

    Returns
    -------
    ndarray, shape (..., 3)
        Unit vectors; ``...`` is the broadcast shape of ``theta`` and ``phi``.

    Examples
    --------
    >>> import math
    >>> spherical_direction(math.pi / 2, 0.0)
    array([1., 0., 0.])
    """
    dt = working_dtype(theta, phi) if dtype is None else check_float_dtype(dtype).type
    theta, phi = _angles(theta=theta, phi=phi)
    ct, st = cos_sin(theta.astype(dt))
    cp, sp = cos_sin(phi.astype(dt))
    return np.stack(np.broadcast_arrays(st * cp, st * sp, ct), axis=-1)


def direction_from_elevation(elevation_deg, azimuth_deg=0.0) -> np.ndarray:
    """Unit vector ``elevation_deg`` above the xy-plane at ``azimuth_deg`` from +x toward +y (degrees).

    Exact at multiples of 90° (an elevation of 0 is exactly on the horizon, 90 exactly overhead).

    Parameters
    ----------
    elevation_deg : float or array_like
        Angle above the xy-plane in degrees (negative: below it); finite real numbers.
    azimuth_deg : float or array_like, optional
        Angle from +x toward +y in degrees (default 0); broadcasts with ``elevation_deg``.

    Returns
    -------
    ndarray, shape (..., 3)
        Unit vectors; ``...`` is the broadcast shape of the angles.  In their float dtype (float64 for
        Python numbers).

    Examples
    --------
    >>> direction_from_elevation(0.0, 90.0)
    array([0., 1., 0.])
    """
    elevation, azimuth = _angles(elevation_deg=elevation_deg, azimuth_deg=azimuth_deg)
    ce, se = cos_sin_deg(elevation.astype(working_dtype(elevation_deg, azimuth_deg)))
    ca, sa = cos_sin_deg(azimuth.astype(working_dtype(elevation_deg, azimuth_deg)))
    return np.stack(np.broadcast_arrays(ce * ca, ce * sa, se), axis=-1)


def _angles(**angles):
    """Each named angle as a finite real array (text, complex, NaN and inf refused, naming it), broadcast together."""
    arrays = [real_array(name, value, allowed="finite real angles") for name, value in angles.items()]
    try:
        np.broadcast_shapes(*(a.shape for a in arrays))
    except ValueError:
        shapes = " and ".join(f"{name} {a.shape}" for name, a in zip(angles, arrays, strict=True))
        raise ValueError(f"{' and '.join(angles)} must broadcast together; got shapes {shapes}") from None
    return arrays


def to_local(d, n) -> np.ndarray:
    """Express world direction ``d`` in the shading frame whose ``z`` is ``n``.

    Parameters
    ----------
    d : array_like, shape (..., 3)
        World directions (finite, real).
    n : array_like, shape (..., 3)
        Normals, normalized here; broadcast with ``d``.

    Returns
    -------
    ndarray, shape (..., 3)
        ``(d·t, d·b, d·n̂)`` with ``(t, b)`` from :func:`orthonormal_basis`.  float32 when ``n`` is a
        float32 array and ``d`` float32 or a Python sequence; float64 otherwise (also for a tuple ``n``).
    """
    d = _vec(d, working_dtype(d, n), "d")
    t, b = orthonormal_basis(n)
    return np.stack([dot(d, t), dot(d, b), dot(d, normalize(n))], axis=-1)


def from_local(d_local, n) -> np.ndarray:
    """Inverse of :func:`to_local`.

    Parameters
    ----------
    d_local : array_like, shape (..., 3)
        Directions in the shading frame (finite, real).
    n : array_like, shape (..., 3)
        Normals (the frame's ``z``), normalized here; broadcast with ``d_local``.

    Returns
    -------
    ndarray, shape (..., 3)
        ``d_local[0] t + d_local[1] b + d_local[2] n̂``.  dtype as :func:`to_local`: float32 when ``n``
        is a float32 array and ``d_local`` float32 or a Python sequence, float64 otherwise.
    """
    dt = working_dtype(d_local, n)
    d_local = _vec(d_local, dt, "d_local")
    t, b = orthonormal_basis(np.asarray(_vec(n, dt, "n")))
    return d_local[..., 0:1] * t + d_local[..., 1:2] * b + d_local[..., 2:3] * normalize(n)

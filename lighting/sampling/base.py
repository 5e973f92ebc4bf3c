r"""The sampler protocol of the models: :class:`Sampler`, :class:`Samples`, and the uniform hemisphere.

Each model owns its importance sampler (``model.sampler()``, the pbrt ``BxDF::Sample_f``/``PDF``
pair) and defines it beside itself: :class:`~lighting.models.lambert.CosineSampler`,
:class:`~lighting.models.phong.PhongSampler`,
:class:`~lighting.sampling.microfacet.MicrofacetSampler`.  This module holds what
they share: the base class, the uniform hemisphere, the argument checks and the
warps' building blocks.  Everything works in the **local shading frame** (``z`` = the
normal) and in float64.  Mixtures, the dispatch by model and the estimators are in
:mod:`lighting.sampling.brdf`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._budget import check_budget
from .._text import quote
from .._validate import check_count, check_vectors, real_array
from ..vec import _direct_path, orthonormal_basis

__all__ = [
    "Samples",
    "Sampler",
    "UniformSampler",
    "square_to_uniform_hemisphere",
    "uniform_hemisphere_pdf",
]

_TWO_PI = 2.0 * math.pi


class Samples(NamedTuple):
    """Directions ``(..., 3)`` (local frame) and their density per steradian ``(...)``."""

    directions: np.ndarray
    pdf: np.ndarray



#: Peak bytes per drawn direction in the samplers and estimators (directions, densities, weights and
#: their temporaries, in float64), for the memory estimate made before allocating.
BYTES_PER_SAMPLE = 256


def _count(name: str, value) -> int:
    """A sample count >= 1 whose arrays fit the memory budget."""
    n = check_count(name, value, 1)
    check_budget(name, n * BYTES_PER_SAMPLE, what=f"{n} directions")
    return n


def _check_size(name: str, *shapes) -> None:
    """Refuse a broadcast of ``shapes`` whose sample arrays exceed the memory budget."""
    try:
        size = math.prod(np.broadcast_shapes(*shapes))
    except ValueError:
        return  # reported by _broadcast
    check_budget(name, size * BYTES_PER_SAMPLE, what=f"{size} directions")


def _broadcast(a: str, sa: tuple, b: str, sb: tuple) -> None:
    try:
        np.broadcast_shapes(sa, sb)
    except ValueError:
        raise ValueError(f"{a} and {b} must broadcast together; got leading shapes {sa} and {sb}") from None


def _unit_square(name: str, u) -> np.ndarray:
    """Points of the unit square ``(..., 2)``: finite reals in ``[0, 1]``, float64."""
    allowed = "points of the unit square [0, 1]², shape (..., 2)"
    arr = real_array(name, u, allowed=allowed, dtype=np.float64)
    if arr.shape[-1:] != (2,):
        raise ValueError(f"{name} must be {allowed}; got shape {arr.shape}: {quote(u)}")
    if arr.size and (np.min(arr) < 0 or np.max(arr) > 1):
        raise ValueError(f"{name} must be {allowed}; got values in [{np.min(arr):.6g}, {np.max(arr):.6g}]")
    return arr


def _directions(name: str, d) -> np.ndarray:
    return check_vectors(name, d, dtype=np.float64)



def square_to_uniform_hemisphere(u) -> Samples:
    """Uniform directions on the upper hemisphere: ``cos θ = u₀``, ``φ = 2π u₁``, ``p = 1/(2π)``.

    Parameters
    ----------
    u : array_like, shape (..., 2)
        Points of the unit square.

    Returns
    -------
    Samples
        Directions ``(..., 3)`` and their density ``(...)``.

    Examples
    --------
    >>> s = square_to_uniform_hemisphere(np.array([1.0, 0.0]))
    >>> s.directions.tolist(), round(float(s.pdf) * 2 * math.pi, 12)
    ([0.0, 0.0, 1.0], 1.0)
    """
    u = _unit_square("u", u)
    z = u[..., 0]
    r = np.sqrt(np.clip((1 - z) * (1 + z), 0.0, None))
    phi = _TWO_PI * u[..., 1]
    d = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1)
    return Samples(d, np.full(z.shape, 1.0 / _TWO_PI))


def uniform_hemisphere_pdf(d) -> np.ndarray:
    """``1/(2π)`` above the horizon (``z > 0``), 0 below.

    Parameters
    ----------
    d : array_like, shape (..., 3)
        Directions in the local frame.

    Returns
    -------
    ndarray, shape (...)
    """
    d = _directions("d", d)
    return np.where(d[..., 2] > 0, 1.0 / _TWO_PI, 0.0)



def _local_v(v) -> np.ndarray:
    v = np.asarray(v, dtype=np.float64)
    if v.shape[-1:] != (3,):
        raise ValueError(f"v must have shape (..., 3); got shape {v.shape}")
    return v


def _upper(h):
    """``h`` turned into the upper hemisphere, ``np.where(h[..., 2:3] < 0, -h, h)``: the same numbers.

    Negated in place, one component at a time, where ``h_z < 0``: the condition broadcast over the axis of
    length 3 runs NumPy's inner loop three elements at a time, several times slower on long arrays.
    """
    h = np.asarray(h)
    out = np.array(h, copy=True)
    down = h[..., 2] < 0
    for k in range(3):
        np.negative(h[..., k], out=out[..., k], where=down)
    return out


def _columns_of(l, v):  # noqa: E741
    """The three columns of ``l`` if it is an array (n, 3) of float64 and ``v`` a single float64 view, else None."""
    if l.ndim == 2 and l.shape[1] == 3 and l.dtype == np.float64 and v.shape == (3,) and v.dtype == np.float64:
        return l[:, 0], l[:, 1], l[:, 2]
    return None


def _unit_columns(s0, s1, s2):
    """``normalize(s)`` of ``s`` given as three float64 columns, and ``_dot(s, s)``: ``(u0, u1, u2, ss)``, the
    same numbers, or None if a row leaves ``normalize``'s direct path (zero, tiny or huge: the caller then
    takes the reference).  Component by component, as ``normalize`` itself divides, without forming the
    (n, 3) arrays between the steps."""
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        ss = s0 * s0 + s1 * s1 + s2 * s2
    if not np.all(_direct_path(ss, np.float64)):
        return None
    r = np.sqrt(ss)
    return s0 / r, s1 / r, s2 / r, ss


def _half_columns(s0, s1, s2):
    """``_upper(normalize(s))`` and ``_dot(s, s)`` of three columns, ``(h0, h1, h2, ss)``, or None as
    :func:`_unit_columns`."""
    unit = _unit_columns(s0, s1, s2)
    if unit is None:
        return None
    h0, h1, h2, ss = unit
    down = h2 < 0
    for c in (h0, h1, h2):
        np.negative(c, out=c, where=down)
    return h0, h1, h2, ss


def _stack3(c0, c1, c2):
    out = np.empty((len(c0), 3))
    out[:, 0], out[:, 1], out[:, 2] = c0, c1, c2
    return out


class Sampler:
    """Base class: draws ``l`` for a viewer ``v`` (local frame) and evaluates the density.

    ``sample(u, v)`` takes unit-square points ``u`` ``(..., 2)`` (finite, in
    ``[0, 1]``) and view directions ``v`` broadcastable to ``(..., 3)`` (finite
    real vectors); ``pdf(l, v)`` is the density per steradian of the
    directions it produces, on the whole sphere.  Both check their arguments
    (ValueError naming the parameter; :class:`~lighting._validate.ArgumentTypeError`
    for text, complex or objects) and then call ``_sample`` / ``_pdf``, which
    subclasses implement and the integrators call directly on checked data.
    """

    name = "sampler"
    #: The sampler draws a Dirac delta (the ideal mirror's): ``pdf`` of a sample is a probability, not a
    #: density, and ``pdf(l, v)`` is 0 for every pair (see :class:`~lighting.models.mirror.MirrorSampler`).
    delta = False

    def sample(self, u, v) -> Samples:
        """Directions and densities for unit-square points ``u`` and viewers ``v``.

        Parameters
        ----------
        u : array_like, shape (..., 2)
            Points of the unit square ``[0, 1]²``.
        v : array_like, shape (..., 3)
            View directions in the local frame (``z`` = the normal), broadcasting with ``u``.

        Returns
        -------
        Samples
            ``directions`` ``(..., 3)`` and ``pdf`` ``(...)`` per steradian.
        """
        u = _unit_square("u", u)
        v = check_vectors("v", v, dtype=np.float64)
        _broadcast("u", u.shape[:-1], "v", v.shape[:-1])
        _check_size("u", u.shape[:-1], v.shape[:-1])
        return self._sample(u, v)

    def pdf(self, l, v) -> np.ndarray:  # noqa: E741
        """Density per steradian of :meth:`sample`'s directions.

        Parameters
        ----------
        l, v : array_like, shape (..., 3)
            Directions and viewers in the local frame, broadcasting together.

        Returns
        -------
        ndarray, shape (...)
            The density on the whole sphere (>= 0).
        """
        l = check_vectors("l", l, dtype=np.float64)  # noqa: E741
        v = check_vectors("v", v, dtype=np.float64)
        _broadcast("l", l.shape[:-1], "v", v.shape[:-1])
        _check_size("l", l.shape[:-1], v.shape[:-1])
        return self._pdf(l, v)

    def _sample(self, u, v) -> Samples:
        raise NotImplementedError

    def _pdf(self, l, v) -> np.ndarray:  # noqa: E741
        raise NotImplementedError

    def __repr__(self):
        return f"{type(self).__name__}()"


class _ViewIndependentSampler(Sampler):
    """A fixed density over the hemisphere, ``_warp(u)`` with density ``_density(l)``; ``v`` only broadcasts."""

    _warp = None
    _density = None

    def _sample(self, u, v):
        s = type(self)._warp(u)
        shape = np.broadcast_shapes(s.pdf.shape, _local_v(v).shape[:-1])
        return Samples(np.broadcast_to(s.directions, shape + (3,)), np.broadcast_to(s.pdf, shape))

    def _pdf(self, l, v):  # noqa: E741
        return np.broadcast_to(type(self)._density(l), np.broadcast_shapes(np.shape(l)[:-1], np.shape(v)[:-1]))


class UniformSampler(_ViewIndependentSampler):
    """Uniform over the hemisphere (ignores ``v``)."""

    name = "uniform"
    _warp = staticmethod(square_to_uniform_hemisphere)
    _density = staticmethod(uniform_hemisphere_pdf)



def _one_minus_cos_power(u0: np.ndarray, k: float) -> np.ndarray:
    """``1 − (1 − u₀)^{1/k}`` accurately (``expm1``/``log1p``): inverse CDF of ``cos^{k−1}``-type lobes."""
    with np.errstate(divide="ignore"):
        return -np.expm1(np.log1p(-np.minimum(u0, 1.0)) / k)


def _around(axis: np.ndarray, one_minus_cos: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """Direction at angle ``ψ`` (given as ``1 − cos ψ``) from ``axis`` and azimuth ``phi`` around it."""
    omc = one_minus_cos
    cos_psi = 1.0 - omc
    sin_psi = np.sqrt(np.clip(omc * (2.0 - omc), 0.0, None))
    t, b = orthonormal_basis(axis)
    return cos_psi[..., None] * axis + (sin_psi * np.cos(phi))[..., None] * t + (sin_psi * np.sin(phi))[..., None] * b


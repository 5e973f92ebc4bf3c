r"""Hemisphere and BRDF sampling for Monte Carlo integration of the rendering equation.

Everything here works in the **local shading frame** (``z`` = the normal ``n``,
conventions.md) and in float64: these are integration tools, and the
estimators they feed divide by densities that float32 would round badly.

A Monte Carlo estimate of ``∫ g(l) dω_l`` draws ``l_k`` with density ``p(l_k)``
per steradian and averages ``g(l_k) / p(l_k)``; the closer ``p`` is to being
proportional to ``g``, the smaller the variance.  Each sampler maps points
``u`` of the unit square ``[0, 1)²`` (independent uniforms, or a jittered
grid from :func:`jittered` for stratified sampling) to directions, and returns
them with their density (:class:`Samples`).  View-dependent samplers
(:class:`Sampler` subclasses) also evaluate their density at any direction
(:meth:`Sampler.pdf`), which mixtures and multiple importance sampling need.

Strategies, from blind to informed:

* uniform over the hemisphere, ``p = 1/(2π)``;
* cosine-weighted, ``p = cos θ / π`` (Malley's method through the concentric
  disk map of Shirley & Chiu 1997, which keeps stratification intact);
* the Phong lobe around the mirror direction ``R_v``:
  ``p(l) = (e+1)/(2π) (R_v·l)^e``;
* microfacet normal sampling (Walter et al. 2007, eqs. 28, 35 and the
  Blinn–Phong analogue): draw ``h`` with density ``D(h) (n·h)``, reflect
  ``l = 2 (v·h) h − v``, and convert the density with the Jacobian of that
  reflection, ``p(l) = D(h) (n·h) / (4 (v·h))``;
* for a sum of models, a one-sample mixture of the parts' samplers with
  weights from rough albedo estimates; evaluating the estimator with the full
  mixture density ``Σ_k w_k p_k(l)`` is the balance heuristic of multiple
  importance sampling (Veach & Guibas 1995).

Samples that land below the horizon are kept (with their density): the
integrand is zero there, so they contribute nothing but are counted.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._numeric import (
    ArgumentTypeError,
    _fmt,
    check_bool,
    check_budget,
    check_choice,
    check_count,
    check_nonnegative,
    check_positive,
    check_vectors,
    real_array,
)
from ..models import microfacet as _mf
from ..models.brdf import BRDF, Geometry, cos_power
from ..vec import orthonormal_basis

__all__ = [
    "Samples",
    "as_generator",
    "jittered",
    "jittered_batch",
    "square_to_uniform_hemisphere",
    "square_to_cosine_hemisphere",
    "uniform_hemisphere_pdf",
    "cosine_hemisphere_pdf",
    "sample_uniform",
    "sample_cosine",
    "sample_stratified",
    "Sampler",
    "UniformSampler",
    "CosineSampler",
    "PhongSampler",
    "MicrofacetSampler",
    "MixtureSampler",
    "importance_sampler",
    "sample_brdf",
    "f_cos_local",
]

_TWO_PI = 2.0 * math.pi
_N = np.array([0.0, 0.0, 1.0])


class Samples(NamedTuple):
    """Directions ``(..., 3)`` (local frame) and their density per steradian ``(...)``."""

    directions: np.ndarray
    pdf: np.ndarray


def as_generator(seed=None) -> np.random.Generator:
    """A :class:`numpy.random.Generator` from a seed (int or None) or a generator (returned as is)."""
    if isinstance(seed, np.random.Generator):
        return seed
    allowed = "None, an integer >= 0 or a numpy.random.Generator"
    if seed is None:
        return np.random.default_rng()
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (int, np.integer)):
        raise ArgumentTypeError(f"seed must be {allowed}; got {type(seed).__name__} {_fmt(seed)}")
    if seed < 0:
        raise ValueError(f"seed must be {allowed}; got {_fmt(seed)}")
    return np.random.default_rng(int(seed))


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
        raise ValueError(f"{name} must be {allowed}; got shape {arr.shape}: {_fmt(u)}")
    if arr.size and (np.min(arr) < 0 or np.max(arr) > 1):
        raise ValueError(f"{name} must be {allowed}; got values in [{np.min(arr):.6g}, {np.max(arr):.6g}]")
    return arr


def _directions(name: str, d) -> np.ndarray:
    return check_vectors(name, d, dtype=np.float64)


def jittered(count: int, seed=None) -> np.ndarray:
    """Stratified points of the unit square: one uniform point in each cell of a ``k_x × k_y`` grid.

    ``k_x = ⌊√count⌋`` and ``k_y = ⌊count / k_x⌋``, so ``k_x k_y <= count``
    points are returned (all of them when ``count`` is a product of two
    near-equal integers).  Rows are in random order, so any prefix is not
    biased toward one side of the square.

    Examples
    --------
    >>> u = jittered(16, seed=1)
    >>> u.shape, sorted(np.floor(u[:, 0] * 4).astype(int).tolist()) == sorted([0, 1, 2, 3] * 4)
    ((16, 2), True)
    """
    rng = as_generator(seed)
    u = jittered_batch((), count, rng)
    return u[rng.permutation(len(u))]


def jittered_batch(batch: tuple, count: int, seed=None) -> np.ndarray:
    """Independent jittered grids (see :func:`jittered`) for every index of ``batch``: ``batch + (k_x k_y, 2)``."""
    count = _count("count", count)
    if not isinstance(batch, tuple) or not all(isinstance(k, (int, np.integer)) and k >= 0 for k in batch):
        raise ArgumentTypeError(f"batch must be a tuple of integers >= 0; got {_fmt(batch)}")
    _check_size("batch", tuple(int(k) for k in batch) + (count,))
    rng = as_generator(seed)
    kx = math.isqrt(count)
    ky = count // kx
    i, j = np.meshgrid(np.arange(kx), np.arange(ky), indexing="ij")
    cells = np.stack([i.ravel(), j.ravel()], axis=-1).astype(np.float64)
    return (cells + rng.random(tuple(batch) + cells.shape)) / np.array([kx, ky], dtype=np.float64)


# --------------------------------------------------------------------------- blind warps
def square_to_uniform_hemisphere(u) -> Samples:
    """Uniform directions on the upper hemisphere: ``cos θ = u₀``, ``φ = 2π u₁``, ``p = 1/(2π)``.

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
    """``1/(2π)`` above the horizon (``z > 0``), 0 below."""
    d = _directions("d", d)
    return np.where(d[..., 2] > 0, 1.0 / _TWO_PI, 0.0)


def _concentric_disk(u: np.ndarray):
    """Shirley–Chiu concentric map of the square onto the unit disk (area preserving, low distortion)."""
    a = 2 * u[..., 0] - 1
    b = 2 * u[..., 1] - 1
    first = np.abs(a) > np.abs(b)
    r = np.where(first, a, b)
    with np.errstate(divide="ignore", invalid="ignore"):
        phi = np.where(
            first,
            (math.pi / 4) * (b / np.where(a != 0, a, 1.0)),
            (math.pi / 2) - (math.pi / 4) * (a / np.where(b != 0, b, 1.0)),
        )
    phi = np.where((a == 0) & (b == 0), 0.0, phi)
    return r * np.cos(phi), r * np.sin(phi)


def square_to_cosine_hemisphere(u) -> Samples:
    """Cosine-weighted directions (Malley's method): ``p = cos θ / π``.

    Examples
    --------
    >>> s = square_to_cosine_hemisphere(np.array([0.5, 0.5]))
    >>> s.directions.tolist(), round(float(s.pdf) * math.pi, 12)
    ([0.0, 0.0, 1.0], 1.0)
    """
    u = _unit_square("u", u)
    x, y = _concentric_disk(u)
    z = np.sqrt(np.clip(1 - x * x - y * y, 0.0, None))
    return Samples(np.stack([x, y, z], axis=-1), z / math.pi)


def cosine_hemisphere_pdf(d) -> np.ndarray:
    """``max(cos θ, 0) / π``."""
    d = _directions("d", d)
    return np.maximum(d[..., 2], 0.0) / math.pi


def sample_uniform(count: int, seed=None) -> Samples:
    """``count`` independent uniform hemisphere directions (see :func:`square_to_uniform_hemisphere`)."""
    u = as_generator(seed).random((_count("count", count), 2))
    return square_to_uniform_hemisphere(u)


def sample_cosine(count: int, seed=None) -> Samples:
    """``count`` independent cosine-weighted directions (see :func:`square_to_cosine_hemisphere`)."""
    u = as_generator(seed).random((_count("count", count), 2))
    return square_to_cosine_hemisphere(u)


def sample_stratified(count: int, seed=None, warp: str = "cosine") -> Samples:
    """A jittered grid (:func:`jittered`) mapped to the hemisphere by ``warp`` ("cosine" or "uniform")."""
    warp = check_choice("warp", warp, ("cosine", "uniform"))
    u = jittered(count, seed)
    if warp == "cosine":
        return square_to_cosine_hemisphere(u)
    return square_to_uniform_hemisphere(u)


# --------------------------------------------------------------------------- view-dependent samplers
def _local_v(v) -> np.ndarray:
    v = np.asarray(v, dtype=np.float64)
    if v.shape[-1:] != (3,):
        raise ValueError(f"v must have shape (..., 3); got shape {v.shape}")
    return v


def _dot(a, b):
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]


class Sampler:
    """Base class: draws ``l`` for a viewer ``v`` (local frame) and evaluates the density.

    ``sample(u, v)`` takes unit-square points ``u`` ``(..., 2)`` (finite, in
    ``[0, 1]``) and view directions ``v`` broadcastable to ``(..., 3)`` (finite
    real vectors); ``pdf(l, v)`` is the density per steradian of the
    directions it produces, on the whole sphere.  Both check their arguments
    (ValueError naming the parameter; :class:`~lighting._numeric.ArgumentTypeError`
    for text, complex or objects) and then call ``_sample`` / ``_pdf``, which
    subclasses implement and the integrators call directly on checked data.
    """

    name = "sampler"

    def sample(self, u, v) -> Samples:
        """Directions and densities for unit-square points ``u`` ``(..., 2)`` and viewers ``v`` ``(..., 3)``."""
        u = _unit_square("u", u)
        v = check_vectors("v", v, dtype=np.float64)
        _broadcast("u", u.shape[:-1], "v", v.shape[:-1])
        _check_size("u", u.shape[:-1], v.shape[:-1])
        return self._sample(u, v)

    def pdf(self, l, v) -> np.ndarray:  # noqa: E741
        """Density per steradian of :meth:`sample`'s directions at ``l`` ``(..., 3)`` for viewers ``v``."""
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


class CosineSampler(_ViewIndependentSampler):
    """Cosine-weighted over the hemisphere (ignores ``v``): exact importance sampling for Lambert."""

    name = "cosine"
    _warp = staticmethod(square_to_cosine_hemisphere)
    _density = staticmethod(cosine_hemisphere_pdf)


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


class PhongSampler(Sampler):
    r"""The Phong lobe around the mirror direction ``R_v = 2 n (n·v) − v``.

        p(l) = (e + 1)/(2π) · max(R_v·l, 0)^e        (on the whole sphere)

    drawn as ``cos ψ = (1 − u₀)^{1/(e+1)}``, ``φ = 2π u₁`` around ``R_v``.  For
    the slides' Phong BRDF ``f_r (n·l) = k_s (R_v·l)^e / π`` the weight
    ``f_r (n·l) / p`` is the constant ``2 k_s / (e + 1)`` above the horizon.

    Examples
    --------
    >>> s = PhongSampler(10).sample(np.array([0.0, 0.25]), np.array([0.0, 0.0, 1.0]))
    >>> s.directions.round(12).tolist(), round(float(s.pdf) * 2 * math.pi, 12)  # R_v itself, density (e+1)/(2π)
    ([0.0, 0.0, 1.0], 11.0)
    """

    name = "phong"

    def __init__(self, exponent: float):
        self.exponent = check_nonnegative("exponent", exponent)

    def __repr__(self):
        return f"PhongSampler({self.exponent!r})"

    @staticmethod
    def _mirror(v):
        return v * np.array([-1.0, -1.0, 1.0])

    def _sample(self, u, v):
        u = np.asarray(u, dtype=np.float64)
        v = _local_v(v)
        e = self.exponent
        omc = _one_minus_cos_power(u[..., 0], e + 1)
        shape = np.broadcast_shapes(omc.shape, v.shape[:-1])
        r = np.broadcast_to(self._mirror(v), shape + (3,))
        l = _around(r, np.broadcast_to(omc, shape), np.broadcast_to(_TWO_PI * u[..., 1], shape))  # noqa: E741
        # pdf = (e+1)/(2π) cos^e α with cos α = (1 − u₀)^{1/(e+1)}; u₀ = 1 is the lobe's rim, where
        # log1p(−1) = −inf: the density there is 0 (1 when e = 0, never 0·inf).
        with np.errstate(under="ignore", divide="ignore"):
            log_c = np.log1p(-np.minimum(u[..., 0], 1.0))
            scaled = e / (e + 1) * log_c if e > 0 else np.zeros_like(log_c)
            pdf = (e + 1) / _TWO_PI * np.exp(scaled)
        return Samples(l, np.broadcast_to(pdf, shape))

    def _pdf(self, l, v):  # noqa: E741
        l, v = np.asarray(l, dtype=np.float64), _local_v(v)  # noqa: E741
        d = l - self._mirror(v)
        lobe = cos_power(np.clip(0.5 * _dot(d, d), 0.0, 2.0), self.exponent)
        return (self.exponent + 1) / _TWO_PI * lobe


class MicrofacetSampler(Sampler):
    r"""Sample a microfacet normal ``h`` with density ``D(h) (n·h)``, then reflect ``v`` about it.

    Inverse CDFs in ``θ_h`` (``φ_h = 2π u₁``; Walter et al. 2007):

    * Beckmann: ``tan²θ_h = −α² ln(1 − u₀)``
    * GGX:      ``tan²θ_h = α² u₀ / (1 − u₀)``
    * Blinn–Phong ``(e+2)/(2π)(n·h)^e``: ``cos θ_h = (1 − u₀)^{1/(e+2)}``

    and with ``l = 2 (v·h) h − v``, ``dω_h / dω_l = 1 / (4 |v·h|)``, so

        p(l) = D(h) (n·h) / (4 |v·h|).

    Parameters
    ----------
    ndf : {"beckmann", "ggx", "blinn-phong"}
    alpha : float > 0
        Roughness α (for "blinn-phong", ``e = 2/α² − 2``, as
        :class:`lighting.models.brdf.CookTorrance` uses) — or give ``exponent``.
    exponent : float >= 0, optional
        Blinn–Phong exponent ``e`` directly.

    Examples
    --------
    >>> s = MicrofacetSampler("ggx", 0.5)
    >>> h = s.sample_normals(np.array([0.0, 0.0]))
    >>> h.directions.tolist(), round(float(h.pdf) * math.pi * 0.25, 12)  # D(n)·1 = 1/(π α²)
    ([0.0, 0.0, 1.0], 1.0)
    """

    name = "microfacet"

    def __init__(self, ndf: str, alpha: float | None = None, *, exponent: float | None = None):
        ndf = check_choice("ndf", ndf, ("beckmann", "ggx", "blinn-phong"))
        self.ndf = ndf
        if ndf == "blinn-phong" and exponent is not None:
            self.alpha = None
            self.exponent = check_nonnegative("exponent", exponent)
        else:
            if alpha is None:
                need = "alpha (roughness > 0) or exponent (>= 0)" if ndf == "blinn-phong" else "alpha (roughness > 0)"
                raise ValueError(f"{need} is required for ndf={ndf!r}; got alpha=None")
            self.alpha = check_positive("alpha", alpha)
            self.exponent = float(_mf.blinn_phong_exponent(self.alpha)) if ndf == "blinn-phong" else None

    def __repr__(self):
        par = f"exponent={self.exponent!r}" if self.alpha is None else f"alpha={self.alpha!r}"
        return f"MicrofacetSampler({self.ndf!r}, {par})"

    # -- normals ------------------------------------------------------------------
    def normal_pdf(self, h) -> np.ndarray:
        """``D(h) (n·h)`` for unit ``h`` ``(..., 3)`` (0 below the horizon)."""
        return self._normal_pdf(_directions("h", h))

    def _normal_pdf(self, h) -> np.ndarray:
        c = h[..., 2]
        s2 = np.clip(h[..., 0] ** 2 + h[..., 1] ** 2, 0.0, 1.0)
        # h is checked (or built here): the NDFs' unchecked forms, as the models' own evaluation uses.
        dt = c.dtype
        if self.ndf == "blinn-phong":
            d = _mf._blinn_phong_ndf(c, self.exponent, s2, dt)
        elif self.ndf == "beckmann":
            d = _mf._beckmann_ndf(c, self.alpha, s2, dt)
        else:
            d = _mf._ggx_ndf(c, self.alpha, s2, dt)
        return d * np.maximum(c, 0.0)

    def sample_normals(self, u) -> Samples:
        """Microfacet normals ``h`` with density ``D(h)(n·h)`` (upper hemisphere) from points ``u`` ``(..., 2)``."""
        u = _unit_square("u", u)
        _check_size("u", u.shape[:-1])
        return self._sample_normals(u)

    def _sample_normals(self, u) -> Samples:
        u0 = np.minimum(u[..., 0], 1.0)
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            if self.ndf == "blinn-phong":
                omc = _one_minus_cos_power(u0, self.exponent + 2)
                cos_t = 1.0 - omc
                sin_t = np.sqrt(np.clip(omc * (2.0 - omc), 0.0, None))
            else:
                a2 = self.alpha * self.alpha
                if self.ndf == "beckmann":
                    tan2 = -a2 * np.log1p(-u0)
                else:
                    tan2 = np.where(u0 < 1, a2 * u0 / np.where(u0 < 1, 1.0 - u0, 1.0), np.inf)
                cos_t = np.where(np.isfinite(tan2), 1.0 / np.sqrt(1.0 + tan2), 0.0)
                sin_t = np.where(np.isfinite(tan2), np.sqrt(tan2) * cos_t, 1.0)
        phi = _TWO_PI * u[..., 1]
        h = np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), cos_t], axis=-1)
        return Samples(h, self._normal_pdf(h))

    # -- directions ---------------------------------------------------------------
    def _sample(self, u, v):
        v = _local_v(v)
        hs = self._sample_normals(u)
        shape = np.broadcast_shapes(hs.pdf.shape, v.shape[:-1])
        h = np.broadcast_to(hs.directions, shape + (3,))
        vh = _dot(v, h)
        l = 2 * vh[..., None] * h - v  # noqa: E741
        return Samples(l, self._to_l(np.broadcast_to(hs.pdf, shape), vh))

    @staticmethod
    def _to_l(pdf_h, vh):
        den = 4.0 * np.abs(vh)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            p = np.where(den > 0, pdf_h / np.where(den > 0, den, 1.0), 0.0)
        return np.nan_to_num(p, nan=0.0, posinf=np.finfo(np.float64).max)

    def _pdf(self, l, v):  # noqa: E741
        l, v = np.asarray(l, dtype=np.float64), _local_v(v)  # noqa: E741
        s = l + v
        length = np.sqrt(_dot(s, s))
        with np.errstate(divide="ignore", invalid="ignore"):
            h = np.where(length[..., None] > 0, s / np.where(length > 0, length, 1.0)[..., None], 0.0)
        # The sampled h lies in the upper hemisphere; l + v may point either way along it.
        h = np.where(h[..., 2:3] < 0, -h, h)
        return np.where(length > 0, self._to_l(self._normal_pdf(h), _dot(v, h)), 0.0)


class MixtureSampler(Sampler):
    r"""One-sample mixture of samplers: pick sampler ``k`` with probability ``w_k(v)``.

        p(l) = Σ_k w_k(v) p_k(l)

    The first coordinate of ``u`` chooses the component and is then rescaled to
    ``[0, 1)``, so stratification of ``u`` carries through.  Estimating with
    ``f / p`` (the full mixture density) is the balance heuristic.

    Parameters
    ----------
    samplers : sequence of Sampler
    weights : callable or array_like
        ``weights(v) → (..., K)`` (nonnegative, not all zero), or fixed weights ``(K,)``.
    """

    name = "mixture"

    def __init__(self, samplers, weights):
        allowed = "a nonempty sequence of Sampler"
        if isinstance(samplers, (str, bytes, Sampler)) or not hasattr(samplers, "__iter__"):
            raise ArgumentTypeError(f"samplers must be {allowed}; got {type(samplers).__name__} {_fmt(samplers)}")
        self.samplers = tuple(samplers)
        if not self.samplers:
            raise ValueError(f"samplers must be {allowed}; got an empty sequence")
        if not all(isinstance(s, Sampler) for s in self.samplers):
            raise ArgumentTypeError(f"samplers must be {allowed}; got {_fmt(samplers)}")
        if callable(weights):
            self._weights = weights
        else:
            allowed = f"{len(self.samplers)} finite numbers >= 0, not all 0, or a callable"
            w = real_array("weights", weights, allowed=allowed, dtype=np.float64)
            if w.shape != (len(self.samplers),) or np.any(w < 0) or w.sum() <= 0:
                raise ValueError(f"weights must be {allowed}; got {_fmt(weights)}")
            w = w / w.sum()
            self._weights = lambda v: np.broadcast_to(w, np.shape(v)[:-1] + w.shape)

    def __repr__(self):
        return f"MixtureSampler({list(self.samplers)!r})"

    def weights(self, v) -> np.ndarray:
        """Normalized component probabilities for viewer ``v`` ``(..., 3)``: ``(..., K)``."""
        return self._weights_of(_directions("v", v))

    def _weights_of(self, v) -> np.ndarray:
        w = np.asarray(self._weights(v), dtype=np.float64)
        return w / np.sum(w, axis=-1, keepdims=True)

    def _sample(self, u, v):
        u = np.asarray(u, dtype=np.float64)
        v = _local_v(v)
        w = self._weights_of(v)
        cdf = np.cumsum(w, axis=-1)
        shape = np.broadcast_shapes(u.shape[:-1], v.shape[:-1])
        cdf = np.broadcast_to(cdf, shape + cdf.shape[-1:])
        wk = np.broadcast_to(w, cdf.shape)
        u0 = np.broadcast_to(u[..., 0], shape)
        k = np.minimum(np.sum(u0[..., None] >= cdf, axis=-1), len(self.samplers) - 1)
        lo = np.take_along_axis(cdf, k[..., None], -1)[..., 0] - np.take_along_axis(wk, k[..., None], -1)[..., 0]
        width = np.take_along_axis(wk, k[..., None], -1)[..., 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            u0r = np.clip(
                np.where(width > 0, (u0 - lo) / np.where(width > 0, width, 1.0), 0.5), 0.0, np.nextafter(1, 0)
            )
        ur = np.stack([u0r, np.broadcast_to(u[..., 1], shape)], axis=-1)
        l = np.zeros(shape + (3,))  # noqa: E741
        for i, s in enumerate(self.samplers):
            cand = s._sample(ur, v).directions
            l = np.where((k == i)[..., None], cand, l)  # noqa: E741
        return Samples(l, self._pdf(l, v))

    def _pdf(self, l, v):  # noqa: E741
        v = _local_v(v)
        w = self._weights_of(v)
        l = np.asarray(l, dtype=np.float64)  # noqa: E741
        total = 0.0
        for i, s in enumerate(self.samplers):
            total = total + w[..., i] * s._pdf(l, v)
        return total


# --------------------------------------------------------------------------- BRDF dispatch
def _check_brdf(brdf) -> BRDF:
    if not isinstance(brdf, BRDF):
        raise ArgumentTypeError(
            f"brdf must be a lighting.models.brdf model (Lambert, Phong, ...); got {type(brdf).__name__} {_fmt(brdf)}"
        )
    return brdf


def f_cos_local(brdf: BRDF, l, v) -> np.ndarray:
    """``f_r (n·l)`` in the local frame (``n = +z``), float64, ``(..., 3)``, for unit ``l`` and ``v`` ``(..., 3)``."""
    _check_brdf(brdf)
    l = _directions("l", l)  # noqa: E741
    v = _directions("v", v)
    _broadcast("l", l.shape[:-1], "v", v.shape[:-1])
    _check_size("l", l.shape[:-1], v.shape[:-1])
    return _f_cos(brdf, l, v)


def _f_cos(brdf: BRDF, l, v) -> np.ndarray:  # noqa: E741
    """:func:`f_cos_local` on checked float64 arrays (the integrators' hot path)."""
    shape = np.broadcast_shapes(l.shape, v.shape)
    g = Geometry(np.broadcast_to(_N, shape), np.broadcast_to(l, shape), np.broadcast_to(v, shape), unit=True)
    return np.asarray(brdf.eval_cos_geometry(g), dtype=np.float64)


def _part_sampler(part: BRDF) -> Sampler:
    return part.sampler()


_TABLE_MU = np.linspace(0.0, 1.0, 17)


def _rough_albedo_table(part: BRDF, sampler: Sampler) -> np.ndarray:
    """Albedo (channel mean) of ``part`` at ``cos θ_v`` in :data:`_TABLE_MU`, by 64 midpoint-grid samples."""
    g = (np.arange(8) + 0.5) / 8
    u = np.stack(np.meshgrid(g, g, indexing="ij"), axis=-1).reshape(-1, 2)
    mu = np.maximum(_TABLE_MU, 1e-3)
    v = np.stack([np.sqrt((1 - mu) * (1 + mu)), np.zeros_like(mu), mu], axis=-1)[:, None, :]
    s = sampler._sample(u, v)
    f = _f_cos(part, s.directions, np.broadcast_to(v, s.directions.shape)).mean(axis=-1)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        w = np.where(s.pdf > 0, f / np.where(s.pdf > 0, s.pdf, 1.0), 0.0)
    return np.nan_to_num(w, nan=0.0, posinf=0.0).mean(axis=-1)


def importance_sampler(brdf: BRDF) -> Sampler:
    """The importance sampler for a model: each model's own (``model.sampler()``), mixed for a sum.

    * :class:`~lighting.models.brdf.Lambert` → cosine-weighted;
    * :class:`~lighting.models.brdf.Phong` → Phong lobe around ``R_v`` (uniform for ``e = 0``);
    * :class:`~lighting.models.brdf.BlinnPhong` → Blinn–Phong normal distribution
      ``∝ (n·h)^{e+1}`` (uniform / cosine for ``e = 0``);
    * :class:`~lighting.models.brdf.CookTorrance` → its NDF's ``D(h)(n·h)``;
    * a sum → :class:`MixtureSampler` of the parts' samplers, weighted by each
      part's albedo, tabulated over ``cos θ_v`` and interpolated (at least 1 %
      each, so no part with nonzero reflectance is starved).

    Examples
    --------
    >>> from lighting.models.brdf import Lambert, Phong
    >>> importance_sampler(Lambert(0.5) + Phong(0.5, 20))
    MixtureSampler([CosineSampler(), PhongSampler(20.0)])
    """
    parts = _check_brdf(brdf).parts
    if len(parts) == 1:
        return _part_sampler(parts[0])
    samplers = [_part_sampler(p) for p in parts]
    table = np.stack([_rough_albedo_table(p, s) for p, s in zip(parts, samplers, strict=True)], axis=-1)
    total = table.sum(axis=-1, keepdims=True)
    k = len(parts)
    table = np.where(total > 0, table / np.where(total > 0, total, 1.0), 1.0 / k)
    table = np.maximum(table, 0.01)
    table = table / table.sum(axis=-1, keepdims=True)

    def weights(v):
        mu = np.clip(v[..., 2], 0.0, 1.0)
        return np.stack([np.interp(mu, _TABLE_MU, table[:, i]) for i in range(k)], axis=-1)

    return MixtureSampler(samplers, weights)


def sample_brdf(brdf: BRDF, v, count: int, seed=None, *, stratified: bool = False) -> Samples:
    """``count`` directions importance-sampled for ``brdf`` and viewer ``v`` (local frame).

    ``v`` of shape ``(..., 3)`` gives directions ``(..., count', 3)`` and densities
    ``(..., count')``; ``count' = count`` unless ``stratified`` (then the
    :func:`jittered` grid size).

    Examples
    --------
    >>> from lighting.models.brdf import Phong
    >>> s = sample_brdf(Phong(1.0, 50), np.array([0.0, 0.0, 1.0]), 1000, seed=3)
    >>> s.directions.shape, bool(np.all(s.directions[:, 2] > 0.5))
    ((1000, 3), True)
    """
    sampler = importance_sampler(brdf)
    count = _count("count", count)
    stratified = check_bool("stratified", stratified)
    v = _directions("v", v)
    _check_size("count", v.shape[:-1] + (count,))
    rng = as_generator(seed)
    u = jittered(count, rng) if stratified else rng.random((count, 2))
    return sampler._sample(u, v[..., None, :])

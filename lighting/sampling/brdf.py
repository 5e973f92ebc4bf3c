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

The samplers of single models belong to the models (each model's ``sampler()``, defined
beside it: :mod:`lighting.sampling.base`, :mod:`lighting.models.lambert`,
:mod:`lighting.models.phong`, :mod:`lighting.sampling.microfacet`) and are re-exported
here; this module adds the jittered grids, the mixtures, the dispatch by model and the
estimators' helpers.

Samples that land below the horizon are kept (with their density): the
integrand is zero there, so they contribute nothing but are counted.
"""

from __future__ import annotations

import math

import numpy as np

from .._text import quote
from .._validate import ArgumentTypeError, check_bool, check_choice, real_array
from ..models.base import BRDFFlags
from ..models.brdf import BRDF, Geometry
from ..models.lambert import CosineSampler, cosine_hemisphere_pdf, square_to_cosine_hemisphere
from ..models.mirror import MirrorSampler
from ..models.phong import PhongSampler
from .base import (
    Sampler,
    Samples,
    UniformSampler,
    _broadcast,
    _check_size,
    _count,
    _directions,
    _local_v,
    square_to_uniform_hemisphere,
    uniform_hemisphere_pdf,
)
from .microfacet import MicrofacetSampler, VisibleNormalSampler

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
    "VisibleNormalSampler",
    "MirrorSampler",
    "MixtureSampler",
    "importance_sampler",
    "sample_brdf",
    "f_cos_local",
]


_N = np.array([0.0, 0.0, 1.0])


def as_generator(seed=None) -> np.random.Generator:
    """A :class:`numpy.random.Generator` from a seed (int or None) or a generator (returned as is).

    Parameters
    ----------
    seed : None, int >= 0 or numpy.random.Generator

    Returns
    -------
    numpy.random.Generator
    """
    if isinstance(seed, np.random.Generator):
        return seed
    allowed = "None, an integer >= 0 or a numpy.random.Generator"
    if seed is None:
        return np.random.default_rng()
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (int, np.integer)):
        raise ArgumentTypeError(f"seed must be {allowed}; got {type(seed).__name__} {quote(seed)}")
    if seed < 0:
        raise ValueError(f"seed must be {allowed}; got {quote(seed)}")
    return np.random.default_rng(int(seed))


def jittered(count: int, seed=None) -> np.ndarray:
    """Stratified points of the unit square: one uniform point in each cell of a ``k_x × k_y`` grid.

    ``k_x = ⌊√count⌋`` and ``k_y = ⌊count / k_x⌋``, so ``k_x k_y <= count``
    points are returned (all of them when ``count`` is a product of two
    near-equal integers).  Rows are in random order, so any prefix is not
    biased toward one side of the square.

    Parameters
    ----------
    count : int >= 1
        The number of points asked for.
    seed : None, int >= 0 or numpy.random.Generator

    Returns
    -------
    ndarray, shape (k_x k_y, 2)

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
    """Independent jittered grids (see :func:`jittered`) for every index of ``batch``.

    Parameters
    ----------
    batch : tuple of int >= 0
        The leading shape.
    count : int >= 1
        Points per grid, as :func:`jittered`.
    seed : None, int >= 0 or numpy.random.Generator

    Returns
    -------
    ndarray, shape batch + (k_x k_y, 2)
        Rows in grid order (not shuffled).
    """
    count = _count("count", count)
    if not isinstance(batch, tuple) or not all(isinstance(k, (int, np.integer)) and k >= 0 for k in batch):
        raise ArgumentTypeError(f"batch must be a tuple of integers >= 0; got {quote(batch)}")
    _check_size("batch", tuple(int(k) for k in batch) + (count,))
    rng = as_generator(seed)
    kx = math.isqrt(count)
    ky = count // kx
    i, j = np.meshgrid(np.arange(kx), np.arange(ky), indexing="ij")
    cells = np.stack([i.ravel(), j.ravel()], axis=-1).astype(np.float64)
    return (cells + rng.random(tuple(batch) + cells.shape)) / np.array([kx, ky], dtype=np.float64)


def sample_uniform(count: int, seed=None) -> Samples:
    """``count`` independent uniform hemisphere directions (see :func:`square_to_uniform_hemisphere`).

    Parameters
    ----------
    count : int >= 1
    seed : None, int >= 0 or numpy.random.Generator

    Returns
    -------
    Samples
    """
    u = as_generator(seed).random((_count("count", count), 2))
    return square_to_uniform_hemisphere(u)


def sample_cosine(count: int, seed=None) -> Samples:
    """``count`` independent cosine-weighted directions (see :func:`square_to_cosine_hemisphere`).

    Parameters
    ----------
    count : int >= 1
    seed : None, int >= 0 or numpy.random.Generator

    Returns
    -------
    Samples
    """
    u = as_generator(seed).random((_count("count", count), 2))
    return square_to_cosine_hemisphere(u)


def sample_stratified(count: int, seed=None, warp: str = "cosine") -> Samples:
    """A jittered grid (:func:`jittered`) mapped to the hemisphere by ``warp``.

    Parameters
    ----------
    count : int >= 1
    seed : None, int >= 0 or numpy.random.Generator
    warp : {"cosine", "uniform"}

    Returns
    -------
    Samples
    """
    warp = check_choice("warp", warp, ("cosine", "uniform"))
    u = jittered(count, seed)
    if warp == "cosine":
        return square_to_cosine_hemisphere(u)
    return square_to_uniform_hemisphere(u)


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
            raise ArgumentTypeError(f"samplers must be {allowed}; got {type(samplers).__name__} {quote(samplers)}")
        self.samplers = tuple(samplers)
        if not self.samplers:
            raise ValueError(f"samplers must be {allowed}; got an empty sequence")
        if not all(isinstance(s, Sampler) for s in self.samplers):
            raise ArgumentTypeError(f"samplers must be {allowed}; got {quote(samplers)}")
        if callable(weights):
            self._weights = weights
        else:
            allowed = f"{len(self.samplers)} finite numbers >= 0, not all 0, or a callable"
            w = real_array("weights", weights, allowed=allowed, dtype=np.float64)
            if w.shape != (len(self.samplers),) or np.any(w < 0) or w.sum() <= 0:
                raise ValueError(f"weights must be {allowed}; got {quote(weights)}")
            w = w / w.sum()
            self._weights = lambda v: np.broadcast_to(w, np.shape(v)[:-1] + w.shape)

    def __repr__(self):
        return f"MixtureSampler({list(self.samplers)!r})"

    def weights(self, v) -> np.ndarray:
        """Normalized component probabilities for viewers ``v``.

        Parameters
        ----------
        v : array_like, shape (..., 3)

        Returns
        -------
        ndarray, shape (..., K)
        """
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
        # An empty slot's width is replaced by 1: no division by zero.
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
            f"brdf must be a lighting.models.brdf model (Lambert, Phong, ...); got {type(brdf).__name__} {quote(brdf)}"
        )
    return brdf


def f_cos_local(brdf: BRDF, l, v) -> np.ndarray:
    """``f_r (n·l)`` in the local frame (``n = +z``).

    Parameters
    ----------
    brdf : BRDF
    l, v : array_like, shape (..., 3)
        Unit directions toward the light and the viewer, broadcasting together.

    Returns
    -------
    ndarray, shape (..., 3)
        float64.
    """
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

    * :class:`~lighting.models.lambert.Lambert` → cosine-weighted;
    * :class:`~lighting.models.phong.Phong` → Phong lobe around ``R_v`` (uniform for ``e = 0``);
    * :class:`~lighting.models.blinn_phong.BlinnPhong` → Blinn–Phong normal distribution
      ``∝ (n·h)^{e+1}`` (uniform / cosine for ``e = 0``);
    * :class:`~lighting.models.cook_torrance.CookTorrance` → its NDF's ``D(h)(n·h)``;
    * a sum → :class:`MixtureSampler` of the parts' samplers, weighted by each
      part's albedo, tabulated over ``cos θ_v`` and interpolated (at least 1 %
      each, so no part with nonzero reflectance is starved);
    * :class:`~lighting.models.mirror.Mirror` (``BRDFFlags.DELTA``) → its
      :class:`~lighting.models.mirror.MirrorSampler` (``delta = True``: every draw is ``R_v``,
      ``pdf`` 1 as a discrete probability, ``weight(v)`` its reflectance); a sum of delta parts only → one
      such sampler with their reflectances added.  In a sum with smooth parts the delta parts are left
      out of the mixture (their density is 0 at every direction the others draw, and they would add
      nothing to ``f (n·l)/p``): the sampler is the smooth parts', and the integrators add the delta
      parts exactly (:mod:`lighting.integrate._delta`).

    Parameters
    ----------
    brdf : BRDF

    Returns
    -------
    Sampler

    Examples
    --------
    >>> from lighting.models.brdf import Lambert, Phong
    >>> importance_sampler(Lambert(0.5) + Phong(0.5, 20))
    MixtureSampler([CosineSampler(), PhongSampler(20.0)])
    """
    parts = _check_brdf(brdf).parts
    smooth = tuple(p for p in parts if BRDFFlags.DELTA not in p.flags)
    if not smooth:
        # Delta parts only: they share the one direction R_v, and their weights add.  (Imported here: the
        # integrators import this module.)
        from ..integrate._delta import _DeltaSum

        return _part_sampler(parts[0]) if len(parts) == 1 else MirrorSampler(_DeltaSum(parts))
    parts = smooth
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

    Parameters
    ----------
    brdf : BRDF
    v : array_like, shape (..., 3)
        Viewers in the local frame.
    count : int >= 1
    seed : None, int >= 0 or numpy.random.Generator
    stratified : bool
        Draw from a jittered grid instead of independent uniforms.

    Returns
    -------
    Samples

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

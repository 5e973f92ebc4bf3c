r"""Image-based lighting: the fast split-sum approximation beside its Monte-Carlo reference.

Under a distant environment the rendering equation (CMSC 435 deck),

$$
L_o(v) = ∫_Ω f_r(v, l)\, L_i(l)\, (n·l)\, dω_l,
$$

has two ways of being evaluated per pixel here:

**Fast** (:func:`split_sum_radiance`): each part of the model is split by its
:class:`~lighting.models.protocol.Lobe`,

* a lobe about the normal (diffuse) reflects ``ρ(μ_v) E(n) / π``, with ``E`` the SH9 irradiance
  (Ramamoorthi & Hanrahan 2001) — exact for Lambert up to SH9's truncation;
* a lobe about the mirror direction ``r = 2 n (n·v) − v`` (Phong's ``(r·l)^e``, width ``σ``) or of
  half vectors about ``n`` (Blinn–Phong, microfacets, width ``σ_h``; the reflected lobe is about
  twice as wide, ``σ = 2 σ_h``) reflects ``ρ(μ_v) · \bar L(r, σ)``: the split sum (Karis 2013), the
  part's directional albedo times the environment averaged over a lobe of that width
  (:class:`~lighting.integrate.prefilter.PrefilteredEnvironment`): the von Mises–Fisher lobe for a
  mirror lobe, Karis's ``D(h) (n·l)`` with ``n = v = r`` for a half-vector lobe (Beckmann's shape, or
  GGX's with its long tails: :attr:`~lighting.models.protocol.Lobe.tails`);
* a delta part (the ideal mirror) reflects ``R(μ_v) L(r)`` exactly.

``ρ(μ_v)`` is the engine's own directional albedo of the part: the ``E(μ, α)`` table of
:mod:`lighting.models.energy` for a microfacet part with ``F = 1`` (times ``k_s``), otherwise a
table over ``θ_v`` computed once per part by :func:`lighting.integrate.directional_albedo`
(deterministic quadrature).  What the split sum leaves out — the lobe's shape at grazing views, its
off-specular shift, the environment varying across it — is measured, not assumed: against the
reference in the accuracy report (``report accuracy --only ibl``).

**Reference** (:class:`ProgressiveRadiance`): Monte Carlo with multiple importance sampling (the
model's sampler and the environment's, balance heuristic) of :func:`outgoing_radiance`, accumulated
pass after pass with a per-pixel standard error from the spread of the passes, so an image refines
while a viewer rests.

References
----------
B. Karis, "Real Shading in Unreal Engine 4", SIGGRAPH 2013 course notes.
R. Ramamoorthi and P. Hanrahan, "An efficient representation for irradiance environment maps",
SIGGRAPH 2001.
"""

from __future__ import annotations

import math
import time

import numpy as np

from .._budget import check_budget
from .._recent import Recent
from .._text import quote
from .._validate import ArgumentTypeError, check_count, check_vectors
from ..lights.environment import as_environment
from ..numerics import working_dtype
from ..sampling.brdf import _check_brdf
from ..shading.batch import in_blocks
from ._delta import delta_albedo, delta_radiance, split_delta
from .prefilter import PrefilteredEnvironment, kernel_of_lobe, prefilter_environment
from .radiance import _frames, _radiance_batch, _to_world

__all__ = ["ALBEDO_ANGLES", "lobe_albedo", "lobe_sigma", "split_sum_radiance", "ProgressiveRadiance"]

#: View angles (radians) of the albedo tables: 0° to 88.5° in 1.5° steps, and 90° (held at the 88.5° value).
ALBEDO_ANGLES = np.append(np.radians(np.arange(0.0, 89.6, 1.5)), math.pi / 2)
#: Albedo tables kept (the one used longest ago goes first).
_albedo_cache = Recent(64)
#: Pixels per block of a split-sum re-shade (a multiple of 64; the blocks are balanced between the shading threads, each
#: pixel computed on its own): few enough that a block's arrays stay in the processor's caches, many enough that the
#: shading threads seldom wait on each other for the interpreter between its NumPy passes (``bench --ibl``).
RESHADE_BLOCK = 1 << 16


def lobe_sigma(lobe) -> float:
    """The angular width ``σ`` (radians) of the reflected lobe about the mirror direction; ``inf``: diffuse.

    Parameters
    ----------
    lobe : Lobe or None
        A model's :meth:`~lighting.models.base.BRDF.lobe`.

    Returns
    -------
    float
        ``width`` for a ``"mirror"`` lobe, ``2 width`` for a ``"half"`` lobe (a half vector tilted by
        ``θ_h`` reflects ``l`` by ``2 θ_h``), ``inf`` for a ``"normal"`` lobe, no lobe, or an unknown one
        (``None``: treated as diffuse, the coarsest guess).

    Examples
    --------
    >>> from lighting.models.brdf import Phong, BlinnPhong
    >>> round(lobe_sigma(Phong(1.0, 100).lobe()), 6), round(lobe_sigma(BlinnPhong(1.0, 100).lobe()), 6)
    (0.1, 0.2)
    """
    if lobe is None or lobe.axis == "normal" or not math.isfinite(lobe.width):
        return math.inf
    return float(lobe.width) * (2.0 if lobe.axis == "half" else 1.0)


def _energy_table_albedo(part):
    """``k_s E(μ, α)`` from :func:`lighting.models.energy.albedo_table` where it applies (``F = 1``), else None."""
    mf = part.microfacet()
    if mf is None or mf.fresnel != "none" or mf.energy_compensation or not mf.isotropic or mf.denominator != "4":
        return None
    from ..models import energy

    try:
        table = energy.albedo_table(mf.ndf, mf.geometry)
    except (ValueError, TypeError):
        return None
    mu = np.cos(ALBEDO_ANGLES)
    return np.asarray(table.E(mu, float(mf.alpha_x)), dtype=np.float64)[:, None] * mf.specular


def lobe_albedo(part) -> np.ndarray:
    """The directional albedo ``ρ(θ_v)`` of one part at :data:`ALBEDO_ANGLES`, ``(len, 3)``; cached per part.

    Parameters
    ----------
    part : BRDF
        One part of a model (not a sum; not a delta).

    Returns
    -------
    ndarray
        Float64 RGB albedos; the last row (``θ_v = 90°``) repeats the one at 88.5° (a viewer on the horizon
        sees nothing, and the shading gives 0 there; just above it a Lambert surface still reflects ``k_d``).

    Notes
    -----
    A microfacet part with ``F = 1`` reads the engine's ``E(μ, α)`` table (:mod:`lighting.models.energy`,
    accurate to 2e-3); every other part is integrated by deterministic quadrature
    (:func:`lighting.integrate.directional_albedo`, 4096 nodes per angle) on first use.
    """
    key = (type(part).__qualname__, repr(part))
    table = _albedo_cache.get(key)
    if table is not None:
        return table
    table = _energy_table_albedo(part)
    if table is None:
        from .albedo import directional_albedo

        table = np.asarray(directional_albedo(part, ALBEDO_ANGLES[:-1]), dtype=np.float64)
        table = np.concatenate([table, table[-1:]])
    table = np.asarray(table, dtype=np.float64)
    table.setflags(write=False)
    return _albedo_cache.put(key, table)


def _albedo_at(table, theta, dt):
    """``table`` interpolated at the view angles ``theta`` (radians; linear in ``θ_v``): ``(..., 3)`` in ``dt``."""
    return np.stack(_albedo_columns(table, theta, dt), axis=-1)


def _albedo_columns(table, theta, dt):
    """:func:`_albedo_at`'s three channels, each an array of ``theta``'s shape in ``dt`` (one array for all three of a
    grey lobe, most materials' specular part: one channel's values are the same numbers in all three)."""
    if np.array_equal(table[:, 0], table[:, 1]) and np.array_equal(table[:, 0], table[:, 2]):
        grey = np.interp(theta, ALBEDO_ANGLES, table[:, 0]).astype(dt, copy=False)
        return [grey] * 3
    return [np.interp(theta, ALBEDO_ANGLES, table[:, c]).astype(dt, copy=False) for c in range(3)]


def _check_prefiltered(prefiltered):
    if isinstance(prefiltered, PrefilteredEnvironment):
        return prefiltered
    try:
        return prefilter_environment(prefiltered)
    except ArgumentTypeError:
        raise ArgumentTypeError(
            f"prefiltered must be a PrefilteredEnvironment (prefilter_environment(env)) or an environment; "
            f"got {type(prefiltered).__name__} {quote(prefiltered)}"
        ) from None


def split_sum_radiance(brdf, prefiltered, normals, view_dirs, *, split_terms: bool = False):
    r"""Reflected radiance under an environment by SH9 irradiance and the split sum (module notes).

    Parameters
    ----------
    brdf : BRDF
        Any model (sums included); each part is handled by its :meth:`~lighting.models.base.BRDF.lobe`.
    prefiltered : PrefilteredEnvironment or environment
        From :func:`~lighting.integrate.prefilter.prefilter_environment` (an environment is prefiltered
        here on every call: keep the prefiltered one to re-shade).
    normals, view_dirs : array_like, (..., 3), world frame
        Unit surface normals and unit directions toward the viewer (broadcast together).
    split_terms : bool
        Return ``{"diffuse": ..., "specular": ...}`` (normal lobes; mirror, half and delta lobes) instead
        of their sum.

    Returns
    -------
    ndarray, (..., 3) or dict
        ``L_o`` in the dtype of ``normals`` and ``view_dirs`` (float32 stays float32); 0 where
        ``n·v <= 0``.

    Examples
    --------
    >>> from lighting.models.brdf import Lambert
    >>> from lighting.lights.environment import ConstantEnvironment
    >>> pre = prefilter_environment(ConstantEnvironment(2.0), height=16)
    >>> split_sum_radiance(Lambert(0.5), pre, (0, 0, 1.0), (0.6, 0, 0.8)).round(6).tolist()  # furnace: k_d L
    [1.0, 1.0, 1.0]
    """
    brdf = _check_brdf(brdf)
    pre = _check_prefiltered(prefiltered)
    n = check_vectors("normals", normals)
    v = check_vectors("view_dirs", view_dirs)
    dt = working_dtype(n, v)
    shape = np.broadcast_shapes(n.shape, v.shape)
    check_budget("normals", math.prod(shape) * np.dtype(dt).itemsize * 12, what=f"{math.prod(shape) // 3} pixels")
    n = np.broadcast_to(n, shape).reshape(-1, 3).astype(dt, copy=False)
    v = np.broadcast_to(v, shape).reshape(-1, 3).astype(dt, copy=False)
    diffuse = np.zeros(n.shape, dtype=dt)
    specular = np.zeros(n.shape, dtype=dt)
    smooth, deltas = split_delta(brdf)
    # What every pixel reads of a part, made once before the blocks: its lobe's width and kernel, its albedo table.
    lobes = []
    for part in () if smooth is None else smooth.parts:
        lobe = part.lobe()
        lobes.append((lobe_sigma(lobe), kernel_of_lobe(lobe), lobe_albedo(part)))

    def block(rows):
        nn, vv = n[rows], v[rows]
        cos_v = np.einsum("ij,ij->i", nn, vv)
        r = 2 * cos_v[:, None] * nn - vv
        dif, spec = diffuse[rows], specular[rows]
        if deltas:
            reflectance = delta_albedo(deltas, np.clip(cos_v, 0, 1).astype(np.float64)).astype(dt)
            spec += reflectance * pre._lookup(r, 0.0, "mirror")
        irradiance = None
        theta_v = np.arccos(np.clip(cos_v.astype(np.float64), 0.0, 1.0))
        for sigma, kernel, table in lobes:
            rho = _albedo_at(table, theta_v, dt)
            if math.isinf(sigma):
                if irradiance is None:
                    irradiance = pre._irradiance_sh(nn) * np.asarray(1 / math.pi, dtype=dt)
                dif += rho * irradiance
            else:
                spec += rho * pre._lookup(r, min(sigma, pre.sigmas[-1]), kernel)
        unseen = ~(cos_v > 0)
        dif[unseen] = 0
        spec[unseen] = 0

    # Every pixel on its own: blocks of pixels that stay in the processor's caches, on the shading threads.
    in_blocks(n.shape[0], RESHADE_BLOCK, block, balanced=True)
    out_shape = shape[:-1] + (3,)
    if split_terms:
        return {"diffuse": diffuse.reshape(out_shape), "specular": specular.reshape(out_shape)}
    return (diffuse + specular).reshape(out_shape)


class ProgressiveRadiance:
    r"""The Monte-Carlo reference of ``L_o`` per pixel, refined pass by pass (MIS, balance heuristic).

    Each pass draws ``samples`` directions per pixel, half from the model's importance sampler and
    half from the environment's (:func:`lighting.integrate.outgoing_radiance` with ``method="mis"``,
    the same estimator); :attr:`value` is the mean over all passes and :attr:`error` its standard
    error from the spread of the passes (honest once a few passes are in: use it with 4 or more).

    Parameters
    ----------
    brdf : BRDF
    environment : Environment, scalar/RGB radiance or callable
    normals, view_dirs : array_like, (N, 3)
        Unit normals and view directions (world frame) of the pixels.
    seed : int >= 0 or None
        Pass ``k``'s chunk ``j`` of pixels draws from ``SeedSequence(seed, spawn_key=(k, j))``, so a run is
        reproducible whichever thread integrates which chunk (``None``: fresh entropy).

    Examples
    --------
    >>> from lighting.models.brdf import Lambert
    >>> from lighting.lights.environment import ConstantEnvironment
    >>> up = np.tile([0.0, 0.0, 1.0], (1000, 1))
    >>> p = ProgressiveRadiance(Lambert(0.5), ConstantEnvironment(1.0), up, up, seed=1)
    >>> for _ in range(8):
    ...     _ = p.add(16)
    >>> p.samples, bool(np.mean(np.abs(p.value - 0.5) < 2 * p.error) > 0.85)  # the furnace k_d L, within 2σ
    (128, True)
    """

    def __init__(self, brdf, environment, normals, view_dirs, *, seed=0):
        self.brdf = _check_brdf(brdf)
        self.environment = as_environment(environment)
        n = check_vectors("normals", normals)
        v = check_vectors("view_dirs", view_dirs)
        self.dtype = working_dtype(n, v)
        self._shape, self._n, self._t, self._b, self._vl, self._valid = _frames(n, v, self.brdf)
        if seed is not None and (not isinstance(seed, (int, np.integer)) or isinstance(seed, bool) or seed < 0):
            raise ArgumentTypeError(f"seed must be an integer >= 0 or None; got {quote(seed)}")
        # Pass k, chunk j draws from SeedSequence(entropy, (k, j)): the same image whatever thread runs it.
        self._entropy = np.random.SeedSequence(seed).entropy
        count = self._n.shape[0]
        self._sum = np.zeros((count, 3))
        self._sum_sq = np.zeros((count, 3))
        self.passes = 0
        self.samples = 0
        self.seconds = 0.0

    def __repr__(self):
        return f"ProgressiveRadiance({self._n.shape[0]} pixels, {self.samples} samples per pixel)"

    def add(self, samples: int = 8, *, chunk: int = 4096):
        """Run one more pass of ``samples`` directions per pixel (an even count: half from each sampler).

        Parameters
        ----------
        samples : int >= 2
        chunk : int
            Pixels integrated at once (memory: about ``chunk · samples · 200`` bytes).

        Returns
        -------
        ProgressiveRadiance
            ``self``, so passes chain.
        """
        samples = check_count("samples", samples, 2, 1 << 16)
        chunk = check_count("chunk", chunk, 1, 1 << 22)
        chunk = min(chunk, max(self._n.shape[0], 1))  # a pass never holds more pixels than there are
        check_budget("samples", chunk * samples * 200, what=f"a pass of {samples} samples on {chunk} pixels")
        t0 = time.perf_counter()
        count = self._n.shape[0]
        smooth, deltas = split_delta(self.brdf)
        value = np.zeros((count, 3))
        if deltas:  # exact: R(μ_v) L(r), the same every pass
            to_world = lambda d: _to_world(d, self._t, self._b, self._n)  # noqa: E731
            value += delta_radiance(deltas, self.environment, self._vl, to_world)
        if smooth is not None:
            env, k = self.environment, self.passes

            def run(i):
                sl = slice(i, i + chunk)
                rng = np.random.default_rng(np.random.SeedSequence(self._entropy, spawn_key=(k, i // chunk)))
                val, *_ = _radiance_batch(smooth, env, self._n[sl], self._t[sl], self._b[sl], self._vl[sl], "mis",
                                          samples, rng, 0, want_error=False)  # fmt: skip
                value[sl] += val

            starts = range(0, count, chunk)
            if len(starts) == 1:
                run(0)
            else:
                from ..shading.batch import _pool

                for _ in _pool().map(run, starts):  # NumPy releases the GIL: the chunks run on every core
                    pass
        value = np.where((self._valid & (self._vl[:, 2] > 0))[:, None], value, 0.0)
        self._sum += value
        self._sum_sq += value * value
        self.passes += 1
        self.samples += samples
        self.seconds += time.perf_counter() - t0
        return self

    @property
    def value(self) -> np.ndarray:
        """The mean over the passes, ``(N, 3)`` in the inputs' dtype (zeros before the first pass)."""
        k = max(self.passes, 1)
        return (self._sum / k).reshape(self._shape + (3,)).astype(self.dtype)

    @property
    def error(self) -> np.ndarray:
        """The standard error of :attr:`value` from the spread of the passes (``inf`` before two passes)."""
        k = self.passes
        if k < 2:
            return np.full(self._shape + (3,), np.inf, dtype=self.dtype)
        mean = self._sum / k
        var = np.maximum(self._sum_sq / k - mean * mean, 0.0) * (k / (k - 1))
        return np.sqrt(var / k).reshape(self._shape + (3,)).astype(self.dtype)

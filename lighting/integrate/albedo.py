r"""Directional and hemispherical albedo: the rendering equation under a uniform white sky.

With ``L_i = 1`` everywhere the rendering equation gives the directional albedo (conventions.md):

    ρ(v) = ∫_Ω f_r(v, l) (n·l) dω(l),

the fraction of light from a uniform sky that the surface sends toward ``v``
(equivalently, by reciprocity, the fraction of a beam from ``v`` that is
reflected at all).  A model conserves energy when ``ρ(v) <= 1`` for every ``v``.

An ideal mirror (a part with ``is_delta``, :class:`~lighting.models.mirror.Mirror`) reflects into the
one direction ``R_v``: its albedo is its ``reflectance(cos θ_v)``, added exactly (zero error) whatever the
method, while the smooth parts of a sum are integrated as usual.

Every function takes ``samples`` (its cost: BRDF evaluations per result) and a ``method`` of
:data:`METHODS`: ``"quadrature"`` (:mod:`lighting.integrate.quadrature`, deterministic) or one of the
Monte Carlo methods of :mod:`lighting.integrate.montecarlo`; with ``return_error=True`` an
:class:`~lighting.integrate.estimate.Estimate` with an honest error.
"""

from __future__ import annotations

import math
import time
from typing import NamedTuple

import numpy as np

from .._budget import check_budget
from .._text import quote
from .._validate import check_bool, check_choice, check_count, real_array
from ..models.brdf import BRDF
from ..numerics import working_dtype
from ..sampling.brdf import _f_cos, as_generator
from ._checks import _NODE_BUDGET, _check_brdf, _out, _replicates, _samples
from ._delta import delta_albedo, split_delta
from .estimate import _ROUNDING, Estimate, _combine
from .montecarlo import _mc_estimates, _probe_count
from .quadrature import _coarse_rules, _gl01, _lobe_rule, _split

__all__ = ["METHODS", "AlbedoCurve", "directional_albedo", "albedo_curve", "hemispherical_albedo"]

#: The methods of :func:`directional_albedo` and :func:`hemispherical_albedo`.
METHODS = ("quadrature", "uniform", "cosine", "importance", "stratified")


class AlbedoCurve(NamedTuple):
    """Directional albedo over view angles: ``theta`` (T,), ``albedo`` and ``error`` (T, 3).

    ``unconverged`` (T, 3) flags the values whose relative error is above 2 %, as :class:`Estimate` does.
    """

    theta: np.ndarray
    albedo: np.ndarray
    error: np.ndarray
    samples: int
    seconds: float
    method: str

    @property
    def unconverged(self) -> np.ndarray:
        """True where ``error / |albedo|`` exceeds :data:`UNCONVERGED_RELATIVE_ERROR`."""
        return Estimate(self.albedo, self.error, self.samples, self.seconds, self.method).unconverged

    def __repr__(self) -> str:
        """One line: the method, the counts, the largest and smallest albedo and the largest error."""
        from ..analysis._display import albedo_repr  # every result prints the same way, from one module

        return albedo_repr(self)

    def _repr_png_(self):
        """The picture in a notebook: ρ against the view angle (None without Matplotlib)."""
        from ..analysis._display import albedo_png

        return albedo_png(self)


def _thetas(theta_v, name="theta_v"):
    allowed = "finite angles in [0, π/2] radians"
    t = real_array(name, theta_v, allowed=allowed)
    dt = working_dtype(t)
    t = t.astype(np.float64)
    # π/2 rounded to float32 (1.5707964) is a little above π/2: accept it as π/2.
    if t.size and (np.min(t) < 0 or np.max(t) > math.pi / 2 * (1 + 1e-6)):
        raise ValueError(f"{name} must be {allowed}; got {quote(theta_v)}")
    check_budget(name, t.size * 3 * 8 * 8, what=f"{t.size} view angles")
    return np.minimum(t, math.pi / 2), dt


def _view_local(theta: np.ndarray) -> np.ndarray:
    """``v = (sin θ, 0, cos θ)``; exactly grazing (θ = π/2) gives ``n·v = 0``, not 6e-17."""
    c = np.where(theta >= math.pi / 2, 0.0, np.cos(theta))
    return np.stack([np.sin(theta), np.zeros_like(theta), c], axis=-1)


def _quad_albedo(brdf: BRDF, v: np.ndarray, samples: int, want_error: bool = True):
    """The fine rule's albedo ``(B, 3)``, its error estimate (zero without ``want_error``) and the nodes used.

    The coarse rules serve the error estimate alone: without it they are not evaluated, and the value is the
    same fine rule's, bit for bit.
    """
    parts = brdf.parts
    (nr, nph), (cr, cph) = _split(samples, len(parts))
    total = np.zeros(v.shape[:-1] + (3,))
    err = np.zeros_like(total)
    used = 0
    for part in parts:
        vals = []
        coarse = _coarse_rules(part, v, cr, cph) if want_error else ()
        for rule in (_lobe_rule(part, v, nr, nph, 2), *coarse):
            f = _f_cos(part, rule.l, np.broadcast_to(v[:, None, :], rule.l.shape))
            vals.append(np.einsum("bm,bmk->bk", rule.w, f))
            used += rule.l.shape[1]
        total += vals[0]
        if want_error:
            err += np.max([np.abs(vals[0] - c) for c in vals[1:]], axis=0)
    return total, np.maximum(err, _ROUNDING * np.abs(total)), used


def _albedo_batch(brdf, v, method, samples, rng, replicates, want_error):
    if method == "quadrature":
        val, err, used = _quad_albedo(brdf, v, samples, want_error)
        return val, err, np.zeros_like(err), used
    return _mc_estimates(brdf, v, method, samples, rng, replicates, want_error)


def _albedo(brdf, theta, method, samples, rng, reps, want_error):
    """Albedo, standard error and rule-of-three term ``(T, 3)`` for flat view angles ``theta`` (T,).

    Delta parts (the ideal mirror) give ``R(cos θ_v)`` exactly, with no error and no sample; the smooth
    remainder goes through ``method``.  A model with delta parts only spends one evaluation per angle.
    """
    v = _view_local(theta)
    smooth, deltas = split_delta(brdf)
    val = delta_albedo(deltas, v[:, 2])
    se = np.zeros_like(val)
    rare = np.zeros_like(val)
    if smooth is None:
        return val, se, rare, 1
    used = samples
    per_view = samples + (_probe_count(smooth) if want_error and method != "quadrature" else 0)
    chunk = max(1, _NODE_BUDGET // per_view)
    for i in range(0, v.shape[0], chunk):
        sl = slice(i, i + chunk)
        a, se[sl], rare[sl], used = _albedo_batch(smooth, v[sl], method, samples, rng, reps, want_error)
        val[sl] += a
    return val, se, rare, used


def directional_albedo(
    brdf: BRDF,
    theta_v,
    samples: int = 4096,
    method: str = "quadrature",
    *,
    seed=None,
    replicates: int | None = None,
    return_error: bool = False,
):
    r"""Directional albedo ``ρ(v) = ∫_Ω f_r(v, l) (n·l) dω_l`` for a viewer at polar angle ``θ_v``.

    Parameters
    ----------
    brdf : BRDF
        Any model of :mod:`lighting.models.brdf` (sums included: each part is
        integrated with its own rule, or sampled by a mixture).  A delta part
        (``is_delta``: the ideal mirror) adds its ``reflectance(cos θ_v)`` exactly,
        with zero error, under every method.
    theta_v : float or array_like, radians in [0, π/2]
        The viewer's angle from the normal (isotropic models: the azimuth does
        not matter).  At exactly π/2 the albedo is 0 (``n·v = 0``).
    samples : int >= 1
        Cost: BRDF evaluations per angle (quadrature: nodes of the fine and the
        error-estimating coarse rule together; the smallest rules use a few
        dozen whatever is asked).  One Monte Carlo sample has no spread: its
        error is the whole range its weight could take.
    method : {"quadrature", "uniform", "cosine", "importance", "stratified"}
        ``"quadrature"``: the deterministic lobe-centred rules of :mod:`lighting.integrate.quadrature`;
        the others: Monte Carlo (:mod:`lighting.integrate.montecarlo`).
    seed : int, Generator or None
        Random source of the Monte Carlo methods.
    replicates : int, optional
        Independent jittered grids for ``"stratified"`` (default
        ``clip(samples // 64, 2, 16)``); their spread is the error estimate.
    return_error : bool
        Return an :class:`Estimate` (value, error, samples, seconds): an honest
        error (see :mod:`lighting.integrate.estimate`) and the public flag
        ``Estimate.unconverged`` (relative error above 2 %), which the explorer
        reads.

    Returns
    -------
    ndarray, shape theta_v.shape + (3,) (RGB), or Estimate
        Dtype of ``theta_v`` when it is a float array, else float64.

    Raises
    ------
    ValueError
        ``theta_v`` outside ``[0, π/2]`` or not finite; ``samples`` below 1
        or over the memory budget (:func:`lighting._budget.check_budget`); an
        unknown ``method``; ``replicates`` outside ``[2, samples]``; a negative
        ``seed``.
    TypeError (ArgumentTypeError, also a ValueError)
        ``brdf`` not a model; text, bytes, complex or None where a number is
        expected; a non-integer count; a non-bool ``return_error``.

    Examples
    --------
    >>> from lighting.models.brdf import Lambert, Phong
    >>> directional_albedo(Lambert((0.2, 0.5, 0.8)), 0.3).round(12).tolist()
    [0.2, 0.5, 0.8]
    >>> round(float(directional_albedo(Phong(1.0, 0.0), 0.0)[0]), 12)  # the slides' Phong BRDF, e = 0: 2/(e+1)
    2.0
    >>> est = directional_albedo(Lambert(0.5), [0.0, 1.0], 256, "cosine", seed=1, return_error=True)
    >>> est.value.shape, float(est.error.max()) < 1e-12  # cosine sampling is exact for Lambert
    ((2, 3), True)
    >>> from lighting.models.mirror import Mirror
    >>> est = directional_albedo(Mirror(1.0, 0.04, "schlick"), 0.0, return_error=True)
    >>> est.value.round(12).tolist(), est.error.tolist()  # the delta: F0 exactly, no error
    ([0.04, 0.04, 0.04], [0.0, 0.0, 0.0])
    """
    t0 = time.perf_counter()
    brdf = _check_brdf(brdf)
    method = check_choice("method", method, METHODS)
    theta, dt = _thetas(theta_v)
    samples = _samples(samples, 1, method, brdf, theta.size)
    reps = _replicates(replicates, samples)
    return_error = check_bool("return_error", return_error)
    rng = as_generator(seed)
    val, se, rare, used = _albedo(brdf, theta.reshape(-1), method, samples, rng, reps, return_error)
    shape = theta.shape + (3,)
    value = _out(val.reshape(shape), dt)
    if not return_error:
        return value
    err = _combine(se, rare)
    return Estimate(value, _out(err.reshape(shape), dt), used, time.perf_counter() - t0, method)


def albedo_curve(
    brdf: BRDF,
    thetas=None,
    samples: int = 4096,
    method: str = "quadrature",
    *,
    seed=None,
    replicates: int | None = None,
) -> AlbedoCurve:
    """Directional albedo over view angles, for a plot of ``ρ(θ_v)``.

    Parameters
    ----------
    brdf : BRDF
        Any model of :mod:`lighting.models` (sums included; delta parts exactly, as in
        :func:`directional_albedo`).
    thetas : array_like, 1-D, radians in [0, π/2], optional
        View angles; default 0°, 1°, …, 90° (in radians).
    samples, method, seed, replicates
        As in :func:`directional_albedo`.

    Returns
    -------
    AlbedoCurve
        The angles ``(T,)``, the RGB albedo ``(T, 3)``, its error estimate ``(T, 3)``, the cost and the method.

    Examples
    --------
    >>> from lighting.models.brdf import Phong
    >>> c = albedo_curve(Phong(1.0, 1.0), [0.0, 0.5, 1.0])
    >>> c.albedo[:, 0].round(6).tolist()  # 2/(e+1) = 1 at normal incidence, less as the lobe sinks
    [1.0, 0.938791, 0.770151]
    """
    if thetas is None:
        thetas = np.radians(np.arange(91.0))
    theta, _ = _thetas(thetas, "thetas")
    if theta.ndim != 1:
        raise ValueError(f"thetas must be a 1-D list of angles in [0, π/2] radians; got shape {theta.shape}")
    est = directional_albedo(brdf, thetas, samples, method, seed=seed, replicates=replicates, return_error=True)
    return AlbedoCurve(np.asarray(thetas, dtype=np.float64), est.value, est.error, est.samples, est.seconds, method)


def hemispherical_albedo(
    brdf: BRDF,
    samples: int = 4096,
    method: str = "quadrature",
    *,
    view_samples: int = 16,
    seed=None,
    replicates: int | None = None,
    return_error: bool = False,
):
    r"""Cosine-weighted average of the directional albedo over view directions.

        ρ_hh = (1/π) ∫_Ω ρ(v) (n·v) dω_v = ∫_0^1 ρ(μ) 2μ dμ,   μ = cos θ_v,

    the fraction of light from a uniform sky that is reflected at all.  The
    ``μ`` integral is ``view_samples``-point Gauss–Legendre (exact for ``ρ``
    polynomial of degree < 2·view_samples − 1 in μ: a mirror's ``k_s`` from one
    node, Schlick's ``F_0 + (1 − F_0)/21`` from four).  The reported error adds
    the ``μ`` rule's own error — its difference to the rule with half the
    nodes (or with two for a single node), plus ``μ₁² max ρ`` for the sliver
    below the smallest node ``μ₁`` that neither rule sees (a lobe cut by the
    horizon changes ρ there; the bound assumes ρ there stays below the largest
    albedo found at the nodes) — to the inner integrals' errors:
    quadrature errors and the rule-of-three terms (which can share a sign:
    every angle may miss the same kind of region) add linearly, Monte Carlo
    standard errors (independent) in quadrature.  Cost: ``view_samples ×
    samples``, half as much again with ``return_error``.

    Parameters
    ----------
    brdf, samples, method, seed, replicates, return_error
        As in :func:`directional_albedo`.
    view_samples : int in [1, 1024]
        Gauss–Legendre nodes in ``μ``.

    Returns
    -------
    ndarray, (3,) (RGB, float64), or Estimate
        ``ρ_hh``; with ``return_error`` an :class:`~lighting.integrate.estimate.Estimate` whose error
        combines the ``μ`` rule's and the inner integrals' as described above.

    Examples
    --------
    >>> from lighting.models.brdf import Lambert
    >>> hemispherical_albedo(Lambert(0.6)).round(12).tolist()
    [0.6, 0.6, 0.6]
    """
    t0 = time.perf_counter()
    brdf = _check_brdf(brdf)
    method = check_choice("method", method, METHODS)
    view_samples = check_count("view_samples", view_samples, 1, 1024)
    samples = _samples(samples, 1, method, brdf, view_samples)
    reps = _replicates(replicates, samples)
    return_error = check_bool("return_error", return_error)
    rng = as_generator(seed)
    mu, wmu = _gl01(view_samples)
    # The μ rule's own error: the difference to a rule with half the nodes (two when one is asked).
    mu_c, wmu_c = _gl01(view_samples // 2 if view_samples > 1 else 2)
    k = view_samples if return_error else 0
    theta = np.arccos(np.concatenate([mu, mu_c]) if return_error else mu)
    val, se, rare, used = _albedo(brdf, theta, method, samples, rng, reps, return_error)
    w = (2 * mu * wmu)[:, None]
    value = np.sum(w * val[:view_samples], axis=0)
    if not return_error:
        return value
    outer = np.abs(value - np.sum((2 * mu_c * wmu_c)[:, None] * val[k:], axis=0))
    # No node of either rule lies below the smallest μ, where a lobe cut by the horizon changes ρ
    # fastest: that sliver, ∫_0^μ₁ 2μ ρ dμ, is bounded by μ₁² times the largest albedo seen.
    outer = outer + np.min(mu) ** 2 * np.max(np.abs(val) + se + rare, axis=0)
    se, rare = se[:k], rare[:k]
    if method == "quadrature":
        err = np.sum(w * se, axis=0) + outer
    else:
        err = np.sqrt(np.sum((w * se) ** 2, axis=0)) + np.sum(w * rare, axis=0) + outer
    return Estimate(value, err, used * theta.size, time.perf_counter() - t0, method)

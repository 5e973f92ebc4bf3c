r"""Monte Carlo estimation of hemisphere integrals: sampled means and the probes of their error term.

The Monte Carlo methods of :mod:`lighting.integrate` (every one takes ``samples``: integrand
evaluations per result):

``"uniform"``, ``"cosine"``
    Uniform or cosine-weighted hemisphere directions (the cosine warp through the concentric disk map
    of Shirley & Chiu 1997, :mod:`lighting.sampling.brdf`).
``"importance"``
    :func:`lighting.sampling.brdf.importance_sampler`: each model's own lobe sampler, a
    balance-heuristic mixture for sums.
``"stratified"``
    The importance sampler fed a jittered grid (:func:`lighting.sampling.brdf.jittered`), in
    ``replicates`` independent copies whose spread gives the error.

The estimate of ``∫ g(l) dω_l`` is the mean of ``g(l_k) / p(l_k)``; its error is the sample standard
error plus the rule-of-three term of :mod:`lighting.integrate.estimate`, whose weight bounds come from
the drawn samples and from a deterministic probe set (:func:`_lobe_probes`: the lobe-centred quadrature
nodes of every part).

Delta parts (the ideal mirror, ``BRDFFlags.DELTA``) never reach these estimators: their ``f_r`` is 0 at every
direction a sampler can draw, so :mod:`lighting.integrate.albedo` and :mod:`lighting.integrate.radiance`
add them exactly (:mod:`lighting.integrate._delta`) and pass only the smooth parts here.

References
----------
P. Shirley and K. Chiu, "A low distortion map between disk and square", Journal of Graphics Tools 2(3), 1997.
"""

from __future__ import annotations

import numpy as np

from ..models.brdf import BRDF
from ..sampling.brdf import CosineSampler, UniformSampler, _f_cos, importance_sampler, jittered_batch
from .estimate import _mean_err, _ratio, _terms, _weight_range
from .quadrature import _lobe_rule

__all__: list[str] = []

_PROBE_RULE = (24, 32)  # radial x azimuthal nodes of the lobe-centred probe set, per part
_ENV_PROBES = 16  # an ENV_PROBES² grid of the environment's own sampling map


def _lobe_probes(brdf: BRDF, v: np.ndarray) -> np.ndarray:
    """The lobe-centred quadrature nodes of every part for viewers ``v`` ``(B, 3)``: ``(B, M, 3)``."""
    return np.concatenate([_lobe_rule(p, v, *_PROBE_RULE).l for p in brdf.parts], axis=1)


def _probe_count(brdf: BRDF, env=None) -> int:
    """Directions :func:`~lighting.integrate.estimate._weight_range` evaluates per viewer (mirrored ones included)."""
    k = 0 if env is None else _ENV_PROBES**2
    return 2 * (len(brdf.parts) * _PROBE_RULE[0] * _PROBE_RULE[1] * 2 + k)


def _method_sampler(brdf: BRDF, method: str):
    """The sampler of a Monte Carlo ``method``: uniform, cosine, or the model's importance sampler."""
    if method == "uniform":
        return UniformSampler()
    if method == "cosine":
        return CosineSampler()
    return importance_sampler(brdf)


def _sampled_mean(sampler, integrand, vv, batch, samples, replicates, rng):
    """Mean of ``integrand / pdf`` over ``sampler``'s directions for ``batch`` viewers ``vv`` (B, 1, 3).

    ``replicates > 0`` stratifies: that many independent jittered sets, whose means give the standard
    error; otherwise ``samples`` independent directions.  Returns ``(value, standard error, weights,
    samples used)``; the weights feed the rule-of-three term.
    """
    if replicates:
        u = jittered_batch((batch, replicates), max(1, samples // replicates), rng)  # (B, R, M, 2)
        m = u.shape[2]
        s = sampler._sample(u.reshape(batch, replicates * m, 2), vv)
        w = _ratio(integrand(s.directions), s.pdf)
        val, se = _mean_err(_mean_err(w.reshape(batch, replicates, m, 3), axis=2)[0], axis=1)
        return val, se, w, replicates * m
    s = sampler._sample(rng.random((batch, samples, 2)), vv)
    w = _ratio(integrand(s.directions), s.pdf)
    val, se = _mean_err(w, axis=1)
    return val, se, w, samples


def _mc_estimates(brdf, v, method, samples, rng, replicates, want_error=True):
    """Monte Carlo for viewers ``v`` (B, 3): value, standard error, rule-of-three term, samples used."""
    sampler = _method_sampler(brdf, method)
    b = v.shape[0]
    vv = v[:, None, :]

    def g(l):  # noqa: E741
        return _f_cos(brdf, l, np.broadcast_to(vv, l.shape))

    val, se, w, used = _sampled_mean(sampler, g, vv, b, samples, replicates if method == "stratified" else 0, rng)
    if not want_error:
        return val, se, np.zeros_like(se), used
    lo, hi = _weight_range(g, lambda l: sampler._pdf(l, vv), _lobe_probes(brdf, v), w)  # noqa: E741
    return (val, *_terms(val, se, used, lo, hi), used)

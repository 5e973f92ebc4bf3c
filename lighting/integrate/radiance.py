r"""The rendering equation under an environment: reflected radiance by quadrature, Monte Carlo, MIS or SH.

The CMSC 435 deck's rendering equation, for a surface with normal ``n`` seen from ``v``:

    L_o(v) = ∫_Ω f_r(v, l) L_i(l) (n·l) dω(l)                (full environment)
    L_o(v) = Σ_i f_r(v, l_i) E_i (n·l_i)                      (point lights)

:func:`outgoing_radiance` integrates the first under a :class:`lighting.lights.environment.Environment`
(the methods of :data:`RADIANCE_METHODS`); :func:`point_light_limit` shows the second as the limit of
the first for a small bright patch (the deck's "Results" slide).

Methods besides those of :mod:`lighting.integrate.albedo`:

``"environment"``, ``"mis"``
    Directions drawn from the environment's own density, or half from the BRDF and half from the
    environment combined with the balance heuristic of multiple importance sampling (Veach & Guibas
    1995; Veach 1997, ch. 9).
``"sh"`` (Lambertian models, plus mirrors)
    Nine spherical-harmonic coefficients of the environment and the irradiance formula of
    Ramamoorthi & Hanrahan (2001) (:mod:`lighting.integrate.sh`).

Delta parts (the ideal mirror, ``BRDFFlags.DELTA``) are never sampled: each adds ``R(n·v) L_i(R_v)``, exact,
before the smooth parts reach any of these methods (:mod:`lighting.integrate._delta`).

Every point is integrated in its own shading frame (``z`` the normal, :func:`lighting.vec.orthonormal_basis`).

References
----------
E. Veach and L. J. Guibas, "Optimally combining sampling techniques for Monte Carlo rendering", SIGGRAPH 1995.
E. Veach, "Robust Monte Carlo methods for light transport simulation", PhD thesis, Stanford University, 1997.
R. Ramamoorthi and P. Hanrahan, "An efficient representation for irradiance environment maps", SIGGRAPH 2001.
"""

from __future__ import annotations

import math
import time
from typing import NamedTuple

import numpy as np

from .._budget import check_budget
from .._text import quote
from .._validate import check_bool, check_choice, check_color, check_count, check_vectors, real_array
from ..lights.environment import SmallPatchEnvironment, as_environment
from ..models.base import BRDFFlags
from ..models.brdf import BRDF
from ..models.geometry import Geometry
from ..numerics import safe_div, working_dtype
from ..sampling.base import BYTES_PER_SAMPLE
from ..sampling.brdf import _f_cos, as_generator, importance_sampler
from ..vec import orthonormal_basis
from ._checks import _NODE_BUDGET, _check_brdf, _out, _replicates, _samples, _unit_rows
from ._delta import delta_radiance, split_delta
from .albedo import METHODS
from .estimate import _ROUNDING, Estimate, _combine, _mean_err, _ratio, _terms, _weight_range
from .montecarlo import _ENV_PROBES, _lobe_probes, _method_sampler, _probe_count, _sampled_mean
from .quadrature import _cap_rule, _coarse_rules, _lobe_rule, _split
from .sh import _sh_coefficients, _sh_error_bound, _sh_irradiance, _sh_truncation_error

__all__ = ["RADIANCE_METHODS", "outgoing_radiance", "point_light_limit"]

#: The methods of :func:`outgoing_radiance`.
RADIANCE_METHODS = METHODS + ("environment", "mis", "sh")


def _frames(normals, view_dirs, brdf):
    """Each point's shading frame: ``(shape, n, t, b, v_local, valid)``, flat over the points.

    Normals and view directions are broadcast together and made unit (a zero vector becomes ``+z`` and
    marks its point invalid).  ``t, b`` complete ``n``: for an anisotropic model, the frame its lobe is
    oriented in everywhere else in the engine (the default tangent ``ẑ × n``, :class:`Geometry`), so that an
    integral over the sphere and a direct light agree on where its long axis lies; an isotropic lobe turns
    with any frame, and takes Duff et al.'s, continuous everywhere but at one normal
    (:func:`lighting.vec.orthonormal_basis`).
    """
    n = np.asarray(normals, dtype=np.float64)
    v = np.asarray(view_dirs, dtype=np.float64)
    try:
        shape = np.broadcast_shapes(n.shape, v.shape)
    except ValueError:
        raise ValueError(f"normals and view_dirs must broadcast together; got shapes {n.shape} and {v.shape}") from None
    check_budget("normals", math.prod(shape) * 8 * 16, what=f"{math.prod(shape) // 3} shading points")
    n, nlen = _unit_rows(np.broadcast_to(n, shape).reshape(-1, 3), np.array([0.0, 0.0, 1.0]))
    v, vlen = _unit_rows(np.broadcast_to(v, shape).reshape(-1, 3), np.array([0.0, 0.0, 1.0]))
    valid = (nlen[:, 0] > 0) & (vlen[:, 0] > 0)
    if BRDFFlags.ANISOTROPIC in brdf.flags:
        frame = Geometry(n, n, n, unit=True, dtype=np.float64)
        t, b = frame.t, frame.b
    else:
        t, b = orthonormal_basis(n)
    vl = np.stack([np.sum(v * t, -1), np.sum(v * b, -1), np.sum(v * n, -1)], axis=-1)
    return shape[:-1], n, t, b, vl, valid


def _to_world(l, t, b, n):  # noqa: E741
    """Local directions ``l`` ``(B, M, 3)`` in the world frame of each point's ``(t, b, n)`` ``(B, 3)``.

    Component by component (:func:`_to_world_reference`'s products broadcast over the axis of length 3, three
    elements per inner loop): the same sums in the same order.
    """
    shape = np.broadcast_shapes(l.shape, (t.shape[0], 1, 3))
    out = np.empty(shape, dtype=np.result_type(l, t, b, n))
    l0, l1, l2 = l[..., 0], l[..., 1], l[..., 2]
    for c in range(3):
        comp = out[..., c]
        np.multiply(l0, t[:, None, c], out=comp)
        comp += l1 * b[:, None, c]
        comp += l2 * n[:, None, c]
    return out


def _to_world_reference(l, t, b, n):  # noqa: E741
    """:func:`_to_world` by broadcasting over the components (tests hold them equal)."""
    return l[..., 0:1] * t[:, None, :] + l[..., 1:2] * b[:, None, :] + l[..., 2:3] * n[:, None, :]


def _to_local(d, t, b, n):
    """World directions ``d`` ``(B, M, 3)`` in each point's local frame (inverse of :func:`_to_world`).

    Each dot product as :func:`_to_local_reference`'s sum over the last axis forms it, ``((0 + x) + y) + z``:
    ``x + y + z`` and a final ``+ 0`` (the sum's start), which takes an all-``−0`` sum to ``+0``.
    """
    d0, d1, d2 = d[..., 0], d[..., 1], d[..., 2]
    comps = []
    for axis in (t, b, n):
        dot = d0 * axis[:, None, 0]
        dot += d1 * axis[:, None, 1]
        dot += d2 * axis[:, None, 2]
        dot += 0.0
        comps.append(dot)
    return np.stack(comps, axis=-1)


def _to_local_reference(d, t, b, n):
    """:func:`_to_local` by sums over the components (tests hold them equal)."""
    return np.stack(
        [np.sum(d * t[:, None, :], -1), np.sum(d * b[:, None, :], -1), np.sum(d * n[:, None, :], -1)], axis=-1
    )


def _pair_mean(ga, pa, gb, pb):
    """The mean over axis 1 of ``_ratio(ga, pa) + _ratio(gb, pb)`` (``g`` ``(B, M, 3)``, ``p`` ``(B, M)``), as
    :func:`_mean_err` finds it (each channel's ``M`` weights summed pairwise from one contiguous row).

    Channel by channel, into the rows the mean reads: :func:`_ratio`'s quotients (``safe_div``) without its
    broadcasts over the axis of length 3 or the copy that turns the weights' samples into the last axis.
    """
    bsz, m = pa.shape
    w = np.empty((bsz, 3, m), dtype=np.result_type(ga, pa, gb, pb))
    for c in range(3):
        w[:, c, :] = safe_div(ga[..., c], pa)
        w[:, c, :] += safe_div(gb[..., c], pb)
    return w.mean(axis=-1)


def _radiance_batch(brdf, env, n, t, b, vl, method, samples, rng, reps, want_error=True):
    """L_o, its standard error and the rule-of-three term for a batch of points (float64).

    Without ``want_error`` the error terms may be ``None`` (multiple importance sampling does not form them).
    """
    bsz = n.shape[0]
    vv = vl[:, None, :]

    def cosine_brdf(l_local):
        return _f_cos(brdf, l_local, np.broadcast_to(vv, l_local.shape))

    def integrand(l_local):
        return cosine_brdf(l_local) * env._radiance(_to_world(l_local, t, b, n))

    if method == "quadrature":
        if env.support is not None:
            axis, cap = env.support
            c = _to_local(np.broadcast_to(axis, (bsz, 1, 3)), t, b, n)[:, 0, :]
            (nr, nph), (cr, cph) = _split(samples, 1)
            vals = []
            used = 0
            for a, m, k in ((nr, nph, 2), (cr, cph, 1)):
                rule = _cap_rule(c, cap, a, m, k)
                vals.append(np.einsum("bm,bmk->bk", rule.w, integrand(rule.l)))
                used += rule.l.shape[1]
            err = np.maximum(np.abs(vals[0] - vals[1]), _ROUNDING * np.abs(vals[0]))
            return vals[0], err, np.zeros_like(err), used
        parts = brdf.parts
        (nr, nph), (cr, cph) = _split(samples, len(parts))
        total = np.zeros((bsz, 3))
        err = np.zeros_like(total)
        used = 0
        for part in parts:
            vals = []
            for rule in (_lobe_rule(part, vl, nr, nph, 2), *_coarse_rules(part, vl, cr, cph)):
                f = _f_cos(part, rule.l, np.broadcast_to(vv, rule.l.shape))
                vals.append(np.einsum("bm,bmk->bk", rule.w, f * env._radiance(_to_world(rule.l, t, b, n))))
                used += rule.l.shape[1]
            total += vals[0]
            err += np.max([np.abs(vals[0] - c) for c in vals[1:]], axis=0)
        err = np.maximum(err, _ROUNDING * np.abs(total))
        return total, err, np.zeros_like(err), used

    def env_pdf(l_local):
        return env._pdf(_to_world(l_local, t, b, n))

    def probes():
        # The lobe-centred nodes, and the environment's own map of a midpoint grid (where its light is).
        g = (np.arange(_ENV_PROBES) + 0.5) / _ENV_PROBES
        u = np.stack(np.meshgrid(g, g, indexing="ij"), axis=-1).reshape(-1, 2)
        d, _ = env._sample(u)
        le = _to_local(np.broadcast_to(d, (bsz,) + d.shape), t, b, n)
        return np.concatenate([_lobe_probes(brdf, vl), le], axis=1)

    if method in ("environment", "mis"):
        n_env = samples if method == "environment" else max(1, samples // 2)
        d, pe = env._sample(rng.random((bsz, n_env, 2)))
        le = _to_local(d, t, b, n)
        # A model is 0 below the surface (its contract), so only the samples above it are evaluated: the others
        # weigh 0 whatever the BRDF's density there.  Their radiance is read where they were drawn (not turned
        # into the pixel's frame and back).
        above = np.nonzero(le[..., 2] > 0)
        l_up, v_up = le[above], np.broadcast_to(vv, le.shape)[above]
        ge = np.zeros(le.shape)
        ge[above] = _f_cos(brdf, l_up, v_up) * env._radiance(d[above])
        if method == "environment":
            w = _ratio(ge, pe)
            val, se = _mean_err(w, axis=1)
            if not want_error:
                return val, se, np.zeros_like(se), n_env
            lo, hi = _weight_range(integrand, env_pdf, probes(), w)
            return (val, *_terms(val, se, n_env, lo, hi), n_env)
        sampler = importance_sampler(brdf)
        s = sampler._sample(rng.random((bsz, n_env, 2)), vv)
        # The environment's radiance and density at the BRDF's samples, from one turn of them into the world.
        radiance_b, pe_b = env._radiance_and_pdf(_to_world(s.directions, t, b, n))
        gb = cosine_brdf(s.directions) * radiance_b  # the integrand, its radiance read with the density
        pb_e = np.zeros(le.shape[:-1])  # BRDF density at the environment's samples (those above the surface)
        pb_e[above] = sampler._pdf(l_up, v_up)
        # Two-sample balance heuristic with equal counts: each pair contributes g/(p_b + p_e) twice.
        if not want_error:
            return _pair_mean(ge, pe + pb_e, gb, s.pdf + pe_b), None, None, 2 * n_env
        wa, wb = _ratio(ge, pe + pb_e), _ratio(gb, s.pdf + pe_b)
        val, se = _mean_err(wa + wb, axis=1)
        lo, hi = _weight_range(
            integrand,
            lambda l: env_pdf(l) + sampler._pdf(l, vv),
            probes(),
            np.concatenate([wa, wb], axis=1),  # noqa: E741
        )
        # A pair's sum z = w(l_e) + w(l_b) lies in [2 lo, 2 hi].
        return (val, *_terms(val, se, n_env, 2 * lo, 2 * hi), 2 * n_env)

    sampler = _method_sampler(brdf, method)
    val, se, w, used = _sampled_mean(sampler, integrand, vv, bsz, samples, reps if method == "stratified" else 0, rng)
    if not want_error:
        return val, se, np.zeros_like(se), used
    lo, hi = _weight_range(integrand, lambda l: sampler._pdf(l, vv), probes(), w)  # noqa: E741
    return (val, *_terms(val, se, used, lo, hi), used)


def outgoing_radiance(
    brdf: BRDF,
    environment,
    normals,
    view_dirs,
    *,
    method: str = "quadrature",
    samples: int = 1024,
    seed=None,
    replicates: int | None = None,
    sh_samples: int = 4096,
    return_error: bool = False,
):
    r"""Reflected radiance ``L_o(v) = ∫_Ω f_r(v, l) L_i(l) (n·l) dω_l`` under an environment.

    Parameters
    ----------
    brdf : BRDF
        Any model of :mod:`lighting.models` (sums included).  A delta part (``BRDFFlags.DELTA``:
        the ideal mirror) adds ``reflectance(n·v) · L_env(R_v)``, ``R_v = 2 n (n·v) − v``,
        exactly and with zero error, whatever the method; the other parts are integrated by it.
    environment : Environment, scalar/RGB radiance or callable
        A :class:`lighting.lights.environment.Environment`; a constant radiance or a
        function of direction is wrapped.
    normals, view_dirs : array_like, (..., 3), world frame
        Surface normals and directions toward the viewer (broadcast together;
        need not be unit length).  A zero vector gives 0.
    method : {"quadrature", "uniform", "cosine", "importance", "stratified", "environment", "mis", "sh"}
        ``"quadrature"`` puts its nodes on the BRDF's lobe, or — for an
        environment that is black outside a small cap
        (:class:`~lighting.lights.environment.SmallPatchEnvironment`) — on the cap.
        ``"sh"`` needs a Lambertian model (a :class:`~lighting.models.brdf.Lambert`
        or a sum of them, plus mirrors): ``L_o = k_d/π · E(n)`` with ``E`` from
        :func:`sh_irradiance` (an approximation, about 1 % for typical
        environments, up to ~9 % for a single small light).
    samples : int
        Cost: integrand evaluations per point (ignored by ``"sh"``).
    seed, replicates
        As in :func:`directional_albedo`.
    sh_samples : int
        Quadrature nodes used to project the environment for ``"sh"``.
    return_error : bool
        Return an :class:`Estimate` (honest error, ``unconverged`` flag: see
        :mod:`lighting.integrate.estimate`); for ``"sh"`` the error is the projection's quadrature
        estimate plus what the bands above 2 add: bands 4, 6 and 8 evaluated
        exactly, the rest bounded by Cauchy–Schwarz and Parseval on the
        environment's energy (close for smooth skies, loose for a single small
        light, which the 2 % flag then marks).

    Returns
    -------
    ndarray (..., 3) or Estimate
        ``L_o`` per point (RGB), in the dtype of ``normals`` and ``view_dirs`` when they are float arrays,
        else float64; 0 where a normal or view direction is zero or the viewer is below the horizon.

    Examples
    --------
    >>> from lighting.models.brdf import Lambert
    >>> from lighting.lights.environment import ConstantEnvironment
    >>> L = outgoing_radiance(Lambert(0.5), ConstantEnvironment(2.0), (0, 0, 1.0), (0.6, 0, 0.8))  # furnace: k_d L
    >>> L.round(12).tolist()
    [1.0, 1.0, 1.0]
    """
    t0 = time.perf_counter()
    brdf = _check_brdf(brdf)
    env = as_environment(environment)
    method = check_choice("method", method, RADIANCE_METHODS)
    normals = check_vectors("normals", normals)
    view_dirs = check_vectors("view_dirs", view_dirs)
    dt = working_dtype(normals, view_dirs)
    shape, n, t, b, vl, valid = _frames(normals, view_dirs, brdf)
    samples = _samples(samples, 1, method, brdf, n.shape[0])
    reps = _replicates(replicates, samples)
    sh_samples = check_count("sh_samples", sh_samples, 8)
    check_budget("sh_samples", sh_samples * BYTES_PER_SAMPLE * 4, what=f"{sh_samples} sphere nodes")
    return_error = check_bool("return_error", return_error)
    rng = as_generator(seed)
    # Delta parts (the ideal mirror) exactly: R(cos θ_v) L(R_v), no error; the smooth rest by `method`.
    smooth, deltas = split_delta(brdf)
    val = delta_radiance(deltas, env, vl, lambda d: _to_world(d, t, b, n))
    err = np.zeros_like(val)
    used = 1
    if smooth is None:
        pass
    elif method == "sh":
        kd = _lambertian_albedo(smooth)
        # sh_samples and the normals are checked and budgeted above (more strictly than sh.py's own checks).
        coeffs = _sh_coefficients(env, sh_samples, True, time.perf_counter())
        e = _sh_irradiance(coeffs.value, n, True)
        e_err = _sh_error_bound(coeffs.error, n) + _sh_truncation_error(env, coeffs.value, n, sh_samples)
        val += np.where((valid & (vl[:, 2] > 0))[:, None], kd / math.pi * e, 0.0)
        err = np.where((valid & (vl[:, 2] > 0))[:, None], kd / math.pi * e_err, 0.0)
        used = coeffs.samples
    else:
        used = samples
        probing = return_error and method != "quadrature"
        chunk = max(1, _NODE_BUDGET // (samples + (_probe_count(smooth, env) if probing else 0)))
        for i in range(0, n.shape[0], chunk):
            sl = slice(i, i + chunk)
            a, se, rare, used = _radiance_batch(
                smooth, env, n[sl], t[sl], b[sl], vl[sl], method, samples, rng, reps, return_error
            )
            val[sl] += a
            if return_error:
                err[sl] = _combine(se, rare)
    val = np.where(valid[:, None], val, 0.0)
    err = np.where(valid[:, None], err, 0.0)
    value = _out(val.reshape(shape + (3,)), dt)
    if not return_error:
        return value
    return Estimate(value, _out(err.reshape(shape + (3,)), dt), used, time.perf_counter() - t0, method)


def _lambertian_albedo(brdf: BRDF) -> np.ndarray:
    if not all(BRDFFlags.LAMBERTIAN in p.flags for p in brdf.parts):
        raise ValueError(
            f"method 'sh' (spherical-harmonic irradiance) needs a Lambertian model (Lambert or a sum of them, "
            f"mirrors allowed); got {brdf!r}"
        )
    return sum((p.diffuse_albedo for p in brdf.parts), np.zeros(3))


class PointLimitRow(NamedTuple):
    """One solid angle of :func:`point_light_limit`."""

    solid_angle: float
    patch: np.ndarray  # L_o under the patch (3,)
    point: np.ndarray  # f_r (n·l) E with E = L Ω (3,)
    relative_error: float  # max over channels of |patch − point| / point


def point_light_limit(
    brdf: BRDF,
    light_dir,
    normal=(0.0, 0.0, 1.0),
    view_dir=(0.0, 0.0, 1.0),
    radiance=1.0,
    solid_angles=(1e-1, 1e-2, 1e-3, 1e-4, 1e-5),
    *,
    samples: int = 1024,
) -> list[PointLimitRow]:
    r"""The deck's two "Results": a small bright patch tends to a point light.

    For each ``Ω`` in ``solid_angles``, integrates the rendering equation under
    a :class:`~lighting.lights.environment.SmallPatchEnvironment` of radiance ``L``
    (by quadrature on the patch) and compares with the point-light sum
    ``f_r(v, l) (n·l) E`` for ``E = L Ω``.  The relative difference is
    ``O(Ω)`` for models smooth across the patch.

    Parameters
    ----------
    brdf : BRDF
        Any model of :mod:`lighting.models`.  A delta part (the ideal mirror) contributes 0 to the
        point-light term, as every point, directional or spot light gives it (its ``eval`` is 0: the
        light would be seen only where ``R_l = v`` exactly), but ``R(n·v) L`` to the patch's radiance
        when ``R_v`` falls inside the patch, however small: the mirror image of a light keeps its
        radiance, so for a mirror the relative difference does not fall with ``Ω`` — a point light
        has no image in a mirror.
    light_dir, normal, view_dir : 3-vectors, nonzero (world frame)
        Direction toward the patch centre, the surface normal and the direction toward the viewer
        (need not be unit length).
    radiance : float or RGB triple, >= 0
        ``L`` inside the patch.
    solid_angles : sequence of float in (0, 4π], at most 64
        The patch sizes ``Ω`` in steradians.
    samples : int >= 1
        Quadrature nodes per patch integral (as in :func:`outgoing_radiance`).

    Returns
    -------
    list of PointLimitRow
        Per ``Ω``: the patch's ``L_o`` (3,), the point-light term (3,) and their largest relative difference.

    Examples
    --------
    >>> from lighting.models.brdf import Lambert
    >>> rows = point_light_limit(Lambert(1.0), (0.0, 0.6, 0.8), solid_angles=(1e-2, 1e-4))
    >>> [f"{r.relative_error:.1e}" for r in rows]
    ['8.0e-04', '8.0e-06']
    """
    brdf = _check_brdf(brdf)
    vectors = []
    for name, value in (("light_dir", light_dir), ("normal", normal), ("view_dir", view_dir)):
        d = check_vectors(name, value, dtype=np.float64, nonzero=True)
        if d.shape != (3,):
            raise ValueError(f"{name} must be one finite nonzero 3-vector; got shape {d.shape}: {quote(value)}")
        vectors.append(d / np.max(np.abs(d)))
    ld, n, v = vectors
    check_color("radiance", radiance)
    allowed = "a nonempty list of solid angles in (0, 4π] steradians"
    oms = real_array("solid_angles", solid_angles, allowed=allowed, dtype=np.float64)
    if oms.ndim != 1 or oms.size == 0 or oms.size > 64 or np.any(oms <= 0) or np.any(oms > 4 * math.pi):
        raise ValueError(f"solid_angles must be {allowed} (at most 64); got {quote(solid_angles)}")
    samples = _samples(samples, 1, "quadrature", brdf)
    rows = []
    for om in oms.tolist():
        env = SmallPatchEnvironment(ld, om, radiance)
        patch = outgoing_radiance(brdf, env, n, v, method="quadrature", samples=samples)
        point = brdf.eval_cos(n, env.direction, v) * env.irradiance_limit
        rel = np.where(point > 0, np.abs(patch - point) / np.where(point > 0, point, 1.0), np.abs(patch - point))
        rows.append(PointLimitRow(float(om), patch, point, float(np.max(rel))))
    return rows

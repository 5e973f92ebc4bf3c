r"""Numerical stability of the shading formulas on stiff and extreme inputs.

Every model of :mod:`lighting.models.brdf` and the point and spot lights of
:mod:`lighting.lights.punctual` are evaluated, in float32 and in float64, on the inputs
where shading formulas go wrong — shininess up to 1e6, roughness down to 1e-6,
directions near the lobe peak, light and view within 1e-8 rad of the horizon,
``l = −v``, ``l = v = n``, zero and non-unit normals, point lights at distance
0, 1e-12 and 1e12, spot cutoffs 0, 90 and 180, huge and tiny intensities — and
each value is compared with a reference computed by mpmath at 80 significant
digits from **the same binary inputs** (the float32 or float64 vector
components, converted exactly).

The error measure and the bound
-------------------------------
For a value ``f`` whose true value is a normal number of the type:

    relative error  = |f_engine − f_true| / |f_true|
    bound           = 8 · max(κ, 1) · u,      u = 2^-24 (float32), 2^-53 (float64)

``κ`` is the componentwise relative condition number of the formula at that
point with respect to every input it is given: the nine vector components
(``n``, ``l``, ``v``; for lights the surface point, the light position and the
spot axis) and the model's shape parameters (shininess ``e``, roughness ``α``,
``f0``; for lights the falloff coefficients and the spot exponent):

    κ = Σ_i max_± |f(x with x_i → x_i (1 ± δ)) − f(x)| / (|f(x)| δ),   δ = 1e-30,

evaluated in mpmath.  It is the worst-case amplification of simultaneous
relative perturbations of one unit each in every input: rounding the inputs to
the type already costs ``κ u``, so no algorithm can promise less.  A
shininess-1e6 lobe seen 1e-3 rad from its peak has ``κ ≈ 2000``; ``κ`` near 1
means the formula must be accurate to a few units in the last place.  The
parameters count because the engine must round functions of them (``α²``,
``π α²``, ``√f0``): one ulp of ``α`` is two ulps of a GGX peak ``1/(π α²)``.
The pure scale factors ``k_d``, ``k_s`` and the light intensity are left out
(``f`` is proportional to them).  Where ``8 κ u >= 1`` the linear bound allows
100 % and stops describing the error; there the same first-order statement is
applied to the logarithm, ``|ln(f_engine / f_true)| <= 8 κ u``.

Where the formula has a discontinuity — the horizon mask ``n·l > 0``, the
clamp ``max(R·v, 0)`` of Phong, the spot cone test — a point whose decision
flips under relative perturbations of ``8 u`` of its inputs is an *edge point*:
both sides are acceptable there, and only finiteness and sign are required.
Where the true value is zero (below the horizon, a zero normal, a point at the
light) the engine must return exactly 0; where it exceeds the type's largest
finite value the engine must return that value (saturation, never ``inf``);
where it underflows the normal range the engine may differ from it by at most
the smallest normal number.

The behaviour that must hold is checked too: no negative values; lobes
non-increasing away from their peak along sweeps of the viewing direction
(for every pair whose true difference exceeds the two error bounds);
reciprocity ``f(l, v) = f(v, l)`` within the sum of the two bounds for the
reciprocal models (Lambert, normalized Blinn–Phong, Cook–Torrance); falloff
non-increasing with distance and the spot factor with the angle from its axis.

:func:`run` computes it all; :mod:`explorer.reports.stability` prints the table,
writes the CSV and draws the figure.  mpmath is imported inside the functions
that need it, so ``import lighting`` stays NumPy-only.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Sequence

import numpy as np

from .cases import (
    BOUND_FACTOR,
    BRDF_FORMS,
    CASE_FAMILIES,
    LIGHT_CASE_FAMILIES,
    LIGHT_FORMS,
    REFERENCE_DPS,
    ROUGHNESS,
    SHININESS,
    BrdfCase,
    LightCase,
    LightSpec,
    ModelSpec,
    brdf_cases,
    brdf_specs,
    light_cases,
    light_specs,
    unit_roundoff,
)
from .classify import _classify
from .engine import _engine_brdf, _engine_brdf_stacked, _engine_light
from .rearrangements import Rearrangement, _legacy_engine, _legacy_light, _worst, rearrangement_list
from .reference import reference_brdf, reference_light
from .summary import StabilityResult, SummaryRow, _binary, _group_rows, _order_stats, _sweep_pairs
from .tables import PREDICATES, _brdf_forms, _columns, _ref_table

__all__ = [
    "SHININESS",
    "ROUGHNESS",
    "BOUND_FACTOR",
    "REFERENCE_DPS",
    "CASE_FAMILIES",
    "LIGHT_CASE_FAMILIES",
    "unit_roundoff",
    "BrdfCase",
    "LightCase",
    "ModelSpec",
    "LightSpec",
    "SummaryRow",
    "StabilityResult",
    "brdf_cases",
    "light_cases",
    "brdf_specs",
    "light_specs",
    "reference_brdf",
    "reference_light",
    "Rearrangement",
    "rearrangement_list",
    "run",
]


def _run_jobs(jobs, workers, progress):
    """Run ``(fn, args, count)`` jobs, in worker processes when ``workers > 1``; results in job order."""
    results = [None] * len(jobs)
    if workers <= 1 or len(jobs) <= 1:
        for i, (fn, args, count) in enumerate(jobs):
            results[i] = fn(*args)
            if progress:
                progress(count)
        return results
    import concurrent.futures as cf
    import multiprocessing
    import warnings

    # The workers only run mpmath on their inputs; fork starts them in milliseconds and, unlike
    # spawn, does not re-import the caller's main module (which may be stdin or a notebook).
    methods = multiprocessing.get_all_start_methods()
    ctx = multiprocessing.get_context("fork" if "fork" in methods else "spawn")
    with warnings.catch_warnings(), cf.ProcessPoolExecutor(max_workers=workers, mp_context=ctx) as ex:
        warnings.simplefilter("ignore", DeprecationWarning)  # Python >= 3.12 warns about fork with threads
        futs = {ex.submit(fn, *args): i for i, (fn, args, _) in enumerate(jobs)}
        for f in cf.as_completed(futs):
            i = futs[f]
            results[i] = f.result()
            if progress:
                progress(jobs[i][2])
    return results


def _batches(items, size):
    return [items[i : i + size] for i in range(0, len(items), size)]


def run(
    quick: bool = False,
    dtypes: Sequence = (np.float32, np.float64),
    *,
    workers: int | None = None,
    progress: Callable[[int], None] | None = None,
    on_start: Callable[[int], None] | None = None,
    rearrangements: bool = True,
) -> StabilityResult:
    """Run the sweep: every model and light, every case family, every dtype.

    Parameters
    ----------
    quick : bool
        Fewer points per case family (every family and extreme is still there).
    dtypes : sequence of {np.float32, np.float64}
    workers : int, optional
        Processes for the mpmath references (default: up to 2, one per core).
    progress : callable, optional
        Called with the number of inputs finished, as references complete.
    on_start : callable, optional
        Called once with the total number of inputs before the work starts.
    rearrangements : bool
        Also evaluate the engine with each rearranged formula of
        :func:`rearrangement_list` put back, one at a time, on the same references
        (``StabilityResult.rearrangements``).

    Returns
    -------
    StabilityResult
    """
    t0 = time.perf_counter()
    dtypes = tuple(np.dtype(d).type for d in dtypes)
    cases = brdf_cases(quick)
    lcases = light_cases(quick)
    specs = brdf_specs()
    lspecs = light_specs()
    cols = _columns(specs, _brdf_forms)
    if workers is None:
        workers = max(1, min(2, os.cpu_count() or 1))
    jobs = []
    for dt in dtypes:
        inputs = [(_binary(c.n, dt), _binary(c.l, dt), _binary(c.v, dt), bool(c.sweep)) for c in cases]
        jobs += [(_ref_table, ("brdf", np.dtype(dt).name, b), len(b)) for b in _batches(inputs, 6)]
    for dt in dtypes:
        inputs = [(c.spec, _binary(c.point, dt)) for c in lcases]
        jobs += [(_ref_table, ("light", np.dtype(dt).name, b), len(b)) for b in _batches(inputs, 40)]
    if on_start:
        on_start(len(cases) * len(dtypes) + len(lcases) * len(dtypes))
    results = _run_jobs(jobs, workers, progress)
    t_ref = time.perf_counter() - t0

    nb = len(_batches(list(range(len(cases))), 6))
    nl = len(_batches(list(range(len(lcases))), 40))

    def merge(parts):
        return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}

    rows: list[SummaryRow] = []
    points: list = []
    t1 = time.perf_counter()
    fam_rows = {f: np.flatnonzero([c.family == f for c in cases]) for f in CASE_FAMILIES}
    pa, pb = _sweep_pairs(cases)
    fam_of = np.array([c.family for c in cases], dtype=object)
    pred_sel = np.array([[p in specs[si].predicates for p in PREDICATES] for si, _ in cols])
    meta = [(specs[si].family, specs[si].label, form if form in BRDF_FORMS else None) for si, form in cols]
    lobe_of = {}  # carrier column -> lobe column (the lobe's order checks are reported on the carrier row)
    for c, (si, form) in enumerate(cols):
        sp = specs[si]
        carrier = "eval" if sp.lobe == "D" else sp.lobe
        if sp.lobe and form == carrier:
            lobe_of[c] = cols.index((si, sp.lobe))
    rearr = rearrangement_list() if rearrangements else []
    for di, dt in enumerate(dtypes):
        dtname = np.dtype(dt).name
        u = unit_roundoff(dt)
        tiny = float(np.finfo(dt).tiny)
        ref = merge(results[di * nb : (di + 1) * nb])
        n = np.array([c.n for c in cases], dtype=dt)
        l = np.array([c.l for c in cases], dtype=dt)  # noqa: E741
        v = np.array([c.v for c in cases], dtype=dt)
        eng, swapped, nwarn = _engine_brdf(specs, cols, n, l, v)
        edge = np.any((ref["pred"][:, None, :] * (BOUND_FACTOR * u) >= 1) & pred_sel[None], axis=-1)
        cls, err, ratio, ok = _classify(ref["hi"], ref["lo"], ref["nz"], ref["kappa"], ref["logref"], edge, eng, dt)
        # The image path (all directional lights at once) is held to the same bound: each
        # point reports the worse of the two paths.
        eng_s, nwarn_s = _engine_brdf_stacked(specs, cols, n, l, v, eng)
        _, err_s, ratio_s, ok_s = _classify(
            ref["hi"], ref["lo"], ref["nz"], ref["kappa"], ref["logref"], edge, eng_s, dt
        )
        ok &= ok_s
        err, ratio = np.fmax(err, err_s), np.fmax(ratio, ratio_s)
        nwarn += nwarn_s
        eng = np.where(np.isfinite(eng_s) & (eng_s >= 0), eng, eng_s)  # a bad stacked value is counted too
        refv = ref["hi"] + ref["lo"]
        k1 = np.maximum(np.nan_to_num(ref["kappa"], nan=1.0), 1.0)
        recip = {}
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            for c, sw in swapped.items():
                a, b = eng[:, c].max(axis=-1), sw.max(axis=-1)
                recip[c] = (np.abs(a - b) / (refv[:, c] * k1[:, c] * u), a, b)
        lobe_cols = sorted(lobe_of)
        for fam in CASE_FAMILIES:
            sel = fam_rows[fam]
            if not len(sel):
                continue
            mono = {}
            fam_pairs = fam_of[pa] == fam if len(pa) else np.zeros(0, bool)
            if np.any(fam_pairs):
                lc = [lobe_of[c] for c in lobe_cols]
                sig, wrong, monotone = _order_stats(
                    pa[fam_pairs], pb[fam_pairs], refv[:, lc], k1[:, lc], eng[:, lc], cls[:, lc], u, tiny
                )
                mono = {c: (int(sig[j]), int(wrong[j]), bool(monotone[j])) for j, c in enumerate(lobe_cols)}
            # Cook–Torrance's D (not masked by the horizon) is checked for finiteness and sign on the eval row.
            extra = {"warnings": nwarn, "mono": mono, "recip": recip}
            start = len(rows)
            _group_rows(rows, points, sel, meta, cls, err, ratio, ok, eng, refv, ref["kappa"], cases, dtname, dt, extra)
            by_col = {(r.model, r.form): r for r in rows[start:]}
            for c, lc in lobe_of.items():
                si, form = cols[c]
                if cols[lc][1] == "D":
                    e = eng[sel, lc]
                    r = by_col[(specs[si].label, form)]
                    r.nonfinite += int(np.sum(~np.all(np.isfinite(e), axis=-1)))
                    r.negative += int(np.sum(np.any(e < 0, axis=-1)))

        if rearrangements:
            form_ok = np.array([form in BRDF_FORMS for _, form in cols])
            for rr in rearr:
                if rr.name == "spot cone near its axis":
                    continue
                leg = _legacy_engine(rr.name, specs, cols, n, l, v)
                mask = np.isfinite(leg).all(axis=-1).any(axis=0) & form_ok
                if not np.any(mask):
                    continue
                mask = np.broadcast_to(mask, cls.shape)
                lcls_, _, lratio_, lok_ = _classify(
                    ref["hi"], ref["lo"], ref["nz"], ref["kappa"], ref["logref"], edge, np.nan_to_num(leg, nan=-1.0), dt
                )
                rr.before[dtname] = _worst(lcls_, lratio_, lok_, mask)
                rr.after[dtname] = _worst(cls, ratio, ok, mask)

        lref = merge(results[len(dtypes) * nb + di * nl : len(dtypes) * nb + (di + 1) * nl])
        leng, lwarn = _engine_light(lspecs, lcases, dt)
        ledge = lref["pred"][:, :1] * (BOUND_FACTOR * u) >= 1
        ledge = np.broadcast_to(ledge, lref["hi"].shape)
        lcls, lerr, lratio, lok = _classify(
            lref["hi"], lref["lo"], lref["nz"], lref["kappa"], lref["logref"], ledge, leng, dt
        )
        lrefv = lref["hi"] + lref["lo"]
        lk1 = np.maximum(np.nan_to_num(lref["kappa"], nan=1.0), 1.0)
        if rearrangements:
            leg = _legacy_light(lspecs, lcases, dt)
            spot = np.isfinite(leg).all(axis=-1)
            c2, _, r2, o2 = _classify(
                lref["hi"],
                lref["lo"],
                lref["nz"],
                lref["kappa"],
                lref["logref"],
                ledge,
                np.nan_to_num(leg, nan=-1.0),
                dt,
            )
            for rr in rearr:
                if rr.name == "spot cone near its axis":
                    rr.before[dtname] = _worst(c2, r2, o2, spot)
                    rr.after[dtname] = _worst(lcls, lratio, lok, spot)
        la, lb = _sweep_pairs(lcases)
        spec_of = np.array([c.spec for c in lcases])
        for si, sp in enumerate(lspecs):
            for fam in LIGHT_CASE_FAMILIES:
                sel = np.flatnonzero((spec_of == si) & np.array([c.family == fam for c in lcases]))
                if not len(sel):
                    continue
                inpair = np.isin(la, sel)
                sig, wrong, monotone = _order_stats(
                    la[inpair], lb[inpair], lrefv[:, :1], lk1[:, :1], leng[:, :1], lcls[:, :1], u, tiny
                )
                extra = {"warnings": lwarn, "mono": {0: (int(sig[0]), int(wrong[0]), bool(monotone[0]))}}
                lmeta = [(sp.family, sp.label, form) for form in LIGHT_FORMS]
                _group_rows(
                    rows, points, sel, lmeta, lcls, lerr, lratio, lok, leng, lrefv, lref["kappa"], lcases, dtname, dt,
                    extra,
                )  # fmt: skip
    pts = {}
    if points:
        pts = {
            "err": np.concatenate([p[0] for p in points]),
            "kappa": np.concatenate([p[1] for p in points]),
            "ill": np.concatenate([p[2] for p in points]),
            "dtype": np.concatenate([np.full(len(p[0]), p[3], dtype=object) for p in points]),
            "model_family": np.concatenate([np.full(len(p[0]), p[4], dtype=object) for p in points]),
            "case_family": np.concatenate([np.full(len(p[0]), p[5], dtype=object) for p in points]),
            "form": np.concatenate([np.full(len(p[0]), p[6], dtype=object) for p in points]),
        }
    t_eng = time.perf_counter() - t1
    return StabilityResult(
        rows,
        pts,
        tuple(np.dtype(d).name for d in dtypes),
        len(cases),
        len(lcases),
        {"reference": t_ref, "engine_and_checks": t_eng, "total": time.perf_counter() - t0},
        [rr for rr in rearr if rr.before],
    )

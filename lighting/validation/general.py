r"""The stability sweep's general reference path: a model's whole ``f_r`` at 80 digits and its condition number.

The models beyond the slides (Oren–Nayar, Ward, Ashikhmin–Shirley, Disney, Cook–Torrance with the
height-correlated ``G2`` or anisotropic roughness) do not factor into the shared table of
:mod:`lighting.validation.reference`; their specs (``ModelSpec.general``) take this path instead:

* the value: :func:`lighting.validation.model_references.model_value` on a
  :func:`~lighting.validation.model_references.frame` of the exact binary inputs;
* the condition number by its definition, perturbing each input directly:

      κ = Σ_i max_± |f(x with x_i → x_i (1 ± δ)) − f(x)| / (|f(x)| δ),   δ = 1e-30,

  over the nine components of ``n``, ``l``, ``v`` (one frame per perturbed input, shared by every
  model) and the model's shape parameters (σ, α, α_x, α_y, ν_u, ν_v, R_s, Disney's weights …;
  the pure scales ``k_s`` and a qualitative Oren–Nayar's ``k_d`` are left out, as ``k_s`` and
  ``k_d`` are for the slides' models).  A perturbation that moves a direction across the horizon
  makes κ infinite, as on the factor path.

Columns are computed per form: ``f_r``, ``f_r (n·l)``, ``π f_r (n·l)`` and, for Cook–Torrance,
``D(h)`` (on the peak sweeps only, like the factor path's ``D``).
"""

from __future__ import annotations

import math

import numpy as np

from .cases import DELTA, ModelSpec, perturbed_inputs
from .model_references import (
    arithmetic,
    condition_parameters,
    frame,
    microfacet_ndf,
    model_parameters,
    model_value,
)
from .mpfr import mpfr_context


def _ndf_value(model, q, prm):
    if "alpha" in prm:
        ax = ay = prm["alpha"]
    else:
        ax, ay = prm["alpha_x"], prm["alpha_y"]
    return microfacet_ndf(model.ndf, q["ht"], q["hb"], q["nh"], ax, ay)


def _form_values(mp, model, forms, q, prm):
    """The columns' values at one frame and parameter set (``None`` where the frame is below the horizon)."""
    if not q["above"]:
        return [mp.zero] * len(forms)
    f = None
    out = []
    for form in forms:
        if form == "D":
            out.append(_ndf_value(model, q, prm))
            continue
        if f is None:
            f = model_value(model, q, prm)
        if form == "eval":
            out.append(f)
        elif form == "eval_cos":
            out.append(f * q["nl"])
        else:
            out.append(mp.pi * f * q["nl"])
    return out


def general_table(specs: list[ModelSpec], cols: list[tuple[int, str]], inputs, dps: int) -> dict:
    """Reference values and condition numbers of the general columns ``cols`` for a batch of inputs.

    Parameters
    ----------
    specs : list of ModelSpec
        Every spec of the sweep (``cols`` index into it; each of those specs has ``general``).
    cols : list of (int, str)
        ``(spec index, form)`` of the columns to compute, in their order.
    inputs : sequence
        ``(n, l, v, on_a_sweep)`` with the components already rounded to the dtype.
    dps : int
        Decimal digits.

    Returns
    -------
    dict
        ``hi``, ``lo`` (the double-double value), ``nz``, ``kappa``, ``logref``, each ``(len(inputs), len(cols))``.
    """
    import mpmath

    m, k = len(inputs), len(cols)
    out = {
        "hi": np.zeros((m, k)),
        "lo": np.zeros((m, k)),
        "nz": np.zeros((m, k), dtype=bool),
        "kappa": np.full((m, k), np.nan),
        "logref": np.full((m, k), np.nan),
    }
    groups: dict = {}  # spec index -> [(column, form)]
    for c, (si, form) in enumerate(cols):
        groups.setdefault(si, []).append((c, form))
    # Each input in MPFR where gmpy2 is installed; a model whose values there leave MPFR's exponent range (or divide
    # by 0) is computed again in mpmath, whose exponents have no bound (lighting.validation.mpfr).
    fast = mpfr_context()
    params = {si: (model_parameters(specs[si].model), condition_parameters(specs[si].model)) for si in groups}
    for r, item in enumerate(inputs):
        cells, again = [], list(groups)
        if fast is not None:
            with fast.workdps(dps), arithmetic(fast):
                frames = _frames(fast, item)
                if not fast.exceptional():  # the frames (products of binary inputs) stay in range in practice
                    again = []
                    for si, members in groups.items():
                        fast.clear_flags()
                        found = _cells(fast, frames, specs[si].model, members, params[si])
                        if fast.exceptional():
                            again.append(si)
                        else:
                            cells += found
        if again:
            with mpmath.mp.workdps(dps), arithmetic(mpmath.mp):
                frames = _frames(mpmath.mp, item)
                for si in again:
                    cells += _cells(mpmath.mp, frames, specs[si].model, groups[si], params[si])
        for c, kappa, hi, lo, logref in cells:
            out["kappa"][r, c] = kappa
            out["hi"][r, c] = hi
            out["lo"][r, c] = lo
            out["nz"][r, c] = True
            out["logref"][r, c] = logref
    return out


def split_raw(raw) -> tuple[float, float]:
    """An mpmath number's raw tuple (``x._mpf_``) rounded to the nearest double, and its remainder rounded to 64 bits
    and then to a double (0 where the double is 0 or not finite): the double-double value the sweep keeps."""
    import mpmath.libmp as libmp

    hi = libmp.to_float(raw)
    lo = 0.0
    if math.isfinite(hi) and hi != 0:
        lo = libmp.to_float(libmp.mpf_sub(raw, libmp.from_float(hi), 64, "n"))
    return hi, lo


def _double_double(mp, val) -> tuple[float, float]:
    """:func:`split_raw` of ``val``, an mpmath or an MPFR number (the same two roundings in MPFR)."""
    if hasattr(val, "_mpf_"):
        return split_raw(val._mpf_)
    hi = float(val)
    lo = 0.0
    if math.isfinite(hi) and hi != 0:
        with mp.workprec(64):
            lo = float(val - mp.mpf(hi))
    return hi, lo


def _frames(mp, item):
    """The frame at one input and at each of its perturbed inputs, in ``mp``.

    Returns ``(d, sweep, q0, perturbed)``: δ, whether the input is on a peak sweep, the input's :func:`frame` and
    ``(input index, side, frame)`` of each perturbed input (``q0["above"]`` False: nothing to compute).
    """
    d = mp.mpf(DELTA)
    x = [mp.mpf(float(c)) for c in (*item[0], *item[1], *item[2])]
    sweep = len(item) > 3 and bool(item[3])
    q0 = frame(x[0:3], x[3:6], x[6:9])
    perturbed = []
    if q0["above"]:
        perturbed = [(i, j, frame(xp[0:3], xp[3:6], xp[6:9])) for i, j, xp in perturbed_inputs(x, d)]
    return d, sweep, q0, perturbed


def _cells(mp, frames, model, members, params) -> list:
    """``(column, κ, hi, lo, log value)`` of each nonzero column of one model at one input (:func:`_frames`).

    ``members`` are the model's ``(column, form)``; ``params`` its parameters (floats) and the names perturbed.
    """
    d, sweep, q0, perturbed = frames
    members = [(c, f) for c, f in members if f != "D" or sweep]
    if not q0["above"] or not members:
        return []
    forms = [f for _, f in members]
    values, pnames = params
    prm0 = {key: mp.mpf(val) for key, val in values.items()}
    base = _form_values(mp, model, forms, q0, prm0)
    rel = np.zeros((len(forms), 9 + len(pnames), 2))
    for i, j, qp in perturbed:
        if qp["above"] != q0["above"]:
            rel[:, i, j] = np.inf
            continue
        vals = _form_values(mp, model, forms, qp, prm0)
        for a, (v0, v1) in enumerate(zip(base, vals, strict=True)):
            rel[a, i, j] = float((v1 - v0) / (v0 * d)) if v0 != 0 else 0.0
    for pi_, name in enumerate(pnames):
        for j, sgn in enumerate((1, -1)):
            prm = dict(prm0)
            prm[name] = prm[name] * (1 + sgn * d)
            vals = _form_values(mp, model, forms, q0, prm)
            for a, (v0, v1) in enumerate(zip(base, vals, strict=True)):
                rel[a, 9 + pi_, j] = float((v1 - v0) / (v0 * d)) if v0 != 0 else 0.0
    # Every column's κ at once (each row of the sums is the sum np.sum forms of that column alone).
    finite = np.isfinite(rel).all(axis=(1, 2))
    kappas = np.sum(np.max(np.abs(rel), axis=2), axis=1)
    cells = []
    for a, (c, _) in enumerate(members):
        val = base[a]
        if val == 0:
            continue
        kappa = float(kappas[a]) if finite[a] else math.inf
        hi, lo = _double_double(mp, val)
        cells.append((c, kappa, hi, lo, float(mp.log(val))))
    return cells

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

from .cases import DELTA, ModelSpec
from .model_references import condition_parameters, frame, microfacet_ndf, model_parameters, model_value


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
    import mpmath.libmp as libmp

    mp = mpmath.mp
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
    with mp.workdps(dps):
        d = mp.mpf(DELTA)
        prm0 = {si: {key: mp.mpf(val) for key, val in model_parameters(specs[si].model).items()} for si in groups}
        pnames_of = {si: condition_parameters(specs[si].model) for si in groups}
        for r, item in enumerate(inputs):
            x = [mp.mpf(float(c)) for c in (*item[0], *item[1], *item[2])]
            sweep = len(item) > 3 and bool(item[3])
            q0 = frame(x[0:3], x[3:6], x[6:9])
            if not q0["above"]:
                continue
            perturbed = []  # (row, side, frame)
            for i, xi in enumerate(x):
                if xi == 0:
                    continue
                for j, sgn in enumerate((1, -1)):
                    xp = list(x)
                    xp[i] = xi * (1 + sgn * d)
                    perturbed.append((i, j, frame(xp[0:3], xp[3:6], xp[6:9])))
            for si, members in groups.items():
                model = specs[si].model
                members = [(c, f) for c, f in members if f != "D" or sweep]
                if not members:
                    continue
                forms = [f for _, f in members]
                base = _form_values(mp, model, forms, q0, prm0[si])
                pnames = pnames_of[si]
                rel = np.zeros((len(forms), 9 + len(pnames), 2))
                for i, j, qp in perturbed:
                    if qp["above"] != q0["above"]:
                        rel[:, i, j] = np.inf
                        continue
                    vals = _form_values(mp, model, forms, qp, prm0[si])
                    for a, (v0, v1) in enumerate(zip(base, vals, strict=True)):
                        rel[a, i, j] = float((v1 - v0) / (v0 * d)) if v0 != 0 else 0.0
                for pi_, name in enumerate(pnames):
                    for j, sgn in enumerate((1, -1)):
                        prm = dict(prm0[si])
                        prm[name] = prm[name] * (1 + sgn * d)
                        vals = _form_values(mp, model, forms, q0, prm)
                        for a, (v0, v1) in enumerate(zip(base, vals, strict=True)):
                            rel[a, 9 + pi_, j] = float((v1 - v0) / (v0 * d)) if v0 != 0 else 0.0
                for a, (c, _) in enumerate(members):
                    val = base[a]
                    if val == 0:
                        continue
                    g = rel[a]
                    out["kappa"][r, c] = (
                        float(np.sum(np.max(np.abs(g), axis=1))) if np.all(np.isfinite(g)) else math.inf
                    )
                    raw = val._mpf_
                    hi = libmp.to_float(raw)
                    out["hi"][r, c] = hi
                    if math.isfinite(hi) and hi != 0:
                        out["lo"][r, c] = libmp.to_float(libmp.mpf_sub(raw, libmp.from_float(hi), 64, "n"))
                    out["nz"][r, c] = True
                    out["logref"][r, c] = float(mp.log(val))
    return out

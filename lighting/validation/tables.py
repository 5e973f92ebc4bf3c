"""The reference tables of the stability sweep: values, condition numbers and predicates per batch of inputs.

:func:`_ref_table` is the worker entry point of :func:`lighting.validation.stability.run`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from .cases import DELTA, LIGHT_FORMS, REFERENCE_DPS, ModelSpec, brdf_specs, light_specs
from .general import general_table, split_raw
from .reference import _brdf_gradients, _constant, _light_gradients, _mp


# ============================================================================ reference tables
def _kappa(g: np.ndarray) -> float:
    """``Σ_i max_± |relative change| / δ`` from a ``(rows, 2)`` array of relative changes."""
    if not np.all(np.isfinite(g)):
        return math.inf
    return float(np.sum(np.max(np.abs(g), axis=1)))


def _columns(specs, forms_of) -> list[tuple[int, str]]:
    return [(i, f) for i, s in enumerate(specs) for f in forms_of(s)]


def _brdf_forms(spec: ModelSpec):
    return tuple(spec.terms)


PREDICATES = ("nl", "nv", "rv")


def _ref_table(kind: str, dtname: str, inputs: Sequence, dps: int = REFERENCE_DPS) -> dict:
    """Reference values, condition numbers and predicate condition numbers for a batch: worker entry point.

    ``kind`` is ``"brdf"`` (inputs ``(n, l, v)``) or ``"light"`` (inputs ``(spec index,
    point)``), each component already rounded to ``dtname``.  Besides the double-double
    value (``hi + lo``) the natural logarithm of the value is returned (``logref``): it
    stays meaningful beyond the float64 range and serves the logarithmic test of
    ill-conditioned points.
    """
    mp = _mp()
    import mpmath.libmp as _libmp

    general_cols: list = []
    if kind == "brdf":
        specs = brdf_specs()
        all_cols = _columns(specs, _brdf_forms)
        # The models with a whole-f_r reference (ModelSpec.general) come last: the factor columns keep
        # their places, and the general ones are appended (lighting.validation.general).
        factor_cols = [(si, form) for si, form in all_cols if not specs[si].general]
        general_cols = [(si, form) for si, form in all_cols if specs[si].general]
        assert all_cols == factor_cols + general_cols
        cols = [specs[si].terms[form] for si, form in factor_cols]
        preds = PREDICATES
    else:
        lspecs = light_specs()
        cols = [("1", ((form, 1),)) for form in LIGHT_FORMS]
        preds = ("cone",)
    m, k = len(inputs), len(cols)
    out = {
        "hi": np.zeros((m, k)),
        "lo": np.zeros((m, k)),
        "nz": np.zeros((m, k), dtype=bool),
        "kappa": np.full((m, k), np.nan),
        "pred": np.zeros((m, len(preds))),
        "logref": np.full((m, k), np.nan),
    }
    # Every column is  constant × Π factor^power:  its log-gradient is the same combination of
    # the factors' log-gradients (one matrix product), its value a product shared by prefix.
    fkeys = sorted({key for _, factors in cols for key, _ in factors})
    fidx = {key: i for i, key in enumerate(fkeys)}
    powers = np.zeros((k, len(fkeys)))
    for c, (_, factors) in enumerate(cols):
        for key, pw in factors:
            powers[c, fidx[key]] += pw
    # The products as a program: prefix nodes (parent, factor, power) shared between columns.
    prog_nodes: list = []
    node_of: dict = {}
    prog_cols = np.full(k, -1)
    for c, (_, factors) in enumerate(cols):
        parent = -1
        for key, pw in factors:
            nk = (parent, fidx[key], pw)
            if nk not in node_of:
                node_of[nk] = len(prog_nodes)
                prog_nodes.append(nk)
            parent = node_of[nk]
        prog_cols[c] = parent
    col_ok = np.ones(k, dtype=bool)
    is_d = np.array(
        [
            kind == "brdf" and form == "D"
            for _, form in (factor_cols if kind == "brdf" else [(0, f) for f in LIGHT_FORMS])
        ]
    )

    def item_sweep(item):
        return kind != "brdf" or (len(item) > 3 and bool(item[3]))

    with mp.workdps(dps):
        consts = {name: _constant(mp, name) for name in {cname for cname, _ in cols}}
        logconst = np.array([float(mp.log(consts[cname])) for cname, _ in cols])
        const_raw = [consts[cname]._mpf_ for cname, _ in cols]
        for r, item in enumerate(inputs):
            if kind == "brdf":
                x = [mp.mpf(float(c)) for c in (*item[0], *item[1], *item[2])]
            else:
                sp = lspecs[item[0]]
                axis = sp.direction if sp.direction is not None else (0.0, 0.0, 0.0)
                x = [mp.mpf(float(c)) for c in (*item[1], *sp.position, *axis)]
            if kind == "brdf":
                above, base, grads = _brdf_gradients(mp, x, DELTA)
                base["above"] = above
            else:
                base, grads = _light_gradients(mp, x, lspecs[item[0]], DELTA)
            for j, key in enumerate(preds):
                if key in base:
                    out["pred"][r, j] = math.inf if base[key] == 0 else _kappa(grads[key])
            if not base["above"]:
                continue
            nx = next(iter(grads.values())).shape[0]  # vector components, then parameters
            fg = np.zeros((len(fkeys), nx * 2))
            flog = np.zeros(len(fkeys))
            zero = np.zeros(len(fkeys), dtype=bool)
            for key, i in fidx.items():
                val = base.get(key)
                if val is None or val == 0:
                    zero[i] = True
                    continue
                fg[i] = grads[key].reshape(-1)
                flog[i] = float(mp.log(abs(val)))
            with np.errstate(invalid="ignore"):
                g = (powers @ np.where(np.isfinite(fg), fg, 0.0)).reshape(k, nx, 2)
                bad = (np.abs(powers) > 0) @ ~np.all(np.isfinite(fg), axis=1)
            kap = np.sum(np.max(np.abs(g), axis=2), axis=1)
            kap[bad] = np.inf
            colzero = (np.abs(powers) > 0) @ zero
            # Products on raw mpmath tuples (libmp): the wrappers cost more than the arithmetic here.
            prec = mp.prec
            fac_raw = [None] * len(fkeys)
            for key, i in fidx.items():
                if not zero[i]:
                    fac_raw[i] = base[key]._mpf_
            inv_raw = {}
            pre = [None] * len(prog_nodes)
            for pid, (parent, fi, pw) in enumerate(prog_nodes):
                if zero[fi] or (parent >= 0 and pre[parent] is None):
                    continue  # a zero factor: the columns through this node are 0
                if pw == 1:
                    f = fac_raw[fi]
                else:
                    f = inv_raw.get((fi, pw))
                    if f is None:
                        f = inv_raw[(fi, pw)] = (base[fkeys[fi]] ** pw)._mpf_
                pre[pid] = f if parent < 0 else _libmp.mpf_mul(pre[parent], f, prec, "n")
            logs = logconst + powers @ flog
            wanted = col_ok if item_sweep(item) else col_ok & ~is_d
            for c in np.flatnonzero(wanted & ~colzero):
                t = const_raw[c]
                pid = prog_cols[c]
                val = t if pid < 0 else _libmp.mpf_mul(t, pre[pid], prec, "n")
                out["hi"][r, c], out["lo"][r, c] = split_raw(val)
                out["nz"][r, c] = True
                out["kappa"][r, c] = kap[c]
                out["logref"][r, c] = logs[c]
    if general_cols:
        gen = general_table(specs, general_cols, inputs, dps)
        for key, arr in gen.items():
            out[key] = np.concatenate([out[key], arr], axis=1)
    return out

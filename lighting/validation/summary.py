"""The summary of the stability sweep: one row per model variant × case family × dtype × form."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .cases import BOUND_FACTOR, BrdfCase, unit_roundoff
from .classify import CLASSES, EDGE, ILL, NORMAL, OVER, ZERO


# ============================================================================ summary
@dataclass
class SummaryRow:
    """One model variant × case family × dtype × form of the sweep.

    ``max_rel_err`` is the largest relative error among the points whose true
    value is a normal number of the dtype (and that are not edge points);
    ``worst_*`` are the inputs of that point (for BRDFs ``n``, ``l``, ``v``; for
    lights the surface point, the light position and the spot axis), each as
    three ``repr`` floats.  ``max_ratio`` is the largest ``err / (max(κ,1) u)``:
    the row meets the bound when it is <= 8.
    """

    model_family: str
    model: str
    case_family: str
    dtype: str
    form: str
    points: int = 0
    nonfinite: int = 0
    negative: int = 0
    warnings: int = 0
    normal: int = 0
    ill: int = 0
    edge: int = 0
    zero: int = 0
    over: int = 0
    under: int = 0
    failures: int = 0
    max_rel_err: float = 0.0
    kappa_at_max_err: float = float("nan")
    max_ratio: float = 0.0
    kappa_at_max_ratio: float = float("nan")
    worst_case: str = ""
    worst_ratio_case: str = ""
    worst_a: str = ""
    worst_b: str = ""
    worst_c: str = ""
    worst_engine: float = float("nan")
    worst_reference: float = float("nan")
    mono_pairs: int = 0
    mono_fail: int = 0
    lobe_monotone: bool = True
    recip_pairs: int = 0
    recip_fail: int = 0
    recip_max_ratio: float = 0.0
    ill_max_ratio: float = 0.0
    first_failure: str = ""

    @property
    def passed(self) -> bool:
        """Every check of the row holds and the worst ratio is within :data:`BOUND_FACTOR`."""
        return (
            self.nonfinite == 0
            and self.negative == 0
            and self.warnings == 0
            and self.failures == 0
            and self.mono_fail == 0
            and self.recip_fail == 0
            and not self.max_ratio > BOUND_FACTOR
        )


@dataclass
class StabilityResult:
    """Everything :func:`run` measured (see :class:`SummaryRow`)."""

    rows: list
    points: dict
    dtypes: tuple
    n_brdf_cases: int
    n_light_cases: int
    seconds: dict = field(default_factory=dict)
    rearrangements: list = field(default_factory=list)

    @property
    def passed(self) -> bool:
        """Every row passed."""
        return all(r.passed for r in self.rows)


def _vec_str(x) -> str:
    return " ".join(repr(float(c)) for c in x)


def _binary(x, dt) -> list:
    """The components of ``x`` rounded to ``dt``, as exact Python floats."""
    return np.asarray(x, dtype=dt).astype(np.float64).tolist()


def _sweep_pairs(cases) -> tuple[np.ndarray, np.ndarray]:
    """Index pairs ``(a, b)`` of consecutive points of every sweep (``b`` one step further from the peak)."""
    groups: dict = {}
    for i, c in enumerate(cases):
        if c.sweep:
            groups.setdefault((c.family, c.sweep), []).append(i)
    a, b = [], []
    for idx in groups.values():
        idx = sorted(idx, key=lambda i: cases[i].step)
        a += idx[:-1]
        b += idx[1:]
    return np.array(a, dtype=int), np.array(b, dtype=int)


def _order_stats(pa, pb, ref, k1, eng, cls, u, tiny):
    """Per column: pairs whose true values differ by more than both error bounds, pairs the engine
    orders differently, and whether the true values never increase along the sweep."""
    if not len(pa):
        k = ref.shape[1]
        return np.zeros(k, int), np.zeros(k, int), np.ones(k, bool)
    ra, rb = ref[pa], ref[pb]
    skip = np.isin(cls[pa], (EDGE, ZERO)) | np.isin(cls[pb], (EDGE, ZERO))
    with np.errstate(invalid="ignore", over="ignore"):
        slack = BOUND_FACTOR * u * (k1[pa] * ra + k1[pb] * rb) + 2 * tiny
        sig = ~skip & (np.abs(ra - rb) > slack)
    ea, eb = eng[pa].max(axis=-1), eng[pb].max(axis=-1)
    wrong = sig & (((ra > rb) & ~(ea >= eb)) | ((ra < rb) & ~(ea <= eb)))
    monotone = ~np.any(~skip & (rb > ra * (1 + 1e-40)), axis=0)
    return sig.sum(axis=0), wrong.sum(axis=0), monotone


def _group_rows(rows_out, points_out, sel, meta, cls, err, ratio, ok, eng, ref, kappa, cases, dtname, dt, extra):
    """Append one :class:`SummaryRow` per column for the points ``sel`` (one case family)."""
    c_ = cls[sel]
    e_ = eng[sel]
    finite = np.all(np.isfinite(e_), axis=-1)
    neg = np.any(e_ < 0, axis=-1)
    counts = {name: np.sum(c_ == code, axis=0) for code, name in enumerate(CLASSES)}
    fails = ~ok[sel]
    errn = np.where(c_ == NORMAL, err[sel], -1.0)
    ratn = np.where(c_ == NORMAL, ratio[sel], -1.0)
    rati = np.where((c_ == ILL) & np.isfinite(ratio[sel]), ratio[sel], -1.0)
    ie, ir, ff = errn.argmax(axis=0), ratn.argmax(axis=0), fails.argmax(axis=0)
    big = float(np.finfo(dt).max)
    for c, (family, model, form) in enumerate(meta):
        if form is None:
            continue
        r = SummaryRow(family, model, cases[sel[0]].family, dtname, form)
        r.points = len(sel)
        r.nonfinite = int(np.sum(~finite[:, c]))
        r.negative = int(np.sum(neg[:, c]))
        r.warnings = extra["warnings"]
        for name in CLASSES:
            setattr(r, name, int(counts[name][c]))
        r.failures = int(np.sum(fails[:, c]))
        if r.failures:
            i = sel[ff[c]]
            r.first_failure = (
                f"{cases[i].label} [{CLASSES[cls[i, c]]}: engine {eng[i, c].max():.9g}, true {ref[i, c]:.9g}]"
            )
        if errn[ie[c], c] >= 0:
            i, j = sel[ie[c]], sel[ir[c]]
            r.max_rel_err, r.kappa_at_max_err = float(err[i, c]), float(kappa[i, c])
            r.max_ratio, r.kappa_at_max_ratio = float(ratio[j, c]), float(kappa[j, c])
            r.worst_case, r.worst_ratio_case = cases[i].label, cases[j].label
            cs = cases[i]
            if isinstance(cs, BrdfCase):
                r.worst_a, r.worst_b, r.worst_c = (_vec_str(_binary(x, dt)) for x in (cs.n, cs.l, cs.v))
            else:
                r.worst_a = _vec_str(_binary(cs.point, dt))
            r.worst_engine, r.worst_reference = float(eng[i, c].max()), float(ref[i, c])
        if rati[:, c].max() >= 0:
            r.ill_max_ratio = float(rati[:, c].max())
        keep = (c_[:, c] == NORMAL) | (c_[:, c] == ILL)
        if np.any(keep):
            # The error as judged: relative for normal points, |ln(f/f_true)| for ill-conditioned ones.
            kk = kappa[sel, c][keep]
            judged = ratio[sel, c][keep] * np.maximum(kk, 1.0) * unit_roundoff(dt)
            points_out.append((judged, kk, c_[keep, c] == ILL, dtname, family, r.case_family, form))
        if "mono" in extra and c in extra["mono"]:
            r.mono_pairs, r.mono_fail, r.lobe_monotone = extra["mono"][c]
        if "recip" in extra and c in extra["recip"]:
            q, a, b = extra["recip"][c]
            cc = c_[:, c]
            qs, as_, bs = q[sel], a[sel], b[sel]
            normal = cc == NORMAL
            r.recip_pairs = int(np.sum(normal | (cc == ZERO) | (cc == OVER)))
            r.recip_max_ratio = float(qs[normal].max()) if np.any(normal) else 0.0
            r.recip_fail = int(
                np.sum(normal & (qs > 2 * BOUND_FACTOR))
                + np.sum((cc == ZERO) & ~((as_ == 0) & (bs == 0)))
                + np.sum((cc == OVER) & ~((as_ == big) & (bs == big)))
            )
        rows_out.append(r)

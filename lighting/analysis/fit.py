r"""Fitting a model's parameters to a measured (or any other) BRDF by cosine-weighted least squares.

The loss compares the reflected radiance each BRDF gives under unit irradiance from ``l``:

$$
\mathcal{L}(\theta) = \sum_{(l, v)} w_{lv}\,\bigl(f_\theta(l, v) - f_\text{target}(l, v)\bigr)^2 (n\cdot l)^2,
$$

over a fixed, dense set of direction pairs (:func:`lighting.analysis.audit.direction_pairs`, which
includes near-mirror pairs where sharp lobes live), each channel a residual of its own.  Weighting by
``n·l`` is what a rendered image sees (``f_r (n·l)``): grazing light, where measured data are noisiest
and ``f_r`` of many models diverges, counts little.  The optimizer is SciPy's trust-region reflective
``least_squares`` within each parameter's range (imported when a fit runs); parameters the table marks
``log`` (exponents, roughness) are fitted as their logarithm, which makes the problem far better scaled.

Examples
--------
>>> from lighting.analysis.fit import fit_brdf
>>> from lighting.models import BlinnPhong
>>> target = BlinnPhong(0.4, 60.0, normalized=True)
>>> result = fit_brdf("blinn-phong-normalized", target, n_theta=8, n_phi=12)
>>> round(result.parameters["shininess"], 3), round(float(result.parameters["ks"][0]), 4)
(60.0, 0.4)
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..models.base import BRDF
from ..models.lambert import Lambert
from ..models.protocol import model_class, model_variants
from . import _display

__all__ = ["FitResult", "fit_brdf"]


class FitResult(NamedTuple):
    """What :func:`fit_brdf` found.

    Attributes
    ----------
    model : BRDF
        The fitted model.
    parameters : dict
        The fitted values by name (colours as 3-tuples), the fixed ones included.
    rms : float
        The cosine-weighted root-mean-square residual ``√(mean((f − f_target)² (n·l)²))`` in 1/sr.
    relative_rms : float
        ``rms`` over the same measure of the target (0: a perfect fit).
    errors : dict
        One standard error per fitted parameter (colours as 3-tuples), from the residuals and the Jacobian
        at the solution (the heteroscedasticity-consistent sandwich estimate, mapped through ``exp`` for
        log-fitted rows): what noise in the data leaves uncertain, if the model fits and the noise is
        independent from pair to pair.
    evaluations : int
        How many times the model was evaluated.
    success : bool
        Whether the optimizer reports convergence.
    message : str
        The optimizer's message.
    """

    model: BRDF
    parameters: dict
    rms: float
    relative_rms: float
    errors: dict
    evaluations: int
    success: bool
    message: str

    __repr__ = _display.fit_repr


def _free_rows(cls, fixed: dict):
    return [p for p in cls.parameters if p.name not in fixed and p.kind in ("float", "color") and p.default is not None]


def _bounds(p):
    lo, hi = p.low, p.high
    if p.log:
        lo = math.log(max(lo, 1e-12) if not p.low_open else max(lo, 1e-12) * (1 + 1e-12))
        hi = math.log(hi) if math.isfinite(hi) else math.log(1e12)
    elif p.low_open:
        lo = lo + max(abs(lo), 1.0) * 1e-12
    return lo, hi


def fit_brdf(model: str, target, *, fixed: dict | None = None, start: dict | None = None, n_theta: int = 12,
             n_phi: int = 16, max_theta_deg: float = 85.0, lambert: bool = False) -> FitResult:  # fmt: skip
    """Fit the continuous parameters of a registered model to a target BRDF.

    Parameters
    ----------
    model : str
        A registered model or variant name (:func:`lighting.models.model_names`); its ``float`` and
        ``color`` rows are fitted (a colour as three channels), ``bool`` and ``choice`` rows keep their
        defaults or the values in ``fixed``.
    target : BRDF or callable
        The data: a model (e.g. one read by :func:`lighting.load_brdf`) or a function ``f(n, l, v)``
        returning ``f_r`` of shape ``(P, 3)``.
    fixed : dict, optional
        Parameters held at the given values.
    start : dict, optional
        Starting values (defaults: the table's defaults).
    n_theta, n_phi, max_theta_deg
        The direction pairs compared (:func:`lighting.analysis.audit.direction_pairs`).
    lambert : bool
        Fit ``Lambert(k_d) + model``: ``k_d`` (RGB, the ``start`` key ``"kd"``) together with the model's
        rows.  Without a start it begins where it best explains the target beside the model's starting
        values (linear least squares in the same weights).  A specular lobe alone, fitted to a surface that
        is mostly diffuse, comes out a broad lobe that stands for the diffuse part too.

    Returns
    -------
    FitResult
        With ``lambert``, ``model`` is the sum and ``parameters`` and ``errors`` hold ``kd`` first.

    Raises
    ------
    ValueError
        An unknown model or parameter, a model with nothing to fit, or a target that gives non-finite
        values.

    Notes
    -----
    The residual of each pair and channel is ``(f_θ − f_target)(n·l)``; the result's ``relative_rms``
    says how much of the target the model cannot express.  A local optimizer finds a local minimum:
    ``start`` near the answer helps for sharp lobes.

    References
    ----------
    Ngan, Durand, Matusik, "Experimental analysis of BRDF models", EGSR 2005 (fitting analytic models
    to measured data, and why the weighting matters).
    """
    from scipy.optimize import least_squares  # a fit is rare; SciPy loads only then

    from .audit import direction_pairs

    variants = model_variants()
    if model not in variants:
        model_class(model)  # raises the registry's "unknown model … did you mean"
    cls, variant_fixed = variants[model]
    fixed = {**variant_fixed, **(fixed or {})}
    start = dict(start or {})
    table = {p.name: p for p in cls.parameters}
    kd_row = None
    if lambert:
        if "kd" in table:
            raise ValueError(f"fit_brdf: {model!r} has its own kd; lambert=True would add a second one")
        kd_row = next(p for p in Lambert.parameters if p.name == "kd")
    for name in (*fixed, *start):
        if name not in table and not (kd_row is not None and name == "kd" and name in start):
            raise ValueError(f"fit_brdf: {model!r} has no parameter {name!r}; it has {', '.join(table)}")
    fixed = {k: (v if k in variant_fixed else table[k].check(v)) for k, v in fixed.items()}
    rows = _free_rows(cls, fixed)
    if not rows:
        raise ValueError(f"fit_brdf: {model!r} has no continuous parameter left to fit")
    if kd_row is not None:
        table["kd"] = kd_row
        rows = [kd_row, *rows]

    l, v = direction_pairs(n_theta, n_phi, max_theta_deg)  # noqa: E741
    n = np.broadcast_to([0.0, 0.0, 1.0], l.shape)
    cos_l = l[:, 2:3]
    want = np.asarray(target.eval(n, l, v) if isinstance(target, BRDF) else target(n, l, v), dtype=np.float64)
    if want.shape != l.shape[:1] + (3,) or not np.all(np.isfinite(want)):
        raise ValueError(f"fit_brdf: the target must give finite f_r of shape ({len(l)}, 3); got shape {want.shape}")
    target_rms = float(np.sqrt(np.mean((want * cos_l) ** 2)))

    if kd_row is not None and "kd" not in start:
        # k_d starts where it explains the target best beside the model's starting values.
        spec0 = cls(**{**{p.name: start.get(p.name, p.default) for p in rows[1:]}, **fixed}).eval(n, l, v)
        w = cos_l**2
        start["kd"] = np.clip(math.pi * np.sum((want - spec0) * w, axis=0) / np.sum(w), 0.0, 1.0)

    # The vector of unknowns: one entry per float row, three per colour row, log where the table says.
    slots, x0, lo, hi = [], [], [], []
    for p in rows:
        value = np.broadcast_to(np.asarray(table[p.name].check(start.get(p.name, p.default)), float), (3,) if p.kind
                                == "color" else ())  # fmt: skip
        b = _bounds(p)
        for x in np.atleast_1d(value):
            x = float(np.clip(x, p.low, p.high))
            x = math.log(max(x, math.exp(b[0]))) if p.log else x
            x0.append(min(max(x, b[0]), b[1]))
            lo.append(b[0])
            hi.append(b[1])
        slots.append((p, len(np.atleast_1d(value))))
    evaluations = 0

    def build(x):
        values, i = dict(fixed), 0
        for p, k in slots:
            part = np.exp(x[i : i + k]) if p.log else np.asarray(x[i : i + k])
            values[p.name] = tuple(float(c) for c in part) if p.kind == "color" else float(part[0])
            i += k
        if kd_row is None:
            return cls(**values), values
        kd = values.pop("kd")
        return Lambert(kd) + cls(**values), {"kd": kd, **values}

    def residual(x):
        nonlocal evaluations
        evaluations += 1
        brdf, _ = build(x)
        return ((brdf.eval(n, l, v) - want) * cos_l).ravel()

    solution = least_squares(residual, np.array(x0), bounds=(np.array(lo), np.array(hi)), method="trf",
                             x_scale="jac", xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=2000)  # fmt: skip
    brdf, values = build(solution.x)
    res = residual(solution.x)
    evaluations -= 1  # that evaluation is not the optimizer's
    rms = float(np.sqrt(np.mean(res**2)))
    errors = _standard_errors(solution.jac, res, solution.x, slots)
    return FitResult(brdf, values, rms, rms / target_rms if target_rms > 0 else 0.0, errors, evaluations,
                     bool(solution.success), str(solution.message))  # fmt: skip


def _standard_errors(jac, res, x, slots) -> dict:
    """The sandwich ``(JᵀJ)⁻¹ Jᵀ diag(r²) J (JᵀJ)⁻¹ · m/(m − k)`` per fitted row (delta method through ``exp``).

    Measured data are noisier where they are brighter (relative noise), so one variance for every residual
    (``σ² (JᵀJ)⁻¹``) would understate the errors of lobe parameters; the sandwich (White 1980, "HC1")
    takes each residual's own size.
    """
    m, k = jac.shape
    with np.errstate(all="ignore"):
        bread = np.linalg.pinv(jac.T @ jac)
        meat = (jac * (res**2)[:, None]).T @ jac
        cov = bread @ meat @ bread * (m / max(m - k, 1))
    sd = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    out, i = {}, 0
    for p, count in slots:
        part = sd[i : i + count] * (np.exp(x[i : i + count]) if p.log else 1.0)
        out[p.name] = tuple(float(c) for c in part) if p.kind == "color" else float(part[0])
        i += count
    return out

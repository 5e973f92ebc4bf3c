"""Rearranged formulas: the engine with one formula put back to its earlier or textbook form.

Each :class:`Rearrangement` names the registered models it applies to (``models``, by
``model.name``) and how ``f_r`` is evaluated with the formula undone (``variant``): the
engine's own model on a :class:`~lighting.models.geometry.Geometry` carrying a textbook
quantity, or the textbook form of a model's formula built from the engine's own factors
(:mod:`lighting.validation.forms`); the spot light's textbook cone multiplies the falloff of
a public :class:`~lighting.lights.punctual.PointLight`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..models import Geometry
from ..numerics import cos_sin_deg, safe_div, saturate_to
from .cases import LIGHT_FORMS
from .classify import NORMAL
from .forms import (
    batch_normalize,
    blinn_phong_peak_form_fr,
    cook_torrance_fr,
    cos_squared_half_angle,
    plain_half_vector,
    textbook_r_dot_v,
)


@dataclass
class Rearrangement:
    """A formula the engine evaluates in a rearranged form, and what it bought on this sweep.

    ``before[dtype]`` / ``after[dtype]`` are ``(worst err / (max(κ,1) u), failing values)``
    over the ``f_r`` values (``eval``) of the affected models in every case family, with
    only this one formula put back to its earlier (or textbook) form.  ``existing`` marks rearrangements that were in
    the engine before this sweep was written (they are checked the same way).
    """

    name: str
    where: str
    formula_before: str
    formula_after: str
    existing: bool = False
    #: The registered model names (``model.name``) whose ``f_r`` carries the formula.
    models: tuple = ()
    #: The geometry the variant evaluates on, from the engine's and ``(n, l, v)``: ``q(g, n, l, v)``.
    quantities: Callable | None = field(default=None, repr=False, compare=False)
    #: ``f_r`` with the formula undone: ``variant(model, q, n, l, v)``, ``None`` where it does not apply.
    variant: Callable | None = field(default=None, repr=False, compare=False)
    before: dict = field(default_factory=dict)
    after: dict = field(default_factory=dict)


# ============================================================================ the variants
def _engine_fr(model, q, n, l, v):  # noqa: E741
    """The engine's own ``f_r`` on the geometry the rearrangement built (a quantity or the vectors put back)."""
    return model.eval_geometry(q)


def _batch_normalized(g, n, l, v):  # noqa: E741
    return Geometry(*(batch_normalize(x) for x in (n, l, v)), unit=True)


def _bp_peak_form(model, q, n, l, v):  # noqa: E741
    return blinn_phong_peak_form_fr(model, q)


def _divided_in_dtype(model, q, n, l, v):  # noqa: E741
    """``(k_s lobe/π) / (n·l)``: ``eval_cos`` (the lobe rounded to the dtype) divided by ``n·l``."""
    if model.name == "blinn-phong" and model.normalized:
        return None
    return safe_div(model.eval_cos(n, l, v), q.n_dot_l[..., None])


def _ct(form, float32_only=False, dielectric_only=False):
    def variant(model, q, n, l, v):  # noqa: E741
        if float32_only and n.dtype != np.float32:
            return None
        if dielectric_only and model.fresnel != "dielectric":
            return None
        return cook_torrance_fr(model, q, frozenset({form}))

    return variant


def textbook_spot(light, l):  # noqa: E741
    """The textbook spot factor: ``cos ψ >= cos(cutoff)`` and ``(cos ψ)^e``, ``cos ψ = −l·ŝ``.

    Parameters
    ----------
    light : SpotLight
        Its ``direction``, ``cutoff_deg`` and ``exponent`` are read.
    l : ndarray, shape (..., 3)
        Unit directions toward the light (float64).

    Returns
    -------
    ndarray
        The factor in [0, 1], float64.

    References
    ----------
    The OpenGL 2.1 specification, §2.14.1 (``spot_i``).
    """
    d = light.direction
    c = -(l[..., 0] * d[0] + l[..., 1] * d[1] + l[..., 2] * d[2])
    if light.cutoff_deg == 180:
        return np.ones_like(c)
    inside = c >= float(cos_sin_deg(light.cutoff_deg)[0])
    with np.errstate(under="ignore"):
        pw = np.ones_like(c) if light.exponent == 0 else np.maximum(c, 0.0) ** light.exponent
    return np.where(inside, pw, 0.0)


def rearrangement_list() -> list[Rearrangement]:
    """The rearranged formulas checked by :func:`run` (new ones first, then those the engine already had).

    Returns
    -------
    list of Rearrangement
        Fresh objects (``before`` and ``after`` empty).
    """
    return [
        Rearrangement(
            "half vector near l = −v",
            "models.geometry.Geometry._l_plus_v, models.geometry._unit_sum",
            "l + v from the normalized vectors",
            "where l·v < −1/2, components that cancel from (l_i²|v|² − v_i²|l|²)/(|l||v|(l_i|v| − v_i|l|)),"
            " with l_i²|v|² − v_i²|l|² = Σ_j (l_i v_j − v_i l_j)(l_i v_j + v_i l_j)",
            models=("blinn-phong", "cook-torrance"),
            quantities=lambda g, n, l, v: plain_half_vector(g),
            variant=_engine_fr,
        ),
        Rearrangement(
            "normalization path chosen per vector",
            "vec.normalize",
            "fast or scaled path for the whole batch",
            "per vector (a mirror pair l, R_l stays bit-symmetric whatever else is in the batch)",
            models=("lambert", "phong", "blinn-phong", "cook-torrance"),
            quantities=_batch_normalized,
            variant=_engine_fr,
        ),
        Rearrangement(
            "Blinn–Phong power far from the peak",
            "models.blinn_phong.BlinnPhong._lobe, models.microfacet.blinn_phong_ndf",
            "exp(e log1p(−(1 − n·h))) everywhere",
            "(n·h)^e directly (pow) where n·h < 1/2",
            models=("blinn-phong",),
            variant=_bp_peak_form,
        ),
        Rearrangement(
            "Phong / Blinn–Phong f_r divided in float64",
            "models.phong.Phong._f, models.blinn_phong.BlinnPhong._f, models.base._lobe_over_cos",
            "(k_s lobe / π) / (n·l) with the lobe rounded to the dtype (subnormal in float32)",
            "k_s lobe / (π n·l) in float64; exp(ln lobe − ln(π n·l)) where the lobe is subnormal in float64",
            models=("phong", "blinn-phong"),
            variant=_divided_in_dtype,
        ),
        Rearrangement(
            "Cook–Torrance D in float64 before the division",
            "models.cook_torrance.CookTorrance._separable",
            "D rounded to the dtype, then D G F / (c (n·v)(n·l))",
            "D in float64 (its tail may be subnormal in float32 where f_r is not)",
            models=("cook-torrance",),
            variant=_ct("d-dtype", float32_only=True),
        ),
        Rearrangement(
            "visibility G/((n·v)(n·l)) formed directly",
            "models.cook_torrance.CookTorrance._visibility, models.microfacet._smith_g1_den_*",
            "D G / (c (n·v)(n·l))",
            "Smith: 4 / (d_v d_l), G1 = 2 cos/d;  V-cavity: min(1/((n·v)(n·l)), (2 n·h/v·h)/max(n·v, n·l))",
            models=("cook-torrance",),
            variant=_ct("visibility"),
        ),
        Rearrangement(
            "dielectric Fresnel without a rounded η",
            "models.fresnel._dielectric_from_f0",
            "dielectric(v·h, η), η = (1 + √f0)/(1 − √f0) rounded",
            "r_par, r_perp multiplied through by (1 ∓ √f0): F(1) = f0 exactly",
            models=("cook-torrance",),
            variant=_ct("dielectric", dielectric_only=True),
        ),
        Rearrangement(
            "spot cone near its axis",
            "lights.punctual.SpotLight.spot_factor",
            "cos ψ ≥ cos(cutoff),  (cos ψ)^e",
            "1 − cos ψ = |l + ŝ|²/2 ≤ 2 sin²(cutoff/2),  exp(e log1p(−(1 − cos ψ)))",
        ),
        Rearrangement(
            "Phong lobe from |R_l − v|²/2",
            "models.geometry.Geometry.one_minus_r_dot_v",
            "(R_l·v)^e, R_l·v = 2 (n·l)(n·v) − l·v",
            "exp(e log1p(−|R_l − v|²/2))",
            existing=True,
            models=("phong",),
            quantities=lambda g, n, l, v: textbook_r_dot_v(g),
            variant=_engine_fr,
        ),
        Rearrangement(
            "tan²θ_h from the cross product",
            "models.geometry.Geometry.sin2_h, one_minus_n_dot_h",
            "sin²θ_h = 1 − cos²θ_h,  1 − n·h",
            "sin²θ_h = |n × h|²,  1 − n·h = sin²θ_h / (1 + n·h)",
            existing=True,
            models=("blinn-phong", "cook-torrance"),
            quantities=lambda g, n, l, v: cos_squared_half_angle(g),
            variant=_engine_fr,
        ),
        Rearrangement(
            "microfacet terms in float64",
            "models.cook_torrance.CookTorrance._separable",
            "D G F / (c (n·v)(n·l)) in float32 for float32 inputs",
            "in float64, rounded once at the end",
            existing=True,
            models=("cook-torrance",),
            variant=_ct("float32", float32_only=True),
        ),
    ]


def _legacy_engine(name, specs, cols, n, l, v):  # noqa: E741
    """Engine ``f_r`` values ``(m, len(cols), 3)`` with rearrangement ``name`` undone (NaN in other columns)."""
    import warnings

    rr = next(r for r in rearrangement_list() if r.name == name)
    out = np.full((n.shape[0], len(cols), 3), np.nan)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        g = Geometry(n, l, v)
        q = rr.quantities(g, n, l, v) if rr.quantities is not None else g
        for c, (si, form) in enumerate(cols):
            if form != "eval":  # f_r itself carries every rearranged formula; the other forms share them
                continue
            model = specs[si].model
            # The variants are of the slides' forms; the models on the general reference path
            # (correlated and anisotropic Cook–Torrance among them) are not rearranged there.
            if model.name not in rr.models or specs[si].general:
                continue
            f = rr.variant(model, q, n, l, v)
            if f is not None:
                out[:, c, :] = np.broadcast_to(f, (n.shape[0], 3))
    return out


def _legacy_light(specs, cases, dt):
    """Light values ``(m, len(LIGHT_FORMS), 3)`` with the spot lights' textbook cone (NaN for point lights)."""
    import warnings

    from ..lights.punctual import PointLight

    m = len(cases)
    vals = np.full((m, len(LIGHT_FORMS), 3), np.nan)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for si in sorted({c.spec for c in cases}):
            sp = specs[si]
            if sp.cutoff_deg is None:
                continue
            point = PointLight(sp.position, 1.0, sp.intensity, sp.attenuation)
            idx = [i for i, c in enumerate(cases) if c.spec == si]
            pts = np.array([cases[i].point for i in idx], dtype=dt)
            inc = next(point.incident(pts, dtype=dt))
            # The falloff and directions in float64 (the light's own precision), then the textbook cone.
            inc64 = next(point.incident(pts, dtype=np.float64))
            inc = inc._replace(scale=saturate_to(inc64.scale * textbook_spot(sp.light, inc64.direction), dt))
            vals[idx, 0, :] = np.asarray(inc.scale, dtype=np.float64)[:, None]
            vals[idx, 1, :] = np.broadcast_to(np.asarray(inc.irradiance, dtype=np.float64), (len(idx), 3))
    return vals


def _worst(cls, ratio, ok, mask):
    """``(worst ratio over normal points, failing values)`` within ``mask`` (columns that were evaluated)."""
    r = np.where(mask & (cls == NORMAL), ratio, -1.0)
    worst = float(r.max()) if r.size else 0.0
    return max(worst, 0.0), int(np.sum(mask & ~ok))

"""Rearranged formulas: the engine with one formula put back to its earlier or textbook form."""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np

from .cases import LIGHT_FORMS
from .classify import NORMAL


# ============================================================================ rearrangements
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
    before: dict = field(default_factory=dict)
    after: dict = field(default_factory=dict)


def _legacy_normalize(a):
    """The earlier :func:`lighting.vec.normalize`: one path (fast or scaled) for the whole batch."""
    from ..vec import _scaled

    fi = np.finfo(a.dtype)
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        len2 = a[..., 0] * a[..., 0] + a[..., 1] * a[..., 1] + a[..., 2] * a[..., 2]
    lo, hi = float(fi.tiny) * 1e4, float(fi.max) * 1e-4
    if np.all((len2 > lo) & (len2 < hi)):
        return a / np.sqrt(len2)[..., None]
    sc, _ = _scaled(a)
    len_s = np.sqrt(sc[..., 0] ** 2 + sc[..., 1] ** 2 + sc[..., 2] ** 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.where(len_s[..., None] > 0, sc / np.where(len_s > 0, len_s, 1)[..., None], 0)
    return out.astype(a.dtype, copy=False)


@functools.lru_cache(maxsize=1)
def _legacy_classes():
    """Engine classes with one formula each put back to its earlier or textbook form."""
    from functools import cached_property

    from .._numeric import saturate_to
    from ..lights.punctual import SpotLight, _cos_deg
    from ..models import fresnel as fr
    from ..models.brdf import BRDF, BlinnPhong, CookTorrance, Geometry, Phong, cos_power

    class PlainSum(Geometry):
        @cached_property
        def _l_plus_v(self):
            s = self.l + self.v
            return s, self._dot(s, s)

    class CosSquared(Geometry):  # textbook sin²θ_h = 1 − cos²θ_h
        @cached_property
        def sin2_h(self):
            c = np.clip(self.n_dot_h, -1, 1)
            return np.clip(1 - c * c, 0, 1)

        @cached_property
        def one_minus_n_dot_h(self):
            return 1 - np.minimum(self.n_dot_h, 1)

    class TextbookRv(Geometry):  # 1 − R_l·v with R_l·v = 2 (n·l)(n·v) − l·v, as the slides compute it
        @cached_property
        def one_minus_r_dot_v(self):
            return np.clip(1 - self.r_dot_v, 0, 2)

    class BPPeakOnly(BlinnPhong):  # (n·h)^e from 1 − n·h everywhere
        def _lobe(self, g, dtype=None, scale=1.0):
            dt = dtype or g.dtype
            lobe = cos_power(g.one_minus_n_dot_h.astype(dt), self.shininess)
            if scale != 1:  # the normalization multiplied on, as it was
                with np.errstate(over="ignore", under="ignore"):
                    lobe = saturate_to(lobe * scale, dt)
            return np.where(g.above, lobe, 0).astype(dt, copy=False)

    class PhongDtypeDivision(Phong):  # f_r = (k_s lobe/π) / (n·l) with the lobe rounded to the dtype first
        def _f(self, g):
            return BRDF._f(self, g)

    class BPDtypeDivision(BlinnPhong):
        def _f(self, g):
            return BRDF._f(self, g) if not self.normalized else super()._f(g)

    class LegacyCT(CookTorrance):
        legacy: frozenset = frozenset()

        def _separable(self, g, with_n_dot_l):
            if not self.legacy:
                return super()._separable(g, with_n_dot_l)
            wide = np.float32 if "float32" in self.legacy else np.float64
            d = self.D(g) if self.legacy & {"d-dtype", "float32"} else self._D(g, np.float64)
            if self.legacy & {"visibility", "float32"}:
                dg = d.astype(wide) * self.G(g).astype(wide)
                dg = np.where(g.above, dg, 0)
                den = wide(self._den_const()) * g.n_dot_v.astype(wide)
                if with_n_dot_l:
                    den = den * g.n_dot_l.astype(wide)
                with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
                    sv = np.where(den > 0, dg / np.where(den > 0, den, 1), 0)
            else:
                with np.errstate(over="ignore", invalid="ignore"):
                    dv = d.astype(np.float64) * self._visibility(g, with_n_dot_l)
                sv = np.where(g.above & ~np.isnan(dv), dv, 0) / self._den_const()
            sv = np.minimum(sv, np.finfo(wide).max).astype(np.float64)
            if self.fresnel == "none":
                return [(sv, self.ks)]
            vh = np.clip(g.v_dot_h.astype(wide), 0, 1)
            if self.fresnel == "schlick":
                m = ((1 - vh) ** 5).astype(np.float64)
                return [(sv, self.ks * self.f0), (sv * m, self.ks * (1.0 - self.f0))]
            if self.legacy & {"dielectric", "float32"}:
                f = fr.dielectric(vh, fr.eta_from_f0(self.f0)).astype(g.dtype).astype(np.float64)
            else:
                f = fr._dielectric_from_f0(vh, self.f0)
            return [(sv * f[..., i], self.ks * np.eye(3)[i]) for i in range(3)]

    class LegacySpot(SpotLight):
        def _spot(self, l):  # noqa: E741
            d = self.direction
            c = -(l[..., 0] * d[0] + l[..., 1] * d[1] + l[..., 2] * d[2])
            if self.cutoff_deg == 180:
                return np.ones_like(c)
            inside = c >= _cos_deg(self.cutoff_deg)
            with np.errstate(under="ignore"):
                pw = np.ones_like(c) if self.exponent == 0 else np.maximum(c, 0.0) ** self.exponent
            return np.where(inside, pw, 0.0)

    return {
        "PlainSum": PlainSum,
        "CosSquared": CosSquared,
        "TextbookRv": TextbookRv,
        "BPPeakOnly": BPPeakOnly,
        "PhongDtypeDivision": PhongDtypeDivision,
        "BPDtypeDivision": BPDtypeDivision,
        "LegacyCT": LegacyCT,
        "LegacySpot": LegacySpot,
    }


def _ct_variant(model, legacy):
    cls = _legacy_classes()["LegacyCT"]
    m = cls(**model._params())
    m.legacy = frozenset(legacy)
    return m


def rearrangement_list() -> list[Rearrangement]:
    """The rearranged formulas checked by :func:`run` (new ones first, then those the engine already had)."""
    return [
        Rearrangement(
            "half vector near l = −v",
            "brdf.Geometry._l_plus_v, brdf._unit_sum",
            "l + v from the normalized vectors",
            "where l·v < −1/2, components that cancel from (l_i²|v|² − v_i²|l|²)/(|l||v|(l_i|v| − v_i|l|)),"
            " with l_i²|v|² − v_i²|l|² = Σ_j (l_i v_j − v_i l_j)(l_i v_j + v_i l_j)",
        ),
        Rearrangement(
            "normalization path chosen per vector",
            "vec.normalize",
            "fast or scaled path for the whole batch",
            "per vector (a mirror pair l, R_l stays bit-symmetric whatever else is in the batch)",
        ),
        Rearrangement(
            "Blinn–Phong power far from the peak",
            "brdf.BlinnPhong._lobe, microfacet.blinn_phong_ndf",
            "exp(e log1p(−(1 − n·h))) everywhere",
            "(n·h)^e directly (pow) where n·h < 1/2",
        ),
        Rearrangement(
            "Phong / Blinn–Phong f_r divided in float64",
            "brdf.Phong._f, brdf.BlinnPhong._f, brdf._lobe_over_cos",
            "(k_s lobe / π) / (n·l) with the lobe rounded to the dtype (subnormal in float32)",
            "k_s lobe / (π n·l) in float64; exp(ln lobe − ln(π n·l)) where the lobe is subnormal in float64",
        ),
        Rearrangement(
            "Cook–Torrance D in float64 before the division",
            "brdf.CookTorrance._separable",
            "D rounded to the dtype, then D G F / (c (n·v)(n·l))",
            "D in float64 (its tail may be subnormal in float32 where f_r is not)",
        ),
        Rearrangement(
            "visibility G/((n·v)(n·l)) formed directly",
            "brdf.CookTorrance._visibility, microfacet._smith_g1_den_*",
            "D G / (c (n·v)(n·l))",
            "Smith: 4 / (d_v d_l), G1 = 2 cos/d;  V-cavity: min(1/((n·v)(n·l)), (2 n·h/v·h)/max(n·v, n·l))",
        ),
        Rearrangement(
            "dielectric Fresnel without a rounded η",
            "fresnel._dielectric_from_f0",
            "dielectric(v·h, η), η = (1 + √f0)/(1 − √f0) rounded",
            "r_par, r_perp multiplied through by (1 ∓ √f0): F(1) = f0 exactly",
        ),
        Rearrangement(
            "spot cone near its axis",
            "lights.SpotLight._spot",
            "cos ψ ≥ cos(cutoff),  (cos ψ)^e",
            "1 − cos ψ = |l + ŝ|²/2 ≤ 2 sin²(cutoff/2),  exp(e log1p(−(1 − cos ψ)))",
        ),
        Rearrangement(
            "Phong lobe from |R_l − v|²/2",
            "brdf.Geometry.one_minus_r_dot_v",
            "(R_l·v)^e, R_l·v = 2 (n·l)(n·v) − l·v",
            "exp(e log1p(−|R_l − v|²/2))",
            existing=True,
        ),
        Rearrangement(
            "tan²θ_h from the cross product",
            "brdf.Geometry.sin2_h, one_minus_n_dot_h",
            "sin²θ_h = 1 − cos²θ_h,  1 − n·h",
            "sin²θ_h = |n × h|²,  1 − n·h = sin²θ_h / (1 + n·h)",
            existing=True,
        ),
        Rearrangement(
            "microfacet terms in float64",
            "brdf.CookTorrance._separable",
            "D G F / (c (n·v)(n·l)) in float32 for float32 inputs",
            "in float64, rounded once at the end",
            existing=True,
        ),
    ]


def _legacy_engine(name, specs, cols, n, l, v):  # noqa: E741
    """Engine ``f_r`` values ``(m, len(cols), 3)`` with rearrangement ``name`` undone (NaN in other columns)."""
    import warnings

    from ..models.brdf import BlinnPhong, CookTorrance, Geometry, Phong

    lc = _legacy_classes()
    out = np.full((n.shape[0], len(cols), 3), np.nan)
    geom_cls = {
        "half vector near l = −v": lc["PlainSum"],
        "tan²θ_h from the cross product": lc["CosSquared"],
        "Phong lobe from |R_l − v|²/2": lc["TextbookRv"],
    }.get(name)
    ct_flag = {
        "Cook–Torrance D in float64 before the division": "d-dtype",
        "visibility G/((n·v)(n·l)) formed directly": "visibility",
        "dielectric Fresnel without a rounded η": "dielectric",
        "microfacet terms in float64": "float32",
    }.get(name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if name == "normalization path chosen per vector":
            g = Geometry(*(_legacy_normalize(x) for x in (n, l, v)), unit=True)
        geoms: dict = {}
        for c, (si, form) in enumerate(cols):
            if form != "eval":  # f_r itself carries every rearranged formula; the other forms share them
                continue
            model = specs[si].model
            variant, gclass = None, Geometry
            if name == "normalization path chosen per vector":
                variant = model
            elif name == "Phong lobe from |R_l − v|²/2":
                if isinstance(model, Phong):
                    variant, gclass = model, geom_cls
            elif geom_cls is not None and isinstance(model, (BlinnPhong, CookTorrance)):
                variant, gclass = model, geom_cls
            elif name == "Blinn–Phong power far from the peak" and isinstance(model, BlinnPhong):
                variant = lc["BPPeakOnly"](**model._params())
            elif name == "Phong / Blinn–Phong f_r divided in float64" and isinstance(model, (Phong, BlinnPhong)):
                if isinstance(model, BlinnPhong) and model.normalized:
                    continue
                variant = lc["PhongDtypeDivision" if isinstance(model, Phong) else "BPDtypeDivision"](**model._params())
            elif ct_flag is not None and isinstance(model, CookTorrance):
                if ct_flag == "dielectric" and model.fresnel != "dielectric":
                    continue
                if ct_flag in ("float32", "d-dtype") and n.dtype != np.float32:
                    continue
                variant = _ct_variant(model, {ct_flag})
            if variant is None:
                continue
            if name != "normalization path chosen per vector":
                if gclass not in geoms:
                    geoms[gclass] = gclass(n, l, v)
                g = geoms[gclass]
            f = getattr(
                variant, {"eval": "eval_geometry", "eval_cos": "eval_cos_geometry"}.get(form, "classic_geometry")
            )
            out[:, c, :] = np.broadcast_to(f(g), (n.shape[0], 3))
    return out


def _legacy_light(specs, cases, dt):
    import warnings

    lc = _legacy_classes()
    m = len(cases)
    vals = np.full((m, len(LIGHT_FORMS), 3), np.nan)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for si in sorted({c.spec for c in cases}):
            sp = specs[si]
            if sp.cutoff_deg is None:
                continue
            light = lc["LegacySpot"](
                sp.position, 1.0, sp.intensity, sp.attenuation, direction=sp.direction, cutoff_deg=sp.cutoff_deg,
                exponent=sp.exponent,
            )  # fmt: skip
            idx = [i for i, c in enumerate(cases) if c.spec == si]
            pts = np.array([cases[i].point for i in idx], dtype=dt)
            inc = next(light.incident(pts, dtype=dt))
            vals[idx, 0, :] = np.asarray(inc.scale, dtype=np.float64)[:, None]
            vals[idx, 1, :] = np.broadcast_to(np.asarray(inc.irradiance, dtype=np.float64), (len(idx), 3))
    return vals


def _worst(cls, ratio, ok, mask):
    """``(worst ratio over normal points, failing values)`` within ``mask`` (columns that were evaluated)."""
    r = np.where(mask & (cls == NORMAL), ratio, -1.0)
    worst = float(r.max()) if r.size else 0.0
    return max(worst, 0.0), int(np.sum(mask & ~ok))

r"""The Disney "principled" BRDF (Burley 2012), as Disney's BRDF Explorer evaluates it, and its sampler.

    f_r = (1 − metallic) [ base/π · mix(F_d, ss, subsurface) + sheen C_sheen F_H ]
        + D_s(h) G_s(l) G_s(v) F_s(θ_d) / (4 (n·l)(n·v))
        + clearcoat/4 · D_c(h) G_c(l) G_c(v) F_c(θ_d) / (4 (n·l)(n·v))

The sampler is a mixture of a smoothed cosine ``∝ (1 + cos θ)^4`` (diffuse, sheen), anisotropic
GTR2 half vectors (specular) and GTR1 half vectors (clearcoat), with its exact mixture density.
"""

from __future__ import annotations

import math

import numpy as np

from .._validate import check_range
from ..numerics import safe_div, saturate_to
from ..sampling.base import _TWO_PI, Sampler, Samples, _local_v
from ..vec import _dot, normalize
from .base import BRDF, BRDFFlags, _color, _color_text
from .geometry import Geometry
from .protocol import Lobe, Parameter, register_model

__all__ = ["Disney", "DisneySampler", "gtr1", "gtr2_aniso", "smith_ggx_aniso_over_2cos", "smooth_cosine_pdf"]

_INV_PI = 1.0 / math.pi
_BIG = float(np.finfo(np.float64).max)

#: The clearcoat's fixed Smith roughness (the explorer's ``smithG_GGX(NdotL, .25)``).
CLEARCOAT_G_ALPHA = 0.25
#: The clearcoat's Fresnel reflectance at normal incidence (a dielectric of index 1.5).
CLEARCOAT_F0 = 0.04


# --------------------------------------------------------------------------- the terms (float64, unchecked)
def gtr2_aniso(h_local, ax: float, ay: float) -> np.ndarray:
    r"""Anisotropic GTR2 (GGX) normal distribution, in the local frame ``(t, b, n)``.

        D(h) = 1 / (π α_x α_y ((h_t/α_x)² + (h_b/α_y)² + (h·n)²)²),   0 for h·n <= 0

    The explorer's ``GTR2_aniso``; a sum of squares, so no cancellation at the peak however small α.
    ``∫ D(h) (n·h) dω_h = 1``.

    Parameters
    ----------
    h_local : ndarray, shape (..., 3)
        Unit half vectors ``(h·t, h·b, h·n)`` (float64).
    ax, ay : float
        The roughnesses along ``t`` and ``b`` (> 0).

    Returns
    -------
    ndarray, shape (...)
        ``D`` in 1/sr, float64.
    """
    hx, hy, hz = h_local[..., 0], h_local[..., 1], h_local[..., 2]
    s = (hx / ax) ** 2 + (hy / ay) ** 2 + hz * hz
    with np.errstate(divide="ignore", over="ignore"):
        d = np.where(s > 0, 1.0 / (math.pi * ax * ay * s * s), 0.0)
    return np.where(hz > 0, np.minimum(d, _BIG), 0.0)


def gtr1(cos_h, sin2_h, a: float) -> np.ndarray:
    r"""GTR1 (Berry) normal distribution of the clearcoat.

        D(h) = (α² − 1) / (π ln(α²) (1 + (α² − 1) cos²θ_h))
             = (1 − α²) / (π (−ln α²) (sin²θ_h + α² cos²θ_h)),   0 for cos θ_h <= 0

    (``1/π`` at α = 1, the explorer's special case.)  The second form keeps its digits at the peak.
    ``∫ D(h) (n·h) dω_h = 1``.

    Parameters
    ----------
    cos_h, sin2_h : ndarray
        ``n·h`` and ``sin²θ_h = |n × h|²`` (float64).
    a : float
        α in (0, 1].

    Returns
    -------
    ndarray
        ``D`` in 1/sr, float64.
    """
    c = np.asarray(cos_h, dtype=np.float64)
    if a >= 1:
        return np.where(c > 0, _INV_PI, 0.0)
    a2 = a * a
    k = -math.expm1(math.log(a2)) / (math.pi * -math.log(a2))  # (1 − α²)/(π (−ln α²))
    t = np.asarray(sin2_h, dtype=np.float64) + a2 * c * c
    with np.errstate(divide="ignore", over="ignore"):
        d = np.where(t > 0, k / np.where(t > 0, t, 1.0), 0.0)
    return np.where(c > 0, d, 0.0)


def smith_ggx_aniso_over_2cos(w_local, ax: float, ay: float) -> np.ndarray:
    r"""``G1(ω) / (2 n·ω)`` of the anisotropic Smith GGX masking: the explorer's ``smithG_GGX_aniso``.

        G1(ω) / (2 n·ω) = 1 / (n·ω + √((ω_t α_x)² + (ω_b α_y)² + (n·ω)²))

    so that ``G1(l) G1(v) / (4 (n·l)(n·v))`` is the product of two of these, with no division by
    a grazing cosine.  With ``α_x = α_y = α`` it is the isotropic ``1/(n·ω + √(α² + (1 − α²)(n·ω)²))``.

    Parameters
    ----------
    w_local : ndarray, shape (..., 3)
        Unit directions ``(ω·t, ω·b, ω·n)`` (float64).
    ax, ay : float
        The roughnesses along ``t`` and ``b`` (> 0).

    Returns
    -------
    ndarray, shape (...)
        Float64; 0 where ``n·ω <= 0``.
    """
    x, y, z = w_local[..., 0], w_local[..., 1], w_local[..., 2]
    zp = np.maximum(z, 0.0)
    den = zp + np.sqrt((x * ax) ** 2 + (y * ay) ** 2 + zp * zp)
    return np.where((z > 0) & (den > 0), 1.0 / np.where(den > 0, den, 1.0), 0.0)  # no 1/0: 0 is replaced by 1


def _schlick_weight(c) -> np.ndarray:
    """``(1 − c)^5`` with ``c`` clamped to [0, 1] (the explorer's ``SchlickFresnel``)."""
    m = np.clip(1.0 - c, 0.0, 1.0)
    m2 = m * m
    return m2 * m2 * m


def _pow5(one_minus_c) -> np.ndarray:
    """``m^5`` for ``m = 1 − c`` given directly, clamped to [0, 1]."""
    m = np.clip(one_minus_c, 0.0, 1.0)
    m2 = m * m
    return m2 * m2 * m


def _one_minus_cos(c, near_one) -> np.ndarray:
    """``1 − c``: ``near_one`` (a cancellation-free form) where ``c >= 1/2``, ``1 − c`` itself below."""
    return np.where(c < 0.5, 1.0 - c, near_one)


def _one_minus_pow5(c, p5) -> np.ndarray:
    """``1 − (1 − c)^5`` given ``p5 = (1 − c)^5``: ``c (1 + m + m² + m³ + m⁴)``, ``m = 1 − c``, for ``c < 1/2``."""
    m = 1.0 - c
    return np.where(c < 0.5, c * (1 + m * (1 + m * (1 + m * (1 + m)))), 1.0 - p5)


def _lum(c) -> float:
    """The explorer's luminance approximation ``0.3 R + 0.6 G + 0.1 B``."""
    return float(0.3 * c[0] + 0.6 * c[1] + 0.1 * c[2])


def _unit01(name, value) -> float:
    return check_range(name, value, 0.0, 1.0)


# --------------------------------------------------------------------------- the model
class Disney(BRDF):
    r"""The Disney principled BRDF (Burley 2012) as Disney's BRDF Explorer shader ``disney.brdf`` has it.

    With ``θ_d`` the angle between ``l`` and ``h`` (``cos θ_d = l·h = v·h``), ``F_L = (1 − n·l)^5``,
    ``F_V = (1 − n·v)^5``, ``F_H = (1 − cos θ_d)^5`` (Schlick weights), ``r`` the roughness:

        f_r = (1 − metallic) · ( base/π · mix(F_d, ss, subsurface) + sheen · C_sheen · F_H )
            + D_s G_s F_s / (4 (n·l)(n·v))
            + 0.25 clearcoat · D_c G_c F_c / (4 (n·l)(n·v))

        diffuse     F_d  = (1 + (F_D90 − 1) F_L)(1 + (F_D90 − 1) F_V),   F_D90 = 0.5 + 2 r cos²θ_d
        subsurface  ss   = 1.25 (F_ss (1/(n·l + n·v) − 0.5) + 0.5)        (Hanrahan–Krueger)
                    F_ss = (1 + (F_ss90 − 1) F_L)(1 + (F_ss90 − 1) F_V),  F_ss90 = r cos²θ_d
        sheen       C_sheen = mix(1, C_tint, sheen_tint),   C_tint = base / lum(base)  (1 if lum = 0)
        specular    D_s  = GTR2_aniso = 1 / (π α_x α_y ((h_t/α_x)² + (h_b/α_y)² + (h·n)²)²)
                    α = r²,  aspect = √(1 − 0.9 anisotropic),  α_x = max(0.001, α/aspect),
                    α_y = max(0.001, α·aspect)
                    G_s  = G1(l) G1(v),  G1(ω) = 2 (n·ω) / (n·ω + √((ω_t α_x)² + (ω_b α_y)² + (n·ω)²))
                    F_s  = C_spec0 + (1 − C_spec0) F_H,
                    C_spec0 = mix(0.08 specular · mix(1, C_tint, specular_tint), base, metallic)
        clearcoat   D_c  = GTR1 = (α_c² − 1) / (π ln(α_c²) (1 + (α_c² − 1) cos²θ_h)),
                    α_c = mix(0.1, 0.001, clearcoat_gloss)
                    G_c  = G1(l) G1(v) with the isotropic α = 0.25,   F_c = 0.04 + 0.96 F_H

    where ``lum(c) = 0.3 c_R + 0.6 c_G + 0.1 c_B`` and ``h_t, h_b`` (``ω_t, ω_b``) are the components
    along the tangent ``t`` and bitangent ``b`` of the shading frame (``eval(..., tangent=...)``;
    without one, :attr:`lighting.models.geometry.Geometry.t`).  ``α_x`` runs along ``t``.

    Parameters
    ----------
    base_color : float or RGB triple in [0, 1]
        The surface colour (linear RGB): the diffuse albedo, and the metal's specular colour.
    metallic : float in [0, 1]
        0 dielectric, 1 metal (no diffuse or sheen; specular tinted by ``base_color``).
    subsurface : float in [0, 1]
        Blend of the Burley diffuse toward the Hanrahan–Krueger subsurface approximation.
    specular : float in [0, 1]
        The dielectric's normal-incidence reflectance, ``F0 = 0.08 specular`` (0.5: F0 = 0.04, η = 1.5).
    roughness : float in [0, 1]
        Perceptual roughness ``r``; the GGX ``α = r²`` (clamped at 0.001); also the diffuse
        retro-reflection.
    specular_tint : float in [0, 1]
        Tints the dielectric specular toward the base colour's hue.
    anisotropic : float in [0, 1]
        Aspect ratio of the specular lobe, ``α_y/α_x = 1 − 0.9 anisotropic``.
    sheen : float in [0, 1]
        A grazing sheen lobe for cloth, ``sheen · F_H``.
    sheen_tint : float in [0, 1]
        Tints the sheen toward the base colour's hue.
    clearcoat : float in [0, 1]
        A second, fixed white specular lobe of weight ``0.25 clearcoat``.
    clearcoat_gloss : float in [0, 1]
        The clearcoat's gloss: GTR1 ``α_c`` from 0.1 (satin) to 0.001 (gloss).

    Notes
    -----
    *Version.*  The formula is that of the shader ``disney.brdf`` of Disney's BRDF Explorer
    (github.com/wdas/brdf, ``src/brdfs/disney.brdf``, the revision with the anisotropic Smith G),
    which is the 2012 course notes' model with one change the notes do not have: the specular's
    Smith G uses the lobe's own ``α_x, α_y`` (separable anisotropic Smith GGX), where the 2012 notes
    remap the roughness for G to ``α_g = (0.5 + r/2)²`` (isotropic), a remapping Burley's 2015
    notes withdrew.  Departures from the shader:

    * ``base_color`` is linear RGB, as every colour of the engine; the explorer's ``mon2lin``
      (``x^2.2``) of its slider value is not applied;
    * the reflectance is 0 for ``n·l <= 0`` or ``n·v <= 0`` (the shader: ``< 0``; at 0 its
      ``1/(n·l + n·v)`` may be infinite);
    * the distributions are written in forms that keep their digits at a sharp peak: GTR2 as the
      shader's sum of squares (not ``1 + (α² − 1) cos²θ_h``), GTR1 with ``sin²θ_h + α² cos²θ_h``,
      and ``G1/(2 n·ω)`` with ``√(n·ω² + α² sin²θ)`` — the same functions, rounded differently.

    As in the shader (and pbrt-v3's ``DisneySheen``), the sheen term is not divided by π.

    *Reciprocity.*  Every term is symmetric in ``l`` and ``v`` (``F_d`` and ``F_ss`` are products
    of an ``l`` and a ``v`` factor, ``1/(n·l + n·v)``, ``θ_d``, ``h`` and the separable Smith
    ``G`` are symmetric), so the whole model is reciprocal: the diffuse, subsurface, sheen,
    specular and clearcoat parts each.

    *Energy.*  The model is not energy conserving by construction: the retro-reflective diffuse
    (``F_D90`` up to 2.5), the subsurface's ``1/(n·l + n·v)``, the sheen and the clearcoat add to
    the specular without the specular taking from them.  At the default parameters the
    directional albedo stays below 1 at every view (0.841 at the normal, rising to 0.989 near grazing;
    tests/models/test_disney.py); a white base at roughness 1 exceeds 1 everywhere (1.05 at the
    normal, 1.6 at grazing).

    *Numerics.*  Everything is computed in float64 from the geometry's cosines and local
    components and rounded once to the dtype of the vectors; the Schlick weights are formed from
    ``1 − cos`` given without cancellation (``sin²θ/(1 + cos θ)``, ``|l − v|²/(4 (1 + cos θ_d))``), so
    that a specular that is nothing but ``F_H`` (``specular = 0``) keeps its digits near the normal.
    ``f_r`` is bounded (``ss`` grows as ``1/(n·l + n·v)`` when both directions graze, to about
    ``6e5`` at 1e-6 rad; the specular is at most ``1/(π α_x α_y min(α_x, α_y)²)``, ``3.2e11`` for a
    mirror pair grazing at α = 0.001, and ``1/(4π α_x α_y) <= 8e4`` at the normal), so nothing saturates
    in float32.

    *Sampler.*  :class:`DisneySampler`: one-sample mixture of a smoothed cosine
    ``5 (1 + cos θ)^4/(64 π)`` (diffuse and sheen; :func:`smooth_cosine_pdf` says why not the
    clamped cosine), GTR2 half vectors with density ``D_s(h)(n·h)`` (specular) and GTR1 half
    vectors with density ``D_c(h)(n·h)`` (clearcoat), weighted by an estimate of each lobe's
    reflectance (see :class:`DisneySampler`), with the exact mixture density.

    References
    ----------
    B. Burley, "Physically-Based Shading at Disney", in *Practical Physically-Based Shading in Film
    and Game Production*, SIGGRAPH 2012 Course Notes, 2012 (the model; GTR; the remapped α_g).
    B. Burley, "Extending the Disney BRDF to a BSDF with Integrated Subsurface Scattering", in
    *Physically Based Shading in Theory and Practice*, SIGGRAPH 2015 Course Notes, 2015 (the
    roughness remapping of G dropped).
    Walt Disney Animation Studios, *BRDF Explorer*, ``src/brdfs/disney.brdf``,
    https://github.com/wdas/brdf, 2012–2015 (the shader followed here).
    P. Hanrahan and W. Krueger, "Reflection from layered surfaces due to subsurface scattering",
    Proceedings of SIGGRAPH 93, 165–174, 1993.
    B. Walter, S. R. Marschner, H. Li and K. E. Torrance, "Microfacet models for refraction
    through rough surfaces", EGSR 2007 (GGX = GTR2, Smith G1, half-vector sampling).
    E. Heitz, "Understanding the masking-shadowing function in microfacet-based BRDFs", Journal of
    Computer Graphics Techniques 3(2), 48–107, 2014 (the anisotropic Smith G1).
    C. Schlick, "An inexpensive BRDF model for physically-based rendering", Computer Graphics
    Forum 13(3), 233–246, 1994.

    Examples
    --------
    At normal incidence (``F_L = F_V = F_H = 0``) with the defaults: ``0.8/π`` of diffuse plus
    ``C_spec0 D(n) G/4 = 0.04 · 1/(π 0.25²) · 1/4``:

    >>> m = Disney()
    >>> round(float(m.eval((0, 0, 1.0), (0, 0, 1.0), (0, 0, 1.0))[0]), 6)
    0.305577
    >>> round(0.8 / math.pi + 0.04 / (math.pi * 0.0625) / 4, 6)
    0.305577
    """

    name = "disney"
    flags = BRDFFlags.SPECULAR | BRDFFlags.OWN_DIFFUSE  # the Burley diffuse (and sheen) beside the specular lobes
    parameters = (
        Parameter("base_color", "color", 0.8, high=1.0, slider=(0.0, 1.0),
                  description="base colour (linear RGB): diffuse albedo, metal's specular colour"),
        Parameter("metallic", "float", 0.0, high=1.0, description="0 dielectric, 1 metal"),
        Parameter("subsurface", "float", 0.0, high=1.0,
                  description="blend of the diffuse toward the Hanrahan–Krueger subsurface shape"),
        Parameter("specular", "float", 0.5, high=1.0,
                  description="dielectric specular amount: F0 = 0.08 · specular (0.5: F0 = 0.04)"),
        Parameter("roughness", "float", 0.5, high=1.0,
                  description="perceptual roughness r (GGX α = r², at least 0.001)"),
        Parameter("specular_tint", "float", 0.0, high=1.0,
                  description="tints the dielectric specular toward the base colour's hue"),
        Parameter("anisotropic", "float", 0.0, high=1.0,
                  description="specular aspect ratio α_y/α_x = 1 − 0.9 · anisotropic"),
        Parameter("sheen", "float", 0.0, high=1.0, description="grazing sheen lobe for cloth"),
        Parameter("sheen_tint", "float", 0.5, high=1.0,
                  description="tints the sheen toward the base colour's hue"),
        Parameter("clearcoat", "float", 0.0, high=1.0,
                  description="second white specular lobe (GTR1), weight 0.25 · clearcoat"),
        Parameter("clearcoat_gloss", "float", 1.0, high=1.0,
                  description="clearcoat gloss: GTR1 α from 0.1 (satin) to 0.001 (gloss)"),
    )

    def __init__(
        self,
        base_color=0.8,
        metallic=0.0,
        subsurface=0.0,
        specular=0.5,
        roughness=0.5,
        specular_tint=0.0,
        anisotropic=0.0,
        sheen=0.0,
        sheen_tint=0.5,
        clearcoat=0.0,
        clearcoat_gloss=1.0,
    ):
        self.base_color = _color("base_color", base_color, hi=1.0)
        self.metallic = _unit01("metallic", metallic)
        self.subsurface = _unit01("subsurface", subsurface)
        self.specular = _unit01("specular", specular)
        self.roughness = _unit01("roughness", roughness)
        self.specular_tint = _unit01("specular_tint", specular_tint)
        self.anisotropic = _unit01("anisotropic", anisotropic)
        self.sheen = _unit01("sheen", sheen)
        self.sheen_tint = _unit01("sheen_tint", sheen_tint)
        self.clearcoat = _unit01("clearcoat", clearcoat)
        self.clearcoat_gloss = _unit01("clearcoat_gloss", clearcoat_gloss)
        # The derived constants, as the shader forms them.
        lum = _lum(self.base_color)
        c_tint = self.base_color / lum if lum > 0 else np.ones(3)
        m = self.metallic
        spec_dielectric = self.specular * 0.08 * ((1 - self.specular_tint) + self.specular_tint * c_tint)
        self.c_spec0 = (1 - m) * spec_dielectric + m * self.base_color
        self.c_sheen = (1 - self.sheen_tint) + self.sheen_tint * c_tint
        aspect = math.sqrt(1 - 0.9 * self.anisotropic)
        alpha = self.roughness * self.roughness
        self.alpha_x = max(0.001, alpha / aspect)
        self.alpha_y = max(0.001, alpha * aspect)
        if self.alpha_x != self.alpha_y:
            self.flags = type(self).flags | BRDFFlags.ANISOTROPIC
        self.alpha_c = (1 - self.clearcoat_gloss) * 0.1 + self.clearcoat_gloss * 0.001

    # -- description ------------------------------------------------------------------
    def lobe(self):
        """``Lobe("half", √(α_x α_y)/√2)``: the specular GTR2 lobe (whose width the GGX peak has like Beckmann's
        ``α/√2``), with the quadrature scale the narrowest of ``α_x``, ``α_y`` and, with a clearcoat, ``α_c``;
        ``horizon="smith"``.  Anisotropic (``α_x ≠ α_y``): ``widths`` ``(α_x/√2, α_y/√2)`` and ``quadrature_widths``
        ``(α_x, α_y)``, the ellipse quadrature follows (the clearcoat, at most a quarter of a Schlick reflectance, is
        left to the rule's radial grading: its own ``α_c`` in both scales would make the rule round again, measured 3 %
        off at 89° against 5e-5 for the ellipse at ``r = 0.1``, ``anisotropic = 1``, clearcoat 1).
        """
        width = math.sqrt(self.alpha_x * self.alpha_y) / math.sqrt(2.0)
        scales = [self.alpha_x, self.alpha_y] + ([self.alpha_c] if self.clearcoat > 0 else [])
        if self.alpha_x != self.alpha_y:
            axes = (self.alpha_x, self.alpha_y)
            r2 = math.sqrt(2.0)
            return Lobe("half", width, quadrature_width=min(scales), horizon="smith",
                        widths=(axes[0] / r2, axes[1] / r2), quadrature_widths=axes, tails="ggx")  # fmt: skip
        return Lobe("half", width, quadrature_width=min(scales), horizon="smith", tails="ggx")

    @property
    def diffuse_albedo(self):
        """The base-colour terms' albedo at normal incidence (:attr:`BRDF.diffuse_albedo`).

        ``(1 − metallic) base_color ρ₁`` with ``ρ₁ = 2 ∫₀¹ f₁(μ) μ dμ`` the albedo at ``v = n`` of the
        diffuse and subsurface mix for a white base (``π f_r`` of those terms: ``f₁``), which is round
        about ``n`` there (``cos θ_d = cos(θ_l/2)``).  ``f₁`` is this model's own value with the base
        white minus its value with the base black (sheen, specular and clearcoat set to 0, so nothing
        else differs), on 32 Gauss–Legendre nodes in ``μ = n·l`` (a polynomial of degree 7 and
        ``1/(1 + μ)``: exact to rounding).  The sheen is not counted (a white grazing lobe, not the
        surface's colour).

        Returns
        -------
        numpy.ndarray, (3,)
        """
        if "_diffuse_albedo" not in self.__dict__:
            x, w = np.polynomial.legendre.leggauss(32)
            mu, w = 0.5 * (x + 1.0), 0.5 * w
            l = np.stack([np.sqrt((1 - mu) * (1 + mu)), np.zeros_like(mu), mu], axis=-1)  # noqa: E741
            n = np.array([0.0, 0.0, 1.0])
            kw = {"subsurface": self.subsurface, "roughness": self.roughness, "specular": 0.0, "sheen": 0.0}
            white = Disney(base_color=1.0, **kw).eval(n, l, n)[:, 0]
            black = Disney(base_color=0.0, **kw).eval(n, l, n)[:, 0]
            rho1 = 2.0 * math.pi * float(np.sum(w * (white - black) * mu))
            self.__dict__["_diffuse_albedo"] = (1.0 - self.metallic) * self.base_color * rho1
        return self.__dict__["_diffuse_albedo"].copy()

    def sampler(self):
        """``DisneySampler``: the mixture of cosine, GTR2 (``α_x, α_y``) and GTR1 (``α_c``) sampling with this model's
        weights.
        """
        return DisneySampler(
            self.alpha_x,
            self.alpha_y,
            self.alpha_c,
            diffuse=(1 - self.metallic) * float(np.mean(self.base_color)),
            sheen=(1 - self.metallic) * self.sheen * float(np.mean(self.c_sheen)),
            specular0=float(np.mean(self.c_spec0)),
            clearcoat=0.25 * self.clearcoat,
        )

    def summary(self):
        """For example ``"base=0.8 metallic=0 r=0.5 specular=0.5"``, followed by the other parameters that are not at
        their defaults.
        """
        text = (f"base={_color_text(self.base_color)} metallic={self.metallic:g} r={self.roughness:g} "
                f"specular={self.specular:g}")
        for p in self.parameters[5:]:
            value = getattr(self, p.name)
            if value != p.default:
                text += f" {p.name}={value:g}"
        if self.subsurface != 0:
            text += f" subsurface={self.subsurface:g}"
        return text

    def _params(self):
        return {p.name: getattr(self, p.name) for p in self.parameters}

    # -- evaluation -------------------------------------------------------------------
    def _lobes(self, g: Geometry):
        """``f_r`` in float64, shape ``(..., 3)``, 0 below the horizon; and ``n·l`` in float64."""
        f64 = np.float64
        nl = g.n_dot_l.astype(f64)
        nv = g.n_dot_v.astype(f64)
        above = g.above
        cd = np.clip(g.v_dot_h.astype(f64), 0.0, 1.0)  # cos θ_d = l·h = v·h
        # The Schlick weights from 1 − cos, formed without cancellation: 1 − n·ω = sin²θ/(1 + n·ω) and
        # 1 − cos θ_d = |l − v|²/(4 (1 + cos θ_d)) (as 1 − cos²θ_d = |l − v|²/4 for unit l, v) near
        # cos = 1; below cos = 1/2, where 1 − cos is exact to half an ulp, directly (the quotient's three
        # roundings, times 5 in the power, reached 17 ulp at grazing pairs).
        fl = _pow5(_one_minus_cos(nl, g.sin2_l.astype(f64) / (1 + np.maximum(nl, 0.0))))
        fv = _pow5(_one_minus_cos(nv, g.sin2_v.astype(f64) / (1 + np.maximum(nv, 0.0))))
        d = g.l.astype(f64) - g.v.astype(f64)
        fh = _pow5(_one_minus_cos(cd, np.sum(d * d, axis=-1) / (4 * (1 + cd))))
        terms = []
        if self.metallic < 1:
            cd2r = self.roughness * cd * cd
            fd90 = 0.5 + 2 * cd2r
            diffuse = (1 + (fd90 - 1) * fl) * (1 + (fd90 - 1) * fv)
            if self.subsurface > 0:
                # 1 + (F_ss90 − 1) F_L = (1 − F_L) + F_ss90 F_L: F_ss90 = r cos²θ_d is small at grazing pairs,
                # where 1 − F_L = 1 − (1 − n·l)^5 is itself small (5 n·l) and is taken without cancelling.
                fss = (_one_minus_pow5(nl, fl) + cd2r * fl) * (_one_minus_pow5(nv, fv) + cd2r * fv)
                s = nl + nv
                inv = np.where(s > 0, 1.0 / np.where(s > 0, s, 1.0), 0.0)
                ss = 1.25 * (fss * (inv - 0.5) + 0.5)
                diffuse = (1 - self.subsurface) * diffuse + self.subsurface * ss
            k = (1 - self.metallic) * _INV_PI
            terms.append(diffuse[..., None] * (k * self.base_color))
            if self.sheen > 0:
                terms.append(fh[..., None] * ((1 - self.metallic) * self.sheen * self.c_sheen))
        # Specular: D_s G1(l) G1(v) / (4 (n·l)(n·v)) = D_s · [G1(l)/(2 n·l)] · [G1(v)/(2 n·v)].
        ax, ay = self.alpha_x, self.alpha_y
        h_loc = g.h_local.astype(f64)
        ds = gtr2_aniso(h_loc, ax, ay)
        vis = smith_ggx_aniso_over_2cos(g.l_local.astype(f64), ax, ay) * smith_ggx_aniso_over_2cos(
            g.v_local.astype(f64), ax, ay)
        spec = ds * vis
        terms.append(spec[..., None] * (self.c_spec0 + (1 - self.c_spec0) * fh[..., None]))
        if self.clearcoat > 0:
            dc = gtr1(h_loc[..., 2], g.sin2_h.astype(f64), self.alpha_c)
            a2 = CLEARCOAT_G_ALPHA**2
            gl = _iso_g_over_2cos(nl, g.sin2_l.astype(f64), a2)
            gv = _iso_g_over_2cos(nv, g.sin2_v.astype(f64), a2)
            fc = CLEARCOAT_F0 + (1 - CLEARCOAT_F0) * fh
            terms.append((0.25 * self.clearcoat * dc * gl * gv * fc)[..., None] * np.ones(3))
        with np.errstate(over="ignore", invalid="ignore"):
            f = sum(terms)
        f = np.where(above[..., None], f, 0.0)
        return np.nan_to_num(f, nan=0.0, posinf=_BIG), nl

    def _f(self, g):
        f, _ = self._lobes(g)
        return saturate_to(f, g.dtype)

    def _f_cos(self, g):
        f, nl = self._lobes(g)
        return saturate_to(f * np.maximum(nl, 0.0)[..., None], g.dtype)

    def classic_geometry(self, g):
        """``π f_r (n·l)``, rounded once from float64. In the dtype of ``g``."""
        f, nl = self._lobes(g)
        return saturate_to(f * (math.pi * np.maximum(nl, 0.0))[..., None], g.dtype)


def _iso_g_over_2cos(c, s2, a2: float) -> np.ndarray:
    """Isotropic ``G1/(2 cos θ) = 1/(cos θ + √(cos²θ + α² sin²θ))`` (the explorer's ``smithG_GGX``), float64."""
    cp = np.maximum(c, 0.0)
    den = cp + np.sqrt(cp * cp + a2 * s2)
    return np.where((c > 0) & (den > 0), 1.0 / np.where(den > 0, den, 1.0), 0.0)  # no 1/0: 0 is replaced by 1


# --------------------------------------------------------------------------- the sampler
def smooth_cosine_pdf(z) -> np.ndarray:
    r"""The diffuse component's density ``p(l) = 5 (1 + cos θ)^4 / (64 π)`` on the whole sphere.

    A smooth stand-in for the clamped cosine ``max(cos θ, 0)/π``: it has no kink at the horizon
    (where a quadrature of the density, such as the contract's, loses digits), sends 31/32 of its
    directions above the horizon, and for a Lambertian lobe its weight
    ``(n·l)/(π p) = 12.8 cos θ/(1 + cos θ)^4`` is bounded (by 1.35, at ``cos θ = 1/3``), with a relative
    variance of 1/15 per sample where the clamped cosine has 0.  (The Disney diffuse is not
    Lambertian, so the clamped cosine would not be exact for it either.)

    Parameters
    ----------
    z : ndarray
        ``cos θ = l·n`` of unit directions (float64).

    Returns
    -------
    ndarray
        The density per steradian.
    """
    t = 1.0 + np.clip(z, -1.0, 1.0)
    t2 = t * t
    return (5.0 / (64.0 * math.pi)) * t2 * t2


def _smooth_cosine_directions(u) -> np.ndarray:
    """Directions with density :func:`smooth_cosine_pdf`: ``1 + cos θ = 2 u₀^{1/5}``, ``φ = 2π u₁``."""
    u0 = np.clip(u[..., 0], 0.0, 1.0)
    with np.errstate(divide="ignore"):
        t = 2.0 * np.exp(np.log(u0) / 5.0)  # 1 + cos θ in [0, 2]
    z = t - 1.0
    r = np.sqrt(np.clip(t * (2.0 - t), 0.0, 1.0))  # sin θ = √((1 + z)(1 − z))
    phi = _TWO_PI * u[..., 1]
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1)


class DisneySampler(Sampler):
    r"""One-sample mixture for the Disney BRDF: smoothed cosine, GTR2 (anisotropic) and GTR1 half vectors.

        p(l) = w_d p_d(l) + w_s D_s(h)(n·h)/(4 |v·h|) + w_c D_c(h)(n·h)/(4 |v·h|)

    with ``h = (l + v)/|l + v|`` (turned into the upper hemisphere).  Components (local frame
    ``t = x̂``, ``b = ŷ``, ``n = ẑ``):

    * diffuse and sheen: ``p_d = 5 (1 + cos θ)^4/(64 π)`` on the whole sphere
      (:func:`smooth_cosine_pdf`), drawn as ``1 + cos θ = 2 u₀^{1/5}``, ``φ = 2π u₁``;

    * GTR2 (GGX) with ``α_x, α_y``: slopes are an affinely stretched isotropic GGX, so with
      ``φ = 2π u₁``, ``h ∝ (α_x √u₀ cos φ, α_y √u₀ sin φ, √(1 − u₀))`` has density ``D_s(h)(n·h)``;
    * GTR1 with ``α_c``: ``cos²θ_h = (α_c^{2u₀} − 1)/(α_c² − 1)``, ``φ = 2π u₁`` (the inverse of the
      CDF ``ln(1 + (α_c² − 1) cos²θ_h)/ln α_c²``), density ``D_c(h)(n·h)``;

    then ``l = 2 (v·h) h − v`` and ``p(l) = p(h)/(4 |v·h|)``.

    Weights, before normalization: with ``F_V = (1 − n·v)^5`` (the Schlick weight of the view; the
    reflectance of each lobe seen from ``v`` for smooth surfaces):

    * diffuse:   ``w_d = diffuse + sheen · F_V``  (``diffuse = (1 − metallic) mean(base)``,
      ``sheen = (1 − metallic) sheen mean(C_sheen)``)
    * GTR2:      ``w_s = s0 + (1 − s0) F_V``  (``s0 = mean(C_spec0)``)
    * GTR1:      ``w_c = clearcoat · (0.04 + 0.96 F_V)``  (``clearcoat`` = the model's ``0.25 clearcoat``)

    and only the diffuse component where all three vanish.  Each component alone has a positive density
    wherever ``f_r > 0`` (the upper hemisphere), so any weights give an unbiased estimator; they
    only set the variance.

    Parameters
    ----------
    alpha_x, alpha_y : float > 0
        The GTR2 roughnesses along ``t`` and ``b``.
    alpha_c : float in (0, 1]
        The GTR1 α.
    diffuse, sheen, specular0, clearcoat : float >= 0
        The reflectance estimates above.
    """

    name = "disney"

    def __init__(self, alpha_x, alpha_y, alpha_c, *, diffuse=1.0, sheen=0.0, specular0=0.04, clearcoat=0.0):
        self.alpha_x = check_range("alpha_x", alpha_x, 0.0, lo_open=True)
        self.alpha_y = check_range("alpha_y", alpha_y, 0.0, lo_open=True)
        self.alpha_c = check_range("alpha_c", alpha_c, 0.0, 1.0, lo_open=True)
        self.diffuse = check_range("diffuse", diffuse, 0.0)
        self.sheen = check_range("sheen", sheen, 0.0)
        self.specular0 = check_range("specular0", specular0, 0.0, 1.0)
        self.clearcoat = check_range("clearcoat", clearcoat, 0.0)

    def __repr__(self):
        return (f"DisneySampler(alpha_x={self.alpha_x!r}, alpha_y={self.alpha_y!r}, alpha_c={self.alpha_c!r}, "
                f"diffuse={self.diffuse!r}, sheen={self.sheen!r}, specular0={self.specular0!r}, "
                f"clearcoat={self.clearcoat!r})")

    def weights(self, v) -> np.ndarray:
        """Normalized component probabilities ``(w_d, w_s, w_c)`` for viewers ``v`` (local frame).

        Parameters
        ----------
        v : array_like, shape (..., 3)

        Returns
        -------
        ndarray, shape (..., 3)
        """
        return self._weights(_local_v(normalize(np.asarray(v, dtype=np.float64))))

    def _weights(self, v) -> np.ndarray:
        fv = _schlick_weight(v[..., 2])
        w = np.stack(
            [
                self.diffuse + self.sheen * fv,
                self.specular0 + (1 - self.specular0) * fv,
                self.clearcoat * (CLEARCOAT_F0 + (1 - CLEARCOAT_F0) * fv),
            ],
            axis=-1,
        )
        total = np.sum(w, axis=-1, keepdims=True)
        fallback = np.array([1.0, 0.0, 0.0])
        # Weights in [0, 1] over their positive sum (or 1): quotients in [0, 1].
        return np.where(total > 0, w / np.where(total > 0, total, 1.0), fallback)

    # -- half vectors ------------------------------------------------------------------
    def _gtr2_normals(self, u) -> np.ndarray:
        u0 = np.clip(u[..., 0], 0.0, 1.0)
        phi = _TWO_PI * u[..., 1]
        r = np.sqrt(u0)
        h = np.stack([self.alpha_x * r * np.cos(phi), self.alpha_y * r * np.sin(phi), np.sqrt(1.0 - u0)], axis=-1)
        return normalize(h)

    def _gtr1_normals(self, u) -> np.ndarray:
        u0 = np.clip(u[..., 0], 0.0, 1.0)
        phi = _TWO_PI * u[..., 1]
        a = self.alpha_c
        if a >= 1:  # D = 1/π: n·h uniform in cos²θ_h
            cos2 = u0
            sin2 = 1.0 - u0
        else:
            lg = math.log(a * a)  # < 0
            den = math.expm1(lg)  # α² − 1 < 0
            cos2 = np.expm1(u0 * lg) / den
            # 1 − cos² = e^{u₀ L} (1 − e^{(1−u₀) L}) / (1 − e^L), without cancellation near u₀ = 1.
            sin2 = np.exp(u0 * lg) * np.expm1((1.0 - u0) * lg) / den
        cos_t = np.sqrt(np.clip(cos2, 0.0, 1.0))
        sin_t = np.sqrt(np.clip(sin2, 0.0, 1.0))
        return np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), cos_t], axis=-1)

    def _half_pdfs(self, h):
        """``D_s(h)(n·h)`` and ``D_c(h)(n·h)`` for upper-hemisphere unit ``h``."""
        c = np.maximum(h[..., 2], 0.0)
        ps = gtr2_aniso(h, self.alpha_x, self.alpha_y) * c
        s2 = np.clip(h[..., 0] ** 2 + h[..., 1] ** 2, 0.0, 1.0)
        pc = gtr1(c, s2, self.alpha_c) * c
        return ps, pc

    # -- directions ---------------------------------------------------------------------
    def _sample(self, u, v):
        u = np.asarray(u, dtype=np.float64)
        v = _local_v(v)
        w = self._weights(v)
        shape = np.broadcast_shapes(u.shape[:-1], v.shape[:-1])
        u0 = np.broadcast_to(u[..., 0], shape)
        u1 = np.broadcast_to(u[..., 1], shape)
        wd = np.broadcast_to(w[..., 0], shape)
        ws = np.broadcast_to(w[..., 1], shape)
        wc = np.broadcast_to(w[..., 2], shape)
        # Choose the component by u₀ and rescale u₀ to [0, 1) within the chosen interval.
        k = np.where(u0 < wd, 0, np.where(u0 < wd + ws, 1, 2))
        k = np.where((k == 2) & (wc <= 0), np.where(ws > 0, 1, 0), k)
        lo = np.where(k == 0, 0.0, np.where(k == 1, wd, wd + ws))
        width = np.where(k == 0, wd, np.where(k == 1, ws, wc))
        ur0 = np.where(width > 0, (u0 - lo) / np.where(width > 0, width, 1.0), 0.5)  # an empty slot's width is 1
        ur = np.stack([np.clip(ur0, 0.0, np.nextafter(1.0, 0.0)), u1], axis=-1)
        vb = np.broadcast_to(v, shape + (3,))
        l_cos = _smooth_cosine_directions(ur)
        h = np.where((k == 1)[..., None], self._gtr2_normals(ur), self._gtr1_normals(ur))
        vh = _dot(vb, h)
        l_half = 2 * vh[..., None] * h - vb
        l = np.where((k == 0)[..., None], l_cos, l_half)  # noqa: E741
        return Samples(l, self._pdf(l, vb))

    def _pdf(self, l, v):  # noqa: E741
        l, v = np.asarray(l, dtype=np.float64), _local_v(v)  # noqa: E741
        w = self._weights(v)
        p_cos = smooth_cosine_pdf(l[..., 2])
        s = l + v
        h = normalize(s)
        h = np.where(h[..., 2:3] < 0, -h, h)
        ps, pc = self._half_pdfs(h)
        p_half = np.where(_dot(s, s) > 0, safe_div(w[..., 1] * ps + w[..., 2] * pc, 4.0 * np.abs(_dot(v, h))), 0.0)
        return w[..., 0] * p_cos + p_half


register_model(Disney)

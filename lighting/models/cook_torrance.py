r"""Cook–Torrance microfacet reflection: ``f_r = k_s D G F / (4 (n·v)(n·l))`` (or the slide's π form).

The factors live in :mod:`lighting.models.microfacet` (``D``, ``G``) and
:mod:`lighting.models.fresnel` (``F``); the sampler in :mod:`lighting.sampling.microfacet`.
"""

from __future__ import annotations

import math

import numpy as np

from .._validate import check_bool, check_choice, check_positive
from ..numerics import saturate_to
from ..sampling.microfacet import MicrofacetSampler, VisibleNormalSampler
from . import fresnel as _fresnel
from . import microfacet as _mf
from .base import _UNIT_RGB, BRDFFlags, MicrofacetLobe, SeparableBRDF, _color, _color_text, _combine
from .geometry import Geometry
from .protocol import Lobe, Parameter, register_model

__all__ = ["CookTorrance"]


class CookTorrance(SeparableBRDF):
    r"""Cook–Torrance microfacet specular reflection.

    Default (energy-consistent, Walter et al. 2007):

        f_r = k_s D(h) G(n, v, l) F(v·h) / (4 (n·v)(n·l))

    With ``denominator="pi"`` the slide's (and the 1982 paper's) form:

        f_r = k_s D G F / (π (n·v)(n·l))

    which, with a normalized ``D``, reflects up to ``4/π ≈ 1.27`` times too
    much; it is kept so the plausibility audit and the figures can show that.

    Parts: ``D`` Beckmann (Gaussian slopes, the slides'), GGX, or the slides'
    normalized Blinn–Phong lobe with exponent ``e = 2/α² − 2``; ``G`` the
    slides' V-cavity term, separable Smith ``G1(v) G1(l)`` or the height-correlated Smith
    ``G2 = 1 / (1 + Λ(v) + Λ(l))`` for the chosen NDF (``G1 = 1/(1 + Λ)``):

        GGX:       Λ(θ) = (−1 + sqrt(1 + α² tan²θ)) / 2
        Beckmann:  Λ(θ) = (erf(a) − 1)/2 + exp(−a²) / (2 a √π),   a = 1 / (α tan θ)

    (Blinn–Phong lobes take Beckmann's of the same α); ``F`` Schlick, the exact dielectric formula
    with ``η`` from ``f0``, ``"none"`` (F = 1), or the exact conductor formula
    (:func:`lighting.models.fresnel.conductor`) of the complex index ``η + i k`` per channel, from ``eta`` and
    ``k`` or from a named ``metal``.

    Parameters
    ----------
    ks : float or RGB triple, >= 0
        Scale of the specular lobe (1 for a pure microfacet model).
    roughness : float > 0
        The NDF's α.  Values down to 1e-6 are evaluated as given (results stay
        finite; the peak of ``D`` is ``1/(π α²)``).
    f0 : float or RGB triple in [0, 1]
        Fresnel reflectance at normal incidence (0.04 for common dielectrics).  Not used with
        ``fresnel="conductor"``, whose ``F0`` follows from ``η`` and ``k``: the model's :attr:`f0` is then that
        value, ``((η − 1)² + k²) / ((η + 1)² + k²)`` per channel (what the audit, captions and the split
        sum's albedo read), and ``f0`` given only supplies ``η`` when ``eta`` is left unset.
    ndf : {"beckmann", "ggx", "blinn-phong"}
    geometry : {"v-cavity", "smith", "smith-correlated"}
        ``"smith-correlated"`` lies between ``G1(v) G1(l)`` and ``min(G1(v), G1(l))``: a microfacet
        visible from ``v`` is more likely visible from ``l`` too (both are high on the surface).
    fresnel : {"schlick", "dielectric", "none", "conductor"}
    denominator : {"4", "pi"}
    alpha_x, alpha_y : float > 0 or None
        Anisotropic roughness along the tangent ``t`` and the bitangent ``b = n × t`` (GGX and Beckmann;
        each defaults to ``roughness``).  With ``h = (h_t, h_b, h_n)`` in the frame ``(t, b, n)``:

            GGX:       D(h) = 1 / (π α_x α_y ((h_t/α_x)² + (h_b/α_y)² + h_n²)²)
            Beckmann:  D(h) = exp(−((h_t/α_x)² + (h_b/α_y)²) / h_n²) / (π α_x α_y h_n⁴)

        and Λ is the isotropic one with ``α(φ) = sqrt(cos²φ α_x² + sin²φ α_y²)`` for the direction's
        azimuth φ.  The tangent comes from ``eval(..., tangent=t)``; without one the frame of
        :attr:`lighting.models.geometry.Geometry.t`.  ``α_x = α_y`` is the isotropic model bit for bit
        (the isotropic code, with that α); an anisotropic model is not :attr:`stackable`.
    energy_compensation : bool
        Add Kulla and Conty's (2017) multiple-scattering lobe (:mod:`lighting.models.energy`), which gives
        back the light that single scattering loses to shadowing on rough surfaces:

            f_ms = k_s F_ms (1 − E(n·v)) (1 − E(n·l)) / (π (1 − E_avg)),
            F_ms = F_avg² E_avg / (1 − F_avg (1 − E_avg)),

        ``E(μ)`` the directional albedo of this lobe with ``F = 1`` (a table in ``(μ, √α)``, ``α`` clamped
        to 1), ``E_avg = 2 ∫ E μ dμ``, ``F_avg = 2 ∫ F μ dμ`` (``f0 + (1 − f0)/21`` for Schlick).  With
        ``F = 1`` the directional albedo is then 1 at every view up to 85° (within the table's 2e-3).
        Only for the Smith geometries with a GGX or Beckmann ``D``, the denominator 4 and an isotropic
        ``α`` (``ValueError`` otherwise).  False (the default) is the single-scattering model, bit for bit.
    eta, k : float or RGB triple, or None
        The conductor's index ``η + i k`` relative to the outside (``η > 0``, ``k >= 0``, finite), for
        ``fresnel="conductor"`` only (set with another ``fresnel``: ``ValueError``).  None: ``η`` of ``f0``
        (:func:`~lighting.models.fresnel.eta_from_f0`) and ``k = 0``, the exact dielectric.
    metal : {"none", "gold", "silver", "copper", "aluminium", "chromium"}
        A named metal's ``η`` and ``k`` (:data:`lighting.models.fresnel.METALS`: published optical constants
        at 630, 532 and 465 nm), for ``fresnel="conductor"`` only; ``eta`` and ``k`` are then left unset:

            CookTorrance(roughness=0.2, ndf="ggx", geometry="smith-correlated", fresnel="conductor", metal="gold")

    Notes
    -----
    The ``"smith-correlated"`` geometry and visible-normal sampling follow Heitz (2014, 2018); at
    ``θ_v = 0`` the two Smith forms agree (``Λ(v) = 0``), so the height-correlated GGX albedo at
    normal incidence and ``α = 1`` (``F = 1``) is ``1 − ln 2``, as the separable one's.

    References
    ----------
    R. L. Cook and K. E. Torrance, "A reflectance model for computer graphics", ACM
    Transactions on Graphics 1(1), 7–24, 1982 (the model, Beckmann's D, the V-cavity G).
    B. Walter, S. R. Marschner, H. Li and K. E. Torrance, "Microfacet models for refraction
    through rough surfaces", EGSR 2007 (GGX, the denominator 4, Smith G for each NDF).
    B. G. Smith, "Geometrical shadowing of a random rough surface", IEEE Transactions on
    Antennas and Propagation 15(5), 668–671, 1967.
    C. Schlick, "An inexpensive BRDF model for physically-based rendering", Computer
    Graphics Forum 13(3), 233–246, 1994.
    E. Heitz, "Understanding the masking-shadowing function in microfacet-based BRDFs",
    Journal of Computer Graphics Techniques 3(2), 48–107, 2014 (Smith G1 and Λ, the
    height-correlated G2, eq. 99, and the anisotropic D and Λ, sec. 5).
    E. Heitz, "Sampling the GGX distribution of visible normals", Journal of Computer Graphics
    Techniques 7(4), 1–13, 2018.

    Examples
    --------
    >>> ct = CookTorrance(1.0, 0.3, 1.0)
    >>> round(float(ct.eval((0, 0, 1.0), (0, 0, 1.0), (0, 0, 1.0))[0]), 6)  # D(0)/4
    0.884194
    >>> aniso = CookTorrance(1.0, f0=1.0, ndf="ggx", geometry="smith-correlated", alpha_x=0.2, alpha_y=0.5)
    >>> round(float(aniso.eval((0, 0, 1.0), (0, 0, 1.0), (0, 0, 1.0))[0]), 6)  # 1/(4π α_x α_y)
    0.795775
    >>> gold = CookTorrance(roughness=0.2, fresnel="conductor", metal="gold")
    >>> gold
    CookTorrance(ks=1, roughness=0.2, fresnel='conductor', metal='gold')
    >>> gold.f0.round(3).tolist()   # its normal-incidence reflectance, R G B
    [0.942, 0.704, 0.404]
    """

    name = "cook-torrance"
    NDFS = ("beckmann", "ggx", "blinn-phong")
    GEOMETRIES = ("v-cavity", "smith", "smith-correlated")
    FRESNELS = ("schlick", "dielectric", "none", "conductor")
    DENOMINATORS = ("4", "pi")
    parameters = (
        Parameter("ks", "color", 1.0, slider=(0.0, 1.0), description="specular coefficient k_s"),
        Parameter("roughness", "float", 0.3, slider=(1e-6, 1.0), log=True, low_open=True,
                  description="the NDF's roughness α"),
        Parameter("f0", "color", 0.04, high=1.0, description="Fresnel reflectance at normal incidence F0"),
        Parameter("ndf", "choice", "beckmann", choices=NDFS, description="normal distribution D"),
        Parameter("geometry", "choice", "v-cavity", choices=GEOMETRIES, description="shadowing–masking G"),
        Parameter("fresnel", "choice", "schlick", choices=FRESNELS, description="Fresnel term F"),
        Parameter("denominator", "choice", "4", choices=DENOMINATORS,
                  description="4 (n·v)(n·l), or the slide's π (n·v)(n·l)"),
        Parameter("alpha_x", "float", None, slider=(1e-3, 1.0), log=True, low_open=True,
                  description="α along the tangent t (anisotropic GGX/Beckmann); None: roughness"),
        Parameter("alpha_y", "float", None, slider=(1e-3, 1.0), log=True, low_open=True,
                  description="α along the bitangent b = n × t; None: roughness"),
        Parameter("energy_compensation", "bool", False,
                  description="add the multiple-scattering lobe of Kulla and Conty (Smith GGX/Beckmann)"),
        *_fresnel.CONDUCTOR_PARAMETERS,
    )

    def __init__(
        self,
        ks=1.0,
        roughness=0.3,
        f0=0.04,
        ndf="beckmann",
        geometry="v-cavity",
        fresnel="schlick",
        denominator="4",
        alpha_x=None,
        alpha_y=None,
        energy_compensation=False,
        eta=None,
        k=None,
        metal="none",
    ):
        self.ks = _color("ks", ks)
        self.roughness = check_positive("roughness", roughness)
        self.f0 = _color("f0", f0, hi=1.0)
        self.ndf = check_choice("ndf", ndf, self.NDFS)
        self.geometry = check_choice("geometry", geometry, self.GEOMETRIES)
        self.fresnel = check_choice("fresnel", fresnel, self.FRESNELS)
        #: The conductor's η and k as used (RGB float64; None unless ``fresnel="conductor"``), the metal named.
        self.eta, self.k, self.metal, self.f0 = _fresnel._conductor_setup(self.fresnel, self.f0, eta, k, metal)
        if isinstance(denominator, (int, np.integer)) and not isinstance(denominator, (bool, np.bool_)):
            denominator = str(denominator)  # 4 means "4"
        self.denominator = check_choice("denominator", denominator, self.DENOMINATORS)
        self.alpha_x = None if alpha_x is None else check_positive("alpha_x", alpha_x)
        self.alpha_y = None if alpha_y is None else check_positive("alpha_y", alpha_y)
        ax = self.roughness if self.alpha_x is None else self.alpha_x
        ay = self.roughness if self.alpha_y is None else self.alpha_y
        #: (α_x, α_y) as used; the isotropic code paths take ``_alpha`` (the roughness unless both are given).
        self._ax, self._ay = ax, ay
        if ax != ay:
            self.flags = type(self).flags | BRDFFlags.ANISOTROPIC
        if self.anisotropic and self.ndf == "blinn-phong":
            raise ValueError(f"alpha_x and alpha_y must be equal (or None) for ndf 'blinn-phong', which has no "
                             f"anisotropic form; got alpha_x={alpha_x!r}, alpha_y={alpha_y!r} "
                             "(use ndf 'ggx' or 'beckmann')")
        self._alpha = ax
        self._exponent = float(_mf.blinn_phong_exponent(self._alpha))
        self.energy_compensation = check_bool("energy_compensation", energy_compensation)
        #: The multiple-scattering lobe (:class:`lighting.models.energy.MultipleScattering`), or None.
        self._ms = self._multiple_scattering() if self.energy_compensation else None

    @property
    def is_black(self):
        return not np.any(self.ks > 0)

    @property
    def anisotropic(self) -> bool:
        """``α_x ≠ α_y`` (``BRDFFlags.ANISOTROPIC in flags``)."""
        return BRDFFlags.ANISOTROPIC in self.flags

    @property
    def stackable(self) -> bool:
        """Isotropic instances only: the stacked fast path carries no tangents."""
        return not self.anisotropic

    def microfacet(self):
        return MicrofacetLobe(self.ndf, self._ax, self._ay, self.geometry, self.fresnel, self.denominator,
                              np.broadcast_to(np.asarray(self.ks, dtype=np.float64), (3,)),
                              self.energy_compensation)  # fmt: skip

    def _multiple_scattering(self):
        """Kulla and Conty's lobe for this model; refuses the settings it has no table or meaning for."""
        from . import energy  # the tables are made on first use, not at import

        refuse = []
        if self.geometry == "v-cavity":
            refuse.append("geometry 'smith' or 'smith-correlated' (got 'v-cavity')")
        if self.ndf not in energy.NDFS:
            refuse.append(f"ndf 'ggx' or 'beckmann' (got {self.ndf!r}, whose Smith term is Beckmann's)")
        if self.denominator != "4":
            refuse.append(f"denominator '4' (got {self.denominator!r}, which reflects up to 4/π too much)")
        if self.anisotropic:
            refuse.append(f"alpha_x = alpha_y (got {self._ax:g} and {self._ay:g}; the tables are isotropic)")
        if refuse:
            raise ValueError("energy_compensation=True needs " + "; ".join(refuse))
        # The settings are the model's, checked and refused above where no table applies.
        table = energy._table(self.ndf, self.geometry, energy.RESOLUTION)
        f_avg = energy._fresnel_average(self.fresnel, self.f0, self.eta, self.k)
        colour = self.ks * energy.multiple_scattering_colour(f_avg, table._e_avg(self._alpha))
        return energy.MultipleScattering(table, self._alpha, colour)

    def lobe(self):
        """A ``"half"`` lobe of width ``α/√2`` (``inf`` when ``ks`` is 0), quadrature width ``α`` and ``horizon``
        ``"v-cavity"`` or ``"smith"`` (both Smith forms) after :attr:`geometry`.  Anisotropic: width ``√(α_x α_y)/√2``
        and quadrature width ``min(α_x, α_y)``, with ``widths`` ``(α_x/√2, α_y/√2)`` and ``quadrature_widths`` ``(α_x,
        α_y)`` along ``t`` and ``b``, the ellipse quadrature follows.
        """
        # Beckmann's exp(−tan²θ_h/α²) has standard deviation α/√2 about n; quadrature scales by α.
        # Anisotropic: the geometric mean for the width, the narrower α for the quadrature's scale.
        alpha = math.sqrt(self._ax * self._ay) if self.anisotropic else self._alpha
        width = alpha / math.sqrt(2.0) if np.any(self.ks > 0) else math.inf
        horizon = "v-cavity" if self.geometry == "v-cavity" else "smith"
        quad = min(self._ax, self._ay) if self.anisotropic else self._alpha
        tails = "ggx" if self.ndf == "ggx" else "gaussian"
        if self.anisotropic and width < math.inf:
            axes = (self._ax, self._ay)
            widths = (axes[0] / math.sqrt(2.0), axes[1] / math.sqrt(2.0))
            return Lobe("half", width, quadrature_width=quad, horizon=horizon, widths=widths, quadrature_widths=axes,
                        tails=tails)  # fmt: skip
        return Lobe("half", width, quadrature_width=quad, horizon=horizon, tails=tails)

    def sampler(self):
        """``MicrofacetSampler or VisibleNormalSampler``: for the Smith geometries with a GGX or Beckmann ``D``,
        ``VisibleNormalSampler(ndf, roughness)``: half vectors drawn from the normals visible from ``v`` (Heitz 2018;
        Heitz and d'Eon 2014), density ``G1(v) D(h) / (4 n·v)``, so each sample's weight ``f_r (n·l) / p`` is ``F
        G1(l)`` (separable) or ``F G2 / G1(v)`` (height-correlated), at most ``F``.  Otherwise ``MicrofacetSampler(ndf,
        roughness)``: half vectors drawn from ``D(h)(n·h)``.  Anisotropic models (any geometry) take
        ``VisibleNormalSampler(ndf, α_x, alpha_y=α_y)``, whose local frame has ``x`` along the tangent ``t`` and ``y``
        along ``b``.  With :attr:`energy_compensation`, a ``MixtureSampler`` of that sampler and the cosine-weighted one
        (for ``f_ms ∝ (1 − E(n·l))``), the cosine's share ``m (1 − E(μ_o)) / (s E(μ_o) + m (1 − E(μ_o)))`` at most 0.9
        (``s``, ``m`` the channel means of ``k_s F_avg`` and of the lobe's colour: each lobe's albedo, roughly).
        """
        if self._ms is not None:
            return self._mixture_sampler()
        return self._single_sampler()

    def _mixture_sampler(self):
        from ..sampling.brdf import MixtureSampler  # the integrators import the models
        from .energy import _fresnel_average
        from .lambert import CosineSampler

        ms = self._ms
        s = float(np.mean(self.ks * _fresnel_average(self.fresnel, self.f0, self.eta, self.k)))
        m = float(np.mean(ms.colour))

        def weights(v):
            mu = np.clip(np.asarray(v, dtype=np.float64)[..., 2], 0.0, 1.0)
            lost = ms.albedo(mu) * m
            total = s * (1.0 - ms.loss(mu)) + lost
            share = np.clip(np.where(total > 0, lost / np.where(total > 0, total, 1.0), 0.0), 0.0, 0.9)
            return np.stack([1.0 - share, share], axis=-1)

        return MixtureSampler([self._single_sampler(), CosineSampler()], weights)

    def _single_sampler(self):
        if self.anisotropic:
            return VisibleNormalSampler(self.ndf, self._ax, alpha_y=self._ay)
        if self.geometry != "v-cavity" and self.ndf != "blinn-phong":
            return VisibleNormalSampler(self.ndf, self._alpha)
        return MicrofacetSampler(self.ndf, self._alpha)

    def summary(self):
        """For example ``"ks=1 α=0.3 beckmann/v-cavity schlick f0=0.04 /4(n·v)(n·l)"`` (``F=1`` for ``fresnel="none"``;
        ``conductor gold`` or ``conductor η=… k=…`` for the conductor; ``" +ms"`` appended with
        :attr:`energy_compensation`).
        """
        f = _fresnel_text(self)
        den = "4(n·v)(n·l)" if self.denominator == "4" else "π(n·v)(n·l)"
        alpha = f"αx={self._ax:g} αy={self._ay:g}" if self.anisotropic else f"α={self._alpha:g}"
        ms = " +ms" if self.energy_compensation else ""
        return f"ks={_color_text(self.ks)} {alpha} {self.ndf}/{self.geometry} {f} /{den}{ms}"

    def to_dict(self):
        """``alpha_x`` and ``alpha_y`` appear only when given (not None), ``energy_compensation`` only when True (the
        tables of older scenes stay as they were); with ``fresnel="conductor"``, ``metal`` when one is named, else
        ``eta`` and ``k`` (and no ``f0``, which the conductor does not use).
        """
        d = {"model": self.name}
        for p in self.parameters:
            if p.name in ("eta", "k", "metal") or (p.name == "f0" and self.fresnel == "conductor"):
                continue
            value = getattr(self, p.name)
            if value is None or (p.kind == "bool" and not value):
                continue
            if p.kind == "color":
                value = [float(x) for x in np.asarray(value, dtype=np.float64).reshape(-1)]
            elif p.kind == "float":
                value = float(value)
            elif p.kind == "bool":
                value = bool(value)
            d[p.name] = value
        d.update(_fresnel._conductor_table(self))
        return d

    def _params(self):
        extra = {k: getattr(self, k) for k in ("alpha_x", "alpha_y") if getattr(self, k) is not None}
        if self.energy_compensation:
            extra["energy_compensation"] = True
        out = {
            "ks": self.ks,
            "roughness": self.roughness,
            "f0": self.f0,
            "ndf": self.ndf,
            "geometry": self.geometry,
            "fresnel": self.fresnel,
            "denominator": self.denominator,
            **extra,
            **_fresnel._conductor_table(self, plain=False),
        }
        if self.fresnel == "conductor":
            del out["f0"]  # follows from η and k
        return out

    # The three factors, public so that figures can show each one.
    def D(self, g: Geometry):
        """Normal distribution at ``h`` (1/sr).

        Parameters
        ----------
        g : Geometry
            The shading directions (``n·h`` and ``sin²θ_h`` are read).

        Returns
        -------
        ndarray, shape (...)
            ``D(h)`` >= 0 for :attr:`ndf` and :attr:`roughness`, 0 where ``n·h <= 0``, finite (saturated),
            in the dtype of ``g``.
        """
        return self._D(g, g.dtype)

    # The unchecked microfacet functions: the parameters were checked by the constructor, and the
    # cosines come from a Geometry (the renderer's path must not pay for a check per call).
    def _D(self, g: Geometry, dtype):
        if self.anisotropic:
            x, y, z = g.h_tbn
            f = _mf._ggx_ndf_aniso if self.ndf == "ggx" else _mf._beckmann_ndf_aniso
            return f(x, y, z, self._ax, self._ay, dtype)
        c, s2 = g.n_dot_h.astype(dtype, copy=False), g.sin2_h.astype(dtype, copy=False)
        if self.ndf == "blinn-phong":
            return _mf._blinn_phong_ndf(c, self._exponent, s2, dtype)
        f = _mf._beckmann_ndf if self.ndf == "beckmann" else _mf._ggx_ndf
        return f(c, self._alpha, s2, dtype)

    def G(self, g: Geometry):
        """Shadowing–masking in [0, 1].

        Parameters
        ----------
        g : Geometry
            The shading directions.

        Returns
        -------
        ndarray, shape (...)
            The V-cavity ``G``, Smith's ``G1(v) G1(l)`` or the height-correlated ``1/(1 + Λ(v) + Λ(l))``
            for :attr:`ndf` (after :attr:`geometry`), in the dtype of ``g``.
        """
        if self.geometry == "v-cavity":
            return _mf._vcavity_g(g.n_dot_h, g.n_dot_v, g.n_dot_l, g.v_dot_h)
        if self.geometry == "smith-correlated":
            nv = g.n_dot_v.astype(np.float64)
            nl = g.n_dot_l.astype(np.float64)
            lv, ll = self._lambda_cos_vl(g)
            with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
                # Λ = (Λ cos θ)/cos θ; an infinite Λ (cos θ underflowing) gives G2 = 0.
                total = 1 + lv / np.where(nv > 0, nv, 1.0) + ll / np.where(nl > 0, nl, 1.0)
                g2 = np.where((nv > 0) & (nl > 0), 1 / total, 0.0)
            return _mf._finish(g2, g.dtype)
        # Blinn–Phong lobes use the Beckmann G1 of the equivalent α (Walter et al. 2007).
        g1 = _mf._smith_g1_ggx if self.ndf == "ggx" else _mf._smith_g1_beckmann
        if self.anisotropic:  # G1 = cos θ / (cos θ + Λ cos θ)
            lv, ll = self._lambda_cos_vl(g)
            nv = np.maximum(g.n_dot_v.astype(np.float64), 0.0)
            nl = np.maximum(g.n_dot_l.astype(np.float64), 0.0)
            with np.errstate(divide="ignore", invalid="ignore", under="ignore"):
                g1v = np.where(nv > 0, nv / (nv + lv), 0.0)
                g1l = np.where(nl > 0, nl / (nl + ll), 0.0)
            return _mf._finish(g1v * g1l, g.dtype)
        return g1(g.n_dot_v, self._alpha, g.sin2_v, g.dtype) * g1(g.n_dot_l, self._alpha, g.sin2_l, g.dtype)

    def F(self, g: Geometry):
        """Fresnel reflectance per channel, shape ``(..., 3)``.

        Parameters
        ----------
        g : Geometry
            The shading directions (``v·h`` is read).

        Returns
        -------
        ndarray, shape (..., 3)
            ``F(v·h)`` in [0, 1] for :attr:`fresnel` and :attr:`f0` (ones for ``"none"``; the conductor's
            ``F`` of :attr:`eta` and :attr:`k`), in the dtype of ``g``.
        """
        c = g.v_dot_h
        if self.fresnel == "none":
            return np.ones(c.shape + (3,), dtype=g.dtype)
        if self.fresnel == "schlick":
            return _fresnel.schlick(c, self.f0)
        if self.fresnel == "conductor":
            return self._conductor_f(c).astype(g.dtype)
        # The exact dielectric formula with η = (1 + √f0)/(1 − √f0), written in √f0 itself.
        return _fresnel._dielectric_from_f0(c, self.f0).astype(g.dtype)

    @property
    def _lambda_cos(self):
        """``Λ(θ) cos θ`` (float64) for :attr:`ndf`: GGX's, or Beckmann's (also for Blinn–Phong lobes)."""
        return _mf._smith_lambda_cos_ggx if self.ndf == "ggx" else _mf._smith_lambda_cos_beckmann

    def _lambda_cos_vl(self, g: Geometry):
        """``Λ(v) n·v`` and ``Λ(l) n·l`` (float64; 0 below the horizon), anisotropic through the tangent frame."""
        if self.anisotropic:
            return tuple(_mf._smith_lambda_cos_aniso(self.ndf, x, y, np.asarray(z, dtype=np.float64),
                                                     self._ax, self._ay) for x, y, z in (g.v_tbn, g.l_tbn))
        lam = self._lambda_cos
        return (lam(g.n_dot_v.astype(np.float64), self._alpha, g.sin2_v.astype(np.float64)),
                lam(g.n_dot_l.astype(np.float64), self._alpha, g.sin2_l.astype(np.float64)))

    def _den_const(self):
        return 4.0 if self.denominator == "4" else math.pi

    def _visibility(self, g: Geometry, with_n_dot_l: bool) -> np.ndarray:
        """``G / ((n·v)(n·l))`` (or ``G / (n·v)``) in float64, without multiplying the cosines in and out.

        At grazing ``G`` is itself proportional to the cosines it is divided by (Smith
        ``G1(v) ≈ 2 a √π`` with ``a ∝ n·v``), so ``f_r`` stays moderate while ``G`` and
        ``(n·v)(n·l)`` both vanish; forming each ratio directly saves the roundings of the
        product and the quotient.  Smith: ``G1(θ) = 2 cos θ / d(θ)`` with ``d`` from
        :func:`lighting.models.microfacet._smith_g1_den_beckmann` (or ``_ggx``).  Height-correlated
        Smith: ``1 / ((n·v)(n·l) + (n·l)(Λ(v) n·v) + (n·v)(Λ(l) n·l))`` with ``Λ cos θ`` from
        ``_smith_lambda_cos_beckmann`` (or ``_ggx``), finite at the horizon.  V-cavity:
        ``G/((n·v)(n·l)) = min(1/((n·v)(n·l)), (2 n·h / v·h) / max(n·v, n·l))``.
        """
        nv = g.n_dot_v.astype(np.float64, copy=False)  # read only: no copy of a float64 geometry's cosines
        nl = g.n_dot_l.astype(np.float64, copy=False)
        if self.geometry == "smith-correlated":
            # G2/((n·v)(n·l)) = 1 / ((n·v)(n·l) + (n·l) Λ(v)(n·v) + (n·v) Λ(l)(n·l)): every term finite
            # at grazing (Λ cos θ → α/(2√π) or α/2 there), so no small G divided by a small cosine.
            lv, ll = self._lambda_cos_vl(g)
            den = nv * nl + nl * lv + nv * ll
            with np.errstate(divide="ignore", over="ignore", invalid="ignore", under="ignore"):
                vis = 1 / den if with_n_dot_l else nl / den
            return np.where((nv > 0) & (nl > 0), vis, 0.0)
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            if self.geometry == "smith":
                den = _mf._smith_g1_den_ggx if self.ndf == "ggx" else _mf._smith_g1_den_beckmann
                s2v = g.sin2_v.astype(np.float64)
                s2l = g.sin2_l.astype(np.float64)
                # G1 = 2 cos θ / d:  G1(v) G1(l) / ((n·v)(n·l)) = 4 / (d_v d_l),
                # and G1(v) G1(l) / (n·v) = 4 (n·l) / (d_v d_l).
                if self.anisotropic:  # d = 2 (cos θ + Λ cos θ)
                    lv, ll = self._lambda_cos_vl(g)
                    dd = 4 * (nv + lv) * (nl + ll)
                else:
                    dd = den(nv, self._alpha, s2v) * den(nl, self._alpha, s2l)
                vis = 4 / dd if with_n_dot_l else 4 * nl / dd
                return np.where((nv > 0) & (nl > 0), vis, 0.0)
            nh = g.n_dot_h.astype(np.float64)
            vh = g.v_dot_h.astype(np.float64)
            k = 2 * nh / np.where(vh > 0, vh, 1)
            if with_n_dot_l:
                return np.minimum(1 / (nv * nl), k / np.maximum(nv, nl))
            return np.minimum(1 / nv, k * np.minimum(1, nl / nv))

    def _separable(self, g, with_n_dot_l: bool):
        """``k_s D G F / (c (n·v) [(n·l)])`` split into scalar lobes × RGB colours (float64)."""
        # D in float64 even for float32 inputs: its tail may be subnormal in float32 where
        # D / ((n·v)(n·l)) is not (grazing light and view).
        with np.errstate(over="ignore", invalid="ignore"):
            dv = self._D(g, np.float64) * self._visibility(g, with_n_dot_l)
        # 0·∞ (a D that underflowed times a visibility that overflowed) is 0, as is everything below the horizon.
        dv = np.where(g.above & ~np.isnan(dv), dv, 0.0)
        s = np.minimum(dv / self._den_const(), np.finfo(np.float64).max)
        if self.fresnel == "none":
            return [(s, self.ks)] + self._ms_terms(g, with_n_dot_l)
        if self.fresnel == "schlick":
            # F = f0 + (1 − f0)(1 − v·h)^5: two lobes with colours k_s f0 and k_s (1 − f0).
            m = (1.0 - np.clip(g.v_dot_h.astype(np.float64), 0.0, 1.0)) ** 5
            return [(s, self.ks * self.f0), (s * m, self.ks * (1.0 - self.f0))] + self._ms_terms(g, with_n_dot_l)
        # The exact forms are no sum of two separable terms: one term per channel, F_i (float64, not rounded to
        # the dtype first) in the scalar field.
        if self.fresnel == "conductor":
            fr = self._conductor_f(g.v_dot_h)
        else:
            fr = _fresnel._dielectric_from_f0(g.v_dot_h, self.f0)
        return [(s * fr[..., i], self.ks * _UNIT_RGB[i]) for i in range(3)] + self._ms_terms(g, with_n_dot_l)

    def _conductor_f(self, c):
        """The conductor's ``F`` at the cosines ``c`` (clamped to [0, 1]), float64 ``(..., 3)``."""
        return _fresnel._conductor(np.clip(np.asarray(c, dtype=np.float64), 0.0, 1.0), self.eta, self.k)

    def _ms_terms(self, g, with_n_dot_l: bool):
        """Kulla and Conty's lobe as one more separable term (``f_ms``, or ``f_ms (n·l)`` for the cosine forms)."""
        if self._ms is None:
            return []
        return [(self._ms.field(g.n_dot_v, g.n_dot_l, g.above, times_n_dot_l=not with_n_dot_l), self._ms.colour)]

    def _f(self, g):
        return saturate_to(_combine(self._separable(g, True), np.float64), g.dtype)

    def separable_cos(self, g):
        """With ``s = D G / (c (n·v))`` (``c`` 4 or π, 0 below the horizon) in the dtype of ``g``: ``(s, ks)`` for
        ``fresnel="none"``; ``(s, ks f0)`` and ``(s (1 − v·h)^5, ks (1 − f0))`` for Schlick; ``(s F_i, ks e_i)`` per
        channel ``i`` for the dielectric and the conductor ``F``.
        """
        return [(saturate_to(s, g.dtype), c) for s, c in self._separable(g, False)]

    def separable_classic(self, g):
        """The terms of :meth:`separable_cos` with their scalar fields times π."""
        with np.errstate(over="ignore"):  # a field near the dtype's largest value times π saturates below
            return [(saturate_to(s * math.pi, g.dtype), c) for s, c in self._separable(g, False)]



def _fresnel_text(model) -> str:
    """The Fresnel part of a model's :meth:`summary`: ``F=1``, ``schlick f0=0.04``, ``conductor gold`` …"""
    if model.fresnel == "none":
        return "F=1"
    if model.fresnel == "conductor":
        if model.metal != "none":
            return f"conductor {model.metal}"
        return f"conductor η={_color_text(model.eta)} k={_color_text(model.k)}"
    return f"{model.fresnel} f0={_color_text(model.f0)}"


register_model(CookTorrance)

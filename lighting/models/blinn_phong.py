r"""Blinn–Phong: the highlight from the half vector, raw (the slides', OpenGL's) or NDF-normalized.

    classic term k_s (n·h)^e,      normalized: f_r = k_s (e + 2)/(2π) (n·h)^e
"""

from __future__ import annotations

import math

import numpy as np

from .._validate import check_bool, check_nonnegative
from ..numerics import saturate_to
from ..sampling.base import UniformSampler
from ..sampling.microfacet import MicrofacetSampler
from .base import SeparableBRDF, _color, _color_text, _lobe_over_cos, _rgb
from .lambert import CosineSampler
from .protocol import Lobe, Parameter, register_model

__all__ = ["BlinnPhong"]


class BlinnPhong(SeparableBRDF):
    r"""Blinn–Phong (Jim Blinn, 1977): the highlight from the half vector.

    Unnormalized (the slides' and OpenGL's form, ``normalized=False``):

        classic term: k_s (n·h)^e,     f_r = k_s (n·h)^e / (π (n·l))

    Normalized (``normalized=True``), the CMSC 435 slide's "think of it as an NDF":

        f_r = k_s (e + 2)/(2π) (n·h)^e,   classic term: π f_r (n·l)

    The lobe ``D(h) = (e+2)/(2π)(n·h)^e`` integrates to one against
    ``(n·h) dω_h``, so the highlight keeps its energy as it sharpens, and the
    BRDF is reciprocal.  Used on its own as a BRDF (as the slide's sum does)
    it still reflects too much for ``k_s = 1``: the directional albedo at
    normal incidence is

        ρ(e) = 4 (e+2) [2/(e+4) − 1/(e+2) − 2^{−(e+4)/2}·2/(e+4) + 2^{−(e+2)/2}/(e+2)]

    — exactly 1 at ``e = 0``, rising toward 4 for sharp lobes, because the
    microfacet Jacobian ``1/(4 (v·h))`` and the ``G/(n·l)(n·v)`` factors are
    missing.  "Combine with other terms", as the slide says, is
    :class:`CookTorrance` with ``ndf="blinn-phong"``, which conserves energy.

    Parameters
    ----------
    ks : float or RGB triple, >= 0
    shininess : float >= 0
        Exponent ``e``; the slides' roughness ``r`` is ``1/e``.
    normalized : bool
        Use the NDF-normalized form.

    References
    ----------
    J. F. Blinn, "Models of light reflection for computer synthesized pictures", Computer
    Graphics (SIGGRAPH '77) 11(2), 192–198, 1977.

    Examples
    --------
    >>> BlinnPhong(1.0, 50).classic((0, 0, 1.0), (0, 0, 1.0), (0, 0, 1.0)).tolist()
    [1.0, 1.0, 1.0]
    """

    name = "blinn-phong"
    stackable = True
    parameters = (
        Parameter("ks", "color", 0.5, slider=(0.0, 1.0), description="specular coefficient k_s"),
        Parameter("shininess", "float", 32.0, slider=(0.0, 1e6), log=True, description="the exponent e"),
        Parameter("normalized", "bool", False, description="the NDF-normalized form (e+2)/(2π) (n·h)^e"),
    )
    variants = {"blinn-phong-normalized": {"normalized": True}}

    def __init__(self, ks=0.5, shininess=32.0, normalized=False):
        self.ks = _color("ks", ks)
        self.shininess = check_nonnegative("shininess", shininess)
        self.normalized = check_bool("normalized", normalized)

    @property
    def is_black(self):
        return not np.any(self.ks > 0)

    def _params(self):
        return {"ks": self.ks, "shininess": self.shininess, "normalized": self.normalized}

    def lobe(self):
        """``Lobe("normal")`` for ``e = 0``; else a ``"half"`` lobe of width ``1/√e`` (``inf`` when ``ks`` is 0) and
        quadrature width ``1/√(e + 1)``.
        """
        e = self.shininess
        if e == 0:
            return Lobe("normal")
        # Half vectors ∝ (n·h)^e ≈ exp(−e θ_h²/2) about n: standard deviation 1/√e.
        width = 1.0 / math.sqrt(e) if np.any(self.ks > 0) else math.inf
        return Lobe("half", width, quadrature_width=1.0 / math.sqrt(e + 1.0))

    def sampler(self):
        """For ``e = 0`` :class:`CosineSampler` (normalized) or :class:`UniformSampler` (raw), else
        ``MicrofacetSampler("blinn-phong", exponent=e)``.
        """
        if self.shininess == 0:
            # f_r (n·l) is ∝ n·l (normalized) or constant (raw): cosine or uniform sampling is exact.
            return CosineSampler() if self.normalized else UniformSampler()
        return MicrofacetSampler("blinn-phong", exponent=self.shininess)

    def summary(self):
        """``"ks=0.5 e=32"``, or ``"ks=0.5 e=32 normalized"`` for the normalized form."""
        return f"ks={_color_text(self.ks)} e={self.shininess:g}" + (" normalized" if self.normalized else "")

    def _lobe(self, g, dtype=None, scale: float = 1.0):
        """``scale · (n·h)^e`` (0 below the horizon) in ``dtype`` (that of ``g`` by default).

        ``e · log(n·h)`` comes from the geometry (:meth:`~lighting.models.geometry.Geometry.log_n_dot_h_power`,
        each geometry's accurate form), then :meth:`_exp_scaled` exponentiates and scales it:
        where ``(n·h)^e`` alone would be subnormal the constant factor goes into the exponent,
        ``exp(e log(n·h) + log scale)``: the normalized lobe's ``(e + 2)/(2π)`` (1.6e6 at
        ``e = 1e7``) would otherwise scale a subnormal ``(n·h)^e`` whose digits are already lost
        (7 % at a result of 1.2e-38 in float32).  Values beyond the dtype saturate at its
        largest one.  Entries the geometry's form does not serve are evaluated again on a
        plain geometry of their own (:meth:`~lighting.models.geometry.Geometry.refine`).
        """
        dt = dtype or g.dtype
        if self.shininess == 0:
            return saturate_to(np.where(g.above, scale, 0), dt)
        with np.errstate(divide="ignore", over="ignore", under="ignore", invalid="ignore"):
            t, shape = g.log_n_dot_h_power(self.shininess, dt)
            t = self._exp_scaled(t, dt, scale)
        t *= g.above_mask
        t = g.refine(t, dt, lambda sub: self._lobe(sub, scale=scale))
        return t.reshape(shape).astype(dt, copy=False)

    @staticmethod
    def _exp_scaled(t, dt, scale):
        """``exp(t) · scale`` in place (``t <= 0``, ``scale > 0``), saturated at the dtype's largest value.

        Where ``exp(t)`` is a normal number the factor itself multiplies it (one rounding, so the
        peak value ``(e + 2)/(2π)`` is right to the last bit; ``exp(log(scale))`` would add
        ``|log scale| u``); where ``exp(t)`` alone would be subnormal — its digits lost before the
        factor could restore them — the factor goes into the exponent, ``exp(t + log scale)``,
        whose error ``|t + log scale| u`` is within the lobe's own conditioning ``~|t| u`` there.
        A factor beyond the dtype puts every entry into the exponent and saturates.
        """
        if scale == 1:
            return np.exp(t, out=t)
        log_scale = math.log(scale)
        info = np.finfo(dt)
        if log_scale > math.log(float(info.max)) - 1:
            t += dt(log_scale)
            t = np.exp(t, out=t)
            return np.minimum(t, info.max, out=t)
        # The entries whose scaled value is subnormal or better but exp(t) alone is not normal.
        low = t < dt(math.log(float(info.tiny)))
        low &= t > dt(math.log(float(info.smallest_subnormal)) - log_scale - 1)
        t_low = t[low] + dt(log_scale) if np.any(low) else None
        t = np.exp(t, out=t)
        t *= dt(scale)
        if t_low is not None:
            t[low] = np.exp(t_low)
        return t

    def _norm(self):
        return (self.shininess + 2) / (2 * math.pi)

    def _f(self, g):
        if not self.normalized:
            lobe = self._lobe(g, np.float64)
            if self.shininess == 0:
                return _lobe_over_cos(g, lobe, np.zeros_like(lobe), self.ks)
            c = g.n_dot_h.astype(np.float64)
            d = np.minimum(g.one_minus_n_dot_h.astype(np.float64), 1.0)
            with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
                log_lobe = self.shininess * np.where(c < 0.5, np.log(np.where(c > 0, c, 0)), np.log1p(-d))
            return _lobe_over_cos(g, lobe, log_lobe, self.ks)
        return _rgb(self._lobe(g, scale=self._norm()), self.ks)

    def separable_cos(self, g):
        """One term: ``((e + 2)/(2π) (n·h)^e (n·l), ks)`` (normalized) or ``((n·h)^e / π, ks)`` (raw); the scalar field
        is 0 below the horizon, in the dtype of ``g``.
        """
        if self.normalized:
            # n·l of unit vectors may round to 1 + ulp: clipped, so a saturated lobe stays finite.
            return [(self._lobe(g, scale=self._norm()) * np.clip(g.n_dot_l, 0, 1), self.ks)]
        return [(self._lobe(g) / g.dtype(math.pi), self.ks)]

    def separable_classic(self, g):
        """One term: π times that of :meth:`separable_cos` (normalized) or ``((n·h)^e, ks)`` (raw), in the dtype of
        ``g``.
        """
        if self.normalized:
            return super().separable_classic(g)
        return [(self._lobe(g), self.ks)]



register_model(BlinnPhong)

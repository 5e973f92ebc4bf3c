r"""Phong's specular lobe about the mirror direction, and its sampler.

    classic term k_s (R_l·v)^e,      f_r = k_s (R_l·v)^e / (π (n·l)),      p(l) = (e+1)/(2π) (R_v·l)^e
"""

from __future__ import annotations

import math

import numpy as np

from .._validate import check_nonnegative
from ..sampling.base import _TWO_PI, Sampler, Samples, UniformSampler, _around, _local_v, _one_minus_cos_power
from ..vec import _one_minus_cos_between
from .base import SeparableBRDF, _color, _color_text, _lobe_over_cos, cos_power
from .protocol import Lobe, Parameter, register_model

__all__ = ["Phong", "PhongSampler"]


class Phong(SeparableBRDF):
    r"""Phong lighting (Bui-Tuong Phong, 1975), as the slides write it.

        classic term: k_s (R_l·v)^e,          R_l = 2 n (n·l) − l
        BRDF:         f_r = k_s (R_l·v)^e / (π (n·l))

    The BRDF form is the one the CMSC 435 deck gives (up to the engine's single
    π).  It is **not physical**, which is the teaching point and is kept:

    * dividing by ``n·l`` breaks reciprocity (``f(l, v) ≠ f(v, l)``);
    * it reflects more energy than comes in: at normal incidence the
      directional albedo is ``2 k_s / (e + 1)``, twice the input at ``e = 0``.

    ``eval`` saturates (stays finite) where ``n·l → 0``; ``eval_cos`` and
    ``classic`` never divide.  ``(R·v)^e`` is clamped to ``R·v >= 0`` and
    ``0^0 = 1``.

    Parameters
    ----------
    ks : float or RGB triple, >= 0
        Specular coefficient (highlight colour).
    shininess : float >= 0
        The exponent ``e`` (the slides' ``n_s``).

    References
    ----------
    B. T. Phong, "Illumination for computer generated pictures", Communications of the ACM
    18(6), 311–317, 1975.

    Examples
    --------
    >>> Phong(1.0, 10).classic((0, 0, 1.0), (0, 0, 1.0), (0, 0, 1.0)).tolist()
    [1.0, 1.0, 1.0]
    """

    name = "phong"
    stackable = True
    parameters = (
        Parameter("ks", "color", 0.5, slider=(0.0, 1.0), description="specular coefficient k_s"),
        Parameter("shininess", "float", 32.0, slider=(0.0, 1e6), log=True, description="the exponent e"),
    )

    def __init__(self, ks=0.5, shininess=32.0):
        self.ks = _color("ks", ks)
        self.shininess = check_nonnegative("shininess", shininess)

    @property
    def is_black(self):
        return not np.any(self.ks > 0)

    def _params(self):
        return {"ks": self.ks, "shininess": self.shininess}

    def lobe(self):
        """``Lobe("normal")`` for ``e = 0``; else a ``"mirror"`` lobe of width ``1/√e`` (``inf`` when ``ks`` is 0),
        quadrature width ``1/√(e + 1)`` and ``power = e``.
        """
        e = self.shininess
        if e == 0:
            return Lobe("normal")  # f_r (n·l) is constant over the hemisphere
        # (R·v)^e ≈ exp(−e ψ²/2) about R_v: standard deviation 1/√e; quadrature scales by 1/√(e+1).
        width = 1.0 / math.sqrt(e) if np.any(self.ks > 0) else math.inf
        return Lobe("mirror", width, quadrature_width=1.0 / math.sqrt(e + 1.0), power=e)

    def sampler(self):
        """:class:`UniformSampler` for ``e = 0``, else ``PhongSampler(e)``."""
        # e = 0: f_r (n·l) is constant over the hemisphere, which uniform sampling integrates exactly.
        return UniformSampler() if self.shininess == 0 else PhongSampler(self.shininess)

    def summary(self):
        """``"ks=0.5 e=32"`` (a coloured ``ks`` as ``(r,g,b)``)."""
        return f"ks={_color_text(self.ks)} e={self.shininess:g}"

    def _lobe(self, g):
        lobe = cos_power(g.one_minus_r_dot_v, self.shininess)
        return np.where(g.above, lobe, 0).astype(g.dtype, copy=False)

    def _f(self, g):
        d = np.minimum(g.one_minus_r_dot_v.astype(np.float64), 1.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            log_lobe = self.shininess * np.log1p(-d) if self.shininess else np.zeros_like(d)
        return _lobe_over_cos(g, cos_power(d, self.shininess), log_lobe, self.ks)

    def separable_cos(self, g):
        """One term ``(max(R_l·v, 0)^e / π, ks)``: the scalar field is 0 below the horizon, in the dtype of ``g``."""
        return [(self._lobe(g) / g.dtype(math.pi), self.ks)]

    def separable_classic(self, g):
        """One term ``(max(R_l·v, 0)^e, ks)``: the scalar field is 0 below the horizon, in the dtype of ``g``."""
        return [(self._lobe(g), self.ks)]



class PhongSampler(Sampler):
    r"""The Phong lobe around the mirror direction ``R_v = 2 n (n·v) − v``.

        p(l) = (e + 1)/(2π) · max(R_v·l, 0)^e        (on the whole sphere)

    drawn as ``cos ψ = (1 − u₀)^{1/(e+1)}``, ``φ = 2π u₁`` around ``R_v``.  For
    the slides' Phong BRDF ``f_r (n·l) = k_s (R_v·l)^e / π`` the weight
    ``f_r (n·l) / p`` is the constant ``2 k_s / (e + 1)`` above the horizon.

    Examples
    --------
    >>> s = PhongSampler(10).sample(np.array([0.0, 0.25]), np.array([0.0, 0.0, 1.0]))
    >>> s.directions.round(12).tolist(), round(float(s.pdf) * 2 * math.pi, 12)  # R_v itself, density (e+1)/(2π)
    ([0.0, 0.0, 1.0], 11.0)
    """

    name = "phong"

    def __init__(self, exponent: float):
        self.exponent = check_nonnegative("exponent", exponent)

    def __repr__(self):
        return f"PhongSampler({self.exponent!r})"

    @staticmethod
    def _mirror(v):
        return v * np.array([-1.0, -1.0, 1.0])

    def _sample(self, u, v):
        u = np.asarray(u, dtype=np.float64)
        v = _local_v(v)
        e = self.exponent
        omc = _one_minus_cos_power(u[..., 0], e + 1)
        shape = np.broadcast_shapes(omc.shape, v.shape[:-1])
        r = np.broadcast_to(self._mirror(v), shape + (3,))
        l = _around(r, np.broadcast_to(omc, shape), np.broadcast_to(_TWO_PI * u[..., 1], shape))  # noqa: E741
        # pdf = (e+1)/(2π) cos^e α with cos α = (1 − u₀)^{1/(e+1)}; u₀ = 1 is the lobe's rim, where
        # log1p(−1) = −inf: the density there is 0 (1 when e = 0, never 0·inf).
        with np.errstate(under="ignore", divide="ignore"):
            log_c = np.log1p(-np.minimum(u[..., 0], 1.0))
            scaled = e / (e + 1) * log_c if e > 0 else np.zeros_like(log_c)
            pdf = (e + 1) / _TWO_PI * np.exp(scaled)
        return Samples(l, np.broadcast_to(pdf, shape))

    def _pdf(self, l, v):  # noqa: E741
        l, v = np.asarray(l, dtype=np.float64), _local_v(v)  # noqa: E741
        lobe = cos_power(_one_minus_cos_between(l, self._mirror(v)), self.exponent)
        return (self.exponent + 1) / _TWO_PI * lobe



register_model(Phong)

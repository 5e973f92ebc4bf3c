r"""Microfacet normal sampling (Walter et al. 2007): the importance sampler of the microfacet lobes.

Draw ``h`` with density ``D(h) (n·h)``, reflect ``l = 2 (v·h) h − v``, and convert the
density with the Jacobian of that reflection::

    p(l) = D(h) (n·h) / (4 (v·h))

B. Walter, S. R. Marschner, H. Li and K. E. Torrance, "Microfacet models for refraction
through rough surfaces", Eurographics Symposium on Rendering, 2007 (eqs. 28, 35).
"""

from __future__ import annotations

import numpy as np

from .._numeric import check_choice, check_nonnegative, check_positive, safe_div
from ..vec import normalize
from . import microfacet as _mf
from .sampler import (
    _TWO_PI,
    Sampler,
    Samples,
    _check_size,
    _directions,
    _dot,
    _local_v,
    _one_minus_cos_power,
    _unit_square,
)

__all__ = ["MicrofacetSampler"]


class MicrofacetSampler(Sampler):
    r"""Sample a microfacet normal ``h`` with density ``D(h) (n·h)``, then reflect ``v`` about it.

    Inverse CDFs in ``θ_h`` (``φ_h = 2π u₁``; Walter et al. 2007):

    * Beckmann: ``tan²θ_h = −α² ln(1 − u₀)``
    * GGX:      ``tan²θ_h = α² u₀ / (1 − u₀)``
    * Blinn–Phong ``(e+2)/(2π)(n·h)^e``: ``cos θ_h = (1 − u₀)^{1/(e+2)}``

    and with ``l = 2 (v·h) h − v``, ``dω_h / dω_l = 1 / (4 |v·h|)``, so

        p(l) = D(h) (n·h) / (4 |v·h|).

    Parameters
    ----------
    ndf : {"beckmann", "ggx", "blinn-phong"}
    alpha : float > 0
        Roughness α (for "blinn-phong", ``e = 2/α² − 2``, as
        :class:`lighting.models.cook_torrance.CookTorrance` uses) — or give ``exponent``.
    exponent : float >= 0, optional
        Blinn–Phong exponent ``e`` directly.

    Examples
    --------
    >>> import math
    >>> s = MicrofacetSampler("ggx", 0.5)
    >>> h = s.sample_normals(np.array([0.0, 0.0]))
    >>> h.directions.tolist(), round(float(h.pdf) * math.pi * 0.25, 12)  # D(n)·1 = 1/(π α²)
    ([0.0, 0.0, 1.0], 1.0)
    """

    name = "microfacet"

    def __init__(self, ndf: str, alpha: float | None = None, *, exponent: float | None = None):
        ndf = check_choice("ndf", ndf, ("beckmann", "ggx", "blinn-phong"))
        self.ndf = ndf
        if ndf == "blinn-phong" and exponent is not None:
            self.alpha = None
            self.exponent = check_nonnegative("exponent", exponent)
        else:
            if alpha is None:
                need = "alpha (roughness > 0) or exponent (>= 0)" if ndf == "blinn-phong" else "alpha (roughness > 0)"
                raise ValueError(f"{need} is required for ndf={ndf!r}; got alpha=None")
            self.alpha = check_positive("alpha", alpha)
            self.exponent = float(_mf.blinn_phong_exponent(self.alpha)) if ndf == "blinn-phong" else None

    def __repr__(self):
        par = f"exponent={self.exponent!r}" if self.alpha is None else f"alpha={self.alpha!r}"
        return f"MicrofacetSampler({self.ndf!r}, {par})"

    # -- normals ------------------------------------------------------------------
    def normal_pdf(self, h) -> np.ndarray:
        """``D(h) (n·h)``, the density of the sampled normals (0 below the horizon).

        Parameters
        ----------
        h : array_like, shape (..., 3)
            Unit microfacet normals in the local frame.

        Returns
        -------
        ndarray, shape (...)
        """
        return self._normal_pdf(_directions("h", h))

    def _normal_pdf(self, h) -> np.ndarray:
        c = h[..., 2]
        s2 = np.clip(h[..., 0] ** 2 + h[..., 1] ** 2, 0.0, 1.0)
        # h is checked (or built here): the NDFs' unchecked forms, as the models' own evaluation uses.
        dt = c.dtype
        if self.ndf == "blinn-phong":
            d = _mf._blinn_phong_ndf(c, self.exponent, s2, dt)
        elif self.ndf == "beckmann":
            d = _mf._beckmann_ndf(c, self.alpha, s2, dt)
        else:
            d = _mf._ggx_ndf(c, self.alpha, s2, dt)
        return d * np.maximum(c, 0.0)

    def sample_normals(self, u) -> Samples:
        """Microfacet normals ``h`` with density ``D(h)(n·h)`` (upper hemisphere).

        Parameters
        ----------
        u : array_like, shape (..., 2)
            Points of the unit square.

        Returns
        -------
        Samples
            Normals ``(..., 3)`` and their density ``(...)``.
        """
        u = _unit_square("u", u)
        _check_size("u", u.shape[:-1])
        return self._sample_normals(u)

    def _sample_normals(self, u) -> Samples:
        u0 = np.minimum(u[..., 0], 1.0)
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            if self.ndf == "blinn-phong":
                omc = _one_minus_cos_power(u0, self.exponent + 2)
                cos_t = 1.0 - omc
                sin_t = np.sqrt(np.clip(omc * (2.0 - omc), 0.0, None))
            else:
                a2 = self.alpha * self.alpha
                if self.ndf == "beckmann":
                    tan2 = -a2 * np.log1p(-u0)
                else:
                    tan2 = np.where(u0 < 1, a2 * u0 / np.where(u0 < 1, 1.0 - u0, 1.0), np.inf)
                cos_t = np.where(np.isfinite(tan2), 1.0 / np.sqrt(1.0 + tan2), 0.0)
                sin_t = np.where(np.isfinite(tan2), np.sqrt(tan2) * cos_t, 1.0)
        phi = _TWO_PI * u[..., 1]
        h = np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), cos_t], axis=-1)
        return Samples(h, self._normal_pdf(h))

    # -- directions ---------------------------------------------------------------
    def _sample(self, u, v):
        v = _local_v(v)
        hs = self._sample_normals(u)
        shape = np.broadcast_shapes(hs.pdf.shape, v.shape[:-1])
        h = np.broadcast_to(hs.directions, shape + (3,))
        vh = _dot(v, h)
        l = 2 * vh[..., None] * h - v  # noqa: E741
        return Samples(l, self._to_l(np.broadcast_to(hs.pdf, shape), vh))

    @staticmethod
    def _to_l(pdf_h, vh):
        """``p(l) = p(h) / (4 |v·h|)``: 0 where ``v·h = 0``, saturated where it overflows."""
        return safe_div(pdf_h, 4.0 * np.abs(vh))

    def _pdf(self, l, v):  # noqa: E741
        l, v = np.asarray(l, dtype=np.float64), _local_v(v)  # noqa: E741
        s = l + v
        h = normalize(s)  # h = (l + v)/|l + v| (vec.halfway's formula); the zero vector where l = −v
        # The sampled h lies in the upper hemisphere; l + v may point either way along it.
        h = np.where(h[..., 2:3] < 0, -h, h)
        return np.where(_dot(s, s) > 0, self._to_l(self._normal_pdf(h), _dot(v, h)), 0.0)


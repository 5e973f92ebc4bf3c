r"""Microfacet normal sampling (Walter et al. 2007): the importance sampler of the microfacet lobes.

Draw ``h`` with density ``D(h) (n·h)``, reflect ``l = 2 (v·h) h − v``, and convert the
density with the Jacobian of that reflection:

    p(l) = D(h) (n·h) / (4 (v·h))

B. Walter, S. R. Marschner, H. Li and K. E. Torrance, "Microfacet models for refraction
through rough surfaces", Eurographics Symposium on Rendering, 2007 (eqs. 28, 35).

:class:`VisibleNormalSampler` draws ``h`` from the distribution of normals visible from ``v``
instead (Heitz 2018 for GGX, Heitz and d'Eon 2014 for Beckmann): the importance sampler of the
Smith models, whose density ``G1(v) D(h) / (4 n·v)`` leaves a weight of just ``G1(l)`` (separable)
or ``G2/G1(v)`` (height-correlated) per sample.
"""

from __future__ import annotations

import math

import numpy as np

from .._validate import check_choice, check_nonnegative, check_positive
from ..models import microfacet as _mf
from ..numerics import safe_div
from ..vec import _dot, normalize
from .base import (
    _TWO_PI,
    Sampler,
    Samples,
    _check_size,
    _columns_of,
    _directions,
    _half_columns,
    _local_v,
    _one_minus_cos_power,
    _stack3,
    _unit_columns,
    _unit_square,
    _upper,
)

__all__ = ["MicrofacetSampler", "VisibleNormalSampler"]


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
        cols = _columns_of(l, v)
        half = None if cols is None else _half_columns(*(c + v[k] for k, c in enumerate(cols)))
        if half is not None:
            # Directions (n, 3) for one view: the reference's steps below, column by column.
            h0, h1, h2, ss = half
            vh = v[0] * h0 + v[1] * h1 + v[2] * h2
            return np.where(ss > 0, self._to_l(self._normal_pdf(_stack3(h0, h1, h2)), vh), 0.0)
        s = l + v
        h = normalize(s)  # h = (l + v)/|l + v| (vec.halfway's formula); the zero vector where l = −v
        # The sampled h lies in the upper hemisphere; l + v may point either way along it.
        h = _upper(h)
        return np.where(_dot(s, s) > 0, self._to_l(self._normal_pdf(h), _dot(v, h)), 0.0)



class VisibleNormalSampler(MicrofacetSampler):
    r"""Sample the microfacet normals visible from ``v``, then reflect ``v`` about them.

    The distribution of visible normals (Heitz 2014, eq. 38):

        D_v(h) = G1(v) max(0, v·h) D(h) / (n·v),

    and with ``l = 2 (v·h) h − v``, ``dω_h / dω_l = 1 / (4 v·h)``:

        p(l) = G1(v) D(h) / (4 n·v)     (v·h > 0, n·h > 0; else 0),

    evaluated as ``D(h) / (2 d_v)`` with ``G1(v) = 2 (n·v) / d_v``, finite at grazing views.

    * GGX: Heitz 2018 — stretch ``v`` to the unit-roughness configuration, sample the projected
      hemisphere seen from it (a disk whose far half is compressed by ``(1 + cos θ)/2``), and
      unstretch the normal.  Exact and closed form.
    * Beckmann: Heitz and d'Eon 2014 — stretch, sample the slope along ``v``'s azimuth by inverting
      its CDF ``(1 + erf x + tan θ exp(−x²)/√π)/(1 + erf(cot θ) + tan θ exp(−cot²θ)/√π)`` by safeguarded
      Newton iteration in the ``erf`` domain (to 1e-14 in the CDF; pbrt-v3's scheme), the other slope
      Gaussian.

    Views at or below the horizon (``n·v <= 0``, where the visible distribution is undefined) fall
    back to :class:`MicrofacetSampler`'s ``D(h)(n·h)`` sampling and its density, so that ``pdf``
    stays a density on the sphere for every ``v``.

    Parameters
    ----------
    ndf : {"beckmann", "ggx"}
    alpha : float > 0
        Roughness α (``α_x``, along the local ``x`` axis — the tangent — when ``alpha_y`` is given).
    alpha_y : float > 0, optional
        Roughness along the local ``y`` axis (the bitangent) for anisotropic distributions
        (``D ∝ 1/(α_x α_y ((h_x/α_x)² + (h_y/α_y)² + h_z²)²)`` for GGX); both methods stretch by
        ``(α_x, α_y)`` natively.

    References
    ----------
    E. Heitz, "Sampling the GGX distribution of visible normals", Journal of Computer Graphics
    Techniques 7(4), 1–13, 2018.
    E. Heitz and E. d'Eon, "Importance sampling microfacet-based BSDFs using the distribution of
    visible normals", Computer Graphics Forum 33(4) (EGSR), 2014.
    E. Heitz, "Understanding the masking-shadowing function in microfacet-based BRDFs", JCGT 3(2), 2014.

    Examples
    --------
    >>> s = VisibleNormalSampler("ggx", 0.5)
    >>> l = s.sample(np.array([0.0, 0.0]), np.array([0.0, 0.0, 1.0]))
    >>> l.directions.tolist(), round(float(l.pdf) * math.pi, 12)  # at v = n: D(n)/4 = 1/(4π α²)
    ([0.0, 0.0, 1.0], 1.0)
    """

    name = "visible-normals"

    def __init__(self, ndf: str, alpha: float, *, alpha_y: float | None = None):
        ndf = check_choice("ndf", ndf, ("beckmann", "ggx"))
        super().__init__(ndf, alpha)
        self.alpha_y = None if alpha_y is None else check_positive("alpha_y", alpha_y)
        self._ay = self.alpha if self.alpha_y is None else self.alpha_y
        self._aniso = self._ay != self.alpha

    def __repr__(self):
        extra = "" if self.alpha_y is None else f", alpha_y={self.alpha_y!r}"
        return f"VisibleNormalSampler({self.ndf!r}, alpha={self.alpha!r}{extra})"

    def _den_v(self, v):
        """``d_v`` with ``G1(v) = 2 (n·v) / d_v`` (1 where ``n·v <= 0``)."""
        s2 = np.clip(v[..., 0] ** 2 + v[..., 1] ** 2, 0.0, 1.0)
        if self._aniso:
            lc = _mf._smith_lambda_cos_aniso(self.ndf, v[..., 0], v[..., 1], v[..., 2], self.alpha, self._ay)
            d = 2 * (v[..., 2] + lc)
            return np.where((v[..., 2] > 0) & (d > 0), d, 1.0)
        den = _mf._smith_g1_den_ggx if self.ndf == "ggx" else _mf._smith_g1_den_beckmann
        return den(v[..., 2], self.alpha, s2)

    def _normal_pdf(self, h) -> np.ndarray:
        if not self._aniso:
            return super()._normal_pdf(h)
        f = _mf._ggx_ndf_aniso if self.ndf == "ggx" else _mf._beckmann_ndf_aniso
        c = h[..., 2]
        return f(h[..., 0], h[..., 1], c, self.alpha, self._ay, np.float64) * np.maximum(c, 0.0)

    def _sample_normals(self, u) -> Samples:
        if not self._aniso:
            return super()._sample_normals(u)
        # D(h)(n·h) for the anisotropic NDF: the visible normals of the view v = n are exactly these.
        n = np.zeros(u.shape[:-1] + (3,))
        n[..., 2] = 1.0
        h = self._visible_normals(u, n)
        return Samples(h, self._normal_pdf(h))

    def _visible_normals(self, u, v):
        """Visible normals ``h`` (upper hemisphere, ``v·h >= 0``) for unit views ``v`` with ``v_z > 0``."""
        al, ay = self.alpha, self._ay
        # Stretch the view to the unit-roughness configuration.
        vs = normalize(np.stack([al * v[..., 0], ay * v[..., 1], v[..., 2]], axis=-1))
        if self.ndf == "ggx":
            lensq = vs[..., 0] ** 2 + vs[..., 1] ** 2
            # 1/√lensq of a positive lensq (even subnormal) is finite; 0 is replaced by 1 before dividing.
            inv = np.where(lensq > 0, 1 / np.sqrt(np.where(lensq > 0, lensq, 1.0)), 0.0)
            t1 = np.stack([np.where(lensq > 0, -vs[..., 1] * inv, 1.0), np.where(lensq > 0, vs[..., 0] * inv, 0.0),
                           np.zeros_like(lensq)], axis=-1)
            t2 = np.cross(vs, t1)
            r = np.sqrt(u[..., 0])
            phi = _TWO_PI * u[..., 1]
            p1 = r * np.cos(phi)
            p2 = r * np.sin(phi)
            sh = 0.5 * (1 + vs[..., 2])
            p2 = (1 - sh) * np.sqrt(np.clip(1 - p1 * p1, 0.0, None)) + sh * p2
            p3 = np.sqrt(np.clip(1 - p1 * p1 - p2 * p2, 0.0, None))
            nh = p1[..., None] * t1 + p2[..., None] * t2 + p3[..., None] * vs
            h = np.stack([al * nh[..., 0], ay * nh[..., 1], np.maximum(nh[..., 2], 0.0)], axis=-1)
            return normalize(h)
        # Beckmann: slopes of the stretched configuration, along the view's azimuth and across it.
        sin_t = np.hypot(vs[..., 0], vs[..., 1])
        cos_t = vs[..., 2]
        # sin_t = hypot(vs_x, vs_y) >= |vs_x|, |vs_y| (1 where it is 0): quotients in [−1, 1].
        cos_p = np.where(sin_t > 0, vs[..., 0] / np.where(sin_t > 0, sin_t, 1.0), 1.0)
        sin_p = np.where(sin_t > 0, vs[..., 1] / np.where(sin_t > 0, sin_t, 1.0), 0.0)
        sx = _beckmann_slope_x(cos_t, sin_t, u[..., 0])
        sy = _erfinv(2 * np.clip(u[..., 1], 1e-12, 1 - 1e-12) - 1)
        x = al * (cos_p * sx - sin_p * sy)
        y = ay * (sin_p * sx + cos_p * sy)
        return normalize(np.stack([-x, -y, np.ones_like(x)], axis=-1))

    def _sample(self, u, v):
        v = _local_v(v)
        shape = np.broadcast_shapes(u.shape[:-1], v.shape[:-1])
        u = np.broadcast_to(u, shape + (2,))
        vb = np.broadcast_to(v, shape + (3,))
        up = vb[..., 2] > 0
        if np.all(up):
            # Every view above the horizon: the visible normals alone (the same batch, in the same order, as
            # the masked rows below), and no fallback to draw.
            vu = normalize(vb.reshape(-1, 3))
            h = self._visible_normals(u.reshape(-1, 2), vu)
            vh = _dot(vu, h)
            l = 2 * vh[..., None] * h - vu  # noqa: E741
            # One view for every draw: its d_v (for Beckmann a continued fraction) once, not once per row, and
            # remembered with the densities' (the same view's pdf asks for it next).
            den = self._den_of_view(vu[0]) if v.size == 3 else None
            return Samples(l.reshape(shape + (3,)), self._visible_pdf(h, vu, vh, den).reshape(shape))
        fallback = super()._sample(u, vb)
        if not np.any(up):
            return fallback
        vu = normalize(vb[up])
        h = self._visible_normals(u[up], vu)
        vh = _dot(vu, h)
        l = 2 * vh[..., None] * h - vu  # noqa: E741
        dirs = np.array(fallback.directions)
        pdf = np.array(fallback.pdf, dtype=np.float64)
        dirs[up] = l
        pdf[up] = self._visible_pdf(h, vu, vh)
        return Samples(dirs, pdf)

    def _visible_pdf(self, h, v, vh, den=None):
        """``p(l) = D(h) / (2 d_v)`` where ``v·h > 0`` and ``n·h > 0``, else 0 (``v`` unit, ``v_z > 0``).

        ``den``: ``self._den_v(v)`` if the caller has it (broadcasting with ``h``).
        """
        c = h[..., 2]
        if self._aniso:
            f = _mf._ggx_ndf_aniso if self.ndf == "ggx" else _mf._beckmann_ndf_aniso
            d = f(h[..., 0], h[..., 1], c, self.alpha, self._ay, np.float64)
        else:
            s2 = np.clip(h[..., 0] ** 2 + h[..., 1] ** 2, 0.0, 1.0)
            ndf = _mf._ggx_ndf if self.ndf == "ggx" else _mf._beckmann_ndf
            d = ndf(c, self.alpha, s2, np.float64)
        with np.errstate(over="ignore"):
            p = d / (2 * (self._den_v(v) if den is None else den))
        return np.where((vh > 0) & (c > 0), np.minimum(p, np.finfo(np.float64).max), 0.0)

    def _pdf(self, l, v):  # noqa: E741
        l, v = np.asarray(l, dtype=np.float64), _local_v(v)  # noqa: E741
        if np.all(v[..., 2] > 0):
            # Every view above the horizon (an integrator's usual call): no fallback to evaluate, and each
            # view's d_v once, however many directions share it.
            return self._visible_pdf_of(l, v)
        shape = np.broadcast_shapes(l.shape[:-1], v.shape[:-1])
        fallback = np.array(np.broadcast_to(super()._pdf(l, v), shape), dtype=np.float64)
        vb = np.broadcast_to(v, shape + (3,))
        up = vb[..., 2] > 0
        if not np.any(up):
            return fallback
        fallback[up] = self._visible_pdf_of(np.broadcast_to(l, shape + (3,))[up], vb[up])
        return fallback

    def _visible_pdf_of(self, l, v):  # noqa: E741
        """The visible-normal density of directions ``l`` for views ``v`` above the horizon (broadcasting)."""
        vu = normalize(v)
        cols = _columns_of(l, vu)
        nl = None if cols is None else _unit_columns(*cols)
        if nl is not None:
            half = _half_columns(*(c + vu[k] for k, c in enumerate(nl[:3])))
            if half is not None:
                # Directions (n, 3) above the horizon for one view: the steps below, column by column.
                h0, h1, h2, ss = half
                vh = vu[0] * h0 + vu[1] * h1 + vu[2] * h2
                h = _stack3(h0, h1, h2)
                return np.where(ss > 0, self._visible_pdf(h, vu, vh, self._den_of_view(vu)), 0.0)
        s = normalize(l) + vu
        h = normalize(s)
        h = _upper(h)  # l is unchanged by h → −h; the sampled h is the upper one
        vh = _dot(vu, h)
        return np.where(_dot(s, s) > 0, self._visible_pdf(h, vu, vh, self._den_of_view(vu)), 0.0)

    def _den_of_view(self, vu):
        """``self._den_v(vu)``, remembered for a single view: an integrator asks for the same view's density
        over many blocks of directions, and Beckmann's ``d_v`` is a continued fraction.  Per-row views are
        not remembered (None: :meth:`_visible_pdf` computes them)."""
        if vu.shape != (3,):
            return None
        key = vu.tobytes()
        cache = self.__dict__.setdefault("_den_cache", {})
        den = cache.get(key)
        if den is None:
            if len(cache) >= 64:
                cache.clear()
            den = cache[key] = self._den_v(vu)
        return den


def _erfinv(x):
    from scipy.special import erfinv

    return erfinv(x)


def _beckmann_slope_x(cos_t, sin_t, u0):
    """The slope along the view's azimuth of a Beckmann (α = 1) visible normal, by inverting its CDF.

    In ``b = erf(x)`` the CDF is ``P(b) = (1 + b + tan θ exp(−erfinv(b)²)/√π) / (1 + erf(cot θ) +
    tan θ exp(−cot²θ)/√π)`` on ``b ∈ [−1, erf(cot θ)]`` with ``dP/db ∝ 1 − erfinv(b) tan θ`` (Heitz and
    d'Eon 2014; pbrt-v3's ``BeckmannSample11``): Newton steps kept inside a shrinking bracket, until the
    CDF matches ``u`` to 1e-14 (typically 4–6 steps; at most 60).
    """
    from scipy.special import erf

    sp = 1 / math.sqrt(math.pi)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore", under="ignore"):
        tan_t = np.where(cos_t > 0, sin_t / np.where(cos_t > 0, cos_t, 1.0), np.inf)
        cot_t = np.where(sin_t > 0, cos_t / np.where(sin_t > 0, sin_t, 1.0), np.inf)
        lo = np.full(np.shape(u0), -1.0)
        hi = np.array(erf(cot_t), dtype=np.float64)
        tail = np.where(sin_t > 0, tan_t * sp * np.exp(-cot_t * cot_t), 0.0)
        norm = 1 / (1 + hi + tail)
        target = np.clip(u0, 1e-12, 1 - 1e-12)
        # pbrt-v3's initial guess (a fit in θ of the stretched view); Newton refines it.
        theta = np.arctan2(sin_t, cos_t)
        fit = 1 + theta * (-0.876 + theta * (0.4265 - 0.0594 * theta))
        b = hi - (1 + hi) * np.power(1 - target, fit)
        tan_f = np.where(np.isfinite(tan_t), tan_t, 0.0)
        for _ in range(60):
            # Bisect only where Newton left the bracket (inclusive: a converged b sits on an end of it).
            b = np.where((b >= lo) & (b <= hi), b, 0.5 * (lo + hi))
            x = _erfinv(b)
            value = norm * (1 + b + np.where(sin_t > 0, tan_f * sp * np.exp(-x * x), 0.0)) - target
            if np.all(np.abs(value) <= 1e-14):  # the CDF matched to 1e-14 everywhere: done
                break
            deriv = norm * (1 - x * tan_f)
            lo = np.where(value <= 0, b, lo)
            hi = np.where(value > 0, b, hi)
            step = np.where(deriv > 0, value / np.where(deriv > 0, deriv, 1.0), 0.0)
            b = b - step
        b = np.where((b >= lo) & (b <= hi), b, 0.5 * (lo + hi))
        return _erfinv(b)

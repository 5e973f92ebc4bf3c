r"""Oren–Nayar rough diffuse reflection: Lambertian V-cavities with Gaussian slopes of deviation σ.

    qualitative:  f_r = k_d/π (A + B max(0, cos(φ_l − φ_v)) sin α tan β),   α = max(θ_l, θ_v), β = min(θ_l, θ_v)
    full:         the paper's C1, C2, C3 direct term plus the two-bounce interreflection term (k_d²)

Both equal Lambert's ``k_d/π`` at σ = 0; the sampler is Lambert's cosine-weighted hemisphere.
"""

from __future__ import annotations

import math

import numpy as np

from .._text import quote
from .._validate import check_choice, real_array
from ..numerics import saturate_to
from ..vec import _dot
from .base import BRDFFlags, SeparableBRDF, _color, _color_text, _combine
from .geometry import Geometry
from .lambert import CosineSampler
from .protocol import Lobe, Parameter, register_model

__all__ = ["OrenNayar"]

_TINY = np.finfo(np.float64).tiny
_BIG = np.finfo(np.float64).max


def _check_sigma(sigma) -> float:
    """``sigma``: a finite real number >= 0 (radians)."""
    allowed = "a finite number >= 0 (radians)"
    arr = real_array("sigma", sigma, allowed=allowed, dtype=np.float64)
    if arr.shape != () or not np.isfinite(arr) or arr < 0:
        raise ValueError(f"sigma must be {allowed}; got {quote(sigma)}")
    return float(arr)


def _cross(a, b):
    return np.stack(
        [
            a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
            a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
            a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0],
        ],
        axis=-1,
    )


def _dot3(a, b):
    """``_dot`` of two vectors given as their three component arrays (the same products, summed in the same order)."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cross3(a, b):
    """``_cross`` of two vectors given as component arrays, returned as a tuple of three (no stacking)."""
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _angles(g: Geometry):
    """Float64 ``cos θ_l, cos θ_v, sin θ_l, sin θ_v`` and ``P = (n×l)·(n×v) = sin θ_l sin θ_v cos(φ_l − φ_v)``.

    ``n × l`` is the projection of ``l`` onto the tangent plane turned by 90° about ``n`` (the same
    turn for ``v``), so ``P`` is the dot product of the two projections: no tangent frame is needed,
    and ``P = 0`` where either direction lies along ``n`` (where ``φ`` is undefined).

    The projections are carried as tuples of three component arrays: the arithmetic of
    :func:`_angles_reference` element by element, without NumPy stacking the cross products and
    striding over the axis of length 3 again in each dot product.
    """
    n, l, v = (np.asarray(x, dtype=np.float64) for x in (g.n, g.l, g.v))  # noqa: E741
    n, l, v = ((x[..., 0], x[..., 1], x[..., 2]) for x in (n, l, v))  # noqa: E741
    cl, cv = _dot3(n, l), _dot3(n, v)
    xl, xv = _cross3(n, l), _cross3(n, v)
    sl, sv = np.sqrt(_dot3(xl, xl)), np.sqrt(_dot3(xv, xv))
    return cl, cv, np.minimum(sl, 1.0), np.minimum(sv, 1.0), _dot3(xl, xv), (xl, sl, xv, sv)


def _angles_reference(g: Geometry):
    """:func:`_angles` on stacked ``(..., 3)`` vectors (the projections returned stacked): the readable form."""
    n, l, v = (np.asarray(x, dtype=np.float64) for x in (g.n, g.l, g.v))  # noqa: E741
    cl, cv = _dot(n, l), _dot(n, v)
    xl, xv = _cross(n, l), _cross(n, v)
    sl, sv = np.sqrt(_dot(xl, xl)), np.sqrt(_dot(xv, xv))
    return cl, cv, np.minimum(sl, 1.0), np.minimum(sv, 1.0), _dot(xl, xv), (xl, sl, xv, sv)


def _cos_dphi(xl, sl, xv, sv):
    """``cos Δφ`` and ``1 − |cos Δφ|`` (float64) from the projections ``n × l``, ``n × v`` and their lengths.

    With the unit projections ``a = (n×l)/|n×l|``, ``b = (n×v)/|n×v|``: ``1 − a·b = |a − b|²/2`` and
    ``1 + a·b = |a + b|²/2``, so ``1 − |cos Δφ|`` keeps its digits where the azimuths nearly agree or
    are nearly opposite (``1 − |P/(sin θ_l sin θ_v)|`` cancels there: at Δφ = π − 1e-3 it lost 10 % of
    its value to a sine clamped at 1).  Both are 0 and 1 where either direction is along ``n``.

    ``xl`` and ``xv`` are component tuples (:func:`_angles`); :func:`_cos_dphi_reference` is the same on
    stacked vectors.
    """
    ok = (sl > 0) & (sv > 0)
    # Each projection divided by its own length (or by 1 where that is 0): finite, of length <= 1.
    ql, qv = np.where(ok, sl, 1.0), np.where(ok, sv, 1.0)
    a = tuple(x / ql for x in xl)
    b = tuple(x / qv for x in xv)
    cphi = np.clip(_dot3(a, b), -1.0, 1.0)
    sign = np.where(cphi >= 0, 1.0, -1.0)
    d = tuple(ai - sign * bi for ai, bi in zip(a, b, strict=True))
    return np.where(ok, cphi, 0.0), np.where(ok, np.minimum(_dot3(d, d) / 2, 1.0), 1.0)


def _cos_dphi_reference(xl, sl, xv, sv):
    """The readable form of :func:`_cos_dphi`, on stacked ``(..., 3)`` projections."""
    ok = (sl > 0) & (sv > 0)
    # Each projection divided by its own length (or by 1 where that is 0): finite, of length <= 1.
    a = xl / np.where(ok, sl, 1.0)[..., None]
    b = xv / np.where(ok, sv, 1.0)[..., None]
    cphi = np.clip(_dot(a, b), -1.0, 1.0)
    d = a - np.where(cphi >= 0, 1.0, -1.0)[..., None] * b
    return np.where(ok, cphi, 0.0), np.where(ok, np.minimum(_dot(d, d) / 2, 1.0), 1.0)


class OrenNayar(SeparableBRDF):
    r"""Oren–Nayar reflection from a rough surface of Lambertian V-cavities (slopes with deviation σ).

    The qualitative model (``form="qualitative"``, the paper's eq. 30 and the default):

        f_r = k_d/π · (A + B · max(0, cos(φ_l − φ_v)) · sin α · tan β)
        A = 1 − 0.5 σ²/(σ² + 0.33),    B = 0.45 σ²/(σ² + 0.09)
        α = max(θ_l, θ_v),             β = min(θ_l, θ_v)

    The full model (``form="full"``): the direct (one-bounce) term with the three coefficients
    C1, C2, C3 of the paper's functional approximation, plus its two-bounce interreflection term:

        f_r = k_d/π · max(0, C1 + cos Δφ · C2 · tan β + (1 − |cos Δφ|) · C3 · tan((α + β)/2))
            + k_d²/π · 0.17 σ²/(σ² + 0.13) · (1 − cos Δφ · (2β/π)²)
        C1 = 1 − 0.5 σ²/(σ² + 0.33)
        C2 = 0.45 σ²/(σ² + 0.09) · sin α                      (cos Δφ >= 0)
        C2 = 0.45 σ²/(σ² + 0.09) · (sin α − (2β/π)³)          (cos Δφ < 0)
        C3 = 0.125 σ²/(σ² + 0.09) · (4 α β / π²)²

    with ``Δφ = φ_l − φ_v``.  The interreflection term is quadratic in the facet albedo, so per
    channel it scales with ``k_d²``, not ``k_d``.

    Both forms are Lambert's ``k_d/π`` at σ = 0 (A = C1 = 1, B = C2 = C3 = 0, no interreflection),
    bit for bit in ``eval``, ``eval_cos`` and ``classic``, both dtypes.  Both are reciprocal
    (symmetric in ``l`` and ``v``).

    Parameters
    ----------
    kd : float or RGB triple, >= 0
        The facets' albedo ``ρ`` (the surface colour), as Lambert's ``k_d``.
    sigma : float >= 0
        Roughness: the standard deviation of the facet slope angle, in radians.  0 is Lambert;
        the paper's measured surfaces lie below about 0.7 (40°).
    form : {"qualitative", "full"}
        The simplified model or the full one with C1, C2, C3 and interreflections.

    Notes
    -----
    ``cos(φ_l − φ_v)`` comes from the projections of ``l`` and ``v`` onto the tangent plane,
    ``(n × l)·(n × v) / (sin θ_l sin θ_v)``; no tangent frame is needed.  In the qualitative
    model ``sin α tan β cos Δφ = (n × l)·(n × v) / max(n·l, n·v)`` exactly (the sines cancel), so
    no angle is formed and a direction along ``n`` needs no guard (the product is 0 there).  The
    full model needs ``α`` and ``β`` themselves (``atan2`` of the sine and cosine, in float64),
    ``tan((α+β)/2) = (sin α + sin β)/(cos α + cos β)``, and ``cos Δφ`` (taken as 0 where either
    direction is along ``n``: every term it multiplies vanishes there with ``β``).

    The functional form is an approximation, not an energy-conserving BRDF:

    * the qualitative model's directional albedo is, in closed form,
      ``ρ(θ_v) = k_d [A + (2B/π)(sin θ_v (θ_v/2 − sin 2θ_v / 4) + tan θ_v (1 − sin³θ_v)/3)]``,
      rising from ``k_d A`` at the normal to ``k_d (A + B/2)`` at grazing; ``A + B/2 ≈ 1 + 0.985 σ²``
      for small σ exceeds 1 for every ``0 < σ < 0.326`` rad (by at most 1.5 %, at σ ≈ 0.199), so
      a white surface there reflects slightly more than it receives at grazing views;
    * the full model's directional albedo is ``k_d D(θ_v) + k_d² R`` with ``R = 0.17 σ²/(σ² + 0.13)``
      exactly (the ``cos Δφ`` part of the interreflection term integrates to 0); ``D`` stays below
      ``A + B/2`` and peaks near 1.0035 (σ ≈ 0.15, grazing), so for ``k_d`` near 1 the sum exceeds
      ``k_d`` at grazing views (1.040 at σ = 0.2, ``k_d = 1``);
    * the full model's direct term turns negative for σ > 0.665 rad at forward-scattering
      grazing geometry: at ``cos Δφ = −1`` with both angles near 90°, ``C2 tan β`` tends to
      ``(6/π) · 0.45 σ²/(σ² + 0.09)``, which exceeds ``C1`` there.  It is clamped at 0 here (a BRDF
      is never negative); the interreflection term is >= 0 everywhere.

    Both ``tan β`` and ``tan((α+β)/2)`` grow without bound when ``l`` and ``v`` both graze, so
    ``eval`` does too (it saturates at the dtype's largest value); ``f_r (n·l)`` stays bounded by
    ``k_d (A + B)/π`` in the qualitative model.  The delicate parts are computed in float64.

    The importance sampler is Lambert's cosine-weighted hemisphere (:class:`CosineSampler`): exact
    at σ = 0, and for σ > 0 the weight ``f_r (n·l)/p = π f_r`` is bounded for every view off the
    horizon (by ``k_d (A + B tan θ_v)`` in the qualitative model).

    References
    ----------
    M. Oren and S. K. Nayar, "Generalization of Lambert's reflectance model", Proceedings of
    SIGGRAPH 94 (Computer Graphics, Annual Conference Series), 239–246, 1994.
    M. Oren and S. K. Nayar, "Generalization of the Lambertian model and implications for machine
    vision", International Journal of Computer Vision 14(3), 227–251, 1995.

    Examples
    --------
    >>> on = OrenNayar(1.0, 0.5)
    >>> round(float(on.eval((0, 0, 1.0), (0, 0, 1.0), (0, 0, 1.0))[0]), 6)  # A/π, A = 1 − 0.125/0.58
    0.249709
    >>> l, v = (1.0, 0, 1.0), (1.0, 0, 1.0)  # both at 45°, same azimuth: A + B sin 45° tan 45°
    >>> round(float(on.eval((0, 0, 1.0), l, v)[0] * math.pi), 6)
    1.018452
    >>> from lighting.models.lambert import Lambert
    >>> n, v = (0, 0, 1.0), (0, 1.0, 1.0)
    >>> bool((OrenNayar(0.8, 0.0).eval(n, l, v) == Lambert(0.8).eval(n, l, v)).all())  # σ = 0: Lambert
    True
    """

    name = "oren-nayar"
    flags = BRDFFlags.DIFFUSE
    FORMS = ("qualitative", "full")
    parameters = (
        Parameter("kd", "color", 0.8, slider=(0.0, 1.0), description="facet albedo k_d (the surface colour)"),
        Parameter(
            "sigma",
            "float",
            0.3,
            slider=(0.0, math.pi / 2),
            unit="rad",
            description="roughness σ: standard deviation of the facet slope angle (0 is Lambert)",
        ),
        Parameter(
            "form",
            "choice",
            "qualitative",
            choices=FORMS,
            description="the qualitative model (A, B) or the full one (C1, C2, C3 and interreflections)",
        ),
    )

    def __init__(self, kd=0.8, sigma=0.3, form="qualitative"):
        self.kd = _color("kd", kd)
        self.sigma = _check_sigma(sigma)
        self.form = check_choice("form", form, self.FORMS)
        s2 = self.sigma * self.sigma  # Python floats: 0 or inf at the ends of the range, without a warning

        def ratio(c):  # σ²/(σ² + c), also where σ² underflows to 0 or overflows to inf
            return 1.0 / (1.0 + c / s2) if s2 > 0 else 0.0

        self._A = 1.0 - 0.5 * ratio(0.33)  # = C1
        self._B = 0.45 * ratio(0.09)  # C2 / sin α (cos Δφ >= 0)
        self._C3 = 0.125 * ratio(0.09)  # C3 / (4αβ/π²)²
        self._R = 0.17 * ratio(0.13)  # the interreflection term's scale
        with np.errstate(over="ignore"):
            self._kd2 = np.minimum(self.kd * self.kd, _BIG)

    # -- the description ---------------------------------------------------------------
    @property
    def is_black(self):
        return not np.any(self.kd > 0)

    def _params(self):
        return {"kd": self.kd, "sigma": self.sigma, "form": self.form}

    def lobe(self):
        """``Lobe("normal")``: spread over the hemisphere about ``n``."""
        return Lobe("normal")

    def sampler(self):
        """``CosineSampler``: exact for σ = 0; for σ > 0 the weight ``π f_r`` is bounded for views off the horizon."""
        return CosineSampler()

    def summary(self):
        """``"kd=0.8 σ=0.3"`` (``" full"`` appended for the full model; a coloured ``kd`` as ``(r,g,b)``)."""
        text = f"kd={_color_text(self.kd)} σ={self.sigma:g}"
        return text + (" full" if self.form == "full" else "")

    @property
    def diffuse_albedo(self):
        """The directional albedo at normal incidence (:attr:`BRDF.diffuse_albedo`): ``k_d A``, full ``k_d A + k_d² R``.

        For ``v = n``, ``β = 0``: the ``B``, ``C2`` and ``C3`` terms vanish and ``f_r = k_d A/π`` (plus the
        interreflection's ``k_d² R/π``, whose ``cos Δφ`` part has the factor ``β²``).  At σ = 0 it is
        ``k_d`` (Lambert's).  ``f_r`` is not the constant ``k_d/π`` for σ > 0, so :attr:`lambertian` is
        False and no closed form of Lambert's is applied to this model.

        Returns
        -------
        numpy.ndarray, (3,)
        """
        rho = self.kd * self._A
        if self.form == "full":
            rho = rho + self.kd * self.kd * self._R
        return rho

    # -- the values ----------------------------------------------------------------------
    def factors(self, g: Geometry):
        """The two float64 fields ``F1``, ``F2`` with ``f_r = k_d/π F1 + k_d²/π F2`` (0 below the horizon).

        Parameters
        ----------
        g : Geometry
            The shading directions.

        Returns
        -------
        F1, F2 : ndarray (float64)
            ``F1 = A + B max(0, cos Δφ) sin α tan β`` (qualitative) or the full model's clamped direct
            term; ``F2`` the interreflection factor (0 for the qualitative model).  Finite, >= 0.
        """
        above = np.asarray(g.above)
        # At σ = 0, A = C1 = 1 and B = C2 = C3 = 0 exactly, and every field below is finite: F1 = 1, F2 = 0.
        cl, cv, sl, sv, p, proj = _angles(g)
        cmax = np.maximum(np.maximum(cl, cv), _TINY)
        with np.errstate(over="ignore"):
            if self.form == "qualitative":
                f1 = self._A + self._B * (np.maximum(p, 0.0) / cmax)
                f2 = np.zeros_like(f1)
            else:
                f1, f2 = self._full(cl, cv, sl, sv, proj, cmax)
        f1 = np.where(above, np.minimum(f1, _BIG), 0.0)
        f2 = np.where(above, np.minimum(f2, _BIG), 0.0)
        return f1, f2

    def _full(self, cl, cv, sl, sv, proj, cmax):
        # β is the direction nearer the normal (the larger cosine, the smaller sine), α the other; taking
        # max and min of each keeps every quantity symmetric in l and v to the last bit (reciprocity).
        cb, sb = cmax, np.minimum(sl, sv)
        ca, sa = np.maximum(np.minimum(cl, cv), 0.0), np.maximum(sl, sv)
        alpha, beta = np.arctan2(sa, ca), np.arctan2(sb, cb)
        cphi, one_minus_abs = _cos_dphi(*proj)
        tan_b = sb / cb
        tan_mid = (sa + sb) / np.maximum(ca + cb, _TINY)  # tan((α+β)/2)
        # sin α − (2β/π)³ where both graze is the difference of two numbers near 1 (at 1e-8 rad from the
        # horizon it kept 8 digits, which tan β ~ 1e8 then multiplied): with u = 2(π/2 − β)/π, the
        # elevation of β's direction taken directly, it is u(3 − 3u + u²) − cos²α/(1 + sin α).
        u = np.arctan2(cb, sb) * (2 / math.pi)
        c2 = self._B * np.where(cphi >= 0, sa, u * (3 - 3 * u + u * u) - ca * ca / (1 + sa))
        c3 = self._C3 * (4 * alpha * beta / math.pi**2) ** 2
        direct = self._A + cphi * c2 * tan_b + one_minus_abs * c3 * tan_mid
        inter = self._R * (1 - cphi * (2 * beta / math.pi) ** 2)
        return np.maximum(direct, 0.0), inter

    def _terms(self, g: Geometry, scale):
        """``[(scale·F1, kd), (scale·F2, kd²)]`` with ``scale`` a dtype field, products rounded to the dtype."""
        f1, f2 = self.factors(g)
        s = np.asarray(scale, dtype=g.dtype).astype(np.float64)
        with np.errstate(over="ignore"):
            terms = [(saturate_to(s * f1, g.dtype), self.kd)]
            if self.form == "full":
                terms.append((saturate_to(s * f2, g.dtype), self._kd2))
        return terms

    def _f(self, g):
        # Lambert's own rounding: the dtype's 1/π times the factor (1 at σ = 0).
        return _combine(self._terms(g, g.dtype(1 / math.pi)), g.dtype)

    def _f_cos(self, g):
        return _combine(self.separable_cos(g), g.dtype)

    def separable_cos(self, g):
        """``(n·l/π · F1, kd)`` and, for the full model, ``(n·l/π · F2, kd²)`` (:meth:`factors`); the fields are 0 below
        the horizon, in the dtype of ``g``.
        """
        return self._terms(g, np.maximum(g.n_dot_l, 0) / g.dtype(math.pi))

    def separable_classic(self, g):
        """``(n·l · F1, kd)`` and, for the full model, ``(n·l · F2, kd²)``, in the dtype of ``g``."""
        return self._terms(g, np.maximum(g.n_dot_l, 0))


register_model(OrenNayar)

r"""The Ashikhmin–Shirley anisotropic Phong BRDF and its half-vector sampler.

    f_s = √((n_u+1)(n_v+1))/(8π) · (n·h)^{(n_u (h·t)² + n_v (h·b)²)/(1 − (n·h)²)} / ((h·k) max(n·l, n·v)) · F(k·h)
    f_d = 28 R_d/(23π) (1 − R_s) (1 − (1 − n·l/2)⁵) (1 − (1 − n·v/2)⁵)
    p(h) = √((n_u+1)(n_v+1))/(2π) (n·h)^{n_u cos²φ_h + n_v sin²φ_h},     p(l) = p(h) / (4 k·h)
"""

from __future__ import annotations

import math

import numpy as np

from .._validate import check_bool, check_nonnegative
from ..numerics import safe_div, saturate_to
from ..sampling.base import _TWO_PI, Sampler, Samples, _local_v
from ..vec import _dot, _one_minus_cos_between, normalize
from .base import BRDFFlags, SeparableBRDF, _color, _color_text
from .protocol import Lobe, Parameter, register_model

__all__ = ["AshikhminShirley", "AshikhminShirleySampler"]

_TINY64 = np.finfo(np.float64).tiny
_MAX64 = np.finfo(np.float64).max
#: 28/(23π): the diffuse term's constant (its directional albedo is then R_d (1 − R_s)(1 − (1 − n·v/2)⁵)).
_DIFFUSE_CONST = 28.0 / (23.0 * math.pi)


def _log_lobe(ht, hb, hn, nu: float, nv: float) -> np.ndarray:
    """``E log(n·h)`` with ``E = (n_u h_t² + n_v h_b²)/(h_t² + h_b²)`` (float64; −∞ where ``n·h <= 0``).

    ``E`` is a weighted mean of ``n_u`` and ``n_v`` formed from the tangential components of ``h``
    (never from ``1 − (n·h)²``, which cancels at the peak); ``h = n`` gives ``(n·h)^E = 1`` for
    every ``E``.  ``log(n·h)`` is ``log1p(−s²/(1 + n·h))`` near the peak (``n·h >= 1/2``,
    ``s² = h_t² + h_b² = (1 − n·h)(1 + n·h)``) and ``log(n·h)`` far from it, where it keeps the
    digits of a small ``n·h``.
    """
    ht2, hb2 = ht * ht, hb * hb
    s2 = ht2 + hb2
    with np.errstate(divide="ignore", over="ignore", under="ignore", invalid="ignore"):
        # inf only for exponents near the largest float, where s² > 0 makes the lobe 0 anyway.
        e = np.where(s2 > 0, (nu * ht2 + nv * hb2) / np.where(s2 > 0, s2, 1.0), 0.0)
        hn_pos = np.maximum(hn, 0.0)
        log_cos = np.where(hn >= 0.5, np.log1p(-s2 / (1.0 + hn_pos)), np.log(hn_pos))
        out = np.where(log_cos < 0, e * log_cos, 0.0)
    return np.where(hn > 0, out, -np.inf)


def _one_minus_half_power5(x: np.ndarray) -> np.ndarray:
    """``1 − (1 − x/2)⁵`` without cancellation at small ``x`` (``−expm1(5 log1p(−x/2))``)."""
    return -np.expm1(5.0 * np.log1p(-0.5 * np.clip(x, 0.0, 1.0)))


def _log_norm(nu: float, nv: float) -> float:
    """``log √((n_u+1)(n_v+1))``, without overflow for huge exponents."""
    return 0.5 * (math.log1p(nu) + math.log1p(nv))


class AshikhminShirley(SeparableBRDF):
    r"""The Ashikhmin–Shirley anisotropic Phong BRDF (2000): a coupled diffuse and specular pair.

    In the shading frame ``(t, b, n)`` (tangent, bitangent, normal), with ``k = v`` the viewer,
    ``h = (l + v)/|l + v|`` and Schlick's ``F(c) = R_s + (1 − R_s)(1 − c)⁵``:

        f_r = f_s + f_d
        f_s = √((n_u+1)(n_v+1)) / (8π) · (n·h)^E / ((h·k) max(n·l, n·v)) · F(k·h)
              E = (n_u (h·t)² + n_v (h·b)²) / (1 − (h·n)²)
        f_d = 28 R_d / (23π) · (1 − R_s) · (1 − (1 − n·l/2)⁵) · (1 − (1 − n·v/2)⁵)

    ``n_u`` is the Phong exponent along the tangent ``t``, ``n_v`` along ``b``: the highlight is
    narrower along the direction with the larger exponent.  ``n_u = n_v = e`` is isotropic,
    a normalized Blinn–Phong lobe ``(e+1)/(8π) (n·h)^e`` over ``(h·k) max(n·l, n·v)``.

    The model is reciprocal, and designed to conserve energy: the diffuse term's directional
    albedo is exactly ``R_d (1 − R_s)(1 − (1 − n·v/2)⁵)`` (the constant ``28/23`` makes
    ``∫ (1 − (1 − μ/2)⁵) μ dμ`` come out right), the part ``1 − R_s`` the specular layer passes
    down, and the ``max(n·l, n·v)`` denominator keeps the specular albedo below ``F``.

    Numerics: ``E log(n·h)`` is formed from the tangential components ``h·t``, ``h·b`` (never
    ``1 − (n·h)²``, which cancels at the peak; ``h = n`` gives ``(n·h)^E = 1`` for every ``E``),
    ``1 − (1 − x/2)⁵`` with ``expm1``/``log1p``, ``1 − k·h = (1 − l·v)/(2 (1 + k·h))``; all in
    float64, saturated at the dtype's largest value.  ``eval_cos`` multiplies by
    ``n·l / max(n·l, n·v) <= 1`` instead of dividing.

    Parameters
    ----------
    rd : float or RGB triple, >= 0
        Diffuse colour ``R_d`` (the diffuse albedo of the substrate).
    rs : float or RGB triple in [0, 1]
        Specular colour ``R_s``: the reflectance at normal incidence, Schlick's ``F0``.
    nu, nv : float >= 0
        Phong exponents along the tangent ``t`` and the bitangent ``b``.
    diffuse : bool
        Include the paper's coupled diffuse term ``f_d`` (default True); False gives the
        specular layer alone.

    Notes
    -----
    The tangent frame: ``eval(n, l, v, tangent=t)``; without ``tangent``, ``t = ẑ × n / |ẑ × n|``
    (``x̂`` at the poles), so in the local frame ``n = +z`` the exponent ``n_u`` runs along x.
    Not stackable (the stacked fast path carries no tangents).

    The importance sampler (:meth:`sampler`) draws half vectors from the paper's
    ``p(h) = √((n_u+1)(n_v+1))/(2π) (n·h)^{n_u cos²φ + n_v sin²φ}`` (exactly normalized) and
    reflects ``v`` about them; with the diffuse term it is a one-sample mixture with the
    cosine-weighted hemisphere, weighted per view by each term's rough albedo (see
    :meth:`sampler`).

    References
    ----------
    M. Ashikhmin and P. Shirley, "An anisotropic Phong BRDF model", Journal of Graphics Tools
    5(2), 25–32, 2000.

    Examples
    --------
    At normal incidence ``h = n``: ``f_s = (e+1)/(8π) R_s`` and ``f_d = 28/(23π) R_d (1 − R_s)(31/32)²``.

    >>> m = AshikhminShirley(rd=0.5, rs=0.04, nu=100, nv=100)
    >>> z = (0.0, 0.0, 1.0)
    >>> round(float(m.eval(z, z, z)[0]), 6)
    0.335307
    >>> round(101 / (8 * math.pi) * 0.04 + 28 / (23 * math.pi) * 0.5 * 0.96 * (31 / 32) ** 2, 6)
    0.335307
    """

    name = "ashikhmin-shirley"
    flags = BRDFFlags.SPECULAR | BRDFFlags.OWN_DIFFUSE  # the coupled diffuse term beside the specular lobe
    parameters = (
        Parameter("rd", "color", 0.5, slider=(0.0, 1.0), description="diffuse colour R_d"),
        Parameter("rs", "color", 0.05, high=1.0, slider=(0.0, 1.0),
                  description="specular colour R_s (reflectance at normal incidence, Schlick's F0)"),
        Parameter("nu", "float", 200.0, slider=(0.0, 1e4), log=True, description="Phong exponent along the tangent t"),
        Parameter("nv", "float", 20.0, slider=(0.0, 1e4), log=True,
                  description="Phong exponent along the bitangent b"),
        Parameter("diffuse", "bool", True, description="include the coupled diffuse term"),
    )  # fmt: skip

    def __init__(self, rd=0.5, rs=0.05, nu=200.0, nv=20.0, diffuse=True):
        self.rd = _color("rd", rd)
        self.rs = _color("rs", rs, hi=1.0)
        self.nu = check_nonnegative("nu", nu)
        self.nv = check_nonnegative("nv", nv)
        if self.nu != self.nv:
            self.flags = type(self).flags | BRDFFlags.ANISOTROPIC
        self.diffuse = check_bool("diffuse", diffuse)

    def _params(self):
        return {"rd": self.rd, "rs": self.rs, "nu": self.nu, "nv": self.nv, "diffuse": self.diffuse}

    # -- description ----------------------------------------------------------------------
    def lobe(self):
        """A ``"half"`` lobe: ``(n·h)^E ≈ exp(−E θ_h²/2)``, so the width is ``1/√(√(n_u n_v))`` (the geometric mean of
        the two axes' standard deviations; at most 1 rad), and the quadrature width ``1/√(max(n_u, n_v) + 1)`` resolves
        the narrower axis.  Along ``t`` and ``b`` (``E = n_u cos²φ + n_v sin²φ``): ``widths`` ``(1/√n_u, 1/√n_v)`` (each
        at most 1 rad). The quadrature stays round (equal ``quadrature_widths``): the ellipse's azimuths crowd toward
        the lobe's long axis and starve the coupled diffuse term, which shares the part (measured at ``n_u = 10⁴``,
        ``n_v = 1``, ``R_d = 0.5``: 4 % off with the ellipse, 2.7e-4 round), and one rule with and without the diffuse
        term keeps their difference exact.
        """
        g = math.sqrt(self.nu) * math.sqrt(self.nv)
        width = min(1.0 / math.sqrt(g), 1.0) if g > 0 else 1.0
        axes = tuple(min(1.0 / math.sqrt(e), 1.0) if e > 0 else 1.0 for e in (self.nu, self.nv))
        quad = 1.0 / math.sqrt(max(self.nu, self.nv) + 1.0)
        return Lobe("half", width, quadrature_width=quad, widths=axes, quadrature_widths=(quad, quad))

    def sampler(self):
        """:class:`AshikhminShirleySampler` ``(nu, nv)`` alone when the diffuse term is off or ``R_d = 0``; otherwise
        ``MixtureSampler([CosineSampler(), AshikhminShirleySampler])`` with per-view weights ``w_d = mean(R_d (1 − R_s))
        (1 − (1 − μ/2)⁵)`` (the diffuse term's exact albedo) and ``w_s = mean(R_s + (1 − R_s)(1 − μ)⁵)`` (Schlick at ``μ
        = n·v``, a rough bound on the specular albedo), the specular share clamped to [0.1, 0.9] so that neither term is
        starved.
        """
        spec = AshikhminShirleySampler(self.nu, self.nv)
        if not self.diffuse or not np.any(self.rd > 0):
            return spec
        from ..sampling.brdf import MixtureSampler  # the integrators import the models
        from .lambert import CosineSampler

        kd = float(np.mean(self.rd * (1.0 - self.rs)))
        rs = self.rs

        def weights(v):
            mu = np.clip(np.asarray(v, dtype=np.float64)[..., 2], 0.0, 1.0)
            wd = kd * _one_minus_half_power5(mu)
            ws = np.mean(rs + (1.0 - rs) * ((1.0 - mu)[..., None] ** 5), axis=-1)
            total = wd + ws
            share = np.clip(ws / np.where(total > 0, total, 1.0), 0.1, 0.9)
            return np.stack([1.0 - share, share], axis=-1)

        return MixtureSampler([CosineSampler(), spec], weights)

    def summary(self):
        """``"rd=0.5 rs=0.05 nu=200 nv=20"`` (``" specular only"`` appended without the diffuse term)."""
        text = f"rd={_color_text(self.rd)} rs={_color_text(self.rs)} nu={self.nu:g} nv={self.nv:g}"
        return text if self.diffuse else text + " specular only"

    @property
    def diffuse_albedo(self):
        """The diffuse term's albedo at normal incidence (:attr:`BRDF.diffuse_albedo`): ``(31/32) R_d (1 − R_s)``.

        ``ρ_d(v) = R_d (1 − R_s) (1 − (1 − n·v/2)⁵)`` (the 28/(23π) normalization makes the ``l``
        integral 1), at ``n·v = 1``; zeros without the diffuse term.  Not :attr:`lambertian`: the coupled
        term is not a constant.

        Returns
        -------
        numpy.ndarray, (3,)
        """
        if not self.diffuse:
            return np.zeros(3)
        return self.rd * (1.0 - self.rs) * (31.0 / 32.0)

    # -- evaluation -----------------------------------------------------------------------
    def _fields(self, g, cos: bool):
        """Float64 fields ``(S, w, D)``, 0 below the horizon, with ``f_r = S (R_s + (1 − R_s) w) + D c_d``.

        ``c_d = 28 R_d (1 − R_s)/(23π)`` is the diffuse colour constant.

        ``S`` is the specular lobe without its Fresnel factor (saturated at the float64 maximum),
        ``w = (1 − k·h)⁵``, ``D`` the diffuse shape (``None`` without the diffuse term); with
        ``cos=True`` each is multiplied by ``n·l`` (the specular one as ``n·l / max(n·l, n·v) <= 1``).
        """
        above = g.above
        ht, hb, hn = (np.asarray(x, dtype=np.float64) for x in g.h_tbn)  # h_local's columns, unstacked
        nl = g.n_dot_l.astype(np.float64)
        nvw = g.n_dot_v.astype(np.float64)
        vh = g.v_dot_h.astype(np.float64)
        log_lobe = _log_lobe(ht, hb, hn, self.nu, self.nv)
        m = np.maximum(nl, nvw)
        log_norm = _log_norm(self.nu, self.nv) - math.log(8.0 * math.pi)
        with np.errstate(divide="ignore", over="ignore", under="ignore", invalid="ignore"):
            lobe = np.exp(log_lobe)
            norm = math.sqrt(self.nu + 1.0) * math.sqrt(self.nv + 1.0) / (8.0 * math.pi)
            if cos:
                ratio = nl / np.where(above, m, 1.0)
                direct = norm * lobe * ratio / vh
                log_s = log_norm + log_lobe + np.log(ratio) - np.log(vh)
            else:
                direct = norm * lobe / (vh * m)
                log_s = log_norm + log_lobe - np.log(vh) - np.log(m)
            # Where the lobe is subnormal (or 0) but the denominator tiny, the logarithms keep the digits.
            s = np.where(lobe >= _TINY64, direct, np.exp(log_s))
            s = np.where(above, np.minimum(s, _MAX64), 0.0)  # saturated before F multiplies it
            # Schlick's (1 − k·h)⁵ with 1 − k·h = (1 − l·v) / (2 (1 + k·h)), accurate where l ≈ v.
            omc = _one_minus_cos_between(g.l.astype(np.float64), g.v.astype(np.float64)) / (2.0 * (1.0 + vh))
            w5 = np.clip(omc, 0.0, 1.0) ** 5
        d = None
        if self.diffuse:
            d = _one_minus_half_power5(nl) * _one_minus_half_power5(nvw)
            if cos:
                d = d * nl
            d = np.where(above, d, 0.0)
        return s, w5, d

    @property
    def _diffuse_color(self):
        return _DIFFUSE_CONST * self.rd * (1.0 - self.rs)

    def _rgb64(self, g, cos):
        s, w5, d = self._fields(g, cos)
        with np.errstate(over="ignore"):
            out = s[..., None] * (self.rs + (1.0 - self.rs) * w5[..., None])
            if d is not None:
                out = out + d[..., None] * self._diffuse_color
        return out

    def _f(self, g):
        return saturate_to(self._rgb64(g, cos=False), g.dtype)

    def _f_cos(self, g):
        return saturate_to(self._rgb64(g, cos=True), g.dtype)

    def separable_cos(self, g):
        """``(S, R_s)``, ``(S w, 1 − R_s)`` and, with the diffuse term, ``(D, 28 R_d (1 − R_s)/(23π))``: the specular
        lobe times ``n·l`` without its Fresnel factor, that times ``w = (1 − k·h)⁵``, and the diffuse shape times
        ``n·l``; scalar fields in the dtype of ``g`` (saturated).  Not on a stacked geometry: the model reads
        the tangent frame.
        """
        s, w5, d = self._fields(g, cos=True)
        dt = g.dtype
        with np.errstate(over="ignore"):
            terms = [(saturate_to(s, dt), self.rs), (saturate_to(s * w5, dt), 1.0 - self.rs)]
        if d is not None:
            terms.append((saturate_to(d, dt), self._diffuse_color))
        return terms


class AshikhminShirleySampler(Sampler):
    r"""The Ashikhmin–Shirley half-vector distribution, reflected about ``h`` (local frame, ``t = x̂``).

        φ_h = atan(√((n_u+1)/(n_v+1)) tan(π u₀/2))      (first quadrant; the others by symmetry)
        cos θ_h = (1 − u₁)^{1/(n_u cos²φ_h + n_v sin²φ_h + 1)}
        p(h) = √((n_u+1)(n_v+1))/(2π) (n·h)^{n_u cos²φ_h + n_v sin²φ_h}
        l = 2 (v·h) h − v,      p(l) = p(h) / (4 |v·h|)

    ``u₀`` picks the quadrant (``q = ⌊4 u₀⌋``) and is rescaled to ``r = 4 u₀ − q``; quadrants 1
    and 3 run backwards (``φ = π − φ(1 − r)``, ``2π − φ(1 − r)``) so the map is continuous.  The
    arctangent is taken as ``atan2(√(n_u+1) sin(πr/2), √(n_v+1) cos(πr/2))`` (no ``tan(π/2)``).
    ``p(h)`` integrates to exactly 1 over the hemisphere (``∫ dφ/(E(φ)+1) = 2π/√((n_u+1)(n_v+1))``).
    Directions below the horizon are produced (with their density): the integrators weight them 0.

    Parameters
    ----------
    nu, nv : float >= 0
        The exponents along ``x`` (the tangent) and ``y`` (the bitangent).

    Examples
    --------
    >>> s = AshikhminShirleySampler(10, 10).sample(np.array([0.3, 0.0]), np.array([0.0, 0.0, 1.0]))
    >>> (s.directions.round(12) + 0.0).tolist(), round(float(s.pdf) * 8 * math.pi, 12)  # h = n: p = 11/(8π)
    ([0.0, 0.0, 1.0], 11.0)
    """

    name = "ashikhmin-shirley"

    def __init__(self, nu: float, nv: float):
        self.nu = check_nonnegative("nu", nu)
        self.nv = check_nonnegative("nv", nv)

    def __repr__(self):
        return f"AshikhminShirleySampler(nu={self.nu!r}, nv={self.nv!r})"

    def _normal_pdf(self, h) -> np.ndarray:
        """``p(h)`` for unit ``h`` (0 for ``n·h <= 0``)."""
        log_p = _log_norm(self.nu, self.nv) - math.log(_TWO_PI) + _log_lobe(h[..., 0], h[..., 1], h[..., 2],
                                                                              self.nu, self.nv)  # fmt: skip
        with np.errstate(under="ignore", over="ignore"):
            return np.minimum(np.exp(log_p), _MAX64)

    def _sample_normals(self, u) -> np.ndarray:
        u0 = np.clip(u[..., 0], 0.0, 1.0)
        u1 = np.clip(u[..., 1], 0.0, 1.0)
        q = np.minimum(np.floor(4.0 * u0), 3.0)
        r = 4.0 * u0 - q
        back = (q == 1) | (q == 3)
        rr = np.where(back, 1.0 - r, r)
        a = 0.5 * math.pi * rr
        phi0 = np.arctan2(math.sqrt(self.nu + 1.0) * np.sin(a), math.sqrt(self.nv + 1.0) * np.cos(a))
        phi = np.select([q == 0, q == 1, q == 2], [phi0, math.pi - phi0, math.pi + phi0], _TWO_PI - phi0)
        c, s = np.cos(phi), np.sin(phi)
        e = self.nu * c * c + self.nv * s * s
        with np.errstate(divide="ignore"):
            omc = -np.expm1(np.log1p(-np.minimum(u1, 1.0)) / (e + 1.0))  # 1 − cos θ_h, accurately
        sin_t = np.sqrt(np.clip(omc * (2.0 - omc), 0.0, None))
        return np.stack([sin_t * c, sin_t * s, 1.0 - omc], axis=-1)

    def sample_normals(self, u) -> Samples:
        """Half vectors ``h`` with density ``p(h)`` (upper hemisphere).

        Parameters
        ----------
        u : array_like, shape (..., 2)
            Points of the unit square.

        Returns
        -------
        Samples
            Half vectors ``(..., 3)`` and ``p(h)`` ``(...)``.
        """
        from ..sampling.base import _check_size, _unit_square

        u = _unit_square("u", u)
        _check_size("u", u.shape[:-1])
        h = self._sample_normals(u)
        return Samples(h, self._normal_pdf(h))

    def _sample(self, u, v):
        u = np.asarray(u, dtype=np.float64)
        v = _local_v(v)
        h = self._sample_normals(u)
        shape = np.broadcast_shapes(h.shape[:-1], v.shape[:-1])
        h = np.broadcast_to(h, shape + (3,))
        vh = _dot(v, h)
        l = 2 * vh[..., None] * h - v  # noqa: E741
        return Samples(l, safe_div(self._normal_pdf(h), 4.0 * np.abs(vh)))

    def _pdf(self, l, v):  # noqa: E741
        l, v = np.asarray(l, dtype=np.float64), _local_v(v)  # noqa: E741
        s = l + v
        h = normalize(s)  # the zero vector where l = −v
        h = np.where(h[..., 2:3] < 0, -h, h)  # the sampled h lies in the upper hemisphere
        return np.where(_dot(s, s) > 0, safe_div(self._normal_pdf(h), 4.0 * np.abs(_dot(v, h))), 0.0)


register_model(AshikhminShirley)

r"""The report's own transcription of Cook–Torrance's ``f_r``, with its earlier forms as options.

``f_r = k_s D G F / (c (n·v)(n·l))``, ``c = 4`` (Walter et al. 2007) or ``π`` (Cook and
Torrance 1982), with the Beckmann (1963), GGX (Walter et al. 2007) or Blinn–Phong ``D``,
the V-cavity or Smith ``G`` and the Schlick or dielectric Fresnel ``F``.  The engine's
form: ``D`` in float64, the visibility ``G/((n·v)(n·l))`` formed directly, the dielectric
Fresnel written in ``√f0``.  Each ``legacy`` flag of :func:`cook_torrance_fr` puts one of
them back (see :mod:`lighting.validation.forms` for why these are transcriptions).

References
----------
P. Beckmann and A. Spizzichino, "The scattering of electromagnetic waves from rough
surfaces", 1963.
R. L. Cook and K. E. Torrance, "A reflectance model for computer graphics", 1982.
C. Schlick, "An inexpensive BRDF model for physically-based rendering", 1994.
B. Walter, S. R. Marschner, H. Li and K. E. Torrance, "Microfacet models for refraction
through rough surfaces", 2007.
"""

from __future__ import annotations

import math

import numpy as np

from .._numeric import saturate_to
from .forms import combine

_EXP_CUTOFF = 745.0  # exp(-745) is the last nonzero float64
_INV_SQRT_PI = 0.5641895835477563  # 1/√π, correctly rounded
_UNIT_RGB = np.eye(3)


def _erf(x):
    from scipy.special import erf

    return erf(x)


def _cos_sin2(cos_theta, sin2_theta):
    c = np.asarray(cos_theta, dtype=np.float64)
    return c, np.clip(np.asarray(sin2_theta, dtype=np.float64), 0.0, 1.0)


def _finish(x, dt):
    big = float(np.finfo(dt).max)
    x = np.nan_to_num(x, nan=0.0, posinf=big, neginf=0.0)
    return np.minimum(x, big).astype(dt)


# ============================================================================ D
def ndf(model, q, dtype):
    """``D(h)`` of ``model`` (1/sr) from ``n·h`` and ``sin²θ_h`` of ``q`` rounded to ``dtype``.

    Beckmann ``exp(−tan²θ_h/α²) / (π α² cos⁴θ_h)``, GGX ``α² / (π (sin²θ_h + α² cos²θ_h)²)``,
    Blinn–Phong ``(e+2)/(2π) (n·h)^e`` with ``e = 2/α² − 2``.

    Parameters
    ----------
    model : CookTorrance
    q : Geometry or Quantities
    dtype : type

    Returns
    -------
    ndarray
        In ``dtype``.
    """
    c, s2 = _cos_sin2(q.n_dot_h.astype(dtype, copy=False), q.sin2_h.astype(dtype, copy=False))
    a = model.roughness
    with np.errstate(divide="ignore", over="ignore", invalid="ignore", under="ignore"):
        if model.ndf == "blinn-phong":
            e = np.clip(2.0 / (a * a) - 2.0, 0.0, np.finfo(np.float64).max)
            e = float(e)
            cp = np.maximum(c, 0.0)
            one_minus = np.where(c > 0, s2 / (1.0 + cp), 1.0)
            p = np.exp(e * np.log1p(-np.minimum(one_minus, 1.0)))
            p = np.where(cp < 0.5, np.power(cp, e), p)
            p = np.where(one_minus < 1, p, np.where(e == 0, 1.0, 0.0))
            d = np.where(c > 0, (e + 2) / (2 * math.pi) * p, 0.0)
        elif model.ndf == "beckmann":
            ac = a * c
            x = np.where(ac > 0, s2 / (ac * ac), np.inf)
            xc = np.minimum(x, _EXP_CUTOFF)
            t = a * a * xc
            d = np.exp(-xc) * (1.0 + t) ** 2 / (math.pi * a * a)
            d = np.where((c > 0) & (x < _EXP_CUTOFF), d, 0.0)
        else:
            den = s2 + (a * c) ** 2
            d = np.where(den > 0, (a * a) / (math.pi * den * den), np.inf)
            d = np.where(c > 0, d, 0.0)
    return _finish(d, dtype)


# ============================================================================ G
def _smith_g1(model, cos_theta, sin2_theta, dt):
    c, s2 = _cos_sin2(cos_theta, sin2_theta)
    al = model.roughness
    s = np.sqrt(s2)
    if model.ndf == "ggx":
        cp = np.maximum(c, 0.0)
        with np.errstate(over="ignore", under="ignore"):
            den = cp + np.hypot(cp, al * s)
        with np.errstate(divide="ignore", invalid="ignore"):
            g = np.where(den > 0, 2 * cp / np.where(den > 0, den, 1.0), 0.0)
        return _finish(np.where(c > 0, g, 0.0), dt)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        a = np.where(al * s > 0, c / (al * s), np.inf)
    a = np.clip(a, 0.0, 1e8)
    sp = math.sqrt(math.pi)
    with np.errstate(under="ignore"):
        g = 2 * a * sp / (a * sp * (1 + _erf(a)) + np.exp(-a * a))
    return _finish(np.where(c > 0, np.minimum(g, 1.0), 0.0), dt)


def shadowing(model, q):
    """``G`` in [0, 1]: V-cavity ``min(1, 2 (n·h)(n·v)/(v·h), 2 (n·h)(n·l)/(v·h))`` or Smith ``G1(v) G1(l)``.

    Parameters
    ----------
    model : CookTorrance
    q : Geometry or Quantities

    Returns
    -------
    ndarray
        In the dtype of ``q``.
    """
    if model.geometry == "v-cavity":
        nh, nv, nl, vh = (np.asarray(x, dtype=np.float64) for x in (q.n_dot_h, q.n_dot_v, q.n_dot_l, q.v_dot_h))
        m = np.minimum(nv, nl)
        with np.errstate(divide="ignore", over="ignore", invalid="ignore", under="ignore"):
            g = np.where(vh > 0, 2 * nh * m / np.where(vh > 0, vh, 1.0), 0.0)
        g = np.where((nh > 0) & (nv > 0) & (nl > 0), np.clip(g, 0.0, 1.0), 0.0)
        return _finish(g, q.dtype)
    return _smith_g1(model, q.n_dot_v, q.sin2_v, q.dtype) * _smith_g1(model, q.n_dot_l, q.sin2_l, q.dtype)


def _smith_den(model, cos_theta, sin2_theta):
    """``d`` with ``G1 = 2 cos θ / d`` (float64); 1 where ``cos θ <= 0``."""
    al = float(model.roughness)
    c, s2 = _cos_sin2(cos_theta, sin2_theta)
    if model.ndf == "ggx":
        cp = np.maximum(c, 0.0)
        d = cp + np.hypot(cp, al * np.sqrt(s2))
        return np.where((c > 0) & (d > 0), d, 1.0)
    s = np.sqrt(s2)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore", under="ignore"):
        a = np.clip(np.where(al * s > 0, c / (al * s), np.inf), 0.0, 1e8)
        d = c * (1 + _erf(a)) + (al * _INV_SQRT_PI) * s * np.exp(-a * a)
    return np.where((c > 0) & (d > 0), d, 1.0)


def visibility(model, q):
    """``G / ((n·v)(n·l))`` in float64, formed directly.

    Smith: ``4 / (d_v d_l)`` with ``G1 = 2 cos θ / d``; V-cavity:
    ``min(1/((n·v)(n·l)), (2 n·h / v·h) / max(n·v, n·l))``.

    Parameters
    ----------
    model : CookTorrance
    q : Geometry or Quantities

    Returns
    -------
    ndarray
    """
    nv = q.n_dot_v.astype(np.float64)
    nl = q.n_dot_l.astype(np.float64)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        if model.geometry == "smith":
            s2v = q.sin2_v.astype(np.float64)
            s2l = q.sin2_l.astype(np.float64)
            dd = _smith_den(model, nv, s2v) * _smith_den(model, nl, s2l)
            return np.where((nv > 0) & (nl > 0), 4 / dd, 0.0)
        nh = q.n_dot_h.astype(np.float64)
        vh = q.v_dot_h.astype(np.float64)
        k = 2 * nh / np.where(vh > 0, vh, 1)
        return np.minimum(1 / (nv * nl), k / np.maximum(nv, nl))


# ============================================================================ F
def dielectric_from_f0(cos_theta_i, f0):
    """The dielectric Fresnel reflectance written in ``g = √f0`` (no rounded ``η``), float64.

    Parameters
    ----------
    cos_theta_i : ndarray
        In [0, 1].
    f0 : array_like
        Scalar or RGB.

    Returns
    -------
    ndarray
        With a trailing RGB axis when ``f0`` is a triple.
    """
    c = np.clip(np.asarray(cos_theta_i, dtype=np.float64), 0, 1)
    g = np.sqrt(np.clip(np.asarray(f0, dtype=np.float64), 0, 1))
    if g.ndim:
        c = c[..., None]
    p, m = 1 + g, 1 - g
    ct = np.sqrt(np.maximum(p * p - (1 - c) * (1 + c) * (m * m), 0))
    pc = p * p * c
    d_par = pc + m * ct
    d_perp = m * c + ct
    with np.errstate(divide="ignore", invalid="ignore"):
        r_par = np.where(d_par > 0, (pc - m * ct) / np.where(d_par > 0, d_par, 1), 1)
        r_perp = np.where(d_perp > 0, (m * c - ct) / np.where(d_perp > 0, d_perp, 1), 1)
    return 0.5 * (r_par * r_par + r_perp * r_perp)


# ============================================================================ f_r
def cook_torrance_fr(model, q, legacy=frozenset()):
    """Cook–Torrance ``f_r`` of ``model`` on ``q``, with the earlier forms named in ``legacy``.

    ``"d-dtype"``: ``D`` rounded to the dtype before the division; ``"visibility"``:
    ``D G / (c (n·v)(n·l))`` (``G`` and the cosines multiplied out); ``"dielectric"``:
    ``dielectric(v·h, η)`` with the rounded ``η = (1 + √f0)/(1 − √f0)``; ``"float32"``: all
    three, in float32.  An empty set is the engine's form.  A conductor ``F`` has no earlier form: it is
    :func:`~lighting.models.fresnel.conductor` at ``v·h`` in every case.

    Parameters
    ----------
    model : CookTorrance
    q : Geometry or Quantities
    legacy : set of str

    Returns
    -------
    ndarray, shape (..., 3)
        In the dtype of ``q``.
    """
    if model.geometry not in ("v-cavity", "smith") or getattr(model, "anisotropic", False):
        raise ValueError(
            f"the transcription covers the isotropic V-cavity and separable Smith forms; got geometry="
            f"{model.geometry!r}{', anisotropic' if getattr(model, 'anisotropic', False) else ''}"
        )
    wide = np.float32 if "float32" in legacy else np.float64
    d = ndf(model, q, q.dtype) if legacy & {"d-dtype", "float32"} else ndf(model, q, np.float64)
    c = 4.0 if model.denominator == "4" else math.pi
    if legacy & {"visibility", "float32"}:
        dg = d.astype(wide) * shadowing(model, q).astype(wide)
        dg = np.where(q.above, dg, 0)
        den = wide(c) * q.n_dot_v.astype(wide)
        den = den * q.n_dot_l.astype(wide)
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            sv = np.where(den > 0, dg / np.where(den > 0, den, 1), 0)
    else:
        with np.errstate(over="ignore", invalid="ignore"):
            dv = d.astype(np.float64) * visibility(model, q)
        sv = np.where(q.above & ~np.isnan(dv), dv, 0) / c
    sv = np.minimum(sv, np.finfo(wide).max).astype(np.float64)
    if model.fresnel == "none":
        terms = [(sv, model.ks)]
    else:
        vh = np.clip(q.v_dot_h.astype(wide), 0, 1)
        if model.fresnel == "schlick":
            m = ((1 - vh) ** 5).astype(np.float64)
            terms = [(sv, model.ks * model.f0), (sv * m, model.ks * (1.0 - model.f0))]
        else:
            if model.fresnel == "conductor":  # no earlier form: the engine's conductor F
                from ..fresnel import conductor

                f = conductor(vh, model.eta, model.k).astype(np.float64)
            elif legacy & {"dielectric", "float32"}:
                from ..fresnel import dielectric, eta_from_f0

                f = dielectric(vh, eta_from_f0(model.f0)).astype(q.dtype).astype(np.float64)
            else:
                f = dielectric_from_f0(vh, model.f0)
            terms = [(sv * f[..., i], model.ks * _UNIT_RGB[i]) for i in range(3)]
    return saturate_to(combine(terms, np.float64), q.dtype)

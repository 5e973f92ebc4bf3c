r"""The report's own transcriptions of the shading formulas, in their careful and earlier forms.

:mod:`lighting.validation.rearrangements` measures what each rearranged formula of the
engine bought by evaluating ``f_r`` with that one formula put back to its earlier (or
textbook) form.  The formulas are written out here as plain functions of the shading
quantities and the models' public parameters, so that the report depends on the
engine's public API only (model constructors and attributes, ``eval_cos``, the public
:class:`~lighting.models.brdf.Geometry` and its quantities, the public lights and Fresnel
functions, :mod:`lighting.vec`, :mod:`lighting._numeric`), never on how a model arranges
its private helpers.  Each transcription performs the operations of the form it names in
the same order and dtype, so a form that is also the engine's gives the engine's bits.

Quantities
----------
:class:`Quantities` is a geometry's quantities with some replaced: the rearrangements of
the geometry (the half vector from the plain sum ``l + v``, ``sin²θ_h = 1 − cos²θ_h``,
``1 − R_l·v`` from ``R_l·v``) are functions of a public :class:`Geometry` returning one.

Models
------
* Phong (Phong 1975): ``f_r = k_s (R_l·v)^e / (π n·l)``;
* Blinn–Phong (Blinn 1977): ``f_r = k_s (n·h)^e / (π n·l)``, normalized ``k_s (e+2)/(2π) (n·h)^e``;
* Cook–Torrance (Cook and Torrance 1982; Walter et al. 2007):
  ``f_r = k_s D G F / (c (n·v)(n·l))`` with the Beckmann, GGX or Blinn–Phong ``D``, the
  V-cavity or Smith ``G`` and the Schlick (1994) or dielectric Fresnel ``F``.

References
----------
B. T. Phong, "Illumination for computer generated pictures", 1975.
J. F. Blinn, "Models of light reflection for computer synthesized pictures", 1977.
R. L. Cook and K. E. Torrance, "A reflectance model for computer graphics", 1982.
C. Schlick, "An inexpensive BRDF model for physically-based rendering", 1994.
B. Walter, S. R. Marschner, H. Li and K. E. Torrance, "Microfacet models for refraction
through rough surfaces", 2007.
"""

from __future__ import annotations

import math

import numpy as np

from .._numeric import log1p, log_corrected, saturate_to
from ..vec import normalize

_EXP_CUTOFF = 745.0  # exp(-745) is the last nonzero float64
_INV_SQRT_PI = 0.5641895835477563  # 1/√π, correctly rounded
_F64_TINY = float(np.finfo(np.float64).tiny)
_F64_MAX = float(np.finfo(np.float64).max)


# ============================================================================ quantities
class Quantities:
    """The shading quantities of a geometry, some of them replaced by the report's own formulas.

    Parameters
    ----------
    g : Geometry
        The public :class:`~lighting.models.brdf.Geometry` whose other quantities are read.
    **replaced : ndarray
        The quantities given in their own form (``h``, ``n_dot_h``, ``sin2_h`` …).
    """

    def __init__(self, g, **replaced):
        self._g = g
        self.__dict__.update(replaced)

    def __getattr__(self, name):
        return getattr(self._g, name)


def _dot(a, b):
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]


def _cross2(a, b):
    """``|a × b|²``."""
    x = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    y = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    z = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return x * x + y * y + z * z


def plain_half_vector(g) -> Quantities:
    """The half vector from the plain sum ``l + v`` of the normalized vectors (no cancellation-free rows).

    ``h = (l + v)/|l + v|`` (the scaled normalization of :func:`lighting.vec.normalize` where
    ``|l + v|²`` is tiny), ``v·h = |l + v|/2``, ``sin²θ_h = |n × h|²``,
    ``1 − n·h = sin²θ_h / (1 + n·h)``.

    Parameters
    ----------
    g : Geometry

    Returns
    -------
    Quantities
        ``g`` with ``h``, ``n_dot_h``, ``v_dot_h``, ``sin2_h`` and ``one_minus_n_dot_h`` replaced.
    """
    s = g.l + g.v
    len2 = _dot(s, s)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        h = s * (1 / np.sqrt(len2))[..., None]
    tiny = len2 < np.finfo(g.dtype).tiny * 1e4
    if np.any(tiny):
        h = np.array(np.broadcast_to(h, s.shape))
        h[tiny] = normalize(s[tiny])
    n_dot_h = _dot(g.n, h)
    sin2_h = np.clip(_cross2(g.n, h), 0, 1)
    return Quantities(
        g, h=h, n_dot_h=n_dot_h, v_dot_h=0.5 * np.sqrt(len2), sin2_h=sin2_h,
        one_minus_n_dot_h=sin2_h / (1 + np.maximum(n_dot_h, 0)),
    )  # fmt: skip


def cos_squared_half_angle(g) -> Quantities:
    """The textbook ``sin²θ_h = 1 − cos²θ_h`` and ``1 − n·h`` formed directly.

    Parameters
    ----------
    g : Geometry

    Returns
    -------
    Quantities
        ``g`` with ``sin2_h`` and ``one_minus_n_dot_h`` replaced.
    """
    c = np.clip(g.n_dot_h, -1, 1)
    return Quantities(g, sin2_h=np.clip(1 - c * c, 0, 1), one_minus_n_dot_h=1 - np.minimum(g.n_dot_h, 1))


def textbook_r_dot_v(g) -> Quantities:
    """``1 − R_l·v`` with ``R_l·v = 2 (n·l)(n·v) − l·v``, as the slides compute it.

    Parameters
    ----------
    g : Geometry

    Returns
    -------
    Quantities
        ``g`` with ``one_minus_r_dot_v`` replaced.
    """
    return Quantities(g, one_minus_r_dot_v=np.clip(1 - g.r_dot_v, 0, 2))


def batch_normalize(a):
    """The earlier :func:`lighting.vec.normalize`: one path (fast or scaled) for the whole batch.

    Parameters
    ----------
    a : ndarray, shape (..., 3)

    Returns
    -------
    ndarray
        ``a / |a|`` in the dtype of ``a`` (0 for a zero vector).
    """
    fi = np.finfo(a.dtype)
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        len2 = a[..., 0] * a[..., 0] + a[..., 1] * a[..., 1] + a[..., 2] * a[..., 2]
    lo, hi = float(fi.tiny) * 1e4, float(fi.max) * 1e-4
    if np.all((len2 > lo) & (len2 < hi)):
        return a / np.sqrt(len2)[..., None]
    m = np.max(np.abs(a), axis=-1, keepdims=True)  # scaled by the largest component first
    with np.errstate(divide="ignore", invalid="ignore"):
        sc = np.where(m > 0, a / np.where(m > 0, m, 1), 0).astype(a.dtype, copy=False)
    len_s = np.sqrt(sc[..., 0] ** 2 + sc[..., 1] ** 2 + sc[..., 2] ** 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.where(len_s[..., None] > 0, sc / np.where(len_s > 0, len_s, 1)[..., None], 0)
    return out.astype(a.dtype, copy=False)


# ============================================================================ helpers
def exponent_in(dtype, exponent: float):
    """A lobe exponent ``e >= 0`` as a scalar of ``dtype``, clamped to the type's positive finite range.

    Parameters
    ----------
    dtype : type
    exponent : float

    Returns
    -------
    numpy scalar
        0 for ``e = 0``; otherwise ``e`` within [smallest subnormal, largest finite].
    """
    if exponent == 0:
        return dtype(0)
    info = np.finfo(dtype)
    return dtype(min(max(float(exponent), float(info.smallest_subnormal)), float(info.max)))


def cos_power(one_minus_cos, exponent: float):
    """``max(cos φ, 0)^e = exp(e log1p(−(1 − cos φ)))`` from ``1 − cos φ``, with ``0^0 = 1``.

    Parameters
    ----------
    one_minus_cos : ndarray
        ``1 − cos φ`` in [0, 2].
    exponent : float

    Returns
    -------
    ndarray
        In the dtype of ``one_minus_cos``.
    """
    d = one_minus_cos
    if exponent == 0:
        return np.ones_like(d)
    e = exponent_in(d.dtype.type, exponent)
    with np.errstate(divide="ignore", over="ignore", under="ignore", invalid="ignore"):
        out = np.exp(e * log1p(-np.minimum(d, 1)))
    return np.where(d < 1, out, 0).astype(d.dtype, copy=False)


def rgb(values, coeff):
    """Scalar field times RGB coefficient, formed in float64, saturated to the dtype of ``values``.

    Parameters
    ----------
    values : ndarray
    coeff : array_like, shape (3,)

    Returns
    -------
    ndarray, shape values.shape + (3,)
    """
    with np.errstate(over="ignore"):
        out = values[..., None] * np.asarray(coeff, dtype=np.float64)
    return saturate_to(out, values.dtype)


def combine(terms, dt):
    """``Σ_k s_k c_k`` of separable terms → ``(..., 3)`` in ``dt``, saturated.

    Parameters
    ----------
    terms : list of (ndarray, ndarray)
    dt : type

    Returns
    -------
    ndarray
    """
    big = np.finfo(dt).max
    with np.errstate(over="ignore"):
        out = sum(rgb(np.asarray(s, dtype=dt), c) for s, c in terms)
    return np.minimum(out, big)


def lobe_over_cos(q, lobe64, log_lobe64, coeff):
    """``coeff · lobe / (π n·l)`` divided in float64 (``exp(ln lobe − ln(π n·l))`` where the lobe is subnormal).

    Parameters
    ----------
    q : Geometry or Quantities
    lobe64, log_lobe64 : ndarray
        The lobe in float64 and its logarithm.
    coeff : array_like, shape (3,)

    Returns
    -------
    ndarray, shape (..., 3)
        In the dtype of ``q``.
    """
    nl = q.n_dot_l.astype(np.float64)
    den = math.pi * np.where(nl > 0, nl, 1.0)
    with np.errstate(divide="ignore", over="ignore", under="ignore", invalid="ignore"):
        r = np.where(lobe64 >= _F64_TINY, lobe64 / den, np.exp(log_lobe64 - np.log(den)))
    r = np.where(q.above, np.minimum(r, _F64_MAX), 0.0)
    return saturate_to(rgb(r, coeff), q.dtype)


# ============================================================================ Phong, Blinn–Phong
def phong_fr(model, q):
    """Phong's ``f_r = k_s (R_l·v)^e / (π n·l)``, the lobe from ``1 − R_l·v`` of ``q``.

    Parameters
    ----------
    model : Phong
    q : Geometry or Quantities

    Returns
    -------
    ndarray, shape (..., 3)
    """
    d = np.minimum(q.one_minus_r_dot_v.astype(np.float64), 1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        log_lobe = model.shininess * np.log1p(-d) if model.shininess else np.zeros_like(d)
    return lobe_over_cos(q, cos_power(d, model.shininess), log_lobe, model.ks)


def _exp_scaled(t, dt, scale):
    """``exp(t) · scale`` in place; the factor goes into the exponent where ``exp(t)`` alone is subnormal."""
    if scale == 1:
        return np.exp(t, out=t)
    log_scale = math.log(scale)
    info = np.finfo(dt)
    if log_scale > math.log(float(info.max)) - 1:
        t += dt(log_scale)
        t = np.exp(t, out=t)
        return np.minimum(t, info.max, out=t)
    low = t < dt(math.log(float(info.tiny)))
    low &= t > dt(math.log(float(info.smallest_subnormal)) - log_scale - 1)
    t_low = t[low] + dt(log_scale) if np.any(low) else None
    t = np.exp(t, out=t)
    t *= dt(scale)
    if t_low is not None:
        t[low] = np.exp(t_low)
    return t


def blinn_phong_lobe(model, q, dtype=None, scale: float = 1.0):
    """``scale · (n·h)^e`` (0 below the horizon): ``exp(e log(n·h))`` far from the peak, ``log1p(−(1 − n·h))`` near it.

    Parameters
    ----------
    model : BlinnPhong
    q : Geometry or Quantities
    dtype : type, optional
        Default: the dtype of ``q``.
    scale : float

    Returns
    -------
    ndarray
    """
    dt = dtype or q.dtype
    if model.shininess == 0:
        return saturate_to(np.where(q.above, scale, 0), dt)
    d = q.one_minus_n_dot_h.astype(dt, copy=False)
    c = q.n_dot_h.astype(dt, copy=False)
    shape = np.broadcast_shapes(np.shape(c), np.shape(d))
    c, d = np.atleast_1d(c), np.atleast_1d(d)
    # The two logarithms blended arithmetically in one log_corrected pass, as the engine does.
    farf = (c < 0.5).astype(dt)
    nearf = 1 - farf
    y = np.abs(c)
    y *= farf
    y0 = np.subtract(1, d)
    y0 *= nearf
    y += y0
    x = y - 1
    x *= farf
    nearf *= d
    x -= nearf
    with np.errstate(divide="ignore", over="ignore", under="ignore", invalid="ignore"):
        t = log_corrected(y, x)
        t *= exponent_in(dt, model.shininess)
        t = _exp_scaled(t, dt, scale)
    t *= q.above_mask
    return t.reshape(np.broadcast_shapes(shape, np.shape(q.above))).astype(dt, copy=False)


def blinn_phong_lobe_peak_form(model, q, dtype=None, scale: float = 1.0):
    """``scale · (n·h)^e`` from ``1 − n·h`` everywhere (:func:`cos_power`), the factor multiplied on.

    Parameters
    ----------
    model : BlinnPhong
    q : Geometry or Quantities
    dtype : type, optional
    scale : float

    Returns
    -------
    ndarray
    """
    dt = dtype or q.dtype
    lobe = cos_power(q.one_minus_n_dot_h.astype(dt), model.shininess)
    if scale != 1:
        with np.errstate(over="ignore", under="ignore"):
            lobe = saturate_to(lobe * scale, dt)
    return np.where(q.above, lobe, 0).astype(dt, copy=False)


def blinn_phong_fr(model, q, lobe=blinn_phong_lobe):
    """Blinn–Phong's ``f_r``: ``k_s lobe / (π n·l)`` divided in float64, or ``k_s (e+2)/(2π) lobe`` normalized.

    Parameters
    ----------
    model : BlinnPhong
    q : Geometry or Quantities
    lobe : callable
        :func:`blinn_phong_lobe` or :func:`blinn_phong_lobe_peak_form`.

    Returns
    -------
    ndarray, shape (..., 3)
    """
    e = model.shininess
    if not model.normalized:
        lobe64 = lobe(model, q, np.float64)
        if e == 0:
            return lobe_over_cos(q, lobe64, np.zeros_like(lobe64), model.ks)
        c = q.n_dot_h.astype(np.float64)
        d = np.minimum(q.one_minus_n_dot_h.astype(np.float64), 1.0)
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            log_lobe = e * np.where(c < 0.5, np.log(np.where(c > 0, c, 0)), np.log1p(-d))
        return lobe_over_cos(q, lobe64, log_lobe, model.ks)
    return rgb(lobe(model, q, scale=(e + 2) / (2 * math.pi)), model.ks)

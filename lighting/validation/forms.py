r"""The textbook and earlier forms that the stability study puts back into the engine, one at a time.

:mod:`lighting.validation.rearrangements` measures what each rearranged formula of the engine
bought by evaluating ``f_r`` with that one formula put back to its earlier (or textbook) form.
The careful forms are the engine's own, called: a model's ``eval_geometry``, ``eval_cos``, its
factors ``D``, ``G`` and ``F``, :class:`~lighting.models.geometry.Geometry`'s derived quantities,
:func:`lighting.vec.normalize`, :func:`lighting.models.base.cos_power` and
:mod:`lighting.fresnel`.  What this module writes out are the forms the engine does not
contain, as the textbooks write them; they are the subject of the study, not copies.

Geometry
--------
A textbook quantity replaces the engine's on a fresh :class:`Geometry` (:func:`with_quantities`),
and the engine derives every other quantity from it and evaluates the model on it:

* the half vector from the plain sum, ``h = (l + v)/|l + v|`` (Blinn 1977), :func:`plain_half_vector`;
* ``sin²θ_h = 1 − cos²θ_h`` and ``1 − n·h`` formed directly, :func:`cos_squared_half_angle`;
* ``R_l·v = 2 (n·l)(n·v) − l·v`` (Phong 1975, as the slides compute it), :func:`textbook_r_dot_v`;
* one normalization path for a whole batch, :func:`batch_normalize`.

Models
------
* Blinn–Phong's ``(n·h)^e = exp(e log1p(−(1 − n·h)))`` at every ``n·h``,
  :func:`blinn_phong_peak_form_fr`;
* Cook–Torrance's ``f_r = k_s D G F / (c (n·v)(n·l))`` (Cook and Torrance 1982; Walter et al.
  2007) with ``D`` rounded to the dtype, ``G`` and the cosines multiplied out, the dielectric
  Fresnel of a rounded ``η`` or everything in float32, :func:`cook_torrance_fr`.

References
----------
B. T. Phong, "Illumination for computer generated pictures", CACM 18(6), 1975.
J. F. Blinn, "Models of light reflection for computer synthesized pictures", SIGGRAPH 1977.
R. L. Cook and K. E. Torrance, "A reflectance model for computer graphics", ACM TOG 1(1), 1982.
C. Schlick, "An inexpensive BRDF model for physically-based rendering", CGF 13(3), 1994.
B. Walter, S. R. Marschner, H. Li and K. E. Torrance, "Microfacet models for refraction
through rough surfaces", EGSR 2007.
"""

from __future__ import annotations

import math

import numpy as np

from ..fresnel import dielectric, eta_from_f0
from ..models import Geometry
from ..models.base import cos_power
from ..numerics import _exponent_in, log1p, saturate_to
from ..vec import normalize


# ============================================================================ geometry
def with_quantities(g: Geometry, cls=Geometry, **quantities) -> Geometry:
    """A fresh geometry on the unit vectors of ``g`` with some of its derived quantities given.

    The engine derives every other quantity from the given ones when a model asks for it.

    Parameters
    ----------
    g : Geometry
        The engine's geometry; its unit vectors and dtype are taken.
    cls : type, optional
        A subclass of :class:`Geometry` to build.
    **quantities : ndarray
        Derived quantities by their public names (``h``, ``v_dot_h``, ``sin2_h`` …).

    Returns
    -------
    Geometry
    """
    q = cls(g.n, g.l, g.v, unit=True, dtype=g.dtype)
    for name, value in quantities.items():
        setattr(q, name, value)  # the cached quantities are plain instance attributes
    return q


def in_float64(g: Geometry) -> Geometry:
    """``g`` in float64: the same vectors and derived quantities, converted exactly.

    The engine evaluates Cook–Torrance's factors in float64 from the quantities of a float32
    geometry; on this one its float64 results are those of ``g``.

    Parameters
    ----------
    g : Geometry
        Usually float32.

    Returns
    -------
    Geometry
    """
    names = ("n_dot_l", "n_dot_v", "n_dot_h", "v_dot_h", "sin2_h", "sin2_v", "sin2_l")
    wide = Geometry(*(x.astype(np.float64) for x in (g.n, g.l, g.v)), unit=True, dtype=np.float64)
    for name in names:
        setattr(wide, name, getattr(g, name).astype(np.float64))
    return wide


def _dot(a, b):
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]


def plain_half_vector(g: Geometry) -> Geometry:
    """The half vector from the plain sum of the normalized vectors: ``h = (l + v)/|l + v|``, ``v·h = |l + v|/2``.

    ``h = (l + v) · (1/|l + v|)``; where ``|l + v|²`` is tiny, :func:`lighting.vec.normalize` of the sum.

    Parameters
    ----------
    g : Geometry
        The engine's geometry; its unit ``l`` and ``v`` are read.

    Returns
    -------
    Geometry
        ``g`` with ``h`` and ``v_dot_h`` given; ``n·h``, ``sin²θ_h`` and ``1 − n·h`` are the engine's
        from that ``h``.

    References
    ----------
    Blinn (1977): ``H = (L + E)/|L + E|``.
    """
    s = g.l + g.v
    len2 = _dot(s, s)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        h = s * (1 / np.sqrt(len2))[..., None]
    h = np.where((len2 < np.finfo(g.dtype).tiny * 1e4)[..., None], normalize(s), h)
    return with_quantities(g, h=h, v_dot_h=0.5 * np.sqrt(len2))


def cos_squared_half_angle(g: Geometry) -> Geometry:
    """The textbook ``sin²θ_h = 1 − cos²θ_h`` and ``1 − n·h`` formed directly.

    Parameters
    ----------
    g : Geometry
        The engine's geometry; its ``n·h`` is read.

    Returns
    -------
    Geometry
        ``g`` with ``sin2_h`` and ``one_minus_n_dot_h`` given.

    References
    ----------
    Cook and Torrance (1982), Beckmann's ``D`` in ``tan²θ_h = (1 − cos²θ_h)/cos²θ_h``.
    """
    c = np.clip(g.n_dot_h, -1, 1)
    return with_quantities(g, sin2_h=np.clip(1 - c * c, 0, 1), one_minus_n_dot_h=1 - np.minimum(g.n_dot_h, 1))


def textbook_r_dot_v(g: Geometry) -> Geometry:
    """``1 − R_l·v`` with ``R_l·v = 2 (n·l)(n·v) − l·v``, as the slides compute it.

    Parameters
    ----------
    g : Geometry
        The engine's geometry; its ``R_l·v`` is read.

    Returns
    -------
    Geometry
        ``g`` with ``one_minus_r_dot_v`` given.

    References
    ----------
    Phong (1975); the slides' ``R_l = 2 n (n·l) − l``.
    """
    return with_quantities(g, one_minus_r_dot_v=np.clip(1 - g.r_dot_v, 0, 2))


def batch_normalize(a):
    """The earlier normalization: the direct ``a/|a|`` for the whole batch, or the scaled form for all of it.

    The scaled form divides by the largest component first, ``s = a / max|a_i|``, then ``s/|s|``.

    Parameters
    ----------
    a : ndarray, shape (..., 3)

    Returns
    -------
    ndarray
        ``a / |a|`` in the dtype of ``a`` (0 for a zero vector).

    References
    ----------
    The engine's :func:`lighting.vec.normalize` before it chose the path per vector.
    """
    fi = np.finfo(a.dtype)
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        len2 = _dot(a, a)
    if np.all((len2 > float(fi.tiny) * 1e4) & (len2 < float(fi.max) * 1e-4)):
        return a / np.sqrt(len2)[..., None]
    m = np.max(np.abs(a), axis=-1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(m > 0, a / np.where(m > 0, m, 1), 0).astype(a.dtype, copy=False)
    return normalize(s)  # |s| >= 1 where s is not zero: the direct path, vector by vector


# ============================================================================ Blinn–Phong
class _PeakFormLobe(Geometry):
    """A geometry whose ``e · log(n·h)`` is ``e · log1p(−(1 − n·h))`` everywhere (no ``log(n·h)`` far from the peak)."""

    def log_n_dot_h_power(self, exponent: float, dtype):
        d = np.atleast_1d(self.one_minus_n_dot_h.astype(dtype, copy=False))
        with np.errstate(divide="ignore", over="ignore", under="ignore", invalid="ignore"):
            t = log1p(-np.minimum(d, 1)) * _exponent_in(dtype, exponent)
        return t, np.broadcast_shapes(np.shape(self.one_minus_n_dot_h), np.shape(self.above))


def blinn_phong_peak_form_fr(model, g: Geometry):
    """Blinn–Phong's ``f_r`` with ``(n·h)^e = exp(e log1p(−(1 − n·h)))`` at every ``n·h``.

    Normalized: ``k_s (e+2)/(2π) (n·h)^e`` (:func:`lighting.models.base.cos_power`); raw: the
    model's own ``f_r`` on a geometry that gives it that lobe.

    Parameters
    ----------
    model : BlinnPhong
    g : Geometry

    Returns
    -------
    ndarray, shape (..., 3)
        In the dtype of ``g``.

    References
    ----------
    Blinn (1977); the normalization ``(e+2)/(2π)`` as in Walter et al. (2007).
    """
    if not model.normalized:
        return model.eval_geometry(with_quantities(g, cls=_PeakFormLobe))
    dt = g.dtype
    with np.errstate(over="ignore", under="ignore"):
        lobe = cos_power(g.one_minus_n_dot_h.astype(dt), model.shininess)
        lobe = saturate_to(lobe * ((model.shininess + 2) / (2 * math.pi)), dt)
        lobe = np.where(g.above, lobe, 0).astype(dt, copy=False)
        return saturate_to(lobe[..., None] * np.asarray(model.ks, dtype=np.float64), dt)


# ============================================================================ Cook–Torrance
#: The earlier forms :func:`cook_torrance_fr` can put back.
COOK_TORRANCE_FORMS = ("d-dtype", "visibility", "dielectric", "float32")


def _careful_visibility(model, g64: Geometry):
    """The engine's ``G/((n·v)(n·l))`` formed directly (float64).

    The model keeps this factor private (``D``, ``G`` and ``F`` are public): the one place the
    study reaches into it.
    """
    return model._visibility(g64, True)


def cook_torrance_fr(model, g: Geometry, put_back=frozenset()):
    """Cook–Torrance's ``f_r = k_s D G F / (c (n·v)(n·l))`` with the earlier forms named in ``put_back``.

    ``"d-dtype"``: ``D`` rounded to the dtype before the division; ``"visibility"``:
    ``D G / (c (n·v)(n·l))`` with ``G`` and the cosines multiplied out; ``"dielectric"``:
    ``dielectric(v·h, η)`` with the rounded ``η = (1 + √f0)/(1 − √f0)``; ``"float32"``: all three,
    in float32.  The other factors are the model's: ``D`` in float64, the visibility formed
    directly, ``F`` in float64 (the conductor's ``F`` has no earlier form).  With nothing put
    back this is the model's ``f_r``.

    Parameters
    ----------
    model : CookTorrance
        Isotropic, with the V-cavity or separable Smith geometry.
    g : Geometry
    put_back : set of str
        Names from :data:`COOK_TORRANCE_FORMS`.

    Returns
    -------
    ndarray, shape (..., 3)
        In the dtype of ``g``.

    References
    ----------
    Cook and Torrance (1982); Walter et al. (2007), the denominator 4; Schlick (1994).
    """
    g64 = in_float64(g)
    wide = np.float32 if "float32" in put_back else np.float64
    d = model.D(g) if put_back & {"d-dtype", "float32"} else model.D(g64)
    c = 4.0 if model.denominator == "4" else math.pi
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        if put_back & {"visibility", "float32"}:
            dg = np.where(g.above, d.astype(wide) * model.G(g).astype(wide), 0)
            den = wide(c) * g.n_dot_v.astype(wide) * g.n_dot_l.astype(wide)
            s = np.where(den > 0, dg / np.where(den > 0, den, 1), 0)
        else:
            dv = d.astype(np.float64) * _careful_visibility(model, g64)
            s = np.where(g.above & ~np.isnan(dv), dv, 0) / c
        s = np.minimum(s, np.finfo(wide).max).astype(np.float64)
        ks = np.asarray(model.ks, dtype=np.float64)
        if model.fresnel == "none":
            fr = s[..., None] * ks
        elif model.fresnel == "schlick":  # F = f0 + (1 − f0)(1 − v·h)^5, one lobe per term
            m = ((1 - np.clip(g.v_dot_h.astype(wide), 0, 1)) ** 5).astype(np.float64)
            fr = s[..., None] * (ks * model.f0) + (s * m)[..., None] * (ks * (1.0 - model.f0))
        else:
            if model.fresnel == "dielectric" and put_back & {"dielectric", "float32"}:
                vh = np.clip(g.v_dot_h.astype(wide), 0, 1)
                f = dielectric(vh, eta_from_f0(model.f0)).astype(g.dtype).astype(np.float64)
            else:
                f = model.F(g64)
            fr = (s[..., None] * f) * ks
    return saturate_to(fr, g.dtype)


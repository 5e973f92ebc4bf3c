r"""Reflectance models: the BRDFs of the two lecture decks.

Every model is one small class with the slide's formula in its docstring and the
code that computes exactly it.  The radiometric contract (conventions.md):

* ``eval(n, l, v)`` returns the physical BRDF ``f_r`` in 1/sr per RGB channel,
  shape ``(..., 3)``, zero below the horizon (``n·l <= 0`` or ``n·v <= 0``).
* ``eval_cos(n, l, v)`` returns ``f_r (n·l)``, the integrand of the reflection
  and rendering equations.  It is computed directly (never as
  ``eval(...) * (n·l)``), so it stays exact where ``f_r`` itself divides by
  ``n·l`` (the slides' Phong BRDF) and blows up at grazing light.
* ``classic(n, l, v)`` returns the slides' illumination term,
  ``π f_r (n·l)`` — ``k_d (n·l)`` for Lambert, ``k_s (R_l·v)^e`` for Phong —
  so that ``I = I_a k_a + Σ_p I_p / A(d_p) · classic`` is the slides' equation.

Vectors need not be unit length: ``n``, ``l`` and ``v`` are normalized on entry
(a zero vector gives zero reflectance, never NaN).  Models broadcast over the
leading axes and keep the float dtype of their vector inputs.

Models add: ``Lambert(0.6) + Phong(0.3, 20)`` is a :class:`BRDFSum` whose
``parts`` are the slides' decomposition ``f_r = f_d + f_s``.
"""

from __future__ import annotations

import math

import numpy as np

from .._numeric import (
    ArgumentTypeError,
    _fmt,
    as_float,
    check_bool,
    check_budget,
    check_choice,
    check_color,
    check_nonnegative,
    check_positive,
    check_vectors,
    log1p,
    log_corrected,
    real_array,
    safe_div,
    saturate_to,
    working_dtype,
)
from ..vec import normalize
from . import fresnel as _fresnel
from . import microfacet as _mf
from .protocol import Lobe, Parameter, register_model

__all__ = [
    "Geometry",
    "StackedGeometry",
    "BRDF",
    "Lambert",
    "Phong",
    "BlinnPhong",
    "CookTorrance",
    "BRDFSum",
    "cos_power",
]


class _cached:
    """``functools.cached_property`` without its lock.

    Python 3.11's ``cached_property`` holds one lock per property *for all
    instances* while computing, so two threads shading two halves of an image
    took turns on every derived quantity (measured: two halves in parallel 10.1
    ms against 5.4 ms for one).  Each :class:`Geometry` is used by one thread, so
    no lock is needed: the value is computed and stored in the instance dict,
    which shadows this non-data descriptor from then on.
    """

    def __init__(self, fn):
        self.fn = fn
        self.name = fn.__name__
        self.__doc__ = fn.__doc__

    def __set_name__(self, owner, name):
        self.name = name

    def __get__(self, obj, cls=None):
        if obj is None:
            return self
        value = self.fn(obj)
        obj.__dict__[self.name] = value
        return value


def _exponent_in(dtype, exponent: float):
    """A lobe exponent ``e >= 0`` as a scalar of ``dtype``, kept inside the type's positive range.

    Rounding ``e`` to float32 would turn ``e = 1e-300`` into 0, so ``0^e`` (a half vector on
    the horizon, ``l = −v``) became ``0^0``: ``exp(0 · log 0) = exp(0 · −∞)`` is NaN.  And
    ``e = 1e39`` would become ``inf``, which makes ``1^e`` NaN the same way.  So a positive
    ``e`` is rounded up to the smallest subnormal and down to the largest finite number of
    the type.  Neither changes a single lobe value: ``x^e`` for every ``x`` in ``(0, 1]`` of
    the type rounds to 1 for all ``e`` below the first (``|e log x| < 1e-42``), and to 0 or
    exactly 1 for all ``e`` above the second (``log x <= −6e-8`` for ``x < 1``).

    >>> [float(_exponent_in(np.float32, e)) for e in (0.0, 1e-300, 1e300)]
    [0.0, 1.401298464324817e-45, 3.4028234663852886e+38]
    """
    if exponent == 0:
        return dtype(0)
    info = np.finfo(dtype)
    return dtype(min(max(float(exponent), float(info.smallest_subnormal)), float(info.max)))


def cos_power(one_minus_cos: np.ndarray, exponent: float) -> np.ndarray:
    """``max(cos φ, 0)^e`` from ``1 − cos φ`` (given accurately), with ``0^0 = 1``.

    Written as ``exp(e · log1p(−(1 − cos φ)))``: for a shininess of 1e6 the
    lobe lives where ``1 − cos φ ~ 1e-6``, and forming ``cos φ`` first would
    throw away the digits that the millionth power then amplifies.  Any
    exponent from 0 to the largest float works in either dtype (:func:`_exponent_in`).
    A building block of the shading path: it does not check its arguments
    (``one_minus_cos`` an array in [0, 2], ``exponent`` a finite number >= 0).
    """
    d = one_minus_cos
    if exponent == 0:
        return np.ones_like(d)
    e = _exponent_in(d.dtype.type, exponent)
    # e · log(...) may overflow to −∞ (e near the type's largest value): exp gives the 0 it should.
    with np.errstate(divide="ignore", over="ignore", under="ignore", invalid="ignore"):
        out = np.exp(e * log1p(-np.minimum(d, 1)))
    return np.where(d < 1, out, 0).astype(d.dtype, copy=False)


class Geometry:
    """The slides' shading directions at a set of points, each derived quantity on demand.

    ``n``, ``l``, ``v`` are normalized on construction (pass ``unit=True`` when
    they already are).  Derived quantities (``n_dot_l``, ``h``, ``r_dot_v`` …)
    are computed the first time a model asks for them and cached, so a model
    that never needs the half vector never pays for it.

    This is the shading path's object and does not check its arguments (finite
    ``(..., 3)`` arrays that broadcast); the public ``eval``/``eval_cos``/``classic``
    check them once and build it.
    """

    def __init__(self, n, l, v, *, unit: bool = False, dtype=None):  # noqa: E741
        dt = dtype or working_dtype(n, l, v)
        n, l, v = (as_float(x, dt) for x in (n, l, v))
        if not unit:
            n, l, v = normalize(n), normalize(l), normalize(v)
        self.dtype = dt
        self.n, self.l, self.v = n, l, v

    @staticmethod
    def _dot(a, b):
        return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]

    @staticmethod
    def _cross2(a, b):
        """``|a × b|²``."""
        x = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
        y = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
        z = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
        return x * x + y * y + z * z

    @_cached
    def n_dot_l(self):
        return self._dot(self.n, self.l)

    @_cached
    def n_dot_v(self):
        return self._dot(self.n, self.v)

    @_cached
    def above(self):
        """Both directions strictly above the surface: where any BRDF may be nonzero."""
        return (self.n_dot_l > 0) & (self.n_dot_v > 0)

    @_cached
    def above_mask(self):
        """:attr:`above` as 0/1 in the dtype: multiplying by it is a plain float pass."""
        return self.above.astype(self.dtype)

    @_cached
    def _l_plus_v(self):
        """``l + v`` and ``|l + v|²`` (in [0, 4] for unit ``l``, ``v``).

        Where ``l·v < −1/2`` the sum cancels, and the few-ulp rounding in the lengths of
        the normalized ``l`` and ``v`` would turn ``h`` by up to ``u·tan ψ`` (``2ψ`` the
        angle between them) — e.g. light and viewer grazing from opposite sides, where
        the highlight lives.  Those rows are rebuilt from the tangential parts
        (:func:`_unit_sum`), which depends on the directions only.
        """
        s = self.l + self.v
        len2 = self._dot(s, s)
        far = len2 < 1
        if np.any(far):
            s = _unit_sum(self.l, self.v, s, far)
            len2 = self._dot(s, s)
        return s, len2

    @_cached
    def h(self):
        s, len2 = self._l_plus_v
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            h = s * (1 / np.sqrt(len2))[..., None]
        tiny = len2 < np.finfo(self.dtype).tiny * 1e4
        if np.any(tiny):
            # Near l = −v the scaled normalization keeps the digits; only those rows take it,
            # so a row's h does not depend on what else is in the batch.
            h = np.array(np.broadcast_to(h, s.shape))
            h[tiny] = normalize(s[tiny])
        return h

    @_cached
    def n_dot_h(self):
        return self._dot(self.n, self.h)

    @_cached
    def v_dot_h(self):
        """``v·h = l·h = |l + v| / 2`` for unit ``l``, ``v``: symmetric in ``l`` and ``v`` to the last bit."""
        return 0.5 * np.sqrt(self._l_plus_v[1])

    @_cached
    def sin2_h(self):
        """``sin²θ_h = |n × h|²``: exact at the lobe peak, unlike ``1 − (n·h)²``."""
        return np.clip(self._cross2(self.n, self.h), 0, 1)

    @_cached
    def one_minus_n_dot_h(self):
        """``1 − n·h = sin²θ_h / (1 + n·h)`` without cancellation."""
        return self.sin2_h / (1 + np.maximum(self.n_dot_h, 0))

    @_cached
    def sin2_v(self):
        """``sin²θ_v = |n × v|²``."""
        return np.clip(self._cross2(self.n, self.v), 0, 1)

    @_cached
    def sin2_l(self):
        """``sin²θ_l = |n × l|²``."""
        return np.clip(self._cross2(self.n, self.l), 0, 1)

    @_cached
    def r_dot_v(self):
        """``R_l·v = 2 (n·l)(n·v) − l·v`` (equal to ``R_v·l``)."""
        return 2 * self.n_dot_l * self.n_dot_v - self._dot(self.l, self.v)

    @_cached
    def one_minus_r_dot_v(self):
        """``1 − R_l·v = |R_l − v|² / 2`` (accurate near the mirror direction)."""
        r = 2 * self.n * self.n_dot_l[..., None] - self.l
        d = r - self.v
        return np.clip(0.5 * self._dot(d, d), 0, 2)


def _unit_sum(l: np.ndarray, v: np.ndarray, s: np.ndarray, rows: np.ndarray) -> np.ndarray:  # noqa: E741
    """``s = l + v`` with the ``rows`` recomputed as ``l/|l| + v/|v|`` without cancellation.

    ``l`` and ``v`` are unit vectors up to rounding.  A component with ``l_i v_i < 0`` is
    rewritten with ``a + b = (a² − b²)/(a − b)``::

        l_i/|l| + v_i/|v| = (l_i²|v|² − v_i²|l|²) / (|l||v| (l_i|v| − v_i|l|)),
        l_i²|v|² − v_i²|l|² = Σ_{j≠i} (l_i v_j − v_i l_j)(l_i v_j + v_i l_j),

    in which the ``l_i² v_i²`` terms have cancelled exactly: the result depends on the
    directions of ``l`` and ``v`` alone (their lengths only divide, where nothing
    cancels), so it is as accurate as the direction components themselves.
    """
    shape = np.broadcast_shapes(l.shape, v.shape)
    s = np.array(np.broadcast_to(s, shape))
    rows = np.broadcast_to(rows, shape[:-1])
    L = np.broadcast_to(l, shape)[rows]
    V = np.broadcast_to(v, shape)[rows]
    nl = np.sqrt(L[:, 0] * L[:, 0] + L[:, 1] * L[:, 1] + L[:, 2] * L[:, 2])
    nv = np.sqrt(V[:, 0] * V[:, 0] + V[:, 1] * V[:, 1] + V[:, 2] * V[:, 2])
    out = L + V
    for i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        li, vi = L[:, i], V[:, i]
        num = (li * V[:, j] - vi * L[:, j]) * (li * V[:, j] + vi * L[:, j]) + (li * V[:, k] - vi * L[:, k]) * (
            li * V[:, k] + vi * L[:, k]
        )
        den = nl * nv * (li * nv - vi * nl)
        opposite = li * vi < 0  # then li·nv and −vi·nl have one sign: den is never 0
        with np.errstate(divide="ignore", invalid="ignore"):
            out[:, i] = np.where(opposite, num / np.where(opposite, den, 1), out[:, i])
    s[rows] = out
    return s


def _dot_planes(a, b):
    """``a·b`` of vectors given as three component planes (broadcasting: ``(K, 1)`` with ``(N,)`` → ``(K, N)``)."""
    out = a[0] * b[0]
    out += a[1] * b[1]
    out += a[2] * b[2]
    return out


def _cross_planes(a, b):
    """``a × b`` of vectors given as component planes, as three planes (broadcasting like :func:`_dot_planes`)."""
    return [a[j] * b[k] - a[k] * b[j] for j, k in ((1, 2), (2, 0), (0, 1))]


def _cross2_planes(a, b):
    """``|a × b|²`` of vectors given as component planes, in the order of :meth:`Geometry._cross2`."""
    q = a[1] * b[2]
    q -= a[2] * b[1]
    q *= q
    t = a[2] * b[0]
    t -= a[0] * b[2]
    t *= t
    q += t
    np.multiply(a[0], b[1], out=t)
    t -= a[1] * b[0]
    t *= t
    q += t
    return q


class StackedGeometry:
    """:class:`Geometry` of ``K`` distant lights over ``N`` points at once, as ``(K, N)`` planes.

    A directional light has one direction ``l`` for every point, so the vectors
    are kept as component planes — ``(N,)`` per point, ``(K, 1)`` per light — and
    every quantity below is a ``(K, N)`` array (or broadcastable to it) formed in
    whole-array passes for all lights at once.  The models consume it unchanged:
    the same property names and the same accurate formulations as
    :class:`Geometry`:

    * ``s = l + v`` per point, rebuilt from the tangential parts by
      :func:`_unit_sum` where ``|s|² < 1`` (light and viewer nearly opposite);
    * ``h = s / |s|``, ``n·h``, ``sin²θ_h = |n × h|²`` (exact at the lobe peak),
      ``1 − n·h = sin²θ_h / (1 + n·h)`` and ``v·h = |s| / 2`` — formed from the
      unit ``h`` as :class:`Geometry` forms them, so that ``(n·h)² + sin²θ_h = 1``
      to rounding (the GGX NDF at α = 1 depends on exactly that);
    * ``1 − R_l·v = |2 n (n·l) − l − v|² / 2``, ``sin²θ_v = |n × v|²``,
      ``sin²θ_l = |n × l|²``.

    Parameters
    ----------
    n : (N, 3) unit normals
    l : (K, 3) unit light directions
    v : (N, 3) unit view vectors, or one (3,) direction toward a distant viewer
    dtype : float32 or float64
    view_cache : dict, optional
        Keeps the quantities of ``n`` and ``v`` alone (``n·v``, ``|n × v|²``) for
        the next geometry over the same ``n`` and ``v`` (a renderer whose lights
        move).

    Examples
    --------
    >>> n = np.array([[0, 0, 1.0], [0, 0.6, 0.8]])
    >>> g = StackedGeometry(n, np.array([[0, 0, 1.0], [0.6, 0, 0.8]]), np.array([0, 0, 1.0]))
    >>> g.n_dot_l.round(6).tolist()
    [[1.0, 0.8], [0.8, 0.64]]
    >>> bool(np.allclose(g.n_dot_h[1], Geometry(n, [0.6, 0, 0.8], [0, 0, 1.0]).n_dot_h))  # light 1
    True
    """

    def __init__(self, n, l, v, *, dtype=None, view_cache=None):  # noqa: E741
        dt = dtype or working_dtype(n, l, v)
        self.dtype = dt
        self.n = as_float(n, dt)
        self.l = as_float(l, dt)
        self.v = as_float(v, dt)
        self._distant = self.v.ndim == 1
        self._view = {} if view_cache is None else view_cache

    def _per_view(self, key, make):
        if key not in self._view:
            self._view[key] = make()
        return self._view[key]

    @_cached
    def _n_planes(self):
        return self._per_view("n planes", lambda: [self.n[:, k] for k in range(3)])

    @_cached
    def _v_planes(self):
        if self._distant:
            return [self.v[k] for k in range(3)]
        return self._per_view("v planes", lambda: [self.v[:, k] for k in range(3)])

    @_cached
    def _l_planes(self):
        return [self.l[:, k, None] for k in range(3)]

    # Dot products over the component axis of stacked (3, ...) arrays are one einsum call each:
    # the same products added in the same order as three planes (bitwise equal), without the
    # temporaries (measured 0.13 against 0.18 ms for 3 × 77,500 float32 values).
    @_cached
    def _n3(self):
        return self._per_view("n rows", lambda: np.ascontiguousarray(self.n.T))

    @_cached
    def _v3(self):
        return self._per_view("v rows", lambda: np.ascontiguousarray(self.v.T))

    @_cached
    def n_dot_l(self):
        return np.einsum("kc,cn->kn", np.ascontiguousarray(self.l), self._n3)

    @_cached
    def n_dot_v(self):
        return self._per_view("n_dot_v", lambda: _dot_planes(self._n_planes, self._v_planes))

    @_cached
    def above(self):
        facing = self._per_view("facing", lambda: self.n_dot_v > 0)
        above = self.n_dot_l > 0
        above &= facing
        return above

    @_cached
    def above_mask(self):
        """:attr:`above` as 0/1 in the dtype: multiplying by it is a plain float pass."""
        return self.above.astype(self.dtype)

    @_cached
    def _sum(self):
        """``s = l + v`` as three ``(K, N)`` planes (``(K, 1)`` for a distant viewer) and ``|s|²``.

        Where ``|s|² < 1`` (``l·v < −1/2``) the sum cancels and those rows are rebuilt
        from the tangential parts by :func:`_unit_sum`, exactly as :class:`Geometry`
        does.
        """
        if self._distant:
            s = [lk + vk for lk, vk in zip(self._l_planes, self._v_planes, strict=True)]
            len2 = _dot_planes(s, s)
        else:
            s = self.l.T[:, :, None] + self._v3[:, None, :]  # (3, K, N): s[c] is a plane
            len2 = np.einsum("ckn,ckn->kn", s, s)
        far = len2 < 1
        if np.any(far):
            k, i = np.nonzero(far)
            L = self.l[k]
            V = np.broadcast_to(self.v, (len(k), 3)) if self._distant else self.v[i]
            fixed = _unit_sum(L, V, L + V, np.ones(len(k), dtype=bool))
            for c in range(3):
                s[c][k, i] = fixed[:, c]
            len2[k, i] = Geometry._dot(fixed, fixed)
        return s, len2

    @_cached
    def _h(self):
        """Unit half vector planes ``s / |s|`` (zero where ``l = −v``; tiny sums normalized with scaling)."""
        s, len2 = self._sum
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            inv = 1 / np.sqrt(len2)
            h = [sk * inv for sk in s] if self._distant else s * inv
        tiny = len2 < np.finfo(self.dtype).tiny * 1e4
        if np.any(tiny):
            k, i = np.nonzero(tiny)
            hk = normalize(np.stack([sk[k, i] for sk in s], axis=-1))
            for c in range(3):
                h[c][k, i] = hk[:, c]
        return h

    @_cached
    def _len2(self):
        return self._sum[1]

    @_cached
    def n_dot_h(self):
        if self._distant:
            return _dot_planes(self._n_planes, self._h)
        return np.einsum("cn,ckn->kn", self._n3, self._h)

    @_cached
    def v_dot_h(self):
        """``|l + v| / 2``, as in :class:`Geometry`."""
        return np.sqrt(self._len2) * self.dtype(0.5)

    @_cached
    def sin2_h(self):
        """``|n × h|²`` from the unit half vector, as :class:`Geometry` forms it."""
        q = _cross2_planes(self._n_planes, self._h)
        return np.clip(q, 0, 1, out=q)

    @_cached
    def one_minus_n_dot_h(self):
        den = np.maximum(self.n_dot_h, 0)
        den += self.dtype(1)
        return np.divide(self.sin2_h, den, out=den)

    # -- tan²θ_h from cross products, without forming h ----------------------------------------
    @_cached
    def _n_cross_v(self):
        """``n × v`` as three planes, kept per view (it depends on the normals and the viewer alone)."""
        return self._per_view("n x v", lambda: _cross_planes(self._n3, self.v if self._distant else self._v3))

    @_cached
    def _tangent_form(self):
        """``(tan²θ_h, delicate)``: see :attr:`tan2_h` and :attr:`delicate`."""
        dt = self.dtype
        tangential = None  # |n × s|² = |n × l + n × v|², s = l + v
        for d, d_view in zip(_cross_planes(self._n3, self._l_planes), self._n_cross_v, strict=True):
            d += d_view
            d *= d
            tangential = d if tangential is None else tangential.__iadd__(d)
        normal2 = self.n_dot_l + self.n_dot_v  # n·s: a sum of positives wherever the lobe is lit
        normal2 *= normal2
        # Unlit entries get (n·s)² + 1: finite quotients there, and >= 1 in both tests below.
        normal2 += 1 - self.above_mask
        # Lit entries where this form is not to be trusted: l·v < −1/2 (|s|² < 1, where l + v
        # cancels and Geometry rebuilds s with _unit_sum), and n·s so small that tan²θ_h
        # would overflow (h within ~1e-15 rad of the horizon in float32).
        delicate = tangential + normal2 < 1
        delicate |= normal2 < np.finfo(dt).tiny * dt(1e9)
        with np.errstate(over="ignore"):  # at delicate entries only, which are not read
            np.divide(tangential, normal2, out=tangential)
        return tangential, (np.nonzero(delicate) if np.any(delicate) else None)

    @property
    def tan2_h(self):
        r"""``tan²θ_h = |n × s|² / (n·s)²`` with ``s = l + v``, formed without the half vector.

        ``(n·h)^e = (1 + tan²θ_h)^{−e/2}`` then needs neither ``h`` nor ``n·h``:
        ``n × s = n × l + n × v`` (``n × v`` kept per view) carries ``sin θ_h``
        near the peak as accurately as ``n × h`` does, ``n·s = n·l + n·v`` (a sum
        of positives wherever the lobe is lit) carries ``n·h`` far from it, and
        the quotient does not depend on the lengths of ``n`` or ``s``.  Finite
        everywhere; meaningful where :attr:`above`, except at the
        :attr:`delicate` entries.
        """
        return self._tangent_form[0]

    @property
    def delicate(self):
        """``(k, i)`` index arrays of lit entries :attr:`tan2_h` does not serve (None if there are none).

        Models evaluate these on :meth:`entries`, a :class:`Geometry` of just
        those pairs: light and viewer more than 120° apart (``|l + v| < 1``) or
        a half vector within about ``1e-15`` rad of the horizon.
        """
        return self._tangent_form[1]

    def entries(self, k, i) -> Geometry:
        """A :class:`Geometry` of the pairs (light ``k[j]``, point ``i[j]``)."""
        v = self.v if self._distant else self.v[i]
        return Geometry(self.n[i], self.l[k], v, unit=True, dtype=self.dtype)

    @_cached
    def sin2_v(self):
        return self._per_view("sin2_v", lambda: np.clip(_cross2_planes(self._n_planes, self._v_planes), 0, 1))

    @_cached
    def sin2_l(self):
        return np.clip(_cross2_planes(self._n_planes, self._l_planes), 0, 1)

    @_cached
    def r_dot_v(self):
        return 2 * self.n_dot_l * self.n_dot_v - _dot_planes(self._l_planes, self._v_planes)

    @_cached
    def one_minus_r_dot_v(self):
        two_nl = 2 * self.n_dot_l
        q = None
        for nk, lk, vk in zip(self._n_planes, self._l_planes, self._v_planes, strict=True):
            d = two_nl * nk
            d -= lk
            d -= vk
            d *= d
            q = d if q is None else q.__iadd__(d)
        q *= self.dtype(0.5)
        return np.clip(q, 0, 2, out=q)


def _lobe_over_cos(g, lobe64: np.ndarray, log_lobe64: np.ndarray, coeff: np.ndarray) -> np.ndarray:
    """``coeff · lobe / (π n·l)`` in the dtype of ``g``, from a float64 lobe and its logarithm.

    Dividing in float64 keeps a lobe that is subnormal in float32 (1e-42) from losing
    its digits before the division by a grazing ``n·l`` (1e-4) brings it back into range;
    where the lobe is subnormal even in float64 the quotient is ``exp(ln lobe − ln(π n·l))``.
    """
    nl = g.n_dot_l.astype(np.float64)
    den = math.pi * np.where(nl > 0, nl, 1.0)
    with np.errstate(divide="ignore", over="ignore", under="ignore", invalid="ignore"):
        q = np.where(lobe64 >= np.finfo(np.float64).tiny, lobe64 / den, np.exp(log_lobe64 - np.log(den)))
    # Saturated before the colour multiplies it: an overflowed quotient times a zero channel would be NaN.
    q = np.where(g.above, np.minimum(q, np.finfo(np.float64).max), 0.0)
    return saturate_to(_rgb(q, coeff), g.dtype)


def _rgb(values: np.ndarray, coeff: np.ndarray) -> np.ndarray:
    """Scalar field ``(...)`` times RGB coefficient ``(3,)`` → ``(..., 3)``, in the dtype of ``values``.

    The product is formed in float64 (a coefficient of 1e300 has no float32 value) and
    saturates at the dtype's largest finite number.
    """
    with np.errstate(over="ignore"):
        out = values[..., None] * np.asarray(coeff, dtype=np.float64)
    return saturate_to(out, values.dtype)


_UNIT_RGB = np.eye(3)


def _saturating_sum(terms, dt) -> np.ndarray:
    """``Σ terms`` (non-negative, finite) saturated at the dtype's largest finite value, without a warning."""
    with np.errstate(over="ignore"):
        out = sum(terms)
    return np.minimum(out, np.finfo(dt).max).astype(dt, copy=False)


def _combine(terms, dt) -> np.ndarray:
    """``Σ_k s_k c_k`` → ``(..., 3)`` (the inverse of the separable form)."""
    big = np.finfo(dt).max
    with np.errstate(over="ignore"):
        out = sum(_rgb(np.asarray(s, dtype=dt), c) for s, c in terms)
    return np.minimum(out, big)


def _color(name: str, value, hi: float | None = None) -> np.ndarray:
    """A reflectance coefficient: a finite scalar or RGB triple, every entry >= 0 (and <= ``hi``).

    :func:`~lighting._numeric.real_array` first, so that complex values, booleans and text are
    refused as types (``check_color`` alone would drop an imaginary part).
    """
    allowed = "a finite scalar or RGB triple with every entry >= 0" + (f" and <= {hi:g}" if hi is not None else "")
    arr = real_array(name, value, allowed=allowed, dtype=np.float64)
    if arr.shape not in ((), (3,)):
        raise ValueError(f"{name} must be {allowed}; got shape {arr.shape}: {_fmt(value)}")
    if np.any(arr < 0) or (hi is not None and np.any(arr > hi)):
        raise ValueError(f"{name} must be {allowed}; got {_fmt(value)}")
    return check_color(name, arr)


#: Peak bytes per shading point of one public ``eval`` call: the normalized vectors, the cached
#: derived quantities of a :class:`Geometry` and the models' float64 temporaries (measured with
#: tracemalloc: 18 float64 values per point for Lambert, 29 for Blinn–Phong, 56 for Cook–Torrance
#: with Smith and the dielectric Fresnel; float32 inputs still take most of them in float64).
_BYTES_PER_POINT = 64 * 8


def _public_geometry(n, l, v) -> Geometry:  # noqa: E741
    """The arguments of ``eval``/``eval_cos``/``classic``, checked once: a :class:`Geometry`.

    ``n``, ``l``, ``v``: real, finite, shape ``(..., 3)``, broadcasting together, within the
    memory budget.  Zero vectors are allowed (the contract's directions are unit; a zero one
    has no direction and gives zero reflectance).  The dtype is decided on the arguments as
    given (a tuple is weak), then every one is converted to it.
    """
    dt = working_dtype(n, l, v)
    arrays = [check_vectors(name, x, dtype=dt) for name, x in (("n", n), ("l", l), ("v", v))]
    try:
        shape = np.broadcast_shapes(*(a.shape for a in arrays))
    except ValueError:
        shapes = ", ".join(str(a.shape) for a in arrays)
        raise ValueError(f"n, l and v must broadcast together (shapes (..., 3)); got shapes {shapes}") from None
    points = math.prod(shape[:-1])
    check_budget("n, l, v", points * _BYTES_PER_POINT, what=f"{points} shading points")
    return Geometry(*arrays, dtype=dt)


class BRDF:
    """Base class: a reflectance model ``f_r(n, l, v)``.

    Subclasses implement ``_f(g)`` (the BRDF) and/or ``_f_cos(g)`` (``f_r (n·l)``)
    on a :class:`Geometry`; each default derives one from the other.
    """

    #: Which term of the slides' decomposition this model is ("diffuse" or "specular").
    term = "specular"
    #: Whether the separable forms accept a :class:`StackedGeometry` (all lights at once);
    #: a model that reads the vectors ``g.n``, ``g.l``, ``g.v`` themselves leaves it False.
    stackable = False
    #: The registered name (scene files, the command line, the explorer); ``None`` if unregistered.
    name: str | None = None
    #: The parameter table (:class:`~lighting.models.protocol.Parameter`): the constructor's keywords,
    #: their kinds, ranges, defaults, units and descriptions, in the constructor's order.
    parameters: tuple[Parameter, ...] = ()
    #: Named variants a model list shows as entries of their own: name → fixed keyword arguments.
    variants: dict = {}
    #: ``f_r`` is the constant ``diffuse_albedo / π``: shading and integration may use closed forms.
    lambertian = False

    # -- evaluation -----------------------------------------------------------------
    def eval(self, n, l, v):  # noqa: E741
        """Physical BRDF ``f_r`` in 1/sr, shape ``(..., 3)``; 0 below the horizon.

        Parameters
        ----------
        n, l, v : array_like, shape (..., 3)
            Normal, direction toward the light, direction toward the viewer: finite real
            vectors that broadcast together, normalized on entry.  A zero vector gives 0.

        Returns
        -------
        ndarray, shape (..., 3)
            Finite and >= 0, in the float dtype of the vector arguments (saturated at its
            largest value where the true value is larger).

        Raises
        ------
        ValueError
            Naming ``n``, ``l`` or ``v``: NaN or infinite entries, a last axis other than 3,
            shapes that do not broadcast, more points than the memory budget allows
            (``ArgumentTypeError``, also a ``TypeError``, for text, complex, booleans, None).
        """
        return self.eval_geometry(_public_geometry(n, l, v))

    def eval_cos(self, n, l, v):  # noqa: E741
        """``f_r (n·l)``, computed without dividing by ``n·l``; shape ``(..., 3)``.  Arguments as :meth:`eval`."""
        return self.eval_cos_geometry(_public_geometry(n, l, v))

    def classic(self, n, l, v):  # noqa: E741
        """The slides' illumination term ``π f_r (n·l)``; shape ``(..., 3)``.  Arguments as :meth:`eval`."""
        return self.classic_geometry(_public_geometry(n, l, v))

    def eval_geometry(self, g: Geometry):
        return self._f(g)

    def eval_cos_geometry(self, g: Geometry):
        return self._f_cos(g)

    def classic_geometry(self, g: Geometry):
        return _combine(self.separable_classic(g), g.dtype)

    def _f(self, g: Geometry):
        nl = g.n_dot_l
        return safe_div(self._f_cos(g), nl[..., None])

    def _f_cos(self, g: Geometry):
        return _combine(self.separable_cos(g), g.dtype)

    # -- separable form: what the shading pass uses -------------------------------------
    def separable_cos(self, g: Geometry) -> list[tuple[np.ndarray, np.ndarray]]:
        """``f_r (n·l)`` as ``Σ_k s_k c_k``: scalar fields ``s_k (...)`` times RGB constants ``c_k (3,)``.

        Most models are one scalar lobe times a colour (``k_d``, ``k_s``), so a
        shading pass can combine colours once per term instead of once per
        pixel and channel.  The default splits the RGB result into channels.
        """
        f = self._f_cos(g)
        return [(f[..., i], _UNIT_RGB[i]) for i in range(3)]

    def separable_classic(self, g: Geometry) -> list[tuple[np.ndarray, np.ndarray]]:
        """The classic term ``π f_r (n·l)`` in the separable form of :meth:`separable_cos`."""
        pi = g.dtype(math.pi)
        with np.errstate(over="ignore"):
            return [(saturate_to(s * pi, g.dtype), c) for s, c in self.separable_cos(g)]

    # -- what the rest of the engine asks a model ---------------------------------------
    def lobe(self) -> Lobe | None:
        """Where ``f_r (n·l)`` concentrates (:class:`~lighting.models.protocol.Lobe`); ``None``: unknown.

        Quadrature then covers the hemisphere about the normal, and plots measure the lobe's width
        numerically.
        """
        return None

    def sampler(self):
        """The importance sampler of this model (``sample(u, v)`` and ``pdf(l, v)``, local frame).

        The default samples the cosine-weighted hemisphere, which any model with a finite
        ``f_r`` can use (unbiased, if slow for sharp lobes).
        """
        from ..integrate.sampling import CosineSampler

        return CosineSampler()

    def summary(self) -> str:
        """A short parameter summary (the plausibility audit's model column)."""
        return repr(self)

    def to_dict(self) -> dict:
        """The model as a scene file's part table: ``{"model": name, parameter: value, ...}``.

        Colours become lists of floats, numbers floats, in the order of :attr:`parameters`.
        """
        if self.name is None or self.parts != (self,):
            raise ValueError(f"no scene-file form for the model {type(self).__name__}")
        d = {"model": self.name}
        for p in self.parameters:
            value = getattr(self, p.name)
            if p.kind == "color":
                value = [float(x) for x in np.asarray(value, dtype=np.float64).reshape(-1)]
            elif p.kind == "float":
                value = float(value)
            elif p.kind == "bool":
                value = bool(value)
            d[p.name] = value
        return d

    @classmethod
    def from_dict(cls, table: dict) -> BRDF:
        """The inverse of :meth:`to_dict` (the ``model`` key, if present, is ignored)."""
        return cls(**{k: v for k, v in table.items() if k != "model"})

    # -- structure ------------------------------------------------------------------
    @property
    def parts(self) -> tuple[BRDF, ...]:
        """The terms of the slides' decomposition ``f_d + f_s`` (just ``self`` here)."""
        return (self,)

    def __add__(self, other: BRDF) -> BRDFSum:
        if not isinstance(other, BRDF):
            return NotImplemented
        return BRDFSum(*self.parts, *other.parts)

    @property
    def diffuse_albedo(self) -> np.ndarray:
        """The Lambertian ``k_d`` of this model (zeros for a purely specular one)."""
        return np.zeros(3)

    def __repr__(self) -> str:
        fields = ", ".join(f"{k}={_short(v)}" for k, v in self._params().items())
        return f"{type(self).__name__}({fields})"

    def _params(self) -> dict:
        return {}


def _color_text(c) -> str:
    """``0.5`` for a grey coefficient, ``(0.8,0.2,0.1)`` for a coloured one."""
    c = np.asarray(c)
    if np.all(c == c.flat[0]):
        return f"{float(c.flat[0]):g}"
    return "(" + ",".join(f"{float(x):g}" for x in c) + ")"


def _short(v):
    if isinstance(v, np.ndarray):
        if np.all(v == v.flat[0]):
            return repr(float(v.flat[0]))
        return "(" + ", ".join(f"{x:g}" for x in v) + ")"
    return repr(v)


class Lambert(BRDF):
    r"""Ideal diffuse (Lambertian, "matte") reflection.

        f_r = k_d / π                (BRDF constant)
        classic term: k_d (n·l)      (Lambert's cosine law)

    ``kd`` is the albedo: a Lambertian surface reflects the fraction ``k_d`` of
    the light it receives, in every direction alike.

    Parameters
    ----------
    kd : float or RGB triple, >= 0
        Diffuse albedo (the surface colour).

    Examples
    --------
    >>> Lambert(1.0).eval((0, 0, 1.0), (0, 0, 1.0), (0, 0, 1.0)).round(6).tolist()
    [0.31831, 0.31831, 0.31831]
    """

    name = "lambert"
    term = "diffuse"
    stackable = True
    lambertian = True
    parameters = (
        Parameter("kd", "color", 0.8, slider=(0.0, 1.0), description="diffuse albedo k_d (the surface colour)"),
    )

    def __init__(self, kd=0.8):
        self.kd = _color("kd", kd)

    def lobe(self):
        return Lobe("normal")

    def sampler(self):
        from ..integrate.sampling import CosineSampler

        return CosineSampler()

    def summary(self):
        return f"kd={_color_text(self.kd)}"

    def _params(self):
        return {"kd": self.kd}

    @property
    def diffuse_albedo(self):
        return self.kd

    def _f(self, g):
        return _rgb(np.where(g.above, 1 / math.pi, 0).astype(g.dtype), self.kd)

    def separable_cos(self, g):
        return [(np.where(g.above, g.n_dot_l / g.dtype(math.pi), 0).astype(g.dtype), self.kd)]

    def separable_classic(self, g):
        return [((g.n_dot_l * g.above_mask).astype(g.dtype, copy=False), self.kd)]


class Phong(BRDF):
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

    def _params(self):
        return {"ks": self.ks, "shininess": self.shininess}

    def lobe(self):
        e = self.shininess
        if e == 0:
            return Lobe("normal")  # f_r (n·l) is constant over the hemisphere
        # (R·v)^e ≈ exp(−e ψ²/2) about R_v: standard deviation 1/√e; quadrature scales by 1/√(e+1).
        width = 1.0 / math.sqrt(e) if np.any(self.ks > 0) else math.inf
        return Lobe("mirror", width, quadrature_width=1.0 / math.sqrt(e + 1.0), power=e)

    def sampler(self):
        from ..integrate.sampling import PhongSampler, UniformSampler

        # e = 0: f_r (n·l) is constant over the hemisphere, which uniform sampling integrates exactly.
        return UniformSampler() if self.shininess == 0 else PhongSampler(self.shininess)

    def summary(self):
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
        return [(self._lobe(g) / g.dtype(math.pi), self.ks)]

    def separable_classic(self, g):
        return [(self._lobe(g), self.ks)]


class BlinnPhong(BRDF):
    r"""Blinn–Phong (Jim Blinn, 1977): the highlight from the half vector.

    Unnormalized (the slides' and OpenGL's form, ``normalized=False``)::

        classic term: k_s (n·h)^e,     f_r = k_s (n·h)^e / (π (n·l))

    Normalized (``normalized=True``), the CMSC 435 slide's "think of it as an NDF"::

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

    def _params(self):
        return {"ks": self.ks, "shininess": self.shininess, "normalized": self.normalized}

    def lobe(self):
        e = self.shininess
        if e == 0:
            return Lobe("normal")
        # Half vectors ∝ (n·h)^e ≈ exp(−e θ_h²/2) about n: standard deviation 1/√e.
        width = 1.0 / math.sqrt(e) if np.any(self.ks > 0) else math.inf
        return Lobe("half", width, quadrature_width=1.0 / math.sqrt(e + 1.0))

    def sampler(self):
        from ..integrate.sampling import CosineSampler, MicrofacetSampler, UniformSampler

        if self.shininess == 0:
            # f_r (n·l) is ∝ n·l (normalized) or constant (raw): cosine or uniform sampling is exact.
            return CosineSampler() if self.normalized else UniformSampler()
        return MicrofacetSampler("blinn-phong", exponent=self.shininess)

    def summary(self):
        return f"ks={_color_text(self.ks)} e={self.shininess:g}" + (" normalized" if self.normalized else "")

    def _lobe(self, g, dtype=None, scale: float = 1.0):
        """``scale · (n·h)^e`` (0 below the horizon) in ``dtype`` (that of ``g`` by default).

        Where ``(n·h)^e`` alone would be subnormal the constant factor goes into the exponent,
        ``exp(e log(n·h) + log scale)``: the normalized lobe's ``(e + 2)/(2π)`` (1.6e6 at ``e = 1e7``)
        would otherwise scale a subnormal ``(n·h)^e`` whose digits are already lost (7 % at a
        result of 1.2e-38 in float32).  Elsewhere it multiplies (see :meth:`_exp_scaled`).  Values
        beyond the dtype saturate at its largest one.
        """
        dt = dtype or g.dtype
        if self.shininess == 0:
            return saturate_to(np.where(g.above, scale, 0), dt)
        if isinstance(g, StackedGeometry) and dt == g.dtype:
            return self._lobe_tangent(g, scale)
        d = g.one_minus_n_dot_h.astype(dt, copy=False)
        c = g.n_dot_h.astype(dt, copy=False)
        shape = np.broadcast_shapes(np.shape(c), np.shape(d))
        c, d = np.atleast_1d(c), np.atleast_1d(d)  # the in-place passes below need arrays
        # (n·h)^e = exp(e · log(n·h)), the logarithm taken from the accurate input: near the
        # peak 1 − n·h (log1p), far from it (n·h < 1/2) n·h itself — 1 − n·h has lost the
        # digits of a small n·h there (at n·h = 1e-8 all of them).  Both are one vectorized
        # log: y = n·h (far) or fl(1 − d) (near), and x = y − 1 (far) or −d (near), so
        # log_corrected(y, x) is log(n·h) far from the peak and log1p(−d) near it.
        # The branches are blended arithmetically (all operands finite): np.where on a
        # data-dependent mask costs several times more (measured 2.3 against 0.4 ms here).
        # |n·h| (not max(n·h, 0): a plain pass, where NumPy's max is a slow NaN-aware one) is n·h
        # wherever the lobe is kept: n·l > 0 and n·v > 0 make n·h > 0.  1 − d needs no clamp: the
        # near branch has d <= 1/2, and elsewhere the (finite) value is multiplied by 0.
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
            t = log_corrected(y, x)  # in [−∞, 0]: −∞ where n·h = 0 (h on the horizon, l = −v)
            t *= _exponent_in(dt, self.shininess)  # > 0, so −∞ · e is −∞, never NaN
            t = self._exp_scaled(t, dt, scale)
        t *= g.above_mask
        return t.reshape(np.broadcast_shapes(shape, np.shape(g.above))).astype(dt, copy=False)

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

    def _lobe_tangent(self, g, scale: float = 1.0):
        """``scale · (n·h)^e = scale · exp(−(e/2) log1p(tan²θ_h))`` on a :class:`StackedGeometry`.

        Half the passes of the ``n·h`` form below, and as accurate: ``tan²θ_h``
        carries ``sin θ_h`` near the peak and ``n·h`` far from it to the accuracy of
        the vectors (:attr:`StackedGeometry.tan2_h`).  The few entries it does not
        serve (:attr:`StackedGeometry.delicate`) take the ``n·h`` form on their own.
        """
        with np.errstate(divide="ignore", over="ignore", under="ignore", invalid="ignore"):
            t = log1p(g.tan2_h)  # finite and >= 0 everywhere
            t *= -_exponent_in(g.dtype, 0.5 * self.shininess)
            t = self._exp_scaled(t, g.dtype, scale)
        t *= g.above_mask
        if g.delicate is not None:
            t[g.delicate] = self._lobe(g.entries(*g.delicate), scale=scale)
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
        if self.normalized:
            # n·l of unit vectors may round to 1 + ulp: clipped, so a saturated lobe stays finite.
            return [(self._lobe(g, scale=self._norm()) * np.clip(g.n_dot_l, 0, 1), self.ks)]
        return [(self._lobe(g) / g.dtype(math.pi), self.ks)]

    def separable_classic(self, g):
        if self.normalized:
            return super().separable_classic(g)
        return [(self._lobe(g), self.ks)]


class CookTorrance(BRDF):
    r"""Cook–Torrance microfacet specular reflection.

    Default (energy-consistent, Walter et al. 2007)::

        f_r = k_s D(h) G(n, v, l) F(v·h) / (4 (n·v)(n·l))

    With ``denominator="pi"`` the slide's (and the 1982 paper's) form::

        f_r = k_s D G F / (π (n·v)(n·l))

    which, with a normalized ``D``, reflects up to ``4/π ≈ 1.27`` times too
    much; it is kept so the plausibility audit and the figures can show that.

    Parts: ``D`` Beckmann (Gaussian slopes, the slides'), GGX, or the slides'
    normalized Blinn–Phong lobe with exponent ``e = 2/α² − 2``; ``G`` the
    slides' V-cavity term or separable Smith ``G1(v) G1(l)`` for the chosen NDF;
    ``F`` Schlick, the exact dielectric formula with ``η`` from ``f0``, or
    ``"none"`` (F = 1).

    Parameters
    ----------
    ks : float or RGB triple, >= 0
        Scale of the specular lobe (1 for a pure microfacet model).
    roughness : float > 0
        The NDF's α.  Values down to 1e-6 are evaluated as given (results stay
        finite; the peak of ``D`` is ``1/(π α²)``).
    f0 : float or RGB triple in [0, 1]
        Fresnel reflectance at normal incidence (0.04 for common dielectrics).
    ndf : {"beckmann", "ggx", "blinn-phong"}
    geometry : {"v-cavity", "smith"}
    fresnel : {"schlick", "dielectric", "none"}
    denominator : {"4", "pi"}

    Examples
    --------
    >>> ct = CookTorrance(1.0, 0.3, 1.0)
    >>> round(float(ct.eval((0, 0, 1.0), (0, 0, 1.0), (0, 0, 1.0))[0]), 6)  # D(0)/4
    0.884194
    """

    name = "cook-torrance"
    NDFS = ("beckmann", "ggx", "blinn-phong")
    GEOMETRIES = ("v-cavity", "smith")
    FRESNELS = ("schlick", "dielectric", "none")
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
    )

    stackable = True

    def __init__(
        self,
        ks=1.0,
        roughness=0.3,
        f0=0.04,
        ndf="beckmann",
        geometry="v-cavity",
        fresnel="schlick",
        denominator="4",
    ):
        self.ks = _color("ks", ks)
        self.roughness = check_positive("roughness", roughness)
        self.f0 = _color("f0", f0, hi=1.0)
        self.ndf = check_choice("ndf", ndf, self.NDFS)
        self.geometry = check_choice("geometry", geometry, self.GEOMETRIES)
        self.fresnel = check_choice("fresnel", fresnel, self.FRESNELS)
        if isinstance(denominator, (int, np.integer)) and not isinstance(denominator, (bool, np.bool_)):
            denominator = str(denominator)  # 4 means "4"
        self.denominator = check_choice("denominator", denominator, self.DENOMINATORS)
        self._exponent = float(_mf.blinn_phong_exponent(self.roughness))

    def lobe(self):
        # Beckmann's exp(−tan²θ_h/α²) has standard deviation α/√2 about n; quadrature scales by α.
        width = self.roughness / math.sqrt(2.0) if np.any(self.ks > 0) else math.inf
        horizon = "v-cavity" if self.geometry == "v-cavity" else "smith"
        return Lobe("half", width, quadrature_width=self.roughness, horizon=horizon)

    def sampler(self):
        from ..integrate.sampling import MicrofacetSampler

        return MicrofacetSampler(self.ndf, self.roughness)

    def summary(self):
        f = "F=1" if self.fresnel == "none" else f"{self.fresnel} f0={_color_text(self.f0)}"
        den = "4(n·v)(n·l)" if self.denominator == "4" else "π(n·v)(n·l)"
        return f"ks={_color_text(self.ks)} α={self.roughness:g} {self.ndf}/{self.geometry} {f} /{den}"

    def _params(self):
        return {
            "ks": self.ks,
            "roughness": self.roughness,
            "f0": self.f0,
            "ndf": self.ndf,
            "geometry": self.geometry,
            "fresnel": self.fresnel,
            "denominator": self.denominator,
        }

    # The three factors, public so that figures can show each one.
    def D(self, g: Geometry):
        """Normal distribution at ``h`` (1/sr)."""
        return self._D(g, g.dtype)

    # The unchecked microfacet functions: the parameters were checked by the constructor, and the
    # cosines come from a Geometry (the renderer's path must not pay for a check per call).
    def _D(self, g: Geometry, dtype):
        c, s2 = g.n_dot_h.astype(dtype, copy=False), g.sin2_h.astype(dtype, copy=False)
        if self.ndf == "blinn-phong":
            return _mf._blinn_phong_ndf(c, self._exponent, s2, dtype)
        f = _mf._beckmann_ndf if self.ndf == "beckmann" else _mf._ggx_ndf
        return f(c, self.roughness, s2, dtype)

    def G(self, g: Geometry):
        """Shadowing–masking in [0, 1]."""
        if self.geometry == "v-cavity":
            return _mf._vcavity_g(g.n_dot_h, g.n_dot_v, g.n_dot_l, g.v_dot_h)
        # Blinn–Phong lobes use the Beckmann G1 of the equivalent α (Walter et al. 2007).
        g1 = _mf._smith_g1_ggx if self.ndf == "ggx" else _mf._smith_g1_beckmann
        return g1(g.n_dot_v, self.roughness, g.sin2_v, g.dtype) * g1(g.n_dot_l, self.roughness, g.sin2_l, g.dtype)

    def F(self, g: Geometry):
        """Fresnel reflectance per channel, shape ``(..., 3)``."""
        c = g.v_dot_h
        if self.fresnel == "none":
            return np.ones(c.shape + (3,), dtype=g.dtype)
        if self.fresnel == "schlick":
            return _fresnel.schlick(c, self.f0)
        # The exact dielectric formula with η = (1 + √f0)/(1 − √f0), written in √f0 itself.
        return _fresnel._dielectric_from_f0(c, self.f0).astype(g.dtype)

    def _den_const(self):
        return 4.0 if self.denominator == "4" else math.pi

    def _visibility(self, g: Geometry, with_n_dot_l: bool) -> np.ndarray:
        """``G / ((n·v)(n·l))`` (or ``G / (n·v)``) in float64, without multiplying the cosines in and out.

        At grazing ``G`` is itself proportional to the cosines it is divided by (Smith
        ``G1(v) ≈ 2 a √π`` with ``a ∝ n·v``), so ``f_r`` stays moderate while ``G`` and
        ``(n·v)(n·l)`` both vanish; forming each ratio directly saves the roundings of the
        product and the quotient.  Smith: ``G1(θ) = 2 cos θ / d(θ)`` with ``d`` from
        :func:`lighting.models.microfacet._smith_g1_den_beckmann` (or ``_ggx``).  V-cavity:
        ``G/((n·v)(n·l)) = min(1/((n·v)(n·l)), (2 n·h / v·h) / max(n·v, n·l))``.
        """
        nv = g.n_dot_v.astype(np.float64)
        nl = g.n_dot_l.astype(np.float64)
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            if self.geometry == "smith":
                den = _mf._smith_g1_den_ggx if self.ndf == "ggx" else _mf._smith_g1_den_beckmann
                s2v = g.sin2_v.astype(np.float64)
                s2l = g.sin2_l.astype(np.float64)
                # G1 = 2 cos θ / d:  G1(v) G1(l) / ((n·v)(n·l)) = 4 / (d_v d_l),
                # and G1(v) G1(l) / (n·v) = 4 (n·l) / (d_v d_l).
                dd = den(nv, self.roughness, s2v) * den(nl, self.roughness, s2l)
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
            return [(s, self.ks)]
        if self.fresnel == "schlick":
            # F = f0 + (1 − f0)(1 − v·h)^5: two lobes with colours k_s f0 and k_s (1 − f0).
            m = (1.0 - np.clip(g.v_dot_h.astype(np.float64), 0.0, 1.0)) ** 5
            return [(s, self.ks * self.f0), (s * m, self.ks * (1.0 - self.f0))]
        fr = _fresnel._dielectric_from_f0(g.v_dot_h, self.f0)  # float64, not rounded to the dtype first
        return [(s * fr[..., i], self.ks * _UNIT_RGB[i]) for i in range(3)]

    def _f(self, g):
        return saturate_to(_combine(self._separable(g, True), np.float64), g.dtype)

    def separable_cos(self, g):
        return [(saturate_to(s, g.dtype), c) for s, c in self._separable(g, False)]

    def separable_classic(self, g):
        return [(saturate_to(s * math.pi, g.dtype), c) for s, c in self._separable(g, False)]


class BRDFSum(BRDF):
    r"""Sum of reflectance models, the slides' decomposition ``f_r = f_d + f_s``.

    ``parts`` gives each term, so a front end can show the diffuse and specular
    contributions separately.  Build it with ``+``.

    Examples
    --------
    >>> m = Lambert(0.5) + BlinnPhong(0.3, 40)
    >>> [p.term for p in m.parts]
    ['diffuse', 'specular']
    """

    def __init__(self, *parts: BRDF):
        if not parts:
            raise ValueError("parts must be one or more BRDF models; got none")
        for i, p in enumerate(parts):
            if not isinstance(p, BRDF):
                raise ArgumentTypeError(f"parts[{i}] must be a BRDF model; got {type(p).__name__} {_fmt(p)}")
        flat = []
        for p in parts:
            flat.extend(p.parts)
        self._parts = tuple(flat)

    @property
    def parts(self):
        return self._parts

    @property
    def diffuse_albedo(self):
        return sum((p.diffuse_albedo for p in self._parts), np.zeros(3))

    def _f(self, g):
        return _saturating_sum([p.eval_geometry(g) for p in self._parts], g.dtype)

    def _f_cos(self, g):
        return _saturating_sum([p.eval_cos_geometry(g) for p in self._parts], g.dtype)

    def separable_cos(self, g):
        return [t for p in self._parts for t in p.separable_cos(g)]

    def separable_classic(self, g):
        return [t for p in self._parts for t in p.separable_classic(g)]

    def __repr__(self):
        return " + ".join(repr(p) for p in self._parts)


for _model in (Lambert, Phong, BlinnPhong, CookTorrance):  # the lectures' order
    register_model(_model)
del _model

r"""The fast path's geometry: every distant light over every point at once, as ``(K, N)`` planes.

:class:`StackedGeometry` offers the quantities of :class:`~lighting.models.geometry.Geometry`
(the reference, one light per sample) under the same names and in the same accurate forms,
formed in whole-array passes for ``K`` lights.  Models consume it through the separable
extension of their protocol (:mod:`lighting.shading.separable`): ``separable_cos`` and
``separable_classic`` of a model whose ``stackable`` is True.  Where the reference's form is
slow, the geometry offers its own (:meth:`StackedGeometry.log_n_dot_h_power`, the tangent form
of the Blinn–Phong lobe) and puts right the few entries that form does not serve
(:meth:`StackedGeometry.refine`); the models never ask which geometry they were given.
"""

from __future__ import annotations

import numpy as np

from ..models.geometry import Geometry, _cached, _unit_sum
from ..numerics import _exponent_in, as_float, log1p, working_dtype
from ..vec import normalize

__all__ = ["StackedGeometry"]


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
    # temporaries (faster: docs/numerics.md).
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

    def log_n_dot_h_power(self, exponent: float, dtype):
        """``e · log(n·h) = −(e/2) log1p(tan²θ_h)`` for all lights at once, and its shape.

        Half the passes of the ``n·h`` form of :meth:`Geometry.log_n_dot_h_power`, and as
        accurate: :attr:`tan2_h` carries ``sin θ_h`` near the peak and ``n·h`` far from it to
        the accuracy of the vectors.  The few entries it does not serve (:attr:`delicate`) are
        put right by :meth:`refine`.  In a dtype other than the geometry's, the ``n·h`` form.

        Parameters
        ----------
        exponent : float
            The lobe exponent ``e >= 0`` (finite).
        dtype : float32 or float64

        Returns
        -------
        t : ndarray, shape (K, N)
            ``e · log(n·h)`` (finite and <= 0 in the geometry's dtype), a fresh array.
        shape : tuple
            ``t.shape``.
        """
        if dtype != self.dtype:
            return Geometry.log_n_dot_h_power(self, exponent, dtype)
        with np.errstate(divide="ignore", over="ignore", under="ignore", invalid="ignore"):
            t = log1p(self.tan2_h)  # finite and >= 0 everywhere
            t *= -_exponent_in(self.dtype, 0.5 * exponent)
        return t, t.shape

    def refine(self, values, dtype, evaluate):
        """``values`` with the :attr:`delicate` entries replaced by ``evaluate(self.entries(*delicate))``.

        Parameters
        ----------
        values : ndarray, shape (K, N)
            Computed from :meth:`log_n_dot_h_power` (modified in place).
        dtype : float32 or float64
            The dtype of ``values``: in another than the geometry's no fast form was used and
            nothing is replaced.
        evaluate : callable
            ``evaluate(sub)`` → the same quantity on a :class:`Geometry` ``sub``.

        Returns
        -------
        ndarray
            ``values``.
        """
        if dtype == self.dtype and self.delicate is not None:
            values[self.delicate] = evaluate(self.entries(*self.delicate))
        return values

    def entries(self, k, i) -> Geometry:
        """A :class:`Geometry` of the pairs (light ``k[j]``, point ``i[j]``).

        Parameters
        ----------
        k : array of int, (M,)
            Light indices in ``[0, K)`` (the first index array of :attr:`delicate`).
        i : array of int, (M,)
            Point indices in ``[0, N)``, one per entry of ``k``.

        Returns
        -------
        Geometry
            ``M`` pairs of unit vectors, in this geometry's dtype; ``entries(*delicate)[j]`` is the entry
            ``(k[j], i[j])`` of the ``(K, N)`` planes.
        """
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


r"""The shading directions at a set of points and the quantities the models derive from them.

:class:`Geometry` is the reference: ``n``, ``l``, ``v`` per sample (any broadcasting
shapes ``(..., 3)``) and, computed on first use and cached, every derived quantity
a model reads — ``n·l``, ``n·v``, the half vector ``h = (l + v)/|l + v|``, ``n·h``,
``v·h``, ``sin²θ_h``, ``1 − n·h``, ``R_l·v`` and ``1 − R_l·v`` — each in its
numerically careful form.  The fast path (:mod:`lighting.shading.stacked`) builds the
same quantities for all lights at once, under the same names.
"""

from __future__ import annotations

import numpy as np

from ..numerics import _exponent_in, as_float, log_corrected, working_dtype
from ..vec import _add_vectors, _dot, _one_minus_cos_between, normalize

__all__ = ["Geometry"]


class _cached:
    """``functools.cached_property`` without its lock.

    Python 3.11's ``cached_property`` holds one lock per property *for all
    instances* while computing, so two threads shading two halves of an image
    took turns on every derived quantity (docs/numerics.md has the numbers).
    Each :class:`Geometry` is used by one thread, so no lock is needed: the value
    is computed and stored in the instance dict, which shadows this non-data
    descriptor from then on.
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

    def __init__(self, n, l, v, *, unit: bool = False, dtype=None, tangent=None):  # noqa: E741
        dt = dtype or working_dtype(n, l, v)
        n, l, v = (as_float(x, dt) for x in (n, l, v))
        if not unit:
            n, l, v = normalize(n), normalize(l), normalize(v)
        self.dtype = dt
        self.n, self.l, self.v = n, l, v
        self._tangent = None if tangent is None else as_float(tangent, dt)

    # -- the tangent frame (anisotropic models only; isotropic ones never ask) ------------
    @_cached
    def t(self):
        """The unit tangent ``t ⊥ n`` of the shading frame ``(t, b, n)``.

        From the ``tangent`` given at construction, made perpendicular to ``n``
        (``t − (n·t) n``, normalized).  Without one, or where it is parallel to ``n``, the
        documented default: ``t = ẑ × n / |ẑ × n|``, the direction of increasing azimuth φ
        about the z axis (on a sphere about z, the UV sphere's φ direction), and ``t = x̂``
        where ``n`` is along ±z.  In the local frame (``n = +z``) that is ``t = x̂``,
        ``b = ŷ``: azimuths are measured from +x toward +y, as everywhere in the engine.
        """
        n = self.n
        zero = np.zeros((), dtype=self.dtype)
        default = np.stack([-n[..., 1], n[..., 0], np.broadcast_to(zero, n[..., 0].shape)], axis=-1)
        if self._tangent is not None:
            given = self._tangent - self._dot(n, self._tangent)[..., None] * n
            ok = self._dot(given, given) > 0
            default = np.where(ok[..., None], given, default)
        t = normalize(default)
        pole = self._dot(t, t) == 0
        if np.any(pole):
            t = np.where(pole[..., None], np.array([1.0, 0.0, 0.0], dtype=self.dtype), t)
        return t

    @_cached
    def b(self):
        """The unit bitangent ``b = n × t``, completing the right-handed frame ``(t, b, n)``."""
        return np.cross(self.n, self.t).astype(self.dtype, copy=False)

    @_cached
    def h_local(self):
        """The half vector's components ``(h·t, h·b, h·n)`` in the shading frame, shape ``(..., 3)``."""
        return np.stack(self.h_tbn, axis=-1)

    @_cached
    def l_local(self):
        """``(l·t, l·b, l·n)``: the light direction in the shading frame, shape ``(..., 3)``."""
        return np.stack(self.l_tbn, axis=-1)

    @_cached
    def v_local(self):
        """``(v·t, v·b, v·n)``: the view direction in the shading frame, shape ``(..., 3)``."""
        return np.stack(self.v_tbn, axis=-1)

    # The same components as three separate (contiguous) arrays: a model that reads them one at a
    # time takes these, instead of stacking them into h_local and striding over its last axis again.
    @_cached
    def h_tbn(self):
        """``(h·t, h·b, h·n)`` as a tuple of three arrays: the components of :attr:`h_local`."""
        h = self.h
        return self._dot(h, self.t), self._dot(h, self.b), self.n_dot_h

    @_cached
    def l_tbn(self):
        """``(l·t, l·b, l·n)`` as a tuple of three arrays: the components of :attr:`l_local`."""
        return self._dot(self.l, self.t), self._dot(self.l, self.b), self.n_dot_l

    @_cached
    def v_tbn(self):
        """``(v·t, v·b, v·n)`` as a tuple of three arrays: the components of :attr:`v_local`."""
        return self._dot(self.v, self.t), self._dot(self.v, self.b), self.n_dot_v

    _dot = staticmethod(_dot)

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
        s = _add_vectors(self.l, self.v)
        len2 = self._dot(s, s)
        far = len2 < 1
        if np.any(far):
            s = _unit_sum(self.l, self.v, s, far)
            len2 = self._dot(s, s)
        return s, len2

    @_cached
    def h(self):
        """The half vector ``h = (l + v) / |l + v|`` (the slides'; :func:`lighting.vec.halfway` is the public form).

        The shading path's careful twin of :func:`~lighting.vec.halfway`: the sum rebuilt without
        cancellation where ``l`` and ``v`` nearly oppose (:attr:`_l_plus_v`), multiplied by
        ``1/|l + v|``, and only the rows with a tiny ``|l + v|²`` normalized with scaling
        (:func:`lighting.vec.normalize`).  The zero vector where ``l = −v``.
        """
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
        return _one_minus_cos_between(r, self.v)

    # -- the lobe of the half vector, each geometry its best way (the separable extension) ---------
    def log_n_dot_h_power(self, exponent: float, dtype):
        """``e · log(n·h)`` (to be exponentiated) and the shape of the lobe it gives.

        The plain form (:func:`_log_n_dot_h_power`): ``log1p(−(1 − n·h))`` near the peak,
        ``log(n·h)`` far from it.  A geometry with a cheaper accurate form overrides this
        (:class:`lighting.shading.stacked.StackedGeometry` uses ``tan²θ_h``); models call it
        and never ask which geometry they were given.

        Parameters
        ----------
        exponent : float
            The lobe exponent ``e >= 0`` (finite).
        dtype : float32 or float64
            The dtype to compute in.

        Returns
        -------
        t : ndarray
            ``e · log(n·h)`` in ``[−∞, 0]`` (−∞ where ``n·h = 0``), a fresh array the caller may
            overwrite.
        shape : tuple
            The shape of the lobe (``t`` broadcast with :attr:`above`).
        """
        t, shape = _log_n_dot_h_power(self, exponent, dtype)
        return t, np.broadcast_shapes(shape, np.shape(self.above))

    def refine(self, values, dtype, evaluate):
        """``values`` with the entries this geometry's fast forms do not serve re-evaluated.

        A plain :class:`Geometry` serves every entry: ``values`` come back as they are.  A
        stacked geometry replaces its delicate entries by ``evaluate(sub)`` on a
        :class:`Geometry` ``sub`` of just those entries.

        Parameters
        ----------
        values : ndarray
            Values computed from this geometry's fast forms (modified in place, if at all).
        dtype : float32 or float64
            The dtype ``values`` were computed in.
        evaluate : callable
            ``evaluate(sub)`` → the same quantity on a :class:`Geometry` ``sub``.

        Returns
        -------
        ndarray
            ``values``.
        """
        return values



def _unit_sum(l: np.ndarray, v: np.ndarray, s: np.ndarray, rows: np.ndarray) -> np.ndarray:  # noqa: E741
    """``s = l + v`` with the ``rows`` recomputed as ``l/|l| + v/|v|`` without cancellation.

    ``l`` and ``v`` are unit vectors up to rounding.  A component with ``l_i v_i < 0`` is
    rewritten with ``a + b = (a² − b²)/(a − b)``:

        l_i/|l| + v_i/|v| = (l_i²|v|² − v_i²|l|²) / (|l||v| (l_i|v| − v_i|l|)),
        l_i²|v|² − v_i²|l|² = Σ_{j≠i} (l_i v_j − v_i l_j)(l_i v_j + v_i l_j),

    in which the ``l_i² v_i²`` terms have cancelled exactly: the result depends on the
    directions of ``l`` and ``v`` alone (their lengths only divide, where nothing
    cancels), so it is as accurate as the direction components themselves.  ``s`` is written in place when it
    is a writable C-contiguous array of the broadcast shape (the callers' fresh sum), else copied first.
    """
    shape = np.broadcast_shapes(l.shape, v.shape)
    if s.shape != shape or not (s.flags.writeable and s.flags.c_contiguous):
        s = np.array(np.broadcast_to(s, shape))
    rows = np.broadcast_to(rows, shape[:-1])
    # The rows' components gathered as contiguous columns (NumPy's passes over strided columns are several times
    # slower); each product below is formed once where the formula repeats it, in the formula's order.
    at = np.flatnonzero(rows)
    lc = [np.broadcast_to(l[..., c], shape[:-1]).reshape(-1).take(at) for c in range(3)]
    vc = [np.broadcast_to(v[..., c], shape[:-1]).reshape(-1).take(at) for c in range(3)]
    nl = np.sqrt(lc[0] * lc[0] + lc[1] * lc[1] + lc[2] * lc[2])
    nv = np.sqrt(vc[0] * vc[0] + vc[1] * vc[1] + vc[2] * vc[2])
    nl_nv = nl * nv
    flat = s.reshape(-1, 3)
    for i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        li, vi = lc[i], vc[i]
        a, b = li * vc[j], vi * lc[j]
        c, d = li * vc[k], vi * lc[k]
        num = (a - b) * (a + b) + (c - d) * (c + d)
        den = nl_nv * (li * nv - vi * nl)
        opposite = li * vi < 0  # then li·nv and −vi·nl have one sign: den is never 0
        with np.errstate(divide="ignore", invalid="ignore"):
            flat[at, i] = np.where(opposite, num / np.where(opposite, den, 1), li + vi)
    return s



def _log_n_dot_h_power(g, exponent: float, dt):
    """``e · log(n·h)`` from ``n·h`` and ``1 − n·h`` of ``g`` in ``dt``, and the broadcast shape of the two.

    (n·h)^e = exp(e · log(n·h)), the logarithm taken from the accurate input: near the
    peak ``1 − n·h`` (log1p), far from it (``n·h < 1/2``) ``n·h`` itself — ``1 − n·h`` has
    lost the digits of a small ``n·h`` there (at ``n·h = 1e-8`` all of them).
    """
    d = g.one_minus_n_dot_h.astype(dt, copy=False)
    c = g.n_dot_h.astype(dt, copy=False)
    shape = np.broadcast_shapes(np.shape(c), np.shape(d))
    c, d = np.atleast_1d(c), np.atleast_1d(d)  # the in-place passes below need arrays
    # Both branches are one vectorized log: y = n·h (far) or fl(1 − d) (near), and x = y − 1
    # (far) or −d (near), so log_corrected(y, x) is log(n·h) far from the peak and log1p(−d)
    # near it.  The branches are blended arithmetically (all operands finite): np.where on a
    # data-dependent mask costs several times more (docs/numerics.md).
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
        t *= _exponent_in(dt, exponent)  # > 0, so −∞ · e is −∞, never NaN
    return t, shape

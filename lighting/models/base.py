r"""The BRDF protocol: the base class every reflectance model derives from, sums of models, shared helpers.

Every model is one small class (one module per family: :mod:`.lambert`, :mod:`.phong`,
:mod:`.blinn_phong`, :mod:`.cook_torrance`) with the slide's formula in its docstring
and the code that computes exactly it.  The radiometric contract (conventions.md):

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

Besides the evaluation, a model owns its description (:mod:`lighting.models.protocol`):
``name``, ``parameters``, ``variants``, ``lambertian``, ``lobe()``, ``sampler()`` (the
importance sampler and its pdf, defined beside the model), ``summary()``, ``to_dict()``
and ``from_dict()``.

Models add: ``Lambert(0.6) + Phong(0.3, 20)`` is a :class:`BRDFSum` whose
``parts`` are the slides' decomposition ``f_r = f_d + f_s``.

The separable extension (what the fast path uses)
-------------------------------------------------
The one extension of the protocol that the shading fast path
(:mod:`lighting.shading.stacked`, :mod:`lighting.shading.equation`) consumes:

* ``eval_geometry(g)``, ``eval_cos_geometry(g)``, ``classic_geometry(g)``: the three
  evaluations on a :class:`~lighting.models.geometry.Geometry` built once (the public
  methods check their arguments and build it);
* ``separable_cos(g)`` and ``separable_classic(g)``: ``f_r (n·l)`` and ``π f_r (n·l)``
  as ``Σ_k s_k c_k``, scalar fields times RGB constants, so that a shading pass combines
  colours once per term instead of once per pixel and channel;
* ``stackable``: whether the separable forms accept a
  :class:`~lighting.shading.stacked.StackedGeometry` (all distant lights at once, as
  ``(K, N)`` planes).  Such a model reads only the derived quantities (``n_dot_l``,
  ``n_dot_h``, ``one_minus_r_dot_v`` …) and the geometry's own forms
  (:meth:`~lighting.models.geometry.Geometry.log_n_dot_h_power`,
  :meth:`~lighting.models.geometry.Geometry.refine`), never the vectors themselves, and
  never asks which kind of geometry it was given.
"""

from __future__ import annotations

import math

import numpy as np

from .._numeric import (
    ArgumentTypeError,
    _exponent_in,
    _fmt,
    check_budget,
    check_color,
    check_vectors,
    log1p,
    real_array,
    safe_div,
    saturate_to,
    working_dtype,
)
from .geometry import Geometry
from .protocol import Lobe, Parameter

__all__ = ["BRDF", "BRDFSum", "cos_power"]


def cos_power(one_minus_cos: np.ndarray, exponent: float) -> np.ndarray:
    """``max(cos φ, 0)^e`` from ``1 − cos φ`` (given accurately), with ``0^0 = 1``.

    Written as ``exp(e · log1p(−(1 − cos φ)))``: for a shininess of 1e6 the
    lobe lives where ``1 − cos φ ~ 1e-6``, and forming ``cos φ`` first would
    throw away the digits that the millionth power then amplifies.  Any
    exponent from 0 to the largest float works in either dtype (:func:`_exponent_in`).
    A building block of the shading path: it does not check its arguments.

    Parameters
    ----------
    one_minus_cos : ndarray
        ``1 − cos φ`` in [0, 2], formed without cancellation (e.g.
        :func:`lighting.vec.one_minus_cos_between`).
    exponent : float
        ``e``, finite and >= 0.

    Returns
    -------
    ndarray
        ``max(cos φ, 0)^e`` in the dtype of ``one_minus_cos``.
    """
    d = one_minus_cos
    if exponent == 0:
        return np.ones_like(d)
    e = _exponent_in(d.dtype.type, exponent)
    # e · log(...) may overflow to −∞ (e near the type's largest value): exp gives the 0 it should.
    with np.errstate(divide="ignore", over="ignore", under="ignore", invalid="ignore"):
        out = np.exp(e * log1p(-np.minimum(d, 1)))
    return np.where(d < 1, out, 0).astype(d.dtype, copy=False)



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


def _public_geometry(n, l, v, tangent=None) -> Geometry:  # noqa: E741
    """The arguments of ``eval``/``eval_cos``/``classic``, checked once: a :class:`Geometry`.

    ``n``, ``l``, ``v``: real, finite, shape ``(..., 3)``, broadcasting together, within the
    memory budget.  Zero vectors are allowed (the contract's directions are unit; a zero one
    has no direction and gives zero reflectance).  The dtype is decided on the arguments as
    given (a tuple is weak), then every one is converted to it.  ``tangent`` (optional) is checked
    the same way and must broadcast with them; anisotropic models orient their lobe by it.
    """
    dt = working_dtype(n, l, v)
    named = (("n", n), ("l", l), ("v", v)) + ((("tangent", tangent),) if tangent is not None else ())
    arrays = [check_vectors(name, x, dtype=dt) for name, x in named]
    try:
        shape = np.broadcast_shapes(*(a.shape for a in arrays))
    except ValueError:
        shapes = ", ".join(str(a.shape) for a in arrays)
        names = "n, l, v and tangent" if tangent is not None else "n, l and v"
        raise ValueError(f"{names} must broadcast together (shapes (..., 3)); got shapes {shapes}") from None
    points = math.prod(shape[:-1])
    check_budget("n, l, v", points * _BYTES_PER_POINT, what=f"{points} shading points")
    return Geometry(*arrays[:3], dtype=dt, tangent=arrays[3] if tangent is not None else None)



class BRDF:
    """Base class: a reflectance model ``f_r(n, l, v)``.

    Subclasses implement ``_f(g)`` (the BRDF) and/or ``_f_cos(g)`` (``f_r (n·l)``)
    on a :class:`Geometry`; each default derives one from the other.
    """

    #: Which term of the slides' decomposition this model is ("diffuse" or "specular").
    term = "specular"
    #: Whether the separable forms accept a :class:`~lighting.shading.stacked.StackedGeometry` (all lights at once);
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
    #: A diffuse term of its own beside its ``term`` (Disney, Ashikhmin–Shirley): front ends add no Lambert part.
    own_diffuse = False
    #: ``f_r`` is a Dirac delta (the ideal mirror): ``eval`` is 0 for every finite pair of directions,
    #: and integrators, plots and the explorer must treat the reflected direction apart
    #: (see :class:`~lighting.models.mirror.Mirror`, ``reflectance(cos_theta)``).
    is_delta = False

    # -- evaluation -----------------------------------------------------------------
    def eval(self, n, l, v, *, tangent=None):  # noqa: E741
        """Physical BRDF ``f_r`` in 1/sr, shape ``(..., 3)``; 0 below the horizon.

        Parameters
        ----------
        n, l, v : array_like, shape (..., 3)
            Normal, direction toward the light, direction toward the viewer: finite real
            vectors that broadcast together, normalized on entry.  A zero vector gives 0.
        tangent : array_like, shape (..., 3), optional
            The surface tangent that orients an anisotropic lobe (made perpendicular to ``n``).
            Without it the frame is ``t = ẑ × n / |ẑ × n|`` (``x̂`` where ``n`` is along ±z); see
            :attr:`lighting.models.geometry.Geometry.t`.  Isotropic models ignore it.

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
        return self.eval_geometry(_public_geometry(n, l, v, tangent))

    def eval_cos(self, n, l, v, *, tangent=None):  # noqa: E741
        """``f_r (n·l)``, computed without dividing by ``n·l``.

        Parameters
        ----------
        n, l, v : array_like, shape (..., 3)
            As :meth:`eval`.
        tangent : array_like, shape (..., 3), optional
            As :meth:`eval`.

        Returns
        -------
        ndarray, shape (..., 3)
            Finite and >= 0, in the float dtype of the vectors.
        """
        return self.eval_cos_geometry(_public_geometry(n, l, v, tangent))

    def classic(self, n, l, v, *, tangent=None):  # noqa: E741
        """The slides' illumination term ``π f_r (n·l)``.

        Parameters
        ----------
        n, l, v : array_like, shape (..., 3)
            As :meth:`eval`.
        tangent : array_like, shape (..., 3), optional
            As :meth:`eval`.

        Returns
        -------
        ndarray, shape (..., 3)
            Finite and >= 0, in the float dtype of the vectors.
        """
        return self.classic_geometry(_public_geometry(n, l, v, tangent))

    def eval_geometry(self, g: Geometry):
        """:meth:`eval` on a :class:`Geometry` built (and checked) already.

        Parameters
        ----------
        g : Geometry
            The shading directions.

        Returns
        -------
        ndarray, shape (..., 3)
            ``f_r`` in the dtype of ``g``.
        """
        return self._f(g)

    def eval_cos_geometry(self, g: Geometry):
        """:meth:`eval_cos` on a :class:`Geometry`; parameters and result as :meth:`eval_geometry`.

        Parameters
        ----------
        g : Geometry
            The shading directions.

        Returns
        -------
        ndarray, shape (..., 3)
            ``f_r (n·l)`` in the dtype of ``g``, finite and >= 0.
        """
        return self._f_cos(g)

    def classic_geometry(self, g: Geometry):
        """:meth:`classic` on a :class:`Geometry`; parameters and result as :meth:`eval_geometry`.

        Parameters
        ----------
        g : Geometry
            The shading directions.

        Returns
        -------
        ndarray, shape (..., 3)
            ``π f_r (n·l)`` in the dtype of ``g``, finite and >= 0.
        """
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

        Parameters
        ----------
        g : Geometry or StackedGeometry
            The shading directions (a stacked one only if :attr:`stackable`).

        Returns
        -------
        list of (ndarray, ndarray)
            Pairs ``(s_k, c_k)``: a scalar field in the dtype of ``g`` and an RGB constant ``(3,)``.
        """
        f = self._f_cos(g)
        return [(f[..., i], _UNIT_RGB[i]) for i in range(3)]

    def separable_classic(self, g: Geometry) -> list[tuple[np.ndarray, np.ndarray]]:
        """The classic term ``π f_r (n·l)`` in the separable form of :meth:`separable_cos`.

        Parameters
        ----------
        g : Geometry or StackedGeometry
            As :meth:`separable_cos`.

        Returns
        -------
        list of (ndarray, ndarray)
            As :meth:`separable_cos`.
        """
        pi = g.dtype(math.pi)
        with np.errstate(over="ignore"):
            return [(saturate_to(s * pi, g.dtype), c) for s, c in self.separable_cos(g)]

    # -- what the rest of the engine asks a model ---------------------------------------
    def lobe(self) -> Lobe | None:
        """Where ``f_r (n·l)`` concentrates (:class:`~lighting.models.protocol.Lobe`); ``None``: unknown.

        Quadrature then covers the hemisphere about the normal, and plots measure the lobe's width
        numerically.

        Returns
        -------
        Lobe or None
        """
        return None

    def sampler(self):
        """The importance sampler of this model (``sample(u, v)`` and ``pdf(l, v)``, local frame).

        The default samples the cosine-weighted hemisphere, which any model with a finite
        ``f_r`` can use (unbiased, if slow for sharp lobes).

        Returns
        -------
        lighting.models.sampler.Sampler
        """
        from .lambert import CosineSampler

        return CosineSampler()

    def summary(self) -> str:
        """A short parameter summary (the plausibility audit's model column).

        Returns
        -------
        str
        """
        return repr(self)

    def to_dict(self) -> dict:
        """The model as a scene file's part table: ``{"model": name, parameter: value, ...}``.

        Colours become lists of floats, numbers floats, in the order of :attr:`parameters`.

        Returns
        -------
        dict

        Raises
        ------
        ValueError
            For an unregistered model or a sum (no single scene-file part).
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
        """The inverse of :meth:`to_dict` (the ``model`` key, if present, is ignored).

        Parameters
        ----------
        table : dict
            Constructor keywords (and optionally ``model``).

        Returns
        -------
        BRDF
        """
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
        """The model's diffuse reflectance at normal incidence: the ``k_d`` its ambient term ``k_a = k_d`` uses.

        The directional albedo ``ρ_d(v = n) = ∫ f_d (n·l) dω_l`` of the part of ``f_r`` that carries the
        surface's diffuse colour, for a viewer along the normal: Lambert's ``k_d`` (at every view),
        Oren–Nayar's ``k_d A`` (+ ``k_d² R`` in the full form), Ashikhmin–Shirley's
        ``(31/32) R_d (1 − R_s)``, Disney's base-colour diffuse and subsurface terms; zeros for a
        purely specular model.  A :class:`~lighting.shading.material.Material` without ``ambient=`` takes
        it as ``k_a``, and a :attr:`lambertian` model's ``f_r`` is ``diffuse_albedo / π``.

        Returns
        -------
        numpy.ndarray, (3,)
            RGB, float64, >= 0.
        """
        return np.zeros(3)

    def __repr__(self) -> str:
        """One short line: ``Phong(ks=0.5, shininess=32)``, numbers to 6 significant digits.

        Options (``choice`` and ``bool`` rows of :attr:`parameters`) appear only when they differ from
        their default, and so do the numbers of a model with more than four of them (Disney) but the
        first, so the line stays short; a grey colour is one number.  ``summary()`` gives the audit's notation.
        """
        table = {p.name: p for p in getattr(type(self), "parameters", ())}
        params = self._params()
        numbers = [k for k in params if k in table and table[k].kind in ("float", "color")]
        many = len(numbers) > 4
        fields = []
        for k, v in params.items():
            p = table.get(k)
            optional = p is not None and (p.kind in ("choice", "bool") or (many and k != numbers[0]))
            if optional and _same(v, p.default):
                continue
            fields.append(f"{k}={_short(v)}")
        return f"{type(self).__name__}({', '.join(fields)})"

    def _params(self) -> dict:
        return {}



def _color_text(c) -> str:
    """``0.5`` for a grey coefficient, ``(0.8,0.2,0.1)`` for a coloured one."""
    c = np.asarray(c)
    if np.all(c == c.flat[0]):
        return f"{float(c.flat[0]):g}"
    return "(" + ",".join(f"{float(x):g}" for x in c) + ")"


def _num(x) -> str:
    """A number in a repr: 6 significant digits, integers without a decimal point (``32``, ``0.5``)."""
    return f"{float(x):.6g}"


def _short(v):
    """A parameter value in a repr: a number, a grey colour as one number, an RGB triple, else ``repr``."""
    if isinstance(v, (bool, np.bool_)) or v is None or isinstance(v, str):
        return repr(v if not isinstance(v, np.bool_) else bool(v))
    if isinstance(v, (int, float, np.integer, np.floating)):
        return _num(v)
    if isinstance(v, (np.ndarray, tuple, list)):
        try:
            a = np.asarray(v, dtype=np.float64).reshape(-1)
        except (TypeError, ValueError):
            return repr(v)
        if a.size and np.all(a == a[0]):
            return _num(a[0])
        return "(" + ", ".join(_num(x) for x in a) + ")"
    return repr(v)


def _same(value, default) -> bool:
    """Whether a parameter's value is its table default (a colour compared as RGB, ``None`` only to ``None``)."""
    if value is None or default is None:
        return value is None and default is None
    if isinstance(value, str) or isinstance(default, str):
        return value == default
    try:
        a = np.broadcast_to(np.asarray(value, dtype=np.float64), (3,))
        b = np.broadcast_to(np.asarray(default, dtype=np.float64), (3,))
    except (TypeError, ValueError):
        return False
    return bool(np.array_equal(a, b))



class BRDFSum(BRDF):
    r"""Sum of reflectance models, the slides' decomposition ``f_r = f_d + f_s``.

    ``parts`` gives each term, so a front end can show the diffuse and specular
    contributions separately.  Build it with ``+``.

    Examples
    --------
    >>> from lighting.models.brdf import BlinnPhong, Lambert
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
        """See :meth:`BRDF.separable_cos`.

        Parameters
        ----------
        g : Geometry or StackedGeometry
            The shading directions (a stacked one only if every part is :attr:`stackable`).

        Returns
        -------
        list of (ndarray, ndarray)
            The terms of every part, concatenated in the order of :attr:`parts`.
        """
        return [t for p in self._parts for t in p.separable_cos(g)]

    def separable_classic(self, g):
        """See :meth:`BRDF.separable_classic`.

        Parameters
        ----------
        g : Geometry or StackedGeometry
            The shading directions (a stacked one only if every part is :attr:`stackable`).

        Returns
        -------
        list of (ndarray, ndarray)
            The terms of every part, concatenated in the order of :attr:`parts`.
        """
        return [t for p in self._parts for t in p.separable_classic(g)]

    def __repr__(self):
        return " + ".join(repr(p) for p in self._parts)


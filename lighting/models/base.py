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

The protocol (pbrt's BxDF and Mitsuba's BSDF are its models):

* required: ``_f(g)``, the BRDF on a :class:`~lighting.models.geometry.Geometry` (or ``_f_cos(g)``
  in its place, for a model whose ``f_r`` divides by ``n·l``);
* optional, each with a default that works: ``_f_cos`` / ``_f`` (the other one), ``classic_geometry``,
  ``flags`` (:class:`BRDFFlags`), ``lobe()``, ``sampler()``, ``microfacet()``, ``diffuse_albedo``,
  ``summary()``, ``to_dict()`` / ``from_dict()`` (from ``name`` and ``parameters``), ``variants``;
* a delta model (``BRDFFlags.DELTA``) adds ``reflectance(cos_theta)``, what it reflects into the
  mirror direction.

Models add: ``Lambert(0.6) + Phong(0.3, 20)`` is a :class:`BRDFSum` whose
``parts`` are the slides' decomposition ``f_r = f_d + f_s``.

The shading pass's fast path has an extension of its own, which :mod:`lighting.shading.separable`
defines (the separable forms ``separable_cos``/``separable_classic`` and ``stackable``).  Every built-in
analytic model implements it through :class:`SeparableBRDF`, which derives the model's values from
those forms, so that each formula has one home.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import numpy as np

from .._budget import check_budget
from .._text import quote
from .._validate import ArgumentTypeError, check_vectors, real_array
from ..numerics import _exponent_in, log1p, safe_div, saturate_to, working_dtype
from .geometry import Geometry
from .protocol import Lobe, Parameter

__all__ = ["BRDF", "BRDFFlags", "BRDFSum", "MicrofacetLobe", "SeparableBRDF", "cos_power"]


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
    coeff = np.asarray(coeff, dtype=np.float64)
    with np.errstate(over="ignore"):
        if coeff.shape != (3,):
            out = values[..., None] * coeff
        else:
            # One multiplication per channel into a strided column, the products ``values[..., None] * coeff``
            # forms: broadcasting over a last axis of length 3 runs NumPy's inner loop three elements at a time.
            out = np.empty((*np.shape(values), 3), dtype=np.result_type(values, coeff))
            for k in range(3):
                np.multiply(values, coeff[k], out=out[..., k])
    return saturate_to(out, values.dtype, overwrite=True)  # the product is a fresh array


_UNIT_RGB = np.eye(3)


def _saturating_sum(terms, dt) -> np.ndarray:
    """``Σ terms`` (non-negative, finite) saturated at the dtype's largest finite value, without a warning."""
    with np.errstate(over="ignore"):
        out = sum(terms)
    return np.minimum(out, np.finfo(dt).max).astype(dt, copy=False)


def _combine(terms, dt) -> np.ndarray:
    """``Σ_k s_k c_k`` → ``(..., 3)`` (the inverse of the separable form)."""
    big = np.finfo(dt).max
    terms = list(terms)
    if not terms:
        return np.minimum(0, big)
    # sum() in place: the same additions in the same order, starting from 0 + the first term
    # (which turns a −0 into +0, as sum() did).
    out = _rgb(np.asarray(terms[0][0], dtype=dt), terms[0][1])
    with np.errstate(over="ignore"):
        np.add(out, 0, out=out)
        for s, c in terms[1:]:
            term = _rgb(np.asarray(s, dtype=dt), c)
            if np.broadcast_shapes(out.shape, term.shape) == out.shape:
                out += term
            else:
                out = out + term
    return np.minimum(out, big, out=out)


def _color(name: str, value, hi: float | None = None) -> np.ndarray:
    """A reflectance coefficient: a finite scalar or RGB triple, every entry >= 0 (and <= ``hi``).

    :func:`~lighting._validate.real_array` first, so that complex values, booleans and text are
    refused as types (``check_color`` alone would drop an imaginary part).
    """
    allowed = "a finite scalar or RGB triple with every entry >= 0" + (f" and <= {hi:g}" if hi is not None else "")
    arr = real_array(name, value, allowed=allowed, dtype=np.float64)
    if arr.shape not in ((), (3,)):
        raise ValueError(f"{name} must be {allowed}; got shape {arr.shape}: {quote(value)}")
    if np.any(arr < 0) or (hi is not None and np.any(arr > hi)):
        raise ValueError(f"{name} must be {allowed}; got {quote(value)}")
    return np.full(3, float(arr)) if arr.ndim == 0 else arr.astype(np.float64)  # an RGB triple, as check_color gives


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



class BRDFFlags(enum.Flag):
    """What kind of reflectance a model is: one field, ``model.flags``, instead of separate booleans.

    ``DIFFUSE`` and ``SPECULAR`` name the term of the slides' decomposition ``f_r = f_d + f_s`` a model
    is (exactly one of them); the others qualify it.  Ask with ``BRDFFlags.DELTA in model.flags``.

    Attributes
    ----------
    DIFFUSE
        The model is the diffuse term ``f_d`` (Lambert, Oren–Nayar).
    SPECULAR
        The model is the specular term ``f_s`` (every other model, the default).
    LAMBERTIAN
        ``f_r`` is the constant ``diffuse_albedo / π``: shading and integration may use closed forms.
    OWN_DIFFUSE
        A diffuse term of its own beside its specular one (Disney, Ashikhmin–Shirley, measured data,
        BRDF Explorer files): front ends add no Lambert part.
    DELTA
        ``f_r`` is a Dirac delta (the ideal mirror): ``eval`` is 0 for every finite pair of directions,
        and integrators, plots and the explorer treat the reflected direction apart through the
        model's ``reflectance(cos_theta)`` (see :class:`~lighting.models.mirror.Mirror`).
    ANISOTROPIC
        The lobe depends on the azimuth about the normal: the model reads the tangent frame.
    """

    DIFFUSE = enum.auto()
    SPECULAR = enum.auto()
    LAMBERTIAN = enum.auto()
    OWN_DIFFUSE = enum.auto()
    DELTA = enum.auto()
    ANISOTROPIC = enum.auto()

    @classmethod
    def of_term(cls, term: str) -> BRDFFlags:
        """The flag of a term of the decomposition: ``"diffuse"`` → ``DIFFUSE``, ``"specular"`` → ``SPECULAR``."""
        return cls.DIFFUSE if term == "diffuse" else cls.SPECULAR

    @classmethod
    def of_terms(cls, terms) -> BRDFFlags:
        """The flags of the terms named in ``terms`` (``"diffuse"``, ``"specular"``; other names add nothing).

        Examples
        --------
        >>> BRDFFlags.of_terms(("ambient", "specular")) == BRDFFlags.SPECULAR
        True
        """
        out = cls(0)
        for term in terms:
            if term in ("diffuse", "specular"):
                out |= cls.of_term(term)
        return out


@dataclass(frozen=True)
class MicrofacetLobe:
    """A microfacet model's specular lobe described for image-based lighting (:meth:`BRDF.microfacet`).

    Parameters
    ----------
    ndf : str
        The normal distribution: ``"beckmann"``, ``"ggx"`` or ``"blinn-phong"``.
    alpha_x, alpha_y : float
        The NDF's widths along the tangent and the bitangent (equal for a round lobe).
    geometry : str
        The shadowing term: ``"v-cavity"``, ``"smith"`` or ``"smith-correlated"``.
    fresnel : str
        The Fresnel factor's form: ``"none"`` (F = 1), ``"schlick"``, ``"dielectric"`` or ``"conductor"``.
    denominator : str
        ``"4"`` for ``4 (n·v)(n·l)``, ``"pi"`` for the slide's ``π (n·v)(n·l)``.
    specular : numpy.ndarray, (3,)
        The specular colour ``k_s`` (RGB, float64).
    energy_compensation : bool
        Whether a multiple-scattering lobe is added (Kulla and Conty).
    """

    ndf: str
    alpha_x: float
    alpha_y: float
    geometry: str
    fresnel: str
    denominator: str
    specular: np.ndarray
    energy_compensation: bool = False

    @property
    def isotropic(self) -> bool:
        """Round about the normal: ``α_x = α_y``."""
        return self.alpha_x == self.alpha_y


#: The boolean class attributes older models set, and the flag each one stands for.
_LEGACY_FLAGS = {"lambertian": BRDFFlags.LAMBERTIAN, "own_diffuse": BRDFFlags.OWN_DIFFUSE, "is_delta": BRDFFlags.DELTA}


class _FromFlags:
    """A read-only view of a model's :class:`BRDFFlags` under an older boolean's name, on the class or an instance."""

    def __init__(self, read, doc):
        self._read, self.__doc__ = read, doc

    def __set_name__(self, owner, name):
        self._name = name

    def __get__(self, obj, cls=None):
        return self._read((cls if obj is None else obj).flags)

    def __set__(self, obj, value):
        raise AttributeError(f"{self._name} is read from flags; set the model's flags (BRDFFlags) instead")


class BRDF:
    """Base class: a reflectance model ``f_r(n, l, v)``.

    The one required member is the value on a :class:`Geometry`: ``_f(g)``, the BRDF ``f_r``
    (shape ``(..., 3)``, 0 below the horizon).  A model whose ``f_r`` divides by ``n·l`` (the
    slides' Phong BRDF) defines ``_f_cos(g) = f_r (n·l)`` instead, or as well; whichever of the two
    is missing derives from the other.  Everything else has a working default: ``classic`` is
    ``π f_r (n·l)``, the sampler samples the cosine-weighted hemisphere, the lobe is unknown
    (``None``), ``flags`` says a specular term, ``microfacet()`` says no microfacet lobe.  The
    shading pass's separable forms are an optional extension that :mod:`lighting.shading.separable`
    defines; a model without them is shaded channel by channel from ``eval_cos``/``classic``.
    """

    #: What kind of reflectance this is (:class:`BRDFFlags`); an instance may hold its own (Cook–Torrance
    #: and Ward add ``ANISOTROPIC`` when their two widths differ).
    flags: BRDFFlags = BRDFFlags.SPECULAR
    #: The registered name (scene files, the command line, the explorer); ``None`` if unregistered.
    name: str | None = None
    #: The parameter table (:class:`~lighting.models.protocol.Parameter`): the constructor's keywords,
    #: their kinds, ranges, defaults, units and descriptions, in the constructor's order.
    parameters: tuple[Parameter, ...] = ()
    #: Named variants a model list shows as entries of their own: name → fixed keyword arguments.
    variants: dict = {}
    def __init_subclass__(cls, **kwargs):
        # The older spelling (``term = "diffuse"``, ``is_delta = True`` … as class attributes) still
        # defines a model: it becomes the class's flags, and the read-only properties answer from them.
        super().__init_subclass__(**kwargs)
        own = cls.__dict__
        legacy = [k for k in ("term", *_LEGACY_FLAGS) if k in own and not isinstance(own[k], _FromFlags)]
        if not legacy:
            return
        flags = own.get("flags", cls.flags)
        if "term" in legacy:
            flags = (flags & ~(BRDFFlags.DIFFUSE | BRDFFlags.SPECULAR)) | BRDFFlags.of_term(own["term"])
        for key, flag in _LEGACY_FLAGS.items():
            if key in legacy:
                flags = (flags | flag) if own[key] else (flags & ~flag)
        for key in legacy:
            delattr(cls, key)
        cls.flags = flags

    # -- the flags, read one at a time (on the class or an instance) -------------------
    term = _FromFlags(lambda f: "diffuse" if BRDFFlags.DIFFUSE in f else "specular",
                      """The term of the slides' decomposition this model is, ``"diffuse"`` or ``"specular"``.""")
    lambertian = _FromFlags(lambda f: BRDFFlags.LAMBERTIAN in f, "``BRDFFlags.LAMBERTIAN in flags``.")
    own_diffuse = _FromFlags(lambda f: BRDFFlags.OWN_DIFFUSE in f, "``BRDFFlags.OWN_DIFFUSE in flags``.")
    is_delta = _FromFlags(lambda f: BRDFFlags.DELTA in f, "``BRDFFlags.DELTA in flags``.")

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
        with np.errstate(over="ignore"):
            return saturate_to(self.eval_cos_geometry(g) * g.dtype(math.pi), g.dtype)

    def _f(self, g: Geometry):
        if type(self)._f_cos is BRDF._f_cos:
            raise NotImplementedError(f"{type(self).__name__} must define _f(g) (the BRDF) or _f_cos(g) (f_r n·l)")
        nl = g.n_dot_l
        return safe_div(self._f_cos(g), nl[..., None])

    def _f_cos(self, g: Geometry):
        if type(self)._f is BRDF._f:
            raise NotImplementedError(f"{type(self).__name__} must define _f(g) (the BRDF) or _f_cos(g) (f_r n·l)")
        f = self._f(g)
        return np.where(g.above[..., None], f * g.n_dot_l[..., None], 0).astype(f.dtype, copy=False)

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

    def microfacet(self) -> MicrofacetLobe | None:
        """The model's specular lobe as a microfacet description, for image-based lighting; ``None``: not one.

        Image-based lighting reads the engine's albedo tables and samples visible normals for a lobe
        it knows (:mod:`lighting.integrate.ibl`, :mod:`lighting.integrate.dominant`); every other model is
        integrated numerically.

        Returns
        -------
        MicrofacetLobe or None
        """
        return None

    def sampler(self):
        """The importance sampler of this model (``sample(u, v)`` and ``pdf(l, v)``, local frame).

        The default samples the cosine-weighted hemisphere, which any model with a finite
        ``f_r`` can use (unbiased, if slow for sharp lobes).

        Returns
        -------
        lighting.sampling.base.Sampler
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
    def is_black(self) -> bool:
        """Whether the model reflects nothing for any pair of directions (its colour is zero in every channel).

        A render may then leave the part out.  The default, ``False``, is always safe; a model whose
        reflectance is its colour times a lobe says so from its colour.

        Returns
        -------
        bool
        """
        return False

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



class SeparableBRDF(BRDF):
    """A model written in the separable forms of :class:`lighting.shading.separable.Separable`.

    A subclass defines ``separable_cos(g)`` (``f_r (n·l)`` as ``Σ_k s_k c_k``, scalar fields times RGB
    constants) and ``_f(g)``, and may define ``separable_classic(g)`` (default: π times the terms of
    ``separable_cos``) and ``stackable`` (default False).  ``eval_cos`` and ``classic`` are the sums of
    those terms, so the shading pass and the public methods compute the same numbers.
    """

    #: Whether the separable forms accept a stacked geometry (:func:`lighting.shading.separable.stacks`).
    stackable = False

    def separable_cos(self, g) -> list[tuple[np.ndarray, np.ndarray]]:
        """``f_r (n·l)`` as ``[(s_k, c_k), ...]`` (:meth:`lighting.shading.separable.Separable.separable_cos`)."""
        raise NotImplementedError(f"{type(self).__name__} must define separable_cos(g)")

    def separable_classic(self, g) -> list[tuple[np.ndarray, np.ndarray]]:
        """``π f_r (n·l)`` as ``[(s_k, c_k), ...]``: by default π times the terms of :meth:`separable_cos`."""
        pi = g.dtype(math.pi)
        with np.errstate(over="ignore"):
            return [(saturate_to(s * pi, g.dtype), c) for s, c in self.separable_cos(g)]

    def _f_cos(self, g):
        return _combine(self.separable_cos(g), g.dtype)

    def classic_geometry(self, g):
        return _combine(self.separable_classic(g), g.dtype)


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
                raise ArgumentTypeError(f"parts[{i}] must be a BRDF model; got {type(p).__name__} {quote(p)}")
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

    @property
    def is_black(self):
        return all(p.is_black for p in self._parts)

    def _f(self, g):
        return _saturating_sum([p.eval_geometry(g) for p in self._parts], g.dtype)

    def _f_cos(self, g):
        return _saturating_sum([p.eval_cos_geometry(g) for p in self._parts], g.dtype)

    # The sum implements the separable extension whatever its parts: a part without separable forms
    # gives its channels (lighting.shading.separable.terms).
    @property
    def stackable(self) -> bool:
        """Every part's separable forms accept a stacked geometry."""
        from ..shading.separable import stacks

        return all(stacks(p) for p in self._parts)

    def separable_cos(self, g):
        """The terms of every part, concatenated in the order of :attr:`parts`."""
        from ..shading.separable import terms

        return [t for p in self._parts for t in terms(p, g, "cos")]

    def separable_classic(self, g):
        """The terms of every part, concatenated in the order of :attr:`parts`."""
        from ..shading.separable import terms

        return [t for p in self._parts for t in terms(p, g, "classic")]

    def classic_geometry(self, g):
        return _combine(self.separable_classic(g), g.dtype)

    def __repr__(self):
        return " + ".join(repr(p) for p in self._parts)


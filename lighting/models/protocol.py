"""What every reflectance model tells the rest of the engine about itself, and the registry of models by name.

A model (a :class:`~lighting.models.brdf.BRDF` subclass) owns:

* its values: ``eval``, ``eval_cos``, ``classic``;
* its importance sampler and density: ``sampler()`` (pbrt's ``Sample_f``/``PDF`` pair);
* where its reflectance concentrates: ``lobe()``, a :class:`Lobe` that quadrature rules, polar
  slices and lobe meshes follow instead of asking which class the model is;
* its parameter table: ``parameters``, a tuple of :class:`Parameter` from which scene files, the
  command line and the explorer's controls are generated;
* ``to_dict()`` / ``from_dict()`` and a registered ``name``.

Adding a model is one module that defines the class and calls :func:`register_model`, plus its
tests; nothing else in the engine or the explorer names the class.

Examples
--------
>>> from lighting.models import model_class, model_names
>>> model_names()[:4]
('lambert', 'phong', 'blinn-phong', 'cook-torrance')
>>> model_class("phong").from_dict({"model": "phong", "ks": 0.5, "shininess": 10}).to_dict()
{'model': 'phong', 'ks': [0.5, 0.5, 0.5], 'shininess': 10.0}
"""

from __future__ import annotations

import difflib
import math
from dataclasses import dataclass

__all__ = ["Parameter", "Lobe", "register_model", "model_class", "model_names", "model_variants", "create_model"]

#: Kinds of parameter a table may hold, and what each one is in a scene file.
PARAMETER_KINDS = ("float", "color", "bool", "choice")


@dataclass(frozen=True)
class Parameter:
    """One row of a model's parameter table.

    Parameters
    ----------
    name : str
        The keyword of the model's constructor (and the key in scene files).
    kind : {"float", "color", "bool", "choice"}
        A number, a scalar-or-RGB colour, a flag, or one of ``choices``.
    default
        The constructor's default.
    low, high : float
        The allowed range (inclusive unless ``low_open``); ``high = inf`` for none.
    slider : tuple of float, optional
        The range an interactive control offers (within ``[low, high]``); defaults to the range.
    log : bool
        Whether a control should move on a logarithmic scale (exponents, roughness).
    unit : str
        The unit, or ``""`` for a pure number.
    description : str
        One line for help texts and tooltips.
    choices : tuple of str
        The allowed values of a ``"choice"`` parameter.
    low_open : bool
        ``low`` itself is not allowed (roughness ``> 0``).
    """

    name: str
    kind: str
    default: object
    low: float = 0.0
    high: float = math.inf
    slider: tuple[float, float] | None = None
    log: bool = False
    unit: str = ""
    description: str = ""
    choices: tuple[str, ...] = ()
    low_open: bool = False

    def __post_init__(self):
        if self.kind not in PARAMETER_KINDS:
            raise ValueError(f"Parameter {self.name!r}: kind must be one of {PARAMETER_KINDS}; got {self.kind!r}")
        if self.kind == "choice" and self.default not in self.choices:
            raise ValueError(f"Parameter {self.name!r}: the default {self.default!r} is not among {self.choices}")

    def check(self, value):
        """``value`` checked for this row; a ``ValueError`` naming the parameter, the value and what is allowed.

        Numbers are numbers (text, bytes and bools are refused with
        :class:`~lighting._validate.ArgumentTypeError`, both a TypeError and a ValueError); colours are one
        number (grey) or three; choices accept any case and ``_`` for ``-``.  Constructors may check more
        (combinations of parameters); this is what the table alone says.

        Parameters
        ----------
        value
            The value given.

        Returns
        -------
        float, tuple of float, bool, str or None
            The value in plain form: a colour is a float for grey, else a 3-tuple.

        Examples
        --------
        >>> Parameter("sigma", "float", 0.3, low=0.0, high=1.5).check(1)
        1.0
        >>> Parameter("sigma", "float", 0.3, low=0.0, high=1.5).check(2)
        Traceback (most recent call last):
        ...
        ValueError: sigma must be a number in [0, 1.5]; got 2
        """
        from .._text import abbreviate
        from .._validate import ArgumentTypeError, check_bool, real_array

        name, given = self.name, abbreviate(repr(value))
        if self.kind == "bool":
            return check_bool(name, value)
        if self.kind == "choice":
            allowed = f"one of {', '.join(self.choices)}"
            if not isinstance(value, str):
                raise ArgumentTypeError(f"{name} must be {allowed}; got {type(value).__name__} {given}")
            key = value.strip().lower().replace("_", "-").replace(" ", "-")
            if key not in self.choices:
                raise ValueError(f"{name} must be {allowed}; got {given}")
            return key
        if self.kind in ("float", "color") and value is None and self.default is None:
            return None
        kind = "a number" if self.kind == "float" else "one number or three numbers r,g,b"
        allowed = f"{kind} in {self.interval}" + (" or None" if self.default is None else "")
        try:
            arr = real_array(name, value, allowed=allowed).astype(float).reshape(-1)
        except ArgumentTypeError:
            raise ArgumentTypeError(f"{name} must be {allowed}; got {type(value).__name__} {given}") from None
        except ValueError:  # NaN or inf
            raise ValueError(f"{name} must be {allowed}; got {given}") from None
        above = (arr > self.low) if self.low_open else (arr >= self.low)
        if arr.size not in ((1,) if self.kind == "float" else (1, 3)) or not (above.all() and (arr <= self.high).all()):
            raise ValueError(f"{name} must be {allowed}; got {given}")
        return float(arr[0]) if arr.size == 1 else tuple(float(x) for x in arr)

    @property
    def interval(self) -> str:
        """The allowed range as text: ``"[0, 1]"``, ``"(0, inf)"``."""
        left = "(" if self.low_open else "["
        right = ")" if math.isinf(self.high) else "]"
        return f"{left}{self.low:g}, {'inf' if math.isinf(self.high) else f'{self.high:g}'}{right}"

    @property
    def control_range(self) -> tuple[float, float]:
        """The range an interactive control offers: ``slider``, else ``[low, high]``."""
        return self.slider if self.slider is not None else (self.low, self.high)


@dataclass(frozen=True)
class Lobe:
    """Where a model's reflectance ``f_r (n·l)`` concentrates, for a viewer ``v``.

    Parameters
    ----------
    axis : {"normal", "mirror", "half"}
        ``"normal"``: spread over the hemisphere about ``n`` (diffuse, or no lobe at all);
        ``"mirror"``: a cone about ``R_v = 2 n (n·v) − v`` (Phong);
        ``"half"``: a distribution of half vectors ``h`` about ``n`` (Blinn–Phong, microfacets),
        whose reflected lobe lies about the mirror direction.
    width : float
        The lobe's angular standard deviation about its axis, in radians (``inf``: no lobe to
        follow; a model with nothing to reflect says so here).  ``(R·v)^e ≈ exp(−e ψ²/2)`` has
        ``1/√e``; Beckmann's ``exp(−tan²θ_h/α²)`` has ``α/√2``.
    quadrature_width : float, optional
        The radial scale of a quadrature rule centred on the axis (defaults to ``width``);
        rules in :mod:`lighting.integrate` place their nodes by it.
    power : float, optional
        For a mirror lobe ``(R_v·l)^e``: ``e``, which tapers the rule's outer end.
    horizon : {None, "v-cavity", "smith"}
        What the shadowing term does near the horizon: the V-cavity ``min(1, G_v, G_l)`` has kinks;
        Smith's ``G1`` falls to 0 within about the roughness of it.  Quadrature places panel breaks there.
    widths : (float, float), optional
        An anisotropic lobe's widths along the tangent ``t`` and the bitangent ``b`` (the principal axes
        of its elliptical cross-section; ``width`` is then their geometric mean).  ``None``: round.
        Only ``"half"`` lobes may be anisotropic.
    quadrature_widths : (float, float), optional
        The radial scales of a quadrature rule along ``t`` and ``b`` (defaults to ``widths``, else
        ``rule_width`` both ways); a rule whose two scales differ follows the ellipse
        (:mod:`lighting.integrate.quadrature`).
    orientation : float
        The azimuth (radians, from ``x̂`` toward ``ŷ`` in the local frame) of the axis ``widths[0]``
        lies along: 0 for a model oriented by its tangent (the local frame's ``t`` is ``x̂``); a wrapper
        that turns the tangent it passes on turns its lobe with it.
    tails : {"gaussian", "ggx"}
        How the lobe falls off beyond its width: like a Gaussian (Phong, Blinn–Phong, Beckmann, Ward), or
        with GGX's long tails ``D ∝ (α² + tan²θ_h)^{-2}`` (GGX, Disney's GTR2), which hold about 5 % of the
        lobe beyond six widths.  Image-based lighting prefilters with a kernel of the same kind.

    Notes
    -----
    A lobe whose half vectors spread as ``exp(−tan²θ_h (cos²φ/α_t² + sin²φ/α_b²))`` (Ward,
    anisotropic Beckmann; GGX and Ashikhmin–Shirley alike near the peak) is round in the stretched
    slopes ``(tan θ_h cos φ/α_t, tan θ_h sin φ/α_b)``: along the azimuth ``φ`` its radial scale is the
    ellipse's radius ``1/√(cos²φ/α_t² + sin²φ/α_b²)``, and equal steps of the stretched azimuth
    ``φ̃ = atan2(α_t sin φ, α_b cos φ)`` hold equal parts of it.  ``(α_t, α_b)`` are the
    ``quadrature_widths``; the engine's local frame has ``t = x̂``, ``b = ŷ``.

    Examples
    --------
    >>> Lobe("half", 0.1, quadrature_widths=(0.3, 0.001)).rule_widths
    (0.3, 0.001)
    >>> Lobe("half", 0.1).isotropic, Lobe("half", 0.1, quadrature_widths=(0.3, 0.001)).isotropic
    (True, False)
    """

    axis: str = "normal"
    width: float = math.inf
    quadrature_width: float | None = None
    power: float | None = None
    horizon: str | None = None
    widths: tuple[float, float] | None = None
    quadrature_widths: tuple[float, float] | None = None
    orientation: float = 0.0
    tails: str = "gaussian"

    def __post_init__(self):
        if self.axis not in ("normal", "mirror", "half"):
            raise ValueError(f"Lobe axis must be 'normal', 'mirror' or 'half'; got {self.axis!r}")
        if self.tails not in ("gaussian", "ggx"):
            raise ValueError(f"Lobe tails must be 'gaussian' or 'ggx'; got {self.tails!r}")
        if self.horizon not in (None, "v-cavity", "smith"):
            raise ValueError(f"Lobe horizon must be None, 'v-cavity' or 'smith'; got {self.horizon!r}")
        for name in ("widths", "quadrature_widths"):
            pair = getattr(self, name)
            if pair is None:
                continue
            try:
                ok = len(pair) == 2 and all(0 < float(x) < math.inf for x in pair)
            except (TypeError, ValueError):
                ok = False
            if not ok:
                raise ValueError(f"Lobe {name} must be None or two finite positive widths (along t, along b); "
                                 f"got {pair!r}")  # fmt: skip
            if self.axis != "half" and pair[0] != pair[1]:
                raise ValueError(f"Lobe {name}: only a 'half' lobe may be anisotropic; got {pair!r} on {self.axis!r}")
            object.__setattr__(self, name, (float(pair[0]), float(pair[1])))
        if not math.isfinite(self.orientation):
            raise ValueError(f"Lobe orientation must be a finite angle in radians; got {self.orientation!r}")

    @property
    def rule_width(self) -> float:
        """The scale quadrature uses: ``quadrature_width``, else ``width``."""
        return self.width if self.quadrature_width is None else self.quadrature_width

    @property
    def rule_widths(self) -> tuple[float, float]:
        """The quadrature scales along ``t`` and ``b``: ``quadrature_widths``, else ``widths``, else ``rule_width``."""
        if self.quadrature_widths is not None:
            return self.quadrature_widths
        if self.widths is not None:
            return self.widths
        return (self.rule_width, self.rule_width)

    @property
    def isotropic(self) -> bool:
        """Round about its axis: the widths and the quadrature scales are equal along ``t`` and ``b``."""
        w = self.widths is None or self.widths[0] == self.widths[1]
        q = self.rule_widths
        return w and q[0] == q[1]


# --------------------------------------------------------------------------- the registry
_REGISTRY: dict[str, type] = {}


def register_model(cls: type, name: str | None = None, *, replace: bool = False) -> type:
    """Register a model class under ``name`` (default: ``cls.name``); usable as a class decorator.

    Scene files (``model = "name"``), the command line and the explorer's model list find
    registered models by this name.

    Parameters
    ----------
    cls : type
        A :class:`~lighting.models.brdf.BRDF` subclass with a ``parameters`` table.
    name : str, optional
        Its name; lower case, words joined by ``-``.
    replace : bool
        Allow replacing a model already registered under ``name``.

    Returns
    -------
    type
        ``cls`` itself.
    """
    name = cls.name if name is None else name
    if not isinstance(name, str) or not name:
        raise ValueError(f"register_model: a model needs a non-empty name; got {name!r} for {cls.__name__}")
    if name in _REGISTRY and _REGISTRY[name] is not cls and not replace:
        raise ValueError(f"register_model: {name!r} is already {_REGISTRY[name].__name__}; pass replace=True")
    if cls.name != name:
        cls.name = name
    _REGISTRY[name] = cls
    return cls


def unregister_model(name: str) -> None:
    """Remove ``name`` from the registry (tests that register a model of their own clean up with it)."""
    _REGISTRY.pop(name, None)


def model_names() -> tuple[str, ...]:
    """Names of the registered models, in registration order (the lectures' order for the built-in ones).

    Returns
    -------
    tuple of str
        The registered names (not the variants': see :func:`model_variants`).
    """
    return tuple(_REGISTRY)


def model_class(name) -> type:
    """The model class registered under ``name``.

    Parameters
    ----------
    name : str
        A registered name, exactly as :func:`model_names` gives it (variant names are not accepted:
        :func:`create_model` takes those).

    Returns
    -------
    type
        The :class:`~lighting.models.brdf.BRDF` subclass.

    Raises
    ------
    ValueError
        For an unknown name, listing the known ones and the nearest ("did you mean").
    """
    cls = _REGISTRY.get(name) if isinstance(name, str) else None
    if cls is None:
        near = difflib.get_close_matches(str(name), list(_REGISTRY), n=1)
        hint = f"did you mean {near[0]!r}? " if near else ""
        raise ValueError(f"model must be one of {', '.join(map(repr, _REGISTRY))}; got {name!r}; {hint}".rstrip("; "))
    return cls


def model_variants() -> dict[str, tuple[type, dict]]:
    """Every entry a model list shows: name → (class, fixed keyword arguments).

    A model's own name comes first, then its named variants (``cls.variants``), such as
    ``"blinn-phong-normalized"`` for ``BlinnPhong(normalized=True)``.

    Returns
    -------
    dict of str to (type, dict)
        A new dict, in registration order: each model's name maps to ``(cls, {})``, each variant's
        name to ``(cls, fixed)`` with a copy of its fixed keyword arguments.
    """
    out = {}
    for name, cls in _REGISTRY.items():
        out[name] = (cls, {})
        for vname, fixed in getattr(cls, "variants", {}).items():
            out[vname] = (cls, dict(fixed))
    return out


def create_model(name, **params):
    """``model_class(name)(**params)``: a model from its registered name (or a variant's).

    Parameters
    ----------
    name : str
        A registered model's name or a variant's (:func:`model_variants`).
    **params
        Constructor keywords; for a variant they override its fixed ones.

    Returns
    -------
    BRDF
        A new instance of the model.

    Raises
    ------
    ValueError
        For an unknown name (as :func:`model_class`) or a parameter the constructor refuses.
    """
    variants = model_variants()
    if isinstance(name, str) and name in variants:
        cls, fixed = variants[name]
        return cls(**{**fixed, **params})
    return model_class(name)(**params)

r"""The explorer's controls: every control value with validated assignment, and the engine objects they make.

:class:`AppState` holds one field per control (model, its parameters, the light, shading options,
plot options) with validated assignment: a bad value raises ``ValueError`` naming the control, the
value and what is allowed.  :data:`CONTROLS` is the table they are validated by (and the command
line's help).  The model list is the engine's registry (:func:`lighting.models.model_variants`):
a model registered anywhere appears here, and the specular part is built from its class and the
values of the controls its parameter table names.  Nothing here imports PyVista or Matplotlib.

Example
-------
>>> state = AppState(model="phong", shininess=20.0, elevation=60.0)
>>> state.specular_model()
Phong(ks=0.5, shininess=20.0)
>>> state.shininess = -1
Traceback (most recent call last):
...
ValueError: shininess must be a number in [0, 1000000]; got -1
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields

import numpy as np

from lighting import AmbientLight, DirectionalLight, Lambert, Material
from lighting._numeric import ArgumentTypeError, abbreviate, check_bool, check_count, check_range, real_array
from lighting.lights import ATTENUATIONS, PointLight, SpotLight, attenuation_polynomial
from lighting.models import model_variants
from lighting.render import SHADING_MODES
from lighting.vec import direction_from_elevation

__all__ = [
    "MODELS",
    "MODEL_LABELS",
    "MODEL_CONTROLS",
    "LIGHT_TYPES",
    "ATTENUATIONS",
    "CHANNELS",
    "CHANNEL_LABELS",
    "FORMS",
    "TERM_NAMES",
    "LIGHT_COLOURS",
    "NDFS",
    "ALBEDO_SAMPLES",
    "Control",
    "CONTROLS",
    "AppState",
    "model_label",
    "model_choices",
]


def model_choices() -> tuple[str, ...]:
    """The explorer's model list now: every registered model and named variant, in registration order.

    Returns
    -------
    tuple of str
        ``tuple(MODELS)``, e.g. ``("lambert", "phong", "blinn-phong", "blinn-phong-normalized",
        "cook-torrance")`` for the built-in models.
    """
    return tuple(model_variants())


def model_label(name: str) -> str:
    """The label a model list shows for a registered model or variant name.

    Each word of the model's own name is capitalized (``"cook-torrance"`` → ``"Cook-Torrance"``);
    a variant adds the rest of its name in words (``"blinn-phong-normalized"`` →
    ``"Blinn-Phong normalized"``).

    Parameters
    ----------
    name : str
        A name of :func:`lighting.models.model_variants`.

    Returns
    -------
    str
        The label.

    Examples
    --------
    >>> [model_label(m) for m in ("lambert", "blinn-phong", "blinn-phong-normalized")]
    ['Lambert', 'Blinn-Phong', 'Blinn-Phong normalized']
    """
    entry = model_variants().get(name)
    base = entry[0].name if entry is not None and entry[0].name else name
    if name != base and name.startswith(base + "-"):
        return model_label(base) + " " + name[len(base) + 1 :].replace("-", " ")
    return "-".join(word[:1].upper() + word[1:] for word in name.split("-"))


class _ModelList(Sequence):
    """The names of the registered models and variants, read from the registry at each use.

    A model registered after the explorer was imported is in the list (and so among the choices of
    the ``model`` control, the command line's ``--model`` and the ``m`` key) from then on.
    """

    def __getitem__(self, index):
        return tuple(model_variants())[index]

    def __len__(self) -> int:
        return len(model_variants())

    def __contains__(self, name) -> bool:
        return name in model_variants()

    def __eq__(self, other):
        return tuple(self) == (tuple(other) if isinstance(other, Sequence) else other)

    def __hash__(self):
        return hash(tuple(self))

    def __repr__(self) -> str:
        return repr(tuple(self))


class _ModelLabels(Mapping):
    """:func:`model_label` of every name of :data:`MODELS`, as a mapping (read from the registry at each use)."""

    def __getitem__(self, name):
        if name not in MODELS:
            raise KeyError(name)
        return model_label(name)

    def __iter__(self):
        return iter(MODELS)

    def __len__(self) -> int:
        return len(MODELS)


#: The model list: every registered model and named variant, in registration order
#: (:func:`lighting.models.model_variants`; the built-in ones in the lectures' order).
MODELS = _ModelList()
MODEL_LABELS = _ModelLabels()
#: Controls that fill the specular model's parameters of the same name (its other parameters keep
#: their defaults).  ``kd`` passes the diffuse albedo ``kd × color``.
MODEL_CONTROLS = ("kd", "ks", "shininess", "roughness", "f0", "ndf")
LIGHT_TYPES = ("directional", "point", "spot", "ambient")
# ATTENUATIONS (imported above) are the engine's falloff presets: (a, b, c) of 1 / (a r² + b r + c).
#: Cost of the albedo readout (BRDF evaluations of the quadrature, fine and coarse rule together).
ALBEDO_SAMPLES = 4096
CHANNELS = ("luminance", "r", "g", "b")
CHANNEL_LABELS = {"luminance": "luminance Y", "r": "red", "g": "green", "b": "blue"}
FORMS = ("classic", "physical")
#: The terms of the illumination equation the explorer switches (emission is always 0 here).
TERM_NAMES = ("ambient", "diffuse", "specular")
LIGHT_COLOURS = {
    "white": (1.0, 1.0, 1.0),
    "warm": (1.0, 0.78, 0.52),
    "cool": (0.62, 0.78, 1.0),
    "red": (1.0, 0.0, 0.0),
    "green": (0.0, 1.0, 0.0),
    "blue": (0.0, 0.0, 1.0),
}
#: The ndf control's choices: those of the registered models' ``ndf`` parameter (Cook-Torrance's NDFs).
NDFS = next(
    (p.choices for cls, _ in model_variants().values() for p in cls.parameters if p.name == "ndf"), ("beckmann",)
)


# =============================================================================== controls
@dataclass(frozen=True)
class Control:
    """How one state field is validated (and how a slider shows it)."""

    kind: str  # "float", "int", "choice", "bool", "rgb", "terms"
    lo: float | None = None
    hi: float | None = None
    choices: tuple = ()
    log: bool = False  # a slider moves log10 of the value
    help: str = ""


CONTROLS: dict[str, Control] = {
    "model": Control("choice", choices=MODELS, help="reflectance model of the specular part (plus Lambert)"),
    "kd": Control("float", 0.0, 1.0, help="diffuse albedo k_d (times the surface colour)"),
    "color": Control("rgb", 0.0, 1.0, help="surface colour (hue of k_d), r,g,b in [0, 1]"),
    "ks": Control("float", 0.0, 1.0, help="specular coefficient k_s"),
    "shininess": Control("float", 0.0, 1e6, log=True, help="Phong / Blinn-Phong exponent e"),
    "roughness": Control("float", 1e-6, 1.0, log=True, help="Cook-Torrance roughness α"),
    "f0": Control("float", 0.0, 1.0, help="Cook-Torrance Fresnel reflectance at normal incidence F0"),
    "ndf": Control("choice", choices=NDFS, help="Cook-Torrance normal distribution"),
    "light": Control("choice", choices=LIGHT_TYPES, help="key light type (ambient: ambient light only)"),
    "elevation": Control("float", -90.0, 90.0, help="light elevation above the image plane, degrees"),
    "azimuth": Control("float", -180.0, 180.0, help="light azimuth in the image plane from +x toward +y, degrees"),
    "intensity": Control("float", 0.0, 10.0, help="key light intensity (irradiance at the nearest sphere point)"),
    "light_color": Control("rgb", 0.0, 1.0, help="key light colour, r,g,b in [0, 1]"),
    "ambient": Control("float", 0.0, 2.0, help="ambient light I_a"),
    "distance": Control("float", 1.5, 20.0, help="point/spot light distance from the sphere centre"),
    "attenuation": Control("choice", choices=tuple(ATTENUATIONS), help="point/spot falloff with distance"),
    "cutoff": Control("float", 0.0, 90.0, help="spot cutoff angle, degrees"),
    "spot_exponent": Control("float", 0.0, 128.0, help="spot exponent (concentration toward the axis)"),
    "mode": Control("choice", choices=SHADING_MODES, help="shading of the lit sphere: per face, vertex or pixel"),
    "form": Control("choice", choices=FORMS, help="classic illumination equation I, or radiance I/π"),
    "terms": Control("terms", choices=TERM_NAMES, help="terms of the illumination equation shown"),
    "tessellation": Control("int", 3, 64, help="latitude bands of the coarse UV sphere (2x as many sectors)"),
    "channel": Control("choice", choices=CHANNELS, help="channel the plots show"),
    "log": Control("bool", help="plot log10(1 + x)"),
    "times_cos": Control("bool", help="plot f_r·(n·l) instead of f_r"),
    "exposure": Control("float", -8.0, 8.0, help="display exposure in stops"),
    "scanline": Control("float", 0.02, 0.98, help="scan line height, fraction of the image from the top"),
}


def _fmt(x: float) -> str:
    return str(int(x)) if float(x).is_integer() and abs(x) < 1e7 else f"{x:g}"


def _allowed(spec: Control) -> str:
    if spec.kind == "rgb":
        return f"one number or three numbers r,g,b in [{_fmt(spec.lo)}, {_fmt(spec.hi)}]"
    kind = "an integer" if spec.kind == "int" else "a number"
    return f"{kind} in [{_fmt(spec.lo)}, {_fmt(spec.hi)}]"


def _refuse(name: str, spec: Control, value, exc_type=ValueError):
    """The one error of a control: names it, what is allowed and the value given (abbreviated)."""
    given = abbreviate(repr(value))
    if exc_type is not ValueError:
        given = f"{type(value).__name__} {given}"
    return exc_type(f"{name} must be {_allowed(spec)}; got {given}")


def _validate(name: str, value):
    """``value`` checked for the control ``name`` (see :data:`CONTROLS`); a named error if it is not allowed.

    Numbers and colours are numbers: text and bytes are refused (``b'1'`` is not 1; the command
    line parses its text first, :meth:`AppState.from_args`), and so are bools.  A wrong type
    raises :class:`~lighting._numeric.ArgumentTypeError` (a TypeError and a ValueError).
    """
    spec = CONTROLS[name]
    if spec.kind == "bool":
        return check_bool(name, value)
    if spec.kind == "choice":
        if isinstance(value, str):
            key = value.strip().lower().replace("_", "-").replace(" ", "-")
            if key in spec.choices:
                return key
            raise ValueError(f"{name} must be one of {', '.join(spec.choices)}; got {abbreviate(repr(value))}")
        raise ArgumentTypeError(
            f"{name} must be one of {', '.join(spec.choices)}; got {type(value).__name__} {abbreviate(repr(value))}"
        )
    if spec.kind == "terms":
        allowed = f"a list of {', '.join(spec.choices)}"
        items = value.split(",") if isinstance(value, str) else value
        if not isinstance(items, (list, tuple, set, frozenset)) or not all(isinstance(t, str) for t in items):
            raise ArgumentTypeError(f"{name} must be {allowed}; got {type(value).__name__} {abbreviate(repr(value))}")
        items = [t.strip().lower() for t in items if t.strip()]
        if any(t not in spec.choices for t in items):
            raise ValueError(f"{name} must be {allowed}; got {abbreviate(repr(value))}")
        return tuple(t for t in spec.choices if t in items)
    if spec.kind == "rgb":
        try:
            arr = real_array(name, value, allowed=_allowed(spec)).astype(np.float64).reshape(-1)
        except ArgumentTypeError:
            raise _refuse(name, spec, value, ArgumentTypeError) from None
        except ValueError:  # NaN or inf
            raise _refuse(name, spec, value) from None
        if arr.size == 1:
            arr = np.repeat(arr, 3)
        if arr.size != 3 or np.any(arr < spec.lo) or np.any(arr > spec.hi):
            raise _refuse(name, spec, value)
        return tuple(float(x) for x in arr)
    # float / int
    value_int = value
    if spec.kind == "int" and isinstance(value, (float, np.floating)):
        # 8.0 is the integer 8; 8.5 is a number but no integer (a slider snaps before, see widgets.py)
        if not (math.isfinite(value) and float(value).is_integer()):
            raise _refuse(name, spec, value)
        value_int = int(value)
    try:
        if spec.kind == "int":
            return check_count(name, value_int, int(spec.lo), int(spec.hi))
        return check_range(name, value, spec.lo, spec.hi)
    except ArgumentTypeError:
        raise _refuse(name, spec, value, ArgumentTypeError) from None
    except ValueError:
        raise _refuse(name, spec, value) from None


def _parse_text(name: str, text: str):
    """Command-line text for a number or a colour: ``"0.5"`` or ``"1,0.5,0"`` (a named error if it is neither)."""
    spec = CONTROLS.get(name, CONTROLS["kd"])
    parts = [p.strip() for p in text.split(",")]
    try:
        numbers = [float(p) for p in parts]
    except ValueError:
        raise ValueError(f"{name} must be {_allowed(spec) if spec.kind == 'rgb' else 'one number or r,g,b'}; "
                         f"got {abbreviate(repr(text))}") from None  # fmt: skip
    return numbers[0] if len(numbers) == 1 else tuple(numbers)


# =============================================================================== state
@dataclass
class AppState:
    """Every control of the explorer, with validated assignment and defaults that look good.

    Assigning a field validates it (``state.kd = 2`` raises ``ValueError``:
    "kd must be a number in [0, 1]; got 2").  Choices accept any case and ``_``
    for ``-``; colours accept one number (grey) or ``r,g,b``; ``terms`` accepts
    ``"ambient,specular"``.  The azimuth wraps into ``(-180, 180]``.

    The surface's diffuse albedo is ``kd × color``; the specular part is white
    (``ks``).  Point and spot lights sit at ``distance`` from the sphere centre in the
    direction given by elevation and azimuth (a spot aims at the centre); their
    intensity is set so that ``intensity`` is the irradiance they deliver at the
    nearest point of the sphere, whatever the falloff.
    """

    model: str = "blinn-phong"
    kd: float = 0.8
    color: tuple = (1.0, 0.42, 0.3)
    ks: float = 0.5
    shininess: float = 40.0
    roughness: float = 0.25
    f0: float = 0.5
    ndf: str = "beckmann"
    light: str = "directional"
    elevation: float = 45.0
    azimuth: float = 135.0
    intensity: float = 1.0
    light_color: tuple = (1.0, 1.0, 1.0)
    ambient: float = 0.08
    distance: float = 4.0
    attenuation: str = "inverse-square"
    cutoff: float = 12.0
    spot_exponent: float = 8.0
    mode: str = "phong"
    form: str = "classic"
    terms: tuple = TERM_NAMES
    tessellation: int = 8
    channel: str = "luminance"
    log: bool = False
    times_cos: bool = False
    exposure: float = 0.0
    scanline: float = 0.4

    def __setattr__(self, name, value):
        if name not in CONTROLS:
            raise AttributeError(f"AppState has no control {name!r}; controls: {', '.join(CONTROLS)}")
        number = isinstance(value, (int, float, np.floating, np.integer)) and not isinstance(value, bool)
        if name == "azimuth" and number and math.isfinite(value):
            value = (float(value) + 180.0) % 360.0 - 180.0
            value = 180.0 if value == -180.0 else value  # (−180, 180]: "from the left" reads 180°
        object.__setattr__(self, name, _validate(name, value))

    # ------------------------------------------------------------------ bulk operations
    def to_dict(self) -> dict:
        """Every control value, by name.

        Returns
        -------
        dict
            Control name → value.
        """
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def update(self, **values) -> set[str]:
        """Assign several controls (all validated first: on error nothing changes); returns the names that changed.

        Parameters
        ----------
        **values
            Control name → new value.

        Returns
        -------
        set of str
            The names whose value changed.
        """
        checked = {}
        trial = AppState(**self.to_dict())
        for k, v in values.items():
            setattr(trial, k, v)
            checked[k] = getattr(trial, k)
        changed = {k for k, v in checked.items() if getattr(self, k) != v}
        for k, v in checked.items():
            setattr(self, k, v)
        return changed

    def reset(self) -> set[str]:
        """Back to the defaults; returns the names that changed.

        Returns
        -------
        set of str
            The names whose value changed.
        """
        return self.update(**AppState().to_dict())

    def copy(self) -> AppState:
        """A copy of the state.

        Returns
        -------
        AppState
            An independent state with the same values.
        """
        return AppState(**self.to_dict())

    @classmethod
    def from_args(cls, args=None, **overrides) -> AppState:
        """A state from parsed command-line options (a namespace or mapping; ``None`` values are skipped).

        ``scene`` (a path) is loaded first with :func:`state_from_scene`; explicit
        options then override it.  ``kd`` may be one number or an RGB triple: a
        triple sets ``kd`` to its largest entry and ``color`` to the triple divided by it.

        Parameters
        ----------
        args : argparse.Namespace or dict, optional
            Parsed options; ``None`` values are skipped, names that are no controls ignored.
        **overrides
            More values, applied after ``args``.

        Returns
        -------
        AppState
            The state.

        Examples
        --------
        >>> AppState.from_args({"model": "Cook_Torrance", "kd": (0.6, 0.3, 0.0)}).color
        (1.0, 0.5, 0.0)
        """
        values = dict(vars(args) if args is not None and not isinstance(args, dict) else (args or {}))
        values.update(overrides)
        values = {k: v for k, v in values.items() if v is not None}
        scene = values.pop("scene", None)
        from .scenes import state_from_scene  # scenes build on the state

        state = state_from_scene(scene) if scene else cls()
        # Command-line text is parsed here, once: the controls themselves take numbers, never text.
        for name in ("kd", "color", "light_color"):
            if isinstance(values.get(name), str):
                values[name] = _parse_text(name, values[name])
        kd = values.pop("kd", None)
        if kd is not None:
            values.update(_split_kd(kd))
        # A command-line namespace carries window options too (size, screenshot, ...): those are not controls.
        state.update(**{k: v for k, v in values.items() if k in CONTROLS})
        return state

    # ------------------------------------------------------------------ engine objects
    @property
    def diffuse_albedo(self) -> np.ndarray:
        """``k_d`` as RGB: ``kd × color``."""
        return self.kd * np.asarray(self.color, dtype=np.float64)

    def specular_model(self):
        """The specular part of the model (None for a Lambertian model, whose only part is the diffuse one).

        The class comes from the registry (:func:`lighting.models.model_variants`: the model's class
        and a variant's fixed arguments); the parameters its table names after a control of
        :data:`MODEL_CONTROLS` take that control's value, the others their defaults.

        Returns
        -------
        BRDF or None
            E.g. ``Phong(ks, shininess)`` for ``model = "phong"``.
        """
        entry = model_variants().get(self.model)
        if entry is None:  # unregistered since it was chosen
            raise ValueError(f"model {self.model!r} is not registered; models: {', '.join(MODELS)}")
        cls, fixed = entry
        if cls.lambertian:
            return None
        values = {p.name: self._model_value(p.name) for p in cls.parameters if p.name in MODEL_CONTROLS}
        return cls(**{**values, **fixed})

    def _model_value(self, name: str):
        return self.diffuse_albedo if name == "kd" else getattr(self, name)

    def brdf(self, parts=("diffuse", "specular")):
        """``Lambert(k_d)`` plus the specular model, restricted to ``parts`` (zero Lambert if none).

        Parameters
        ----------
        parts : collection of str
            ``"diffuse"`` and/or ``"specular"``.

        Returns
        -------
        BRDF
            The model (a sum when both parts are present).
        """
        out = []
        if "diffuse" in parts:
            out.append(Lambert(self.diffuse_albedo))
        spec = self.specular_model() if "specular" in parts else None
        if spec is not None:
            out.append(spec)
        if not out:
            return Lambert(0.0)
        return out[0] if len(out) == 1 else out[0] + out[1]

    def plot_brdf(self):
        """The BRDF the plots show: the parts whose terms are switched on.

        Returns
        -------
        BRDF
            The diffuse and/or specular part, as :attr:`terms` says.
        """
        return self.brdf(self.terms)

    def material(self) -> Material:
        """The surface; its ambient coefficient is the diffuse albedo (``k_a = k_d``).

        Returns
        -------
        Material
            ``Material(self.brdf())``.
        """
        return Material(self.brdf())

    def light_direction(self) -> np.ndarray:
        """Unit vector from the sphere centre toward the light (view frame: x right, y up, z to the viewer).

        Returns
        -------
        ndarray, shape (3,)
            The unit direction, float64.
        """
        # Exact at the horizon: elevation 0 gives z = 0, not cos(90°) = 6e-17 (a light a hair above it).
        return direction_from_elevation(float(self.elevation), float(self.azimuth))

    def light_position(self) -> np.ndarray:
        """Where a point or spot light is: ``distance`` along :meth:`light_direction`.

        Returns
        -------
        ndarray, shape (3,)
            The position, float64.
        """
        return self.distance * self.light_direction()

    def key_light(self):
        """The light of the ``light`` control (None for ambient only).

        Returns
        -------
        Light or None
            A directional, point or spot light.
        """
        d = self.light_direction()
        if self.light == "directional":
            return DirectionalLight(d, color=self.light_color, intensity=self.intensity)
        if self.light == "ambient":
            return None
        att = ATTENUATIONS[self.attenuation]
        r = self.distance - 1.0  # nearest point of the unit sphere
        scale = self.intensity * attenuation_polynomial(r, att)
        pos = self.distance * d
        if self.light == "point":
            return PointLight(pos, color=self.light_color, intensity=scale, attenuation=att)
        return SpotLight(
            position=pos,
            direction=-d,
            color=self.light_color,
            intensity=scale,
            attenuation=att,
            cutoff_deg=self.cutoff,
            exponent=self.spot_exponent,
        )

    def lights(self) -> list:
        """Ambient light ``I_a`` plus the key light.

        Returns
        -------
        list of Light
            The ambient light first.
        """
        key = self.key_light()
        return [AmbientLight(intensity=self.ambient)] + ([key] if key is not None else [])

    def incident_direction(self) -> np.ndarray:
        """The light direction ``l`` at the sphere point facing the viewer (local frame, ``n = +z``).

        Returns
        -------
        ndarray, shape (3,)
            The unit direction, float64.
        """
        if self.light in ("point", "spot"):
            d = self.light_position() - np.array([0.0, 0.0, 1.0])
            return d / np.linalg.norm(d)
        return self.light_direction()

    @property
    def theta_l(self) -> float:
        """Polar angle (rad) of the incident direction from the normal, in ``[0, π]``."""
        d = self.incident_direction()
        return math.atan2(math.hypot(d[0], d[1]), d[2])

    def plot_options(self) -> dict:
        """Keyword arguments of the :mod:`lighting.analysis` functions for the plot controls.

        Returns
        -------
        dict
            ``channel``, ``cosine`` and ``log``.
        """
        return {"channel": self.channel, "cosine": self.times_cos, "log": self.log}

    def quantity_label(self) -> str:
        """What the plots show, e.g. ``log10(1 + f_r·cos θ_l)  [luminance Y]``.

        Returns
        -------
        str
            The label.
        """
        q = "f_r·cos θ_l" if self.times_cos else "f_r"
        q = f"log10(1 + {q})" if self.log else q + " (1/sr)"
        return f"{q}  [{CHANNEL_LABELS[self.channel]}]"


def _split_kd(kd):
    """``kd`` as one number, or an RGB triple split into ``kd`` (its largest entry) and ``color``."""
    if isinstance(kd, (tuple, list, np.ndarray)) and np.size(kd) == 3:
        try:
            arr = real_array("kd", kd, allowed="one number or r,g,b").astype(np.float64).reshape(-1)
        except ValueError:
            return {"kd": kd}  # refused by the kd control, with its message
        top = float(arr.max())
        if top > 0 and np.all(arr >= 0):
            return {"kd": top, "color": tuple(arr / top)}
        return {"kd": top}
    return {"kd": kd}

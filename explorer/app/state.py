r"""The explorer's controls: every control value with validated assignment, and the engine objects they make.

:class:`AppState` holds one value per control (the model, the light, shading and plot options) and the
parameters of every model, each validated on assignment: a bad value raises ``ValueError`` naming the
control or parameter, the value and what is allowed, and leaves the state as it was.  :data:`CONTROLS`
(:mod:`explorer.app.controls`) is the table the controls are validated by (and the command line's help); a
model's parameters are
validated by its own parameter table (:mod:`explorer.app.params`).  The model list is the engine's
registry (:func:`lighting.models.model_variants`): a model registered anywhere appears here, with
controls generated from its table.  Nothing here imports PyVista or Matplotlib.

Example
-------
>>> state = AppState(model="phong", shininess=20.0, elevation=60.0)
>>> state.model_brdf()
Phong(ks=0.5, shininess=20)
>>> state.shininess = -1
Traceback (most recent call last):
...
ValueError: shininess must be a number in [0, inf); got -1
>>> state.model = "ward"; state.model = "phong"; state.shininess  # parameters persist per model
20.0
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from lighting import AmbientLight, DirectionalLight, Lambert, Material
from lighting._text import abbreviate
from lighting._validate import ArgumentTypeError, real_array
from lighting.lights import PointLight, SpotLight, attenuation_polynomial
from lighting.models import BRDFFlags, model_variants
from lighting.vec import direction_from_elevation

from .controls import (
    ALBEDO_SAMPLES,
    ATTENUATIONS,
    CHANNEL_LABELS,
    CHANNELS,
    CONTROLS,
    ENVIRONMENTS,
    FIT_MODELS,
    FORMS,
    LIGHT_COLOURS,
    LIGHT_TYPES,
    MAX_ENTRIES,
    NDFS,
    PANELS,
    TERM_NAMES,
    VIEWS_3D,
    Control,
    parse_text,
    validate,
)
from .lights import engine_lights
from .params import (
    MODEL_LABELS,
    MODELS,
    carries_diffuse,
    implied_parameters,
    model_choices,
    model_label,
    offered_parameters,
    parameter_defaults,
    validate_parameter,
)

__all__ = [
    "MODELS",
    "MODEL_LABELS",
    "DEFAULTS",
    "LIGHT_TYPES",
    "ATTENUATIONS",
    "CHANNELS",
    "CHANNEL_LABELS",
    "FORMS",
    "TERM_NAMES",
    "LIGHT_COLOURS",
    "NDFS",
    "ALBEDO_SAMPLES",
    "FIT_MODELS",
    "PANELS",
    "ENVIRONMENTS",
    "VIEWS_3D",
    "MAX_ENTRIES",
    "Control",
    "CONTROLS",
    "AppState",
    "model_label",
    "model_choices",
]


# =============================================================================== state
#: Every control's default: the explorer's starting look.
DEFAULTS = {
    "model": "blinn-phong",
    "kd": 0.8,
    "color": (1.0, 0.42, 0.3),
    "light": "directional",
    "elevation": 45.0,
    "azimuth": 135.0,
    "intensity": 1.0,
    "light_color": (1.0, 1.0, 1.0),
    "ambient": 0.08,
    "distance": 4.0,
    "attenuation": "inverse-square",
    "cutoff": 12.0,
    "spot_exponent": 8.0,
    "mode": "phong",
    "form": "classic",
    "terms": TERM_NAMES,
    "tessellation": 8,
    "channel": "luminance",
    "log": False,
    "times_cos": False,
    "exposure": 0.0,
    "scanline": 0.4,
    "phi": 180.0,
    "lock": False,
    "panel": "angles",
    "split": False,
    "fit": "ggx",
    "environment": "none",
    "env_rotation": 0.0,
    "env_intensity": 1.0,
    "view3d": "lobe",
    "reference": False,
    "scene_lights": (),
}
#: Controls that wrap into (−180°, 180°].
_ANGLES = ("azimuth", "phi")


class AppState:
    """Every control of the explorer, with validated assignment, and the parameters of every model.

    Assigning a control validates it (``state.kd = 2`` raises ``ValueError``:
    "kd must be a number in [0, 1]; got 2").  Choices accept any case and ``_``
    for ``-``; colours accept one number (grey) or ``r,g,b``; ``terms`` accepts
    ``"ambient,specular"``.  The azimuth and φ wrap into ``(-180, 180]``.

    The model's parameters are kept per model (switching from Phong to Ward and back finds Phong's
    values again): :attr:`params` are the current model's, :meth:`set_param` changes one, validated by
    its table row (:mod:`explorer.app.params`) and then by the model's constructor.  A parameter whose
    name is no control (``shininess``, ``sigma``, ``alpha_x``) may also be read and assigned as an
    attribute, and given to the constructor and :meth:`update`; ``form`` and ``kd`` are controls, so
    Oren–Nayar's ``form`` goes through ``params={"form": "full"}`` or :meth:`set_param`.

    The surface's diffuse albedo is ``kd × color``: the explorer adds ``Lambert(kd × color)`` to a model
    without a diffuse part of its own, and fills the diffuse colour of one that has it
    (:func:`~explorer.app.params.diffuse_parameter`).  Point and spot lights sit at ``distance`` from
    the sphere centre in the direction given by elevation and azimuth (a spot aims at the centre); their
    intensity is set so that ``intensity`` is the irradiance they deliver at the nearest point of the
    sphere, whatever the falloff.

    ``scene_lights`` holds the scene's other lights, light tables in the view frame
    (:mod:`explorer.app.lights`), each checked by the scene loader on assignment; :meth:`lights` adds them
    to the ambient and key light.  Reading it gives a copy: change a light with
    :func:`explorer.app.lights.with_field` and assign the result.

    Parameters
    ----------
    **values
        Controls and parameters of the (new) model, applied with :meth:`update`.
    """

    def __init__(self, **values):
        object.__setattr__(self, "_values", dict(DEFAULTS))
        object.__setattr__(self, "_params", {})
        if values:
            self.update(**values)

    # ------------------------------------------------------------------ attributes
    def __getattr__(self, name):
        values = self.__dict__.get("_values")
        if values is None:
            raise AttributeError(name)
        if name == "scene_lights":  # copies: a table changes only through assignment, which checks it
            return _copy_tables(values[name])
        if name in values:
            return values[name]
        params = self._model_params(values["model"])
        if name in params:
            return params[name]
        raise AttributeError(f"AppState has no control {name!r}; controls: {', '.join(CONTROLS)}; "
                             f"parameters of {values['model']}: {', '.join(params) or 'none'}")  # fmt: skip

    def __setattr__(self, name, value):
        if name in CONTROLS:
            self.update(**{name: value})
            return
        if name in self._model_params(self.model):
            self.set_param(name, value)
            return
        self._unknown(name, value, self.model)

    def _unknown(self, name, value, model):
        if any(name in cls_params for cls_params in _all_parameter_names()):
            have = ", ".join(p.name for p in offered_parameters(model)) or "none"
            raise ValueError(f"{name} must be a parameter of the model {model}, which has {have}; "
                             f"got {name}={abbreviate(repr(value))}")  # fmt: skip
        raise AttributeError(f"AppState has no control {name!r}; controls: {', '.join(CONTROLS)}")

    def __eq__(self, other):
        return isinstance(other, AppState) and self.to_dict() == other.to_dict()

    def __repr__(self):
        return f"AppState(model={self.model!r}, params={self.params!r})"

    def _model_params(self, model: str) -> dict:
        """The stored parameters of ``model`` (its defaults the first time it is asked for)."""
        if model not in self._params:
            self._params[model] = parameter_defaults(model) if model in MODELS else {}
        return self._params[model]

    # ------------------------------------------------------------------ parameters
    @property
    def params(self) -> dict:
        """The current model's parameters (a copy): name → value, the offered rows of its table."""
        return dict(self._model_params(self.model))

    def param(self, name: str):
        """One parameter of the current model.

        Parameters
        ----------
        name : str
            A row of :func:`~explorer.app.params.offered_parameters`.

        Returns
        -------
        object
            Its value.
        """
        params = self._model_params(self.model)
        if name not in params:
            raise ValueError(f"{name} must be a parameter of the model {self.model}: {', '.join(params) or 'none'}")
        return params[name]

    def set_param(self, name: str, value) -> set[str]:
        """Change one parameter of the current model (validated; on error nothing changes).

        Parameters
        ----------
        name : str
            A parameter of the model.
        value
            Its new value.

        Returns
        -------
        set of str
            ``{"params"}`` when the value changed, else empty.
        """
        return self.update(params={name: value})

    # ------------------------------------------------------------------ bulk operations
    def to_dict(self) -> dict:
        """Every control value by name, and ``params``: every model's parameters seen so far.

        Returns
        -------
        dict
            Control name → value; ``"params"`` → {model → {parameter → value}}.
        """
        d = dict(self._values)
        d["scene_lights"] = _copy_tables(d["scene_lights"])
        # Only the models whose parameters were changed: reading a model's defaults changes nothing.
        d["params"] = {m: dict(p) for m, p in self._params.items() if m in MODELS and p != parameter_defaults(m)}
        return d

    def update(self, **values) -> set[str]:
        """Assign several controls and parameters, all validated first (on error nothing changes).

        ``model`` is set first; ``params`` (a dict) and names that are parameters of the model, not
        controls, then set its parameters; the model is built once to let its constructor check them.
        A change of the Fresnel rows carries the rows that follow from it
        (:func:`~explorer.app.params.implied_parameters`: a named metal turns the Fresnel term to the
        conductor's), and turning to a named metal from none also sets ``kd`` to 0 unless the same
        request sets it: a metal reflects no diffuse light, and the explorer's own Lambert part would
        tint it with the surface colour.

        Parameters
        ----------
        **values
            Control name → new value; ``params`` → {parameter → value} of the (new) model.

        Returns
        -------
        set of str
            The names of the controls whose value changed, and ``"params"`` if a parameter of the
            current model did (or the model changed).
        """
        values = dict(values)
        every = values.pop("params", None)
        if every is not None and not isinstance(every, Mapping):
            raise ArgumentTypeError(f"params must be a mapping of parameter names to values; got "
                                    f"{type(every).__name__} {abbreviate(repr(every))}")  # fmt: skip
        new = dict(self._values)
        if "model" in values:
            new["model"] = validate("model", values.pop("model"))
        model = new["model"]
        table = {p.name: p for p in offered_parameters(model)}
        given = dict(every or {})
        for k in [k for k in values if k not in CONTROLS]:
            if k not in table:
                self._unknown(k, values[k], model)
            given[k] = values.pop(k)
        for k, v in values.items():
            number = isinstance(v, (int, float, np.floating, np.integer)) and not isinstance(v, bool)
            if k in _ANGLES and number and math.isfinite(v):
                v = (float(v) + 180.0) % 360.0 - 180.0
                v = 180.0 if v == -180.0 else v  # (−180, 180]: "from the left" reads 180°
            new[k] = validate(k, v)
        params = dict(self._model_params(model))
        for k, v in given.items():
            if k not in table:
                raise ValueError(f"{k} must be a parameter of the model {model}: {', '.join(table) or 'none'}; "
                                 f"got {k}={abbreviate(repr(v))}")  # fmt: skip
            params[k] = validate_parameter(table[k], v)
        if given:
            checked = {k: params[k] for k in given}
            for k, v in implied_parameters(table, params, checked).items():
                params[k] = validate_parameter(table[k], v)
            before = self._model_params(model).get("metal", "none") if model == self.model else "none"
            if "kd" not in values and before == "none" and params.get("metal", "none") != "none":
                new["kd"] = 0.0
            _build(model, params, new)  # the constructor's own checks (e.g. combinations)
        changed = {k for k, v in new.items() if self._values[k] != v}
        if model != self.model or params != self._model_params(model):
            changed.add("params")
        self._values.update(new)
        self._params[model] = params
        return changed

    def reset(self) -> set[str]:
        """Back to the defaults, every model's parameters too; returns the names that changed.

        Returns
        -------
        set of str
            The names whose value changed.
        """
        before = self.to_dict()
        self._params.clear()
        changed = self.update(**DEFAULTS)
        if before["params"].get(self.model, self.params) != self.params:
            changed.add("params")
        return changed

    def copy(self) -> AppState:
        """A copy of the state (every model's parameters included).

        Returns
        -------
        AppState
            An independent state with the same values.
        """
        other = AppState()
        other._values.update(self._values)
        other._params.update({m: dict(p) for m, p in self._params.items()})
        return other

    @classmethod
    def from_args(cls, args=None, **overrides) -> AppState:
        """A state from parsed command-line options (a namespace or mapping; ``None`` values are skipped).

        ``scene`` (a path) is loaded first with :func:`state_from_scene`; explicit
        options then override it.  ``kd`` may be one number or an RGB triple: a
        triple sets ``kd`` to its largest entry and ``color`` to the triple divided by it.
        ``param`` is a list of ``"NAME=VALUE"`` texts for the model's parameters (``--param sigma=0.3``);
        ``ks``, ``shininess``, ``roughness``, ``f0`` and ``ndf`` are parameters too.

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
        >>> AppState.from_args({"model": "oren-nayar", "param": ["sigma=0.5", "form=full"]}).params
        {'sigma': 0.5, 'form': 'full'}
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
                values[name] = parse_text(name, values[name])
        kd = values.pop("kd", None)
        if kd is not None:
            values.update(_split_kd(kd))
        model = values.get("model", state.model)
        table = {p.name: p for p in offered_parameters(validate("model", model))}
        params = {k: values.pop(k) for k in list(values) if k in table and k not in CONTROLS}
        for text in values.pop("param", None) or ():
            params.update(_parse_param(text, table))
        # A command-line namespace carries window options too (size, screenshot, ...): those are not controls.
        state.update(params=params, **{k: v for k, v in values.items() if k in CONTROLS})
        return state

    # ------------------------------------------------------------------ engine objects
    @property
    def diffuse_albedo(self) -> np.ndarray:
        """``k_d`` as RGB: ``kd × color``."""
        return self.kd * np.asarray(self.color, dtype=np.float64)

    @property
    def own_diffuse(self) -> bool:
        """Whether the model carries its own diffuse reflection (then the explorer adds no Lambert part)."""
        return carries_diffuse(model_variants()[self.model][0]) if self.model in MODELS else False

    def model_brdf(self):
        """The chosen model with its parameters (and ``kd × color`` as its diffuse colour, if it has one).

        Returns
        -------
        BRDF
            E.g. ``Phong(ks, shininess)`` for ``model = "phong"``.
        """
        return _build(self.model, self._model_params(self.model), self._values)

    def specular_model(self):
        """The model's part beside the explorer's Lambert: :meth:`model_brdf`, or None for Lambert itself.

        Returns
        -------
        BRDF or None
        """
        brdf = self.model_brdf()
        return None if BRDFFlags.LAMBERTIAN in brdf.flags else brdf

    def brdf(self, parts=("diffuse", "specular")):
        """The surface's BRDF restricted to the terms ``parts`` (zero Lambert if none).

        The explorer's ``Lambert(k_d × colour)`` is the diffuse part of a model without one of its own;
        the model is its ``term`` (``"diffuse"`` for Lambert and Oren–Nayar), as the renderer splits them.

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
        model = self.model_brdf()
        if "diffuse" in parts and not self.own_diffuse:
            out.append(Lambert(self.diffuse_albedo))
        if model.flags & BRDFFlags.of_terms(parts):
            out.append(model)
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
        """The surface; its ambient coefficient is the diffuse albedo (``k_a = k_d × colour``).

        Returns
        -------
        Material
            ``Material(self.brdf(), ambient=kd × color)``.
        """
        return Material(self.brdf(), ambient=self.diffuse_albedo)

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

    def extra_lights(self) -> list:
        """The engine lights of :attr:`scene_lights` (view frame), in their order.

        Returns
        -------
        list of Light
            Built by :func:`explorer.app.lights.engine_lights` (an OpenGL light may add an ambient light).
        """
        tables = self._values["scene_lights"]
        cached = self.__dict__.get("_extra")
        if cached is None or cached[0] is not tables:  # the stored tuple is replaced, never changed
            cached = (tables, [lt for i, t in enumerate(tables) for lt in engine_lights(t, i)])
            object.__setattr__(self, "_extra", cached)
        return list(cached[1])

    def lights(self) -> list:
        """Ambient light ``I_a``, the key light and the extra lights (:attr:`scene_lights`).

        Returns
        -------
        list of Light
            The ambient light first, then the key light (none for ``light = "ambient"``), then
            :meth:`extra_lights`.
        """
        key = self.key_light()
        return [AmbientLight(intensity=self.ambient)] + ([key] if key is not None else []) + self.extra_lights()

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


def _copy_tables(tables) -> tuple:
    """A copy of light tables (their lists too): what the state hands out cannot change what it holds."""
    return tuple({k: list(v) if isinstance(v, list) else v for k, v in t.items()} for t in tables)


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


def _build(model: str, params: dict, values: dict):
    """The model ``model`` with ``params`` (and ``kd × color`` as its diffuse colour); its constructor checks them."""
    from .params import diffuse_parameter

    cls, fixed = model_variants()[model]
    kwargs = {k: v for k, v in params.items()}
    colour = diffuse_parameter(cls)
    if colour is not None:
        kwargs[colour] = values["kd"] * np.asarray(values["color"], dtype=np.float64)
    return cls(**{**kwargs, **fixed})


def _all_parameter_names():
    return [{p.name for p in cls.parameters} for cls, _ in model_variants().values()]


def _parse_param(text, table) -> dict:
    """``"NAME=VALUE"`` from the command line: the value as the parameter's kind reads it."""
    if not isinstance(text, str) or "=" not in text:
        raise ValueError(f"param must be NAME=VALUE with NAME one of {', '.join(table) or 'none'}; "
                         f"got {abbreviate(repr(text))}")  # fmt: skip
    name, value = (x.strip() for x in text.split("=", 1))
    p = table.get(name)
    if p is None:
        raise ValueError(f"param must name a parameter of the model: {', '.join(table) or 'none'}; got {name!r}")
    if p.kind in ("float", "color"):
        value = None if value.lower() == "none" and p.default is None else parse_text(name, value)
    elif p.kind == "bool":
        low = value.lower()
        if low not in ("true", "false", "1", "0", "on", "off", "yes", "no"):
            raise ValueError(f"{name} must be true or false; got {abbreviate(repr(value))}")
        value = low in ("true", "1", "on", "yes")
    return {name: value}

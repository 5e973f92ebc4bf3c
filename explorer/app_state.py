r"""The explorer's state and computations: every control value, and every view's data from the engine.

Nothing here imports PyVista or Matplotlib, so the whole logic of the window can
be driven and checked without a display:

* :class:`AppState` — one field per control (model, its parameters, the light,
  shading options, plot options) with validated assignment: a bad value raises
  ``ValueError`` naming the control, the value and what is allowed.
* :class:`ExplorerModel` — owns the engine's renderers (geometry buffers are
  rasterized once and re-shaded on every change) and computes the data of every
  view: the lit sphere, the coarse sphere lit per vertex and per pixel, the scan
  line profile with its Mach-band metric, the 3D lobe, the polar slice, the
  angle curves, the half/difference image and the directional albedo readout
  (with its error and an "unconverged" flag above 2 %).  :meth:`ExplorerModel.update`
  recomputes only the views whose inputs changed and returns their names; with
  ``only=LIVE_VIEWS`` (a slider being dragged) it recomputes the images and
  keeps the other stale views in ``pending`` for the next full update.

Frames.  The viewer looks down ``−z`` at a unit sphere at the origin: image
right is ``+x``, image up ``+y``, and ``+z`` points at the viewer.  The light's
*elevation* is its angle above the image plane (90° = from the viewer, 0° =
from the side, negative = from behind) and its *azimuth* turns in the image
plane from ``+x`` toward ``+y`` (135° = upper left).  The direction is
:func:`lighting.vec.direction_from_elevation` with ``+z`` as "up" (exact at the
horizon: elevation 0 is ``z = 0``), so the slides' "Lambertian sphere from
several lighting angles" is one drag of the elevation.  The BRDF views use the
local frame of the sphere point that faces the viewer (``n = +z``), so their
incident direction is the light seen from that point; every one of them builds
it through :func:`lighting.vec.spherical_direction`, so a light on or below the
horizon reflects nothing in all of them, and they all sample the lobe's peak
(:func:`lighting.analysis.lobe_peak`), so they report the same peak.

Example
-------
>>> state = AppState(model="phong", shininess=20.0, elevation=60.0)
>>> model = ExplorerModel(state, sphere_size=48, mesh_size=48, lobe_resolution=8)
>>> sorted(model.update())
['albedo', 'coarse', 'halfdiff', 'lobe', 'polar', 'profile', 'sphere', 'theta_d', 'theta_h', 'theta_v']
>>> state.azimuth = 10.0  # turning the light about the view axis: the BRDF plots stay
>>> sorted(model.update())
['coarse', 'profile', 'sphere']
>>> state.elevation = 30.0  # a new incident angle: the plots that depend on it follow
>>> sorted(model.update())
['albedo', 'coarse', 'lobe', 'polar', 'profile', 'sphere', 'theta_h', 'theta_v']
>>> state.shininess = 80.0  # while a slider is dragged: the images at once, the rest on release
>>> sorted(model.update(only=LIVE_VIEWS)), sorted(model.pending)
(['coarse', 'sphere'], ['albedo', 'halfdiff', 'lobe', 'polar', 'profile', 'theta_d', 'theta_h', 'theta_v'])
>>> sorted(model.update()), model.pending
(['albedo', 'halfdiff', 'lobe', 'polar', 'profile', 'theta_d', 'theta_h', 'theta_v'], set())
>>> state.shininess = -1
Traceback (most recent call last):
...
ValueError: shininess must be a number in [0, 1000000]; got -1
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, fields
from functools import cached_property, lru_cache

import numpy as np

from lighting import AmbientLight, BlinnPhong, CookTorrance, DirectionalLight, Lambert, Material, Phong
from lighting._numeric import ArgumentTypeError, abbreviate, check_bool, check_count, check_range, real_array
from lighting.analysis.analysis import (
    half_diff_image,
    lobe_mesh,
    reciprocity_pair,
    theta_d_curve,
    theta_h_curve,
    theta_v_curve,
)
from lighting.analysis.machband import LUMA, edge_jump_metric, scanline_profile
from lighting.integrate.integrate import UNCONVERGED_RELATIVE_ERROR, directional_albedo
from lighting.lights.punctual import PointLight, SpotLight
from lighting.render.image import srgb_to_linear
from lighting.render.mesh import uv_sphere
from lighting.render.renderer import SHADING_MODES, AnalyticSphere, Renderer
from lighting.render.sphere import sphere_camera
from lighting.shading.equation import shade
from lighting.vec import direction_from_elevation, spherical_direction

__all__ = [
    "MODELS",
    "MODEL_LABELS",
    "LIGHT_TYPES",
    "ATTENUATIONS",
    "CHANNELS",
    "FORMS",
    "TERM_NAMES",
    "LIGHT_COLOURS",
    "NDFS",
    "CONTROLS",
    "VIEWS",
    "LIVE_VIEWS",
    "AppState",
    "ExplorerModel",
    "SphereView",
    "CoarseView",
    "ProfileView",
    "LobeView",
    "PolarView",
    "CurveView",
    "HalfDiffView",
    "AlbedoView",
    "ALBEDO_SAMPLES",
    "state_from_scene",
    "encode8",
]

MODELS = ("lambert", "phong", "blinn-phong", "blinn-phong-normalized", "cook-torrance")
MODEL_LABELS = {
    "lambert": "Lambert",
    "phong": "Phong",
    "blinn-phong": "Blinn-Phong",
    "blinn-phong-normalized": "Blinn-Phong normalized",
    "cook-torrance": "Cook-Torrance",
}
LIGHT_TYPES = ("directional", "point", "spot", "ambient")
#: ``(a, b, c)`` of the falloff ``1 / (a r² + b r + c)`` (:class:`lighting.PointLight`).
ATTENUATIONS = {"none": (0.0, 0.0, 1.0), "linear": (0.0, 1.0, 0.0), "inverse-square": (1.0, 0.0, 0.0)}
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
NDFS = CookTorrance.NDFS


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
        # 8.0 is the integer 8; 8.5 is a number but no integer (a slider snaps before, see app.py)
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
        """Every control value, by name."""
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def update(self, **values) -> set[str]:
        """Assign several controls (all validated first: on error nothing changes); returns the names that changed."""
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
        """Back to the defaults; returns the names that changed."""
        return self.update(**AppState().to_dict())

    def copy(self) -> AppState:
        return AppState(**self.to_dict())

    @classmethod
    def from_args(cls, args=None, **overrides) -> AppState:
        """A state from parsed command-line options (a namespace or mapping; ``None`` values are skipped).

        ``scene`` (a path) is loaded first with :func:`state_from_scene`; explicit
        options then override it.  ``kd`` may be one number or an RGB triple: a
        triple sets ``kd`` to its largest entry and ``color`` to the triple divided by it.

        Examples
        --------
        >>> AppState.from_args({"model": "Cook_Torrance", "kd": (0.6, 0.3, 0.0)}).color
        (1.0, 0.5, 0.0)
        """
        values = dict(vars(args) if args is not None and not isinstance(args, dict) else (args or {}))
        values.update(overrides)
        values = {k: v for k, v in values.items() if v is not None}
        scene = values.pop("scene", None)
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
        """The specular part of the model (None for Lambert)."""
        m = self.model
        if m == "phong":
            return Phong(self.ks, self.shininess)
        if m in ("blinn-phong", "blinn-phong-normalized"):
            return BlinnPhong(self.ks, self.shininess, normalized=m == "blinn-phong-normalized")
        if m == "cook-torrance":
            return CookTorrance(self.ks, self.roughness, self.f0, ndf=self.ndf)
        return None

    def brdf(self, parts=("diffuse", "specular")):
        """``Lambert(k_d)`` plus the specular model, restricted to ``parts`` (zero Lambert if none)."""
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
        """The BRDF the plots show: the parts whose terms are switched on."""
        return self.brdf(self.terms)

    def material(self) -> Material:
        """The surface; its ambient coefficient is the diffuse albedo (``k_a = k_d``)."""
        return Material(self.brdf())

    def light_direction(self) -> np.ndarray:
        """Unit vector from the sphere centre toward the light (view frame: x right, y up, z to the viewer)."""
        # Exact at the horizon: elevation 0 gives z = 0, not cos(90°) = 6e-17 (a light a hair above it).
        return direction_from_elevation(float(self.elevation), float(self.azimuth))

    def light_position(self) -> np.ndarray:
        """Where a point or spot light is: ``distance`` along :meth:`light_direction`."""
        return self.distance * self.light_direction()

    def key_light(self):
        """The light of the ``light`` control (None for ambient only)."""
        d = self.light_direction()
        if self.light == "directional":
            return DirectionalLight(d, color=self.light_color, intensity=self.intensity)
        if self.light == "ambient":
            return None
        att = ATTENUATIONS[self.attenuation]
        r = self.distance - 1.0  # nearest point of the unit sphere
        scale = self.intensity * (att[0] * r * r + att[1] * r + att[2])
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
        """Ambient light ``I_a`` plus the key light."""
        key = self.key_light()
        return [AmbientLight(intensity=self.ambient)] + ([key] if key is not None else [])

    def incident_direction(self) -> np.ndarray:
        """The light direction ``l`` at the sphere point facing the viewer (local frame, ``n = +z``)."""
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
        """Keyword arguments of the :mod:`lighting.analysis.analysis` functions for the plot controls."""
        return {"channel": self.channel, "cosine": self.times_cos, "log": self.log}

    def quantity_label(self) -> str:
        """What the plots show, e.g. ``log10(1 + f_r·cos θ_l)  [luminance Y]``."""
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


# =============================================================================== scenes
def state_from_scene(path) -> AppState:
    """An :class:`AppState` from a scene file: the first object's material and the scene's lights.

    The material's Lambert part gives ``kd``/``color``, its specular part the
    model and parameters (an OpenGL material is read as Lambert + Blinn-Phong).
    Ambient lights add up to ``ambient``; the first other light becomes the key
    light, its direction seen from the scene's camera (so it lights the explorer's
    sphere from the same side of the picture) and, for point and spot lights, at
    the same distance from the object's centre, with the irradiance it delivers
    there.  Render options (mode, form, terms, exposure) are taken too.
    """
    try:
        from lighting.scene.scene import GLLight, gl_material_to_engine, load_scene
    except ImportError:  # pragma: no cover - the module ships with the engine
        raise ValueError("scene files need lighting.scene.scene") from None
    from lighting import gl

    scene = load_scene(path)
    state = AppState()
    obj = scene.objects[0]
    material = obj.material
    if isinstance(material, gl.Material):
        material = gl_material_to_engine(material)
    _apply_material(state, material, str(path))
    centre = np.asarray(getattr(obj.geometry, "center", (0.0, 0.0, 0.0)), dtype=np.float64)
    if hasattr(obj.geometry, "vertices"):
        centre = np.asarray(obj.geometry.vertices, dtype=np.float64).mean(axis=0)
    lights = scene.object_lights(0)
    _apply_lights(state, lights, scene.camera, centre, GLLight)
    if any(isinstance(lt, GLLight) for lt in lights):
        # OpenGL's scene ambient light adds to the lights' own ambient parts.
        state.ambient = min(state.ambient + float(np.mean(scene.opengl.scene_ambient[:3])), 2.0)
    state.update(
        mode=scene.object_mode(0),
        form=scene.render.form,
        terms=[t for t in scene.render.terms if t in TERM_NAMES],
        exposure=min(max(scene.image.exposure, -8.0), 8.0),
    )
    return state


def _apply_material(state: AppState, material: Material, source: str):
    kd = np.zeros(3)
    spec = None
    for p in material.brdf.parts:
        if isinstance(p, Lambert):
            kd = kd + p.kd
        elif spec is None:
            spec = p
    top = float(kd.max())
    values = {"kd": min(top, 1.0)}
    if top > 0:
        values["color"] = tuple(np.minimum(kd / top, 1.0))
    if spec is None:
        values["model"] = "lambert"
    else:
        values["ks"] = min(float(np.max(spec.ks)), 1.0)
        if isinstance(spec, Phong):
            values.update(model="phong", shininess=spec.shininess)
        elif isinstance(spec, BlinnPhong):
            values.update(model="blinn-phong-normalized" if spec.normalized else "blinn-phong")
            values["shininess"] = spec.shininess
        elif isinstance(spec, CookTorrance):
            values.update(model="cook-torrance", roughness=min(spec.roughness, 1.0), f0=float(np.max(spec.f0)))
            values["ndf"] = spec.ndf
        else:
            raise ValueError(f"{source}: the explorer cannot show the model {type(spec).__name__}")
    state.update(**values)


def _apply_lights(state: AppState, lights, camera, centre, gl_light_type):
    # View frame of the scene's camera: right, up, toward the viewer.
    frame = np.stack([camera.right, camera.true_up, -camera.forward])
    ambient, key = 0.0, None
    for lt in lights:
        if isinstance(lt, gl_light_type):
            g = lt.light
            pos = np.asarray(g.position, dtype=np.float64)
            colour = np.asarray(g.diffuse[:3], dtype=np.float64)
            ambient += float(np.mean(g.ambient[:3]))
            if key is None and np.any(colour > 0):
                key = ("directional", pos[:3], colour, 1.0) if pos[3] == 0 else ("point", pos[:3] / pos[3], colour, 1.0)
            continue
        if isinstance(lt, AmbientLight):
            ambient += float(np.mean(lt.radiant))
            continue
        if key is not None:
            continue
        if isinstance(lt, DirectionalLight):
            key = ("directional", lt.direction, lt.color, lt.intensity)
        elif isinstance(lt, PointLight):
            kind = "spot" if isinstance(lt, SpotLight) else "point"
            key = (kind, lt.position, lt.color, lt.intensity, lt)
    values = {"ambient": min(ambient, 2.0)}
    if key is None:
        values["light"] = "ambient"
    else:
        kind, vec, colour, intensity = key[:4]
        vec = np.asarray(vec, dtype=np.float64)
        d = vec if kind == "directional" else vec - centre
        dist = float(np.linalg.norm(d))
        view = frame @ (d / dist) if dist > 0 else np.array([0.0, 0.0, 1.0])
        colour = np.asarray(colour, dtype=np.float64)
        top = float(colour.max())
        values.update(
            light=kind,
            elevation=math.degrees(math.asin(float(np.clip(view[2], -1.0, 1.0)))),
            azimuth=math.degrees(math.atan2(view[1], view[0])),
            light_color=tuple(colour / top) if top > 0 else (1.0, 1.0, 1.0),
        )
        irradiance = top * intensity
        if kind != "directional":
            lt = key[4] if len(key) > 4 else None
            a, b, c = lt.attenuation if lt is not None else (0.0, 0.0, 1.0)
            falloff = a * dist * dist + b * dist + c
            irradiance = irradiance / falloff if falloff > 0 else irradiance
            values["distance"] = min(max(dist, 1.5), 20.0)
            named = {v: k for k, v in ATTENUATIONS.items()}
            values["attenuation"] = named.get(tuple(float(x) for x in (a, b, c)), "inverse-square")
            if kind == "spot":
                values["cutoff"] = lt.cutoff_deg if lt.cutoff_deg <= 90 else 90.0
                values["spot_exponent"] = min(lt.exponent, 128.0)
        values["intensity"] = min(max(irradiance, 0.0), 10.0)
    state.update(**values)


# =============================================================================== views
@dataclass(frozen=True, eq=False)
class SphereView:
    """The lit sphere: linear image, its 8-bit sRGB encoding and coverage.

    ``geometry`` is ``"exact sphere"`` (ray-cast, per pixel) in Phong mode and
    ``"<n> triangles"`` (the coarse sphere) in flat and Gouraud mode.
    """

    image: np.ndarray  # (H, W, 3) linear
    rgb8: np.ndarray  # (H, W, 3) uint8 sRGB
    coverage: np.ndarray  # (H, W) bool
    mode: str
    geometry: str
    clipped: int  # pixels clipped by the encoding

    @cached_property
    def brightest(self) -> tuple[int, int]:
        """``(row, column)`` of the pixel of largest luminance."""
        y = self.image.astype(np.float64) @ LUMA
        k = int(np.argmax(y))
        return divmod(k, y.shape[1])


@dataclass(frozen=True, eq=False)
class CoarseView:
    """The coarse sphere, lit per vertex (Gouraud) and per pixel (Phong interpolation).

    The engine's Gouraud image (:attr:`gouraud`) is rendered when first asked for: the
    window draws the vertex colours, only the scan-line profile and its metric need it.
    """

    vertices: np.ndarray  # (V, 3)
    faces: np.ndarray  # (F, 3)
    vertex_colors: np.ndarray  # (V, 3) linear: the engine's lighting at each vertex
    vertex_rgb8: np.ndarray  # (V, 3) uint8 sRGB
    phong: np.ndarray  # (H, W, 3) linear, normals interpolated
    phong_rgb8: np.ndarray
    triangle_id: np.ndarray  # (H, W) int, -1 off the sphere
    coverage: np.ndarray  # (H, W) bool
    tessellation: int
    exposure: float
    render_gouraud: Callable[[], np.ndarray] = field(repr=False, default=None)

    @cached_property
    def gouraud(self) -> np.ndarray:
        """``(H, W, 3)`` linear: the engine's Gouraud image, colours interpolated (rendered once)."""
        return self.render_gouraud()

    @cached_property
    def gouraud_rgb8(self) -> np.ndarray:
        """The engine's Gouraud image, encoded (the window draws the vertex colours instead)."""
        return _encode(self.gouraud, self.coverage, self.exposure)[0]

    @property
    def n_triangles(self) -> int:
        return len(self.faces)


@dataclass(frozen=True, eq=False)
class ProfileView:
    """Intensity along one scan line of the coarse sphere, Gouraud against Phong interpolation.

    ``x`` is the horizontal position of each pixel centre in sphere units
    (``−1 … 1``), ``y`` the height of the row; ``edges`` are the positions where
    the scan line crosses a triangle edge.  The metrics are
    :func:`lighting.analysis.machband.edge_jump_metric` over every twelfth row of each image.
    """

    row: int
    y: float
    x: np.ndarray
    gouraud: np.ndarray
    phong: np.ndarray
    gouraud_d2: np.ndarray  # second differences, at x[1:-1]
    phong_d2: np.ndarray
    edges: np.ndarray
    metric_gouraud: float
    metric_phong: float
    channel: str
    slope: float  # mean |ΔI| along the row (both curves): the scale of the second differences


@dataclass(frozen=True, eq=False)
class LobeView:
    """The 3D lobe, drawn with the light in the ``x``–``z`` plane on the ``−x`` side (mirror on ``+x``).

    ``vertices`` are scaled so the largest radius is 1; ``values`` are the plotted
    quantity (what the colours show) and ``peak`` its largest value.
    """

    vertices: np.ndarray
    faces: np.ndarray
    values: np.ndarray
    peak: float
    scale: float  # display units per plotted unit
    light: np.ndarray  # unit incident direction (local frame)
    mirror: np.ndarray
    peak_direction: np.ndarray
    below_horizon: bool


@dataclass(frozen=True, eq=False)
class PolarView:
    """The polar slice in the plane of incidence: fixed light (swept view) and fixed view (swept light).

    ``angles`` are signed, negative on the light's side (see
    :func:`lighting.analysis.polar_slice`); ``theta_in`` is the incident polar
    angle (clamped to 90° when the light is below the horizon).
    """

    angles: np.ndarray
    light_fixed: np.ndarray
    view_fixed: np.ndarray
    view_angles: np.ndarray
    theta_in: float
    below_horizon: bool


@dataclass(frozen=True, eq=False)
class CurveView:
    """One angle curve: ``values`` against ``angles`` (rad), with ``markers`` (rad) to draw."""

    variable: str
    angles: np.ndarray
    values: np.ndarray
    markers: tuple
    params: dict


@dataclass(frozen=True, eq=False)
class HalfDiffView:
    """The BRDF over ``(θ_h, θ_d)`` at ``φ_d = 90°``: rows θ_d, columns θ_h; ``marker`` = (θ_h, θ_d) of the mirror."""

    theta_h: np.ndarray
    theta_d: np.ndarray
    values: np.ndarray
    peak: float
    marker: tuple


@dataclass(frozen=True, eq=False)
class AlbedoView:
    """The directional albedo ``ρ(θ_v) = ∫ f_r(v, l) (n·l) dω_l`` of the plotted BRDF, with its error.

    ``theta_v`` is the fixed view of the polar panel's dashed slice (``θ_v = θ_l``, 90° when the
    light is below the horizon, where ρ is 0).  ``value`` and ``error`` are the plot channel's
    (luminance: the Rec. 709 weights of the RGB values and errors); ``unconverged`` flags a
    relative error above 2 % (:attr:`lighting.integrate.Estimate.unconverged`), as the accuracy
    report does.  ``rgb`` and ``rgb_error`` are the whole estimate.
    """

    theta_v: float
    value: float
    error: float
    relative_error: float
    unconverged: bool
    rgb: np.ndarray
    rgb_error: np.ndarray
    method: str
    samples: int


MATERIAL_FIELDS = frozenset({"model", "kd", "color", "ks", "shininess", "roughness", "f0", "ndf"})
LIGHT_FIELDS = frozenset(
    {"light", "elevation", "azimuth", "intensity", "light_color", "ambient", "distance", "attenuation", "cutoff"}
    | {"spot_exponent"}
)
#: Pseudo-field: the incident polar angle θ_l at the facing point.  The BRDF views depend on it alone
#: (isotropic models; the plots are drawn in the plane of incidence), so turning the light about the
#: viewing axis (azimuth) re-shades the images but leaves the plots as they are.
INCIDENT_FIELDS = frozenset({"incidence"})
PLOT_FIELDS = frozenset({"channel", "log", "times_cos"})
SHADING_FIELDS = MATERIAL_FIELDS | LIGHT_FIELDS | {"form", "terms", "exposure", "tessellation"}

#: Which controls each view depends on.
VIEW_DEPENDENCIES = {
    "sphere": SHADING_FIELDS | {"mode"},
    "coarse": SHADING_FIELDS,
    "profile": SHADING_FIELDS | {"scanline", "channel"},
    "lobe": MATERIAL_FIELDS | INCIDENT_FIELDS | PLOT_FIELDS | {"terms"},
    "polar": MATERIAL_FIELDS | INCIDENT_FIELDS | PLOT_FIELDS | {"terms"},
    "theta_v": MATERIAL_FIELDS | INCIDENT_FIELDS | PLOT_FIELDS | {"terms"},
    "theta_h": MATERIAL_FIELDS | INCIDENT_FIELDS | PLOT_FIELDS | {"terms"},
    "theta_d": MATERIAL_FIELDS | PLOT_FIELDS | {"terms"},
    "halfdiff": MATERIAL_FIELDS | PLOT_FIELDS | {"terms"},
    "albedo": MATERIAL_FIELDS | INCIDENT_FIELDS | {"terms", "channel"},
}
VIEWS = tuple(VIEW_DEPENDENCIES)
#: The views that follow a slider while it is dragged: the engine's images, cheap and where the eye
#: is.  The scan-line profile, the lobe and the plots wait for the release (``update(only=...)``).
LIVE_VIEWS = frozenset({"sphere", "coarse"})


@lru_cache(maxsize=64)
def _srgb_thresholds(exposure: float, dtype_name: str) -> np.ndarray:
    """Linear values at which the 8-bit sRGB code steps up, divided by ``2**exposure``, in ``dtype``.

    Code ``k`` starts where ``255 · srgb(x) = k − ½`` (``encode_srgb8`` rounds), i.e. at
    ``srgb_to_linear((k − ½)/255)``; the 256th entry is 1, where clipping starts.  Each
    threshold is rounded *up* to the dtype, so ``x >= t`` in that dtype is the same test as
    in float64.
    """
    dt = np.dtype(dtype_name)
    t = np.append(srgb_to_linear((np.arange(1, 256) - 0.5) / 255.0), 1.0) / 2.0**exposure
    t_dt = t.astype(dt)
    below = t_dt.astype(np.float64) < t
    t_dt[below] = np.nextafter(t_dt[below], dt.type(np.inf))
    return t_dt


@lru_cache(maxsize=64)
def _srgb_bucket_table(exposure: float):
    """Look-up tables that give float32 sRGB codes in two steps, or None if they cannot be exact.

    A float32 ``x >= 0`` falls in one of 65536 *buckets* by its top 16 bits (sign, exponent and
    7 mantissa bits): a bucket spans a relative width of at most 2⁻⁷ = 0.78 %.  The 8-bit
    code steps up at linear values at least 0.9 % apart (the closest pair, codes 254 and 255:
    ``((254.5/255 + 0.055)/(253.5/255 + 0.055))^2.4 = 1.009``), and more below, so a bucket
    holds at most one step: the code of ``x`` is the code of its bucket's smallest value,
    plus one if ``x`` reaches the next step.  Returns ``(first, step)``: the code of each
    bucket's smallest value (uint8, 65536 entries; 0 for negatives, 255 for inf and NaN) and
    the step thresholds by code (float32, 256 entries, the last NaN so that no code passes
    255).  The one-step property is checked on every bucket; None if it fails.
    """
    thr = _srgb_thresholds(exposure, "float32")[:255]
    keys = np.arange(1 << 16, dtype=np.uint32)
    first = np.searchsorted(thr, (keys << 16).view(np.float32), side="right")
    finite = keys[:0x7F80]  # positive finite buckets; 0x7F80 starts inf
    last = np.searchsorted(thr, ((finite << 16) | 0xFFFF).view(np.float32), side="right")
    if np.any(last - first[:0x7F80] > 1):  # pragma: no cover - the sRGB curve never does this
        return None
    step = np.append(thr, np.float32(np.nan)).astype(np.float32)
    return first.astype(np.uint8), step


def encode8(image, coverage=None, exposure: float = 0.0):
    """8-bit sRGB codes of a linear image: :func:`lighting.render.image.encode_srgb8` (clamp) by table look-up.

    The same codes as ``encode_srgb8(image, exposure=exposure)``, without evaluating the sRGB
    curve at every pixel.  Code ``k`` starts at the linear value ``t_k = srgb_to_linear((k −
    ½)/255) / 2^exposure``, so the code of ``x`` is the number of ``t_k <= x``.  For float32 images
    two table look-ups find it (:func:`_srgb_bucket_table`: the top 16 bits of ``x`` give the
    code of its bucket, one comparison adds the step inside the bucket), about five times faster
    than a binary search among the 255 ``t_k``, which float64 images still use.  Pixels outside
    ``coverage`` are black.  Returns ``(rgb8, clipped)``: codes ``(..., 3)`` and the number of
    covered pixels with a channel above 1 after the exposure (counted as the engine counts them).

    Examples
    --------
    >>> from lighting.render.image import encode_srgb8
    >>> img = np.array([[[0.0, 0.5, 2.0], [0.001, 0.2, 1.0]]])
    >>> bool(np.array_equal(encode8(img)[0], encode_srgb8(img)[0]))
    True
    >>> bool(np.array_equal(encode8(img.astype(np.float32))[0], encode_srgb8(img)[0]))
    True
    """
    img = np.asarray(image)
    if img.dtype not in (np.float32, np.float64):
        img = img.astype(np.float64)
    x = np.ascontiguousarray(img)
    exposure = float(exposure)
    thr = _srgb_thresholds(exposure, x.dtype.name)
    table = _srgb_bucket_table(exposure) if x.dtype == np.float32 else None
    if table is None:
        codes = np.searchsorted(thr[:255], x, side="right").astype(np.uint8)
    else:
        first, step = table
        codes = first.take(x.view(np.uint32) >> 16)
        codes += x >= step.take(codes)
    cov = None if coverage is None else np.asarray(coverage, dtype=bool).reshape(-1)
    if cov is not None:
        codes *= cov.reshape(x.shape[:-1] + (1,))
    # Clipped: the engine's test ``x · 2^exposure > 1`` in float64, made only on the values that
    # can pass it (at least one step of the dtype below the clip level; usually none).
    near = np.flatnonzero(x.reshape(-1) >= np.nextafter(thr[255], x.dtype.type(0)))
    clipped = 0
    if near.size:
        over = near[x.reshape(-1)[near].astype(np.float64) * 2.0**exposure > 1.0] // 3
        if cov is not None:
            over = over[cov[over]]
        clipped = int(np.count_nonzero(np.diff(over) != 0) + 1) if over.size else 0
    return codes, clipped


def _encode(image, coverage, exposure):
    return encode8(image, coverage, exposure)


def _coarse_camera(size: int):
    # The same framing as the lit sphere's: orthographic from +z, the unit sphere filling 1/1.08 of the height.
    return sphere_camera(size)


class ExplorerModel:
    """Computes every view of the explorer from the engine, recomputing only what a change affects.

    Parameters
    ----------
    state : AppState, optional
        The controls (a fresh default state if omitted); the model reads it on
        every :meth:`update`, so the window changes ``model.state`` and calls
        ``update()``.
    sphere_size : int
        Pixels (width and height) of the lit sphere image.
    mesh_size : int
        Pixels of the coarse sphere images.
    lobe_resolution : int
        Rings of the lobe mesh (:func:`lighting.analysis.lobe_mesh`).
    dtype : float32 or float64
        Shading precision (float32: faster, relative error of a few 1e-7).

    Attributes
    ----------
    views : dict
        ``"sphere"`` :class:`SphereView`, ``"coarse"`` :class:`CoarseView`,
        ``"profile"`` :class:`ProfileView`, ``"lobe"`` :class:`LobeView`, ``"polar"``
        :class:`PolarView`, ``"theta_v"``, ``"theta_h"``, ``"theta_d"``
        :class:`CurveView`, ``"halfdiff"`` :class:`HalfDiffView`, ``"albedo"`` :class:`AlbedoView`.
    """

    def __init__(self, state=None, *, sphere_size=360, mesh_size=256, lobe_resolution=40, dtype=np.float32):
        self.state = state if state is not None else AppState()
        for name, v in (("sphere_size", sphere_size), ("mesh_size", mesh_size)):
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 16 <= v <= 4096:
                raise ValueError(f"{name} must be an integer in [16, 4096]; got {v!r}")
        self.sphere_size, self.mesh_size = int(sphere_size), int(mesh_size)
        self.lobe_resolution = int(lobe_resolution)
        self.dtype = dtype
        self.views: dict = {}
        #: Views whose controls changed but which an ``update(only=...)`` left for later.
        self.pending: set[str] = set()
        self._snapshot: dict | None = None
        self._sphere = Renderer(AnalyticSphere(), sphere_camera(self.sphere_size), dtype=dtype)
        self._meshes: dict = {}
        self._renderers: dict = {}

    # ------------------------------------------------------------------ caches
    def mesh(self, tessellation: int):
        """The coarse UV sphere with ``tessellation`` bands and twice as many sectors (cached)."""
        if tessellation not in self._meshes:
            self._meshes[tessellation] = uv_sphere(tessellation, 2 * tessellation)
        return self._meshes[tessellation]

    def mesh_renderer(self, tessellation: int, size: int) -> Renderer:
        """A renderer of the coarse sphere at ``size`` pixels; rasterized once, kept for the last 12 used."""
        key = (tessellation, size)
        r = self._renderers.pop(key, None)
        if r is None:
            r = Renderer(self.mesh(tessellation), _coarse_camera(size), dtype=self.dtype)
        self._renderers[key] = r
        while len(self._renderers) > 12:
            self._renderers.pop(next(iter(self._renderers)))
        return r

    def is_rasterized(self, tessellation: int, size: int) -> bool:
        """Whether the renderer of that coarse sphere at that size is in the cache."""
        return (tessellation, size) in self._renderers

    @property
    def rasterizations(self) -> int:
        """Rasterizations (or ray casts) so far of the renderers in the cache."""
        return self._sphere.rasterizations + sum(r.rasterizations for r in self._renderers.values())

    # ------------------------------------------------------------------ updates
    def _inputs(self) -> dict:
        d = self.state.to_dict()
        d["incidence"] = round(self.state.theta_l, 12)
        return d

    def changed_fields(self) -> set[str]:
        """Controls whose value differs from the last :meth:`update` (all of them before the first).

        Includes the pseudo-field ``"incidence"`` when the incident polar angle changed.
        """
        now = self._inputs()
        if self._snapshot is None:
            return set(now)
        return {k for k, v in now.items() if v != self._snapshot[k]}

    def stale_views(self, changed=None) -> set[str]:
        """Views that depend on the changed controls."""
        changed = self.changed_fields() if changed is None else set(changed)
        views = {v for v, deps in VIEW_DEPENDENCIES.items() if deps & changed}
        if "sphere" in views and changed <= {"tessellation"} and self.state.mode == "phong":
            views.discard("sphere")  # the exact sphere has no tessellation
        if self._snapshot is None:
            views = set(VIEWS)
        return views

    def update(self, changed=None, *, only=None) -> set[str]:
        """Recompute the views whose controls changed since the last call; return their names.

        ``changed`` adds control names to treat as changed even if their values are
        equal.  ``only`` restricts the work to those views (a slider being dragged
        updates :data:`LIVE_VIEWS`): the other stale views are kept in :attr:`pending`
        and recomputed by the next call that includes them.  :meth:`refresh`
        recomputes everything.
        """
        diff = self.changed_fields() | set(changed or ())
        stale = self.stale_views(diff) | self.pending
        views = stale if only is None else stale & set(only)
        if "profile" in views and "coarse" in stale:
            views.add("coarse")  # the profile is read off the coarse sphere's images
        self.pending = stale - views
        s = self.state
        if views & {"sphere", "coarse", "profile"}:
            material, lights = s.material(), s.lights()
            if "sphere" in views:
                self.views["sphere"] = self._sphere_view(material, lights)
            if "coarse" in views:
                self.views["coarse"] = self._coarse_view(material, lights)
            if "profile" in views:
                self.views["profile"] = self._profile_view()
        if views - {"sphere", "coarse", "profile"}:
            brdf = s.plot_brdf()
            opts = s.plot_options()
            theta = min(s.theta_l, 0.5 * math.pi)
            below = s.theta_l >= 0.5 * math.pi
            if "lobe" in views:
                self.views["lobe"] = self._lobe_view(brdf, theta, below, opts)
            if "polar" in views:
                self.views["polar"] = self._polar_view(brdf, theta, below, opts)
            if "theta_v" in views:
                c = theta_v_curve(brdf, theta, n=181, **opts)
                self.views["theta_v"] = CurveView("theta_v", c.angles, c.values, (-theta, theta), c.params)
            if "theta_h" in views:
                c = theta_h_curve(brdf, theta_d=theta, n=181, **opts)
                self.views["theta_h"] = CurveView("theta_h", c.angles, c.values, (0.0,), c.params)
            if "theta_d" in views:
                c = theta_d_curve(brdf, theta_h=0.0, n=181, **opts)
                self.views["theta_d"] = CurveView("theta_d", c.angles, c.values, (theta,), c.params)
            elif "theta_d" in self.views and "theta_v" in views:
                old = self.views["theta_d"]
                self.views["theta_d"] = CurveView("theta_d", old.angles, old.values, (theta,), old.params)
            if "halfdiff" in views:
                im = half_diff_image(brdf, n_h=91, n_d=91, **opts)
                peak = float(im.values.max())
                self.views["halfdiff"] = HalfDiffView(im.theta_h, im.theta_d, im.values, peak, (0.0, theta))
            elif "halfdiff" in self.views and "theta_v" in views:
                old = self.views["halfdiff"]
                self.views["halfdiff"] = HalfDiffView(old.theta_h, old.theta_d, old.values, old.peak, (0.0, theta))
            if "albedo" in views:
                self.views["albedo"] = self._albedo_view(brdf, theta)
        self._snapshot = self._inputs()
        return views

    def refresh(self) -> set[str]:
        """Recompute every view."""
        self._snapshot = None
        self.pending = set()
        return self.update()

    # ------------------------------------------------------------------ view builders
    def _sphere_view(self, material, lights) -> SphereView:
        s = self.state
        if s.mode == "phong":
            r, geometry = self._sphere, "exact sphere"
        else:
            r = self.mesh_renderer(s.tessellation, self.sphere_size)
            geometry = f"{r.geometry.n_triangles} triangles"
        img = r.render(material, lights, mode=s.mode, form=s.form, terms=s.terms)
        cov = r.gbuffer.coverage
        rgb8, clipped = _encode(img, cov, s.exposure)
        return SphereView(img, rgb8, cov, s.mode, geometry, clipped)

    def _coarse_view(self, material, lights) -> CoarseView:
        s = self.state
        mesh = self.mesh(s.tessellation)
        r = self.mesh_renderer(s.tessellation, self.mesh_size)
        opts = {"form": s.form, "terms": s.terms}
        # The engine's lighting at every vertex: what Gouraud shading interpolates (the renderer's
        # Gouraud image interpolates exactly these colours; orthographic view: v = +z everywhere).
        vertex = shade(mesh.vertices, mesh.normals, material, lights, view_dir=(0.0, 0.0, 1.0), **opts)
        phong = r.render(material, lights, mode="phong", **opts)
        vertex8, _ = encode8(vertex[None], exposure=s.exposure)
        gb = r.gbuffer
        p8, _ = _encode(phong, gb.coverage, s.exposure)
        return CoarseView(
            mesh.vertices, mesh.faces, vertex, vertex8[0], phong, p8, gb.triangle_id, gb.coverage,
            s.tessellation, s.exposure, lambda: r.render(material, lights, mode="gouraud", **opts),
        )  # fmt: skip

    def _profile_view(self) -> ProfileView:
        s = self.state
        c = self.views["coarse"]
        h, w = c.triangle_id.shape
        row = min(h - 1, max(0, int(s.scanline * h)))
        ch = s.channel
        pg = scanline_profile(c.gouraud, row, coverage=c.coverage, channel=ch)
        pp = scanline_profile(c.phong, row, coverage=c.coverage, channel=ch)
        unit = 2.0 * 1.08 / h  # sphere units per pixel (sphere_camera's framing)
        x = (pg.x + 0.5 - 0.5 * w) * unit
        t = c.triangle_id[row, pg.x]
        cross = np.flatnonzero(t[:-1] != t[1:])
        edges = (pg.x[cross] + 1.0 - 0.5 * w) * unit
        rows = range(0, h, 12)
        mg = edge_jump_metric(c.gouraud, c.triangle_id, rows=rows, channel=ch)
        mp = edge_jump_metric(c.phong, c.triangle_id, rows=rows, channel=ch)
        y = (0.5 * h - row - 0.5) * unit
        slope = float(np.mean(np.abs(np.concatenate([pg.d1, pp.d1])))) if pg.d1.size else 0.0
        return ProfileView(row, y, x, pg.intensity, pp.intensity, pg.d2, pp.d2, edges, mg, mp, ch, slope)

    def _lobe_view(self, brdf, theta, below, opts) -> LobeView:
        s = self.state
        l_plot = spherical_direction(theta, math.pi)  # the light on the −x side, exactly on the horizon at π/2
        m = lobe_mesh(brdf, l_plot, resolution=self.lobe_resolution, cosine=s.times_cos, channel=s.channel)
        values = m.values.astype(np.float64)
        if s.log:
            values = np.log1p(values) / math.log(10.0)
        peak = float(values.max()) if values.size else 0.0
        scale = 1.0 / peak if peak > 0 else 1.0
        vertices = (values * scale)[:, None] * m.directions.astype(np.float64)
        mirror = np.array([-l_plot[0], 0.0, l_plot[2]])
        return LobeView(vertices, m.faces, values, peak, scale, l_plot, mirror, m.peak.astype(np.float64), below)

    def _albedo_view(self, brdf, theta) -> AlbedoView:
        # Quadrature on the lobe's nodes: deterministic, a few ms (up to ~30 ms), with an error estimate.
        # Not a live view: computed when the plots follow, on a slider's release, never during a drag.
        est = directional_albedo(brdf, theta, samples=ALBEDO_SAMPLES, method="quadrature", return_error=True)
        rgb = np.asarray(est.value, dtype=np.float64)
        err = np.abs(np.asarray(est.error, dtype=np.float64))
        ch = self.state.channel
        if ch == "luminance":
            value, error = float(rgb @ LUMA), float(err @ LUMA)  # errors add at worst linearly
        else:
            k = "rgb".index(ch)
            value, error = float(rgb[k]), float(err[k])
        rel = error / abs(value) if value != 0 else (math.inf if error > 0 else 0.0)
        return AlbedoView(theta, value, error, rel, bool(rel > UNCONVERGED_RELATIVE_ERROR), rgb, err, est.method,
                          int(est.samples))  # fmt: skip

    def _polar_view(self, brdf, theta, below, opts) -> PolarView:
        a, b = reciprocity_pair(brdf, theta, n=361, **opts)
        return PolarView(a.angles, a.values, b.values, b.angles, theta, below)

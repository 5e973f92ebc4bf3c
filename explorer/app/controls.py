r"""The explorer's controls: their choices, the table they are validated by, and their validation.

:data:`CONTROLS` holds one :class:`Control` per control of :class:`~explorer.app.state.AppState` (the model,
the light, shading and plot options): its kind, range, choices and help (the command line's help is made from
it).  :func:`validate` checks one value for one control and raises ``ValueError`` (or
:class:`~lighting._validate.ArgumentTypeError`) naming the control, what is allowed and the value given.
Nothing here imports PyVista, Qt or Matplotlib.

Example
-------
>>> validate("kd", 0.5)
0.5
>>> validate("mode", "Gouraud")
'gouraud'
>>> validate("kd", 2)
Traceback (most recent call last):
...
ValueError: kd must be a number in [0, 1]; got 2
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from lighting._text import abbreviate
from lighting._validate import ArgumentTypeError, check_bool, check_count, check_range, real_array
from lighting.lights import ATTENUATIONS, SKIES
from lighting.models import model_variants
from lighting.render import SHADING_MODES

from ..compare import FIT_MODELS
from .lights import check_lights
from .params import MODELS

__all__ = [
    "LIGHT_TYPES",
    "PANELS",
    "ENVIRONMENTS",
    "VIEWS_3D",
    "MAX_ENTRIES",
    "ALBEDO_SAMPLES",
    "CHANNELS",
    "CHANNEL_LABELS",
    "FORMS",
    "TERM_NAMES",
    "LIGHT_COLOURS",
    "NDFS",
    "ATTENUATIONS",
    "FIT_MODELS",
    "Control",
    "CONTROLS",
    "validate",
    "parse_text",
]


LIGHT_TYPES = ("directional", "point", "spot", "ambient")
#: What the right BRDF panel shows: the angle curves, or the albedo curves.
PANELS = ("angles", "albedo")
#: The environment choices: none (the key and ambient lights only), each procedural sky, or the file of
#: ``--environment FILE`` (see :mod:`explorer.app.environment`).
ENVIRONMENTS = ("none", *SKIES, "file")
#: What the 3D panel shows: the BRDF lobe, or the lit object (a mesh under the environment).
VIEWS_3D = ("lobe", "object")
#: Entries the window's comparison list holds (each is a row of the Compare panel and a curve in every plot).
MAX_ENTRIES = 6
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

    kind: str  # "float", "int", "choice", "bool", "rgb", "terms", "lights"
    lo: float | None = None
    hi: float | None = None
    choices: tuple = ()
    log: bool = False  # a slider moves log10 of the value
    help: str = ""


CONTROLS: dict[str, Control] = {
    "model": Control(
        "choice", choices=MODELS, help="reflectance model (plus Lambert k_d unless it has its own diffuse)"
    ),
    "kd": Control("float", 0.0, 1.0, help="diffuse albedo k_d (times the surface colour)"),
    "color": Control("rgb", 0.0, 1.0, help="surface colour (hue of k_d), r,g,b in [0, 1]"),
    "light": Control("choice", choices=LIGHT_TYPES, help="key light type (ambient: no key light)"),
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
    "phi": Control(
        "float", -180.0, 180.0, help="azimuth φ_l of the light in the BRDF views, from the tangent t, degrees"
    ),
    "lock": Control("bool", help="view lock: the view follows the light (θ_v = θ_l, φ_v = φ_l), the retro-reflection"),
    "panel": Control("choice", choices=PANELS, help="the right BRDF panel: angle curves, or the albedo ρ(θ_v) of each"),
    "split": Control(
        "bool", help="lit sphere split: left half the current model, right half the solo or first shown comparison"
    ),
    "fit": Control("choice", choices=tuple(FIT_MODELS), help="the analytic model the fit action fits to the current"),
    "environment": Control(
        "choice",
        choices=ENVIRONMENTS,
        help="environment lighting the sphere and the object (with the key light; it replaces the ambient light)",
    ),
    "env_rotation": Control("float", -180.0, 180.0, help="environment turned about its up axis, degrees"),
    "env_intensity": Control("float", 0.0, 10.0, help="environment radiance multiplier"),
    "view3d": Control("choice", choices=VIEWS_3D, help="the 3D panel: the BRDF lobe, or the lit object (--mesh)"),
    "reference": Control(
        "bool", help="environment by the Monte-Carlo reference, refined while the view rests (off: dominant lights)"
    ),
    "scene_lights": Control(
        "lights",
        help="the scene's other lights (directional, point, spot, rect, disk, opengl), light tables in the view "
        "frame (explorer.app.lights)",
    ),
}


def quote(x: float) -> str:
    return str(int(x)) if float(x).is_integer() and abs(x) < 1e7 else f"{x:g}"


def _allowed(spec: Control) -> str:
    if spec.kind == "rgb":
        return f"one number or three numbers r,g,b in [{quote(spec.lo)}, {quote(spec.hi)}]"
    kind = "an integer" if spec.kind == "int" else "a number"
    return f"{kind} in [{quote(spec.lo)}, {quote(spec.hi)}]"


def _refuse(name: str, spec: Control, value, exc_type=ValueError):
    """The one error of a control: names it, what is allowed and the value given (abbreviated)."""
    given = abbreviate(repr(value))
    if exc_type is not ValueError:
        given = f"{type(value).__name__} {given}"
    return exc_type(f"{name} must be {_allowed(spec)}; got {given}")


def validate(name: str, value):
    """``value`` checked for the control ``name`` (see :data:`CONTROLS`); a named error if it is not allowed.

    Numbers and colours are numbers: text and bytes are refused (``b'1'`` is not 1; the command
    line parses its text first, :meth:`AppState.from_args`), and so are bools.  A wrong type
    raises :class:`~lighting._validate.ArgumentTypeError` (a TypeError and a ValueError).
    """
    spec = CONTROLS[name]
    if spec.kind == "lights":
        return check_lights(value)
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


def parse_text(name: str, text: str):
    """Command-line text for a number or a colour: ``"0.5"`` or ``"1,0.5,0"`` (a named error if it is neither)."""
    spec = CONTROLS.get(name, CONTROLS["kd"])
    parts = [p.strip() for p in text.split(",")]
    try:
        numbers = [float(p) for p in parts]
    except ValueError:
        raise ValueError(f"{name} must be {_allowed(spec) if spec.kind == 'rgb' else 'one number or r,g,b'}; "
                         f"got {abbreviate(repr(text))}") from None  # fmt: skip
    return numbers[0] if len(numbers) == 1 else tuple(numbers)

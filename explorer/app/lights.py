r"""The explorer's extra lights: the lights of a scene beside the ambient and the key light, as light tables.

The control ``scene_lights`` of :class:`~explorer.app.state.AppState` is a tuple of light tables, each a
dict as a scene file writes a light (``{"type": "rect", "center": [...], ...}``, the keys of
:data:`lighting.scene.schema.LIGHT_KEYS`), in the explorer's view frame: ``x`` right, ``y`` up, ``z``
toward the viewer, the unit sphere at the origin.  A table is checked, and its engine light built, by
the scene loader itself (:func:`lighting.scene.load.load_scene` reads every light through the same
function), so a bad value gets the loader's message, its key path starting ``scene_lights[i].``.

* :data:`EXTRA_LIGHT_TYPES` — the kinds of extra light; :func:`new_light` — one that lights the
  sphere's visible side; :data:`LIGHT_FIELDS` — what an editor offers for each kind;
  :func:`field_value` — a field as its editor shows it; :func:`with_field` — a new tuple with one
  field changed; :func:`light_label` — one line for a list.
* :func:`check_lights` — the control's validation (the tables with every default filled in);
  :func:`engine_lights` — the engine lights of one table.
* :func:`has_direct_light` and :func:`lights_line` — whether anything but ambient light shines
  on the sphere, and the line the lit sphere's caption says about the lights.

An OpenGL light (``type = "opengl"``) lights the explorer's engine material as the engine's light of
its diffuse colour (a directional light for ``w = 0``, else a point light, or a spot light when its
cutoff is not 180°, with OpenGL's attenuation ``1 / (k_0 + k_1 d + k_2 d²)``), plus an ambient light
of its ambient colour.  That is OpenGL's equation for the mapped material
(:func:`lighting.scene.gl_material_to_engine`) when the light's specular colour equals its diffuse
colour (the default); the per-light ambient term, which OpenGL attenuates and masks by the cone at
each point, is taken at the sphere's centre (exact for a directional light).

Examples
--------
>>> lights = check_lights([{"type": "rect", "center": [0.0, 0.0, 3.0]}])
>>> lights[0]["edge_u"], lights[0]["samples"]  # the scene format's defaults, filled in
([1.0, 0.0, 0.0], 16)
>>> with_field(lights, 0, "intensity", -1.0)
Traceback (most recent call last):
...
ValueError: scene_lights[0].intensity: intensity must be a finite number >= 0; got -1.0
>>> light_label(lights[0])
'rect 1×1 at (0, 0, 3), intensity 1'
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from typing import NamedTuple

import numpy as np

from lighting._text import abbreviate
from lighting._validate import ArgumentTypeError, check_color
from lighting.lights import AmbientLight, DirectionalLight, PointLight, SpotLight
from lighting.scene.checks import _choice, _Ctx, _table
from lighting.scene.errors import SceneError, _describe, _join
from lighting.scene.load import _light
from lighting.scene.schema import LIGHT_KEYS
from lighting.vec import direction_from_elevation

__all__ = [
    "EXTRA_LIGHT_TYPES",
    "LIGHT_FIELDS",
    "LightField",
    "new_light",
    "light_label",
    "field_value",
    "with_field",
    "check_lights",
    "engine_lights",
    "has_direct_light",
    "lights_line",
]

#: The kinds of extra light (the scene format's light types less ambient and environment: those are controls).
EXTRA_LIGHT_TYPES = ("directional", "point", "spot", "rect", "disk", "opengl")

#: The name of the control, the start of every key path in a message.
CONTROL = "scene_lights"

# The scene format's keys of each kind.  An OpenGL light's ``space`` is left out: the explorer's tables are in
# its view frame (:func:`explorer.app.scenes.state_from_scene` takes eye-space lights there).
_KEYS = {kind: {k: v for k, v in LIGHT_KEYS[kind].items() if not (kind == "opengl" and k == "space")}
         for kind in EXTRA_LIGHT_TYPES}  # fmt: skip
#: Keys whose values are integers (an editor's whole float is taken as the integer).
_INTEGER_KEYS = frozenset({"samples", "seed"})


class LightField(NamedTuple):
    """One editable field of an extra light: what an editor offers for it.

    ``kind`` is ``"vec3"`` (three numbers), ``"color"`` (r, g, b), ``"number"``, ``"choice"`` or ``"bool"``;
    ``lo`` and ``hi`` are the editor's range (a vector's for each coordinate; the light's own checks decide what
    is allowed), ``log`` says a slider moves log10 of the value.
    """

    name: str
    kind: str
    lo: float | None
    hi: float | None
    log: bool
    help: str


def _f(name, kind, lo=None, hi=None, log=False, help=""):
    return LightField(name, kind, lo, hi, log, help)


_POSITION = _f("position", "vec3", -20.0, 20.0, help="where the light is (view frame, sphere radii)")
_COLOR = _f("color", "color", 0.0, 1.0, help="light colour, r,g,b")
_ATTENUATION = _f("attenuation", "vec3", 0.0, 4.0, help="(a, b, c) of the falloff 1 / (a d² + b d + c)")
_AREA = (
    _f("color", "color", 0.0, 1.0, help="emitted colour, r,g,b"),
    _f("intensity", "number", 0.0, 50.0, help="radiance L_e of the emitter (times the colour)"),
    _f("samples", "number", 1, 256, help="points sampled on the emitter (an integer; more: smoother, slower)"),
    _f("two_sided", "bool", help="emit from both faces"),
)
#: The editable fields of each kind of extra light, in the order an editor shows them.  Read a field's value
#: with :func:`field_value` and change it with :func:`with_field`: an OpenGL light's ``position`` is its
#: ``x, y, z`` there and its ``w`` the flag ``directional`` (``w = 0``).
LIGHT_FIELDS: dict[str, tuple[LightField, ...]] = {
    "directional": (
        _f("direction", "vec3", -1.0, 1.0, help="direction toward the light (view frame)"),
        _COLOR,
        _f("intensity", "number", 0.0, 10.0, help="irradiance on a surface facing the light (times the colour)"),
    ),
    "point": (
        _POSITION,
        _COLOR,
        _f("intensity", "number", 0.0, 100.0, help="intensity I_0: irradiance 1 / A(d) times it"),
        _ATTENUATION,
    ),
    "spot": (
        _POSITION,
        _f("direction", "vec3", -1.0, 1.0, help="where the spot points"),
        _f("cutoff_deg", "number", 0.0, 90.0, help="cone half-angle, degrees"),
        _f("exponent", "number", 0.0, 128.0, help="concentration toward the axis"),
        _COLOR,
        _f("intensity", "number", 0.0, 100.0, help="intensity I_0 on the axis: irradiance 1 / A(d) times it"),
        _ATTENUATION,
    ),
    "rect": (
        _f("center", "vec3", -20.0, 20.0, help="centre of the rectangle (view frame, sphere radii)"),
        _f("edge_u", "vec3", -10.0, 10.0, help="one edge; the lit face is edge_u × edge_v"),
        _f("edge_v", "vec3", -10.0, 10.0, help="the other edge"),
        *_AREA,
    ),
    "disk": (
        _f("center", "vec3", -20.0, 20.0, help="centre of the disk (view frame, sphere radii)"),
        _f("normal_dir", "vec3", -1.0, 1.0, help="the direction the lit face looks"),
        _f("radius", "number", 0.01, 10.0, log=True, help="disk radius, sphere radii"),
        *_AREA,
    ),
    "opengl": (
        _f("position", "vec3", -20.0, 20.0, help="x, y, z: a position, or the direction toward a directional light"),
        _f("directional", "bool", help="w = 0: a directional light (x, y, z the direction toward it)"),
        _f("ambient", "color", 0.0, 1.0, help="ambient colour a_cl"),
        _f("diffuse", "color", 0.0, 1.0, help="diffuse colour d_cl (the explorer's light colour)"),
        _f("specular", "color", 0.0, 1.0, help="specular colour s_cl (shown as the diffuse colour)"),
        _f("spot_direction", "vec3", -1.0, 1.0, help="axis of the spot cone"),
        _f("spot_cutoff", "number", 0.0, 180.0, help="cone half-angle, degrees: [0, 90], or 180 for no cone"),
        _f("spot_exponent", "number", 0.0, 128.0, help="spot exponent"),
        _f("constant_attenuation", "number", 0.0, 4.0, help="k_0 of 1 / (k_0 + k_1 d + k_2 d²)"),
        _f("linear_attenuation", "number", 0.0, 4.0, help="k_1"),
        _f("quadratic_attenuation", "number", 0.0, 4.0, help="k_2"),
    ),
}


# =============================================================================== checking and building
def _refuse(key: str, detail: str):
    return ValueError(f"{key}: {detail}")


def _checked(table, index: int) -> tuple[dict, object]:
    """The table with every default filled in, and what the scene loader builds of it (a SceneError if bad)."""
    ctx = _Ctx(CONTROL, os.getcwd())
    path = f"{CONTROL}[{index}]"
    if not isinstance(table, Mapping):
        ctx.fail(path, f"must be a light table (a dict with a type: {', '.join(EXTRA_LIGHT_TYPES)}); "
                       f"got {_describe(table)}")  # fmt: skip
    table = dict(table)
    if "type" not in table:
        ctx.fail(_join(path, "type"), f"is required: one of {', '.join(map(repr, EXTRA_LIGHT_TYPES))}")
    kind = _choice(EXTRA_LIGHT_TYPES)(ctx, _join(path, "type"), table["type"])
    what = f"{'an' if kind[0] in 'aeiou' else 'a'} {kind!r} light"
    params = _table(ctx, path, table, _KEYS[kind], what)
    params["type"] = kind
    light = _light(ctx, path, params)  # the loader's own checks and constructor
    if kind == "opengl":
        params["position"] = list(light.light.position)  # [x, y, z] means w = 1: written out
        return {"type": kind, **{k: v for k, v in params.items() if k != "type"}}, _from_gl(ctx, path, light.light)
    return {"type": kind, **{k: v for k, v in params.items() if k != "type"}}, [light]


def _spot_factor(cos_angle: float, cutoff: float, exponent: float) -> float:
    """OpenGL's spot factor for one cosine, through the engine's one home of the formula."""
    if cutoff == 180.0:
        return 1.0
    return float(SpotLight(cutoff_deg=cutoff, exponent=exponent).spot_factor(cos_angle))


def _from_gl(ctx, path, g) -> list:
    """The engine lights of an OpenGL light (see the module notes): the light of its diffuse colour, and its ambient."""
    pos = np.asarray(g.position, dtype=np.float64)
    diffuse = [float(x) for x in g.diffuse[:3]]
    for name in ("diffuse", "ambient"):  # engine light colours: >= 0 (OpenGL allows any), named by their keys
        ctx.build(path, lambda name=name, **c: check_color(name, c[name]), {name: getattr(g, name)[:3]})
    keymap = {"color": "diffuse", "direction": "position", "position": "position"}
    sd = np.asarray(g.spot_direction, dtype=np.float64)
    if pos[3] == 0.0:
        # OpenGL applies the spot factor to a directional light too: one number, the same at every point.
        to = pos[:3] / np.linalg.norm(pos[:3])
        spot = _spot_factor(float(-(to @ sd) / np.linalg.norm(sd)), g.spot_cutoff, g.spot_exponent)
        out = [ctx.build(path, DirectionalLight, {"direction": pos[:3], "color": diffuse, "intensity": spot}, keymap)]
        at_centre = spot
    else:
        p = pos[:3] / pos[3]
        k = (g.quadratic_attenuation, g.linear_attenuation, g.constant_attenuation)  # the engine's (a, b, c)
        kw = {"position": p, "color": diffuse, "attenuation": k}
        if g.spot_cutoff == 180.0:
            out = [ctx.build(path, PointLight, kw, keymap)]
        else:
            kw.update(direction=sd, cutoff_deg=g.spot_cutoff, exponent=g.spot_exponent)
            names = {**keymap, "direction": "spot_direction", "cutoff_deg": "spot_cutoff", "exponent": "spot_exponent"}
            out = [ctx.build(path, SpotLight, kw, names)]
        d = float(np.linalg.norm(p))
        den = g.constant_attenuation + g.linear_attenuation * d + g.quadratic_attenuation * d * d
        cos_c = float(-(p @ sd) / (d * np.linalg.norm(sd))) if d > 0 else 0.0
        at_centre = (1.0 / den if den > 0 else 0.0) * _spot_factor(cos_c, g.spot_cutoff, g.spot_exponent)
    ambient = [float(x) * at_centre for x in g.ambient[:3]]
    if any(a > 0 for a in ambient):
        out.append(ctx.build(path, AmbientLight, {"color": ambient, "intensity": 1.0}, {"color": "ambient"}))
    return out


def _scene_error(e: SceneError) -> ValueError:
    return ValueError(f"{e.key}: {e.detail}" if e.key else f"{CONTROL}: {e.detail}")


def check_light(table, index: int = 0) -> dict:
    """One extra light's table, checked by the scene loader, with every default filled in.

    Parameters
    ----------
    table : mapping
        A light table of a kind in :data:`EXTRA_LIGHT_TYPES`, view-frame coordinates.
    index : int
        Its place in ``scene_lights`` (for the messages).

    Returns
    -------
    dict
        The table as the loader reads it (defaults filled in; an OpenGL position has its ``w``).

    Raises
    ------
    ValueError
        ``"scene_lights[i].key: ..."``: the loader's message for the key at fault.
    """
    try:
        return _checked(table, index)[0]
    except SceneError as e:
        raise _scene_error(e) from None


def check_lights(value) -> tuple:
    """The value of the ``scene_lights`` control, checked: a tuple of light tables with their defaults filled in.

    Parameters
    ----------
    value : list or tuple of mappings
        Light tables (:func:`check_light`).

    Returns
    -------
    tuple of dict

    Raises
    ------
    ValueError
        ``"scene_lights must be ..."`` for a value that is no list of tables (an ArgumentTypeError, a ValueError
        too), ``"scene_lights[i].key: ..."`` for a bad table.
    """
    if not isinstance(value, (list, tuple)):
        raise ArgumentTypeError(f"{CONTROL} must be a list of light tables (dicts with a type: "
                                f"{', '.join(EXTRA_LIGHT_TYPES)}); got {type(value).__name__} "
                                f"{abbreviate(repr(value))}")  # fmt: skip
    return tuple(check_light(t, i) for i, t in enumerate(value))


def engine_lights(table, index: int = 0) -> list:
    """The engine lights of one extra light's table (view frame), built as the scene loader builds them.

    Parameters
    ----------
    table : mapping
        A light table (:func:`check_light`).
    index : int
        Its place in ``scene_lights`` (for the messages).

    Returns
    -------
    list of Light
        One light; an OpenGL light with an ambient colour adds an :class:`~lighting.lights.AmbientLight`.

    Examples
    --------
    >>> engine_lights({"type": "opengl", "position": [0, 0, 1, 0], "diffuse": 0.5})
    [DirectionalLight(direction=(0, 0, 1), color=0.5, intensity=1)]
    """
    try:
        return _checked(table, index)[1]
    except SceneError as e:
        raise _scene_error(e) from None


# =============================================================================== editing
def _rounded(v) -> list:
    return [round(float(x), 4) + 0.0 for x in v]


def new_light(kind: str, state) -> dict:
    """A new extra light of ``kind`` that lights the sphere's visible side.

    It comes from 35° above the image plane, across the sphere from the key light (from the upper right when
    there is no key light), at three sphere radii for the lights with a position, bright enough to give
    about the irradiance 1 at the sphere's nearest point.

    Parameters
    ----------
    kind : str
        One of :data:`EXTRA_LIGHT_TYPES`.
    state : AppState
        The controls (the key light's azimuth places the new light).

    Returns
    -------
    dict
        The light's table, every field set (:func:`check_light`).

    Examples
    --------
    >>> from explorer.app.state import AppState
    >>> new_light("point", AppState(light="ambient"))["position"]
    [1.7377, 1.7377, 1.7207]
    """
    if not isinstance(kind, str) or kind.strip().lower() not in EXTRA_LIGHT_TYPES:
        raise ValueError(f"kind must be one of {', '.join(EXTRA_LIGHT_TYPES)}; got {abbreviate(repr(kind))}")
    kind = kind.strip().lower()
    azimuth = 45.0 if state.light == "ambient" else float(state.azimuth) + 180.0
    d = direction_from_elevation(35.0, azimuth)
    r = 3.0  # distance from the centre; the nearest point of the sphere is r - 1 away
    near = (r - 1.0) ** 2
    if kind == "directional":
        table = {"type": kind, "direction": _rounded(d), "color": 1.0, "intensity": 1.0}
    elif kind == "point":
        table = {"type": kind, "position": _rounded(r * d), "intensity": near}
    elif kind == "spot":
        table = {"type": kind, "position": _rounded(r * d), "direction": _rounded(-d), "cutoff_deg": 25.0,
                 "exponent": 2.0, "intensity": near}  # fmt: skip
    elif kind in ("rect", "disk"):
        # Facing the sphere: a 1 × 1 rectangle (or a disk of that area) with edge_u × edge_v = -d.
        u = np.cross((0.0, 1.0, 0.0), d)
        u = u / np.linalg.norm(u) if np.linalg.norm(u) > 1e-6 else np.array([1.0, 0.0, 0.0])
        v = np.cross(u, d)
        table = {"type": kind, "center": _rounded(r * d), "intensity": near}  # L_e A / d² with A = 1
        if kind == "rect":
            table.update(edge_u=_rounded(u), edge_v=_rounded(v))
        else:
            table.update(normal_dir=_rounded(-d), radius=round(1.0 / math.sqrt(math.pi), 4))
    else:
        table = {"type": kind, "position": [*_rounded(d), 0.0], "diffuse": [1.0, 1.0, 1.0, 1.0],
                 "specular": [1.0, 1.0, 1.0, 1.0]}  # fmt: skip
    return check_light(table)


def _fields(kind: str) -> dict:
    return {f.name: f for f in LIGHT_FIELDS[kind]}


def field_value(table: Mapping, name: str):
    """A field of a light table as its editor shows it (:data:`LIGHT_FIELDS`).

    Parameters
    ----------
    table : mapping
        A checked light table (:func:`check_light`: every default filled in).
    name : str
        A field of its kind.

    Returns
    -------
    tuple of 3 floats, float or bool
        A vector or colour as three numbers (an OpenGL colour without its alpha, a grey as three equal numbers),
        a number as a float, a flag as a bool; an OpenGL light's ``position`` is ``(x, y, z)`` and its
        ``directional`` is ``w == 0``.
    """
    kind = table["type"]
    field = _fields(kind).get(name)
    if field is None:
        raise ValueError(f"{name} must be a field of a {kind!r} light: {', '.join(_fields(kind))}")
    if kind == "opengl" and name == "directional":
        return float(table["position"][3]) == 0.0
    value = table.get(name)
    if field.kind in ("vec3", "color"):
        v = [float(value)] * 3 if isinstance(value, (int, float)) else [float(x) for x in value]
        return tuple(v[:3])
    if field.kind == "bool":
        return bool(value)
    return float(value)


def with_field(lights, index: int, name: str, value) -> tuple:
    """A new tuple of light tables with field ``name`` of light ``index`` set to ``value``.

    Parameters
    ----------
    lights : tuple of dict
        The ``scene_lights`` control's value.
    index : int
        Which light.
    name : str
        A field of its kind (:data:`LIGHT_FIELDS`; an OpenGL light's ``position`` keeps its ``w``,
        ``directional`` sets ``w`` to 0 or 1).
    value
        The new value, as an editor gives it (a colour of three numbers keeps an OpenGL colour's alpha).

    Returns
    -------
    tuple of dict
        The new value of ``scene_lights`` (``lights`` itself is not changed).

    Raises
    ------
    ValueError
        ``"scene_lights[i].name: ..."``: the scene loader's message, when the light refuses the value.
    """
    lights = tuple(lights)
    if isinstance(index, bool) or not isinstance(index, (int, np.integer)) or not 0 <= index < len(lights):
        raise ValueError(
            f"{CONTROL} index must be an integer in [0, {len(lights) - 1}]; got {abbreviate(repr(index))}"
            if lights
            else f"{CONTROL} has no lights to change; got index {abbreviate(repr(index))}"
        )
    index = int(index)
    table = dict(lights[index])
    kind = str(table.get("type", ""))
    key = f"{CONTROL}[{index}].{name}"
    if kind not in LIGHT_FIELDS or name not in _fields(kind):
        known = ", ".join(_fields(kind)) if kind in LIGHT_FIELDS else "none"
        raise ValueError(f"{key}: unknown field of a {kind!r} light; fields: {known}")
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, tuple):
        value = list(value)
    if name in _INTEGER_KEYS and isinstance(value, float) and value.is_integer():
        value = int(value)
    if kind == "opengl":
        pos = list(table["position"])
        if name == "directional":
            if not isinstance(value, (bool, np.bool_)):
                raise ValueError(f"{key}: must be true or false; got {abbreviate(repr(value))}")
            name, value = "position", [*pos[:3], 0.0 if value else 1.0]
        elif name == "position" and isinstance(value, list) and len(value) == 3:
            value = [*value, pos[3]]
        elif name in ("ambient", "diffuse", "specular") and isinstance(value, list) and len(value) == 3:
            value = [*value, table[name][3]]
    table[name] = value
    return lights[:index] + (check_light(table, index),) + lights[index + 1 :]


def _num(x: float) -> str:
    return f"{float(x):.3g}"


def _vec(v) -> str:
    return "(" + ", ".join(_num(x) for x in v) + ")"


def light_label(table: Mapping) -> str:
    """One line for a light table: its kind, where it is and how bright.

    Parameters
    ----------
    table : mapping
        A checked light table.

    Returns
    -------
    str
        E.g. ``"rect 1×1 at (0, 0, 3), intensity 4"``, ``"opengl directional from (1, 1, 1)"``.
    """
    kind = table["type"]
    if kind == "directional":
        return f"directional from {_vec(table['direction'])}, intensity {_num(table['intensity'])}"
    if kind in ("point", "spot"):
        cone = f", cone {_num(table['cutoff_deg'])}°" if kind == "spot" else ""
        return f"{kind} at {_vec(table['position'])}{cone}, intensity {_num(table['intensity'])}"
    if kind == "rect":
        size = f"{_num(np.linalg.norm(table['edge_u']))}×{_num(np.linalg.norm(table['edge_v']))}"
        return f"rect {size} at {_vec(table['center'])}, intensity {_num(table['intensity'])}"
    if kind == "disk":
        return f"disk r {_num(table['radius'])} at {_vec(table['center'])}, intensity {_num(table['intensity'])}"
    pos = table["position"]
    where = f"directional from {_vec(pos[:3])}" if pos[3] == 0 else f"at {_vec(np.asarray(pos[:3]) / pos[3])}"
    cone = f", cone {_num(table['spot_cutoff'])}°" if table["spot_cutoff"] != 180 else ""
    return f"opengl {where}{cone}, diffuse {_vec(table['diffuse'][:3])}"


# =============================================================================== what the captions say
def has_direct_light(state) -> bool:
    """Whether light from somewhere (the key light or an extra light) reaches the sphere, not only ambient light.

    Parameters
    ----------
    state : AppState
        The controls.

    Returns
    -------
    bool
        False only when the key light is off (``light = "ambient"``) and there is no extra light.
    """
    return state.light != "ambient" or bool(state.scene_lights)


def lights_line(state) -> str:
    """The lights' line of the lit sphere's caption: the key light and the extra lights (the one home of that text).

    Parameters
    ----------
    state : AppState
        The controls.

    Returns
    -------
    str
        ``"ambient light only"`` when :func:`has_direct_light` is false; else the key light (type, elevation,
        azimuth, a point or spot light's distance) and e.g. ``"+ 2 scene lights (rect, disk)"``.

    Examples
    --------
    >>> from explorer.app.state import AppState
    >>> s = AppState(light="ambient")
    >>> lights_line(s)
    'ambient light only'
    >>> s.scene_lights = [new_light("rect", s)]
    >>> lights_line(s)
    'no key light + 1 scene light (rect)'
    """
    if not has_direct_light(state):
        return "ambient light only"
    if state.light == "ambient":
        key = "no key light"
    else:
        key = f"{state.light}, elevation {state.elevation:.0f}°, azimuth {state.azimuth:.0f}°"
        if state.light in ("point", "spot"):
            key += f", distance {state.distance:.1f}"
    extra = state.scene_lights
    if not extra:
        return key
    kinds = ", ".join(dict.fromkeys(t["type"] for t in extra))
    return f"{key} + {len(extra)} scene light{'s' if len(extra) != 1 else ''} ({kinds})"

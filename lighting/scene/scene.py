r"""Scenes as files: a TOML scene format, its loader, and a renderer that composites objects by depth.

A scene file says what to draw and how — camera, image, shading options,
materials, objects and lights — as data (the format is specified in full in
``docs/scenes.md``)::

    [camera]
    eye = [0.0, 0.0, 6.0]
    fov_y_deg = 25.0

    [materials.red]
    parts = [{model = "lambert", kd = [0.8, 0.2, 0.2]}, {model = "phong", ks = 0.5, shininess = 40}]

    [[objects]]
    type = "sphere"
    material = "red"

    [[lights]]
    type = "directional"
    direction = [1.0, 1.0, 1.0]

:func:`load_scene` / :func:`parse_scene` turn that into a :class:`Scene` of
engine objects (:class:`~lighting.render.camera.Camera`, meshes or
:class:`~lighting.render.renderer.AnalyticSphere`, :class:`~lighting.shading.equation.Material`,
lights).  Nothing in a file is executed: model, light and object names go
through explicit tables.  Every problem is a :class:`SceneError` (a
``ValueError``) naming the file, the key path (``lights[2].cutoff_deg``) and what
is allowed; the engine's own validation runs on every value and its message is
passed on with the file and key in front.

:class:`SceneRenderer` renders each object with its own
:class:`~lighting.render.renderer.Renderer` (rasterized once, cached) and keeps, per
pixel, the object nearest to the camera (smallest view depth ``f·(p − eye)``
among the objects covering the pixel; ties go to the object listed first), with
the background elsewhere.  Changing lights or materials re-shades without
re-rasterizing.

OpenGL scenes
-------------
Lights of ``type = "opengl"`` carry the fixed-function parameters (separate
ambient, diffuse and specular colours).  Objects lit by them are shaded with
:func:`lighting.shading.opengl.shade_vertices` — the OpenGL 2.1 equation, exactly — at the
shading samples of the object's mode (per triangle centroid, per vertex, or per
pixel), in eye coordinates (``V p`` with the camera's view matrix ``V``).  An
``opengl`` *material* lit by engine lights is mapped onto the classic form
instead: ``Lambert(diffuse) + BlinnPhong(specular, shininess)``, ambient
``k_a`` = the GL ambient, emission = the GL emission (:func:`gl_material_to_engine`).

Examples
--------
>>> scene = parse_scene('''
... [camera]
... eye = [0, 0, 5]
... [image]
... width = 16
... height = 16
... [[objects]]
... type = "sphere"
... material = {parts = [{model = "lambert", kd = 0.5}]}
... [[lights]]
... type = "ambient"
... intensity = 0.4
... ''')
>>> image, info = render_scene(scene)
>>> round(float(image[8, 8, 0]), 12), info["visible_pixels"]  # I_a k_a on the sphere
(0.2, (120,))
"""

from __future__ import annotations

import difflib
import json
import math
import numbers
import os
import re
import stat
import time
import tomllib
from dataclasses import dataclass, field, replace

import numpy as np

from .._numeric import BudgetError, abbreviate, check_budget, check_color
from ..lights import AmbientLight, AreaLight, DirectionalLight, DiskLight, PointLight, RectLight, SpotLight
from ..models.brdf import BRDF, BlinnPhong, CookTorrance, Lambert, Phong
from ..render.camera import Camera
from ..render.image import encode_srgb8
from ..render.mesh import TriangleMesh, icosphere, load_mesh, uv_sphere
from ..render.renderer import SHADING_MODES, AnalyticSphere, Renderer
from ..shading import opengl as gl
from ..shading.equation import FORMS, TERMS, Material

__all__ = [
    "SceneError",
    "SceneBudgetError",
    "Scene",
    "SceneObject",
    "RenderOptions",
    "ImageOptions",
    "OpenGLOptions",
    "GLLight",
    "SceneRenderer",
    "load_scene",
    "parse_scene",
    "render_scene",
    "scene_to_toml",
    "gl_material_to_engine",
    "example_path",
    "list_examples",
    "check_scene_budget",
    "scene_estimate",
    "scene_output_path",
    "FORMAT_VERSION",
    "MAX_NESTING",
]

#: The format version this module reads and writes (``version = 1`` in a file).
FORMAT_VERSION = 1

EXAMPLES_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "examples")


# =============================================================================== errors
class SceneError(ValueError):
    """A malformed scene: ``"<file>: <key path>: <what is wrong and what is allowed>"``.

    Attributes
    ----------
    source : str
        The file (as given) or ``"<string>"``.
    key : str
        The key path, e.g. ``"lights[2].cutoff_deg"`` (empty for the file as a whole).
    detail : str
        The message without file and key.
    """

    def __init__(self, source: str, key: str, detail: str):
        # One line, of bounded length, whatever the file holds: a 100k-character key or value is cut
        # (lighting._numeric.abbreviate) and line breaks inside passed-on messages become spaces.
        source, key, detail = (" ".join(str(x).splitlines()) for x in (source, key, detail))
        source, key, detail = abbreviate(source, 200), abbreviate(key, 160), abbreviate(detail, 800)
        self.source, self.key, self.detail = source, key, detail
        super().__init__(f"{source}: {key}: {detail}" if key else f"{source}: {detail}")


def _join(path: str, key) -> str:
    if isinstance(key, int):
        return f"{path}[{key}]"
    k = key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else json.dumps(key)
    k = abbreviate(k, 60)  # a key is the user's text too: a 100k-character one is cut
    return f"{path}.{k}" if path else k


def _fmt_value(v, depth: int = 0) -> str:
    """A value as TOML-like text for a message: at most a few entries of two levels, abbreviated."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return "nan" if math.isnan(v) else ("inf" if v == math.inf else ("-inf" if v == -math.inf else repr(v)))
    if isinstance(v, numbers.Integral):
        return abbreviate(_int_text(int(v)))
    if isinstance(v, str):
        return abbreviate(json.dumps(v))
    if isinstance(v, (list, tuple)):
        if depth >= 2:
            return "[...]" if v else "[]"
        inner = ", ".join(_fmt_value(x, depth + 1) for x in list(v)[:6])
        return abbreviate("[" + inner + (", ..." if len(v) > 6 else "") + "]")
    if isinstance(v, dict):
        if depth >= 2:
            return "{...}" if v else "{}"
        items = list(v.items())[:4]
        return abbreviate("{" + ", ".join(f"{_join('', k)} = {_fmt_value(x, depth + 1)}" for k, x in items) + "}")
    return abbreviate(repr(v))


def _int_text(n: int) -> str:
    """``str(n)``, or its size for an integer too long to print (Python refuses ints above 4300 digits)."""
    if abs(n) < 10**60:
        return str(n)
    return f"{'-' if n < 0 else ''}<an integer of about {int(abs(n).bit_length() * 0.30103) + 1} digits>"


def _describe(v) -> str:
    """A TOML-flavoured description of a value: its type and the value."""
    if isinstance(v, bool):
        kind = "a boolean"
    elif isinstance(v, numbers.Integral):
        kind = "an integer"
    elif isinstance(v, numbers.Real):
        kind = "a float"
    elif isinstance(v, str):
        kind = "a string"
    elif isinstance(v, (list, tuple)):
        kind = "an array"
    elif isinstance(v, dict):
        return "a table"
    else:
        kind = f"a {type(v).__name__}"
    return f"{kind} {_fmt_value(v)}"


def _norm_name(s: str) -> str:
    return s.strip().lower().replace("_", "-")


def _suggest(word: str, candidates) -> str:
    close = difflib.get_close_matches(_norm_name(word), [_norm_name(c) for c in candidates], n=1, cutoff=0.6)
    if not close:
        return ""
    original = next(c for c in candidates if _norm_name(c) == close[0])
    return f"did you mean {abbreviate(repr(original))}? "


class _Ctx:
    """Where we are: the file label (for messages) and the folder relative paths start from."""

    def __init__(self, source: str, base_dir: str):
        self.source, self.base_dir = source, base_dir
        self.meshes: dict[str, TriangleMesh] = {}
        self.held_bytes = 0  # estimated memory of the geometry built so far (see _charge)

    def charge(self, path: str, nbytes, what: str, *, held: bool = True):
        """Refuse, naming ``path``, a value whose estimated memory (with what the scene holds) is over the budget.

        Called *before* the value is built; ``held`` adds it to what the scene holds from then on.
        """
        total = _clamp(self.held_bytes + nbytes)
        try:
            check_budget("this value", total, what=what + ("; with the rest of the scene" if self.held_bytes else ""))
        except BudgetError as e:
            raise SceneBudgetError(self.source, path, str(e)) from None
        if held:
            self.held_bytes = total

    def fail(self, path: str, detail: str):
        raise SceneError(self.source, path, detail)

    def build(self, path: str, factory, kwargs: dict, keymap: dict | None = None):
        """Call an engine constructor; its ValueError comes back with the file and key in front.

        The engine names the offending parameter first in its messages
        (conventions.md); that name, mapped to the file's key, completes the path.
        """
        try:
            return factory(**kwargs)
        except ValueError as e:
            msg = str(e)
            keymap = keymap or {}
            names = sorted(set(kwargs) | set(keymap), key=len, reverse=True)
            hit = next((k for k in names if re.match(rf"{re.escape(k)}\b", msg)), None)
            key = keymap.get(hit, hit) if hit else None
            raise SceneError(self.source, _join(path, key) if key else path, msg) from None


class SceneBudgetError(SceneError, BudgetError):
    """A scene (or one of its values) whose estimated memory or work is over the budget
    (:func:`lighting._numeric.memory_budget`)."""


# =============================================================================== work and memory estimates
# Measured with tracemalloc on the example scenes and generated spheres (peak bytes of a render):
#: the renderer's images and buffers, per pixel (270–420 bytes with one to four objects) …
BYTES_PER_PIXEL = 256
#: … and per pixel and object (each object keeps its own geometry buffer; 625 bytes with five objects);
BYTES_PER_PIXEL_PER_OBJECT = 96
#: a triangle of a mesh held by the scene: the mesh (about 170 bytes) and its rasterization and shading (240–370);
BYTES_PER_TRIANGLE = 640
#: reading a mesh file, per byte of the file (trimesh: 5–23 times the file size for OBJ, PLY, STL, OFF, GLB);
BYTES_PER_MESH_FILE_BYTE = 32
#: reading a scene file, per byte (tomllib's objects for short numbers: about 20 times the text).
BYTES_PER_SCENE_FILE_BYTE = 64
#: Work is counted against the same budget: one light sample at one shading point (about 50 ns here) counts as
#: 8 bytes, so the 2 GiB default allows 268 million light-sample evaluations (about 15 s on one core).
BYTES_PER_SAMPLE_EVALUATION = 8


def _clamp(n) -> float:
    """An estimate as a float (a scene's integers can exceed the float range: 4**level, n_lat * n_lon)."""
    return float(min(n, 10**300))


def _charge_file(label: str, size: int) -> None:
    check_budget(f"the scene text ({size} bytes)", _clamp(size * BYTES_PER_SCENE_FILE_BYTE), what="reading it")


# =============================================================================== value checks
# A check is f(ctx, path, value) -> normalized value; it only checks the *type* and finiteness.
# Ranges are the engine's business: its constructors run on every value (see _Ctx.build).
REQUIRED = object()
_ABSENT = object()  # optional key with no default: left out


def _is_number(v) -> bool:
    return isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_))


def _finite_number(ctx, path, v, allowed="a finite number"):
    if not _is_number(v):
        ctx.fail(path, f"must be {allowed}; got {_describe(v)}")
    f = float(v)
    if not math.isfinite(f):
        ctx.fail(path, f"must be {allowed}; got {_fmt_value(f)} (nan and inf are not allowed)")
    return f


def _number(ctx, path, v):
    return _finite_number(ctx, path, v)


def _integer_check(minimum=None, maximum=None):
    lo = "" if minimum is None else f" >= {minimum}"
    allowed = f"an integer{lo}" if maximum is None else f"an integer in [{minimum}, {maximum}]"

    def check(ctx, path, v):
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Integral):
            ctx.fail(path, f"must be {allowed}; got {_describe(v)}")
        if (minimum is not None and v < minimum) or (maximum is not None and v > maximum):
            ctx.fail(path, f"must be {allowed}; got {_fmt_value(v)}")
        return int(v)

    return check


def _boolean(ctx, path, v):
    if not isinstance(v, (bool, np.bool_)):
        ctx.fail(path, f"must be true or false; got {_describe(v)}")
    return bool(v)


def _string(ctx, path, v):
    if not isinstance(v, str):
        ctx.fail(path, f"must be a string; got {_describe(v)}")
    return v


def _choice(choices):
    def check(ctx, path, v):
        allowed = "one of " + ", ".join(repr(c) for c in choices)
        if not isinstance(v, str):
            ctx.fail(path, f"must be {allowed}; got {_describe(v)}")
        for c in choices:
            if _norm_name(v) == _norm_name(c):
                return c
        hint = _suggest(v, choices).strip()
        ctx.fail(path, f"must be {allowed}; got {_fmt_value(v)}" + (f" ({hint})" if hint else ""))

    return check


def _numbers(lengths, what):
    """An array of finite numbers of one of ``lengths``; a check function.  ``what`` says what is allowed."""

    def check(ctx, path, v):
        if not isinstance(v, (list, tuple)):
            ctx.fail(path, f"must be {what}; got {_describe(v)}")
        if len(v) not in lengths:
            ctx.fail(path, f"must be {what}; got {len(v)} entries {_fmt_value(v)}")
        return [_finite_number(ctx, _join(path, i), x) for i, x in enumerate(v)]

    return check


_vec3 = _numbers((3,), "a 3-vector (an array of 3 numbers)")


def _number_or(lengths, what):
    """A finite number, or an array as for :func:`_numbers`."""
    vec = _numbers(lengths, what)

    def check(ctx, path, v):
        if _is_number(v):
            return _finite_number(ctx, path, v, f"{what}, finite")
        return vec(ctx, path, v)

    return check


_color = _number_or((3,), "a colour: a number or [r, g, b]")
_rgba_or_number = _number_or((3, 4), "an OpenGL colour: a number, [r, g, b] or [r, g, b, a]")


def _rgba(ctx, path, v):
    """An OpenGL colour as a list of 4: a number is grey, [r, g, b] has alpha 1."""
    c = _rgba_or_number(ctx, path, v)
    c = [c, c, c] if isinstance(c, float) else c
    return c + [1.0] if len(c) == 3 else c


def _terms_check(ctx, path, v):
    if not isinstance(v, (list, tuple)) or not v:
        ctx.fail(path, f"must be a non-empty array of terms from {', '.join(map(repr, TERMS))}; got {_describe(v)}")
    pick = _choice(TERMS)
    out = [pick(ctx, _join(path, i), t) for i, t in enumerate(v)]
    return [t for t in TERMS if t in out]  # canonical order, no duplicates


def _denominator(ctx, path, v):
    if isinstance(v, numbers.Integral) and not isinstance(v, bool) and v == 4:
        return "4"
    return _choice(CookTorrance.DENOMINATORS)(ctx, path, v)


def _table(ctx, path, value, spec: dict, what: str) -> dict:
    """Check a table against ``spec`` (key → (check, default)); unknown keys get a suggestion."""
    if not isinstance(value, dict):
        ctx.fail(path, f"must be a table ({what}); got {_describe(value)}")
    for k in value:
        if k not in spec:
            hint = _suggest(k, spec)
            ctx.fail(_join(path, k), f"unknown key for {what}; {hint}allowed keys: {', '.join(spec)}")
    out = {}
    for k, (check, default) in spec.items():
        if k in value:
            out[k] = check(ctx, _join(path, k), value[k])
        elif default is REQUIRED:
            ctx.fail(_join(path, k), f"is required in {what}")
        elif default is not _ABSENT:
            out[k] = default
    return out


def _array_of_tables(ctx, path, value, what) -> list:
    if not isinstance(value, (list, tuple)) or not all(isinstance(x, dict) for x in value):
        ctx.fail(path, f"must be an array of tables ([[{path}]] entries, {what}); got {_describe(value)}")
    return list(value)


# =============================================================================== the schema
# Each table: key -> (check, default).  docs/scenes.md lists the same keys (a test keeps them in step).
CAMERA_KEYS = {
    "eye": (_vec3, REQUIRED),
    "target": (_vec3, [0.0, 0.0, 0.0]),
    "up": (_vec3, [0.0, 1.0, 0.0]),
    "projection": (_choice(("perspective", "orthographic")), "perspective"),
    "fov_y_deg": (_number, 30.0),
    "ortho_height": (_number, 2.5),
    "near": (_number, _ABSENT),
    "far": (_number, _ABSENT),
}

IMAGE_KEYS = {
    "width": (_integer_check(1, 16384), 512),
    "height": (_integer_check(1, 16384), 512),
    "background": (_color, 0.0),
    "exposure": (_number, 0.0),
    "tonemap": (_choice(("clamp", "reinhard")), "clamp"),
    "output": (_string, _ABSENT),
}

RENDER_KEYS = {
    "mode": (_choice(SHADING_MODES), "phong"),
    "form": (_choice(FORMS), "classic"),
    "terms": (_terms_check, list(TERMS)),
    "cull_backfaces": (_boolean, True),
}

OPENGL_KEYS = {
    "scene_ambient": (_rgba, [0.2, 0.2, 0.2, 1.0]),
    "local_viewer": (_boolean, False),
}

MODEL_KEYS = {
    "lambert": {"model": (_string, REQUIRED), "kd": (_color, 0.8)},
    "phong": {"model": (_string, REQUIRED), "ks": (_color, 0.5), "shininess": (_number, 32.0)},
    "blinn-phong": {
        "model": (_string, REQUIRED),
        "ks": (_color, 0.5),
        "shininess": (_number, 32.0),
        "normalized": (_boolean, False),
    },
    "cook-torrance": {
        "model": (_string, REQUIRED),
        "ks": (_color, 1.0),
        "roughness": (_number, 0.3),
        "f0": (_color, 0.04),
        "ndf": (_choice(CookTorrance.NDFS), "beckmann"),
        "geometry": (_choice(CookTorrance.GEOMETRIES), "v-cavity"),
        "fresnel": (_choice(CookTorrance.FRESNELS), "schlick"),
        "denominator": (_denominator, "4"),
    },
}
_MODEL_CLASSES = {"lambert": Lambert, "phong": Phong, "blinn-phong": BlinnPhong, "cook-torrance": CookTorrance}

MATERIAL_KEYS = {
    "parts": (lambda ctx, path, v: _array_of_tables(ctx, path, v, "reflectance models"), REQUIRED),
    "ambient": (_color, _ABSENT),
    "emission": (_color, 0.0),
}

GL_MATERIAL_KEYS = {
    "model": (_string, REQUIRED),
    "ambient": (_rgba, [0.2, 0.2, 0.2, 1.0]),
    "diffuse": (_rgba, [0.8, 0.8, 0.8, 1.0]),
    "specular": (_rgba, [0.0, 0.0, 0.0, 1.0]),
    "emission": (_rgba, [0.0, 0.0, 0.0, 1.0]),
    "shininess": (_number, 0.0),
}

_T = (_string, REQUIRED)  # the "type" key
_AREA_COMMON = {
    "color": (_color, 1.0),
    "intensity": (_number, 1.0),
    "samples": (_integer_check(1), 16),
    "seed": (_integer_check(), _ABSENT),
    "two_sided": (_boolean, False),
}
LIGHT_KEYS = {
    "ambient": {"type": _T, "color": (_color, 1.0), "intensity": (_number, 0.2)},
    "directional": {"type": _T, "direction": (_vec3, REQUIRED), "color": (_color, 1.0), "intensity": (_number, 1.0)},
    "point": {
        "type": _T,
        "position": (_vec3, REQUIRED),
        "color": (_color, 1.0),
        "intensity": (_number, 1.0),
        "attenuation": (_vec3, [1.0, 0.0, 0.0]),
    },
    "spot": {
        "type": _T,
        "position": (_vec3, REQUIRED),
        "direction": (_vec3, REQUIRED),
        "cutoff_deg": (_number, 30.0),
        "exponent": (_number, 0.0),
        "color": (_color, 1.0),
        "intensity": (_number, 1.0),
        "attenuation": (_vec3, [1.0, 0.0, 0.0]),
    },
    "rect": {
        "type": _T,
        "center": (_vec3, REQUIRED),
        "edge_u": (_vec3, [1.0, 0.0, 0.0]),
        "edge_v": (_vec3, [0.0, -1.0, 0.0]),
        **_AREA_COMMON,
    },
    "disk": {
        "type": _T,
        "center": (_vec3, REQUIRED),
        "normal_dir": (_vec3, [0.0, 0.0, -1.0]),
        "radius": (_number, 0.5),
        **_AREA_COMMON,
    },
    "opengl": {
        "type": _T,
        "ambient": (_rgba, [0.0, 0.0, 0.0, 1.0]),
        "diffuse": (_rgba, [1.0, 1.0, 1.0, 1.0]),
        "specular": (_rgba, [1.0, 1.0, 1.0, 1.0]),
        "position": (_numbers((3, 4), "a position [x, y, z] or [x, y, z, w]"), [0.0, 0.0, 1.0, 0.0]),
        "spot_direction": (_vec3, [0.0, 0.0, -1.0]),
        "spot_exponent": (_number, 0.0),
        "spot_cutoff": (_number, 180.0),
        "constant_attenuation": (_number, 1.0),
        "linear_attenuation": (_number, 0.0),
        "quadratic_attenuation": (_number, 0.0),
        "space": (_choice(("world", "eye")), "world"),
    },
}
_LIGHT_CLASSES = {
    "ambient": AmbientLight,
    "directional": DirectionalLight,
    "point": PointLight,
    "spot": SpotLight,
    "rect": RectLight,
    "disk": DiskLight,
}

_OBJECT_COMMON = {
    "type": _T,
    "name": (_string, _ABSENT),
    "material": (lambda ctx, path, v: v, _ABSENT),  # a name or an inline table: resolved later
    "mode": (_choice(SHADING_MODES), _ABSENT),
    "cull_backfaces": (_boolean, _ABSENT),
    "lights": (lambda ctx, path, v: _array_of_tables(ctx, path, v, "lights for this object"), _ABSENT),
    "translate": (_vec3, [0.0, 0.0, 0.0]),
    "rotate_deg": (_vec3, [0.0, 0.0, 0.0]),
    "scale": (_number_or((3,), "a scale: a number or [sx, sy, sz]"), 1.0),
}
OBJECT_KEYS = {
    "sphere": {**_OBJECT_COMMON, "center": (_vec3, [0.0, 0.0, 0.0]), "radius": (_number, 1.0)},
    "uv_sphere": {
        **_OBJECT_COMMON,
        "center": (_vec3, [0.0, 0.0, 0.0]),
        "radius": (_number, 1.0),
        "n_lat": (_integer_check(), 16),
        "n_lon": (_integer_check(), 32),
    },
    "icosphere": {
        **_OBJECT_COMMON,
        "center": (_vec3, [0.0, 0.0, 0.0]),
        "radius": (_number, 1.0),
        "level": (_integer_check(), 3),
    },
    "mesh": {**_OBJECT_COMMON, "path": (_string, REQUIRED), "weld": (_boolean, True)},
}

TOP_KEYS = {
    "version": (_integer_check(), FORMAT_VERSION),
    "description": (_string, ""),
    "camera": (lambda ctx, path, v: v, REQUIRED),
    "image": (lambda ctx, path, v: v, {}),
    "render": (lambda ctx, path, v: v, {}),
    "opengl": (lambda ctx, path, v: v, {}),
    "materials": (lambda ctx, path, v: v, {}),
    "objects": (lambda ctx, path, v: _array_of_tables(ctx, path, v, "the things to draw"), REQUIRED),
    "lights": (lambda ctx, path, v: _array_of_tables(ctx, path, v, "the light sources"), []),
}


# =============================================================================== scene data
@dataclass(frozen=True)
class RenderOptions:
    """``[render]``: when lighting is computed, which form, which terms."""

    mode: str = "phong"
    form: str = "classic"
    terms: tuple = TERMS
    cull_backfaces: bool = True


@dataclass(frozen=True)
class ImageOptions:
    """``[image]``: size, background and the encoding to 8-bit sRGB."""

    width: int = 512
    height: int = 512
    background: tuple = (0.0, 0.0, 0.0)
    exposure: float = 0.0
    tonemap: str = "clamp"
    output: str | None = None


@dataclass(frozen=True)
class OpenGLOptions:
    """``[opengl]``: the light model of objects lit by ``type = "opengl"`` lights."""

    scene_ambient: tuple = (0.2, 0.2, 0.2, 1.0)
    local_viewer: bool = False


@dataclass(frozen=True)
class GLLight:
    """An OpenGL light as a scene stores it: :class:`lighting.shading.opengl.Light` plus the space of its coordinates.

    ``space = "world"``: ``position`` and ``spot_direction`` are world
    coordinates, taken to eye space with the camera's view matrix (``glLight``
    called after ``gluLookAt``).  ``space = "eye"``: they are eye coordinates
    already (``glLight`` called with an identity modelview: the light moves
    with the camera).
    """

    light: gl.Light
    space: str = "world"

    def in_eye_space(self, view_matrix) -> gl.Light:
        """The :class:`lighting.shading.opengl.Light` with position and spot direction in eye coordinates."""
        if self.space == "eye":
            return self.light
        V = np.asarray(view_matrix, dtype=np.float64)
        pos = V @ np.asarray(self.light.position)
        sd = V[:3, :3] @ np.asarray(self.light.spot_direction)
        return replace(self.light, position=tuple(pos), spot_direction=tuple(sd))


@dataclass(frozen=True, eq=False)
class SceneObject:
    """One ``[[objects]]`` entry, resolved.

    Attributes
    ----------
    geometry : TriangleMesh or AnalyticSphere
        In world coordinates (the transform already applied).
    material : lighting.shading.equation.Material or lighting.shading.opengl.Material
    material_name : str or None
        The ``[materials]`` name it refers to (None for an inline material).
    mode : str or None
        Shading mode override (None: the scene's ``render.mode``).
    cull_backfaces : bool or None
        Override of ``render.cull_backfaces``.
    lights : tuple or None
        Lights for this object alone, replacing the scene's (None: the scene's).
    spec : dict
        The geometry keys as read (type, name, shape parameters, transform), defaults filled in.
    geometry_key : tuple
        Identifies the geometry: equal keys mean equal geometry (a mesh file's
        modification time and size are part of it), so a renderer can keep its
        rasterization.
    """

    type: str
    geometry: object
    material: object
    material_name: str | None = None
    mode: str | None = None
    cull_backfaces: bool | None = None
    lights: tuple | None = None
    spec: dict = field(default_factory=dict)
    geometry_key: tuple = ()

    @property
    def name(self) -> str | None:
        return self.spec.get("name")


@dataclass(frozen=True, eq=False)
class Scene:
    """A scene: what :func:`load_scene` returns and :class:`SceneRenderer` draws.

    Change a part with :func:`dataclasses.replace` (or :meth:`with_lights`,
    :meth:`with_size`); :meth:`to_dict` / :func:`scene_to_toml` write it back.
    """

    camera: Camera
    objects: tuple
    lights: tuple = ()
    render: RenderOptions = RenderOptions()
    image: ImageOptions = ImageOptions()
    opengl: OpenGLOptions = OpenGLOptions()
    materials: dict = field(default_factory=dict)
    source: str = "<string>"
    description: str = ""

    def object_lights(self, index: int) -> tuple:
        """The lights that shade object ``index``: its own override, else the scene's."""
        own = self.objects[index].lights
        return self.lights if own is None else own

    def object_mode(self, index: int) -> str:
        return self.objects[index].mode or self.render.mode

    def is_opengl_lit(self, index: int) -> bool:
        """True when object ``index`` is lit by OpenGL lights (:func:`lighting.shading.opengl.shade_vertices`)."""
        return any(isinstance(lt, GLLight) for lt in self.object_lights(index))

    @property
    def light_count(self) -> int:
        """Scene lights plus every object's own lights."""
        return len(self.lights) + sum(len(o.lights) for o in self.objects if o.lights is not None)

    def with_lights(self, lights) -> Scene:
        """The same scene under other (scene-level) lights."""
        return replace(self, lights=tuple(lights))

    def with_size(self, width: int, height: int) -> Scene:
        """The same scene at another image size (the camera keeps its field of view)."""
        cam = self.camera.replace(width=width, height=height)
        return replace(self, camera=cam, image=replace(self.image, width=cam.width, height=cam.height))

    def to_dict(self) -> dict:
        """The scene as plain data (what a TOML file holds, defaults written out); :func:`parse_scene` reads it."""
        return _scene_to_dict(self)


# =============================================================================== parsing
def load_scene(path) -> Scene:
    """Read a scene file (TOML).  Relative mesh paths are relative to the file's folder.

    Raises
    ------
    SceneError
        For anything wrong with the file: unreadable, invalid TOML (with its line
        and column), unknown keys, wrong types, values out of range, missing or
        unreadable meshes.
    """
    label = os.fspath(path)
    try:
        # O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer (no effect on regular files)
        fd = os.open(label, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
        with open(fd, "rb") as f:
            st = os.fstat(f.fileno())
            if not stat.S_ISREG(st.st_mode):  # a FIFO or a device would block or never end
                raise SceneError(label, "", "is not a regular file (a scene file must be one)")
            _charge_file(label, st.st_size)
            raw = f.read(st.st_size + 1)
    except FileNotFoundError:
        raise SceneError(label, "", "scene file does not exist") from None
    except IsADirectoryError:
        raise SceneError(label, "", "is a directory, not a scene file") from None
    except BudgetError as e:
        raise SceneBudgetError(label, "", str(e)) from None
    except OSError as e:
        raise SceneError(label, "", f"cannot read the scene file: {e.strerror or e}") from None
    return parse_scene(raw, source=label, base_dir=os.path.dirname(os.path.abspath(label)))


def parse_scene(data, source: str = "<string>", *, base_dir=None) -> Scene:
    """A :class:`Scene` from TOML text or from the equivalent dict.

    Parameters
    ----------
    data : str, bytes or dict
        TOML text (bytes: UTF-8), or the dict ``tomllib`` would make of it (e.g. from
        :meth:`Scene.to_dict`).
    source : str
        Name used in error messages (the file name).
    base_dir : path, optional
        Folder that relative mesh paths start from (default: the current folder).
    """
    ctx = _Ctx(source, os.fspath(base_dir) if base_dir is not None else os.getcwd())
    if isinstance(data, (bytes, bytearray)):
        try:
            data = bytes(data).decode("utf-8")
        except UnicodeDecodeError as e:
            line = bytes(data)[: e.start].count(b"\n") + 1
            raise SceneError(source, "", f"invalid TOML: not UTF-8 text (byte {e.start}, line {line})") from None
    if isinstance(data, str):
        try:  # text given directly (load_scene checked the file's size already)
            _charge_file(source, len(data))
        except BudgetError as e:
            raise SceneBudgetError(source, "", str(e)) from None
        _check_text_nesting(ctx, data)
        try:
            data = tomllib.loads(data)
        except tomllib.TOMLDecodeError as e:
            raise SceneError(source, "", f"invalid TOML: {e}") from None
        except RecursionError:  # the scan above should have caught it; a last line of defence
            detail = f"invalid TOML: arrays or tables nested too deep (allowed: {MAX_NESTING})"
            raise SceneError(source, "", detail) from None
        except ValueError as e:  # tomllib passes on int()'s own refusals (an integer of more than 4300 digits)
            raise SceneError(source, "", f"invalid TOML: {e}") from None
    if not isinstance(data, dict):
        raise SceneError(source, "", f"a scene must be TOML text or a dict; got {type(data).__name__}")
    _check_dict_nesting(ctx, data)
    return _parse(ctx, data)


#: Deepest nesting of arrays and tables a scene may use (a scene needs about 7: objects[0].material.parts[0].kd).
#: tomllib reads nested values recursively, and 500 levels exhaust Python's stack: the text is scanned first.
MAX_NESTING = 32

# TOML's lexical pieces that matter for nesting: strings (brackets inside them do not count), comments,
# brackets and braces, line ends; everything else in runs.
_NEST_TOKENS = re.compile(
    r'"""(?:\\.|[^\\])*?"""|\'\'\'.*?\'\'\'|"(?:\\.|[^"\\\n])*"|\'[^\'\n]*\'|#[^\n]*|[\[\]{}\n]|[^"\'#\[\]{}\n]+',
    re.S,
)
_HEADER = re.compile(r"(?m)^[ \t]*(\[\[?)[ \t]*([^\[\]\n]+?)[ \t]*\]")


def _check_text_nesting(ctx, text: str) -> None:
    """Refuse TOML text whose arrays or inline tables nest deeper than :data:`MAX_NESTING`, naming the key."""
    depth, opened = 0, 0
    for m in _NEST_TOKENS.finditer(text):
        tok = m.group()
        if tok in ("[", "{"):
            if depth == 0:
                opened = m.start()
            depth += 1
            if depth > MAX_NESTING:
                ctx.fail(_key_at(text, opened), f"arrays or tables nested more than {MAX_NESTING} deep "
                         f"(line {text.count(chr(10), 0, m.start()) + 1}); a scene needs fewer than 10 levels")
        elif tok in ("]", "}"):
            depth = max(depth - 1, 0)


def _key_at(text: str, pos: int) -> str:
    """The key path of the value starting at ``pos``: the last table header before it and the key on its line."""
    path = ""
    headers = list(_HEADER.finditer(text, 0, pos))
    if headers:
        last = headers[-1]
        name = ".".join(part.strip().strip("\"'") for part in last.group(2).split("."))
        if last.group(1) == "[[":
            index = sum(1 for h in headers if h.group(1) == "[[" and h.group(2) == last.group(2)) - 1
            name = f"{name}[{index}]"
        path = name
    line = text[text.rfind("\n", 0, pos) + 1 : pos]
    if "=" in line:
        key = line.split("=", 1)[0].strip().strip("\"'")
        path = _join(path, key) if key else path
    return path


def _check_dict_nesting(ctx, data: dict) -> None:
    """The same limit for a scene given as a dict (walked without recursion)."""
    stack = [("", data, 1)]
    while stack:
        path, value, depth = stack.pop()
        if depth > MAX_NESTING:
            ctx.fail(path, f"arrays or tables nested more than {MAX_NESTING} deep; a scene needs fewer than 10 levels")
        items = value.items() if isinstance(value, dict) else enumerate(value)
        for k, v in items:
            if isinstance(v, (dict, list, tuple)):
                stack.append((_join(path, k if isinstance(k, (int, str)) else str(k)), v, depth + 1))


def _parse(ctx: _Ctx, data: dict) -> Scene:
    top = _table(ctx, "", data, TOP_KEYS, "a scene file")
    if top["version"] != FORMAT_VERSION:
        ctx.fail("version", f"must be {FORMAT_VERSION} (the only format version); got {top['version']}")

    img = _table(ctx, "image", top["image"], IMAGE_KEYS, "the [image] table")
    image = ImageOptions(
        width=img["width"],
        height=img["height"],
        background=tuple(ctx.build("image", _rgb, {"background": img["background"]})),
        exposure=img["exposure"],
        tonemap=img["tonemap"],
        output=img.get("output"),
    )

    cam = _table(ctx, "camera", top["camera"], CAMERA_KEYS, "the [camera] table")
    _check_view_distance(ctx, cam)
    camera = ctx.build("camera", Camera, {**cam, "width": image.width, "height": image.height})

    r = _table(ctx, "render", top["render"], RENDER_KEYS, "the [render] table")
    render = RenderOptions(mode=r["mode"], form=r["form"], terms=tuple(r["terms"]), cull_backfaces=r["cull_backfaces"])

    o = _table(ctx, "opengl", top["opengl"], OPENGL_KEYS, "the [opengl] table")
    opengl = OpenGLOptions(scene_ambient=tuple(o["scene_ambient"]), local_viewer=o["local_viewer"])

    if not isinstance(top["materials"], dict):
        ctx.fail(
            "materials", f"must be a table of named materials ([materials.NAME]); got {_describe(top['materials'])}"
        )
    materials = {name: _material(ctx, _join("materials", name), m) for name, m in top["materials"].items()}

    lights = tuple(_light(ctx, _join("lights", i), t) for i, t in enumerate(top["lights"]))
    _check_light_mix(ctx, "lights", lights)

    if not top["objects"]:
        ctx.fail("objects", "a scene needs at least one [[objects]] entry")
    objects = tuple(
        _object(ctx, _join("objects", i), t, materials, lights, render) for i, t in enumerate(top["objects"])
    )
    if render.form == "physical":
        for i, ob in enumerate(objects):
            if any(isinstance(lt, GLLight) for lt in (ob.lights if ob.lights is not None else lights)):
                ctx.fail(
                    "render.form",
                    f"'physical' is not available for objects lit by OpenGL lights (objects[{i}]): "
                    "the fixed-function equation has only the classic form; use form = 'classic'",
                )
    return Scene(
        camera=camera,
        objects=objects,
        lights=lights,
        render=render,
        image=image,
        opengl=opengl,
        materials=materials,
        source=ctx.source,
        description=top["description"],
    )


def _check_view_distance(ctx, cam):
    """``target − eye`` and its length must be finite: each key may be finite while their distance is not.

    The camera would then see a zero view direction and blame ``up``; the key at fault is the far point.
    """
    eye, target = np.asarray(cam["eye"]), np.asarray(cam["target"])
    with np.errstate(over="ignore", invalid="ignore"):
        d = target - eye
        big = np.max(np.abs(d))
        length = float(big * np.sqrt(np.sum((d / big) ** 2))) if big > 0 else 0.0
    # far defaults to 1000 times the distance: keep that finite too
    if not length < 1e305:
        key = "camera.eye" if np.max(np.abs(eye)) >= np.max(np.abs(target)) else "camera.target"
        ctx.fail(key, f"eye and target must be a finite distance apart (below 1e305); got eye = "
                      f"{_fmt_value(cam['eye'])}, target = {_fmt_value(cam['target'])}")


def _rgb(background):
    return [float(x) for x in check_color("background", background)]


def _material(ctx, path, table):
    """``[materials.NAME]`` or an inline material: engine parts, or ``model = "opengl"``."""
    if not isinstance(table, dict):
        ctx.fail(path, f"must be a material table (parts = [...], or model = 'opengl'); got {_describe(table)}")
    if "model" in table:
        if "parts" in table:
            ctx.fail(path, "a material has either parts = [...] (engine models) or model = 'opengl', not both")
        if not isinstance(table["model"], str) or _norm_name(table["model"]) != "opengl":
            ctx.fail(
                _join(path, "model"),
                f"a material's own model can only be 'opengl'; got {_describe(table['model'])}. "
                f"Engine models ({', '.join(map(repr, MODEL_KEYS))}) go in parts = [{{model = ..., ...}}]",
            )
        m = _table(ctx, path, table, GL_MATERIAL_KEYS, "an OpenGL material")
        m.pop("model")
        return ctx.build(path, gl.Material, m)
    if "parts" not in table:
        hint = _suggest(next(iter(table), ""), ["parts", "model"]) if table else ""
        ctx.fail(
            _join(path, "parts"),
            f"is required: a material is parts = [{{model = 'lambert', kd = 0.8}}, ...] "
            f"(models {', '.join(map(repr, MODEL_KEYS))}) or model = 'opengl' {hint}".rstrip(),
        )
    m = _table(ctx, path, table, MATERIAL_KEYS, "a material")
    if not m["parts"]:
        ctx.fail(_join(path, "parts"), "must list at least one reflectance model")
    brdf = None
    for i, part in enumerate(m["parts"]):
        ppath = _join(_join(path, "parts"), i)
        if "model" not in part:
            ctx.fail(_join(ppath, "model"), f"is required: one of {', '.join(map(repr, MODEL_KEYS))}")
        name = _choice(tuple(MODEL_KEYS))(ctx, _join(ppath, "model"), part["model"])
        params = _table(ctx, ppath, part, MODEL_KEYS[name], f"a {name!r} model")
        params.pop("model")
        model = ctx.build(ppath, _MODEL_CLASSES[name], params)
        brdf = model if brdf is None else brdf + model
    kwargs = {"brdf": brdf, "emission": m["emission"]}
    if "ambient" in m:
        kwargs["ambient"] = m["ambient"]
    return ctx.build(path, Material, kwargs)


def _light(ctx, path, table):
    if not isinstance(table, dict):
        ctx.fail(path, f"must be a light table; got {_describe(table)}")
    if "type" not in table:
        ctx.fail(_join(path, "type"), f"is required: one of {', '.join(map(repr, LIGHT_KEYS))}")
    kind = _choice(tuple(LIGHT_KEYS))(ctx, _join(path, "type"), table["type"])
    params = _table(ctx, path, table, LIGHT_KEYS[kind], f"a {kind!r} light")
    params.pop("type")
    if kind == "opengl":
        space = params.pop("space")
        return GLLight(ctx.build(path, gl.Light, params), space)
    light = ctx.build(path, _LIGHT_CLASSES[kind], params)
    # The values as written, for writing back: the light keeps only the normalized direction, and
    # normalizing a unit vector again can move its last bit.  The light is frozen, so they stay true.
    try:
        object.__setattr__(light, "_scene_values", params)
    except AttributeError:  # a light class with __slots__: write back its (normalized) fields instead
        pass
    return light


def _check_light_mix(ctx, path, lights):
    gl_idx = [i for i, lt in enumerate(lights) if isinstance(lt, GLLight)]
    if gl_idx and len(gl_idx) != len(lights):
        other = next(i for i, lt in enumerate(lights) if not isinstance(lt, GLLight))
        ctx.fail(
            _join(_join(path, other), "type"),
            f"cannot mix engine lights with OpenGL lights ({path}[{gl_idx[0]}] has type 'opengl'): "
            "OpenGL-lit objects are shaded by the fixed-function equation; give every light type 'opengl' "
            "(use [opengl].scene_ambient for ambient light) or none",
        )


def _rotation(deg) -> np.ndarray:
    """``R = R_z R_y R_x``: rotate about world x, then y, then z (right-hand rule)."""
    ax, ay, az = (math.radians(d) for d in deg)
    cx, sx, cy, sy, cz, sz = math.cos(ax), math.sin(ax), math.cos(ay), math.sin(ay), math.cos(az), math.sin(az)
    rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return rz @ ry @ rx


def object_matrix(translate=(0.0, 0.0, 0.0), rotate_deg=(0.0, 0.0, 0.0), scale=1.0) -> np.ndarray:
    """The 4×4 object-to-world transform ``M = T R_z R_y R_x S`` (scale, then rotate, then translate).

    Examples
    --------
    >>> M = object_matrix(translate=(1, 0, 0), rotate_deg=(0, 0, 90), scale=2)
    >>> (M @ [1, 0, 0, 1]).round(12).tolist()  # (1,0,0) → scaled to (2,0,0) → turned to (0,2,0) → moved
    [1.0, 2.0, 0.0, 1.0]
    """
    s = np.broadcast_to(np.asarray(scale, dtype=np.float64), (3,))
    M = np.eye(4)
    M[:3, :3] = _rotation(rotate_deg) @ np.diag(s)
    M[:3, 3] = translate
    return M


def _object(ctx, path, table, materials, scene_lights, render):
    if not isinstance(table, dict):
        ctx.fail(path, f"must be an object table; got {_describe(table)}")
    if "type" not in table:
        ctx.fail(_join(path, "type"), f"is required: one of {', '.join(map(repr, OBJECT_KEYS))}")
    kind = _choice(tuple(OBJECT_KEYS))(ctx, _join(path, "type"), table["type"])
    spec = _table(ctx, path, table, OBJECT_KEYS[kind], f"a {kind!r} object")
    spec["type"] = kind
    scale = spec["scale"]
    if np.any(np.asarray(scale) == 0):
        ctx.fail(
            _join(path, "scale"),
            f"must be nonzero in every axis (a zero scale flattens the object); got {_fmt_value(scale)}",
        )
    M = object_matrix(spec["translate"], spec["rotate_deg"], scale)
    key_extra = ()

    if kind == "sphere":
        if not _is_number(scale) and len(set(abs(s) for s in scale)) > 1:
            ctx.fail(
                _join(path, "scale"),
                f"an analytic sphere takes only a uniform scale (a number); got {_fmt_value(scale)}; "
                "use type = 'icosphere' or 'uv_sphere' for an ellipsoid",
            )
        base = ctx.build(path, AnalyticSphere, {"center": spec["center"], "radius": spec["radius"]})
        s = abs(float(scale if _is_number(scale) else scale[0]))
        center = M[:3, :3] @ np.asarray(base.center) + M[:3, 3]
        geometry = ctx.build(path, AnalyticSphere, {"center": tuple(center), "radius": base.radius * s})
    else:
        if kind == "uv_sphere":
            n_lat, n_lon = spec["n_lat"], spec["n_lon"]
            triangles = 2 * max(n_lon, 0) * max(n_lat - 1, 0)
            key = "n_lat" if n_lat >= n_lon / 2 else "n_lon"
            ctx.charge(_join(path, key), triangles * BYTES_PER_TRIANGLE, f"a uv sphere of {triangles} triangles")
            args = {k: spec[k] for k in ("n_lat", "n_lon", "radius", "center")}
            mesh = ctx.build(path, uv_sphere, args)
        elif kind == "icosphere":
            triangles = 20 * 4 ** min(max(spec["level"], 0), 40)
            what = f"an icosphere of {triangles} triangles"
            ctx.charge(_join(path, "level"), triangles * BYTES_PER_TRIANGLE, what)
            args = {k: spec[k] for k in ("level", "radius", "center")}
            mesh = ctx.build(path, icosphere, args)
        else:
            p = os.path.join(ctx.base_dir, os.path.expanduser(spec["path"]))
            p = os.path.normpath(p)
            cache_key = (p, spec["weld"])
            if cache_key not in ctx.meshes:
                try:
                    size = os.stat(p).st_size
                except (OSError, ValueError):
                    size = 0  # load_mesh names the problem
                ctx.charge(_join(path, "path"), size * BYTES_PER_MESH_FILE_BYTE, f"reading a mesh file of {size} bytes",
                           held=False)  # fmt: skip
                try:
                    ctx.meshes[cache_key] = load_mesh(p, weld=spec["weld"])
                except ValueError as e:
                    ctx.fail(_join(path, "path"), str(e))
            mesh = ctx.meshes[cache_key]
            what = f"a mesh of {mesh.n_triangles} triangles"
            ctx.charge(_join(path, "path"), mesh.n_triangles * BYTES_PER_TRIANGLE, what)
            try:
                st = os.stat(p)
                key_extra = (p, st.st_mtime_ns, st.st_size)
            except OSError:  # pragma: no cover - vanished between load and stat
                key_extra = (p,)
        geometry = (
            mesh
            if np.array_equal(M, np.eye(4))
            else ctx.build(path, mesh.transformed, {"matrix": M}, {"matrix": "scale"})
        )
        if not np.any(geometry.face_areas > 0):
            ctx.fail(path, "the transformed mesh has only zero-area triangles")

    mode = spec.get("mode")
    if isinstance(geometry, AnalyticSphere) and (mode or render.mode) != "phong":
        where = _join(path, "mode") if mode else "render.mode"
        ctx.fail(
            where,
            f"an analytic sphere ({path}) is ray-cast per pixel and supports only mode 'phong'; "
            f"got {mode or render.mode!r}: set {_join(path, 'mode')} = 'phong' or use type = 'icosphere'",
        )

    own_lights = None
    if "lights" in spec:
        own_lights = tuple(_light(ctx, _join(_join(path, "lights"), i), t) for i, t in enumerate(spec["lights"]))
        _check_light_mix(ctx, _join(path, "lights"), own_lights)
    effective = scene_lights if own_lights is None else own_lights
    gl_lit = any(isinstance(lt, GLLight) for lt in effective)

    material_name = None
    mpath = _join(path, "material")
    if "material" not in spec:
        material = gl.Material() if gl_lit else Material(Lambert(0.8))
    elif isinstance(spec["material"], str):
        material_name = spec["material"]
        if material_name not in materials:
            hint = _suggest(material_name, list(materials))
            known = ", ".join(map(repr, materials)) or "none"
            name = abbreviate(repr(material_name))
            ctx.fail(mpath, f"no material named {name} in [materials]; {hint}defined: {abbreviate(known)}")
        material = materials[material_name]
    else:
        if not isinstance(spec["material"], dict):
            ctx.fail(
                mpath,
                f"must be a material name (a string) or an inline material table; got {_describe(spec['material'])}",
            )
        material = _material(ctx, mpath, spec["material"])
    if gl_lit and not isinstance(material, gl.Material):
        lpath = _join(path, "lights") if own_lights is not None else "lights"
        ctx.fail(
            mpath,
            f"this object is lit by OpenGL lights ({lpath}), so its material must have model = 'opengl' "
            "(the fixed-function equation knows only OpenGL materials); got an engine material"
            + (f" {_fmt_value(material_name)}" if material_name else ""),
        )

    geo_spec = {k: v for k, v in spec.items() if k not in ("material", "lights", "mode", "cull_backfaces")}
    key = (json.dumps(geo_spec, sort_keys=True),) + key_extra
    return SceneObject(
        type=kind,
        geometry=geometry,
        material=material,
        material_name=material_name,
        mode=mode,
        cull_backfaces=spec.get("cull_backfaces"),
        lights=own_lights,
        spec=geo_spec,
        geometry_key=key,
    )


# =============================================================================== OpenGL mapping
def gl_material_to_engine(material: gl.Material) -> Material:
    """An OpenGL material on the engine's classic form.

    ``Lambert(d_cm) + BlinnPhong(s_cm, s_rm)`` (unnormalized, the slides' and
    OpenGL's ``k_s (n·h)^e``), ambient ``k_a = a_cm``, emission ``k_e = e_cm``;
    alpha is dropped.  Under an engine light of colour ``I`` this gives
    ``k_d I (n·l) + k_s I (n·h)^e`` — OpenGL's bracket with ``d_cli = s_cli = I``.

    Examples
    --------
    >>> m = gl_material_to_engine(gl.Material(diffuse=(0.5, 0.5, 0.5), specular=(1, 1, 1), shininess=20))
    >>> m.brdf
    Lambert(kd=0.5) + BlinnPhong(ks=1.0, shininess=20.0, normalized=False)
    """
    if not isinstance(material, gl.Material):
        raise ValueError(f"material must be a lighting.shading.opengl.Material; got {type(material).__name__}")
    brdf = Lambert(material.diffuse[:3]) + BlinnPhong(material.specular[:3], material.shininess, normalized=False)
    return Material(brdf, ambient=material.ambient[:3], emission=material.emission[:3])


def _gl_with_terms(material: gl.Material, terms) -> gl.Material:
    """Keep only the chosen terms: each term of the GL equation is linear in one material colour."""
    zero = (0.0, 0.0, 0.0, 1.0)
    keep = {"emission": "emission", "ambient": "ambient", "diffuse": "diffuse", "specular": "specular"}
    changes = {attr: zero for t, attr in keep.items() if t not in terms}
    if "diffuse" in changes:  # the vertex alpha is the diffuse alpha: keep it
        changes["diffuse"] = (0.0, 0.0, 0.0, material.diffuse[3])
    return replace(material, **changes) if changes else material


# =============================================================================== rendering
def _camera_key(cam: Camera) -> tuple:
    return (
        tuple(cam.eye), tuple(cam.target), tuple(cam.up), cam.projection, cam.fov_y_deg, cam.ortho_height,
        cam.width, cam.height, cam.near, cam.far,
    )  # fmt: skip


class SceneRenderer:
    """Render a :class:`Scene`: one cached :class:`~lighting.render.renderer.Renderer` per object, composited by depth.

    The pipeline of :meth:`render`:

    1. rasterize every object (once: each :class:`~lighting.render.renderer.Renderer`
       keeps its geometry buffer until the object's geometry or the camera change);
    2. :meth:`visibility`: per pixel, the index of the nearest covering object
       (``−1`` for background) — smallest view depth, ties to the lower index;
    3. :meth:`shade_object` for each object (the one lighting call);
    4. composite: each pixel takes the colour of its visible object, the
       background elsewhere.

    Assigning a new scene (``renderer.scene = other``) keeps the rasterization of
    every object whose geometry (:attr:`SceneObject.geometry_key`) and camera are
    unchanged: moving a light or editing a material re-shades only.

    Examples
    --------
    >>> scene = load_scene(example_path("directional_ambient")).with_size(48, 36)
    >>> sr = SceneRenderer(scene)
    >>> image, info = sr.render()
    >>> sr.scene = scene.with_lights([AmbientLight(intensity=0.5)])
    >>> image2, info2 = sr.render()
    >>> info["rasterized"], info2["rasterized"]  # the second render re-used every geometry buffer
    (4, 0)
    """

    def __init__(self, scene: Scene, *, dtype=np.float64, plan=True):
        if not isinstance(scene, Scene):
            raise ValueError(f"scene must be a lighting.scene.Scene; got {type(scene).__name__}")
        if plan not in (True, False, "full"):
            raise ValueError(f"plan must be True, False or 'full'; got {plan!r}")
        check_scene_budget(scene)  # before any buffer is allocated
        self.dtype = dtype
        #: True: evaluate through :mod:`lighting.render.plan` (leave out what the scene does not need);
        #: False: the renderer's general path; "full": the nothing-skipped reference
        #: (:func:`lighting.render.plan.evaluate_full`), for measuring the plan against.
        self.plan = plan
        self._scene = scene
        self._renderers: list[Renderer | None] = [None] * len(scene.objects)
        self._keys: list[tuple | None] = [None] * len(scene.objects)
        self._visibility = None
        self._gl_cache: dict = {}

    # ------------------------------------------------------------------ state
    @property
    def scene(self) -> Scene:
        return self._scene

    @scene.setter
    def scene(self, new: Scene):
        if not isinstance(new, Scene):
            raise ValueError(f"scene must be a lighting.scene.Scene; got {type(new).__name__}")
        check_scene_budget(new)
        same_camera = _camera_key(new.camera) == _camera_key(self._scene.camera)
        old = list(zip(self._keys, self._renderers, strict=True))
        self._scene = new
        self._renderers = [None] * len(new.objects)
        self._keys = [None] * len(new.objects)
        for i in range(len(new.objects)):
            if same_camera and i < len(old) and old[i][0] == self._object_key(i):
                self._keys[i], self._renderers[i] = old[i]
        if not (same_camera and len(old) == len(new.objects) and all(r is not None for r in self._renderers)):
            self._visibility = None
        kept = {i for i, r in enumerate(self._renderers) if r is not None}
        self._gl_cache = {k: v for k, v in self._gl_cache.items() if k[0] in kept}

    def _object_key(self, i: int) -> tuple:
        ob = self._scene.objects[i]
        cull = self._scene.render.cull_backfaces if ob.cull_backfaces is None else ob.cull_backfaces
        return ob.geometry_key + (cull,)

    @property
    def rasterizations(self) -> int:
        """Rasterizations (or ray casts) done by the cached renderers so far."""
        return sum(r.rasterizations for r in self._renderers if r is not None)

    def renderer(self, index: int) -> Renderer:
        """The cached :class:`~lighting.render.renderer.Renderer` of object ``index`` (created on first use)."""
        if self._renderers[index] is None:
            ob = self._scene.objects[index]
            cull = self._scene.render.cull_backfaces if ob.cull_backfaces is None else ob.cull_backfaces
            self._renderers[index] = Renderer(ob.geometry, self._scene.camera, dtype=self.dtype, cull_backfaces=cull)
            self._keys[index] = self._object_key(index)
        return self._renderers[index]

    def visibility(self) -> np.ndarray:
        """``(H, W)`` int: index of the object seen at each pixel, ``−1`` where none is."""
        if self._visibility is None:
            cam = self._scene.camera
            best = np.full((cam.height, cam.width), np.inf)
            owner = np.full((cam.height, cam.width), -1, dtype=np.int64)
            for i in range(len(self._scene.objects)):
                gb = self.renderer(i).gbuffer
                d = np.where(gb.coverage, gb.depth.astype(np.float64), np.inf)
                nearer = d < best
                best = np.where(nearer, d, best)
                owner[nearer] = i
            self._visibility = owner
        return self._visibility

    # ------------------------------------------------------------------ shading
    def shade_object(self, index: int, renderer: Renderer, material, lights) -> np.ndarray:
        """Light object ``index``: its ``(H, W, 3)`` linear image (zero where it does not cover the pixel).

        Engine lights: ``renderer.render(material, lights, mode=…, form=…, terms=…)``
        (an OpenGL material is first mapped by :func:`gl_material_to_engine`).
        OpenGL lights: :func:`lighting.shading.opengl.shade_vertices` at the mode's shading
        samples in eye coordinates.
        """
        scene = self._scene
        mode = scene.object_mode(index)
        if any(isinstance(lt, GLLight) for lt in lights):
            return self._shade_gl(index, renderer, material, lights, mode)
        if isinstance(material, gl.Material):
            material = gl_material_to_engine(material)
        if self.plan is True:
            return self.object_plan(index).execute(renderer)
        if self.plan == "full":
            from ..render.plan import evaluate_full

            opts = {"mode": mode, "form": scene.render.form, "terms": scene.render.terms}
            return evaluate_full(renderer, material, lights, **opts)
        return renderer.render(material, lights, mode=mode, form=scene.render.form, terms=scene.render.terms)

    # ------------------------------------------------------------------ plans
    def object_plan(self, index: int):
        """The evaluation plan of object ``index`` (engine-lit objects; see :mod:`lighting.render.plan`)."""
        from ..render.plan import bounding_sphere, compile_plan

        scene = self._scene
        ob = scene.objects[index]
        material = ob.material
        if isinstance(material, gl.Material):
            material = gl_material_to_engine(material)
        return compile_plan(
            material, scene.object_lights(index), mode=scene.object_mode(index), form=scene.render.form,
            terms=scene.render.terms, bounds=bounding_sphere(ob.geometry),
        )  # fmt: skip

    def _groups(self, visible):
        """Objects to shade, grouped: ``[(indices, plan or None)]``; hidden objects are left out.

        Objects that share one material, one light list and one shading mode are
        shaded in a single evaluation over all their samples.
        """
        scene = self._scene
        groups: dict = {}
        order = []
        for i, ob in enumerate(scene.objects):
            if visible[i] == 0:
                continue
            lights = scene.object_lights(i)
            if scene.is_opengl_lit(i):
                order.append(((i,), None))
                continue
            key = (id(ob.material), tuple(id(lt) for lt in lights), scene.object_mode(i))
            if key not in groups:
                groups[key] = [i]
                order.append((key, None))
            else:
                groups[key].append(i)
        out = []
        for key, _ in order:
            if isinstance(key, tuple) and len(key) == 1 and isinstance(key[0], int):
                out.append((key, None))
            else:
                out.append((tuple(groups[key]), self.object_plan(groups[key][0])))
        return out

    def _planned_composite(self, image, owner, visible):
        """Shade every visible object through its plan and write its visible pixels into ``image``.

        Per-pixel (phong) objects are lit only where they are not hidden behind
        another object; nothing goes through a full-size intermediate image.
        """
        flat_image = image.reshape(-1)
        flat_owner = owner.reshape(-1)

        def write(i, idx, values):
            keep = flat_owner[idx] == i
            idx, values = idx[keep], values[keep]
            for ch in range(3):
                flat_image[idx * 3 + ch] = values[:, ch]

        for indices, plan in self._groups(visible):
            if plan is None:  # OpenGL-lit: the fixed-function equation, evaluated as it is
                i = indices[0]
                ob = self._scene.objects[i]
                c = self.shade_object(i, self.renderer(i), ob.material, self._scene.object_lights(i))
                mine = owner == i
                image[mine] = c[mine]
                continue
            renderers = [self.renderer(i) for i in indices]
            if plan.strategy == "constant":
                for i in indices:
                    idx = np.flatnonzero(flat_owner == i)
                    for ch in range(3):
                        flat_image[idx * 3 + ch] = plan.constant[ch]
                continue
            if plan.mode == "phong":
                for i, r in zip(indices, renderers, strict=True):
                    r.restrict(np.flatnonzero(flat_owner[r.gbuffer.pixels] == i))
            if len(indices) == 1:
                parts = [plan.shade_samples(renderers[0])]
            else:
                group = _GroupSamples(renderers)
                colours = plan.shade_samples(group)
                edges = np.cumsum([0] + group.lengths(plan.mode))
                parts = [colours[a:b] for a, b in zip(edges[:-1], edges[1:], strict=True)]
            for i, r, c in zip(indices, renderers, parts, strict=True):
                write(i, *r.spread_pixels(plan.mode, c))

    def explain(self) -> str:
        """What the scene needs, in plain words: one plan per group of objects, and what was left out."""
        scene = self._scene
        owner = self.visibility()
        visible = tuple(int(np.count_nonzero(owner == i)) for i in range(len(scene.objects)))
        lines = [f"{len(scene.objects)} object(s), {scene.light_count} light(s), {scene.camera.width}x"
                 f"{scene.camera.height} pixels."]  # fmt: skip
        for i, n in enumerate(visible):
            if n == 0:
                lines.append(f"object {i} ({_object_name(scene.objects[i])}): left out — hidden behind other objects")
        for indices, plan in self._groups(visible):
            names = ", ".join(f"{i} ({_object_name(scene.objects[i])})" for i in indices)
            label = "objects" if len(indices) > 1 else "object"
            if plan is None:
                lines.append(f"{label} {names}: OpenGL fixed-function lighting (evaluated as specified)")
                continue
            extra = " — one material, one evaluation for all" if len(indices) > 1 else ""
            lines.append(f"{label} {names}{extra}:")
            lines.extend("  " + ln for ln in plan.describe().splitlines())
        cached = sum(r is not None and r._gbuffer is not None for r in self._renderers)
        if cached:
            lines.append(f"geometry buffers: {cached} cached; re-rendering with new lights or materials re-uses them")
        return "\n".join(lines)

    def _gl_samples(self, index: int, renderer: Renderer, mode: str):
        key = (index, mode)
        if key not in self._gl_cache:
            gb = renderer.gbuffer
            if mode == "phong":
                pts, nrm = gb.position[gb.coverage], gb.normal[gb.coverage]
            else:
                mesh = renderer.geometry
                if mode == "gouraud":
                    pts, nrm = mesh.vertices, mesh.normals
                else:
                    pts, nrm = mesh.vertices[mesh.faces].mean(axis=1), mesh.face_normals
            V = self._scene.camera.view_matrix()
            R = V[:3, :3]
            pts = np.asarray(pts, dtype=np.float64) @ R.T + V[:3, 3]
            nrm = np.asarray(nrm, dtype=np.float64) @ R.T  # V's 3×3 block is a rotation: its inverse transpose
            self._gl_cache[key] = (pts, nrm)
        return self._gl_cache[key]

    def _shade_gl(self, index, renderer, material, lights, mode):
        scene = self._scene
        pts, nrm = self._gl_samples(index, renderer, mode)
        V = scene.camera.view_matrix()
        eye_lights = [lt.in_eye_space(V) for lt in lights]
        mat = _gl_with_terms(material, scene.render.terms)
        rgb = gl.shade_vertices(
            pts, nrm, mat, eye_lights, scene_ambient=scene.opengl.scene_ambient, local_viewer=scene.opengl.local_viewer
        )[..., :3].astype(self.dtype)
        gb = renderer.gbuffer
        if mode == "phong":
            out = np.zeros((gb.coverage.size, 3), dtype=self.dtype)
            out[gb.pixels] = rgb
            return out.reshape(gb.shape + (3,))
        if mode == "gouraud":
            return gb.interpolate(rgb).astype(self.dtype, copy=False)
        return gb.per_face(rgb).astype(self.dtype, copy=False)

    def render(self):
        """``(image, info)``: the linear RGB image ``(H, W, 3)`` and a summary.

        ``info`` holds ``width``, ``height``, ``objects``, ``lights`` (scene
        lights plus objects' own), ``visible_pixels`` (per object, after the
        depth test), ``covered_pixels``, ``rasterized`` (geometry buffers built
        by this call) and ``seconds``.
        """
        t0 = time.perf_counter()
        scene = self._scene
        before = self.rasterizations
        owner = self.visibility()
        cam = scene.camera
        image = np.empty((cam.height, cam.width, 3), dtype=self.dtype)
        image[...] = np.asarray(scene.image.background, dtype=self.dtype)
        visible = tuple(int(np.count_nonzero(owner == i)) for i in range(len(scene.objects)))
        if self.plan is True:
            self._planned_composite(image, owner, visible)
        else:
            for i, ob in enumerate(scene.objects):
                colours = self.shade_object(i, self.renderer(i), ob.material, scene.object_lights(i))
                mine = owner == i
                image[mine] = colours[mine]
        info = {
            "width": cam.width,
            "height": cam.height,
            "objects": len(scene.objects),
            "lights": scene.light_count,
            "visible_pixels": visible,
            "covered_pixels": int(sum(visible)),
            "rasterized": self.rasterizations - before,
            "seconds": time.perf_counter() - t0,
        }
        return image, info

    def encode(self, image, *, exposure=None, tonemap=None):
        """8-bit sRGB of a rendered image with the scene's (or the given) exposure and tone map."""
        opts = self._scene.image
        return encode_srgb8(
            image,
            exposure=opts.exposure if exposure is None else exposure,
            tonemap=opts.tonemap if tonemap is None else tonemap,
        )


def _object_name(ob) -> str:
    return ob.spec.get("type", type(ob.geometry).__name__)


class _GroupSamples:
    """Several renderers' samples seen as one (the interface :meth:`lighting.render.plan.Plan.shade_samples` uses)."""

    def __init__(self, renderers):
        self.renderers = renderers
        self.camera = renderers[0].camera
        self.dtype = renderers[0].dtype

    def sample_points(self, mode):
        return np.asfortranarray(np.concatenate([r.sample_points(mode) for r in self.renderers]))

    def sample_normals(self, mode):
        return np.asfortranarray(np.concatenate([r.sample_normals(mode) for r in self.renderers]))

    def sample_view(self, mode):
        views = [r.sample_view(mode) for r in self.renderers]
        if views[0][0].ndim == 1:  # a distant viewer: one direction for all
            return views[0]
        v = np.asfortranarray(np.concatenate([w[0] for w in views]))
        return v, np.concatenate([w[1] for w in views])

    def lengths(self, mode):
        return [len(r.sample_normals(mode)) for r in self.renderers]


def render_scene(scene: Scene):
    """Render a scene once: ``(linear image (H, W, 3), info)`` (see :meth:`SceneRenderer.render`)."""
    return SceneRenderer(scene).render()


# =============================================================================== budget and outputs
def scene_estimate(scene: Scene) -> dict:
    """Estimated peak memory and work of rendering ``scene``, before anything is allocated.

    Returns a dict: ``bytes`` (memory), ``evaluations`` (light samples times shading points),
    ``parts`` (``[(key, bytes, what)]``, the memory by cause) and ``work_key`` (the key that
    drives the work: the area light with the most samples, else ``"lights"``).  The constants
    (``BYTES_PER_PIXEL`` and the others in this module) were measured on the example scenes.
    """
    cam = scene.camera
    pixels = cam.width * cam.height
    n = len(scene.objects)
    parts = [("image.width × image.height", pixels * (BYTES_PER_PIXEL + BYTES_PER_PIXEL_PER_OBJECT * n),
              f"{cam.width}x{cam.height} pixels, {n} object(s)")]  # fmt: skip
    phong_samples, evaluations = 0, 0
    best = (0, "lights")
    for i, ob in enumerate(scene.objects):
        geo = ob.geometry
        if isinstance(geo, TriangleMesh):
            parts.append((f"objects[{i}]", geo.n_triangles * BYTES_PER_TRIANGLE, f"{geo.n_triangles} triangles"))
        own = ob.lights is not None
        samples = 0
        for j, lt in enumerate(scene.object_lights(i)):
            k = int(lt.samples) if isinstance(lt, AreaLight) else 1
            samples += k
            if k > best[0]:
                best = (k, f"objects[{i}].lights[{j}].samples" if own else f"lights[{j}].samples")
        mode = scene.object_mode(i)
        if mode == "phong" or not isinstance(geo, TriangleMesh):
            phong_samples = max(phong_samples, samples)  # each pixel is shaded for the one object it shows
        else:
            evaluations += samples * (geo.n_vertices if mode == "gouraud" else geo.n_triangles)
    evaluations += pixels * phong_samples
    if best[0] <= 1:
        best = (best[0], "lights")
    return {"bytes": sum(p[1] for p in parts), "evaluations": evaluations, "parts": parts, "work_key": best[1]}


def check_scene_budget(scene: Scene, *, size_flag: str | None = None) -> dict:
    """Refuse a scene whose estimated memory or work (:func:`scene_estimate`) is over the budget.

    The error (:class:`SceneBudgetError`) names the file and the key that weighs most: the image
    size, an object's mesh or a light's ``samples``.  ``size_flag`` (e.g. ``"--size 640x480"``) is
    named instead of the file's image size when the size came from the command line.  Returns the
    estimate.  :class:`SceneRenderer` calls this before it allocates anything.
    """
    est = scene_estimate(scene)
    key, _, _ = max(est["parts"], key=lambda p: p[1])
    whats = "; ".join(w for _, b, w in est["parts"] if b)
    try:
        check_budget("the scene", _clamp(est["bytes"]), what=whats)
    except BudgetError as e:
        if size_flag and key.startswith("image."):
            raise SceneBudgetError(size_flag, "", str(e)) from None
        raise SceneBudgetError(scene.source, key, str(e)) from None
    evaluations = est["evaluations"]
    try:
        check_budget("the lighting", _clamp(evaluations * BYTES_PER_SAMPLE_EVALUATION),
                     what=f"{evaluations:.3g} light-sample evaluations, counted as {BYTES_PER_SAMPLE_EVALUATION} "
                     "bytes each")  # fmt: skip
    except BudgetError as e:
        raise SceneBudgetError(scene.source, est["work_key"], str(e)) from None
    return est


def _within(path: str, folder: str) -> bool:
    return path == folder or path.startswith(folder.rstrip(os.sep) + os.sep)


def scene_output_path(output, scene_file, *, key: str = "image.output", cwd=None) -> str:
    """Where a scene-named output may be written: the resolved path, or :class:`SceneError`.

    A scene file is untrusted input (conventions.md): an output path it names stays inside the scene
    file's folder or the current folder.  Relative paths start from the current folder; the path is
    resolved with :func:`os.path.realpath` (symbolic links followed, ``..`` applied), and refused when
    it lands anywhere else, when it is itself a symbolic link (writing would replace the link or its
    target), or when it is a directory.  The command line's ``-o`` is not checked: the user chose it.

    Returns the resolved path, which is what the caller writes (the place that was checked).
    """
    scene_file = os.fspath(scene_file)
    cwd = os.getcwd() if cwd is None else os.fspath(cwd)
    folders = [os.path.realpath(os.path.dirname(os.path.abspath(scene_file))), os.path.realpath(cwd)]
    allowed = f"a path inside the scene's folder {folders[0]} or the current folder {folders[1]} " \
              "(give -o on the command line to write elsewhere)"  # fmt: skip
    if not isinstance(output, str) or not output.strip() or "\0" in output:
        raise SceneError(scene_file, key, f"must be {allowed}; got {_describe(output)}")
    given = os.path.join(cwd, output)
    if os.path.islink(given):
        raise SceneError(scene_file, key, f"{_fmt_value(output)} is a symbolic link; a scene may not write "
                                          f"through one: it must be {allowed}")  # fmt: skip
    real = os.path.realpath(given)
    if not any(_within(real, f) for f in folders):
        raise SceneError(scene_file, key, f"{_fmt_value(output)} resolves to {abbreviate(real)}; it must be {allowed}")
    if os.path.isdir(real):
        raise SceneError(scene_file, key, f"{_fmt_value(output)} is a directory; it must be a file name, {allowed}")
    if not os.path.isdir(os.path.dirname(real)):
        raise SceneError(scene_file, key, f"{_fmt_value(output)}: folder {abbreviate(os.path.dirname(real))} does "
                                          f"not exist; the output must be {allowed}")  # fmt: skip
    return real


# =============================================================================== writing back
def _floats(a) -> list:
    return [float(x) for x in np.asarray(a, dtype=np.float64).reshape(-1)]


def _model_to_dict(m: BRDF) -> dict:
    return m.to_dict()


def _material_to_dict(m) -> dict:
    if isinstance(m, gl.Material):
        return {
            "model": "opengl",
            "ambient": list(m.ambient),
            "diffuse": list(m.diffuse),
            "specular": list(m.specular),
            "emission": list(m.emission),
            "shininess": m.shininess,
        }
    return {
        "parts": [_model_to_dict(p) for p in m.brdf.parts],
        "ambient": _floats(m.ambient),
        "emission": _floats(m.emission),
    }


def _light_to_dict(lt) -> dict:
    if isinstance(lt, GLLight):
        L = lt.light
        d = {"type": "opengl"}
        for k in gl.Light.__dataclass_fields__:
            v = getattr(L, k)
            d[k] = list(v) if isinstance(v, tuple) else v
        d["space"] = lt.space
        return d
    kind = next((k for k, c in _LIGHT_CLASSES.items() if type(lt) is c), None)
    if kind is None:
        raise ValueError(f"no scene-file form for the light {type(lt).__name__}")
    d = {"type": kind}
    written = getattr(lt, "_scene_values", None)
    if written is not None:
        return {**d, **{k: (list(v) if isinstance(v, (list, tuple)) else v) for k, v in written.items()}}
    for k in LIGHT_KEYS[kind]:
        if k == "type":
            continue
        v = getattr(lt, k)
        if v is None:
            continue
        d[k] = _floats(v) if isinstance(v, (np.ndarray, tuple, list)) else v
    return d


def _scene_to_dict(scene: Scene) -> dict:
    cam = scene.camera
    c = {
        "eye": _floats(cam.eye),
        "target": _floats(cam.target),
        "up": _floats(cam.up),
        "projection": cam.projection,
        "fov_y_deg": cam.fov_y_deg,
        "ortho_height": cam.ortho_height,
    }
    if cam.near != cam.distance / 1000:
        c["near"] = cam.near
    if cam.far != cam.distance * 1000:
        c["far"] = cam.far
    im = scene.image
    image = {
        "width": cam.width,
        "height": cam.height,
        "background": list(im.background),
        "exposure": im.exposure,
        "tonemap": im.tonemap,
    }
    if im.output is not None:
        image["output"] = im.output
    r = scene.render
    out = {
        "version": FORMAT_VERSION,
        "description": scene.description,
        "camera": c,
        "image": image,
        "render": {"mode": r.mode, "form": r.form, "terms": list(r.terms), "cull_backfaces": r.cull_backfaces},
        "opengl": {"scene_ambient": list(scene.opengl.scene_ambient), "local_viewer": scene.opengl.local_viewer},
        "materials": {name: _material_to_dict(m) for name, m in scene.materials.items()},
        "objects": [],
        "lights": [_light_to_dict(lt) for lt in scene.lights],
    }
    for ob in scene.objects:
        d = {k: (list(v) if isinstance(v, (list, tuple)) else v) for k, v in ob.spec.items()}
        d["material"] = ob.material_name if ob.material_name is not None else _material_to_dict(ob.material)
        if ob.mode is not None:
            d["mode"] = ob.mode
        if ob.cull_backfaces is not None:
            d["cull_backfaces"] = ob.cull_backfaces
        if ob.lights is not None:
            d["lights"] = [_light_to_dict(lt) for lt in ob.lights]
        out["objects"].append(d)
    return out


def _toml_key(k: str) -> str:
    return k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else json.dumps(k)


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, numbers.Integral):
        return str(int(v))
    if isinstance(v, numbers.Real):
        r = repr(float(v))
        return r if any(ch in r for ch in ".en") else r + ".0"
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_toml_key(k)} = {_toml_value(x)}" for k, x in v.items()) + "}"
    raise ValueError(f"cannot write {type(v).__name__} to TOML")


def scene_to_toml(scene) -> str:
    """TOML text of a :class:`Scene` (or of a dict from :meth:`Scene.to_dict`) that :func:`parse_scene` reads back.

    Examples
    --------
    >>> s = parse_scene('[camera]\\neye = [0, 0, 5]\\n[[objects]]\\ntype = "sphere"\\n')
    >>> parse_scene(scene_to_toml(s)).to_dict() == s.to_dict()
    True
    """
    d = scene.to_dict() if isinstance(scene, Scene) else scene
    lines = []
    for k, v in d.items():
        if not isinstance(v, (dict, list)) or (isinstance(v, list) and not all(isinstance(x, dict) for x in v)):
            lines.append(f"{_toml_key(k)} = {_toml_value(v)}")
    for k in ("camera", "image", "render", "opengl"):
        if k in d:
            lines += ["", f"[{k}]"] + [f"{_toml_key(a)} = {_toml_value(b)}" for a, b in d[k].items()]
    for name, m in d.get("materials", {}).items():
        lines += ["", f"[materials.{_toml_key(name)}]"] + [f"{_toml_key(a)} = {_toml_value(b)}" for a, b in m.items()]
    for k in ("objects", "lights"):
        for entry in d.get(k, []):
            lines += ["", f"[[{k}]]"] + [f"{_toml_key(a)} = {_toml_value(b)}" for a, b in entry.items()]
    return "\n".join(lines).lstrip("\n") + "\n"


# =============================================================================== examples
def list_examples() -> list[str]:
    """Names of the example scenes shipped with the package (``lighting/scene/examples/*.toml``)."""
    return sorted(f[:-5] for f in os.listdir(EXAMPLES_DIR) if f.endswith(".toml"))


def example_path(name: str) -> str:
    """Path of a shipped example scene, by name (``"spotlight"`` or ``"spotlight.toml"``)."""
    stem = name[:-5] if name.endswith(".toml") else name
    if stem not in list_examples():
        raise ValueError(
            f"no example scene named {name!r}; {_suggest(stem, list_examples())}available: {', '.join(list_examples())}"
        )
    return os.path.join(EXAMPLES_DIR, stem + ".toml")

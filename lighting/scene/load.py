"""Reading scene files: TOML text (or its dict) to a :class:`~lighting.scene.model.Scene` of engine objects.

Nothing in a file is executed: model, light and object names go through the tables of
:mod:`lighting.scene.schema`.  Every problem is a :class:`~lighting.scene.errors.SceneError` naming
the file, the key path and what is allowed.
"""

from __future__ import annotations

import json
import math
import os
import stat
import tomllib
from dataclasses import replace

import numpy as np

from .. import vec
from .._budget import BudgetError
from .._text import abbreviate
from .._validate import check_color
from ..files import file_model, reader_extensions
from ..models import model_class
from ..render.camera import Camera
from ..render.mesh import icosphere, load_mesh, uv_sphere
from ..render.renderer import AnalyticSphere
from ..shading import opengl as gl
from ..shading.equation import Material
from .budget import BRDF_FILE_BYTES, BYTES_PER_MESH_FILE_BYTE, BYTES_PER_TRIANGLE, _charge_file
from .checks import (
    MAX_NESTING,
    REQUIRED,
    Field,
    _check_dict_nesting,
    _check_text_nesting,
    _choice,
    _Ctx,
    _is_number,
    _table,
)
from .envlights import check_one_environment, environment_light
from .errors import SceneBudgetError, SceneError, _describe, _fmt_value, _join, _norm_name, _suggest
from .examples import scene_label
from .model import GLLight, ImageOptions, OpenGLOptions, RenderOptions, Scene, SceneObject, _gl_lit
from .schema import (
    _LIGHT_CLASSES,
    CAMERA_KEYS,
    GL_MATERIAL_KEYS,
    IMAGE_KEYS,
    LIGHT_KEYS,
    MATERIAL_KEYS,
    OBJECT_KEYS,
    OPENGL_KEYS,
    RENDER_KEYS,
    TOP_KEYS,
    model_keys,
    parameter_field,
)

__all__ = ["load_scene", "parse_scene", "object_matrix"]


def load_scene(path, *, source: str | None = None, allow_slow: bool = False) -> Scene:
    """Read a scene file (TOML).  Relative mesh paths are relative to the file's folder.

    Parameters
    ----------
    path : path
        The scene file; it must be a regular file.
    source : str, optional
        The name error messages give the file (default: a shipped example's name, else the path as
        given; :func:`~lighting.scene.examples.scene_label`).
    allow_slow : bool
        Let renders of the scene take longer than the time budget (:data:`lighting._budget.TIME_LIMIT`);
        otherwise a render estimated to take longer is refused before anything is drawn.

    Returns
    -------
    Scene
        The scene, every value checked and every engine object built.

    Raises
    ------
    SceneError
        For anything wrong with the file: unreadable, invalid TOML (with its line
        and column), unknown keys, wrong types, values out of range, missing or
        unreadable meshes.
    """
    path = os.fspath(path)
    label = scene_label(path) if source is None else str(source)
    try:
        # O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer (no effect on regular files)
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
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
    return parse_scene(raw, source=label, base_dir=os.path.dirname(os.path.abspath(path)), allow_slow=allow_slow)


def parse_scene(data, source: str = "<string>", *, base_dir=None, allow_slow: bool = False) -> Scene:
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
    allow_slow : bool
        As for :func:`load_scene`.

    Returns
    -------
    Scene
        The scene, every value checked and every engine object built.

    Raises
    ------
    SceneError
        For anything wrong with the scene (see :func:`load_scene`).
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
    if allow_slow is not True and allow_slow is not False:
        raise ValueError(f"allow_slow must be True or False; got {abbreviate(repr(allow_slow))}")
    scene = _parse(ctx, data)
    return replace(scene, allow_slow=True) if allow_slow else scene


def _parse(ctx: _Ctx, data: dict) -> Scene:
    top = _table(ctx, "", data, TOP_KEYS, "a scene file")

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

    objects = tuple(
        _object(ctx, _join("objects", i), t, materials, lights, render) for i, t in enumerate(top["objects"])
    )
    _check_near_plane_reach(ctx, cam, camera, top["objects"], objects)
    if render.form == "physical":
        for i, ob in enumerate(objects):
            if _gl_lit(ob.lights if ob.lights is not None else lights):
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


#: How far, in multiples of ``camera.near``, a triangle that crosses the near plane may reach from the eye.  Clipping
#: it against the plane in float64 loses every digit near 1/eps (measured on the cube example scaled around the
#: camera: NaN pixels from 6e15 to 1.2e16 times near, for near 1, 0.006 and 0.001); this keeps three orders of
#: magnitude from that.
MAX_NEAR_PLANE_REACH = 1e12


def _check_near_plane_reach(ctx, cam, camera, tables, objects):
    """Refuse, naming the key that made it, a mesh whose triangles across the near plane reach too far from the eye.

    A cube scaled by ``1e14`` around the camera, or a room with ``camera.near = 1e-15``: the rasterizer's
    clipping would turn them into NaN pixels; the loader names ``objects[i].scale`` (or what else set the size).
    """
    if camera.projection != "perspective":
        return
    near = float(camera.near)
    forward = vec.normalize(np.asarray(camera.target, dtype=np.float64) - camera.eye)
    for i, ob in enumerate(objects):
        mesh = ob.geometry
        if not hasattr(mesh, "faces") or not mesh.n_triangles:
            continue
        with np.errstate(over="ignore", invalid="ignore"):
            rel = np.asarray(mesh.vertices, dtype=np.float64) - camera.eye
            depth = np.nan_to_num(rel @ forward, nan=np.inf)[mesh.faces]
            crossing = (depth.min(axis=1) < near) & (depth.max(axis=1) > near)
            if not crossing.any():
                continue
            reach = float(np.abs(rel[mesh.faces[crossing]]).max())
        if reach <= MAX_NEAR_PLANE_REACH * near:
            continue
        table = tables[i]
        path = _join("objects", i)
        scale = table.get("scale", 1.0)
        if np.any(np.asarray(scale, dtype=np.float64) != 1.0):
            key, given = _join(path, "scale"), f"; got {_fmt_value(scale)}"
        elif "near" in cam:
            key, given = "camera.near", f"; got {_fmt_value(cam['near'])}"
        else:
            key = _join(path, "path" if table.get("type") == "mesh" else "radius")
            given = ""
        limit = MAX_NEAR_PLANE_REACH * near
        ctx.fail(key, f"makes triangles that cross the near plane reach {reach:.3g} from the eye; allowed: at most "
                      f"{MAX_NEAR_PLANE_REACH:g} x camera.near = {limit:.3g} (beyond it, clipping in float64 loses "
                      f"every digit): make the object smaller or camera.near larger{given}")  # fmt: skip


def _check_view_distance(ctx, cam):
    """``target − eye`` and its length must be finite: each key may be finite while their distance is not.

    The camera would then see a zero view direction and blame ``up``; the key at fault is the far point.
    """
    eye, target = np.asarray(cam["eye"]), np.asarray(cam["target"])
    with np.errstate(over="ignore", invalid="ignore"):
        d = target - eye
        length = float(vec.length(d)) if np.all(np.isfinite(d)) else math.inf  # the scaled, overflow-free length
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
    models = model_keys()  # the registered models, as they are now
    if "model" in table:
        if "parts" in table:
            ctx.fail(path, "a material has either parts = [...] (engine models) or model = 'opengl', not both")
        if not isinstance(table["model"], str) or _norm_name(table["model"]) != "opengl":
            ctx.fail(
                _join(path, "model"),
                f"a material's own model can only be 'opengl'; got {_describe(table['model'])}. "
                f"Engine models ({', '.join(map(repr, models))}) go in parts = [{{model = ..., ...}}]",
            )
        m = _table(ctx, path, table, GL_MATERIAL_KEYS, "an OpenGL material")
        m.pop("model")
        return ctx.build(path, gl.Material, m)
    if "parts" not in table:
        hint = _suggest(next(iter(table), ""), ["parts", "model"]) if table else ""
        ctx.fail(
            _join(path, "parts"),
            f"is required: a material is parts = [{{model = 'lambert', kd = 0.8}}, ...] "
            f"(models {', '.join(map(repr, models))}) or model = 'opengl' {hint}".rstrip(),
        )
    m = _table(ctx, path, table, MATERIAL_KEYS, "a material")
    brdf = None
    for i, part in enumerate(m["parts"]):
        ppath = _join(_join(path, "parts"), i)
        if "file" in part:
            model = _file_part(ctx, ppath, part)
        else:
            if "model" not in part:
                ctx.fail(_join(ppath, "model"), f"is required: one of {', '.join(map(repr, models))} "
                                                "(or file = 'NAME.brdf' / 'NAME.binary')")  # fmt: skip
            name = _choice(tuple(models))(ctx, _join(ppath, "model"), part["model"])
            params = _table(ctx, ppath, part, models[name], f"a {name!r} model")
            params.pop("model")
            model = ctx.build(ppath, model_class(name), params)
        brdf = model if brdf is None else brdf + model
    kwargs = {"brdf": brdf, "emission": m["emission"]}
    if "ambient" in m:
        kwargs["ambient"] = m["ambient"]
    return ctx.build(path, Material, kwargs)


def _file_part(ctx, path, part):
    """A part ``{file = "paint.brdf", name = value, ...}``: the model a BRDF file describes, its parameters by name.

    The path is relative to the scene file's folder; the file is read once per scene (parts naming it share
    the table) after its memory is charged (:data:`~lighting.scene.budget.BRDF_FILE_BYTES`).
    """
    if "model" in part:
        ctx.fail(path, "a part has either model = NAME (a registered model) or file = PATH (a BRDF file), not both")
    spec = part["file"]
    if not isinstance(spec, str) or not spec.strip() or "\0" in spec:
        ctx.fail(_join(path, "file"), f"must be the path of a BRDF file ({', '.join(reader_extensions())}), relative "
                                      f"to the scene's folder; got {_describe(spec)}")  # fmt: skip
    p = os.path.normpath(os.path.join(ctx.base_dir, os.path.expanduser(spec)))
    ext = os.path.splitext(p)[1].lower()
    if ext not in BRDF_FILE_BYTES:
        ctx.fail(_join(path, "file"), f"{_fmt_value(spec)} is not a BRDF file; allowed extensions: "
                                      f"{', '.join(reader_extensions())}")  # fmt: skip
    if p not in ctx.brdf_files:
        if not os.path.isfile(p):
            what = "does not exist" if not os.path.exists(p) else "is not a regular file"
            ctx.fail(_join(path, "file"), f"{_fmt_value(spec)}{ctx.resolved(spec, p)} {what}; a BRDF file must be an "
                                          "existing file, relative to the scene's folder")  # fmt: skip
        per_byte, fixed = BRDF_FILE_BYTES[ext]
        size = os.stat(p).st_size
        ctx.charge(_join(path, "file"), fixed + per_byte * size, f"reading a BRDF file of {size} bytes")
        try:
            ctx.brdf_files[p] = file_model(p)
        except ValueError as e:
            ctx.fail(_join(path, "file"), str(e))
    cls = ctx.brdf_files[p]
    keys = {"file": Field("string", REQUIRED), **{q.name: parameter_field(q) for q in cls.parameters}}
    params = _table(ctx, path, part, keys, f"the BRDF file {os.path.basename(p)!r}")
    params.pop("file")
    for q in cls.parameters:  # the table's own check names the key (a file's messages start with its name)
        try:
            q.check(params[q.name])
        except ValueError as e:
            ctx.fail(_join(path, q.name), str(e))
    return ctx.build(path, cls, params)


def _light(ctx, path, table):
    if not isinstance(table, dict):
        ctx.fail(path, f"must be a light table; got {_describe(table)}")
    if "type" not in table:
        ctx.fail(_join(path, "type"), f"is required: one of {', '.join(map(repr, LIGHT_KEYS))}")
    kind = _choice(tuple(LIGHT_KEYS))(ctx, _join(path, "type"), table["type"])
    params = _table(ctx, path, table, LIGHT_KEYS[kind], f"{'an' if kind[0] in 'aeiou' else 'a'} {kind!r} light")
    params.pop("type")
    if kind == "opengl":
        space = params.pop("space")
        return GLLight(ctx.build(path, gl.Light, params), space)
    if kind == "environment":
        return environment_light(ctx, path, params)
    light = ctx.build(path, _LIGHT_CLASSES[kind], params)
    # The values as written, for writing back: the light keeps only the normalized direction, and
    # normalizing a unit vector again can move its last bit.  The light is frozen, so they stay true.
    try:
        object.__setattr__(light, "_scene_values", params)
    except AttributeError:  # a light class with __slots__: write back its (normalized) fields instead
        pass
    return light


def _check_light_mix(ctx, path, lights):
    check_one_environment(ctx, path, lights)
    gl_idx = [i for i, lt in enumerate(lights) if isinstance(lt, GLLight)]
    if gl_idx and len(gl_idx) != len(lights):
        other = next(i for i, lt in enumerate(lights) if not isinstance(lt, GLLight))
        if getattr(lights[other], "is_environment", False):
            ctx.fail(
                _join(_join(path, other), "type"),
                f"the OpenGL fixed-function equation has no environment light ({path}[{gl_idx[0]}] has type "
                "'opengl'): light with engine lights only to use an environment",
            )
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

    Parameters
    ----------
    translate : array_like, shape (3,)
        ``T``'s offset.
    rotate_deg : array_like, shape (3,)
        Angles in degrees about world x, then y, then z (right-hand rule).
    scale : float or array_like, shape (3,)
        ``S``: uniform, or per axis.

    Returns
    -------
    numpy.ndarray, shape (4, 4)
        ``M`` (float64).

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
    gl_lit = _gl_lit(effective)

    material_name = None
    mpath = _join(path, "material")
    if "material" not in spec:
        material = gl.Material() if gl_lit else Material(model_class("lambert")(0.8))
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

"""Writing scenes back: a :class:`~lighting.scene.model.Scene` as plain data and as TOML that reads back the same."""

from __future__ import annotations

import numbers
import re

import numpy as np

from ..shading import opengl as gl
from .model import GLLight, Scene
from .schema import _LIGHT_CLASSES, FORMAT_VERSION, LIGHT_KEYS

__all__ = ["scene_to_toml"]


def _floats(a) -> list:
    """An array's entries as a flat list of Python floats."""
    return [float(x) for x in np.asarray(a, dtype=np.float64).reshape(-1)]


def _material_to_dict(m) -> dict:
    """A material as a ``[materials.NAME]`` table: OpenGL's colours, or each model's ``to_dict()``."""
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
        "parts": [p.to_dict() for p in m.brdf.parts],
        "ambient": _floats(m.ambient),
        "emission": _floats(m.emission),
    }


def _light_to_dict(lt) -> dict:
    """A light as a ``[[lights]]`` table, with the values as they were written where the light kept them."""
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
    if kind == "environment" and written is None:  # made in Python: the light writes itself
        return lt.to_dict()
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
    """The body of :meth:`Scene.to_dict <lighting.scene.model.Scene.to_dict>`."""
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


# tomli-w writes an array one entry a line; a scene's arrays are vectors and colours, read best on one line.  Only
# arrays of scalars are joined (an entry holding a bracket or brace stays as written); tomli-w writes no raw line
# break inside a string, so a match never starts or ends inside one.
_ARRAY = re.compile(r"\[\n((?:[ ]+[^\n\[\]{}]+,\n)+)[ ]*\]")


def _plain(v):
    """``v`` in the types tomli-w writes: NumPy numbers as Python's (a dict passed in may hold them)."""
    if isinstance(v, dict):
        return {k: _plain(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_plain(x) for x in v]
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, numbers.Integral):
        return int(v)
    return float(v) if isinstance(v, numbers.Real) else v


def scene_to_toml(scene) -> str:
    """TOML text of a scene that :func:`~lighting.scene.load.parse_scene` reads back.

    Written by tomli-w (floats as their shortest repr, so every value reads back bit for bit), with
    arrays of numbers and names on one line.

    Parameters
    ----------
    scene : Scene or dict
        A scene, or a dict from :meth:`Scene.to_dict <lighting.scene.model.Scene.to_dict>`.

    Returns
    -------
    str
        The TOML text, ending with a newline.

    Examples
    --------
    >>> from lighting.scene import parse_scene
    >>> s = parse_scene('[camera]\\neye = [0, 0, 5]\\n[[objects]]\\ntype = "sphere"\\n')
    >>> parse_scene(scene_to_toml(s)).to_dict() == s.to_dict()
    True
    >>> print(scene_to_toml(s).split("[camera]")[1].split("\\n\\n")[0].strip())
    eye = [0.0, 0.0, 5.0]
    target = [0.0, 0.0, 0.0]
    up = [0.0, 1.0, 0.0]
    projection = "perspective"
    fov_y_deg = 30.0
    ortho_height = 2.5
    """
    import tomli_w  # only saving a scene needs it

    d = scene.to_dict() if isinstance(scene, Scene) else scene
    text = tomli_w.dumps(_plain(d))
    return _ARRAY.sub(lambda m: "[" + ", ".join(x.strip()[:-1] for x in m.group(1).splitlines()) + "]", text)

"""A scene file as the explorer's starting state: the first object's material and the scene's lights.

The material's parts map back onto the controls through the model protocol (``part.flags``,
``part.name``, ``part.variants``, ``part.to_dict()``), never by asking which class a part is.
"""

from __future__ import annotations

import math
import os

import numpy as np

from lighting import AmbientLight, DirectionalLight, Material
from lighting.lights import PointLight, SpotLight, attenuation_polynomial
from lighting.models import BRDFFlags

from .params import diffuse_parameter, offered_parameters
from .state import ATTENUATIONS, MODELS, TERM_NAMES, AppState

__all__ = ["state_from_scene"]


def state_from_scene(path) -> AppState:
    """An :class:`AppState` from a scene file: the first object's material and the scene's lights.

    The material's Lambert part gives ``kd``/``color``, its specular part the
    model and parameters (an OpenGL material is read as Lambert + Blinn-Phong).
    Ambient lights add up to ``ambient``; the first directional, point or spot light
    (or OpenGL light with a diffuse colour) becomes the key light, its direction seen
    from the scene's camera (so it lights the explorer's sphere from the same side of
    the picture) and, for point and spot lights, at the same distance from the
    object's centre, with the irradiance it delivers there.  Every other light but an
    environment (rect and disk lights, further point, spot, directional and OpenGL
    lights) becomes an extra light (``scene_lights``, :mod:`explorer.app.lights`) in
    the explorer's view frame: moved by minus the object's centre, scaled by one over
    its radius (the object becomes the unit sphere; a mesh's radius is its farthest
    vertex from the mean of its vertices), turned into the camera's frame (right, up,
    toward the viewer), with the falloff and sizes scaled so that it delivers the same
    light to the surface.  Render options (mode, form, terms, exposure) are taken too.

    Parameters
    ----------
    path : str or os.PathLike
        A scene file (TOML).

    Returns
    -------
    AppState
        The state; controls the scene does not set keep their defaults.

    Raises
    ------
    ValueError
        For a malformed scene, or a material part no registered model describes.
    """
    try:
        from lighting.scene import GLLight, gl_material_to_engine, load_scene
    except ImportError:  # pragma: no cover - the module ships with the engine
        raise ValueError("scene files need lighting.scene") from None
    from lighting import gl

    scene = load_scene(path)
    state = AppState()
    obj = scene.objects[0]
    material = obj.material
    if isinstance(material, gl.Material):
        material = gl_material_to_engine(material)
    _apply_material(state, material, str(path))
    centre = np.asarray(getattr(obj.geometry, "center", (0.0, 0.0, 0.0)), dtype=np.float64)
    radius = float(getattr(obj.geometry, "radius", 1.0))
    if hasattr(obj.geometry, "vertices"):
        vertices = np.asarray(obj.geometry.vertices, dtype=np.float64)
        centre = vertices.mean(axis=0)
        radius = float(np.max(np.linalg.norm(vertices - centre, axis=-1)))
    lights = scene.object_lights(0)
    _apply_lights(state, lights, scene.camera, centre, GLLight, radius if radius > 0 else 1.0)
    _apply_environment(state, lights)
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


def _environment_light(lights):
    return next((lt for lt in lights if getattr(lt, "is_environment", False)), None)


def _apply_environment(state: AppState, lights):
    """A scene's environment light as the environment controls (a file: :func:`scene_environment_file`)."""
    light = _environment_light(lights)
    if light is None:
        return
    from lighting.lights import SKIES

    intensity = float(np.mean(light.intensity))
    src = light.source
    if isinstance(src, str) and src.strip().lower() in SKIES:
        env = src.strip().lower()
    elif isinstance(src, str) or hasattr(src, "__fspath__"):
        env = "file"
    else:  # a constant radiance: the uniform sky, scaled
        env, intensity = "uniform", intensity * float(np.mean(src))
    state.update(environment=env, env_rotation=float(np.clip((light.rotation + 180.0) % 360.0 - 180.0, -180, 180)),
                 env_intensity=float(np.clip(intensity, 0.0, 10.0)))  # fmt: skip


def scene_environment_file(path):
    """The environment file a scene's first object is lit by, as ``(path, environment)``, or None.

    Parameters
    ----------
    path : path-like
        The scene file.

    Returns
    -------
    tuple or None
        The file's path (from the scene's folder) and the environment the scene read from it (without the
        light's intensity and rotation, which become the controls): ``--environment FILE`` without reading
        the file again.
    """
    from lighting.lights import SKIES
    from lighting.scene import load_scene

    light = _environment_light(load_scene(path).object_lights(0))
    if light is None or not isinstance(light.source, str) or light.source.strip().lower() in SKIES:
        return None
    env = light.environment
    return os.path.join(os.path.dirname(os.path.abspath(path)), light.source), getattr(env, "base", env)


def _apply_material(state: AppState, material: Material, source: str):
    """Set the model, its parameters and ``kd``/``color`` from a material's parts, through the model protocol.

    The Lambertian parts (``BRDFFlags.LAMBERTIAN``) add up to ``kd × color``; the first other part gives
    the model (its registered ``name``, or the variant of ``part.variants`` whose fixed arguments its
    :meth:`~lighting.models.brdf.BRDF.to_dict` matches) and every parameter the explorer offers for it
    (:func:`~explorer.app.params.offered_parameters`); a model with its own diffuse colour gives
    ``kd``/``color`` from that colour.  Colours keep their RGB values.
    """
    parts = material.brdf.parts
    kd = sum((p.diffuse_albedo for p in parts if BRDFFlags.LAMBERTIAN in p.flags), np.zeros(3))
    spec = next((p for p in parts if BRDFFlags.LAMBERTIAN not in p.flags), None)
    values, params = {}, {}
    if spec is None:
        values["model"] = "lambert"
        spec_table = {}
    else:
        try:
            spec_table = spec.to_dict()
        except ValueError:
            spec_table = {}
        if spec_table.get("model") not in MODELS:
            raise ValueError(f"{source}: the explorer cannot show the model {type(spec).__name__}")
        values["model"] = spec_table["model"]
        for variant, fixed in spec.variants.items():
            if all(spec_table.get(k) == v for k, v in fixed.items()):
                values["model"] = variant
        for p in offered_parameters(values["model"]):
            value = spec_table.get(p.name)
            if value is None and p.default is not None:
                continue
            if isinstance(value, list):  # a colour: grey as one number, as the slider shows it
                value = float(value[0]) if all(x == value[0] for x in value) else tuple(value)
            params[p.name] = value
    colour = diffuse_parameter(type(spec)) if spec is not None else "kd"
    if colour is not None and colour in spec_table:
        kd = np.broadcast_to(np.asarray(spec_table[colour], dtype=np.float64), (3,))
    top = float(kd.max())
    values["kd"] = min(top, 1.0)
    if top > 0:
        values["color"] = tuple(np.minimum(kd / top, 1.0))
    state.update(params=params, **values)


def _apply_lights(state: AppState, lights, camera, centre, gl_light_type, radius=1.0):
    # View frame of the scene's camera: right, up, toward the viewer.
    frame = np.stack([camera.right, camera.true_up, -camera.forward])
    ambient, key, extra = 0.0, None, []
    for lt in lights:
        if isinstance(lt, gl_light_type):
            g = lt.light
            pos = np.asarray(g.position, dtype=np.float64)
            colour = np.asarray(g.diffuse[:3], dtype=np.float64)
            if key is None and np.any(colour > 0):
                ambient += float(np.mean(g.ambient[:3]))
                key = ("directional", pos[:3], colour, 1.0) if pos[3] == 0 else ("point", pos[:3] / pos[3], colour, 1.0)
            else:
                extra.append(_gl_view_table(lt, camera, centre, radius))
            continue
        if isinstance(lt, AmbientLight):
            ambient += float(np.mean(lt.radiant))
            continue
        if getattr(lt, "is_environment", False):
            continue  # the environment controls (_apply_environment)
        if key is None and isinstance(lt, (DirectionalLight, PointLight)):
            if isinstance(lt, DirectionalLight):
                key = ("directional", lt.direction, lt.color, lt.intensity)
            else:
                kind = "spot" if isinstance(lt, SpotLight) else "point"
                key = (kind, lt.position, lt.color, lt.intensity, lt)
            continue
        extra.append(_view_table(lt, frame, centre, radius))
    values = {"ambient": min(ambient, 2.0), "scene_lights": tuple(extra)}
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
            falloff = attenuation_polynomial(dist, (a, b, c))
            irradiance = irradiance / falloff if falloff > 0 else irradiance
            values["distance"] = min(max(dist, 1.5), 20.0)
            named = {v: k for k, v in ATTENUATIONS.items()}
            values["attenuation"] = named.get(tuple(float(x) for x in (a, b, c)), "inverse-square")
            if kind == "spot":
                values["cutoff"] = lt.cutoff_deg if lt.cutoff_deg <= 90 else 90.0
                values["spot_exponent"] = min(lt.exponent, 128.0)
        values["intensity"] = min(max(irradiance, 0.0), 10.0)
    state.update(**values)


def _floats(v) -> list:
    return [float(x) for x in np.asarray(v, dtype=np.float64).reshape(-1)]


def _colour(c):
    c = np.asarray(c, dtype=np.float64).reshape(-1)
    return float(c[0]) if np.all(c == c[0]) else _floats(c)


def _view_table(lt, frame, centre, radius) -> dict:
    """An engine light of the scene as a light table of the explorer's view frame (see :func:`state_from_scene`).

    Points move by ``-centre``, scale by ``1 / radius`` and turn by ``frame``; directions only turn.  Light
    reaching the surface is kept: an area light's radiance is unchanged (its solid angles are), a point
    light's falloff ``1 / (a d² + b d + c)`` becomes ``1 / (a r² d'² + b r d' + c)`` for ``d = r d'``.
    """

    def point(p):
        return _floats(frame @ (np.asarray(p, dtype=np.float64) - centre) / radius)

    def turn(d, scale=1.0):
        return _floats(frame @ np.asarray(d, dtype=np.float64) * scale)

    if isinstance(lt, DirectionalLight):
        return {"type": "directional", "direction": turn(lt.direction), "color": _colour(lt.color),
                "intensity": float(lt.intensity)}  # fmt: skip
    if isinstance(lt, PointLight):
        a, b, c = lt.attenuation
        table = {"type": "point", "position": point(lt.position), "color": _colour(lt.color),
                 "intensity": float(lt.intensity), "attenuation": [a * radius * radius, b * radius, c]}  # fmt: skip
        if isinstance(lt, SpotLight):
            table.update(type="spot", direction=turn(lt.direction), cutoff_deg=float(lt.cutoff_deg),
                         exponent=float(lt.exponent))  # fmt: skip
        return table
    from lighting.lights import DiskLight, RectLight

    common = {"color": _colour(lt.color), "intensity": float(lt.intensity), "samples": int(lt.samples),
              "two_sided": bool(lt.two_sided), **({"seed": int(lt.seed)} if lt.seed is not None else {})}  # fmt: skip
    if isinstance(lt, RectLight):
        return {"type": "rect", "center": point(lt.center), "edge_u": turn(lt.edge_u, 1.0 / radius),
                "edge_v": turn(lt.edge_v, 1.0 / radius), **common}  # fmt: skip
    if isinstance(lt, DiskLight):
        return {"type": "disk", "center": point(lt.center), "normal_dir": turn(lt.normal_dir),
                "radius": float(lt.radius) / radius, **common}  # fmt: skip
    raise ValueError(f"the explorer cannot show a light of type {type(lt).__name__}")


def _gl_view_table(lt, camera, centre, radius) -> dict:
    """A scene's OpenGL light as a light table of the explorer's view frame.

    Taken to eye space as the scene renderer takes it (the camera's view matrix, or as it is for
    ``space = "eye"``): eye space is the view frame's orientation, so the position moves by minus the
    object's centre there and scales by ``1 / radius``; OpenGL's ``k_0 + k_1 d + k_2 d²`` becomes
    ``k_0 + k_1 r d' + k_2 r² d'²``.
    """
    g = lt.in_eye_space(camera.view_matrix())
    pos = np.asarray(g.position, dtype=np.float64)
    if pos[3] == 0.0:
        position = [*_floats(pos[:3]), 0.0]
    else:
        c_eye = (camera.view_matrix() @ np.append(centre, 1.0))[:3]
        position = [*_floats((pos[:3] / pos[3] - c_eye) / radius), 1.0]
    return {
        "type": "opengl",
        "ambient": _floats(g.ambient),
        "diffuse": _floats(g.diffuse),
        "specular": _floats(g.specular),
        "position": position,
        "spot_direction": _floats(g.spot_direction),
        "spot_exponent": float(g.spot_exponent),
        "spot_cutoff": float(g.spot_cutoff),
        "constant_attenuation": float(g.constant_attenuation),
        "linear_attenuation": float(g.linear_attenuation) * radius,
        "quadratic_attenuation": float(g.quadratic_attenuation) * radius * radius,
    }

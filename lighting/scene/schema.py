"""The scene-file schema: one table per kind of entry, ``key -> (check, default)``.

``docs/scenes.md`` lists the same keys (a test keeps them in step).  The models' keys are not
written here: :func:`model_keys` builds them from the registry (:func:`lighting.models.model_names`)
and each model's ``parameters`` table, so a model registered anywhere is accepted in scene files.
"""

from __future__ import annotations

from ..lights import AmbientLight, DirectionalLight, DiskLight, PointLight, RectLight, SpotLight
from ..lights.envlight import DEFAULT_ENVIRONMENT_METHOD, ENVIRONMENT_METHODS, EnvironmentLight
from ..models import model_class, model_names
from ..render.image import MAX_EXPOSURE
from ..render.renderer import SHADING_MODES
from ..shading.equation import FORMS, TERMS
from .checks import (
    _ABSENT,
    REQUIRED,
    _array_of_tables,
    _boolean,
    _choice,
    _color,
    _integer_check,
    _number,
    _number_in,
    _number_or,
    _numbers,
    _rgba,
    _string,
    _terms_check,
    _vec3,
)

__all__ = ["FORMAT_VERSION", "MAX_SCENE_IMAGE_SIDE", "model_keys"]

#: The format version this module reads and writes (``version = 1`` in a file).
FORMAT_VERSION = 1

#: The largest ``[image]`` width and height, in pixels (``render --size`` is held to the same).
MAX_SCENE_IMAGE_SIDE = 16384

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
    "width": (_integer_check(1, MAX_SCENE_IMAGE_SIDE), 512),
    "height": (_integer_check(1, MAX_SCENE_IMAGE_SIDE), 512),
    "background": (_color, 0.0),
    "exposure": (_number_in(-MAX_EXPOSURE, MAX_EXPOSURE, "stops"), 0.0),
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

#: What a parameter of each kind is in a scene file; a "choice" parameter is checked against its own choices.
_KIND_CHECKS = {"float": _number, "color": _color, "bool": _boolean}


def _parameter_check(parameter):
    """The check of one row of a model's parameter table (:class:`lighting.models.Parameter`)."""
    if parameter.kind == "choice":
        return _choice(tuple(parameter.choices))
    return _KIND_CHECKS[parameter.kind]


def model_keys() -> dict:
    """The keys of each registered model in a scene file, built from the registry when called.

    Each model's table is ``model`` (required) followed by its parameters in the order of its
    ``parameters`` table, each with its check (by kind) and its default.  Built on each call, so a
    model registered after import (by a test, or a plug-in) is accepted.

    Returns
    -------
    dict
        Model name (in registration order) → ``{key: (check, default)}``.

    Examples
    --------
    >>> list(model_keys()["phong"])
    ['model', 'ks', 'shininess']
    """
    return {
        name: {
            "model": (_string, REQUIRED),
            **{p.name: (_parameter_check(p), p.default) for p in model_class(name).parameters},
        }
        for name in model_names()
    }


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
    # One of source (an image file or a sky name) and radiance; neither: radiance 1.  samples and seed
    # belong to method = "monte-carlo" (absent: 64 and 0).  See lighting.scene.envlights.
    "environment": {
        "type": _T,
        "source": (_string, _ABSENT),
        "radiance": (_color, _ABSENT),
        "intensity": (_color, 1.0),
        "rotation": (_number, 0.0),
        "background": (_boolean, True),
        "method": (_choice(ENVIRONMENT_METHODS), DEFAULT_ENVIRONMENT_METHOD),
        "samples": (_integer_check(2, 1 << 16), _ABSENT),
        "seed": (_integer_check(0), _ABSENT),
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
    "environment": EnvironmentLight,  # built by lighting.scene.envlights (a file, a sky or a radiance)
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

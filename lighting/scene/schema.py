"""The scene-file schema: one table per kind of entry, ``key -> Field`` (:class:`lighting.scene.checks.Field`).

Each field says, as data, what its key holds: the loader checks values against it and the JSON Schema for editors
(``docs/scene.schema.json``) is generated from it.  ``docs/scenes.md`` lists the same keys (a test keeps them in
step).  The models' keys are not written here: :func:`model_keys` builds them from the registry
(:func:`lighting.models.model_names`) and each model's ``parameters`` table, so a model registered anywhere is
accepted in scene files.
"""

from __future__ import annotations

from ..lights import AmbientLight, DirectionalLight, DiskLight, PointLight, RectLight, SpotLight
from ..lights.envlight import DEFAULT_ENVIRONMENT_METHOD, ENVIRONMENT_METHODS, EnvironmentLight
from ..models import model_class, model_names
from ..render.image import MAX_EXPOSURE
from ..render.renderer import SHADING_MODES
from ..shading.equation import FORMS, TERMS
from .checks import ABSENT, REQUIRED, Field

__all__ = ["FORMAT_VERSION", "MAX_SCENE_IMAGE_SIDE", "MAX_ENVIRONMENT_VALUE", "MAX_LIGHT_VALUE", "model_keys",
           "parameter_field"]

#: The format version this module reads and writes (``version = 1`` in a file).
FORMAT_VERSION = 1

#: The largest ``[image]`` width and height, in pixels (``render --size`` is held to the same).
MAX_SCENE_IMAGE_SIDE = 16384

#: The largest entry of an environment light's ``radiance`` and ``intensity``.  An environment's radiance is held
#: in float32 (image files, prefiltered levels; largest 3.4e38): a constant sky of 1e38 overflows the prefilter's
#: sums while 1e36 renders with every method.  This keeps a factor of a million below that, and radiance times
#: intensity (at most 1e60) far inside float64 in every method.
MAX_ENVIRONMENT_VALUE = 1e30

#: The largest ``color`` entry and ``intensity`` of every other light: the same bound, so that colour times
#: intensity (at most 1e60), summed over the lights, stays far inside float64 (1e308 made pixels overflow or
#: clip silently), and 100 stops of exposure (2**100, about 1.3e30) still bring such a light to the display.
MAX_LIGHT_VALUE = MAX_ENVIRONMENT_VALUE

_ORIGIN = [0.0, 0.0, 0.0]
_GL_BLACK = [0.0, 0.0, 0.0, 1.0]

CAMERA_KEYS = {
    "eye": Field("vec3", REQUIRED, "where the camera is; not at target"),
    "target": Field("vec3", _ORIGIN, "the point at the image centre"),
    "up": Field("vec3", [0.0, 1.0, 0.0], "the direction that is up in the image; not parallel to target - eye"),
    "projection": Field("choice", "perspective", "the projection", choices=("perspective", "orthographic")),
    "fov_y_deg": Field("number", 30.0, "vertical field of view in degrees, in (0, 180) (perspective)"),
    "ortho_height": Field("number", 2.5, "world height of the image, > 0 (orthographic)"),
    "near": Field("number", ABSENT, "near clipping distance, > 0 (absent: |target - eye| / 1000)"),
    "far": Field("number", ABSENT, "far clipping distance, > near (absent: 1000 |target - eye|)"),
}

IMAGE_KEYS = {
    "width": Field("integer", 512, "image width in pixels", minimum=1, maximum=MAX_SCENE_IMAGE_SIDE),
    "height": Field("integer", 512, "image height in pixels", minimum=1, maximum=MAX_SCENE_IMAGE_SIDE),
    "background": Field("color", 0.0, "linear RGB, >= 0, where no object covers the pixel centre"),
    "exposure": Field("number", 0.0, "the image is multiplied by 2^exposure when encoded",
                      minimum=-MAX_EXPOSURE, maximum=MAX_EXPOSURE, unit="stops"),
    "tonemap": Field("choice", "clamp", "clamp: values above 1 clip; reinhard: x / (1 + x)",
                     choices=("clamp", "reinhard")),
    "output": Field("string", ABSENT, "PNG path for the command line, inside the scene's folder or the current one"),
}

RENDER_KEYS = {
    "mode": Field("choice", "phong", "shading per triangle (flat), per vertex (gouraud) or per pixel (phong)",
                  choices=SHADING_MODES),
    "form": Field("choice", "classic", "the slides' I (classic) or radiance I / pi (physical)", choices=FORMS),
    "terms": Field("terms", list(TERMS), "the terms of the illumination equation that are drawn", choices=TERMS),
    "cull_backfaces": Field("bool", True, "drop triangles facing away from the camera"),
}

OPENGL_KEYS = {
    "scene_ambient": Field("rgba", [0.2, 0.2, 0.2, 1.0], "OpenGL's scene ambient a_cs"),
    "local_viewer": Field("bool", False, "half vector toward the eye (true) or along +z in eye space (false)"),
}

#: The kind of field of each kind of model parameter (:class:`lighting.models.Parameter`).
_PARAMETER_KINDS = {"float": "number", "color": "color", "bool": "bool", "choice": "choice"}


def parameter_field(parameter) -> Field:
    """The field of one row of a model's parameter table (:class:`lighting.models.Parameter`).

    Its kind, choices, default and description come from the row; its range is the model's own check
    (the constructor's, run on every value).

    Parameters
    ----------
    parameter : lighting.models.Parameter

    Returns
    -------
    Field

    Examples
    --------
    >>> from lighting.models import model_class
    >>> parameter_field(model_class("cook-torrance").parameters[-1]).choices[:2]
    ('none', 'gold')
    """
    kind = _PARAMETER_KINDS[parameter.kind]
    return Field(kind, parameter.default, parameter.description, choices=tuple(parameter.choices))


def model_keys() -> dict:
    """The keys of each registered model in a scene file, built from the registry when called.

    Each model's table is ``model`` (required) followed by its parameters in the order of its
    ``parameters`` table, each a :class:`~lighting.scene.checks.Field` (:func:`parameter_field`).  Built on
    each call, so a model registered after import (by a test, or a plug-in) is accepted.

    Returns
    -------
    dict
        Model name (in registration order) → ``{key: Field}``.

    Examples
    --------
    >>> list(model_keys()["phong"])
    ['model', 'ks', 'shininess']
    """
    return {
        name: {
            "model": Field("string", REQUIRED, "the reflectance model"),
            **{p.name: parameter_field(p) for p in model_class(name).parameters},
        }
        for name in model_names()
    }


MATERIAL_KEYS = {
    "parts": Field("tables", REQUIRED, "the reflectance models, summed", what="reflectance models", ref="part",
                   empty="must list at least one reflectance model"),
    "ambient": Field("color", ABSENT, "k_a, >= 0 (absent: the Lambert kd of the parts)"),
    "emission": Field("color", 0.0, "k_e, >= 0 (classic units)"),
}

GL_MATERIAL_KEYS = {
    "model": Field("string", REQUIRED, "an OpenGL fixed-function material"),
    "ambient": Field("rgba", [0.2, 0.2, 0.2, 1.0], "a_cm, >= 0"),
    "diffuse": Field("rgba", [0.8, 0.8, 0.8, 1.0], "d_cm, >= 0 (its alpha is the vertex alpha)"),
    "specular": Field("rgba", _GL_BLACK, "s_cm, >= 0"),
    "emission": Field("rgba", _GL_BLACK, "e_cm"),
    "shininess": Field("number", 0.0, "s_rm, in [0, 128]"),
}

_TYPE = Field("string", REQUIRED, "the kind of entry")
_COLOR = Field("color", 1.0, "linear RGB, >= 0 (times the intensity)", maximum=MAX_LIGHT_VALUE)
_INTENSITY = Field("number", 1.0, ">= 0", maximum=MAX_LIGHT_VALUE)
_ATTENUATION = Field("vec3", [1.0, 0.0, 0.0], "[a, b, c] of the falloff 1 / (a d^2 + b d + c), each >= 0")
_AREA_COMMON = {
    "color": _COLOR,
    "intensity": Field("number", 1.0, "radiance of the emitter (times the colour), >= 0", maximum=MAX_LIGHT_VALUE),
    "samples": Field("integer", 16, "points sampled on the emitter", minimum=1),
    "seed": Field("integer", ABSENT, "the sampling pattern's seed"),
    "two_sided": Field("bool", False, "emit from both faces"),
}
LIGHT_KEYS = {
    "ambient": {"type": _TYPE, "color": _COLOR, "intensity": Field("number", 0.2, "the slides' I_a, >= 0",
                                                                           maximum=MAX_LIGHT_VALUE)},
    "directional": {
        "type": _TYPE,
        "direction": Field("vec3", REQUIRED, "toward the light; nonzero"),
        "color": _COLOR,
        "intensity": Field("number", 1.0, "irradiance at normal incidence (times the colour), >= 0",
                           maximum=MAX_LIGHT_VALUE),
    },
    "point": {
        "type": _TYPE,
        "position": Field("vec3", REQUIRED, "where the light is"),
        "color": _COLOR,
        "intensity": _INTENSITY,
        "attenuation": _ATTENUATION,
    },
    "spot": {
        "type": _TYPE,
        "position": Field("vec3", REQUIRED, "where the light is"),
        "direction": Field("vec3", REQUIRED, "where the spot points; nonzero"),
        "cutoff_deg": Field("number", 30.0, "cone half-angle in degrees: [0, 90], or 180 for no cone"),
        "exponent": Field("number", 0.0, "concentration toward the axis, >= 0"),
        "color": _COLOR,
        "intensity": _INTENSITY,
        "attenuation": _ATTENUATION,
    },
    "rect": {
        "type": _TYPE,
        "center": Field("vec3", REQUIRED, "centre of the rectangle"),
        "edge_u": Field("vec3", [1.0, 0.0, 0.0], "one edge; the lit face looks along edge_u x edge_v"),
        "edge_v": Field("vec3", [0.0, -1.0, 0.0], "the other edge; not parallel to edge_u"),
        **_AREA_COMMON,
    },
    "disk": {
        "type": _TYPE,
        "center": Field("vec3", REQUIRED, "centre of the disk"),
        "normal_dir": Field("vec3", [0.0, 0.0, -1.0], "the direction the lit face looks; nonzero"),
        "radius": Field("number", 0.5, "> 0"),
        **_AREA_COMMON,
    },
    # One of source (an image file or a sky name) and radiance; neither: radiance 1.  samples and seed
    # belong to method = "monte-carlo" (absent: 64 and 0).  See lighting.scene.envlights.
    "environment": {
        "type": _TYPE,
        "source": Field("string", ABSENT, "an image file (relative to the scene's folder) or a sky name"),
        "radiance": Field("color", ABSENT, "a constant sky instead of source (neither: 1), >= 0",
                          maximum=MAX_ENVIRONMENT_VALUE),
        "intensity": Field("color", 1.0, "multiplies the sky, >= 0", maximum=MAX_ENVIRONMENT_VALUE),
        "rotation": Field("number", 0.0, "turn about +z, degrees"),
        "background": Field("bool", True, "the camera sees the sky behind the objects"),
        "method": Field("choice", DEFAULT_ENVIRONMENT_METHOD, "how the sky lights the objects",
                        choices=ENVIRONMENT_METHODS),
        "samples": Field("integer", ABSENT, "directions per pixel (monte-carlo only; absent: 64)",
                         minimum=2, maximum=1 << 16),
        "seed": Field("integer", ABSENT, "the sampling pattern's seed (monte-carlo only; absent: 0)", minimum=0),
    },
    "opengl": {
        "type": _TYPE,
        "ambient": Field("rgba", _GL_BLACK, "a_cli"),
        "diffuse": Field("rgba", [1.0, 1.0, 1.0, 1.0], "d_cli"),
        "specular": Field("rgba", [1.0, 1.0, 1.0, 1.0], "s_cli"),
        "position": Field("numbers", [0.0, 0.0, 1.0, 0.0], "w = 0: directional, x, y, z toward the light",
                          lengths=(3, 4), what="a position [x, y, z] or [x, y, z, w]"),
        "spot_direction": Field("vec3", [0.0, 0.0, -1.0], "axis of the spot cone; nonzero"),
        "spot_exponent": Field("number", 0.0, "in [0, 128]"),
        "spot_cutoff": Field("number", 180.0, "cone half-angle in degrees: [0, 90], or 180 for no cone"),
        "constant_attenuation": Field("number", 1.0, "k_0 of 1 / (k_0 + k_1 d + k_2 d^2), >= 0; not all three 0"),
        "linear_attenuation": Field("number", 0.0, "k_1, >= 0"),
        "quadratic_attenuation": Field("number", 0.0, "k_2, >= 0"),
        "space": Field("choice", "world", "position and spot_direction in world or eye coordinates",
                       choices=("world", "eye")),
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

_CENTER = Field("vec3", _ORIGIN, "centre before the transform")
_RADIUS = Field("number", 1.0, "> 0")
_OBJECT_COMMON = {
    "type": _TYPE,
    "name": Field("string", ABSENT, "a label"),
    "material": Field("name_or_table", ABSENT, "a [materials] name or an inline material", ref="material"),
    "mode": Field("choice", ABSENT, "the shading mode for this object (absent: render.mode)", choices=SHADING_MODES),
    "cull_backfaces": Field("bool", ABSENT, "for this object (absent: render.cull_backfaces)"),
    "lights": Field("tables", ABSENT, "lights for this object instead of the scene's", what="lights for this object",
                    ref="light"),
    "translate": Field("vec3", _ORIGIN, "offset, applied last"),
    "rotate_deg": Field("vec3", _ORIGIN, "degrees about world x, then y, then z"),
    "scale": Field("numbers", 1.0, "uniform or per axis, nonzero, applied first", lengths=(3,), scalar=True,
                   what="a scale: a number or [sx, sy, sz]"),
}
OBJECT_KEYS = {
    "sphere": {**_OBJECT_COMMON, "center": _CENTER, "radius": _RADIUS},
    "uv_sphere": {
        **_OBJECT_COMMON,
        "center": _CENTER,
        "radius": _RADIUS,
        "n_lat": Field("integer", 16, "rings of latitude, >= 2"),
        "n_lon": Field("integer", 32, "segments of longitude, >= 3"),
    },
    "icosphere": {**_OBJECT_COMMON, "center": _CENTER, "radius": _RADIUS,
                  "level": Field("integer", 3, "subdivisions, 0 to 9: 20 * 4^level triangles")},  # fmt: skip
    "mesh": {
        **_OBJECT_COMMON,
        "path": Field("string", REQUIRED, "the mesh file, relative to the scene's folder"),
        "weld": Field("bool", True, "merge coincident vertices of files without normals"),
    },
}

TOP_KEYS = {
    "version": Field("integer", FORMAT_VERSION, "the format version", choices=(FORMAT_VERSION,),
                     what=f"{FORMAT_VERSION} (the only format version)"),
    "description": Field("string", "", "free text, shown by tools"),
    "camera": Field("table", REQUIRED, "the viewpoint", ref="camera"),
    "image": Field("table", {}, "size, background, encoding", ref="image"),
    "render": Field("table", {}, "shading mode, form, terms", ref="render"),
    "opengl": Field("table", {}, "light model for OpenGL-lit objects", ref="opengl"),
    "materials": Field("named", {}, "named materials", ref="material"),
    "objects": Field("tables", REQUIRED, "what to draw", what="the things to draw", ref="object",
                     empty="a scene needs at least one [[objects]] entry"),
    "lights": Field("tables", [], "the scene's lights", what="the light sources", ref="light"),
}

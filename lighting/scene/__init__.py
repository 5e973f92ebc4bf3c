r"""Scenes as files: a TOML scene format, its loader, and a renderer that composites objects by depth.

A scene file says what to draw and how — camera, image, shading options,
materials, objects and lights — as data (the format is specified in full in
``docs/scenes.md``):

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

Modules: :mod:`~lighting.scene.errors` (:class:`SceneError` and its messages),
:mod:`~lighting.scene.checks` (:class:`~lighting.scene.checks.Field`: a key described as data, and its check; the
nesting limit), :mod:`~lighting.scene.schema` (the fields of each table; the models' keys come from the model
registry), :mod:`~lighting.scene.json_schema` (the JSON Schema generated from the same fields),
:mod:`~lighting.scene.model` (:class:`Scene` and its parts), :mod:`~lighting.scene.load` (reading),
:mod:`~lighting.scene.opengl` (OpenGL materials), :mod:`~lighting.scene.renderer` (:class:`SceneRenderer`),
:mod:`~lighting.scene.budget` (memory and work estimates), :mod:`~lighting.scene.paths` (where a scene may write),
:mod:`~lighting.scene.save` (writing back) and :mod:`~lighting.scene.examples` (the shipped scenes in
``examples/``).

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

from . import budget, checks, errors, examples, load, model, opengl, paths, renderer, save, schema
from .budget import *  # noqa: F403
from .checks import *  # noqa: F403
from .errors import *  # noqa: F403
from .examples import *  # noqa: F403
from .load import *  # noqa: F403
from .model import *  # noqa: F403
from .opengl import *  # noqa: F403
from .paths import *  # noqa: F403
from .renderer import *  # noqa: F403
from .save import *  # noqa: F403
from .schema import *  # noqa: F403

__all__ = [
    "errors",
    "checks",
    "schema",
    "model",
    "load",
    "opengl",
    "renderer",
    "budget",
    "paths",
    "save",
    "examples",
    *errors.__all__,
    *checks.__all__,
    *schema.__all__,
    *model.__all__,
    *load.__all__,
    *opengl.__all__,
    *renderer.__all__,
    *budget.__all__,
    *paths.__all__,
    *save.__all__,
    *examples.__all__,
]

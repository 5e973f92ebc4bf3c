"""Scene files: schema, loading, saving and rendering; example scenes in ``examples/``."""

from __future__ import annotations

from . import scene
from .scene import (  # noqa: F401
    FORMAT_VERSION,
    MAX_NESTING,
    GLLight,
    ImageOptions,
    OpenGLOptions,
    RenderOptions,
    Scene,
    SceneBudgetError,
    SceneError,
    SceneObject,
    SceneRenderer,
    check_scene_budget,
    example_path,
    gl_material_to_engine,
    list_examples,
    load_scene,
    parse_scene,
    render_scene,
    scene_estimate,
    scene_output_path,
    scene_to_toml,
)

__all__ = [
    "scene",
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

"""The scene as data: :class:`Scene`, its objects, options and OpenGL lights, as :func:`~lighting.scene.load.load_scene`
returns them and :class:`~lighting.scene.renderer.SceneRenderer` draws them."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ..render.camera import Camera
from ..shading import opengl as gl
from ..shading.equation import TERMS

__all__ = ["Scene", "SceneObject", "RenderOptions", "ImageOptions", "OpenGLOptions", "GLLight"]


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
        """The :class:`lighting.shading.opengl.Light` with position and spot direction in eye coordinates.

        Parameters
        ----------
        view_matrix : array_like, shape (4, 4)
            The camera's world-to-eye matrix ``V``.

        Returns
        -------
        lighting.shading.opengl.Light
            ``V p`` and ``V₃ₓ₃ d`` for ``space = "world"``; the light as it is for ``"eye"``.
        """
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
        """The object's ``name`` key, or None."""
        return self.spec.get("name")


@dataclass(frozen=True, eq=False)
class Scene:
    """A scene: what :func:`~lighting.scene.load.load_scene` returns and
    :class:`~lighting.scene.renderer.SceneRenderer` draws.

    Change a part with :func:`dataclasses.replace` (or :meth:`with_lights`,
    :meth:`with_size`); :meth:`to_dict` / :func:`~lighting.scene.save.scene_to_toml` write it back.
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
    #: Whether a render may take longer than the time budget (``load_scene(..., allow_slow=True)``, the
    #: command line's ``--allow-slow``; :func:`lighting._budget.check_scene_budget`); never read from a file.
    allow_slow: bool = False

    def object_lights(self, index: int) -> tuple:
        """The lights that shade object ``index``: its own override, else the scene's.

        Parameters
        ----------
        index : int
            The object's index in :attr:`objects`.

        Returns
        -------
        tuple
            Its lights.
        """
        own = self.objects[index].lights
        return self.lights if own is None else own

    def object_mode(self, index: int) -> str:
        """The shading mode of object ``index``: its own override, else ``render.mode``.

        Parameters
        ----------
        index : int
            The object's index in :attr:`objects`.

        Returns
        -------
        str
            ``"flat"``, ``"gouraud"`` or ``"phong"``.
        """
        return self.objects[index].mode or self.render.mode

    def is_opengl_lit(self, index: int) -> bool:
        """Whether object ``index`` is lit by OpenGL lights (:func:`lighting.shading.opengl.shade_vertices`).

        Parameters
        ----------
        index : int
            The object's index in :attr:`objects`.

        Returns
        -------
        bool
            True for OpenGL lights.
        """
        return _gl_lit(self.object_lights(index))

    @property
    def light_count(self) -> int:
        """Scene lights plus every object's own lights."""
        return len(self.lights) + sum(len(o.lights) for o in self.objects if o.lights is not None)

    def with_lights(self, lights) -> Scene:
        """The same scene under other (scene-level) lights.

        Parameters
        ----------
        lights : iterable of lights
            The new scene lights (objects' own lights stay).

        Returns
        -------
        Scene
            A new scene.
        """
        return replace(self, lights=tuple(lights))

    def with_size(self, width: int, height: int) -> Scene:
        """The same scene at another image size (the camera keeps its field of view).

        Parameters
        ----------
        width, height : int
            The image size in pixels.

        Returns
        -------
        Scene
            A new scene.
        """
        cam = self.camera.replace(width=width, height=height)
        return replace(self, camera=cam, image=replace(self.image, width=cam.width, height=cam.height))

    def to_dict(self) -> dict:
        """The scene as plain data (what a TOML file holds, defaults written out).

        Returns
        -------
        dict
            What :func:`~lighting.scene.load.parse_scene` reads back.
        """
        from .save import _scene_to_dict  # save.py writes scenes, and imports this module

        return _scene_to_dict(self)


def _gl_lit(lights) -> bool:
    """Whether ``lights`` are OpenGL lights (a light list holds either kind only, never both)."""
    return any(isinstance(lt, GLLight) for lt in lights)

"""Rendering a scene: one cached renderer per object, composited by depth.

:class:`SceneRenderer` renders each object with its own :class:`~lighting.render.renderer.Renderer`
(rasterized once, cached) and keeps, per pixel, the object nearest to the camera (smallest view depth
``f·(p − eye)`` among the objects covering the pixel; ties go to the object listed first), with the
background elsewhere.  Changing lights or materials re-shades without re-rasterizing.
"""

from __future__ import annotations

import time

import numpy as np

from .._text import plural
from ..render.camera import Camera
from ..render.image import encode_srgb8
from ..render.linear_image import LinearImage
from ..render.renderer import Renderer
from ..shading import opengl as gl
from .budget import check_scene_budget
from .model import Scene, _gl_lit
from .opengl import _engine_material, _gl_with_terms

__all__ = ["SceneRenderer", "render_scene"]


def _camera_key(cam: Camera) -> tuple:
    """Everything about a camera that changes what a rasterization holds."""
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

    Parameters
    ----------
    scene : Scene
        The scene to draw (checked against the budget before anything is allocated).
    dtype : numpy dtype
        The working float type of the renderers.
    plan : {True, False, "full"}
        True: evaluate through :mod:`lighting.render.plan` (leave out what the scene does not
        need); False: the renderer's general path; ``"full"``: the nothing-skipped reference.

    Examples
    --------
    >>> from lighting.lights import AmbientLight
    >>> from lighting.scene import example_path, load_scene
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
        """The scene drawn; assigning another keeps every rasterization whose geometry and camera are unchanged."""
        return self._scene

    @scene.setter
    def scene(self, new: Scene):
        """Draw ``new`` from now on, keeping each object's rasterization if its geometry and the camera are unchanged.

        Parameters
        ----------
        new : Scene
            Refused (``BudgetError``, a ValueError) when it would need more than the memory budget.
        """
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
        return self._scene.objects[i].geometry_key + (self._cull(i),)

    def _cull(self, i: int) -> bool:
        """Whether object ``i`` culls back faces: its own override, else ``render.cull_backfaces``."""
        ob = self._scene.objects[i]
        return self._scene.render.cull_backfaces if ob.cull_backfaces is None else ob.cull_backfaces

    @property
    def rasterizations(self) -> int:
        """Rasterizations (or ray casts) done by the cached renderers so far."""
        return sum(r.rasterizations for r in self._renderers if r is not None)

    def renderer(self, index: int) -> Renderer:
        """The cached :class:`~lighting.render.renderer.Renderer` of object ``index`` (created on first use).

        Parameters
        ----------
        index : int
            The object's index in the scene.

        Returns
        -------
        lighting.render.renderer.Renderer
            Its renderer.
        """
        if self._renderers[index] is None:
            ob = self._scene.objects[index]
            self._renderers[index] = Renderer(ob.geometry, self._scene.camera, dtype=self.dtype,
                                              cull_backfaces=self._cull(index))  # fmt: skip
            self._keys[index] = self._object_key(index)
        return self._renderers[index]

    def visibility(self) -> np.ndarray:
        """Which object each pixel shows: the nearest covering one (ties to the lower index).

        Returns
        -------
        numpy.ndarray, shape (H, W), int64
            Index of the object seen at each pixel, ``−1`` where none is.
        """
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
        (an OpenGL material is first mapped by :func:`~lighting.scene.opengl.gl_material_to_engine`).
        OpenGL lights: :func:`lighting.shading.opengl.shade_vertices` at the mode's shading
        samples in eye coordinates.

        Parameters
        ----------
        index : int
            The object's index in the scene.
        renderer : lighting.render.renderer.Renderer
            Its renderer (:meth:`renderer`).
        material : lighting.shading.equation.Material or lighting.shading.opengl.Material
            The material to shade with.
        lights : sequence of lights
            The lights (engine lights, or :class:`~lighting.scene.model.GLLight` only).

        Returns
        -------
        numpy.ndarray, shape (H, W, 3)
            The object's linear image.
        """
        scene = self._scene
        mode = scene.object_mode(index)
        if _gl_lit(lights):
            return self._shade_gl(index, renderer, material, lights, mode)
        material = _engine_material(material)
        if self.plan is True:
            return self.object_plan(index).execute(renderer)
        if self.plan == "full":
            from ..render.plan import evaluate_full

            opts = {"mode": mode, "form": scene.render.form, "terms": scene.render.terms}
            return evaluate_full(renderer, material, lights, **opts)
        return renderer.render(material, lights, mode=mode, form=scene.render.form, terms=scene.render.terms)

    # ------------------------------------------------------------------ plans
    def object_plan(self, index: int):
        """The evaluation plan of object ``index`` (engine-lit objects; see :mod:`lighting.render.plan`).

        Parameters
        ----------
        index : int
            The object's index in the scene.

        Returns
        -------
        lighting.render.plan.Plan
            What its lighting needs and how it is evaluated.
        """
        from ..render.plan import bounding_sphere, compile_plan

        scene = self._scene
        ob = scene.objects[index]
        return compile_plan(
            _engine_material(ob.material), scene.object_lights(index), mode=scene.object_mode(index),
            form=scene.render.form, terms=scene.render.terms, bounds=bounding_sphere(ob.geometry),
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

    def environment_background(self):
        """The scene's environment as the camera sees it behind the objects, or None.

        The radiance of the scene-level environment lights with ``background = true`` along each
        pixel's camera ray (times π in the classic form, as everything else); the render adds the
        ``[image]`` background to it.  An object's own environment light lights that object only.

        Returns
        -------
        numpy.ndarray, shape (H, W, 3), or None
        """
        shown = [lt for lt in self._scene.lights if getattr(lt, "is_environment", False) and lt.background]
        if not shown:
            return None
        _, dirs = self._scene.camera.rays(dtype=self.dtype)
        total = sum(np.asarray(lt.radiance(dirs), dtype=self.dtype) for lt in shown)
        return total * self.dtype(np.pi) if self._scene.render.form == "classic" else total

    def explain(self) -> str:
        """What the scene needs, in plain words: one plan per group of objects, and what was left out.

        Returns
        -------
        str
            Several lines of text.
        """
        scene = self._scene
        owner = self.visibility()
        visible = tuple(int(np.count_nonzero(owner == i)) for i in range(len(scene.objects)))
        lines = [f"{plural(len(scene.objects), 'object')}, {plural(scene.light_count, 'light')}, "
                 f"{scene.camera.width}x{scene.camera.height} pixels."]  # fmt: skip
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
        lines.extend(_environment_budget_lines(scene))
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

        Returns
        -------
        image : LinearImage, shape (H, W, 3)
            Linear RGB in the renderer's dtype, carrying the scene's ``[image]`` exposure and tone
            map for display (an ``ndarray``; ``np.asarray(image)`` is the plain array).
        info : dict
            The summary above.
        """
        t0 = time.perf_counter()
        scene = self._scene
        before = self.rasterizations
        owner = self.visibility()
        cam = scene.camera
        image = np.empty((cam.height, cam.width, 3), dtype=self.dtype)
        image[...] = np.asarray(scene.image.background, dtype=self.dtype)
        behind = self.environment_background()
        if behind is not None:
            image += behind
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
        return LinearImage(image, exposure=scene.image.exposure, tonemap=scene.image.tonemap), info

    def encode(self, image, *, exposure=None, tonemap=None):
        """8-bit sRGB of a rendered image with the scene's (or the given) exposure and tone map.

        Parameters
        ----------
        image : numpy.ndarray, shape (H, W, 3)
            Linear RGB (:meth:`render`).
        exposure : float, optional
            Stops; default the scene's ``[image].exposure``.
        tonemap : {"clamp", "reinhard"}, optional
            Default the scene's ``[image].tonemap``.

        Returns
        -------
        numpy.ndarray, shape (H, W, 3), uint8
            The encoded image.
        """
        opts = self._scene.image
        return encode_srgb8(
            image,
            exposure=opts.exposure if exposure is None else exposure,
            tonemap=opts.tonemap if tonemap is None else tonemap,
        )


def _environment_budget_lines(scene) -> list:
    """What each environment light costs before the first frame, and the render's estimated time."""
    from .budget import explain_lines

    return explain_lines(scene)


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

    def sample_tangents(self, mode):
        # Asked for only when a material is anisotropic; each object keeps its own tangent field.
        return np.asfortranarray(np.concatenate([r.sample_tangents(mode) for r in self.renderers]))

    def sample_view(self, mode):
        views = [r.sample_view(mode) for r in self.renderers]
        if views[0][0].ndim == 1:  # a distant viewer: one direction for all
            return views[0]
        v = np.asfortranarray(np.concatenate([w[0] for w in views]))
        return v, np.concatenate([w[1] for w in views])

    def lengths(self, mode):
        return [len(r.sample_normals(mode)) for r in self.renderers]


def render_scene(scene: Scene):
    """Render a scene once (see :meth:`SceneRenderer.render`).

    Parameters
    ----------
    scene : Scene
        The scene.

    Returns
    -------
    image : LinearImage, shape (H, W, 3)
        Linear RGB with the scene's exposure and tone map (shows itself sRGB-encoded in Jupyter;
        ``np.asarray(image)`` is the plain array).
    info : dict
        The summary of :meth:`SceneRenderer.render`.
    """
    return SceneRenderer(scene).render()

r"""Image-based lighting in the explorer: the environment light, the lit object and the progressive reference.

The explorer's view frame has ``+y`` up and ``+z`` toward the viewer; an environment's frame has
``+z`` up (:mod:`lighting.lights.environment`).  Under an environment the lit sphere and the object
are rendered in the environment's frame, seen from ``−y``: a direction ``(x, y, z)`` of the view
frame is ``(x, −z, y)`` there (:data:`VIEW_TO_WORLD`), so the key light keeps the place its
elevation and azimuth give it on screen, the sky is above the object and the ground below it.
Mesh files are taken as ``+y`` up (the OBJ and glTF habit) and turned the same way.

Everything is the engine's: the environment is an :class:`lighting.lights.EnvironmentLight` given
to :meth:`lighting.render.Renderer.render` (the engine's default method, the dominant lights; while a
control is dragged the split sum, several times cheaper, and the release re-shades the image by the
dominant lights once), and the reference is
:class:`lighting.integrate.ibl.ProgressiveRadiance` on the renderer's own per-pixel normals and view
vectors, its values spread into the image by the renderer (:meth:`~lighting.render.Renderer.spread`).
With an environment the ambient light is dropped (the environment is the light from everywhere,
done properly); the key light stays (its intensity slider takes it to 0).

The reference runs in tiles of at most :data:`TILE_PIXELS` pixels, one pass of
:data:`PASS_SAMPLES` samples per pixel at a time, so each idle tick of the window does a few tens
of milliseconds of work; :meth:`EnvironmentMixin.refine` adds passes up to a time budget and
re-composes the images.  Any change of a control that the images depend on starts it again.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

import numpy as np

from lighting import Lambert, Material
from lighting.analysis.machband import LUMA
from lighting.lights import SKIES, AmbientLight, EnvironmentLight, load_environment
from lighting.lights.environment import LatLongEnvironment
from lighting.render import AnalyticSphere, Renderer
from lighting.render.camera import Camera

from .encode import encode8

__all__ = [
    "VIEW_TO_WORLD",
    "ENV_FIELDS",
    "ENVIRONMENT_LABELS",
    "ENVIRONMENT_HELP",
    "AUTO_CLIP_FRACTION",
    "environment_label",
    "auto_exposure",
    "TILE_PIXELS",
    "PASS_SAMPLES",
    "MAX_SAMPLES",
    "ObjectView",
    "Refinement",
    "world_light",
    "default_mesh",
    "EnvironmentMixin",
]

#: View frame → environment frame: ``(x, y, z) ↦ (x, −z, y)`` (a rotation: image up is the sky's up).
VIEW_TO_WORLD = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
#: The controls of the environment itself.
ENV_FIELDS = frozenset({"environment", "env_rotation", "env_intensity"})
#: Pixels per tile of the progressive reference, samples per pixel per pass, and where it stops.
TILE_PIXELS = 2048
PASS_SAMPLES = 8
MAX_SAMPLES = 4096
#: Rows of the lat-long map a procedural sky is sampled into (the environment importance-samples it).
SKY_ROWS = 256
#: Camera of the object panel: eye direction (from the object's centre, environment frame) and field of view.
OBJECT_EYE = np.array([0.0, -4.6, 0.9])
OBJECT_TARGET = np.array([0.0, 0.0, 0.12])
OBJECT_FOV_DEG = 29.0
#: What every environment choice is called on every button, menu, caption and command-line help: the
#: engine's own names (``--environment band-limited`` is the button "band-limited"), one table for all.
ENVIRONMENT_LABELS = {"none": "none", **{name: name for name in SKIES}, "file": "file"}
#: One line on each environment choice (tooltips, help): the engine's description of each sky.
ENVIRONMENT_HELP = {
    "none": "no environment: the key light and the ambient light I_a",
    **{name: sky.description for name, sky in SKIES.items()},
    "file": "the environment image given with --environment FILE (lat-long, +z up)",
}
#: The share of the lit sphere's pixels :func:`auto_exposure` lets clip (a sun's highlight).
AUTO_CLIP_FRACTION = 0.01


def environment_label(name: str) -> str:
    """The label of an environment choice (:data:`ENVIRONMENT_LABELS`); an unknown name is refused by name.

    Parameters
    ----------
    name : str
        A choice of the ``environment`` control.

    Returns
    -------
    str

    Examples
    --------
    >>> environment_label("band-limited"), environment_label("none")
    ('band-limited', 'none')
    """
    if name not in ENVIRONMENT_LABELS:
        raise ValueError(f"environment must be one of {', '.join(ENVIRONMENT_LABELS)}; got {name!r}")
    return ENVIRONMENT_LABELS[name]


def auto_exposure(image, coverage, clip_fraction: float = AUTO_CLIP_FRACTION) -> float:
    """The exposure (stops) at which at most ``clip_fraction`` of the covered pixels clip.

    An environment lights the sphere from every direction: in the classic form (``π`` times the
    radiance) a sky of radiance 1 on ``k_d = 0.8`` gives 2.5, and at the default exposure most of the
    sphere is white.  The front ends set the ``exposure`` control to this value when a sky or file is
    switched on (:meth:`EnvironmentMixin.apply_auto_exposure`); the form stays the one the user chose
    (switching to the physical form instead would change what every number on screen means, a factor π,
    and a bright sky or file clips in either form: the exposure is the display's, the numbers stay).
    The value is rounded down to a tenth of a stop and kept in the control's range ``[−8, 8]``.

    Parameters
    ----------
    image : ndarray, (H, W, 3)
        The linear image.
    coverage : ndarray of bool, (H, W)
        The pixels that count (the sphere).
    clip_fraction : float
        The share of covered pixels that may clip, in ``[0, 1)``.

    Returns
    -------
    float
        Stops: ``image · 2^stops`` has at most that share of covered pixels with a channel above 1.

    Examples
    --------
    >>> img = np.full((2, 2, 3), 4.0); img[0, 0] = 100.0
    >>> auto_exposure(img, np.ones((2, 2), bool), 0.25)  # the brightest quarter may clip: 4 → 1
    -2.0
    >>> auto_exposure(np.zeros((2, 2, 3)), np.ones((2, 2), bool))  # nothing lit: nothing to adjust
    0.0
    """
    if not (isinstance(clip_fraction, (int, float)) and 0.0 <= clip_fraction < 1.0):
        raise ValueError(f"clip_fraction must be a number in [0, 1); got {clip_fraction!r}")
    brightest = np.max(np.asarray(image, dtype=np.float64)[np.asarray(coverage, dtype=bool)], axis=-1, initial=0.0)
    if brightest.size == 0 or not np.any(brightest > 0):
        return 0.0
    # The value that the brightest share of pixels above it may exceed: brought to 1 (an order statistic,
    # so no more than that share clips whatever the distribution).
    k = max(int(math.ceil(brightest.size * (1.0 - clip_fraction) - 1e-9)) - 1, 0)
    level = float(np.partition(brightest, k)[k])
    if not level > 0:
        return 0.0
    stops = math.floor(-10.0 * math.log2(level) + 1e-9) / 10.0
    if level * 2.0**stops > 1.0:  # rounding of the logarithm: the level itself never passes 1
        stops = round(stops - 0.1, 1)
    return float(min(max(stops, -8.0), 8.0))


def world_light(light):
    """A light of the explorer's view frame turned into the environment's frame (:data:`VIEW_TO_WORLD`).

    Parameters
    ----------
    light : Light
        A directional, point, spot, rect or disk light, or an OpenGL light (:class:`lighting.gl.Light`, or a
        scene's :class:`~lighting.scene.GLLight`); an ambient light has no direction and is returned as is.

    Returns
    -------
    Light
        The same light, its directions, position, centre and edges turned (an OpenGL position's ``w`` kept).

    Examples
    --------
    >>> from lighting import DirectionalLight
    >>> world_light(DirectionalLight((0.0, 0.0, 1.0))).direction.tolist()  # toward the viewer: -y
    [0.0, -1.0, 0.0]
    >>> from lighting.lights import RectLight
    >>> rect = world_light(RectLight(center=(0.0, 0.0, 3.0)))  # in front of the sphere, facing it (-z)
    >>> rect.center.tolist(), float(rect.normal()[1])  # in front is -y, facing the sphere is +y
    ([0.0, -3.0, 0.0], 1.0)
    """
    if isinstance(light, AmbientLight):
        return light
    if hasattr(light, "light") and hasattr(light, "in_eye_space"):  # a scene's GLLight: its OpenGL light
        return dataclasses.replace(light, light=world_light(light.light))
    changes = {}
    for name in ("direction", "position", "center", "edge_u", "edge_v", "normal_dir", "spot_direction"):
        value = getattr(light, name, None)
        if value is None:
            continue
        v = np.asarray(value, dtype=np.float64)
        if v.shape == (4,):  # an OpenGL position (x, y, z, w)
            changes[name] = tuple(np.append(VIEW_TO_WORLD @ v[:3], v[3]))
        else:
            changes[name] = VIEW_TO_WORLD @ v
    return dataclasses.replace(light, **changes) if changes else light


def default_mesh():
    """The object shown without ``--mesh``: a smooth blob (an icosphere with three bumps a side), ``+y`` up.

    Its curvature changes everywhere, so a reflection of the sky slides over it as the roughness
    changes; its normals are the angle-weighted vertex normals (Phong-interpolated in the panel).

    Returns
    -------
    TriangleMesh
        About 5000 triangles inside the unit ball.
    """
    from lighting.render.mesh import TriangleMesh, icosphere

    ico = icosphere(4)
    v = np.asarray(ico.vertices, dtype=np.float64)
    r = 1.0 + 0.16 * np.sin(3.0 * v[:, 0]) * np.sin(3.0 * v[:, 1] + 0.6) * np.sin(3.0 * v[:, 2] + 1.1)
    v = v * (r / np.max(r))[:, None]
    return TriangleMesh(v, ico.faces)


def _fitted(mesh):
    """The mesh centred on its bounding box, scaled into the unit ball and turned ``+y`` up → ``+z`` up."""
    from lighting.render.mesh import TriangleMesh

    v = np.asarray(mesh.vertices, dtype=np.float64)
    centre = 0.5 * (v.min(axis=0) + v.max(axis=0))
    radius = float(np.max(np.linalg.norm(v - centre, axis=1)))
    v = (v - centre) / (radius if radius > 0 else 1.0)
    normals = np.asarray(mesh.normals, dtype=np.float64) @ VIEW_TO_WORLD.T
    return TriangleMesh(v @ VIEW_TO_WORLD.T, mesh.faces, normals=normals)


@dataclass(frozen=True, eq=False)
class ObjectView:
    """The lit object: linear image (environment behind it), its 8-bit encoding, and how it was lit."""

    image: np.ndarray  # (H, W, 3) linear, background included
    rgb8: np.ndarray
    coverage: np.ndarray  # (H, W) bool: the object's pixels
    triangles: int
    method: str  # "dominant lights", "split sum" (while a control is dragged), "reference" or "key light"
    clipped: int


@dataclass
class _Target:
    """One image the reference refines: its renderer, the image without the environment, where its rows are."""

    name: str
    renderer: Renderer
    mode: str
    key_image: np.ndarray  # the key light alone (no environment)
    background: np.ndarray | None  # the environment behind (None: transparent, the lit sphere)
    rows: slice


class Refinement:
    """The Monte-Carlo reference of the environment term of several images, refined tile by tile.

    Parameters
    ----------
    brdf : BRDF
        The surface's BRDF (the terms shown).
    environment : Environment
        The environment light's environment (intensity and rotation applied).
    normals, view_dirs : ndarray, (N, 3)
        The pixels' normals and view vectors (environment frame), every image's rows in turn.
    tile : int
        Pixels per tile.
    """

    def __init__(self, brdf, environment, normals, view_dirs, *, tile=TILE_PIXELS):
        from lighting.integrate.ibl import ProgressiveRadiance

        n = len(normals)
        self.count = n
        self.tiles = [
            ProgressiveRadiance(brdf, environment, normals[i : i + tile], view_dirs[i : i + tile], seed=k)
            for k, i in enumerate(range(0, n, tile))
        ]
        self.seconds = 0.0
        self.passes = 0

    @property
    def samples(self) -> int:
        """Samples per pixel every pixel has (the fewest of the tiles)."""
        return min((t.samples for t in self.tiles), default=0)

    @property
    def done(self) -> bool:
        """Whether every tile has :data:`MAX_SAMPLES` samples per pixel."""
        return self.samples >= MAX_SAMPLES

    def step(self, budget: float) -> int:
        """Add passes to the tiles furthest behind for about ``budget`` seconds (at least one pass).

        Parameters
        ----------
        budget : float
            Seconds of work.

        Returns
        -------
        int
            Passes added.
        """
        t0 = time.perf_counter()
        added = 0
        while not self.done and self.tiles:
            tile = min(self.tiles, key=lambda t: t.samples)
            tile.add(PASS_SAMPLES)
            added += 1
            if time.perf_counter() - t0 >= budget:
                break
        self.passes += added
        self.seconds += time.perf_counter() - t0
        return added

    @property
    def value(self) -> np.ndarray:
        """``(N, 3)`` float64: the reflected radiance of every pixel (physical form)."""
        if not self.tiles:
            return np.zeros((0, 3))
        return np.concatenate([np.asarray(t.value, dtype=np.float64) for t in self.tiles])

    @property
    def error(self) -> np.ndarray:
        """``(N, 3)`` float64: each pixel's standard error (``inf`` before two passes of its tile)."""
        if not self.tiles:
            return np.zeros((0, 3))
        return np.concatenate([np.asarray(t.error, dtype=np.float64) for t in self.tiles])

    def relative_error(self) -> float:
        """The median over lit pixels of the luminance standard error over the luminance (``inf`` at first).

        Returns
        -------
        float
            E.g. 0.03 for ±3 %.
        """
        y = self.value @ LUMA
        e = self.error @ LUMA  # errors add at worst linearly
        lit = y > 0
        if not np.any(lit):
            return 0.0
        return float(np.median(e[lit] / y[lit]))


class EnvironmentMixin:
    """The environment views of :class:`~explorer.app.views.ExplorerModel` (the lit sphere under a sky, the object).

    Attributes set by :meth:`_init_environment`: :attr:`environment_file` (``--environment FILE``),
    :attr:`object_mesh` and :attr:`refinement` (the running reference, or None).
    """

    #: Whether the views being computed follow a drag (``update(only=...)``, set by the update): the environment's
    #: images are then made by the split sum and marked provisional, for the release to make again.
    live_update: bool = False

    def _init_environment(self, *, object_size=(320, 224), mesh=None, environment_file=None):
        from lighting.render.mesh import TriangleMesh, load_mesh

        self.object_size = (int(object_size[0]), int(object_size[1]))
        if mesh is None:
            mesh = default_mesh()
        self.object_mesh = _fitted(mesh if isinstance(mesh, TriangleMesh) else load_mesh(mesh))
        self._bases: dict = {}
        self._prefiltered: dict = {}
        self.environment_file = None
        if environment_file is not None:
            self.open_environment(environment_file)
        self.refinement: Refinement | None = None
        self._targets: list = []
        self._world_sphere = None
        self._object_renderer = None

    # ------------------------------------------------------------------ the environment
    def open_environment(self, path):
        """Read an environment file (``.hdr``, ``.pfm``, ``.npy``, ``.exr``): the ``"file"`` choice shows it.

        Parameters
        ----------
        path : str or os.PathLike, or (path, Environment)
            The file; a bad one raises ``ValueError`` naming it (:func:`lighting.lights.load_environment`).
            A pair is a file already read.
        """
        if isinstance(path, tuple):
            path, base = path
        else:
            base = load_environment(path)
        self.environment_file = path
        self._bases["file"] = base
        self._prefiltered.pop("file", None)

    def open_mesh(self, path):
        """Read a mesh file (``.obj``, and with trimesh ``.ply .stl .glb .gltf .off``): the lit object becomes it.

        Parameters
        ----------
        path : str or os.PathLike or TriangleMesh
            The mesh; a bad file raises ``ValueError`` naming it (:func:`lighting.render.mesh.load_mesh`).
        """
        from lighting.render.mesh import TriangleMesh, load_mesh

        self.object_mesh = _fitted(path if isinstance(path, TriangleMesh) else load_mesh(path))
        self._object_renderer = None
        self.views.pop("object", None)

    def _base(self, name):
        if name not in self._bases:
            # A sky sampled into a lat-long map: the reference then importance-samples its sun.
            sky = load_environment(name)
            self._bases[name] = LatLongEnvironment.from_function(sky.radiance, SKY_ROWS)
        return self._bases[name]

    @property
    def environment_active(self) -> bool:
        """Whether an environment lights the images: one is chosen (and for ``"file"``, a file was read)."""
        env = self.state.environment
        return env != "none" and (env != "file" or "file" in self._bases)

    def environment_light(self, *, background=True, live=False) -> EnvironmentLight | None:
        """The chosen environment as a light (intensity and rotation of the controls), or None.

        The environment is prefiltered once per source; turning it or scaling it reuses that (the
        rotation and the intensity are applied at lookup).

        Parameters
        ----------
        background : bool
            Show it behind the geometry.
        live : bool
            For an image shown while a control is dragged: the split sum instead of the engine's default,
            the dominant lights (whose re-shade of a glossy lobe costs many times the split sum's:
            ``lighting-explorer bench --ibl``).

        Returns
        -------
        EnvironmentLight or None
        """
        s = self.state
        if not self.environment_active:
            return None
        from lighting.integrate.prefilter import prefilter_environment

        base = self._base(s.environment)
        pre = self._prefiltered.get(s.environment)
        if pre is None:
            pre = self._prefiltered[s.environment] = prefilter_environment(base)
        # The base's levels, the intensity and rotation applied at lookup: a slider makes a new light at every
        # move, and prefiltering once per source (the dominant lights' extraction too) keeps the drag at a re-shade.
        return EnvironmentLight(base, intensity=s.env_intensity, rotation=s.env_rotation, background=background,
                                prefiltered=pre, method="split-sum" if live else "dominant")  # fmt: skip

    def _shown_live(self, view: str) -> bool:
        """Whether ``view`` is being computed for a drag (:attr:`live_update`); then it is marked provisional, so
        that the release computes it again by the dominant lights."""
        if self.live_update:
            self.provisional.add(view)
        return self.live_update

    def apply_auto_exposure(self) -> set[str]:
        """What a front end calls after the ``environment`` control changed: the exposure follows the light.

        With an environment on, the ``exposure`` control is set to the lit sphere's automatic exposure
        (:attr:`~explorer.app.views.SphereView.auto_exposure`, :func:`auto_exposure`), and the exposure it
        had before is remembered; with the environment off again, that exposure comes back (unless the
        automatic one was changed by hand meanwhile).  The state stays the one source of truth: this sets
        the control, as a slider would.

        Returns
        -------
        set of str
            The views recomputed (by the updates this makes).

        Examples
        --------
        >>> from explorer.app.views import ExplorerModel
        >>> model = ExplorerModel(sphere_size=32, mesh_size=32, lobe_resolution=8)
        >>> model.state.environment = "uniform"
        >>> _ = model.apply_auto_exposure(); model.state.exposure
        -2.1
        >>> model.state.environment = "none"
        >>> _ = model.apply_auto_exposure(); model.state.exposure
        0.0
        """
        views = self.update()
        s = self.state
        auto = self.views["sphere"].auto_exposure
        before, applied = getattr(self, "_exposure_before", None), getattr(self, "_exposure_applied", None)
        if auto is not None:
            if before is None or applied is None or s.exposure != applied:
                before = s.exposure  # the exposure to come back to: the user's
            s.update(exposure=auto)
            self._exposure_before, self._exposure_applied = before, auto
        elif before is not None:
            if s.exposure == applied:
                s.update(exposure=before)
            self._exposure_before = self._exposure_applied = None
        return views | self.update()

    def world_lights(self) -> list:
        """The key light and the extra lights in the environment's frame (no ambient light: the environment
        replaces it; an OpenGL extra light's own ambient part stays).

        Returns
        -------
        list of Light
            The key light (none for the "ambient" light type) and :meth:`AppState.extra_lights`, turned by
            :func:`world_light`.
        """
        key = self.state.key_light()
        return [world_light(lt) for lt in ([] if key is None else [key]) + self.state.extra_lights()]

    # ------------------------------------------------------------------ renderers
    def _sphere_renderer_world(self, mode, tessellation):
        s = self.sphere_size
        if mode == "phong":
            if self._world_sphere is None:
                cam = Camera((0.0, -10.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), projection="orthographic",
                             ortho_height=2 * 1.08, width=s, height=s)  # fmt: skip
                self._world_sphere = Renderer(AnalyticSphere(), cam, dtype=self.dtype)
            return self._world_sphere, "exact sphere"
        key = ("world", tessellation, s)
        r = self._renderers.pop(key, None)
        if r is None:
            cam = Camera((0.0, -10.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), projection="orthographic",
                         ortho_height=2 * 1.08, width=s, height=s)  # fmt: skip
            r = Renderer(self.mesh(tessellation).transformed(_as_4x4(VIEW_TO_WORLD)), cam, dtype=self.dtype)
        self._renderers[key] = r
        return r, f"{r.geometry.n_triangles} triangles"

    def object_renderer(self) -> Renderer:
        """The renderer of the lit object: perspective, the environment's ``+z`` up (rasterized once).

        Returns
        -------
        Renderer
            Of :attr:`object_mesh` at :attr:`object_size` pixels, float32.
        """
        if self._object_renderer is None:
            w, h = self.object_size
            cam = Camera.look_at(OBJECT_EYE, OBJECT_TARGET, (0.0, 0.0, 1.0), fov_y_deg=OBJECT_FOV_DEG, width=w,
                                 height=h)  # fmt: skip
            # Normals turned toward the eye where interpolation tips them away: no black specks on the silhouette.
            self._object_renderer = Renderer(self.object_mesh, cam, dtype=np.float32, face_viewer=True)
        return self._object_renderer

    # ------------------------------------------------------------------ views
    def _env_sphere_view(self, material):
        """The lit sphere under the environment (dominant lights; the reference refines it): a SphereView."""
        from .views import SphereView

        s = self.state
        r, geometry = self._sphere_renderer_world(s.mode, s.tessellation)
        lights = self.world_lights() + [self.environment_light(background=False, live=self._shown_live("sphere"))]
        img = r.render(material, lights, mode=s.mode, form=s.form, terms=s.terms)
        target = self.split_target() if s.split and not s.reference else None
        from .split import split_angle, split_render

        if target is not None:
            img = split_render(r, img, Material(target.brdf, ambient=s.diffuse_albedo), lights, s)
        cov = r.gbuffer.coverage
        rgb8, clipped = encode8(img, cov, s.exposure)
        auto = auto_exposure(img, cov)
        if target is None:
            return SphereView(img, rgb8, cov, s.mode, geometry, clipped, auto_exposure=auto)
        return SphereView(img, rgb8, cov, s.mode, geometry, clipped, target.label, target.colour, split_angle(s),
                          auto)  # fmt: skip

    def _object_view(self, material) -> ObjectView:
        s = self.state
        r = self.object_renderer()
        live = self.environment_active and self._shown_live("object")
        env = self.environment_light(live=live)
        if env is None:
            lights = [AmbientLight(intensity=s.ambient)] + self.world_lights()
            method = "key light"
        else:
            lights = self.world_lights() + [env]
            method = "split sum" if live else "dominant lights"
        img = r.render(material, lights, mode="phong", form=s.form, terms=s.terms)
        cov = r.gbuffer.coverage
        return self._object_record(img, cov, method)

    def _object_record(self, img, cov, method):
        s = self.state
        rgb8, _ = encode8(img, None, s.exposure)
        clipped = int(np.count_nonzero(np.any(np.asarray(img)[cov] * 2.0**s.exposure > 1.0, axis=-1)))
        return ObjectView(np.asarray(img), rgb8, cov, self.object_mesh.n_triangles, method, clipped)

    # ------------------------------------------------------------------ the reference
    def _restart_refinement(self, views):
        """A new reference when the images it refines were recomputed (or it is switched off)."""
        s = self.state
        drag = (self.pending or self.provisional) and set(views) & {"sphere", "object"}
        if not (s.reference and self.environment_active) or drag:
            # Off, or a drag in progress (views left for later): the reference starts again once it is released.
            self.refinement, self._targets = None, []
            return
        shown = {"sphere"} | ({"object"} if s.view3d == "object" else set())
        if self.refinement is not None and not (set(views) & shown):
            return
        env = self.environment_light(live=True)  # its environment and background are what is used: either method
        material = s.material()
        key_only = Material(material.brdf, ambient=material.ambient)
        normals, views_, targets, start = [], [], [], 0
        for name in ("sphere", "object"):
            if name not in shown:
                continue
            if name == "sphere":
                r, _ = self._sphere_renderer_world(s.mode, s.tessellation)
                mode, bg = s.mode, None
            else:
                r, mode = self.object_renderer(), "phong"
                black = r.render(Material(Lambert(0.0), ambient=0.0), [env], mode=mode, form=s.form)
                bg = np.asarray(black)
            n = np.asarray(r.sample_normals(mode), dtype=np.float64)
            v = np.broadcast_to(np.asarray(r.sample_view(mode)[0], dtype=np.float64), n.shape)
            key = np.asarray(r.render(key_only, self.world_lights(), mode=mode, form=s.form, terms=s.terms))
            targets.append(_Target(name, r, mode, key, bg, slice(start, start + len(n))))
            normals.append(n)
            views_.append(v)
            start += len(n)
        brdf = s.brdf(tuple(t for t in s.terms if t in ("diffuse", "specular")))
        self.refinement = Refinement(brdf, env.environment, np.concatenate(normals), np.concatenate(views_))
        self._targets = targets

    @property
    def refining(self) -> bool:
        """Whether the reference has passes left to add."""
        return self.refinement is not None and not self.refinement.done

    def refine(self, budget=0.04) -> set[str]:
        """Add reference passes for about ``budget`` seconds and re-compose the images it refines.

        Parameters
        ----------
        budget : float
            Seconds of Monte-Carlo work (a pass at least).

        Returns
        -------
        set of str
            The views updated (``"sphere"``, ``"object"``), empty when there is nothing to refine.
        """
        if not self.refining:
            return set()
        ref = self.refinement
        ref.step(budget)
        value = ref.value
        s = self.state
        scale = math.pi if s.form == "classic" else 1.0
        from .views import SphereView

        for t in self._targets:
            env_img = np.asarray(t.renderer.spread(t.mode, (value[t.rows] * scale).astype(np.float32)))
            img = t.key_image + env_img
            cov = t.renderer.gbuffer.coverage
            if t.background is not None:
                img = np.where(cov[..., None], img, t.background)
            if t.name == "sphere":
                rgb8, clipped = encode8(img, cov, s.exposure)
                old = self.views["sphere"]
                self.views["sphere"] = SphereView(img, rgb8, cov, old.mode, old.geometry, clipped,
                                                  auto_exposure=old.auto_exposure)  # fmt: skip
            else:
                self.views["object"] = self._object_record(img, cov, "reference")
        return {t.name for t in self._targets}

    def refine_caption(self) -> str:
        """``"reference: N spp, ±x %"`` (median relative standard error), or ``""`` without a reference."""
        ref = self.refinement
        if ref is None:
            return ""
        spp = ref.samples
        if spp == 0:
            return "reference: starting (dominant lights shown)"
        rel = ref.relative_error()
        err = f"±{100 * rel:.2g} %" if math.isfinite(rel) else "± ?"
        per_pass = 1e3 * ref.seconds / max(ref.passes, 1)
        return f"reference: {spp} spp, {err} ({per_pass:.0f} ms a pass){'  done' if ref.done else ''}"


def _as_4x4(m3):
    m = np.eye(4)
    m[:3, :3] = m3
    return m

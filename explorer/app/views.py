r"""Every view's data from the engine: :class:`ExplorerModel` and the view records it fills.

Nothing here imports PyVista or Matplotlib, so the whole logic of the window can
be driven and checked without a display (the controls are
:class:`~explorer.app.state.AppState`):

* :class:`ExplorerModel` — owns the engine's renderers (geometry buffers are
  rasterized once and re-shaded on every change) and computes the data of every
  view: the lit sphere, the coarse sphere lit per vertex and per pixel, the scan
  line profile with its Mach-band metric, the 3D lobe, the polar slice, the
  angle curves, the half/difference image and the directional albedo readout
  (with its error and an "unconverged" flag above 2 %).  :meth:`ExplorerModel.update`
  recomputes only the views whose inputs changed and returns their names; with
  ``only=LIVE_VIEWS`` (a slider being dragged) it recomputes the images and
  keeps the other stale views in ``pending`` for the next full update.

Frames.  The viewer looks down ``−z`` at a unit sphere at the origin: image
right is ``+x``, image up ``+y``, and ``+z`` points at the viewer.  The light's
*elevation* is its angle above the image plane (90° = from the viewer, 0° =
from the side, negative = from behind) and its *azimuth* turns in the image
plane from ``+x`` toward ``+y`` (135° = upper left).  The direction is
:func:`lighting.vec.direction_from_elevation` with ``+z`` as "up" (exact at the
horizon: elevation 0 is ``z = 0``), so the slides' "Lambertian sphere from
several lighting angles" is one drag of the elevation.  The BRDF views use the
local frame of the sphere point that faces the viewer (``n = +z``), so their
incident direction is the light seen from that point; every one of them builds
it through :func:`lighting.vec.spherical_direction`, so a light on or below the
horizon reflects nothing in all of them, and they all sample the lobe's peak
(:func:`lighting.analysis.lobe_peak`), so they report the same peak.

Example
-------
>>> state = AppState(model="phong", shininess=20.0, elevation=60.0)
>>> model = ExplorerModel(state, sphere_size=48, mesh_size=48, lobe_resolution=8)
>>> sorted(model.update())
['albedo', 'coarse', 'halfdiff', 'lobe', 'polar', 'profile', 'sphere', 'theta_d', 'theta_h', 'theta_v']
>>> state.azimuth = 10.0  # turning the light about the view axis: the BRDF plots stay
>>> sorted(model.update())
['coarse', 'profile', 'sphere']
>>> state.elevation = 30.0  # a new incident angle: the plots that depend on it follow
>>> sorted(model.update())
['albedo', 'coarse', 'lobe', 'polar', 'profile', 'sphere', 'theta_h', 'theta_v']
>>> state.shininess = 80.0  # while a slider is dragged: the images at once, the rest on release
>>> sorted(model.update(only=LIVE_VIEWS)), sorted(model.pending)
(['coarse', 'sphere'], ['albedo', 'halfdiff', 'lobe', 'polar', 'profile', 'theta_d', 'theta_h', 'theta_v'])
>>> sorted(model.update()), model.pending
(['albedo', 'halfdiff', 'lobe', 'polar', 'profile', 'theta_d', 'theta_h', 'theta_v'], set())
>>> state.shininess = -1
Traceback (most recent call last):
...
ValueError: shininess must be a number in [0, inf); got -1
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from lighting.analysis import (
    edge_jump_metric,
    half_diff_image,
    lobe_mesh,
    reciprocity_pair,
    scanline_profile,
    theta_d_curve,
    theta_h_curve,
    theta_v_curve,
)
from lighting.analysis.machband import LUMA
from lighting.integrate import UNCONVERGED_RELATIVE_ERROR, directional_albedo
from lighting.models import BRDFFlags
from lighting.render import AnalyticSphere, Renderer, needs_tangents, sphere_camera, uv_sphere
from lighting.shading import Material, shade
from lighting.vec import spherical_direction

from .comparing import AlbedoCurveView, CompareMixin, Overlay
from .encode import encode8
from .environment import ENV_FIELDS, EnvironmentMixin, ObjectView
from .split import split_angle, split_mask, split_render
from .state import ALBEDO_SAMPLES, AppState

__all__ = [
    "VIEWS",
    "LIVE_VIEWS",
    "split_angle",
    "split_mask",
    "split_render",
    "VIEW_DEPENDENCIES",
    "ExplorerModel",
    "SphereView",
    "CoarseView",
    "ProfileView",
    "LobeView",
    "PolarView",
    "CurveView",
    "HalfDiffView",
    "AlbedoView",
    "AlbedoCurveView",
    "ObjectView",
    "Overlay",
]


# =============================================================================== views
@dataclass(frozen=True, eq=False)
class SphereView:
    """The lit sphere: linear image, its 8-bit sRGB encoding and coverage.

    ``geometry`` is ``"exact sphere"`` (ray-cast, per pixel) in Phong mode and
    ``"<n> triangles"`` (the coarse sphere) in flat and Gouraud mode.
    """

    image: np.ndarray  # (H, W, 3) linear
    rgb8: np.ndarray  # (H, W, 3) uint8 sRGB
    coverage: np.ndarray  # (H, W) bool
    mode: str
    geometry: str
    clipped: int  # pixels clipped by the encoding
    split: str = ""  # the label of the comparison entry on the other half ("" when not split)
    split_colour: str = ""
    #: The split's divider: its direction in the image (degrees from image right toward image up), through
    #: the centre; the current model is on the half to its counter-clockwise side (:func:`split_mask`).
    split_angle: float = 90.0
    #: Under an environment: the exposure (stops) at which at most 2 % of the sphere clips
    #: (:func:`~explorer.app.environment.auto_exposure`); None without one.
    auto_exposure: float | None = None

    @property
    def split_mask(self) -> np.ndarray:
        """``(H, W)`` bool: the pixels of the current model's half (:func:`split_mask` of :attr:`split_angle`)."""
        return split_mask(self.coverage.shape, self.split_angle)

    @cached_property
    def brightest(self) -> tuple[int, int]:
        """``(row, column)`` of the pixel of largest luminance."""
        y = self.image.astype(np.float64) @ LUMA
        k = int(np.argmax(y))
        return divmod(k, y.shape[1])


@dataclass(frozen=True, eq=False)
class CoarseView:
    """The coarse sphere, lit per vertex (Gouraud) and per pixel (Phong interpolation).

    The engine's Gouraud image (:attr:`gouraud`) is rendered when first asked for: the
    window draws the vertex colours, only the scan-line profile and its metric need it.
    """

    vertices: np.ndarray  # (V, 3)
    faces: np.ndarray  # (F, 3)
    vertex_colors: np.ndarray  # (V, 3) linear: the engine's lighting at each vertex
    vertex_rgb8: np.ndarray  # (V, 3) uint8 sRGB
    phong: np.ndarray  # (H, W, 3) linear, normals interpolated
    phong_rgb8: np.ndarray
    triangle_id: np.ndarray  # (H, W) int, -1 off the sphere
    coverage: np.ndarray  # (H, W) bool
    tessellation: int
    exposure: float
    render_gouraud: Callable[[], np.ndarray] = field(repr=False, default=None)

    @cached_property
    def gouraud(self) -> np.ndarray:
        """``(H, W, 3)`` linear: the engine's Gouraud image, colours interpolated (rendered once)."""
        return self.render_gouraud()

    @cached_property
    def gouraud_rgb8(self) -> np.ndarray:
        """The engine's Gouraud image, encoded (the window draws the vertex colours instead)."""
        return _encode(self.gouraud, self.coverage, self.exposure)[0]

    @property
    def n_triangles(self) -> int:
        """Triangles of the coarse sphere."""
        return len(self.faces)


@dataclass(frozen=True, eq=False)
class ProfileView:
    """Intensity along one scan line of the coarse sphere, Gouraud against Phong interpolation.

    ``x`` is the horizontal position of each pixel centre in sphere units
    (``−1 … 1``), ``y`` the height of the row; ``edges`` are the positions where
    the scan line crosses a triangle edge.  The metrics are
    :func:`lighting.analysis.machband.edge_jump_metric` over every twelfth row of each image.
    """

    row: int
    y: float
    x: np.ndarray
    gouraud: np.ndarray
    phong: np.ndarray
    gouraud_d2: np.ndarray  # second differences, at x[1:-1]
    phong_d2: np.ndarray
    edges: np.ndarray
    metric_gouraud: float
    metric_phong: float
    channel: str
    slope: float  # mean |ΔI| along the row (both curves): the scale of the second differences


@dataclass(frozen=True, eq=False)
class LobeView:
    """The 3D lobe, drawn with the light in the ``x``–``z`` plane on the ``−x`` side (mirror on ``+x``).

    ``vertices`` are scaled so the largest radius is 1; ``values`` are the plotted
    quantity (what the colours show) and ``peak`` its largest value.
    """

    vertices: np.ndarray
    faces: np.ndarray
    values: np.ndarray
    peak: float
    scale: float  # display units per plotted unit
    light: np.ndarray  # unit incident direction (local frame)
    mirror: np.ndarray
    peak_direction: np.ndarray
    below_horizon: bool
    spike: float = 0.0  # an ideal mirror's reflected fraction, drawn as a δ spike (in plotted units)
    spike_direction: np.ndarray | None = None
    lock: bool = False  # the retro-reflection lobe f_r(d, d)


@dataclass(frozen=True, eq=False)
class PolarView:
    """The polar slice in the plane of incidence: fixed light (swept view) and fixed view (swept light).

    ``angles`` are signed, negative on the light's side (see
    :func:`lighting.analysis.polar_slice`); ``theta_in`` is the incident polar
    angle (clamped to 90° when the light is below the horizon).
    """

    angles: np.ndarray
    light_fixed: np.ndarray
    view_fixed: np.ndarray
    view_angles: np.ndarray
    theta_in: float
    below_horizon: bool
    phi_deg: float = 180.0  # the plane's azimuth φ_l about the tangent t
    lock: bool = False  # the view follows the light: the retro-reflection slice
    spike: float = 0.0  # an ideal mirror's reflected fraction R(θ), drawn as a δ spike
    spike_angle: float = 0.0  # where the spike stands (signed angle of the slice)
    overlays: tuple = ()  # Overlay: the light-fixed slice of each shown comparison entry


@dataclass(frozen=True, eq=False)
class CurveView:
    """One angle curve: ``values`` against ``angles`` (rad), with ``markers`` (rad) to draw."""

    variable: str
    angles: np.ndarray
    values: np.ndarray
    markers: tuple
    params: dict
    overlays: tuple = ()  # Overlay: the same curve of each shown comparison entry


@dataclass(frozen=True, eq=False)
class HalfDiffView:
    """The BRDF over ``(θ_h, θ_d)`` at ``φ_d = 90°``: rows θ_d, columns θ_h; ``marker`` = (θ_h, θ_d) of the mirror."""

    theta_h: np.ndarray
    theta_d: np.ndarray
    values: np.ndarray
    peak: float
    marker: tuple


@dataclass(frozen=True, eq=False)
class AlbedoView:
    """The directional albedo ``ρ(θ_v) = ∫ f_r(v, l) (n·l) dω_l`` of the plotted BRDF, with its error.

    ``theta_v`` is the fixed view of the polar panel's dashed slice (``θ_v = θ_l``, 90° when the
    light is below the horizon, where ρ is 0).  ``value`` and ``error`` are the plot channel's
    (luminance: the Rec. 709 weights of the RGB values and errors); ``unconverged`` flags a
    relative error above 2 % (:attr:`lighting.integrate.Estimate.unconverged`), as the accuracy
    report does.  ``rgb`` and ``rgb_error`` are the whole estimate.
    """

    theta_v: float
    value: float
    error: float
    relative_error: float
    unconverged: bool
    rgb: np.ndarray
    rgb_error: np.ndarray
    method: str
    samples: int
    curves: tuple = ()  # AlbedoCurveView: ρ(θ_v) of the current model and each shown entry (albedo panel)

    @property
    def above_one(self) -> bool:
        """Whether the albedo exceeds 1 beyond its error (``value − 2·error > 1``): more light out than in.

        >>> AlbedoView(0.0, 1.365, 3e-8, 2e-8, False, None, None, "quadrature", 4096).above_one
        True
        >>> AlbedoView(0.0, 1.01, 0.01, 0.01, False, None, None, "quadrature", 4096).above_one  # within 2σ
        False
        """
        return self.value - 2.0 * self.error > 1.0

    @property
    def channels_above_one(self) -> tuple[str, ...]:
        """The RGB channels (``"r"``, ``"g"``, ``"b"``) whose albedo exceeds 1 beyond twice its error."""
        if self.rgb is None:
            return ()
        rgb = np.broadcast_to(np.asarray(self.rgb, dtype=np.float64), (3,))
        err = np.broadcast_to(np.asarray(self.rgb_error if self.rgb_error is not None else 0.0, dtype=np.float64),
                              (3,))  # fmt: skip
        return tuple(c for c, v, e in zip("rgb", rgb, err, strict=True) if v - 2.0 * e > 1.0)


#: ``params``: the current model's parameters (:attr:`AppState.params`).
MATERIAL_FIELDS = frozenset({"model", "kd", "color", "params"})
LIGHT_FIELDS = frozenset(
    {"light", "elevation", "azimuth", "intensity", "light_color", "ambient", "distance", "attenuation", "cutoff"}
    | {"spot_exponent", "scene_lights"}
)
#: Pseudo-field: the incident polar angle θ_l at the facing point.  The BRDF views depend on it alone
#: (isotropic models; the plots are drawn in the plane of incidence), so turning the light about the
#: viewing axis (azimuth) re-shades the images but leaves the plots as they are.
INCIDENT_FIELDS = frozenset({"incidence"})
#: The BRDF views' own frame: the light's azimuth φ_l about the tangent t, and the view lock.
FRAME_FIELDS = frozenset({"phi", "lock"})
PLOT_FIELDS = frozenset({"channel", "log", "times_cos"})
SHADING_FIELDS = MATERIAL_FIELDS | LIGHT_FIELDS | {"form", "terms", "exposure", "tessellation"}
#: Pseudo-field: the shown entries of the comparison list (their keys, colours and labels).
COMPARE_FIELDS = frozenset({"compare"})

#: Which controls each view depends on.
VIEW_DEPENDENCIES = {
    "sphere": SHADING_FIELDS | {"mode", "split_target", "reference"} | ENV_FIELDS,  # split_target: the entry on
    # the split sphere's right
    "coarse": SHADING_FIELDS,
    "profile": SHADING_FIELDS | {"scanline", "channel"},
    "lobe": MATERIAL_FIELDS | INCIDENT_FIELDS | FRAME_FIELDS | PLOT_FIELDS | {"terms"},
    "polar": MATERIAL_FIELDS | INCIDENT_FIELDS | FRAME_FIELDS | PLOT_FIELDS | {"terms"} | COMPARE_FIELDS,
    "theta_v": MATERIAL_FIELDS | INCIDENT_FIELDS | {"phi"} | PLOT_FIELDS | {"terms"} | COMPARE_FIELDS,
    "theta_h": MATERIAL_FIELDS | INCIDENT_FIELDS | {"phi"} | PLOT_FIELDS | {"terms"} | COMPARE_FIELDS,
    "theta_d": MATERIAL_FIELDS | {"phi"} | PLOT_FIELDS | {"terms"} | COMPARE_FIELDS,
    "halfdiff": MATERIAL_FIELDS | {"phi"} | PLOT_FIELDS | {"terms"},
    "albedo": MATERIAL_FIELDS | INCIDENT_FIELDS | {"terms", "channel", "panel"} | COMPARE_FIELDS,
}
#: The lit object (the 3D panel's other face) depends on these; it is no member of :data:`VIEWS`: it is
#: made only while the panel shows it (``view3d = "object"``), and then updated like the others.
OBJECT_FIELDS = MATERIAL_FIELDS | LIGHT_FIELDS | {"form", "terms", "exposure", "reference", "view3d"} | ENV_FIELDS
VIEWS = tuple(VIEW_DEPENDENCIES)
#: The views that follow a slider while it is dragged: the engine's images, cheap and where the eye
#: is.  The scan-line profile, the lobe and the plots wait for the release (``update(only=...)``).
LIVE_VIEWS = frozenset({"sphere", "coarse"})


def _delta_height(brdf, cos_theta: float, state) -> float:
    """The reflected fraction ``R(θ)`` of the delta parts (ideal mirrors) of ``brdf``, in the plotted channel.

    A Dirac delta has no height to plot: ``eval`` is 0 everywhere, and all it reflects, the fraction
    ``brdf.reflectance(cos θ)`` of the incident light, leaves in the one mirror direction.  The views draw
    that fraction as a spike (``log10(1 + R)`` with the log option); 0 for a model without a delta part.
    """
    parts = [p for p in brdf.parts if BRDFFlags.DELTA in p.flags]
    if not parts or not cos_theta > 0:
        return 0.0
    rgb = sum(np.asarray(p.reflectance(float(cos_theta)), dtype=np.float64).reshape(-1) for p in parts)
    rgb = np.broadcast_to(rgb, (3,))
    value = float(rgb @ LUMA) if state.channel == "luminance" else float(rgb["rgb".index(state.channel)])
    return math.log1p(value) / math.log(10.0) if state.log else value


def _encode(image, coverage, exposure):
    return encode8(image, coverage, exposure)


def _coarse_camera(size: int):
    # The same framing as the lit sphere's: orthographic from +z, the unit sphere filling 1/1.08 of the height.
    return sphere_camera(size)


class ExplorerModel(CompareMixin, EnvironmentMixin):
    """Computes every view of the explorer from the engine, recomputing only what a change affects.

    Parameters
    ----------
    state : AppState, optional
        The controls (a fresh default state if omitted); the model reads it on
        every :meth:`update`, so the window changes ``model.state`` and calls
        ``update()``.
    sphere_size : int
        Pixels (width and height) of the lit sphere image.
    mesh_size : int
        Pixels of the coarse sphere images.
    lobe_resolution : int
        Rings of the lobe mesh (:func:`lighting.analysis.lobe_mesh`).
    dtype : float32 or float64
        Shading precision (float32: faster, relative error of a few 1e-7).
    compare : explorer.compare.BRDFList, optional
        The comparison list (default: an empty one of :data:`~explorer.app.state.MAX_ENTRIES`);
        see :mod:`explorer.app.comparing` for what the views draw of it.
    object_size : (int, int)
        Width and height in pixels of the lit object's image.
    mesh : path or TriangleMesh, optional
        The lit object's mesh or its file (:func:`lighting.render.mesh.load_mesh`; default: a generated blob).
    environment_file : path or (path, Environment), optional
        The environment of the ``"file"`` choice (:func:`lighting.lights.load_environment`; a pair: already read).

    Attributes
    ----------
    views : dict
        ``"sphere"`` :class:`SphereView`, ``"coarse"`` :class:`CoarseView`,
        ``"profile"`` :class:`ProfileView`, ``"lobe"`` :class:`LobeView`, ``"polar"``
        :class:`PolarView`, ``"theta_v"``, ``"theta_h"``, ``"theta_d"``
        :class:`CurveView`, ``"halfdiff"`` :class:`HalfDiffView`, ``"albedo"`` :class:`AlbedoView`,
        ``"object"`` :class:`~explorer.app.environment.ObjectView` (once the 3D panel shows it).
    compare : explorer.compare.BRDFList
        The comparison list; after changing it, :meth:`update` redraws what shows it.
    """

    def __init__(self, state=None, *, sphere_size=360, mesh_size=256, lobe_resolution=40, dtype=np.float32,
                 compare=None, object_size=(320, 224), mesh=None, environment_file=None):  # fmt: skip
        self.state = state if state is not None else AppState()
        self._init_compare(compare)
        for name, v in (("sphere_size", sphere_size), ("mesh_size", mesh_size)):
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 16 <= v <= 4096:
                raise ValueError(f"{name} must be an integer in [16, 4096]; got {v!r}")
        self.sphere_size, self.mesh_size = int(sphere_size), int(mesh_size)
        self.lobe_resolution = int(lobe_resolution)
        self.dtype = dtype
        self.views: dict = {}
        #: Views whose controls changed but which an ``update(only=...)`` left for later.
        self.pending: set[str] = set()
        #: Views an ``update(only=...)`` made by a cheaper method for the drag (an environment's split sum): current
        #: for what they show, made again by the accurate method at the next full update.
        self.provisional: set[str] = set()
        self._snapshot: dict | None = None
        self._sphere = Renderer(AnalyticSphere(), sphere_camera(self.sphere_size), dtype=dtype)
        self._meshes: dict = {}
        self._renderers: dict = {}
        self._init_environment(object_size=object_size, mesh=mesh, environment_file=environment_file)

    # ------------------------------------------------------------------ caches
    def mesh(self, tessellation: int):
        """The coarse UV sphere with ``tessellation`` bands and twice as many sectors (cached).

        Parameters
        ----------
        tessellation : int
            Latitude bands.

        Returns
        -------
        Mesh
            The UV sphere.
        """
        if tessellation not in self._meshes:
            self._meshes[tessellation] = uv_sphere(tessellation, 2 * tessellation)
        return self._meshes[tessellation]

    def mesh_renderer(self, tessellation: int, size: int) -> Renderer:
        """A renderer of the coarse sphere at ``size`` pixels; rasterized once, kept for the last 12 used.

        Parameters
        ----------
        tessellation : int
            Latitude bands of the coarse sphere.
        size : int
            Image width and height in pixels.

        Returns
        -------
        Renderer
            The renderer (its geometry buffers rasterized once).
        """
        key = (tessellation, size)
        r = self._renderers.pop(key, None)
        if r is None:
            r = Renderer(self.mesh(tessellation), _coarse_camera(size), dtype=self.dtype)
        self._renderers[key] = r
        while len(self._renderers) > 12:
            self._renderers.pop(next(iter(self._renderers)))
        return r

    def is_rasterized(self, tessellation: int, size: int) -> bool:
        """Whether the renderer of that coarse sphere at that size is in the cache.

        Parameters
        ----------
        tessellation, size : int
            As :meth:`mesh_renderer`.

        Returns
        -------
        bool
            True when cached.
        """
        return (tessellation, size) in self._renderers

    @property
    def rasterizations(self) -> int:
        """Rasterizations (or ray casts) so far of the renderers in the cache."""
        return self._sphere.rasterizations + sum(r.rasterizations for r in self._renderers.values())

    # ------------------------------------------------------------------ updates
    def _inputs(self) -> dict:
        d = self.state.to_dict()
        d["params"] = tuple(self.state.params.items())  # the current model's: others' do not show
        d["incidence"] = round(self.state.theta_l, 12)
        d.update(self._compare_inputs())
        return d

    def changed_fields(self) -> set[str]:
        """Controls whose value differs from the last :meth:`update` (all of them before the first).

        Includes the pseudo-fields ``"incidence"`` when the incident polar angle changed, ``"compare"``
        when the shown entries of the comparison list did and ``"split_target"`` when the entry on the
        split sphere's right half did.

        Returns
        -------
        set of str
            Control names (and ``"incidence"``).
        """
        now = self._inputs()
        if self._snapshot is None:
            return set(now)
        return {k for k, v in now.items() if v != self._snapshot[k]}

    def stale_views(self, changed=None) -> set[str]:
        """Views that depend on the changed controls.

        Parameters
        ----------
        changed : collection of str, optional
            Changed controls (default: :meth:`changed_fields`).

        Returns
        -------
        set of str
            View names (every view before the first update).
        """
        changed = self.changed_fields() if changed is None else set(changed)
        views = {v for v, deps in VIEW_DEPENDENCIES.items() if deps & changed}
        if "sphere" in views and changed <= {"tessellation"} and self.state.mode == "phong":
            views.discard("sphere")  # the exact sphere has no tessellation
        if self._snapshot is None:
            views = set(VIEWS)
        if self.state.view3d == "object" and (changed & OBJECT_FIELDS or "object" not in self.views):
            views.add("object")
        return views

    def update(self, changed=None, *, only=None) -> set[str]:
        """Recompute the views whose controls changed since the last call; return their names.

        ``changed`` adds control names to treat as changed even if their values are
        equal.  ``only`` restricts the work to those views (a slider being dragged
        updates :data:`LIVE_VIEWS`): the other stale views are kept in :attr:`pending`
        and recomputed by the next call that includes them.  :meth:`refresh`
        recomputes everything.

        Parameters
        ----------
        changed : collection of str, optional
            Control names to treat as changed.
        only : collection of str, optional
            The views to recompute now (e.g. :data:`LIVE_VIEWS`).

        Returns
        -------
        set of str
            The names of the views recomputed.
        """
        diff = self.changed_fields() | set(changed or ())
        stale = self.stale_views(diff) | self.pending | (self.provisional if only is None else set())
        views = stale if only is None else stale & set(only)
        if "profile" in views and "coarse" in stale:
            views.add("coarse")  # the profile is read off the coarse sphere's images
        self.pending = stale - views
        self.provisional -= views  # a view made for a drag adds itself back (EnvironmentMixin._shown_live)
        self.live_update = only is not None
        s = self.state
        if views & {"sphere", "coarse", "profile"}:
            material, lights = s.material(), s.lights()
            if "sphere" in views:
                self.views["sphere"] = self._sphere_view(material, lights)
            if "coarse" in views:
                self.views["coarse"] = self._coarse_view(material, lights)
            if "profile" in views:
                self.views["profile"] = self._profile_view()
        if "object" in views:
            self.views["object"] = self._object_view(s.material())
        if views - {"sphere", "coarse", "profile"}:
            brdf = s.plot_brdf()
            opts = s.plot_options()
            theta = min(s.theta_l, 0.5 * math.pi)
            below = s.theta_l >= 0.5 * math.pi
            phi = math.radians(s.phi)
            if "lobe" in views:
                self.views["lobe"] = self._lobe_view(brdf, theta, below, opts)
            if "polar" in views:
                self.views["polar"] = self._polar_view(brdf, theta, below, opts)
            if "theta_v" in views:
                c = theta_v_curve(brdf, theta, phi_l=phi, n=181, **opts)
                self.views["theta_v"] = CurveView("theta_v", c.angles, c.values, (-theta, theta), c.params,
                                                  self._overlays("theta_v", theta, opts))  # fmt: skip
            if "theta_h" in views:
                c = theta_h_curve(brdf, theta_d=theta, phi_h=phi, n=181, **opts)
                self.views["theta_h"] = CurveView("theta_h", c.angles, c.values, (0.0,), c.params,
                                                  self._overlays("theta_h", theta, opts))  # fmt: skip
            if "theta_d" in views:
                c = theta_d_curve(brdf, theta_h=0.0, phi_h=phi, n=181, **opts)
                self.views["theta_d"] = CurveView("theta_d", c.angles, c.values, (theta,), c.params,
                                                  self._overlays("theta_d", theta, opts))  # fmt: skip
            elif "theta_d" in self.views and "theta_v" in views:
                old = self.views["theta_d"]
                self.views["theta_d"] = CurveView("theta_d", old.angles, old.values, (theta,), old.params,
                                                  old.overlays)  # fmt: skip
            if "halfdiff" in views:
                im = half_diff_image(brdf, n_h=91, n_d=91, phi_h=phi, **opts)
                peak = float(im.values.max())
                self.views["halfdiff"] = HalfDiffView(im.theta_h, im.theta_d, im.values, peak, (0.0, theta))
            elif "halfdiff" in self.views and "theta_v" in views:
                old = self.views["halfdiff"]
                self.views["halfdiff"] = HalfDiffView(old.theta_h, old.theta_d, old.values, old.peak, (0.0, theta))
            if "albedo" in views:
                self.views["albedo"] = self._albedo_view(brdf, theta)
        self._snapshot = self._inputs()
        self._restart_refinement(views)
        return views

    def refresh(self) -> set[str]:
        """Recompute every view.

        Returns
        -------
        set of str
            The names of every view (:data:`VIEWS`).
        """
        self._snapshot = None
        self.pending, self.provisional = set(), set()
        return self.update()

    def compute(self) -> dict:
        """Compute every view and return them (:meth:`refresh`, then :attr:`views`).

        Returns
        -------
        dict
            View name → view data.
        """
        self.refresh()
        return self.views

    # ------------------------------------------------------------------ view builders
    def _sphere_view(self, material, lights) -> SphereView:
        s = self.state
        if self.environment_active:
            return self._env_sphere_view(material)
        if s.mode == "phong":
            r, geometry = self._sphere, "exact sphere"
        else:
            r = self.mesh_renderer(s.tessellation, self.sphere_size)
            geometry = f"{r.geometry.n_triangles} triangles"
        img = r.render(material, lights, mode=s.mode, form=s.form, terms=s.terms)
        cov = r.gbuffer.coverage
        target = self.split_target() if s.split else None
        if target is not None:
            # The same lights, ambient coefficient, form and terms: only the BRDF differs between the halves.
            img = split_render(r, img, Material(target.brdf, ambient=s.diffuse_albedo), lights, s)
        rgb8, clipped = _encode(img, cov, s.exposure)
        if target is None:
            return SphereView(img, rgb8, cov, s.mode, geometry, clipped)
        return SphereView(img, rgb8, cov, s.mode, geometry, clipped, target.label, target.colour, split_angle(s))

    def _coarse_view(self, material, lights) -> CoarseView:
        s = self.state
        mesh = self.mesh(s.tessellation)
        r = self.mesh_renderer(s.tessellation, self.mesh_size)
        opts = {"form": s.form, "terms": s.terms}
        # The engine's lighting at every vertex: what Gouraud shading interpolates (the renderer's
        # Gouraud image interpolates exactly these colours; orthographic view: v = +z everywhere).
        # Anisotropic models are oriented by the mesh's tangents (along φ), as in the renderer's images.
        tangents = mesh.tangents if needs_tangents(material) else None
        vertex = shade(mesh.vertices, mesh.normals, material, lights, view_dir=(0.0, 0.0, 1.0), tangents=tangents,
                       **opts)  # fmt: skip
        phong = r.render(material, lights, mode="phong", **opts)
        vertex8, _ = encode8(vertex[None], exposure=s.exposure)
        gb = r.gbuffer
        p8, _ = _encode(phong, gb.coverage, s.exposure)
        return CoarseView(
            mesh.vertices, mesh.faces, vertex, vertex8[0], phong, p8, gb.triangle_id, gb.coverage,
            s.tessellation, s.exposure, lambda: r.render(material, lights, mode="gouraud", **opts),
        )  # fmt: skip

    def _profile_view(self) -> ProfileView:
        s = self.state
        c = self.views["coarse"]
        h, w = c.triangle_id.shape
        row = min(h - 1, max(0, int(s.scanline * h)))
        ch = s.channel
        pg = scanline_profile(c.gouraud, row, coverage=c.coverage, channel=ch)
        pp = scanline_profile(c.phong, row, coverage=c.coverage, channel=ch)
        unit = 2.0 * 1.08 / h  # sphere units per pixel (sphere_camera's framing)
        x = (pg.x + 0.5 - 0.5 * w) * unit
        t = c.triangle_id[row, pg.x]
        cross = np.flatnonzero(t[:-1] != t[1:])
        edges = (pg.x[cross] + 1.0 - 0.5 * w) * unit
        rows = range(0, h, 12)
        mg = edge_jump_metric(c.gouraud, c.triangle_id, rows=rows, channel=ch)
        mp = edge_jump_metric(c.phong, c.triangle_id, rows=rows, channel=ch)
        y = (0.5 * h - row - 0.5) * unit
        slope = float(np.mean(np.abs(np.concatenate([pg.d1, pp.d1])))) if pg.d1.size else 0.0
        return ProfileView(row, y, x, pg.intensity, pp.intensity, pg.d2, pp.d2, edges, mg, mp, ch, slope)

    def _lobe_view(self, brdf, theta, below, opts) -> LobeView:
        s = self.state
        # The light at azimuth φ_l about t = +x (180°: on the −x side), exactly on the horizon at π/2.
        l_plot = spherical_direction(theta, math.radians(s.phi))
        m = lobe_mesh(brdf, l_plot, resolution=self.lobe_resolution, cosine=s.times_cos, channel=s.channel,
                      lock=s.lock)  # fmt: skip
        values = m.values.astype(np.float64)
        mirror = np.array([-l_plot[0], -l_plot[1], l_plot[2]])
        spike = _delta_height(brdf, 1.0 if s.lock else l_plot[2], s) if not below or s.lock else 0.0
        if s.log:
            values = np.log1p(values) / math.log(10.0)
        peak = float(values.max()) if values.size else 0.0
        top = max(peak, spike)
        scale = 1.0 / top if top > 0 else 1.0
        vertices = (values * scale)[:, None] * m.directions.astype(np.float64)
        spike_dir = np.array([0.0, 0.0, 1.0]) if s.lock else mirror
        return LobeView(vertices, m.faces, values, peak, scale, l_plot, mirror, m.peak.astype(np.float64), below,
                        spike, spike_dir, s.lock)  # fmt: skip

    def _albedo_view(self, brdf, theta) -> AlbedoView:
        # Quadrature on the lobe's nodes: deterministic, with an error estimate.
        # Not a live view: computed when the plots follow, on a slider's release, never during a drag.
        est = directional_albedo(brdf, theta, samples=ALBEDO_SAMPLES, method="quadrature", return_error=True)
        rgb = np.asarray(est.value, dtype=np.float64)
        err = np.abs(np.asarray(est.error, dtype=np.float64))
        ch = self.state.channel
        if ch == "luminance":
            value, error = float(rgb @ LUMA), float(err @ LUMA)  # errors add at worst linearly
        else:
            k = "rgb".index(ch)
            value, error = float(rgb[k]), float(err[k])
        rel = error / abs(value) if value != 0 else (math.inf if error > 0 else 0.0)
        curves = self._albedo_curves(brdf) if self.state.panel == "albedo" else ()
        return AlbedoView(theta, value, error, rel, bool(rel > UNCONVERGED_RELATIVE_ERROR), rgb, err, est.method,
                          int(est.samples), curves)  # fmt: skip

    def _polar_view(self, brdf, theta, below, opts) -> PolarView:
        s = self.state
        phi = math.radians(s.phi)
        a, b = reciprocity_pair(brdf, theta, n=361, phi_in=phi, lock=s.lock, **opts)
        spike = _delta_height(brdf, 1.0 if s.lock else math.cos(theta), s) if not below or s.lock else 0.0
        return PolarView(a.angles, a.values, b.values, b.angles, theta, below, s.phi, s.lock, spike,
                         0.0 if s.lock else theta, self._overlays("polar", theta, opts))  # fmt: skip

"""The desktop explorer: one PyVista window of linked views; every colour on screen comes from the engine.

Panels (see ``docs/explorer.md``)::

    +--------------+--------------+--------------+------------------+
    | lit sphere   | coarse sphere| coarse sphere| scan-line profile|
    | (engine)     | Gouraud      | Phong interp.| (Matplotlib)     |
    +--------------+--------------+--------------+------------------+
    | 3D BRDF lobe | polar slice  | angle curves and half/diff image|
    +--------------+--------------+---------------------------------+
    | controls: light | point/spot | material | shading | terms, plots|
    +---------------------------------------------------------------+

How the engine's colours reach the screen, with VTK lighting off everywhere:

* per-pixel images (lit sphere, Phong panel) are the engine's images encoded to
  8-bit sRGB and drawn as textures on planes facing an orthographic camera;
* the Gouraud panel is the coarse mesh with the engine's *vertex colours* as RGB
  scalars, interpolated across each triangle by VTK with lighting off — VTK's own
  ``gouraud`` interpolation would light per pixel whenever point normals exist;
* the lobe is coloured by its BRDF value through a perceptual colour map;
* the plots are Matplotlib figures embedded with ``pyvista.ChartMPL`` and updated
  by blitting (:mod:`explorer.app_plots`).

A frame must follow a slider within 50 ms with software OpenGL, so while a slider
is dragged only the engine's images and the light arrow follow each move (the
scan-line profile, the lobe and the plots wait for the release, or for the slider
to rest :data:`IDLE_MS`), and VTK redraws only the panels that changed.

:class:`ExplorerApp` builds the window around an :class:`~explorer.app_state.ExplorerModel`;
its handlers (:meth:`ExplorerApp.set_control`, :meth:`ExplorerApp.on_slider`,
:meth:`ExplorerApp.on_key`, :meth:`ExplorerApp.flush`) are what the widgets call, and
what the tests call.  :func:`benchmark_handlers` times them.  :func:`main` is the
``lighting-explorer`` command (no sub-command, or ``explore``).
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import sys
import time

import numpy as np

from lighting._numeric import check_range

from .app_state import (
    ATTENUATIONS,
    CHANNEL_LABELS,
    CHANNELS,
    CONTROLS,
    FORMS,
    LIGHT_COLOURS,
    LIGHT_TYPES,
    LIVE_VIEWS,
    MODEL_LABELS,
    MODELS,
    NDFS,
    TERM_NAMES,
    AppState,
    ExplorerModel,
)

__all__ = [
    "DEFAULT_WINDOW_SIZE",
    "IDLE_MS",
    "ExplorerApp",
    "albedo_caption",
    "benchmark_handlers",
    "build_parser",
    "has_display",
    "display_problem",
    "no_display_message",
    "main",
]

DEFAULT_WINDOW_SIZE = (1280, 768)
#: Window height for which the font sizes below are given; other sizes scale them (and the plots' dpi).
DESIGN_HEIGHT = 768
BACKGROUND = (0.105, 0.11, 0.125)
TEXT = (0.91, 0.925, 0.94)
MUTED = (0.55, 0.57, 0.6)
ACCENT = (1.0, 0.88, 0.4)
SCANLINE = (1.0, 0.42, 0.42)
HALF = 1.08  # half-width of the engine images in sphere units (lighting.render.sphere.sphere_camera's margin)
SPHERE_SCALE = 1.45  # half-height of the lit sphere panel's view, sphere units (room for the light arrow)
COARSE_SCALE = 1.16
LOBE_SCALE = 1.0
#: While a slider is dragged only the lit sphere and the coarse spheres follow; the profile, the lobe
#: and the plots follow on release, or once the slider has rested this long (milliseconds).
IDLE_MS = 150

# Panels: (row, column) of the subplot grid.
SPHERE, GOURAUD, PHONG, PROFILE = (0, 0), (0, 1), (0, 2), (0, 3)
LOBE, POLAR, ANGLES, CONTROLS_PANEL = (1, 0), (1, 1), (1, 2), (2, 0)
#: The views each panel shows.  During a drag VTK redraws only the panels whose views changed (and
#: the controls); the others keep last frame's pixels, which are still right.
PANEL_VIEWS = {
    SPHERE: frozenset({"sphere"}),
    GOURAUD: frozenset({"coarse", "profile"}),  # the red scan line follows the profile
    PHONG: frozenset({"coarse", "profile"}),
    PROFILE: frozenset({"profile"}),
    LOBE: frozenset({"lobe"}),
    POLAR: frozenset({"polar"}),
    ANGLES: frozenset({"theta_v", "theta_h", "theta_d", "halfdiff"}),
}

def no_display_message(problem: str) -> str:
    """The one line the command prints when no window can open: why, and how to get images instead."""
    return (
        f"lighting-explorer: {problem}, so no window can open; for images instead run "
        "`lighting-explorer --off-screen --screenshot out.png` (any control options work too) "
        "or `lighting-explorer sphere -o sphere.png`"
    )


NO_DISPLAY_MESSAGE = no_display_message("no display (DISPLAY/WAYLAND_DISPLAY unset)")
#: Seconds to wait for an X server to accept a connection before saying that none answers.
DISPLAY_TIMEOUT = 2.0

HELP_TEXT = """ lighting-explorer: keys and mouse

 Drag the sliders below the views; click the boxes to switch plot options.
 Every colour on screen is computed by the engine (VTK lighting is off).

   h           show / hide this help
   s           save a screenshot of the window (PNG in the current folder)
   r           reset every control to its default
   m  /  M     next / previous reflectance model
   t           next light type (directional, point, spot, ambient)
   i           next shading mode of the lit sphere (flat, Gouraud, Phong)
   f           classic  I  /  physical radiance  I/π
   1  2  3     ambient / diffuse / specular term on or off
   c           next plot channel (luminance Y, R, G, B)
   l           plots: log10(1 + x) on or off
   n           plots: × n·l on or off
   e           triangle edges on the coarse spheres on or off
   Up / Down   move the scan line
   Left/Right  coarser / finer coarse sphere
   q           quit

 Mouse: rotate the 3D lobe with the left button, zoom with the wheel. """


def has_display() -> bool:
    """Whether a window can open: on Linux and BSD an X server must answer (see :func:`display_problem`)."""
    return display_problem() is None


def display_problem(timeout: float = DISPLAY_TIMEOUT) -> str | None:
    """Why no window can open, in a few words (``None`` when one can).

    On Linux and BSD the window is an X11 window (VTK's X render window), so ``DISPLAY`` must name
    an X server that answers: a ``DISPLAY`` where nobody listens made the window fail only after
    VTK had set everything up (3 s, no message of ours, exit status 0).  The server is asked as
    Xlib asks it, first its socket (``/tmp/.X11-unix/X<n>`` or TCP port ``6000 + n``, within
    ``timeout`` seconds), then ``XOpenDisplay`` (which also checks the X authority).  Without
    ``DISPLAY``, a Wayland session (``WAYLAND_DISPLAY``) is trusted.  Other systems: ``None``.
    """
    if not sys.platform.startswith(("linux", "freebsd", "openbsd", "netbsd")):
        return None
    display = os.environ.get("DISPLAY")
    if not display:
        return None if os.environ.get("WAYLAND_DISPLAY") else "no display (DISPLAY/WAYLAND_DISPLAY unset)"
    return _x_server_problem(display, timeout)


def _x_server_problem(display: str, timeout: float) -> str | None:
    import ctypes
    import socket
    import threading

    host, sep, rest = display.rpartition(":")
    number = rest.split(".")[0]
    if not sep or not number.isdigit():
        return f"DISPLAY={display!r} is not an X display name (such as :0 or host:0)"
    n = int(number)
    try:
        if host in ("", "unix"):
            path = f"/tmp/.X11-unix/X{n}"
            candidates = [path] + (["\0" + path] if sys.platform.startswith("linux") else [])  # Linux: abstract too
            for k, address in enumerate(candidates):
                with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as sock:
                    sock.settimeout(timeout)
                    try:
                        sock.connect(address)
                        break
                    except OSError:
                        if k == len(candidates) - 1:
                            raise
        else:
            socket.create_connection((host, 6000 + n), timeout=timeout).close()
    except OSError:
        return f"no X server answers at DISPLAY={display}"
    try:
        xlib = ctypes.CDLL("libX11.so.6")
    except OSError:  # the socket answered; without Xlib here the window will tell more
        return None
    xlib.XOpenDisplay.restype = ctypes.c_void_p
    xlib.XOpenDisplay.argtypes = [ctypes.c_char_p]
    xlib.XCloseDisplay.argtypes = [ctypes.c_void_p]
    # XOpenDisplay waits as long as the server is silent (a socket that accepts and never replies):
    # it runs in a daemon thread (ctypes releases the GIL), given ``timeout`` seconds.
    result = {}

    def opener():
        handle = xlib.XOpenDisplay(display.encode())
        result["handle"] = handle
        if handle:
            xlib.XCloseDisplay(handle)

    worker = threading.Thread(target=opener, name="lighting-explorer X probe", daemon=True)
    worker.start()
    worker.join(timeout)
    if "handle" not in result:
        return f"no X server answers at DISPLAY={display} (it accepted the connection, then said nothing)"
    if not result["handle"]:
        return f"the X server at DISPLAY={display} refused the connection (check its X authority, xauth)"
    return None


class _quiet_vtk:
    """Silence VTK's log below errors (off-screen without X, VTK warns once that it found no X server)."""

    def __init__(self, active: bool):
        self.active = active

    def __enter__(self):
        if self.active:
            from vtkmodules.vtkCommonCore import vtkLogger

            self.old = vtkLogger.GetCurrentVerbosityCutoff()
            vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_ERROR)
        return self

    def __exit__(self, *exc):
        if self.active:
            from vtkmodules.vtkCommonCore import vtkLogger

            vtkLogger.SetStderrVerbosity(self.old)
        return False


def albedo_caption(av) -> str:
    """The text of the albedo readout of an :class:`~explorer.app_state.AlbedoView`.

    >>> from explorer.app_state import AlbedoView
    >>> albedo_caption(AlbedoView(0.5, 0.8123, 2e-5, 2.5e-5, False, None, None, "quadrature", 4096))
    'albedo ρ(θ_v = 29°) = 0.8123 ± 2e-05'
    >>> albedo_caption(AlbedoView(0.5, 1.2, 0.05, 0.042, True, None, None, "quadrature", 4096))
    'albedo ρ(θ_v = 29°) = 1.2 ± 0.05  unconverged (4.2 % > 2 %)'
    """
    text = f"albedo ρ(θ_v = {math.degrees(av.theta_v):.0f}°) = {av.value:.4g} ± {av.error:.2g}"
    if av.unconverged:
        rel = f"{100 * av.relative_error:.2g} %" if math.isfinite(av.relative_error) else "no digit"
        text += f"  unconverged ({rel} > 2 %)"
    return text


def _font_file(name: str = "DejaVuSans.ttf") -> str | None:
    """A DejaVu font from Matplotlib's data: VTK's built-in fonts have no Greek letters (θ, Δ)."""
    try:
        import matplotlib

        path = os.path.join(matplotlib.get_data_path(), "fonts", "ttf", name)
    except ImportError:  # pragma: no cover - matplotlib is a dependency of the explorer
        return None
    return path if os.path.exists(path) else None


# =============================================================================== sliders
class SliderSpec:
    """One slider: which control, its range in slider units, and how to show the value.

    An integer control (``CONTROLS[name].kind == "int"``) spans its control's whole range unless
    told otherwise, and :meth:`from_slider` snaps the widget's float to the nearest integer.
    """

    def __init__(self, name, label, lo=None, hi=None, *, log=False, choices=None, fmt="{:.2f}", unit=""):
        self.name, self.label = name, label
        self.choices = tuple(choices) if choices is not None else None
        self.log = log
        control = CONTROLS.get(name)
        self.integer = control is not None and control.kind == "int"
        if self.choices is not None:
            lo, hi = 0.0, float(len(self.choices) - 1)
        elif self.integer:
            lo = control.lo if lo is None else lo
            hi = control.hi if hi is None else hi
        self.lo, self.hi = float(lo), float(hi)
        self.fmt, self.unit = fmt, unit

    def to_slider(self, value) -> float:
        if self.choices is not None:
            return float(self.choices.index(value)) if value in self.choices else 0.0
        if self.log:
            return min(max(math.log10(max(float(value), 10.0**self.lo)), self.lo), self.hi)
        return min(max(float(value), self.lo), self.hi)

    def from_slider(self, x: float):
        """The control value at slider position ``x`` (a float, as VTK reports it; clamped to the range).

        Choices and integer controls snap to the nearest allowed value (ties upward): a float from
        a widget is a position, not a user's error.
        """
        x = check_range(f"{self.name} slider position", x)
        x = min(max(x, self.lo), self.hi)
        if self.choices is not None:
            return self.choices[int(math.floor(x + 0.5))]
        if self.integer:
            return int(math.floor(x + 0.5))
        if self.log:
            return 10.0**x
        return x

    def title(self, value) -> str:
        if self.choices is not None:
            shown = _CHOICE_LABELS.get(self.name, {}).get(value, value)
            return f"{self.label}: {shown}"
        if self.log:
            v = float(value)
            text = f"{v:.3g}" if v < 1e5 else f"{v:.0e}"
        else:
            text = self.fmt.format(value)
        return f"{self.label} = {text}{self.unit}"


_CHOICE_LABELS = {
    "model": MODEL_LABELS,
    "channel": CHANNEL_LABELS,
    "mode": {"flat": "flat (per face)", "gouraud": "Gouraud (per vertex)", "phong": "Phong (per pixel)"},
    "form": {"classic": "classic I", "physical": "physical I/π"},
}

#: The control panel: five columns of sliders (top to bottom).
SLIDER_COLUMNS = (
    (
        "Light",
        (
            SliderSpec("light", "light", choices=LIGHT_TYPES),
            SliderSpec("elevation", "elevation", -90, 90, fmt="{:.0f}", unit="°"),
            SliderSpec("azimuth", "azimuth", -180, 180, fmt="{:.0f}", unit="°"),
            SliderSpec("intensity", "intensity", 0, 4, fmt="{:.2f}"),
            SliderSpec("light_color", "light colour", choices=tuple(LIGHT_COLOURS) + ("custom",)),
        ),
    ),
    (
        "Ambient, point and spot",
        (
            SliderSpec("ambient", "ambient I_a", 0, 1, fmt="{:.2f}"),
            SliderSpec("distance", "point/spot distance", 1.5, 12, fmt="{:.1f}"),
            SliderSpec("attenuation", "falloff", choices=tuple(ATTENUATIONS)),
            SliderSpec("cutoff", "spot cutoff", 0, 90, fmt="{:.0f}", unit="°"),
            SliderSpec("spot_exponent", "spot exponent", 0, 128, fmt="{:.0f}"),
        ),
    ),
    (
        "Material",
        (
            SliderSpec("model", "model", choices=MODELS),
            SliderSpec("kd", "k_d", 0, 1),
            SliderSpec("ks", "k_s", 0, 1),
            SliderSpec("shininess", "shininess e", 0, 6, log=True),
            SliderSpec("roughness", "roughness α (Cook-Torrance)", -4, 0, log=True),
        ),
    ),
    (
        "Shading",
        (
            SliderSpec("f0", "F0 (Cook-Torrance)", 0, 1),
            SliderSpec("mode", "lit sphere", choices=("flat", "gouraud", "phong")),
            SliderSpec("form", "form", choices=FORMS),
            SliderSpec("tessellation", "coarse sphere bands", fmt="{:.0f}"),  # the control's range, 3 … 64
            SliderSpec("exposure", "exposure", -4, 4, fmt="{:+.1f}", unit=" stops"),
        ),
    ),
    ("Terms and plots", (SliderSpec("channel", "plot channel", choices=CHANNELS),)),
)
SLIDERS = {spec.name: spec for _, column in SLIDER_COLUMNS for spec in column}
#: Check boxes of the "Plots" column: (key, label).
CHECKBOXES = (
    ("ambient", "ambient term"),
    ("diffuse", "diffuse term"),
    ("specular", "specular term"),
    ("log", "log10(1 + x)"),
    ("times_cos", "× n·l"),
)


def _light_colour_name(rgb) -> str:
    for name, c in LIGHT_COLOURS.items():
        if np.allclose(c, rgb):
            return name
    return "custom"


def _arrow_matrix(start, end) -> np.ndarray:
    """4×4 matrix taking the unit arrow (0,0,0)→(1,0,0) to ``start``→``end`` (uniform scale)."""
    start, end = np.asarray(start, float), np.asarray(end, float)
    d = end - start
    length = float(np.linalg.norm(d))
    if not length > 0:
        m = np.eye(4)
        m[:3, :3] *= 1e-9
        return m
    x = d / length
    helper = np.array([0.0, 0.0, 1.0]) if abs(x[2]) < 0.9 else np.array([0.0, 1.0, 0.0])
    y = np.cross(helper, x)
    y /= np.linalg.norm(y)
    z = np.cross(x, y)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2] = x * length, y * length, z * length
    m[:3, 3] = start
    return m


# =============================================================================== the window
class ExplorerApp:
    """The explorer window around an :class:`~explorer.app_state.ExplorerModel`.

    Parameters
    ----------
    state : AppState, optional
    window_size : (int, int)
        Window width and height in pixels (default 1280 × 768).
    off_screen : bool
        Render without a window (screenshots, tests); needs no display.
    sphere_size, mesh_size : int, optional
        Pixels of the engine images (default: about the size of their panels).
    """

    def __init__(self, state=None, *, window_size=DEFAULT_WINDOW_SIZE, off_screen=False, sphere_size=None,
                 mesh_size=None, lobe_resolution=40):  # fmt: skip
        import pyvista as pv

        self.pv = pv
        self.window_size = (int(window_size[0]), int(window_size[1]))
        w, h = self.window_size
        row_w, col_w = (1.16, 1.0, 0.72), (1.12, 1.0, 1.0, 1.05)
        self._row_frac = [x / sum(row_w) for x in row_w]
        self._col_frac = [x / sum(col_w) for x in col_w]
        # Engine images at about one texel per screen pixel of their panels.
        row0 = h * self._row_frac[0]
        if sphere_size is None:
            sphere_size = int(min(max(round(row0 * HALF / SPHERE_SCALE / 8) * 8, 128), 1024))
        if mesh_size is None:
            # 0.8 texel per pixel: the coarse images are drawn slightly magnified, to keep a slider move fast.
            mesh_size = int(min(max(round(0.8 * row0 * HALF / COARSE_SCALE / 8) * 8, 96), 1024))
        self.model = ExplorerModel(state, sphere_size=sphere_size, mesh_size=mesh_size, lobe_resolution=lobe_resolution)
        #: Text and plot scale: 1 at the default height, so every window size has the same layout.
        self.ui_scale = h / DESIGN_HEIGHT
        self.off_screen = bool(off_screen)
        self.font = _font_file()
        self.show_edges = True
        self._glyphs_placed = False
        self._building = True
        self._shown = False
        self._screenshot_count = 0
        self.last_screenshot = None
        self._idle_timer = None
        self._last_drag = 0.0
        self._changed_panels = set(PANEL_VIEWS)  # panels changed since the last frame
        with _quiet_vtk(self.off_screen and not has_display()):
            pl = self._make_plotter(row_w, col_w)
        pl.set_background(BACKGROUND)
        # Multisampling costs 3-4x the frame time with software OpenGL, and the engine's images need none.
        pl.ren_win.SetMultiSamples(0)
        self.plotter = pl
        self.sliders: dict = {}
        self.checkboxes: dict = {}
        self.captions: dict = {}
        self._build_sphere_panel()
        self._build_coarse_panels()
        self._build_lobe_panel()
        self._build_charts()
        self._build_controls()
        self._build_help()
        self._bind_keys()
        self._panel_renderers = {panel: self._renderer(panel) for panel in PANEL_VIEWS}
        pl.ren_win.AddObserver("EndEvent", self._after_render)
        self.refresh(render=False, force=True)
        self._building = False
        if self.off_screen:
            pl.show(auto_close=False)  # off-screen: renders once and returns, after which render() works

    def _make_plotter(self, row_w, col_w):
        return self.pv.Plotter(
            shape=(3, 4),
            groups=[(1, np.s_[2:]), (2, np.s_[:])],
            row_weights=row_w,
            col_weights=col_w,
            window_size=list(self.window_size),
            off_screen=self.off_screen,
            border=True,
            border_color=(0.22, 0.23, 0.26),
            border_width=1.0,
            lighting="none",
            title="lighting-explorer",
        )

    # ------------------------------------------------------------------ small helpers
    @property
    def state(self) -> AppState:
        return self.model.state

    def _renderer(self, panel):
        self.plotter.subplot(*panel)
        return self.plotter.renderer

    def _text(self, panel, key, text, x, y, *, size=11, color=TEXT, align="left", valign="top", bold=False):
        import vtk

        ren = self._renderer(panel)
        actor = vtk.vtkTextActor()
        actor.SetInput(text)
        prop = actor.GetTextProperty()
        prop.SetFontSize(self._font_px(size))
        prop.SetColor(*color)
        prop.SetBold(bold)
        if self.font:
            prop.SetFontFamily(vtk.VTK_FONT_FILE)
            prop.SetFontFile(self.font)
        prop.SetJustification({"left": 0, "center": 1, "right": 2}[align])
        prop.SetVerticalJustification({"bottom": 0, "center": 1, "top": 2}[valign])
        coord = actor.GetPositionCoordinate()
        coord.SetCoordinateSystemToNormalizedViewport()
        coord.SetValue(x, y)
        ren.AddViewProp(actor)
        self.captions[key] = actor
        return actor

    def _font_px(self, size) -> int:
        return max(7, round(size * self.ui_scale))

    def _set_text(self, key, text):
        actor = self.captions[key]
        if actor.GetInput() != text:
            actor.SetInput(text)

    def _ortho_camera(self, scale, centre=(0.0, 0.0)):
        cam = self.plotter.camera
        cam.SetParallelProjection(True)
        cam.SetPosition(centre[0], centre[1], 10.0)
        cam.SetFocalPoint(centre[0], centre[1], 0.0)
        cam.SetViewUp(0.0, 1.0, 0.0)
        cam.SetParallelScale(scale)
        cam.SetClippingRange(1.0, 30.0)

    def _image_plane(self, size, z=0.0):
        """A textured square ``[−HALF, HALF]²`` at depth ``z`` showing an RGBA image of ``size`` pixels."""
        pv = self.pv
        blank = np.zeros((size, size, 4), dtype=np.uint8)
        texture = pv.Texture(blank)
        texture.interpolate = True
        plane = pv.Plane(center=(0.0, 0.0, z), direction=(0.0, 0.0, 1.0), i_size=2 * HALF, j_size=2 * HALF)
        actor = self.plotter.add_mesh(plane, texture=texture, lighting=False, show_scalar_bar=False)
        # Drawn with the opaque geometry: an RGBA texture would make VTK composite the panel in a
        # translucent pass (several extra full-panel buffers, slow with software OpenGL).  The
        # transparent texels still blend with what was drawn before (see _build_sphere_panel).
        actor.ForceOpaqueOn()
        image = texture.to_image()
        pixels = image.point_data.active_scalars
        return {"texture": texture, "image": image, "pixels": pixels, "actor": actor, "size": size}

    @staticmethod
    def _upload(plane, rgb8, coverage):
        """Put an engine image (rows top-down) into a plane's texture; uncovered pixels are transparent."""
        h, w = coverage.shape
        rgba = np.asarray(plane["pixels"]).reshape(h, w, 4)[::-1]  # VTK images start at the bottom row
        rgba[..., :3] = rgb8
        if plane.get("alpha_of") is not coverage:  # a renderer's coverage stays the same array
            np.multiply(coverage, np.uint8(255), out=rgba[..., 3], casting="unsafe")
            plane["alpha_of"] = coverage
        plane["image"].Modified()
        plane["texture"].Modified()

    # ------------------------------------------------------------------ panels
    def _build_sphere_panel(self):
        pv = self.pv
        self._renderer(SPHERE)
        # The arrow first: the image plane (drawn in the same opaque pass, in order) then hides the
        # part of the arrow behind the sphere, while its transparent corners let the rest show.
        arrow = pv.Arrow(start=(0, 0, 0), direction=(1, 0, 0), tip_length=0.35, tip_radius=0.16, shaft_radius=0.06)
        self.light_arrow = self.plotter.add_mesh(arrow, color=ACCENT, lighting=False)
        bulb = pv.Sphere(radius=0.07, theta_resolution=24, phi_resolution=12)
        self.light_bulb = self.plotter.add_mesh(bulb, color=ACCENT, lighting=False)
        self.sphere_plane = self._image_plane(self.model.sphere_size)
        self._ortho_camera(SPHERE_SCALE)
        self._text(SPHERE, "sphere_title", "", 0.025, 0.98, size=11.5, bold=True)
        self._text(SPHERE, "sphere_legend", "", 0.025, 0.91, size=9.5, color=MUTED)
        self._text(SPHERE, "sphere_info", "", 0.025, 0.02, size=9.5, color=MUTED, valign="bottom")

    def _build_coarse_panels(self):
        pv = self.pv
        c = self._coarse_poly(self.state.tessellation)
        self._renderer(GOURAUD)
        self.gouraud_poly = c
        self.gouraud_actor = self.plotter.add_mesh(
            c, scalars="rgb", rgb=True, lighting=False, show_scalar_bar=False, smooth_shading=False
        )
        # The edges sit a hair outside the surface so the depth test never hides them.
        self.edges_poly = self._edges_poly(c)
        self.gouraud_edges = self._add_edges()
        self.scan_g = pv.Line((-1.12, 0.0, 1.5), (1.12, 0.0, 1.5))
        self.plotter.add_mesh(self.scan_g, color=SCANLINE, line_width=2.0, lighting=False)
        self._ortho_camera(COARSE_SCALE)
        self._text(GOURAUD, "gouraud_title", "", 0.025, 0.98, size=11.5, bold=True)
        self._text(GOURAUD, "gouraud_info", "", 0.025, 0.02, size=9.5, color=MUTED, valign="bottom")

        self._renderer(PHONG)
        self.phong_plane = self._image_plane(self.model.mesh_size, z=-0.01)
        self.phong_edges = self._add_edges()
        self.scan_p = pv.Line((-1.12, 0.0, 1.5), (1.12, 0.0, 1.5))
        self.plotter.add_mesh(self.scan_p, color=SCANLINE, line_width=2.0, lighting=False)
        self._ortho_camera(COARSE_SCALE)
        self._text(PHONG, "phong_title", "Phong interpolation: lit per pixel", 0.025, 0.98, size=11.5, bold=True)
        self._text(PHONG, "phong_info", "normals interpolated, engine lights each pixel\nred line: the scan line",
                   0.025, 0.02, size=9.5, color=MUTED, valign="bottom")  # fmt: skip

    def _add_edges(self):
        # 35 % black over the surface.  Drawn in the opaque pass after the surface (blending still
        # on): the same colours as a translucent actor, without VTK's costly translucent pass; the
        # depth test hides the edges of the far side.
        actor = self.plotter.add_mesh(
            self.edges_poly, style="wireframe", color=(0.0, 0.0, 0.0), opacity=0.35, lighting=False, line_width=1.0,
            show_scalar_bar=False, scalars=None,
        )  # fmt: skip
        actor.ForceOpaqueOn()
        return actor

    def _edges_poly(self, poly):
        edges = self.pv.PolyData(np.asarray(poly.points) * 1.004, poly.faces)
        return edges

    def _coarse_poly(self, tessellation):
        pv = self.pv
        mesh = self.model.mesh(tessellation)
        faces = np.hstack([np.full((mesh.n_triangles, 1), 3), mesh.faces]).ravel()
        poly = pv.PolyData(np.asarray(mesh.vertices, dtype=np.float64), faces)
        poly.point_data["rgb"] = np.zeros((mesh.n_vertices, 3), dtype=np.uint8)
        poly.point_data.active_scalars_name = "rgb"
        return poly

    def _build_lobe_panel(self):
        pv = self.pv
        self._renderer(LOBE)
        disc = pv.Disc(center=(0.0, 0.0, -0.004), inner=0.0, outer=1.3, normal=(0.0, 0.0, 1.0), c_res=72)
        self.plotter.add_mesh(disc, color=(0.3, 0.31, 0.35), lighting=False)
        self.plotter.add_mesh(pv.Line((0, 0, 0), (0, 0, 1.25)), color=MUTED, line_width=2.0, lighting=False)
        base = pv.Arrow(start=(0, 0, 0), direction=(1, 0, 0), tip_length=0.16, tip_radius=0.045, shaft_radius=0.012)
        self.lobe_light = self.plotter.add_mesh(base.copy(), color=ACCENT, lighting=False)  # l: yellow everywhere
        self.lobe_mirror = self.plotter.add_mesh(base.copy(), color=(1.0, 0.42, 0.42), lighting=False)
        self.lobe_poly = pv.PolyData(np.zeros((3, 3)), np.array([3, 0, 1, 2]))
        self.lobe_poly.point_data["value"] = np.zeros(3)
        # Coloured by the plotted value through a perceptual colour map (what the value is: the caption).
        self.lobe_actor = self.plotter.add_mesh(
            self.lobe_poly, scalars="value", cmap="viridis", lighting=False, clim=(0.0, 1.0),
            scalar_bar_args={
                "title": " ", "vertical": True, "position_x": 0.82, "position_y": 0.14, "width": 0.04,
                "height": 0.6, "n_labels": 3, "fmt": "%.3g", "color": TEXT, "title_font_size": 11,
                "label_font_size": 10,
            },
        )  # fmt: skip
        cam = self.plotter.camera
        cam.SetParallelProjection(True)
        cam.SetPosition(0.0, -6.0, 2.4)
        cam.SetFocalPoint(0.0, 0.0, 0.62)
        cam.SetViewUp(0.0, 0.0, 1.0)
        cam.SetParallelScale(LOBE_SCALE)
        cam.SetClippingRange(0.5, 30.0)
        self._lobe_camera = (cam.GetPosition(), cam.GetFocalPoint(), cam.GetViewUp(), cam.GetParallelScale())
        self._text(LOBE, "lobe_title", "", 0.025, 0.98, size=11.5, bold=True)
        self._text(LOBE, "lobe_info", "", 0.025, 0.905, size=9.5, color=MUTED)

    def _build_charts(self):
        from .app_plots import AnglePlots, PolarPlot, ProfilePlot

        pv = self.pv
        w, h = self.window_size
        dpi = 100 * self.ui_scale  # the same layout at every window size
        self.profile_plot = ProfilePlot(self._panel_px(PROFILE, 0.92), dpi=dpi, captions=False)
        self.polar_plot = PolarPlot(self._panel_px(POLAR, 0.92), dpi=dpi, captions=False)
        self.angle_plots = AnglePlots(self._panel_px(ANGLES, 0.92, cols=2), dpi=dpi, captions=False)
        self.charts = {}
        for panel, plot, key in (
            (PROFILE, self.profile_plot, "profile"),
            (POLAR, self.polar_plot, "polar"),
            (ANGLES, self.angle_plots, "angles"),
        ):
            self._renderer(panel)
            chart = pv.ChartMPL(plot.fig, size=(1.0, 0.92), loc=(0.0, 0.0), redraw_on_render=False)
            chart.background_color = (0.0, 0.0, 0.0, 0.0)
            self.plotter.add_chart(chart)
            plot.on_image = self._chart_pusher(chart)
            self.charts[key] = chart
            self._text(panel, f"{key}_title", "", 0.025 if panel != ANGLES else 0.012, 0.98, size=11.5, bold=True)
        self._text(PROFILE, "profile_metric", "", 0.025, 0.905, size=9.5, color=MUTED)
        self._text(POLAR, "polar_quantity", "", 0.025, 0.905, size=9.5, color=MUTED)
        self._text(POLAR, "polar_note", "", 0.5, 0.45, size=11, color=SCANLINE, align="center", valign="center")
        self._text(POLAR, "polar_albedo", "", 0.025, 0.845, size=9.5, color=MUTED)
        self._text(ANGLES, "angles_peak", "", 0.988, 0.015, size=9, color=MUTED, align="right", valign="bottom")

    def _panel_px(self, panel, height_frac=1.0, cols=1):
        w, h = self.window_size
        cw = sum(self._col_frac[panel[1] : panel[1] + cols]) * w
        return (max(int(cw), 50), max(int(self._row_frac[panel[0]] * h * height_frac), 50))

    def _chart_pusher(self, chart):
        """A callback putting a figure's RGBA buffer into ``chart`` (one VTK image, updated in place)."""
        pv = self.pv
        holder = {}

        def push(rgba):
            h, w = rgba.shape[:2]
            image = holder.get("image")
            if image is None or holder["shape"] != (h, w):
                image = pv.ImageData(dimensions=(w, h, 1))
                image.point_data["rgba"] = np.zeros((w * h, 4), dtype=np.uint8)
                image.point_data.active_scalars_name = "rgba"
                holder.update(image=image, shape=(h, w), pixels=image.point_data["rgba"])
                chart.SetImage(image)
            holder["pixels"][:] = rgba[::-1].reshape(-1, 4)
            image.Modified()
            chart.Modified()

        return push

    def _build_controls(self):
        self._renderer(CONTROLS_PANEL)
        ncol = len(SLIDER_COLUMNS)
        width = 1.0 / ncol
        top, step = 0.8, 0.168
        style = self.pv.global_theme.slider_styles.modern
        for c, (header, specs) in enumerate(SLIDER_COLUMNS):
            x0 = c * width
            self._text(CONTROLS_PANEL, f"header{c}", header, x0 + 0.012, 0.97, size=10.5, color=ACCENT, bold=True)
            for r, spec in enumerate(specs):
                y = top - r * step
                self._add_slider(spec, (x0 + 0.018, y), (x0 + width - 0.02, y), style)
        self._text(CONTROLS_PANEL, "hint", "keys: h help · s screenshot · r reset", 1 - 0.006, 0.03, size=9,
                   color=MUTED, align="right", valign="bottom")  # fmt: skip
        # Check boxes under the channel slider, in the last column: terms left, plot options right.
        w, h = self.window_size
        vp_w = w
        vp_h = self._row_frac[2] * h
        box = max(10, round(13 * self.ui_scale))
        for k, (key, label) in enumerate(CHECKBOXES):
            sub, row = (0, k) if k < 3 else (1, k - 3)
            x_px = int(((ncol - 1) * width + 0.016 + sub * 0.52 * width) * vp_w)
            y_px = int((0.56 - row * 0.17) * vp_h)
            widget = self.plotter.add_checkbox_button_widget(
                self._checkbox_callback(key), value=self._checkbox_value(key), position=(x_px, y_px), size=box,
                border_size=2, color_on=ACCENT, color_off=(0.25, 0.26, 0.3), background_color=MUTED,
            )  # fmt: skip
            self.checkboxes[key] = widget
            self._text(CONTROLS_PANEL, f"check_{key}", label, (x_px + box + 6) / vp_w, (y_px + box / 2) / vp_h,
                       size=9.5, valign="center")  # fmt: skip

    def _add_slider(self, spec, a, b, style):
        value = self._state_value(spec.name)
        widget = self.plotter.add_slider_widget(
            self._slider_callback(spec.name), [spec.lo, spec.hi], value=spec.to_slider(value),
            title=spec.title(value), pointa=a, pointb=b, interaction_event="always", style="modern",
            title_height=0.05, title_color=TEXT, color=TEXT, slider_width=0.028, tube_width=0.006,
        )  # fmt: skip
        rep = widget.GetRepresentation()
        rep.ShowSliderLabelOff()
        rep.SetSliderLength(0.022)
        rep.SetEndCapLength(0.0)
        rep.GetTubeProperty().SetColor(0.4, 0.42, 0.47)
        rep.GetSliderProperty().SetColor(*ACCENT)
        rep.GetSelectedProperty().SetColor(1.0, 1.0, 1.0)
        tp = rep.GetTitleProperty()
        tp.SetBold(False)
        tp.SetShadow(False)
        if self.font:
            import vtk

            tp.SetFontFamily(vtk.VTK_FONT_FILE)
            tp.SetFontFile(self.font)
        if spec.choices is not None or spec.integer:  # the knob comes to rest on the value chosen
            widget.AddObserver("EndInteractionEvent", self._snap_callback(spec.name))
        widget.AddObserver("EndInteractionEvent", self._release_callback(spec.name))
        self.sliders[spec.name] = widget

    def _build_help(self):
        import vtk

        # A renderer on a second layer over the whole window (layers above 0 keep what is below).
        ren = vtk.vtkRenderer()
        ren.SetLayer(1)
        ren.SetViewport(0.0, 0.0, 1.0, 1.0)
        ren.InteractiveOff()
        ren.DrawOff()
        actor = vtk.vtkTextActor()
        actor.SetInput(HELP_TEXT)
        prop = actor.GetTextProperty()
        prop.SetFontSize(self._font_px(15))
        prop.SetColor(*TEXT)
        prop.SetLineSpacing(1.2)
        prop.SetBackgroundColor(0.05, 0.055, 0.065)
        prop.SetBackgroundOpacity(0.95)
        prop.SetFrame(True)
        prop.SetFrameColor(*ACCENT)
        prop.SetFrameWidth(2)
        mono = _font_file("DejaVuSansMono.ttf")
        if mono:
            prop.SetFontFamily(vtk.VTK_FONT_FILE)
            prop.SetFontFile(mono)
        prop.SetJustification(0)
        prop.SetVerticalJustification(1)
        actor.GetPositionCoordinate().SetCoordinateSystemToNormalizedViewport()
        actor.GetPositionCoordinate().SetValue(0.27, 0.56)
        ren.AddViewProp(actor)
        rw = self.plotter.ren_win
        rw.SetNumberOfLayers(max(2, rw.GetNumberOfLayers()))
        rw.AddRenderer(ren)
        self.help_renderer = ren

    @property
    def help_visible(self) -> bool:
        return bool(self.help_renderer.GetDraw())

    def toggle_help(self, show=None):
        show = not self.help_visible if show is None else bool(show)
        self.help_renderer.SetDraw(show)
        self._render()
        return show

    # ------------------------------------------------------------------ widget plumbing
    def _state_value(self, name):
        if name == "light_color":
            return _light_colour_name(self.state.light_color)
        return getattr(self.state, name)

    def _checkbox_value(self, key) -> bool:
        return key in self.state.terms if key in TERM_NAMES else bool(getattr(self.state, key))

    def _slider_callback(self, name):
        def callback(value):
            if not self._building:
                self.on_slider(name, value, live=True)

        return callback

    def _release_callback(self, name):
        def release(widget, event):
            # The widget renders after this event: bring the views the drag left behind up to date.
            if not self._building:
                self.flush(render=False)

        return release

    def _snap_callback(self, name):
        def snap(widget, event):
            spec = SLIDERS[name]
            widget.GetRepresentation().SetValue(spec.to_slider(self._state_value(name)))

        return snap

    def _checkbox_callback(self, key):
        def callback(flag):
            if self._building:
                return
            # The button widget renders after calling back.
            if key in TERM_NAMES:
                terms = set(self.state.terms)
                terms = terms | {key} if flag else terms - {key}
                self.set_control("terms", tuple(terms), render=False)
            else:
                self.set_control(key, bool(flag), render=False)

        return callback

    def _sync_widgets(self):
        """Make every slider and check box show the state (after keys, reset, or programmatic changes)."""
        for name, widget in self.sliders.items():
            spec = SLIDERS[name]
            value = self._state_value(name)
            rep = widget.GetRepresentation()
            target = spec.to_slider(value)
            current = rep.GetValue()
            same = spec.from_slider(current) == value if spec.choices is not None else math.isclose(
                spec.from_slider(current), float(value), rel_tol=1e-9, abs_tol=1e-9
            )  # fmt: skip
            if not same:
                rep.SetValue(target)
            rep.SetTitleText(spec.title(value))
        for key, widget in self.checkboxes.items():
            rep = widget.GetRepresentation()
            want = 1 if self._checkbox_value(key) else 0
            if rep.GetState() != want:
                rep.SetState(want)

    # ------------------------------------------------------------------ handlers
    def on_slider(self, name: str, raw: float, *, render=False, live=False) -> set[str]:
        """What a slider calls: ``raw`` in slider units (log10 for log sliders, an index for choices).

        The slider widget renders the window itself after calling back, so by default
        this only updates the scene (``render=True`` renders too).  ``live=True`` is a
        drag in progress (what the widget passes): see :meth:`set_control`.
        """
        spec = SLIDERS[name]
        value = spec.from_slider(raw)
        if name == "light_color":
            if value == "custom":
                return set()
            value = LIGHT_COLOURS[value]
        views = self.set_control(name, value, sync=False, render=render, live=live)
        self.sliders[name].GetRepresentation().SetTitleText(spec.title(self._state_value(name)))
        return views

    def set_control(self, name: str, value, *, sync=True, render=True, live=False) -> set[str]:
        """Change one control (validated), recompute the affected views and show them; returns their names.

        ``live=True`` (a slider being dragged) updates only the views of
        :data:`~explorer.app_state.LIVE_VIEWS` (the lit sphere and the coarse spheres)
        when the change affects one of them, and leaves the others in
        :attr:`stale_views` for :meth:`flush` (the slider's release, or :data:`IDLE_MS`
        without a move).  Otherwise every affected view is updated at once.
        """
        changed = self.state.update(**{name: value})
        if not changed:
            return set()
        views = self.refresh(render=False, live=live)
        if sync:
            self._sync_widgets()
        if render:
            self._render(all_panels=not live)
        return views

    def on_key(self, key: str) -> set[str]:
        """What a key press does (see the help text); returns the views it changed."""
        s = self.state
        cycle = {
            "m": ("model", MODELS, 1),
            "M": ("model", MODELS, -1),
            "t": ("light", LIGHT_TYPES, 1),
            "i": ("mode", ("flat", "gouraud", "phong"), 1),
            "c": ("channel", CHANNELS, 1),
            "f": ("form", FORMS, 1),
        }
        if key in cycle:
            name, options, step = cycle[key]
            value = options[(options.index(getattr(s, name)) + step) % len(options)]
            return self.set_control(name, value)
        if key in ("1", "2", "3"):
            term = TERM_NAMES[int(key) - 1]
            terms = set(s.terms) ^ {term}
            return self.set_control("terms", tuple(terms))
        if key == "l":
            return self.set_control("log", not s.log)
        if key == "n":
            return self.set_control("times_cos", not s.times_cos)
        if key in ("Up", "Down"):
            spec = CONTROLS["scanline"]
            step = -0.02 if key == "Up" else 0.02
            return self.set_control("scanline", min(max(s.scanline + step, spec.lo), spec.hi))
        if key in ("Left", "Right"):
            # One step within the control's own range (the slider's too): finer never makes it coarser.
            spec = CONTROLS["tessellation"]
            t = min(max(s.tessellation + (1 if key == "Right" else -1), int(spec.lo)), int(spec.hi))
            return self.set_control("tessellation", t)
        if key == "r":
            return self.reset()
        if key == "h":
            self.toggle_help()
            return set()
        if key == "e":
            self.show_edges = not self.show_edges
            self.gouraud_edges.SetVisibility(self.show_edges)
            self.phong_edges.SetVisibility(self.show_edges)
            self._render()
            return set()
        if key == "s":
            path = self._next_screenshot_path()
            try:
                self.screenshot(path)
            except ValueError as exc:  # a full disk or a read-only folder: say so, keep the window
                print(f"lighting-explorer: screenshot not saved: {exc}")
                return set()
            print(f"lighting-explorer: saved {path}")
            return set()
        return set()

    def reset(self) -> set[str]:
        """Every control back to its default, cameras too."""
        self.state.reset()
        views = self.refresh(render=False)
        self._sync_widgets()
        self._reset_cameras()
        self._render()
        return views

    def _reset_cameras(self):
        self._renderer(SPHERE)
        self._ortho_camera(SPHERE_SCALE)
        for panel in (GOURAUD, PHONG):
            self._renderer(panel)
            self._ortho_camera(COARSE_SCALE)
        self._renderer(LOBE)
        pos, focal, up, scale = self._lobe_camera
        cam = self.plotter.camera
        cam.SetPosition(*pos)
        cam.SetFocalPoint(*focal)
        cam.SetViewUp(*up)
        cam.SetParallelScale(scale)
        cam.SetClippingRange(1.0, 30.0)

    def _bind_keys(self):
        pl = self.plotter
        keys = ["m", "M", "t", "i", "c", "f", "1", "2", "3", "l", "n", "Up", "Down", "Left", "Right", "r", "h"]
        keys += ["e", "s"]
        for key in keys:
            pl.clear_events_for_key(key, raise_on_missing=False)
            pl.add_key_event(key, self._key_callback(key))
        # VTK's interactor style acts on characters by itself ('w' wireframe, 's' surface, 'r' camera reset,
        # '3' stereo, 'e' exit, ...), which would fight our keys and could turn the image planes into
        # wireframes.  An observer on the style's CharEvent replaces that behaviour; only 'q' still quits.
        style = getattr(pl.iren, "style", None) if pl.iren is not None else None
        if style is not None:
            style.AddObserver("CharEvent", self._on_char)
        iren = self._interactor()
        if iren is not None:
            iren.AddObserver("TimerEvent", self._on_timer)

    @staticmethod
    def _on_char(style, event):
        iren = style.GetInteractor()
        if iren is not None and iren.GetKeySym() == "q":
            iren.ExitCallback()

    def _key_callback(self, key):
        def callback():
            self.on_key(key)  # renders when something changed

        return callback

    # ------------------------------------------------------------------ showing the views
    def refresh(self, *, render=True, force=False, live=False) -> set[str]:
        """Recompute the changed views (all with ``force``) and update the window; returns their names.

        With ``live`` only the live views are recomputed if any of them is stale (see
        :meth:`set_control`); the rest wait in :attr:`stale_views`.
        """
        model = self.model
        if force:
            views = model.refresh()
        elif live and (model.stale_views() | model.pending) & LIVE_VIEWS:
            views = model.update(only=LIVE_VIEWS)
        else:
            views = model.update()
        self._display(views)
        self._changed_panels |= {panel for panel, shown in PANEL_VIEWS.items() if shown & views}
        if live:
            self._skip_unchanged_panels()
        else:
            self._draw_all_panels()
        if model.pending:
            self._last_drag = time.perf_counter()
            self._start_idle_timer()
        if render:
            self._render(all_panels=not live)
        return views

    def _skip_unchanged_panels(self):
        """Let the next frame redraw only the panels changed since the last one (see PANEL_VIEWS)."""
        for panel, ren in self._panel_renderers.items():
            ren.SetDraw(panel in self._changed_panels)

    def _draw_all_panels(self):
        for ren in self._panel_renderers.values():
            ren.SetDraw(True)

    def _after_render(self, window=None, event=None):
        # A frame is on screen: whatever renders next (an expose, a hover, a key) draws every panel.
        self._changed_panels.clear()
        self._draw_all_panels()

    @property
    def stale_views(self) -> set[str]:
        """Views a drag has left behind the controls (empty after :meth:`flush`)."""
        return set(self.model.pending)

    def flush(self, *, render=True) -> set[str]:
        """Bring the views a drag left behind up to date; returns their names (empty if none were).

        Called when a slider is released and when it has rested :data:`IDLE_MS`; the
        views then hold the same data as if every view had been updated at each move.
        """
        if not self.model.pending:
            return set()
        return self.refresh(render=render)

    def _start_idle_timer(self):
        """Ask the interactor for a timer event :data:`IDLE_MS` from now (a window only)."""
        iren = self._interactor()
        if iren is None or not self._shown:
            return
        if self._idle_timer is not None:
            iren.DestroyTimer(self._idle_timer)
        self._idle_timer = iren.CreateOneShotTimer(IDLE_MS)

    def _on_timer(self, iren=None, event=None):
        """A timer went off: after :data:`IDLE_MS` without a move, update the views left behind."""
        self._idle_timer = None
        if self.model.pending and time.perf_counter() - self._last_drag >= 0.9e-3 * IDLE_MS:
            self.flush(render=True)

    def _interactor(self):
        iren = getattr(self.plotter, "iren", None)
        return getattr(iren, "interactor", None) if iren is not None else None

    def _render(self, *, all_panels=True):
        if all_panels:
            self._draw_all_panels()
        if self._shown or self.off_screen:
            self.plotter.render()

    def _display(self, views):
        s = self.state
        m = self.model.views
        label = s.quantity_label()
        if "sphere" in views:
            sv = m["sphere"]
            self._upload(self.sphere_plane, sv.rgb8, sv.coverage)
            where = "per pixel, exact sphere" if sv.mode == "phong" else f"{sv.mode}, {sv.geometry}"
            self._set_text("sphere_title", f"Lit sphere (engine): {MODEL_LABELS[s.model]}")
            share = 100 * sv.clipped / max(int(sv.coverage.sum()), 1)
            share = f"{share:.0f}%" if share >= 0.5 else "under 1%"
            clipped = f"{share} of the sphere above 1: clipped (lower the exposure)\n" if sv.clipped else ""
            self._set_text("sphere_legend", f"{where} · arrow: the light")
            self._set_text("sphere_info", clipped + self._light_summary())
        if views & {"sphere", "lobe"} or not self._glyphs_placed:
            self._update_light_glyphs()
        if "coarse" in views:
            cv = m["coarse"]
            if cv.vertices.shape[0] != self.gouraud_poly.n_points or len(cv.faces) != self.gouraud_poly.n_cells:
                self._replace_coarse_mesh(s.tessellation)
            self.gouraud_poly.point_data["rgb"][:] = cv.vertex_rgb8
            self.gouraud_poly.Modified()
            self._upload(self.phong_plane, cv.phong_rgb8, cv.coverage)
            self._set_text("gouraud_title", "Gouraud: lit at the vertices")
            self._set_text(
                "gouraud_info",
                f"{cv.n_triangles} triangles, {len(cv.vertices)} vertices: engine colours\n"
                "interpolated across each triangle (VTK lighting off)",
            )
        if "profile" in views:
            pv_ = m["profile"]
            for line in (self.scan_g, self.scan_p):
                pts = line.points
                pts[:, 1] = pv_.y
                line.points = pts
            self.profile_plot.set_data(pv_, CHANNEL_LABELS[s.channel])
            self.profile_plot.render()
            self._set_text("profile_title", f"Scan line: intensity ({CHANNEL_LABELS[s.channel]})")
            self._set_text(
                "profile_metric",
                f"Mach-band metric (slope kinks): Gouraud {pv_.metric_gouraud:.2f}, Phong {pv_.metric_phong:.2f}",
            )
        if "lobe" in views:
            self._update_lobe(m["lobe"], label)
        if "polar" in views:
            self.polar_plot.set_data(m["polar"], channel=s.channel, label=label)
            self.polar_plot.render()
            theta_in = math.degrees(m["polar"].theta_in)
            self._set_text("polar_title", f"Polar slice, plane of incidence, θ_l = {theta_in:.0f}°")
            self._set_text("polar_note", "light below the horizon:\nnothing reflected" if m["polar"].below_horizon
                           else "")  # fmt: skip
            scale = self.polar_plot.captions.get("scale", "")
            self._set_text("polar_quantity", f"{label} · {scale}" if scale else label)
        if "albedo" in views:
            self._show_albedo(m["albedo"])
        if views & {"theta_v", "theta_h", "theta_d", "halfdiff"}:
            self.angle_plots.set_data(
                m["theta_v"], m["theta_h"], m["theta_d"], m["halfdiff"], channel=s.channel, label=label
            )
            self.angle_plots.render()
            self._set_text("angles_title", f"{MODEL_LABELS[s.model]}: {label} against θ_v, θ_h, θ_d (Rusinkiewicz)")
            self._set_text("angles_peak", self.angle_plots.captions.get("peak", ""))

    def _show_albedo(self, av):
        """The albedo readout: ``ρ(θ_v) = value ± error``, flagged "unconverged" above 2 % relative error."""
        self._set_text("polar_albedo", albedo_caption(av))
        self.captions["polar_albedo"].GetTextProperty().SetColor(*(SCANLINE if av.unconverged else MUTED))

    def _light_summary(self) -> str:
        s = self.state
        if s.light == "ambient":
            light = "ambient light only"
        else:
            light = f"{s.light}, elevation {s.elevation:.0f}°, azimuth {s.azimuth:.0f}°"
            if s.light in ("point", "spot"):
                light += f", distance {s.distance:.1f}"
        terms = " + ".join(s.terms) or "no terms"
        form = "classic I" if s.form == "classic" else "physical I/π"
        return f"{light}\n{form} · {terms}"

    def _update_light_glyphs(self):
        self._glyphs_placed = True
        s = self.state
        d = s.light_direction()
        # The light is yellow in every panel; a coloured light shows its colour (lightened to stay visible).
        colour = np.asarray(s.light_color, float)
        if np.allclose(colour, colour[0]):
            colour = np.asarray(ACCENT)
        else:
            colour = 0.35 + 0.65 * colour / colour.max()
        visible = s.light != "ambient"
        self.light_arrow.user_matrix = _arrow_matrix(1.34 * d, 1.03 * d)
        self.light_arrow.prop.color = tuple(colour)
        self.light_arrow.SetVisibility(visible)
        self.light_bulb.user_matrix = _arrow_matrix(1.34 * d, 2.34 * d)
        self.light_bulb.prop.color = tuple(colour)
        self.light_bulb.SetVisibility(visible and s.light in ("point", "spot"))
        lv = self.model.views.get("lobe")
        if lv is not None:
            self.lobe_light.user_matrix = _arrow_matrix(1.3 * lv.light, 0.03 * lv.light)
            self.lobe_mirror.user_matrix = _arrow_matrix(0.03 * lv.mirror, 1.3 * lv.mirror)

    def _replace_coarse_mesh(self, tessellation):
        new = self._coarse_poly(tessellation)
        self.gouraud_poly.copy_from(new)
        self.gouraud_poly.point_data.active_scalars_name = "rgb"
        self.edges_poly.copy_from(self._edges_poly(new))

    def _update_lobe(self, lv, label):
        poly = self.lobe_poly
        n = len(lv.vertices)
        if poly.n_points != n or poly.n_cells != len(lv.faces):
            faces = np.hstack([np.full((len(lv.faces), 1), 3), lv.faces]).ravel()
            new = self.pv.PolyData(lv.vertices.copy(), faces)
            new.point_data["value"] = lv.values.copy()
            poly.copy_from(new)
            poly.point_data.active_scalars_name = "value"
        else:
            poly.points[:] = lv.vertices
            poly.point_data["value"][:] = lv.values
            poly.Modified()
        top = lv.peak if lv.peak > 0 else 1.0
        self.lobe_actor.mapper.scalar_range = (0.0, top)
        theta = math.degrees(math.atan2(-lv.light[0], lv.light[2]))
        self._set_text("lobe_title", f"3D lobe: {label}")
        extra = " · light below the horizon" if lv.below_horizon else ""
        self._set_text(
            "lobe_info",
            f"light l at θ_l = {theta:.0f}° (yellow), mirror direction (red)\n"
            f"peak {lv.peak:.3g}, radius scaled to fit{extra}",
        )

    # ------------------------------------------------------------------ output
    def screenshot(self, path) -> str:
        """Render the whole window to an image file at ``path``; returns the path.

        Written through :func:`explorer.output.write_image`: the format follows the extension (PNG,
        and JPEG/TIFF/WebP with Pillow), the file appears complete or not at all, and it gets the
        user's umask.  A bad path raises :class:`explorer.output.OutputError` before anything is drawn.
        """
        from .output import check_output_path, write_image

        path = os.fspath(path)
        check_output_path(path, flag="screenshot", kinds=("rgb8",))
        write_image(path, rgb8=np.ascontiguousarray(self.image(), dtype=np.uint8), flag="screenshot")
        self.last_screenshot = path
        return path

    def image(self) -> np.ndarray:
        """The window as an RGB array ``(H, W, 3)`` (renders first)."""
        self._draw_all_panels()
        self.plotter.render()
        return np.asarray(self.plotter.screenshot(return_img=True))

    def _next_screenshot_path(self) -> str:
        while True:
            self._screenshot_count += 1
            path = os.path.abspath(f"lighting-explorer-{self._screenshot_count}.png")
            if not os.path.exists(path):
                return path

    def panel_viewport(self, panel) -> tuple[float, float, float, float]:
        """Normalized ``(xmin, ymin, xmax, ymax)`` of a panel in the window (origin bottom left)."""
        self.plotter.subplot(*panel)
        return tuple(self.plotter.renderer.GetViewport())

    def show(self):
        """Open the window and run until it is closed."""
        self._shown = True
        self.plotter.show(auto_close=True)

    def close(self):
        self.plotter.close()


# =============================================================================== benchmark
def benchmark_handlers(repeat: int = 15, window_size=DEFAULT_WINDOW_SIZE) -> dict:
    """Median times (ms) of the slider handlers and of whole frames at ``window_size``, off-screen.

    A slider being dragged calls the *drag* handler (:meth:`ExplorerApp.on_slider` with
    ``live=True``): validate and store the value, re-shade the lit sphere and the coarse
    spheres from their cached geometry buffers (never re-rasterized), encode and upload
    them, move the light arrow; the other views wait for the release.  A *frame* adds
    VTK's render of the whole window (software OpenGL here), which is what the eye waits
    for.  Keys:

    * ``azimuth_ms``, ``elevation_ms`` — the drag handler of the light sliders;
    * ``azimuth_frame_ms``, ``light_frame_ms`` — the same plus rendering the window:
      what a drag of the azimuth or elevation slider costs per frame;
    * ``release_ms`` — the frame at the release of the elevation slider: the scan-line
      profile, the lobe and the plots brought up to date, and the window rendered;
    * ``elevation_full_ms``, ``elevation_full_frame_ms`` — one elevation change updating
      every view at once (a key, or :meth:`ExplorerApp.set_control`), without and with
      the render;
    * ``shininess_ms`` — the drag handler of a material slider;
    * ``tessellation_new_ms`` — a coarse sphere not seen before (rasterized), dragged;
    * ``tessellation_cached_ms`` — back to one already rasterized;
    * ``render_ms`` — VTK alone, redrawing the unchanged window.
    """
    import pyvista as pv

    old = pv.OFF_SCREEN
    pv.OFF_SCREEN = True
    app = ExplorerApp(window_size=window_size, off_screen=True)
    try:
        out = {"window": list(app.window_size), "sphere_px": app.model.sphere_size, "mesh_px": app.model.mesh_size}

        def timed(action, n, frame=False, before=None):
            times = []
            for k in range(n):
                if before is not None:
                    before(k)
                t0 = time.perf_counter()
                action(k)
                if frame:
                    app.plotter.render()
                times.append(1e3 * (time.perf_counter() - t0))
            return statistics.median(times)

        def azimuth(k):
            app.on_slider("azimuth", 135.0 + 40.0 * math.sin(0.2 * (k + 1)), live=True)

        def elevation(k):
            app.on_slider("elevation", 45.0 + 20.0 * math.sin(0.3 * (k + 1)), live=True)

        def elevation_full(k):
            app.on_slider("elevation", 45.0 + 20.0 * math.sin(0.3 * (k + 1)))

        timed(elevation, 3, frame=True)
        out["azimuth_ms"] = timed(azimuth, repeat)
        out["elevation_ms"] = timed(elevation, repeat)
        out["azimuth_frame_ms"] = timed(azimuth, repeat, frame=True)
        out["light_frame_ms"] = timed(elevation, repeat, frame=True)
        out["release_ms"] = timed(lambda k: app.flush(render=False), repeat, frame=True, before=elevation)
        out["elevation_full_ms"] = timed(elevation_full, repeat)
        out["elevation_full_frame_ms"] = timed(elevation_full, repeat, frame=True)
        out["shininess_ms"] = timed(lambda k: app.on_slider("shininess", 1.0 + 0.05 * (k % 20 + 1), live=True), repeat)
        app.flush(render=False)
        seq = [t for t in range(5, 41) if not app.model.is_rasterized(t, app.model.mesh_size)]
        n_new = min(repeat, len(seq), 8)  # within the renderer cache (12), so they stay rasterized
        out["tessellation_new_ms"] = timed(lambda k: app.on_slider("tessellation", seq[k], live=True), n_new)
        out["tessellation_cached_ms"] = timed(
            lambda k: app.on_slider("tessellation", seq[k % n_new], live=True), repeat
        )
        app.flush(render=False)
        out["render_ms"] = timed(lambda k: None, repeat, frame=True)
        return out
    finally:
        app.close()
        pv.OFF_SCREEN = old


# =============================================================================== command line
def _window_size(text: str):
    try:
        w, h = (int(x) for x in text.lower().replace("×", "x").split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected WIDTHxHEIGHT in pixels, e.g. 1280x768; got {text!r}") from None
    if not (640 <= w <= 8192 and 400 <= h <= 8192):
        raise argparse.ArgumentTypeError(f"window size must be at least 640x400 and at most 8192x8192; got {text!r}")
    return (w, h)


def build_parser() -> argparse.ArgumentParser:
    from .cli import OneLineParser

    p = OneLineParser(
        prog="lighting-explorer",
        description="Open the explorer window: a lit sphere, Gouraud against Phong, BRDF lobe, polar and angle "
        "plots, all computed by the engine. Every option sets the starting value of a control.",
    )
    h = {name: spec.help for name, spec in CONTROLS.items()}
    g = p.add_argument_group("material")
    g.add_argument("--model", choices=MODELS, help=h["model"])
    g.add_argument("--kd", help="diffuse albedo: one number (times --color) or r,g,b")
    g.add_argument("--color", help=h["color"])
    g.add_argument("--ks", type=float, help=h["ks"])
    g.add_argument("--shininess", type=float, help=h["shininess"])
    g.add_argument("--roughness", type=float, help=h["roughness"])
    g.add_argument("--f0", type=float, help=h["f0"])
    g.add_argument("--ndf", choices=NDFS, help=h["ndf"])
    g = p.add_argument_group("light")
    g.add_argument("--light", choices=LIGHT_TYPES, help=h["light"])
    g.add_argument("--elevation", type=float, help=h["elevation"])
    g.add_argument("--azimuth", type=float, help=h["azimuth"])
    g.add_argument("--intensity", type=float, help=h["intensity"])
    g.add_argument("--light-color", dest="light_color", help=h["light_color"])
    g.add_argument("--ambient", type=float, help=h["ambient"])
    g.add_argument("--distance", type=float, help=h["distance"])
    g.add_argument("--attenuation", choices=tuple(ATTENUATIONS), help=h["attenuation"])
    g.add_argument("--cutoff", type=float, help=h["cutoff"])
    g.add_argument("--spot-exponent", dest="spot_exponent", type=float, help=h["spot_exponent"])
    g = p.add_argument_group("shading and plots")
    g.add_argument("--mode", choices=("flat", "gouraud", "phong"), help=h["mode"])
    g.add_argument("--form", choices=FORMS, help=h["form"])
    g.add_argument("--terms", help="terms shown, comma-separated from ambient,diffuse,specular")
    g.add_argument("--tessellation", type=int, help=h["tessellation"])
    g.add_argument("--channel", choices=CHANNELS, help=h["channel"])
    g.add_argument("--log", action=argparse.BooleanOptionalAction, default=None, help=h["log"])
    g.add_argument("--times-cos", dest="times_cos", action=argparse.BooleanOptionalAction, default=None,
                   help=h["times_cos"])  # fmt: skip
    g.add_argument("--exposure", type=float, help=h["exposure"])
    g.add_argument("--scanline", type=float, help=h["scanline"])
    g = p.add_argument_group("window")
    g.add_argument("--scene", help="start from a scene file (TOML): its first object's material and its lights")
    g.add_argument("--size", type=_window_size, default=DEFAULT_WINDOW_SIZE, help="window size WIDTHxHEIGHT")
    g.add_argument("--off-screen", dest="off_screen", action="store_true", help="render without a window")
    g.add_argument("--screenshot", metavar="PATH",
                   help="render the window to an image (.png; .jpg .tif .webp with Pillow) and exit "
                        "(implies --off-screen)")  # fmt: skip
    return p


def main(argv=None) -> int:
    """``lighting-explorer [options]``: open the window, or with ``--screenshot`` write it to an image."""
    from .cli import PROG, error_line
    from .output import check_output_path, write_image

    try:
        args = build_parser().parse_args(argv)
        if args.screenshot is not None:  # checked before the window is built: no work for a file we cannot write
            check_output_path(args.screenshot, flag="--screenshot", kinds=("rgb8",))
        values = {k: v for k, v in vars(args).items() if k in CONTROLS or k in ("kd", "scene")}
        state = AppState.from_args(values)
    except (ValueError, OSError) as exc:
        print(f"{PROG}: error: {error_line(exc)}", file=sys.stderr)
        return 2
    off_screen = bool(args.off_screen or args.screenshot)
    problem = None if off_screen else display_problem()
    if problem:
        print(no_display_message(problem), file=sys.stderr)
        return 1
    try:
        import pyvista as pv
    except ImportError:
        print("lighting-explorer: error: the window needs PyVista (pip install 'lighting-explorer[explorer]')",
              file=sys.stderr)  # fmt: skip
        return 2
    if off_screen:
        pv.OFF_SCREEN = True
    app = ExplorerApp(state, window_size=args.size, off_screen=off_screen)
    if args.screenshot is not None:
        try:
            rgb8 = np.ascontiguousarray(app.image(), dtype=np.uint8)
        finally:
            app.close()
        try:
            write_image(args.screenshot, rgb8=rgb8, flag="--screenshot")
        except ValueError as exc:
            print(f"{PROG}: error: {error_line(exc)}", file=sys.stderr)
            return 2
        print(f"lighting-explorer: wrote {args.screenshot} ({rgb8.shape[1]}x{rgb8.shape[0]})")
        return 0
    if off_screen:
        app.plotter.render()
        app.close()
        print("lighting-explorer: rendered off-screen (add --screenshot PATH to keep the picture)")
        return 0
    app.show()
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

"""The explorer window: :class:`ExplorerApp`, one PyVista window of linked views around an explorer model.

How the engine's colours reach the screen, with VTK lighting off everywhere:

* per-pixel images (lit sphere, Phong panel) are the engine's images encoded to
  8-bit sRGB and drawn as textures on planes facing an orthographic camera;
* the Gouraud panel is the coarse mesh with the engine's *vertex colours* as RGB
  scalars, interpolated across each triangle by VTK with lighting off — VTK's own
  ``gouraud`` interpolation would light per pixel whenever point normals exist;
* the lobe is coloured by its BRDF value through a perceptual colour map;
* the plots are Matplotlib figures embedded with ``pyvista.ChartMPL`` and updated
  by blitting (:mod:`explorer.app.plots`).

A frame must follow a slider within 50 ms with software OpenGL, so while a slider
is dragged only the engine's images and the light arrow follow each move (the
scan-line profile, the lobe and the plots wait for the release, or for the slider
to rest :data:`~explorer.app.layout.IDLE_MS`), and VTK redraws only the panels that changed.

:class:`ExplorerApp` builds the window around an :class:`~explorer.app.views.ExplorerModel`
from four mixins: the panels (:mod:`explorer.app.panels`), the control widgets
(:mod:`explorer.app.widgets`), the keys and help (:mod:`explorer.app.keys`) and the drawing
of the views (:mod:`explorer.app.drawing`).  Its handlers (:meth:`ExplorerApp.set_control`,
:meth:`ExplorerApp.on_slider`, :meth:`ExplorerApp.on_key`, :meth:`ExplorerApp.flush`) are what
the widgets call, and what the tests call.
"""

from __future__ import annotations

import os
import time

import numpy as np

from .display import _quiet_vtk, has_display
from .drawing import DrawingMixin
from .keys import KeysMixin
from .layout import (
    BACKGROUND,
    COARSE_SCALE,
    DEFAULT_WINDOW_SIZE,
    DESIGN_HEIGHT,
    GOURAUD,
    HALF,
    IDLE_MS,
    LOBE,
    PANEL_VIEWS,
    PHONG,
    SPHERE,
    SPHERE_SCALE,
    _font_file,
)
from .objectpanel import OBJECT_FILL, ObjectPanelMixin
from .panels import PanelsMixin
from .state import AppState
from .views import LIVE_VIEWS, ExplorerModel
from .widgets import WidgetsMixin

__all__ = ["ExplorerApp"]


# =============================================================================== the window
class ExplorerApp(PanelsMixin, WidgetsMixin, KeysMixin, DrawingMixin, ObjectPanelMixin):
    """The explorer window around an :class:`~explorer.app.views.ExplorerModel`.

    Parameters
    ----------
    state : AppState, optional
        The starting controls (default: a fresh :class:`~explorer.app.state.AppState`).
    window_size : (int, int)
        Window width and height in pixels (default 1280 × 768).
    off_screen : bool
        Render without a window (screenshots, tests); needs no display.
    sphere_size, mesh_size : int, optional
        Pixels of the engine images (default: about the size of their panels).
    lobe_resolution : int
        Rings of the lobe mesh.
    brdf_files : sequence of path, optional
        BRDF files to open (``.brdf``, MERL ``.binary``), each registered as a model
        (:func:`lighting.files.file_model`): the first becomes the current model, the others
        entries of the comparison list.  A bad file raises ``ValueError`` naming it (before any
        window is built).
    compare : explorer.compare.BRDFList, optional
        The comparison list to start with (default: an empty one).
    mesh : path, optional
        The lit object's mesh file (default: a generated blob); a bad file raises ``ValueError`` naming it.
    environment_file : path, optional
        An environment image (``.hdr``, ``.pfm``, ``.npy``, ``.exr``): the ``"file"`` environment choice.
    """

    def __init__(self, state=None, *, window_size=DEFAULT_WINDOW_SIZE, off_screen=False, sphere_size=None,
                 mesh_size=None, lobe_resolution=40, brdf_files=(), compare=None, mesh=None,
                 environment_file=None):  # fmt: skip
        import pyvista as pv

        self.pv = pv
        self.window_size = (int(window_size[0]), int(window_size[1]))
        w, h = self.window_size
        row_w, col_w = (1.1, 0.95, 0.95), (1.12, 1.0, 1.0, 1.05)
        self._row_frac = [x / sum(row_w) for x in row_w]
        self._col_frac = [x / sum(col_w) for x in col_w]
        # Engine images at about one texel per screen pixel of their panels.
        row0 = h * self._row_frac[0]
        if sphere_size is None:
            sphere_size = int(min(max(round(row0 * HALF / SPHERE_SCALE / 8) * 8, 128), 1024))
        if mesh_size is None:
            # 0.8 texel per pixel: the coarse images are drawn slightly magnified, to keep a slider move fast.
            mesh_size = int(min(max(round(0.8 * row0 * HALF / COARSE_SCALE / 8) * 8, 96), 1024))
        # The lit object fills the 3D panel: its image at the panel's size in pixels.
        object_size = (max(int(w * self._col_frac[0]), 32), max(int(h * self._row_frac[1] * OBJECT_FILL), 32))
        self.model = ExplorerModel(state, sphere_size=sphere_size, mesh_size=mesh_size, lobe_resolution=lobe_resolution,
                                   compare=compare, object_size=object_size, mesh=mesh,
                                   environment_file=environment_file)  # fmt: skip
        for k, path in enumerate(brdf_files or ()):
            self.model.open_brdf(path, current=k == 0)
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
        # Multisampling multiplies the frame time with software OpenGL, and the engine's images need none.
        pl.ren_win.SetMultiSamples(0)
        self.plotter = pl
        self.sliders: dict = {}
        self.checkboxes: dict = {}
        self.captions: dict = {}
        self._build_sphere_panel()
        self._build_coarse_panels()
        self._build_lobe_panel()
        self._build_object_panel()
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
        # notebook=False: in Jupyter, PyVista would otherwise show a trame view of the whole window as a side
        # effect of the off-screen show() below, in which the VTK sliders do nothing (explorer.notebook is the
        # notebook's front end).
        return self.pv.Plotter(
            notebook=False,
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
        """The controls (the model's :class:`~explorer.app.state.AppState`)."""
        return self.model.state

    # ------------------------------------------------------------------ handlers
    def on_slider(self, name: str, raw: float, *, render=False, live=False) -> set[str]:
        """What a slider calls: ``raw`` in slider units (log10 for log sliders).

        The slider widget renders the window itself after calling back, so by default
        this only updates the scene (``render=True`` renders too).  ``live=True`` is a
        drag in progress (what the widget passes): see :meth:`set_control`.

        Parameters
        ----------
        name : str
            The control (a key of :data:`~explorer.app.widgets.SLIDERS`), or ``"param:NAME"`` for a
            parameter of the model.
        raw : float
            The slider position.
        render : bool
            Render the window afterwards.
        live : bool
            A drag in progress.

        Returns
        -------
        set of str
            The names of the views recomputed.
        """
        spec = self.slider_spec(name)
        value = spec.from_slider(raw)
        if name.startswith("param:"):
            views = self.set_control("params", {name[6:]: value}, sync=False, render=render, live=live)
            none_box = self.checkboxes.get("none:" + name[6:])
            if none_box is not None:  # a None row (α_y = α_x) takes a number from its slider: the lock opens
                none_box.GetRepresentation().SetState(0)
        else:
            views = self.set_control(name, value, sync=False, render=render, live=live)
        self.sliders[name].GetRepresentation().SetTitleText(spec.title(self._state_value(name)))
        return views

    def set_control(self, name: str, value, *, sync=True, render=True, live=False) -> set[str]:
        """Change one control (validated), recompute the affected views and show them; returns their names.

        ``live=True`` (a slider being dragged) updates only the views of
        :data:`~explorer.app.views.LIVE_VIEWS` (the lit sphere and the coarse spheres)
        when the change affects one of them, and leaves the others in
        :attr:`stale_views` for :meth:`flush` (the slider's release, or :data:`IDLE_MS`
        without a move).  Otherwise every affected view is updated at once.

        Parameters
        ----------
        name : str
            The control.
        value
            Its new value (validated; a bad one raises ``ValueError`` naming the control).
        sync : bool
            Make the widgets show the new state.
        render : bool
            Render the window afterwards.
        live : bool
            A drag in progress.

        Returns
        -------
        set of str
            The names of the views recomputed (empty when the value did not change).
        """
        changed = self.state.update(**{name: value})
        if not changed:
            return set()
        views = self.refresh(render=False, live=live)
        if sync or self._params_model != self.state.model:
            self._sync_widgets()  # a new model: its own controls replace the last one's
        if render:
            self._render(all_panels=not live)
        return views

    def reset(self) -> set[str]:
        """Every control back to its default, cameras too.

        Returns
        -------
        set of str
            The names of the views recomputed.
        """
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

    # ------------------------------------------------------------------ showing the views
    def refresh(self, *, render=True, force=False, live=False) -> set[str]:
        """Recompute the changed views (all with ``force``) and update the window; returns their names.

        With ``live`` only the live views are recomputed if any of them is stale (see
        :meth:`set_control`); the rest wait in :attr:`stale_views`.

        Parameters
        ----------
        render : bool
            Render the window afterwards.
        force : bool
            Recompute every view.
        live : bool
            A drag in progress.

        Returns
        -------
        set of str
            The names of the views recomputed.
        """
        model = self.model
        if force:
            views = model.refresh()
        elif live and (model.stale_views() | model.pending) & LIVE_VIEWS:
            views = model.update(only=LIVE_VIEWS)
        else:
            views = model.update()
        self._display(views)
        self._display_object(views)
        self._changed_panels |= {panel for panel, shown in PANEL_VIEWS.items() if shown & views}
        if live:
            self._skip_unchanged_panels()
        else:
            self._draw_all_panels()
        if model.pending:
            self._last_drag = time.perf_counter()
            self._start_idle_timer()
        self._start_refine_timer()
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

        Parameters
        ----------
        render : bool
            Render the window afterwards.

        Returns
        -------
        set of str
            The names of the views recomputed.
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
        fired = iren.GetTimerEventId() if iren is not None and hasattr(iren, "GetTimerEventId") else None
        if fired is not None and fired == self._refine_timer:
            self._on_refine_timer()  # the progressive reference's next tick
            return
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

    # ------------------------------------------------------------------ output
    def screenshot(self, path) -> str:
        """Render the whole window to an image file at ``path``; returns the path.

        Written through :func:`explorer.output.write_image`: the format follows the extension (PNG,
        and JPEG/TIFF/WebP with Pillow), the file appears complete or not at all, and it gets the
        user's umask.  A bad path raises :class:`explorer.output.OutputError` before anything is drawn.

        Parameters
        ----------
        path : str or os.PathLike
            The image file to write.

        Returns
        -------
        str
            ``path``.
        """
        from ..output import check_output_path, write_image

        path = os.fspath(path)
        check_output_path(path, flag="screenshot", kinds=("rgb8",))
        write_image(path, rgb8=np.ascontiguousarray(self.image(), dtype=np.uint8), flag="screenshot")
        self.last_screenshot = path
        return path

    def image(self) -> np.ndarray:
        """The window as an RGB array ``(H, W, 3)`` (renders first).

        Returns
        -------
        ndarray of uint8, shape (H, W, 3)
            The window's pixels, top row first.
        """
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
        """Normalized ``(xmin, ymin, xmax, ymax)`` of a panel in the window (origin bottom left).

        Parameters
        ----------
        panel : (int, int)
            Row and column of the panel (:mod:`explorer.app.layout`).

        Returns
        -------
        tuple of float
            The viewport.
        """
        self.plotter.subplot(*panel)
        return tuple(self.plotter.renderer.GetViewport())

    def show(self):
        """Open the window and run until it is closed."""
        self._shown = True
        self.plotter.show(auto_close=True)

    def close(self):
        """Close the window (and release its render window)."""
        self.plotter.close()

"""The 3D BRDF lobe: VTK renders it off-screen into an image the panel shows, or into pyvistaqt's OpenGL widget.

The lobe's surface, its colours (the plotted value through viridis) and the arrows come from
:class:`explorer.app.views.LobeView`; VTK's lighting is off, so the colours are the values.

By default VTK renders the scene off-screen and the panel shows the picture: a drag turns the camera, the
wheel zooms, and only this panel is repainted.  pyvistaqt's ``QtInteractor`` (``interactive=True``;
``lighting-explorer --opengl-3d``) is a ``QOpenGLWidget``: with one in the window, Qt composes the whole
window through OpenGL at every repaint of any panel, which with software OpenGL (Mesa's llvmpipe) costs
more than a whole drag frame's budget (``lighting-explorer bench --app`` measures both).  Qt's
``offscreen`` platform has no OpenGL widgets at all.
"""

from __future__ import annotations

import os

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from .images import ImageCanvas

__all__ = ["LobeView3D", "has_opengl_widgets", "arrow_matrix"]

ACCENT = (1.0, 0.878, 0.4)
MIRROR = (1.0, 0.42, 0.42)
MUTED = (0.6, 0.63, 0.66)
BACKGROUND = (0.118, 0.125, 0.141)
#: The camera: orthographic, from the front and a little above, the lobe's base at the bottom.
CAMERA = {"position": (0.0, -6.0, 2.4), "focal_point": (0.0, 0.0, 0.62), "view_up": (0.0, 0.0, 1.0), "scale": 1.02}


def has_opengl_widgets() -> bool:
    """Whether Qt's platform can show OpenGL widgets (no on ``offscreen`` and ``minimal``)."""
    app = QtGui.QGuiApplication.instance()
    name = app.platformName() if app is not None else ""
    return name not in ("offscreen", "minimal", "")


def arrow_matrix(start, end) -> np.ndarray:
    """4×4 matrix taking the unit arrow (0,0,0)→(1,0,0) to ``start``→``end`` (uniform scale).

    Parameters
    ----------
    start, end : array_like, shape (3,)
        The arrow's tail and tip.

    Returns
    -------
    ndarray, shape (4, 4)
        A tiny scale at the origin when the arrow has no length (the actor vanishes).
    """
    start, end = np.asarray(start, float), np.asarray(end, float)
    d = end - start
    length = float(np.linalg.norm(d))
    m = np.eye(4)
    if not length > 0:
        m[:3, :3] *= 1e-9
        return m
    x = d / length
    helper = np.array([0.0, 0.0, 1.0]) if abs(x[2]) < 0.9 else np.array([0.0, 1.0, 0.0])
    y = np.cross(helper, x)
    y /= np.linalg.norm(y)
    z = np.cross(x, y)
    m[:3, 0], m[:3, 1], m[:3, 2] = x * length, y * length, z * length
    m[:3, 3] = start
    return m


class LobeView3D(QtWidgets.QWidget):
    """The lobe panel's 3D view.

    Parameters
    ----------
    interactive : bool
        A pyvistaqt ``QtInteractor`` (an OpenGL widget) if True, where Qt can show one
        (:func:`has_opengl_widgets`); VTK off-screen images otherwise (the default).

    Attributes
    ----------
    renders : int
        Frames rendered so far (the bench reads it).
    """

    def __init__(self, parent=None, *, interactive: bool = False):
        super().__init__(parent)
        import pyvista as pv

        self.pv = pv
        self.interactive = bool(interactive) and has_opengl_widgets()
        lay = QtWidgets.QVBoxLayout(self)
        lay.setContentsMargins(0, 0, 0, 0)
        self.renders = 0
        if self.interactive:
            from pyvistaqt import QtInteractor

            self.plotter = QtInteractor(self, auto_update=False)
            self.plotter.enable_trackball_style()
            lay.addWidget(self.plotter.interactor)
            self.canvas = None
        else:
            if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
                # Without a display VTK would try X first (and warn) before it falls back to EGL: go there at once.
                os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
            self.plotter = pv.Plotter(off_screen=True, window_size=(320, 280))
            self.canvas = ImageCanvas(self, min_size=64)
            self.canvas.mouse_dragged.connect(self._on_drag)
            self.canvas.wheel_turned.connect(self._on_wheel)
            lay.addWidget(self.canvas)
            self._drag_from = None
        self.setMinimumSize(96, 72)
        self._auto_zoom = True  # until the student zooms or turns the view
        self._build()
        self._pending = False

    def sizeHint(self):  # noqa: N802 - Qt's name
        return QtCore.QSize(200, 160)

    # ------------------------------------------------------------------ scene
    def _build(self):
        pv, p = self.pv, self.plotter
        p.set_background(BACKGROUND)
        disc = pv.Disc(center=(0.0, 0.0, -0.004), inner=0.0, outer=1.3, normal=(0.0, 0.0, 1.0), c_res=72)
        p.add_mesh(disc, color=(0.3, 0.31, 0.35), lighting=False)
        p.add_mesh(pv.Line((0, 0, 0), (0, 0, 1.25)), color=MUTED, line_width=2.0, lighting=False)
        p.add_mesh(pv.Line((0, 0, 0), (1.28, 0, 0)), color=MUTED, line_width=1.5, lighting=False)
        base = pv.Arrow(start=(0, 0, 0), direction=(1, 0, 0), tip_length=0.16, tip_radius=0.045, shaft_radius=0.012)
        self.light_actor = p.add_mesh(base.copy(), color=ACCENT, lighting=False)
        self.mirror_actor = p.add_mesh(base.copy(), color=MIRROR, lighting=False)
        spike = pv.Arrow(start=(0, 0, 0), direction=(1, 0, 0), tip_length=0.12, tip_radius=0.05, shaft_radius=0.022)
        self.spike_actor = p.add_mesh(spike, color=MIRROR, lighting=False)
        self.spike_actor.SetVisibility(False)
        self.poly = pv.PolyData(np.zeros((3, 3)), np.array([3, 0, 1, 2]))
        self.poly.point_data["value"] = np.zeros(3)
        self.lobe_actor = p.add_mesh(
            self.poly, scalars="value", cmap="viridis", lighting=False, clim=(0.0, 1.0),
            # The colour scale across the top, where the lobe (radius at most 1) leaves the view empty.
            scalar_bar_args={"title": " ", "vertical": False, "position_x": 0.3, "position_y": 0.86, "width": 0.4,
                             "height": 0.08, "n_labels": 3, "fmt": "%.3g", "color": "white", "title_font_size": 12,
                             "label_font_size": 12},
        )  # fmt: skip
        self.reset_camera()

    def reset_camera(self) -> None:
        """The default camera: orthographic, the lobe's base plane seen a little from above."""
        cam = self.plotter.camera
        cam.SetParallelProjection(True)
        cam.SetPosition(*CAMERA["position"])
        cam.SetFocalPoint(*CAMERA["focal_point"])
        cam.SetViewUp(*CAMERA["view_up"])
        cam.SetParallelScale(CAMERA["scale"])
        cam.SetClippingRange(0.5, 30.0)

    def set_lobe(self, lv) -> None:
        """Show :class:`explorer.app.views.LobeView` ``lv`` and redraw this view only."""
        poly = self.poly
        if poly.n_points != len(lv.vertices) or poly.n_cells != len(lv.faces):
            faces = np.hstack([np.full((len(lv.faces), 1), 3), lv.faces]).ravel()
            new = self.pv.PolyData(np.array(lv.vertices, dtype=np.float64), faces)
            new.point_data["value"] = np.array(lv.values, dtype=np.float64)
            poly.copy_from(new)
            poly.point_data.active_scalars_name = "value"
        else:
            poly.points[:] = lv.vertices
            poly.point_data["value"][:] = lv.values
            poly.Modified()
        self.lobe_actor.mapper.scalar_range = (0.0, lv.peak if lv.peak > 0 else 1.0)
        self.light_actor.user_matrix = arrow_matrix(1.3 * lv.light, 0.03 * lv.light)
        self.mirror_actor.user_matrix = arrow_matrix(0.03 * lv.mirror, 1.3 * lv.mirror)
        if lv.spike > 0:
            d = lv.spike_direction
            self.spike_actor.user_matrix = arrow_matrix(0.0 * d, max(lv.spike * lv.scale, 0.05) * d)
        self.spike_actor.SetVisibility(lv.spike > 0)
        self.redraw()

    # ------------------------------------------------------------------ drawing
    def _fit_width(self) -> None:
        # The parallel scale is half the view's height in scene units: a narrow view needs more to keep the
        # disc (radius 1.3) and the arrows across its width.
        w, h = max(self.width(), 1), max(self.height(), 1)
        self.plotter.camera.SetParallelScale(max(CAMERA["scale"], 1.42 * h / w))

    def redraw(self) -> None:
        """Render the scene now (this view only)."""
        self.renders += 1
        if self._auto_zoom:
            self._fit_width()
        if self.interactive:
            self.plotter.render()
            return
        w, h = max(self.canvas.width(), 16), max(self.canvas.height(), 16)
        if tuple(self.plotter.window_size) != (w, h):
            self.plotter.window_size = (w, h)
        self.plotter.render()  # pyvista's screenshot renders only the first time: later frames would be stale
        self.canvas.set_image(self.plotter.screenshot(return_img=True))

    def image(self) -> np.ndarray:
        """The view's current pixels, ``(H, W, 3)`` uint8 (for the window's screenshot)."""
        return np.asarray(self.plotter.screenshot(return_img=True))

    def resizeEvent(self, event):  # noqa: N802 - Qt's name
        super().resizeEvent(event)
        if self._auto_zoom:
            self._fit_width()
        if not self.interactive and not self._pending:
            self._pending = True
            QtCore.QTimer.singleShot(0, self._resized)

    def _resized(self):
        self._pending = False
        if self.plotter.render_window is not None:  # not closed (a resize may arrive after close_view)
            self.redraw()

    def _on_drag(self, x, y, released):
        # Off-screen: a horizontal drag turns the camera about the up axis, a vertical one tilts it.
        if self._drag_from is not None:
            dx, dy = x - self._drag_from[0], y - self._drag_from[1]
            cam = self.plotter.camera
            cam.Azimuth(-0.5 * dx)
            cam.Elevation(0.5 * dy)
            cam.OrthogonalizeViewUp()
            self._auto_zoom = False
            self.redraw()
        self._drag_from = None if released else (x, y)

    def _on_wheel(self, steps: float):
        # One notch (15°) zooms by 10 %, toward or away from the lobe.
        self.plotter.camera.Zoom(1.1 ** steps)
        self._auto_zoom = False
        self.redraw()

    def close_view(self) -> None:
        """Free VTK's window (call before the Qt widget goes)."""
        self.plotter.close()

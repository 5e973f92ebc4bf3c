"""The explorer's Qt window: :class:`ExplorerWindow`, the views around an explorer model and its controls.

Layout (every part follows the window's size):

    +---------------------------------------------------------+----------------+
    | lit sphere | Gouraud | Phong interp. | scan-line profile |  Controls      |
    |------------+---------+---------------+-------------------|  Lights        |
    | 3D lobe / lit object | polar slice  | angle curves/albedo|  Compare (tabs)|
    +---------------------------------------------------------+----------------+
    | status bar: refusals, progress of the Monte-Carlo reference               |

The window maps the controls' state (:class:`~explorer.app.state.AppState`) onto widgets and the widgets'
events back onto it (:meth:`ExplorerWindow.apply`); the views' data come from
:class:`~explorer.app.views.ExplorerModel` and the captions from :mod:`explorer.app.captions`.  Nothing
here computes lighting.  While a slider is dragged only the engine's images follow
(:data:`~explorer.app.views.LIVE_VIEWS`); the lobe and the plots follow on release, or once the slider
rests.  Keys are ``QAction`` shortcuts whose view updates are coalesced: a burst of key presses costs one
update.  The Monte-Carlo reference refines on a ``QTimer`` once the views have rested :data:`IDLE_MS`.
"""

from __future__ import annotations

import math
import os

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from ..app import captions
from ..app.command import DEFAULT_WINDOW_SIZE
from ..app.plots import AlbedoPlot, AnglePlotsGrid, PolarPlot, ProfilePlot
from ..app.state import AppState
from ..app.views import LIVE_VIEWS, ExplorerModel
from .controls import ControlPanel
from .images import ImageCanvas, ImagePanel, WrapLabel
from .lists import ComparePanel, LightsPanel
from .plots import PlotCanvas
from .view3d import LobeView3D

__all__ = ["ExplorerWindow", "DEFAULT_WINDOW_SIZE", "IDLE_MS", "REFINE_MS", "REFINE_BUDGET"]

#: A slider that rests this long (ms) while held counts as released: the plots follow.
IDLE_MS = 150
#: The Monte-Carlo reference refines on a timer of this period (ms) while the views rest (from IDLE_MS after their
#: last change) ...
REFINE_MS = 10
#: ... spending at most this many seconds a tick.
REFINE_BUDGET = 0.04

ACCENT = QtGui.QColor("#ffe066")
SCANLINE = QtGui.QColor("#ff6b6b")
#: The markers of the extra lights (a scene's rect, disk, further point lights ...) on the lit sphere.
EXTRA = QtGui.QColor("#74c0fc")
EDGE = QtGui.QColor(20, 22, 26, 150)

STYLE_SHEET = """
QFrame#viewPanel { background: #1e2024; border: 1px solid #33373d; border-radius: 3px; }
QStatusBar QLabel { padding: 0 4px; }
"""


class ExplorerWindow(QtWidgets.QMainWindow):
    """The explorer window around an :class:`~explorer.app.views.ExplorerModel`.

    Parameters
    ----------
    state : AppState, optional
        The starting controls (default: a fresh :class:`~explorer.app.state.AppState`).
    window_size : (int, int)
        Width and height in pixels (default 1280 × 768).
    compare : explorer.compare.BRDFList, optional
        The comparison list to start with.
    mesh : path or TriangleMesh, optional
        The lit object's mesh (default: a generated blob).
    environment_file : path or (path, Environment), optional
        The environment of the ``"file"`` choice.
    brdf_files : sequence of path, optional
        BRDF files (``.brdf``, MERL ``.binary``): the first becomes the current model, the others entries of
        the comparison list.
    sphere_size, mesh_size : int
        Pixels of the engine's lit-sphere and coarse-sphere images.
    interactive_3d : bool
        The 3D lobe in pyvistaqt's OpenGL widget; default: VTK off-screen images (see :mod:`explorer.qt.view3d`).

    Attributes
    ----------
    state : AppState
        The controls.
    model : ExplorerModel
        Every view's data.
    updates : int
        View updates done so far (a burst of key presses makes one).
    """

    def __init__(self, state=None, *, window_size=DEFAULT_WINDOW_SIZE, compare=None, mesh=None,
                 environment_file=None, brdf_files=(), sphere_size=320, mesh_size=224, lobe_resolution=40,
                 interactive_3d=False, parent=None):  # fmt: skip
        super().__init__(parent)
        self.model = ExplorerModel(state if state is not None else AppState(), sphere_size=sphere_size,
                                   mesh_size=mesh_size, lobe_resolution=lobe_resolution, compare=compare,
                                   mesh=mesh, environment_file=environment_file)  # fmt: skip
        for k, path in enumerate(brdf_files or ()):
            self.model.open_brdf(path, current=k == 0)
        self.updates = 0
        self._extra_light_dirs: list = []
        self._edge_key = None
        self._environment_switched = False
        self.show_edges = True
        self.last_error = ""
        self.setWindowTitle("lighting-explorer")
        self.setStyleSheet(STYLE_SHEET)
        self._build_views(interactive_3d)
        self._build_docks()
        self._build_actions()
        self._build_status()
        self._update_timer = _single_shot(self, 0, self._flush_update)
        self._idle_timer = _single_shot(self, IDLE_MS, self.flush)
        self._live_timer = _single_shot(self, 0, self._follow_live)
        self._refine_timer = QtCore.QTimer(self)
        self._refine_timer.setInterval(REFINE_MS)
        self._refine_timer.timeout.connect(self.refine_tick)
        # The reference's ticks begin once the views have rested IDLE_MS after their last change: a burst of keys
        # or clicks spends nothing on passes that its next event would discard.
        self._rest_timer = _single_shot(self, IDLE_MS, self._start_ticks)
        self._ticking = False
        self.resize(*window_size)
        self.refresh()
        if self.state.environment != "none":  # started under a sky: its exposure, as a switch would choose it
            self._show(self.model.apply_auto_exposure())
            self.controls.sync(self.state)

    # ------------------------------------------------------------------ building
    @property
    def state(self) -> AppState:
        """The controls (the model's state)."""
        return self.model.state

    def _build_views(self, interactive_3d):
        self.sphere_panel = ImagePanel("Lit sphere", warning_line=True)
        self.sphere_panel.canvas.overlay = self._sphere_overlay
        self.gouraud_panel = ImagePanel("Gouraud: lit at the vertices")
        self.gouraud_panel.canvas.overlay = self._coarse_overlay
        self.phong_panel = ImagePanel("Phong interpolation: lit at every pixel")
        self.phong_panel.canvas.overlay = self._coarse_overlay
        self.profile_canvas = PlotCanvas(ProfilePlot)
        self.profile_panel = ImagePanel("Scan line", self.profile_canvas)
        self.lobe_view = LobeView3D(interactive=interactive_3d)
        # The lit object is a picture in the 3D panel's place (its title and caption are the panel's).
        self.object_canvas = ImageCanvas()
        self.stack3d = QtWidgets.QStackedWidget()
        self.stack3d.addWidget(self.lobe_view)
        self.stack3d.addWidget(self.object_canvas)
        self.lobe_panel = ImagePanel("3D lobe", self.stack3d)
        self.polar_canvas = PlotCanvas(PolarPlot)
        self.polar_panel = ImagePanel("Polar slice", self.polar_canvas)
        self.albedo_label = WrapLabel(max_lines=2)
        self.polar_panel.adaptive_labels.append((self.albedo_label, 1, 2))
        self.polar_panel.layout().insertWidget(1, self.albedo_label)
        self.angle_canvas = PlotCanvas(AnglePlotsGrid)
        self.albedo_canvas = PlotCanvas(AlbedoPlot)
        self.stack_plots = QtWidgets.QStackedWidget()
        self.stack_plots.addWidget(self.angle_canvas)
        self.stack_plots.addWidget(self.albedo_canvas)
        self.angles_panel = ImagePanel("Angle curves", self.stack_plots)
        top = _splitter(QtCore.Qt.Orientation.Horizontal,
                        [self.sphere_panel, self.gouraud_panel, self.phong_panel, self.profile_panel])  # fmt: skip
        bottom = _splitter(QtCore.Qt.Orientation.Horizontal, [self.lobe_panel, self.polar_panel, self.angles_panel])
        for k, stretch in enumerate((4, 4, 4, 5)):
            top.setStretchFactor(k, stretch)
        for k, stretch in enumerate((5, 4, 5)):
            bottom.setStretchFactor(k, stretch)
        central = _splitter(QtCore.Qt.Orientation.Vertical, [top, bottom])
        central.setObjectName("views")
        self.setCentralWidget(central)

    def _build_docks(self):
        self.controls = ControlPanel(self.state)
        self.controls.change_requested.connect(self.apply)
        self.lights_panel = LightsPanel(self.state)
        self.lights_panel.change_requested.connect(self.apply)
        if hasattr(self.lights_panel, "section_requested"):
            self.lights_panel.section_requested.connect(self._show_section)
        self.compare_panel = ComparePanel(self.model.compare)
        self.compare_panel.action_requested.connect(self.compare_action)
        self.docks = {}
        previous = None
        for name, widget in (("Controls", self.controls), ("Lights", self.lights_panel),
                             ("Compare", self.compare_panel)):  # fmt: skip
            dock = QtWidgets.QDockWidget(name, self)
            dock.setObjectName(f"dock{name}")
            dock.setWidget(widget)
            dock.setFeatures(QtWidgets.QDockWidget.DockWidgetFeature.DockWidgetMovable
                             | QtWidgets.QDockWidget.DockWidgetFeature.DockWidgetFloatable)  # fmt: skip
            self.addDockWidget(QtCore.Qt.DockWidgetArea.RightDockWidgetArea, dock)
            if previous is not None:
                self.tabifyDockWidget(previous, dock)
            previous = dock
            self.docks[name] = dock
        self.docks["Controls"].raise_()
        self.resizeDocks([self.docks["Controls"]], [340], QtCore.Qt.Orientation.Horizontal)

    def _build_status(self):
        self.message_label = QtWidgets.QLabel()
        self.message_label.setTextFormat(QtCore.Qt.TextFormat.PlainText)
        self.message_label.setSizePolicy(QtWidgets.QSizePolicy.Policy.Ignored,
                                         QtWidgets.QSizePolicy.Policy.Preferred)  # fmt: skip
        self.refine_label = QtWidgets.QLabel()
        self.statusBar().addWidget(self.message_label, 1)
        self.statusBar().addPermanentWidget(self.refine_label)

    def _build_actions(self):
        from .keys import build_actions

        self.actions_by_key = build_actions(self)

    # ------------------------------------------------------------------ state changes
    def apply(self, changes: dict, live: bool = False) -> bool:
        """Apply ``changes`` to the state (validated); show the views that follow.

        Parameters
        ----------
        changes : dict
            Control or parameter name → new value (as :meth:`AppState.update` takes them).
        live : bool
            A slider being dragged: only the engine's images follow now, the rest on release.

        Returns
        -------
        bool
            False when the state refused a value: the message is shown in the status bar and every
            widget returns to the state's value.
        """
        try:
            changed = self.state.update(**changes)
        except (ValueError, TypeError) as exc:
            self.show_error(str(exc))
            self.sync_widgets()
            return False
        self.clear_error()
        if "environment" in changed:
            self._environment_switched = True
        if changed - {"params"} or "params" in changed and not live:
            self.sync_widgets(changed)
        if live:
            # The lit sphere first, painted at once: it is where the eye is.  The coarse spheres follow when
            # the loop is next idle, so a fast drag never queues their work behind the sphere's.
            self._show(self.model.update(only={"sphere"}))
            self.sphere_panel.canvas.repaint()
            self._live_timer.start()
            self._idle_timer.start()
        else:
            self.schedule_update()
        return True

    def set_control(self, name: str, value, *, live: bool = False) -> bool:
        """One control or parameter (what a key or a test sets); see :meth:`apply`."""
        return self.apply({name: value}, live)

    def sync_widgets(self, changed=None) -> None:
        """Every widget shows the state's value (after a refusal, a key, a file opened)."""
        self.controls.sync(self.state)
        if changed is None or changed & {"scene_lights", "light", "environment", "ambient"}:
            self.lights_panel.sync(self.state)

    def schedule_update(self) -> None:
        """Update the views once control returns to the event loop (key bursts coalesce)."""
        self._update_timer.start()

    def _flush_update(self):
        self.flush()

    def _follow_live(self):
        self._show(self.model.update(only=LIVE_VIEWS))

    def flush(self) -> set[str]:
        """Update every stale view now (a slider released or resting, a key, a file opened).

        Returns
        -------
        set of str
            The views recomputed.
        """
        self._update_timer.stop()
        self._idle_timer.stop()
        self._live_timer.stop()
        views = self.model.update()
        if self._environment_switched:
            # A sky never whites out the sphere: the exposure follows the light (and returns when it is off).
            self._environment_switched = False
            views |= self.model.apply_auto_exposure()
            self.controls.sync(self.state)
        self._show(views)
        return views

    def refresh(self) -> set[str]:
        """Recompute and show every view."""
        views = self.model.refresh()
        self._show(views, everything=True)
        return views

    def reset(self) -> None:
        """Every control back to its default."""
        self.state.reset()
        self.sync_widgets()
        self.schedule_update()

    def show_error(self, text: str) -> None:
        """A refusal or failure, in the status bar (whole text in its tooltip)."""
        self.last_error = text
        self.message_label.setStyleSheet("color: #ff8787;")
        self.message_label.setText(text)
        self.message_label.setToolTip(text)

    def show_message(self, text: str) -> None:
        """A note in the status bar."""
        self.message_label.setStyleSheet("")
        self.message_label.setText(text)
        self.message_label.setToolTip(text)

    def clear_error(self) -> None:
        if self.last_error:
            self.last_error = ""
            self.show_message("")

    def _show_section(self, name: str) -> None:
        self.docks["Controls"].raise_()
        if hasattr(self.controls, "show_section"):
            self.controls.show_section(name)

    # ------------------------------------------------------------------ comparison list
    def compare_action(self, action: str, arg=None) -> None:
        """What the Compare panel asks: ``pin``, ``fit``, ``remove``, ``visible``, ``solo``."""
        compare = self.model.compare
        try:
            if action == "pin":
                self.model.pin()
            elif action == "fit":
                self.fit()
                return
            elif action == "remove":
                compare.remove(_index_of(compare, arg))
            elif action == "visible":
                key, on = arg
                compare.set_visible(_index_of(compare, key), bool(on))
            elif action == "solo":
                compare.set_solo(None if arg is None else _index_of(compare, arg))
            else:
                raise ValueError(f"compare action must be pin, fit, remove, visible or solo; got {action!r}")
        except (ValueError, IndexError, KeyError) as exc:
            self.show_error(str(exc))
        # Rebuilding the rows happens after this signal's handler returns (the × clicked is one of them).
        QtCore.QTimer.singleShot(0, lambda: self.compare_panel.sync(self.model.compare))
        self.schedule_update()

    def fit(self) -> None:
        """Fit the ``fit`` control's model to the current one (seconds) and add it to the Compare list."""
        QtWidgets.QApplication.setOverrideCursor(QtCore.Qt.CursorShape.WaitCursor)
        self.show_message(f"fitting {self.state.fit} to the current model …")
        QtWidgets.QApplication.processEvents(QtCore.QEventLoop.ProcessEventsFlag.ExcludeUserInputEvents)
        try:
            entry, _ = self.model.fit()
            self.show_message(f"fitted: {entry.label}")
        except (ValueError, RuntimeError) as exc:
            self.show_error(str(exc))
        finally:
            QtWidgets.QApplication.restoreOverrideCursor()
        self.compare_panel.sync(self.model.compare)
        self.schedule_update()

    # ------------------------------------------------------------------ files
    def open_file(self, kind: str, path: str) -> bool:
        """Open a file of ``kind`` (``scene``, ``brdf``, ``environment``, ``mesh``); a bad file is shown, not raised.

        Returns
        -------
        bool
            Whether the file was opened.
        """
        try:
            if kind == "scene":
                from ..app.scenes import scene_environment_file, state_from_scene

                new = state_from_scene(path)
                env = scene_environment_file(path)
                if env is not None:
                    self.model.open_environment(env)
                self.state.update(**{k: v for k, v in new.to_dict().items() if k != "params"},
                                  params=new.params)  # fmt: skip
            elif kind == "brdf":
                self.model.open_brdf(path, current=True)
            elif kind == "environment":
                self.model.open_environment(path)
                self.state.environment = "file"
                self._environment_switched = True  # the exposure follows the new light
            elif kind == "mesh":
                self.model.open_mesh(path)
                self.state.view3d = "object"
            else:
                raise ValueError(f"file kind must be scene, brdf, environment or mesh; got {kind!r}")
        except (ValueError, OSError) as exc:
            self.show_error(str(exc))
            return False
        self.show_message(f"opened {os.path.basename(str(path))}")
        self.sync_widgets()
        self.compare_panel.sync(self.model.compare)
        self.schedule_update()
        return True

    # ------------------------------------------------------------------ showing the views
    def _show(self, views, *, everything: bool = False) -> None:
        self.updates += 1
        s, m = self.state, self.model.views
        self.setWindowTitle(captions.window_title(s))
        if "sphere" in views:
            sv = m["sphere"]
            self._extra_light_dirs = self._scene_light_directions()
            self.sphere_panel.canvas.set_image(sv.rgb8)
            self.sphere_panel.set_title(captions.sphere_title(s, sv))
            # The clipping note is a warning line of its own; the rest of the caption stays muted.
            parts = (captions.sphere_legend(s, sv), captions.sphere_caption(s, sv, self.model, clipping=False))
            self.sphere_panel.set_warning(captions.clipped_note(sv).strip())
            self.sphere_panel.set_caption("\n".join(t for t in parts if t))
        if "coarse" in views:
            cv = m["coarse"]
            self.gouraud_panel.canvas.set_image(cv.gouraud_rgb8)
            self.phong_panel.canvas.set_image(cv.phong_rgb8)
            self.gouraud_panel.set_title(captions.coarse_title(s))
            # The coarse spheres teach interpolation under the key light: a sky does not light them, say so.
            lit_by_sky = self.model.environment_active
            sky = "\nkey light and ambient only (the sky lights the lit sphere)" if lit_by_sky else ""
            self.gouraud_panel.set_caption(captions.coarse_caption(cv) + sky)
            self.phong_panel.set_title(captions.phong_title(s))
            self.phong_panel.set_caption(captions.phong_caption(s) + sky)
        if "profile" in views:
            pv = m["profile"]
            self.profile_canvas.show_data(pv, captions.channel_label(s))
            self.profile_panel.set_title(captions.profile_title(s))
            self.profile_panel.set_caption(captions.profile_caption(pv))
            self.gouraud_panel.canvas.update()
            self.phong_panel.canvas.update()
        label = s.quantity_label()
        if "lobe" in views:
            lv = m["lobe"]
            self.lobe_view.set_lobe(lv)
            self.lobe_panel.set_title(captions.lobe_title(s, lv))
            self.lobe_panel.set_caption(captions.lobe_caption(s, lv))
        if "object" in views and "object" in m:
            ov = m["object"]
            self.object_canvas.set_image(ov.rgb8)
        self.stack3d.setCurrentIndex(1 if s.view3d == "object" else 0)
        if s.view3d == "object":
            ov = m.get("object")
            self.lobe_panel.set_title(captions.object_title(s, ov) if ov is not None else "Lit object")
            # The lobe's caption names arrows the lit object does not show: the object's own caption instead.
            self.lobe_panel.set_caption(captions.object_caption(s, ov, self.model) if ov is not None else "")
        elif "lobe" in m:  # back from the object: the lobe's title again, though the lobe itself did not change
            self.lobe_panel.set_title(captions.lobe_title(s, m["lobe"]))
            self.lobe_panel.set_caption(captions.lobe_caption(s, m["lobe"]))
        if "polar" in views:
            pv = m["polar"]
            self.polar_canvas.show_data(pv, channel=s.channel, label=label)
            self.polar_panel.set_title(captions.polar_title(s, pv))
            note = captions.polar_note(s, pv)
            caption = captions.polar_caption(s, pv, self.polar_canvas.plot.captions)
            self.polar_panel.set_caption("\n".join(t for t in (note, caption) if t), warn=bool(note))
        if "albedo" in views:
            av = m["albedo"]
            warn = bool(av.unconverged or getattr(av, "above_one", False))
            self.albedo_label.set_full_text(captions.albedo_caption(av))
            if self.albedo_label.property("warn") != warn:
                self.albedo_label.setProperty("warn", warn)
                self.albedo_label.setStyleSheet(f"color: {'#ff8787' if warn else '#9aa1a9'};")
        switched = getattr(self, "_panel_shown", None) != s.panel
        self._panel_shown = s.panel
        if s.panel == "albedo":
            self.stack_plots.setCurrentIndex(1)
            if "albedo" in views or switched or everything:
                av = m["albedo"]
                self.albedo_canvas.show_data(av.curves, channel=s.channel, invalidate=switched)
                self.angles_panel.set_title(captions.albedo_panel_title(s, self.albedo_canvas.plot.captions))
                self.angles_panel.set_caption(self.albedo_canvas.plot.captions.get("flags", ""))
        else:
            self.stack_plots.setCurrentIndex(0)
            if views & {"theta_v", "theta_h", "theta_d", "halfdiff"} or switched or everything:
                self.angle_canvas.show_data(m["theta_v"], m["theta_h"], m["theta_d"], m["halfdiff"],
                                            channel=s.channel, label=label, invalidate=switched)  # fmt: skip
                self.angles_panel.set_title(captions.angles_title(s, m["theta_v"]))
                self.angles_panel.set_caption(self.angle_canvas.plot.captions.get("peak", ""))
        self._update_refinement()

    # ------------------------------------------------------------------ overlays on the images
    def _sphere_overlay(self, p: QtGui.QPainter, scale: float) -> None:
        s = self.state
        sv = self.model.views.get("sphere")
        if sv is None:
            return
        h, w = sv.rgb8.shape[:2]
        cx, cy, r = 0.5 * w, 0.5 * h, 0.5 * h / 1.08  # sphere_camera: the unit sphere fills 1/1.08
        if getattr(sv, "split", ""):
            # The divider through the centre along the split's angle (degrees from image right toward image up).
            angle = math.radians(sv.split_angle)
            p.setPen(QtGui.QPen(QtGui.QColor(sv.split_colour or "#adb5bd"), 2.0 / scale))
            dx, dy = math.cos(angle), -math.sin(angle)
            p.drawLine(QtCore.QPointF(cx - 1.04 * r * dx, cy - 1.04 * r * dy),
                       QtCore.QPointF(cx + 1.04 * r * dx, cy + 1.04 * r * dy))  # fmt: skip
        self._scene_light_marks(p, scale, cx, cy, r)
        if s.light == "ambient":
            return
        d = s.light_direction()
        # The light's arrow outside the sphere's outline, pointing at it (image y grows downward).
        tip = np.array([cx + 1.02 * r * d[0], cy - 1.02 * r * d[1]])
        tail = np.array([cx + 1.32 * r * d[0], cy - 1.32 * r * d[1]])
        if math.hypot(d[0], d[1]) < 0.15:  # from straight ahead or behind: a ring marks it
            style = QtCore.Qt.PenStyle.SolidLine if d[2] > 0 else QtCore.Qt.PenStyle.DashLine
            pen = QtGui.QPen(ACCENT, 2.0 / scale, style)
            p.setPen(pen)
            p.setBrush(QtCore.Qt.BrushStyle.NoBrush)
            p.drawEllipse(QtCore.QPointF(cx, cy), 0.08 * r, 0.08 * r)
            return
        _arrow(p, tail, tip, ACCENT, scale, dashed=d[2] < 0)

    def _scene_light_directions(self) -> list:
        """Unit directions from the sphere's centre toward each extra light (its position, centre or direction)."""
        from ..app.lights import engine_lights

        out = []
        for k, table in enumerate(self.state.scene_lights):
            for light in engine_lights(table, k):
                where = next((getattr(light, a) for a in ("position", "center") if hasattr(light, a)), None)
                d = np.asarray(where if where is not None else getattr(light, "direction", (0, 0, 0)), float)
                length = float(np.linalg.norm(d))
                if np.all(np.isfinite(d)) and length > 0.0:
                    out.append(d / length)
        return out

    def _scene_light_marks(self, p: QtGui.QPainter, scale: float, cx: float, cy: float, r: float) -> None:
        """A small open marker for each extra light, at its direction seen from the sphere's centre."""
        p.setPen(QtGui.QPen(EXTRA, 2.0 / scale))
        p.setBrush(QtCore.Qt.BrushStyle.NoBrush)
        for d in self._extra_light_dirs:  # found when the sphere was shown, not at every paint
            n = float(np.linalg.norm(d[:2]))
            if n < 1e-9:  # in front of or behind the centre: a ring around it
                p.drawEllipse(QtCore.QPointF(cx, cy), 0.12 * r, 0.12 * r)
                continue
            at = QtCore.QPointF(cx + 1.02 * r * d[0] / n, cy - 1.02 * r * d[1] / n)  # on the outline
            p.drawRect(QtCore.QRectF(at.x() - 0.045 * r, at.y() - 0.045 * r, 0.09 * r, 0.09 * r))

    def _coarse_overlay(self, p: QtGui.QPainter, scale: float) -> None:
        cv = self.model.views.get("coarse")
        if cv is None:
            return
        h, w = cv.triangle_id.shape
        if self.show_edges:
            # The triangle edges: where the triangle id changes between neighbouring pixels.  They follow the
            # tessellation and the image size alone, so a drag (a new view every move) reuses them.
            key = (cv.tessellation, cv.triangle_id.shape)
            if self._edge_key != key:
                tid = cv.triangle_id
                edge = np.zeros_like(tid, dtype=bool)
                edge[:, 1:] |= (tid[:, 1:] != tid[:, :-1]) & (tid[:, 1:] >= 0) & (tid[:, :-1] >= 0)
                edge[1:, :] |= (tid[1:, :] != tid[:-1, :]) & (tid[1:, :] >= 0) & (tid[:-1, :] >= 0)
                rgba = np.zeros((h, w, 4), dtype=np.uint8)
                rgba[edge] = (20, 22, 26, 150)
                from .images import qimage

                self._edge_image = qimage(rgba)
                self._edge_key = key
            p.drawImage(QtCore.QRectF(0, 0, w, h), self._edge_image)
        pv = self.model.views.get("profile")
        if pv is not None:
            y = pv.row + 0.5
            p.setPen(QtGui.QPen(SCANLINE, 2.0 / scale))
            p.drawLine(QtCore.QPointF(0, y), QtCore.QPointF(w, y))

    # ------------------------------------------------------------------ the Monte-Carlo reference
    def _update_refinement(self) -> None:
        refining = bool(getattr(self.model, "refining", False))
        if not refining:
            self._rest_timer.stop()
            self._refine_timer.stop()
        elif self._ticking:  # the reference's own new image: its ticks go on
            if not self._refine_timer.isActive():
                self._refine_timer.start()
        else:  # the views changed: the ticks wait until they rest again
            self._refine_timer.stop()
            self._rest_timer.start()
        caption = self.model.refine_caption() if hasattr(self.model, "refine_caption") else ""
        self.refine_label.setText(caption)
        self.refine_label.setToolTip(caption)

    def _start_ticks(self) -> None:
        if getattr(self.model, "refining", False):
            self._refine_timer.start()

    def refine_tick(self, budget: float = REFINE_BUDGET) -> set[str]:
        """One step of the Monte-Carlo reference (the timer's tick): more samples, the images shown.

        Returns
        -------
        set of str
            The views that changed.
        """
        self._ticking = True
        try:
            views = self.model.refine(budget)
            if views:
                self._show(views)
            else:
                self._update_refinement()
        finally:
            self._ticking = False
        return views

    # ------------------------------------------------------------------ pictures
    def image(self) -> np.ndarray:
        """The whole window's pixels, ``(H, W, 3)`` uint8 (the 3D view included, whatever draws it)."""
        QtWidgets.QApplication.processEvents()
        if not self.lobe_view.interactive and self.lobe_view.isVisible():
            self.lobe_view.redraw()  # at the panel's size now (a resize may still be pending)
        pix = self.grab()
        if self.lobe_view.interactive and self.lobe_view.isVisible():
            # A native OpenGL child is not in grab(): paint VTK's own frame where the view is.
            shot = self.lobe_view.image()
            from .images import qimage

            painter = QtGui.QPainter(pix)
            top_left = self.lobe_view.mapTo(self, QtCore.QPoint(0, 0))
            target = QtCore.QRectF(top_left.x(), top_left.y(), self.lobe_view.width(), self.lobe_view.height())
            painter.drawImage(target, qimage(shot))
            painter.end()
        img = pix.toImage().convertToFormat(QtGui.QImage.Format.Format_RGB888)
        w, h = img.width(), img.height()
        ptr = img.constBits()
        a = np.frombuffer(ptr, dtype=np.uint8, count=img.sizeInBytes()).reshape(h, img.bytesPerLine())
        # A copy: the rows live in the QImage, which goes when this returns (a view of them would be freed memory).
        return a[:, : 3 * w].reshape(h, w, 3).copy()

    def screenshot(self, path=None) -> str:
        """Write the window to a PNG (atomically; default: a new ``lighting-explorer-N.png`` here).

        Returns
        -------
        str
            The path written.
        """
        from ..output import write_image

        if path is None:
            k = 1
            while os.path.exists(f"lighting-explorer-{k}.png"):
                k += 1
            path = f"lighting-explorer-{k}.png"
        write_image(path, rgb8=self.image(), flag="--screenshot")
        self.show_message(f"wrote {path}")
        return str(path)

    def export_views(self, folder, fmt: str = "png") -> list[str]:
        """Write the current views into ``folder``: the plots as figures in ``fmt``, the engine's images as PNG.

        Parameters
        ----------
        folder : str or os.PathLike
            An existing folder.
        fmt : {"png", "svg", "pdf"}
            The plots' format (the images are pixels: always PNG).

        Returns
        -------
        list of str
            The files written (each atomically: a failure leaves no partial file).
        """
        import io

        from ..output import atomic_write_many, encode_image

        fmt = str(fmt).lower()
        if fmt not in ("png", "svg", "pdf"):
            raise ValueError(f"format must be png, svg or pdf; got {fmt!r}")
        m = self.model.views
        items = []
        for name, view, attr in (("sphere", "sphere", "rgb8"), ("gouraud", "coarse", "gouraud_rgb8"),
                                 ("phong", "coarse", "phong_rgb8"), ("object", "object", "rgb8")):  # fmt: skip
            if view in m and (view != "object" or self.state.view3d == "object"):
                data = encode_image("png", rgb8=np.ascontiguousarray(getattr(m[view], attr)))
                items.append((os.path.join(folder, f"{name}.png"), data))
        if self.state.view3d == "lobe":
            items.append((os.path.join(folder, "lobe.png"), encode_image("png", rgb8=self.lobe_view.image())))
        plots = [("profile", self.profile_canvas), ("polar", self.polar_canvas),
                 ("albedo" if self.state.panel == "albedo" else "angles",
                  self.albedo_canvas if self.state.panel == "albedo" else self.angle_canvas)]  # fmt: skip
        for name, canvas in plots:
            buf = io.BytesIO()
            fig = canvas.plot.fig
            fig.savefig(buf, format=fmt, facecolor="#1e2024")
            items.append((os.path.join(folder, f"{name}.{fmt}"), buf.getvalue()))
        atomic_write_many(items, flag="export")
        paths = [p for p, _ in items]
        self.show_message(f"wrote {len(paths)} files to {folder}")
        return paths

    def closeEvent(self, event):  # noqa: N802 - Qt's name
        self._rest_timer.stop()
        self._refine_timer.stop()
        self._update_timer.stop()
        self._idle_timer.stop()
        self._live_timer.stop()
        self.lobe_view.close_view()
        super().closeEvent(event)


# =============================================================================== helpers
def _single_shot(parent, ms, slot) -> QtCore.QTimer:
    t = QtCore.QTimer(parent)
    t.setSingleShot(True)
    t.setInterval(ms)
    t.timeout.connect(slot)
    return t


def _splitter(orientation, widgets) -> QtWidgets.QSplitter:
    s = QtWidgets.QSplitter(orientation)
    s.setChildrenCollapsible(False)
    for w in widgets:
        s.addWidget(w)
    return s


def _index_of(compare, key) -> int:
    for k, entry in enumerate(compare):
        if entry.key == key:
            return k
    raise KeyError(f"no entry {key!r} in the Compare list")


def _arrow(p: QtGui.QPainter, tail, tip, colour, scale, *, dashed=False):
    pen = QtGui.QPen(colour, 3.0 / scale)
    pen.setCapStyle(QtCore.Qt.PenCapStyle.RoundCap)
    if dashed:
        pen.setStyle(QtCore.Qt.PenStyle.DashLine)
    p.setPen(pen)
    p.drawLine(QtCore.QPointF(*tail), QtCore.QPointF(*tip))
    d = np.asarray(tip) - np.asarray(tail)
    d = d / max(np.linalg.norm(d), 1e-9)
    n = np.array([-d[1], d[0]])
    head = 12.0 / scale
    a = np.asarray(tip) - head * d + 0.5 * head * n
    b = np.asarray(tip) - head * d - 0.5 * head * n
    p.setBrush(colour)
    p.setPen(QtCore.Qt.PenStyle.NoPen)
    p.drawPolygon(QtGui.QPolygonF([QtCore.QPointF(*tip), QtCore.QPointF(*a), QtCore.QPointF(*b)]))

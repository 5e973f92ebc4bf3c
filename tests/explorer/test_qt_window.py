"""The explorer's Qt window driven through its real widgets: keys, clicks, drags, resizes, files.

Each test plays what a student does (pytest-qt's ``qtbot``: key clicks on the window, mouse presses and drags
on sliders, clicks on check boxes and buttons) and checks what the window then holds and shows: the state,
the texts of its labels, the engine's images, the widgets' places.  One small window serves every test of
this file (building one costs seconds); each test starts from the default controls, an empty Compare list
and the window's first size.  ``test_qt_window_full.py`` holds the longer tests (every window size, the
event storm, the process-level signals).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import textwrap
import time

import pytest

if not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY"):
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
pytest.importorskip("PySide6")
pytest.importorskip("pyvistaqt")
pytest.importorskip("pytestqt")

import numpy as np  # noqa: E402
import shiboken6  # noqa: E402 (after the platform is chosen)
from PySide6 import QtCore, QtGui, QtTest, QtWidgets  # noqa: E402
from qt_window_support import click_box, groove_and_handle  # noqa: E402

from explorer.app import captions  # noqa: E402
from explorer.app.state import MODELS  # noqa: E402
from lighting.analysis.machband import LUMA  # noqa: E402

LEFT = QtCore.Qt.MouseButton.LeftButton
#: The window's first size, and the engine's image sizes: small, for speed.
SIZE = (1024, 640)
SMALL = {"sphere_size": 96, "mesh_size": 96, "lobe_resolution": 16}


# =============================================================================== fixtures and helpers
@pytest.fixture(scope="session")
def qapp():
    """The explorer's QApplication (Fusion style, its palette), the one pytest-qt's ``qtbot`` uses."""
    from explorer.qt.app import qt_application

    return qt_application()


def make_window(size=SIZE, **kwargs):
    """A new explorer window of ``size``, shown, its first views drawn."""
    from explorer.qt.window import ExplorerWindow

    window = ExplorerWindow(window_size=size, **{**SMALL, **kwargs})
    window.show()
    activate(window)
    settle()
    return window


def activate(window) -> None:
    """Make ``window`` the active window (its keys are window shortcuts); an X server without a window manager
    does not activate a window that is shown."""
    if QtWidgets.QApplication.activeWindow() is not window:
        window.activateWindow()
        window.raise_()
        assert QtTest.QTest.qWaitForWindowActive(window, 5000)


@pytest.fixture(scope="module")
def shared_window(qapp):
    window = make_window()
    yield window
    window.close()
    window.deleteLater()
    settle()


@pytest.fixture
def window(shared_window, qtbot):
    """The module's window at its first size, every control at its default and the Compare list empty."""
    w = shared_window
    dialog = getattr(w, "help_dialog", None)
    if dialog is not None and shiboken6.isValid(dialog) and dialog.isVisible():
        dialog.close()
    compare = w.model.compare
    compare.set_solo(None)
    while len(compare):
        compare.remove(0)
    w.state.reset()
    w.show_edges = True
    w.resize(*SIZE)
    w.sync_widgets()
    w.compare_panel.sync(compare)
    w.clear_error()
    w.flush()
    w.docks["Controls"].raise_()
    settle()
    activate(w)
    w.setFocus()
    yield w
    settle()


def settle(passes: int = 8) -> None:
    """Let posted events, deferred deletions and nested layouts finish (each pass settles one more level)."""
    app = QtWidgets.QApplication.instance()
    for _ in range(passes):
        app.sendPostedEvents(None, QtCore.QEvent.Type.DeferredDelete.value)
        app.processEvents()


def current(window) -> None:
    """Every view up to date: the pending key update and any resting slider's update run now."""
    settle()
    window.flush()
    settle()


def press(qtbot, window, key: str, times: int = 1) -> None:
    """Key clicks on the window, as typed: ``"m"``, ``"Shift+M"``, ``"Up"``."""
    seq = QtGui.QKeySequence(key)[0]
    if isinstance(window, QtWidgets.QMainWindow):
        activate(window)
    for _ in range(times):
        qtbot.keyClick(window, seq.key(), seq.keyboardModifiers())






def scroll_to(window, widget) -> None:
    """Bring a control into the control panel's view (the Controls tab raised)."""
    window.docks["Controls"].raise_()
    settle()
    window.controls.ensureWidgetVisible(widget, 10, 40)
    settle()


def type_number(qtbot, window, name: str, text: str) -> None:
    """Type a number into a control's spin box and press Enter."""
    editor = window.controls.widget(name)
    scroll_to(window, editor)
    line = editor.spin.lineEdit()
    line.setFocus()
    line.selectAll()
    qtbot.keyClicks(line, text)
    qtbot.keyClick(line, QtCore.Qt.Key.Key_Return)


def choose(window, name: str, value) -> None:
    """Pick an item of a control's combo box (as choosing it in the drop-down does)."""
    combo = window.controls.widget(name)
    index = combo.findData(value)
    assert index >= 0, (name, value)
    combo.setCurrentIndex(index)


def rect_in(widget, root) -> QtCore.QRect:
    """A widget's rectangle in ``root``'s coordinates."""
    return QtCore.QRect(widget.mapTo(root, QtCore.QPoint(0, 0)), widget.size())


def on_screen(widget) -> bool:
    """Whether a widget shows on screen: visible, and not in a dock's hidden tab or scrolled out of view (a tabbed
    dock's other widgets stay "visible" to Qt, with nothing of them on screen)."""
    return widget.isVisible() and not widget.visibleRegion().isEmpty()


def visible_widgets(window) -> list:
    """The window's widgets shown on screen (its own children; no top-level windows such as the help)."""
    return [w for w in window.findChildren(QtWidgets.QWidget) if not w.isWindow() and on_screen(w)]


def widget_census(window):
    """What is shown, by widget type and parent type, counted."""
    from collections import Counter

    return Counter((type(w).__name__, type(w.parentWidget()).__name__, w.objectName()) for w in visible_widgets(window))


def full(label) -> str:
    """A title's or caption's whole text (a panel's label may show it cut to a few lines, whole in its tooltip)."""
    return label.full_text() if hasattr(label, "full_text") else label.text()


def sphere_luminance(window) -> np.ndarray:
    return np.asarray(window.model.views["sphere"].image, dtype=np.float64) @ LUMA


# =============================================================================== 1b. PySide6's slot calls
SLOT_LOOP = textwrap.dedent("""
    import sys
    from explorer.qt.app import qt_application
    from PySide6 import QtCore

    app = qt_application(off_screen=True)
    calls = [0]
    def tick():
        calls[0] += 1
        if calls[0] == CALLS:
            timer.stop()
            app.quit()
    timer = QtCore.QTimer()
    timer.setInterval(0)
    timer.timeout.connect(tick)
    before = sys.getrefcount(None)
    timer.start()
    app.exec()
    print(calls[0], before - sys.getrefcount(None))
""")


def test_five_thousand_timer_slot_calls_leave_the_process_alive():
    # PySide6 6.12.0 drops a reference to None at every slot call: on Python 3.11 (None is not immortal) the
    # process dies once None's count reaches zero.  The loop runs in a process of its own.
    calls = 5000
    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen"}
    out = subprocess.run([sys.executable, "-c", SLOT_LOOP.replace("CALLS", str(calls))], capture_output=True,
                         text=True, timeout=120, env=env)  # fmt: skip
    assert out.returncode == 0, out.stderr[-2000:]
    done, lost = (int(x) for x in out.stdout.split())
    assert done == calls
    assert lost < calls // 10  # a reference lost per call would show as 5000


# =============================================================================== 5. no stray widget
def test_shading_mode_keys_leave_the_same_widgets_and_nothing_over_the_polar_caption(qtbot, window):
    before = widget_census(window)
    modes = [window.state.mode]
    for _ in range(3):
        press(qtbot, window, "i")
        current(window)
        modes.append(window.state.mode)
        assert widget_census(window) == before  # the mode shows and hides nothing
    assert modes[0] == modes[3] and len(set(modes)) == 3  # flat, Gouraud, Phong and back
    assert [w for w in QtWidgets.QApplication.topLevelWidgets() if w.isVisible() and w is not window] == []
    caption = window.polar_panel.caption
    assert caption.isVisible() and caption.text()
    where = rect_in(caption, window)
    over = [w for w in visible_widgets(window) if w is not caption and not w.isAncestorOf(caption)
            and rect_in(w, window).intersects(where)]  # fmt: skip
    assert over == [], [(type(w).__name__, rect_in(w, window)) for w in over]


# =============================================================================== 7. input
def test_twelve_quick_model_keys_step_twelve_models_in_one_update(qtbot, window):
    models = list(MODELS)
    start = models.index(window.state.model)
    updates = window.updates
    t0 = time.perf_counter()
    press(qtbot, window, "m", 12)
    assert window.state.model == models[(start + 12) % len(models)]
    qtbot.waitUntil(lambda: window.updates > updates and not window._update_timer.isActive(), timeout=2000)
    elapsed = time.perf_counter() - t0
    assert window.updates - updates <= 3  # the burst coalesced into one update of the views
    assert elapsed < 2.0
    assert window.controls.widget("model").currentData() == window.state.model
    assert window.windowTitle() == captions.window_title(window.state)


def test_press_on_a_slider_track_then_drag_follows_the_pointer(qtbot, window):
    editor = window.controls.widget("elevation")
    slider = editor.slider
    scroll_to(window, slider)
    requests = []
    window.controls.change_requested.connect(lambda changes, live: requests.append((dict(changes), live)))
    groove, handle = groove_and_handle(slider)
    x, y = groove.left() + groove.width() // 5, groove.center().y()
    assert abs(x - handle.center().x()) > 3 * handle.width()
    updates = window.updates
    qtbot.mousePress(slider, LEFT, pos=QtCore.QPoint(x, y))
    jumped = editor.from_position(slider.value())
    assert jumped < 45.0 - 30.0 and window.state.elevation == jumped  # the knob jumped under the pointer
    assert requests == [({"elevation": jumped}, True)]
    assert window.updates > updates  # the lit sphere follows at once
    for dx in (20, 40, 60):
        qtbot.mouseMove(slider, QtCore.QPoint(x + dx, y))
        assert window.state.elevation == editor.from_position(slider.value())
    live = [c["elevation"] for c, is_live in requests if is_live]
    assert len(live) >= 4 and live == sorted(live) and len(set(live)) == len(live)
    qtbot.mouseRelease(slider, LEFT, pos=QtCore.QPoint(x + 60, y))
    final = editor.from_position(slider.value())
    assert requests[-1] == ({"elevation": final}, False) and final == live[-1]
    current(window)
    assert window.state.elevation == final and editor.spin.value() == pytest.approx(final)
    assert not window.model.pending  # the plots followed the release
    assert captions.incidence(window.state) in full(window.polar_panel.title)


# =============================================================================== 8. refusals
def test_a_refused_drag_puts_knob_and_spin_back_and_the_lock_box_follows_the_state(qtbot, window):
    assert window.apply({"model": "cook-torrance", "ndf": "blinn-phong", "alpha_x": 0.5, "alpha_y": 0.5})
    current(window)
    editor = window.controls.widget("alpha_x")
    lock = window.controls.widget("alpha_y").none_box
    scroll_to(window, editor)
    slider = editor.slider
    home = editor.to_position(0.5)
    assert slider.value() == home and not lock.isChecked() and window.state.alpha_y == 0.5
    _, handle = groove_and_handle(slider)
    x0, y = handle.center().x(), handle.center().y()
    qtbot.mousePress(slider, LEFT, pos=QtCore.QPoint(x0, y))
    for dx in (15, 30, 45):
        qtbot.mouseMove(slider, QtCore.QPoint(x0 + dx, y))
        assert slider.value() == home and editor.spin.value() == pytest.approx(0.5)
        assert "alpha_x" in window.last_error and "alpha_x" in window.message_label.text()
        assert lock.isChecked() == (window.state.alpha_y is None)
    qtbot.mouseRelease(slider, LEFT, pos=QtCore.QPoint(x0 + 45, y))
    settle()
    assert window.state.alpha_x == 0.5 and slider.value() == home and editor.spin.value() == pytest.approx(0.5)
    assert "alpha_x" in window.message_label.text() and window.message_label.toolTip() == window.last_error
    # The lock: α_y = None (the roughness, 0.3) is refused beside α_x = 0.5; the box stays clear.
    scroll_to(window, lock)
    click_box(qtbot, lock)
    assert window.state.alpha_y == 0.5 and not lock.isChecked() and window.last_error
    assert lock.isChecked() == (window.state.alpha_y is None)
    choose(window, "ndf", "ggx")  # an anisotropic NDF: accepted, and the box says so
    click_box(qtbot, lock)
    assert window.state.alpha_y is None and lock.isChecked() and window.last_error == ""
    assert not window.controls.widget("alpha_y").slider.isEnabled()


# =============================================================================== 10. what the views say
def _numbers(text, pattern):
    m = re.search(pattern, text)
    assert m, (pattern, text)
    return tuple(float(g) for g in m.groups())


def test_mach_band_readout_is_zero_on_a_flat_image_and_positive_for_gouraud_under_the_spot(qtbot, window):
    type_number(qtbot, window, "elevation", "-90")
    current(window)
    assert window.state.elevation == -90.0
    caption = full(window.profile_panel.caption)
    assert _numbers(caption, r"Gouraud (\S+), Phong (\S+)") == (0.0, 0.0)
    assert "Gouraud 0.00, Phong 0.00" in caption
    press(qtbot, window, "r")
    choose(window, "light", "spot")
    current(window)
    gouraud, phong = _numbers(full(window.profile_panel.caption), r"Gouraud (\S+), Phong (\S+)")
    assert gouraud > 0 and gouraud > phong


def test_albedo_above_one_is_flagged_in_the_readout(qtbot, window):
    choose(window, "model", "ward")
    type_number(qtbot, window, "ks", "1")
    current(window)
    assert window.state.model == "ward" and window.state.ks == 1.0
    text = full(window.albedo_label)
    assert "above 1: not energy conserving" in text and window.albedo_label.property("warn") is True
    assert _numbers(text, r"= (\S+) ±")[0] > 1.0
    assert "#ff8787" in window.albedo_label.styleSheet()


def test_a_light_below_the_horizon_is_said_at_its_true_angle(qtbot, window):
    type_number(qtbot, window, "elevation", "-36")
    current(window)
    assert window.state.elevation == -36.0
    assert "θ_l = 126° (below the horizon)" in full(window.polar_panel.title)
    assert "θ_l = 126° (below the horizon)" in full(window.lobe_panel.caption)
    assert "nothing reflected" in full(window.polar_panel.caption)
    # The view lock draws f(d, d), which needs no light above the horizon: nothing to say of nothing.
    box = window.controls.widget("lock")
    scroll_to(window, box)
    click_box(qtbot, box)
    current(window)
    assert window.state.lock is True
    assert "nothing reflected" not in full(window.polar_panel.caption)
    assert "view lock" in full(window.polar_panel.caption) and "view lock" in full(window.polar_panel.title)
    assert "nothing reflected" not in full(window.lobe_panel.caption)


def test_the_sharpest_lobe_is_drawn_at_its_caption_s_peak(qtbot, window):
    type_number(qtbot, window, "shininess", "1000000")
    current(window)
    assert window.state.shininess == 1e6
    lv = window.model.views["lobe"]
    (peak,) = _numbers(full(window.lobe_panel.caption), r"peak (\S+),")
    drawn = float(np.max(window.lobe_view.poly.point_data["value"]))
    assert drawn == pytest.approx(float(np.max(lv.values)))
    assert drawn == pytest.approx(peak, rel=0.01) and lv.peak == pytest.approx(peak, rel=0.01)
    assert window.lobe_view.lobe_actor.mapper.scalar_range[1] == pytest.approx(lv.peak)


def test_split_sphere_shows_both_highlights(qtbot, window):
    alone = sphere_luminance(window)
    press(qtbot, window, "p")
    press(qtbot, window, "v")
    current(window)
    sv = window.model.views["sphere"]
    assert window.state.split is True and sv.split
    y = sphere_luminance(window)
    near = y >= 0.95 * y.max()
    assert y.max() == pytest.approx(alone.max(), rel=1e-6)  # the same model on both halves
    assert near[sv.split_mask].any() and near[~sv.split_mask].any()
    assert "split along the light" in full(window.sphere_panel.caption)


def test_a_sky_turned_on_clips_at_most_five_percent_of_the_sphere(qtbot, window):
    press(qtbot, window, "x")
    current(window)
    sv = window.model.views["sphere"]
    assert window.state.environment != "none"
    assert sv.clipped / int(sv.coverage.sum()) <= 0.05
    assert window.state.exposure == sv.auto_exposure
    assert "(automatic)" in full(window.sphere_panel.caption)
    assert window.controls.widget("exposure").spin.value() == pytest.approx(window.state.exposure, abs=0.01)


def test_help_lists_every_key_in_a_table(qtbot, window):
    press(qtbot, window, "h")
    settle()
    dialog = window.help_dialog
    assert dialog.isVisible()
    table = dialog.findChild(QtWidgets.QTableWidget)
    assert table.rowCount() == len(captions.KEYS) and table.columnCount() == 2
    lefts = set()
    for row, k in enumerate(captions.KEYS):
        key, what = table.item(row, 0), table.item(row, 1)
        assert QtGui.QKeySequence(key.text()) == QtGui.QKeySequence(k.key)
        assert what.text() == k.description
        lefts.add((table.visualItemRect(key).left(), table.visualItemRect(what).left()))
    assert len(lefts) == 1  # two aligned columns
    assert not table.horizontalScrollBar().isVisible()  # every description read without scrolling sideways
    if dialog.height() < int(0.9 * window.screen().availableGeometry().height()):
        assert not table.verticalScrollBar().isVisible()  # and every key without scrolling, where the screen allows
    # Each description whole in its cell (an item's text has the focus frame's margin and a pixel on each side).
    margin = 2 * (table.style().pixelMetric(QtWidgets.QStyle.PixelMetric.PM_FocusFrameHMargin, None, table) + 1)
    fm = table.fontMetrics()
    for column in (0, 1):
        widest = max(fm.horizontalAdvance(table.item(row, column).text()) for row in range(table.rowCount()))
        assert widest + margin <= table.columnWidth(column), column
    press(qtbot, dialog, "h")  # pressed where the help is: it closes
    settle()
    assert not dialog.isVisible()


def test_the_lit_object_replaces_the_lobe_s_title_and_caption_and_gives_them_back(qtbot, window):
    lobe_caption = full(window.lobe_panel.caption)
    assert "(yellow)" in lobe_caption and "peak" in lobe_caption
    press(qtbot, window, "o")
    current(window)
    assert window.state.view3d == "object" and window.stack3d.currentWidget() is window.object_canvas
    ov = window.model.views["object"]
    assert full(window.lobe_panel.title) == captions.object_title(window.state, ov)
    assert "(yellow)" not in full(window.lobe_panel.caption)  # no lobe, no arrows to name
    # One panel, one title and one caption: the object's caption takes the lobe's place.
    assert full(window.lobe_panel.caption) == captions.object_caption(window.state, ov, window.model)
    press(qtbot, window, "o")
    current(window)
    assert window.stack3d.currentWidget() is window.lobe_view
    assert full(window.lobe_panel.caption) == lobe_caption
    assert full(window.lobe_panel.title) == captions.lobe_title(window.state, window.model.views["lobe"])


PI = "const float PI = 3.14159265358979323846;\n"
SIG = "vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)"
LAMBERT_FILE = (f"::begin parameters\ncolor kd 0.8 0.5 0.2\n::end parameters\n::begin shader\n{PI}{SIG} "
                "{ return kd / PI; }\n::end shader\n")  # fmt: skip


def test_a_brdf_file_keeps_its_name_in_the_title(qtbot, window, tmp_path):
    path = tmp_path / "my lambert.brdf"
    path.write_text(LAMBERT_FILE)
    assert window.open_file("brdf", str(path))
    current(window)
    assert "my lambert" in window.windowTitle()
    type_number(qtbot, window, "elevation", "30")
    press(qtbot, window, "i")
    current(window)
    assert "my lambert" in window.windowTitle() and "my lambert" in full(window.sphere_panel.title)
    assert window.message_label.text() == "opened my lambert.brdf"


# =============================================================================== 9. a scene's lights
RECT_SCENE = """
[camera]
eye = [0.0, 0.0, 20.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
projection = "orthographic"
ortho_height = 2.16

[[objects]]
type = "sphere"
center = [0.0, 0.0, 0.0]
radius = 1.0
material = {parts = [{model = "lambert", kd = 0.6}, {model = "blinn-phong", ks = 0.3, shininess = 20}]}

[[lights]]
type = "rect"
center = [1.5, 1.0, 2.5]
edge_u = [1.0, 0.0, 0.0]
edge_v = [0.0, -1.0, 0.0]
intensity = 3.0
samples = 16
"""


def _sphere_mean(window) -> float:
    sv = window.model.views["sphere"]
    return float(np.asarray(sv.rgb8, dtype=np.float64)[sv.coverage].mean())


def _lights_rows(window) -> list:
    lights = window.lights_panel.list
    return [lights.item(i).text() for i in range(lights.count())]


def test_a_scene_lit_by_a_rect_light_alone_is_lit_and_lists_it(qtbot, window, tmp_path, monkeypatch):
    from explorer.app.lights import light_label

    path = tmp_path / "rect.toml"
    path.write_text(RECT_SCENE)
    assert window.open_file("scene", str(path)), window.last_error
    current(window)
    state = window.state
    assert [t["type"] for t in state.scene_lights] == ["rect"]
    assert state.light == "ambient" and state.ambient == 0.0  # the rect light is the scene's only light
    lit = _sphere_mean(window)
    caption = full(window.sphere_panel.caption)
    assert "ambient light only" not in caption and "rect" in caption
    rows = _lights_rows(window)
    assert light_label(state.scene_lights[0]) in rows and "rect" in rows[-1]
    # Removed in the Lights panel: what is left is the ambient light alone (here none), and the caption says so.
    window.docks["Lights"].raise_()
    settle()
    lights = window.lights_panel.list
    item = lights.item(len(rows) - 1)
    qtbot.mouseClick(lights.viewport(), LEFT, pos=lights.visualItemRect(item).center())
    assert window.lights_panel.selected_light() == 0 and window.lights_panel.remove_button.isEnabled()
    qtbot.mouseClick(window.lights_panel.remove_button, LEFT)
    current(window)
    assert state.scene_lights == ()
    ambient_only = _sphere_mean(window)
    assert lit > ambient_only + 20.0, (lit, ambient_only)  # 8-bit levels over the sphere
    assert "ambient light only" in full(window.sphere_panel.caption)
    assert not any("rect" in r for r in _lights_rows(window))
    # Opened again through the File menu (its dialog answered here).
    monkeypatch.setattr(QtWidgets.QFileDialog, "getOpenFileName", lambda *a, **k: (str(path), "Scene files (*.toml)"))
    window.actions_by_key["open-scene"].trigger()
    current(window)
    assert [t["type"] for t in window.state.scene_lights] == ["rect"]
    assert _sphere_mean(window) == pytest.approx(lit)
    assert "ambient light only" not in full(window.sphere_panel.caption)
    assert any("rect" in r for r in _lights_rows(window))
    assert window.message_label.text() == "opened rect.toml"

"""The Qt explorer's control panel, lights panel and comparison list, driven through real widgets.

A fake window applies every request with ``AppState.update`` and, on a refusal, calls ``sync`` (as the
explorer's window does), so each test checks what a user sees: the knob under the mouse, the value in the
spin box, the state behind them, and that they agree after a refusal.
"""

import os

import pytest

if not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY"):
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
pytest.importorskip("PySide6")
pytest.importorskip("pytestqt")

import shiboken6  # noqa: E402 (after the platform is chosen)
from PySide6 import QtCore, QtWidgets  # noqa: E402
from qt_window_support import click_box, groove_and_handle  # noqa: E402

from explorer.app.comparing import pin_label  # noqa: E402
from explorer.app.params import offered_parameters  # noqa: E402
from explorer.app.state import CONTROLS, DEFAULTS, MODELS, AppState  # noqa: E402
from explorer.compare import BRDFList  # noqa: E402
from explorer.qt._controls_editors import (  # noqa: E402
    CheckEditor,
    ChoiceEditor,
    ColourEditor,
    NumberEditor,
    TermsEditor,
)
from explorer.qt.controls import PARAMS, SECTIONS, ControlPanel  # noqa: E402
from explorer.qt.lists import ComparePanel, LightsPanel  # noqa: E402

LEFT = QtCore.Qt.MouseButton.LeftButton
#: Controls with a panel of their own (the lights list), not a row of the control panel.
LISTED_ELSEWHERE = {"scene_lights"}


@pytest.fixture(scope="session")
def qapp():
    """The explorer's QApplication (Fusion style, its palette), the one pytest-qt's ``qtbot`` uses."""
    from explorer.qt.app import qt_application

    return qt_application()


class FakeWindow:
    """What the window does with a panel's requests: ``state.update``, and ``sync`` after a refusal too."""

    def __init__(self, state, panel):
        self.state, self.panel = state, panel
        self.requests, self.refusals = [], []
        panel.change_requested.connect(self.apply)

    def apply(self, changes, live):
        self.requests.append((changes, live))
        try:
            self.state.update(**changes)
        except ValueError as exc:
            self.refusals.append(str(exc))
        self.panel.sync(self.state)


def _settle():
    """Let nested layouts finish: each pass of the event loop settles one more level of them."""
    for _ in range(8):
        QtWidgets.QApplication.processEvents()


def _panel(qtbot, state, width=340, height=900):
    panel = ControlPanel(state)
    qtbot.addWidget(panel)
    panel.resize(width, height)
    panel.show()
    qtbot.waitExposed(panel)
    _settle()
    return panel, FakeWindow(state, panel)


def _scroll_to(panel, widget):
    _settle()
    panel.ensureWidgetVisible(widget, 10, 40)
    _settle()






def _knob_x(slider) -> int:
    return groove_and_handle(slider)[1].center().x()


# ------------------------------------------------------------------ rows generated from the tables
def test_every_control_has_one_editor_of_its_kind_showing_the_state(qtbot):
    state = AppState(model="blinn-phong", shininess=20.0, light="spot")
    panel, _ = _panel(qtbot, state)
    named = [n for _, names in SECTIONS for n in names if n != PARAMS]
    assert sorted(named) == sorted(set(CONTROLS) - LISTED_ELSEWHERE) and len(named) == len(set(named))
    types = {"float": NumberEditor, "int": NumberEditor, "choice": ChoiceEditor, "bool": CheckEditor,
             "rgb": ColourEditor, "terms": TermsEditor}  # fmt: skip
    for name in named:
        editor = panel.widget(name)
        assert isinstance(editor, types[CONTROLS[name].kind]), name
        assert CONTROLS[name].help in editor.toolTip() or CONTROLS[name].help in panel._rows[name].toolTip() or (
            panel._rows[name].label is not None and CONTROLS[name].help in panel._rows[name].label.toolTip()
        ), name
    assert panel.widget("elevation").spin.value() == 45.0
    assert panel.widget("tessellation").slider.value() == DEFAULTS["tessellation"]
    assert panel.widget("model").currentData() == "blinn-phong" and panel.widget("model").currentText() == "Blinn-Phong"
    assert panel.widget("color").value() == DEFAULTS["color"]
    assert [s.value() for s in panel.widget("color").spins] == pytest.approx(DEFAULTS["color"], abs=0.005)
    assert all(box.isChecked() for box in panel.widget("terms").boxes.values())
    # The model's rows: one per offered parameter, the description as tooltip, the old window's labels.
    params = offered_parameters("blinn-phong")
    assert [p.name for p in params] == ["ks", "shininess", "normalized"]
    for p in params:
        assert p.description in panel.widget(p.name).toolTip()
    assert panel.widget("shininess").spin.value() == 20.0
    assert panel.widget("shininess").slider.value() == panel.widget("shininess").to_position(20.0)
    labels = [w.text() for w in panel.sections["Material"].findChildren(QtWidgets.QLabel) if not w.isHidden()]
    assert "shininess e" in labels and "k_s" in labels
    assert panel.widget("normalized").text() == "normalized" and not panel.widget("normalized").isChecked()


def test_model_switch_rebuilds_the_parameter_rows(qtbot):
    state = AppState()
    panel, window = _panel(qtbot, state)
    combo = panel.widget("model")
    # Chosen with the keyboard: the focused box steps to the next model of the list, the normalized variant,
    # which fixes "normalized": its row goes, shininess stays.
    assert list(MODELS)[list(MODELS).index("blinn-phong") + 1] == "blinn-phong-normalized"
    combo.setFocus()
    qtbot.keyClick(combo, QtCore.Qt.Key.Key_Down)
    assert window.requests == [({"model": "blinn-phong-normalized"}, False)]
    assert state.model == "blinn-phong-normalized" and combo.currentText() == "Blinn-Phong normalized"
    assert panel.widget("shininess").spin.value() == 32.0
    with pytest.raises(KeyError, match="normalized"):
        panel.widget("normalized")
    combo.setCurrentIndex(combo.findData("ward"))  # as choosing the item in the drop-down does
    assert window.requests[-1] == ({"model": "ward"}, False) and state.model == "ward"
    with pytest.raises(KeyError, match="shininess"):
        panel.widget("shininess")
    assert panel.widget("alpha_x").spin.value() == pytest.approx(0.2)
    lock = panel.widget("alpha_y").none_box
    assert lock.text() == "α_y = α_x" and lock.isChecked() and state.alpha_y is None
    assert not panel.widget("alpha_y").slider.isEnabled()
    # Oren–Nayar's form is a parameter named like a control: it goes through params, the control stays.
    combo.setCurrentIndex(combo.findData("oren-nayar"))
    form = panel.widget("param:form")
    form.setCurrentIndex(form.findData("full"))
    assert window.requests[-1] == ({"params": {"form": "full"}}, False)
    assert state.params["form"] == "full" and state.form == "classic"
    assert panel.widget("form").currentData() == "classic"


def test_rows_that_do_not_apply_are_hidden(qtbot):
    state = AppState()
    panel, _ = _panel(qtbot, state)
    point_spot = ("distance", "attenuation", "cutoff", "spot_exponent")
    env = ("env_rotation", "env_intensity", "reference")
    assert [panel.row_visible(n) for n in point_spot + env] == [False] * 7
    light = panel.widget("light")
    for kind, shown in (("spot", (True, True, True, True)), ("point", (True, True, False, False)),
                        ("directional", (False, False, False, False))):  # fmt: skip
        light.setCurrentIndex(light.findData(kind))
        assert state.light == kind
        assert tuple(panel.row_visible(n) for n in point_spot) == shown
    env_box = panel.widget("environment")
    env_box.setCurrentIndex(env_box.findData("studio"))
    assert [panel.row_visible(n) for n in env] == [True] * 3


# ------------------------------------------------------------------ sliders under the mouse
def test_click_on_the_track_jumps_the_knob_and_dragging_follows(qtbot):
    state = AppState()
    panel, window = _panel(qtbot, state)
    editor = panel.widget("elevation")
    slider = editor.slider
    _scroll_to(panel, slider)
    groove, handle = groove_and_handle(slider)
    start = editor.to_position(45.0)
    assert slider.value() == start
    # A click far left of the knob, on the track: the knob jumps under the pointer (not a page step).
    x = groove.left() + groove.width() // 5
    y = groove.center().y()
    assert abs(x - handle.center().x()) > 3 * handle.width()
    qtbot.mousePress(slider, LEFT, pos=QtCore.QPoint(x, y))
    assert abs(_knob_x(slider) - x) <= 1
    jumped = editor.from_position(slider.value())
    assert window.requests == [({"elevation": jumped}, True)] and state.elevation == jumped
    assert jumped < 45.0 - 30.0  # a page step would have moved 5 % of the range
    # Dragging from there: the knob follows the pointer, each position requested live.
    for dx in (15, 30, 45):
        qtbot.mouseMove(slider, QtCore.QPoint(x + dx, y))
        assert abs(_knob_x(slider) - (x + dx)) <= 1
    live = [c for c, is_live in window.requests if is_live]
    assert len(live) >= 4 and [c["elevation"] for c in live] == sorted(c["elevation"] for c in live)
    qtbot.mouseRelease(slider, LEFT, pos=QtCore.QPoint(x + 45, y))
    final = editor.from_position(slider.value())
    assert window.requests[-1] == ({"elevation": final}, False)
    assert state.elevation == final == live[-1]["elevation"]
    assert editor.spin.value() == pytest.approx(final)
    assert window.refusals == []


def test_dragging_the_knob_moves_it_by_the_pointer_distance(qtbot):
    state = AppState()
    panel, window = _panel(qtbot, state)
    slider = panel.widget("azimuth").slider
    _scroll_to(panel, slider)
    groove, handle = groove_and_handle(slider)
    x0, y = handle.center().x(), handle.center().y()
    qtbot.mousePress(slider, LEFT, pos=QtCore.QPoint(x0, y))
    assert abs(_knob_x(slider) - x0) <= 1  # a press on the knob does not move it
    qtbot.mouseMove(slider, QtCore.QPoint(x0 - 40, y))
    assert abs(_knob_x(slider) - (x0 - 40)) <= 1
    qtbot.mouseRelease(slider, LEFT, pos=QtCore.QPoint(x0 - 40, y))
    assert window.requests[-1][1] is False
    # The state wraps angles into (−180°, 180°]: the same number up to its last bits.
    value = panel.widget("azimuth").from_position(slider.value())
    assert state.azimuth == pytest.approx(value, abs=1e-12) and value < 135.0


def test_integer_slider_snaps_and_keys_request_final_values(qtbot):
    state = AppState()
    panel, window = _panel(qtbot, state)
    editor = panel.widget("tessellation")
    _scroll_to(panel, editor)
    editor.slider.setFocus()
    qtbot.keyClick(editor.slider, QtCore.Qt.Key.Key_Right)
    assert window.requests == [({"tessellation": 9}, False)]
    assert state.tessellation == 9 and isinstance(state.tessellation, int)
    groove, _ = groove_and_handle(editor.slider)
    qtbot.mouseClick(editor.slider, LEFT, pos=QtCore.QPoint(groove.right() - 2, groove.center().y()))
    assert state.tessellation == CONTROLS["tessellation"].hi == 64 and editor.spin.value() == 64


# ------------------------------------------------------------------ typing, choosing, toggling
def test_typing_into_a_spin_box_sets_the_value(qtbot):
    state = AppState(model="phong")
    panel, window = _panel(qtbot, state)
    for name, text, value in (("intensity", "2.5", 2.5), ("shininess", "100", 100.0)):
        editor = panel.widget(name)
        _scroll_to(panel, editor)
        line = editor.spin.lineEdit()
        line.selectAll()
        qtbot.keyClicks(line, text)
        assert getattr(state, name) != value  # nothing until the number is entered
        qtbot.keyClick(line, QtCore.Qt.Key.Key_Return)
        assert window.requests[-1] == ({name: value}, False)
        assert getattr(state, name) == value
        assert editor.slider.value() == editor.to_position(value)
    # shininess is a log row: 100 sits two thirds up the slider's 1 … 1e6 (log10 0 … 6).
    assert panel.widget("shininess").slider.value() == pytest.approx(1000 * 2 / 6, abs=1)


def test_colour_and_terms_editors(qtbot):
    state = AppState()
    panel, window = _panel(qtbot, state)
    colour = panel.widget("light_color")
    line = colour.spins[1].lineEdit()
    line.selectAll()
    qtbot.keyClicks(line, "0.25")
    qtbot.keyClick(line, QtCore.Qt.Key.Key_Return)
    assert state.light_color == (1.0, 0.25, 1.0) and window.requests[-1] == ({"light_color": (1.0, 0.25, 1.0)}, False)
    terms = panel.widget("terms")
    _scroll_to(panel, terms)
    box = terms.boxes["specular"]
    click_box(qtbot, box)
    assert state.terms == ("ambient", "diffuse") and not box.isChecked()
    log = panel.widget("log")
    _scroll_to(panel, log)
    click_box(qtbot, log)
    assert state.log is True and window.requests[-1] == ({"log": True}, False)


def test_refused_drag_returns_the_knob_to_the_state(qtbot):
    # Blinn-Phong's NDF has no anisotropic form: α_x ≠ α_y is refused, whatever the slider says.
    state = AppState(model="cook-torrance", ndf="blinn-phong")
    state.update(alpha_x=0.3, alpha_y=0.3)
    panel, window = _panel(qtbot, state)
    editor = panel.widget("alpha_x")
    _scroll_to(panel, editor)
    slider = editor.slider
    home = editor.to_position(0.3)
    assert slider.isEnabled() and slider.value() == home and editor.spin.value() == pytest.approx(0.3)
    _, handle = groove_and_handle(slider)
    x0, y = handle.center().x(), handle.center().y()
    qtbot.mousePress(slider, LEFT, pos=QtCore.QPoint(x0, y))
    for dx in (10, 20, 30):
        qtbot.mouseMove(slider, QtCore.QPoint(x0 + dx, y))
        assert slider.value() == home  # refused at once: the knob stays at the state's value
    qtbot.mouseRelease(slider, LEFT, pos=QtCore.QPoint(x0 + 30, y))
    assert [live for _, live in window.requests] == [True, True, True, False]  # a press on the knob moves nothing
    assert all(c["alpha_x"] != 0.3 for c, _ in window.requests)
    assert len(window.refusals) == 4 and "alpha_x and alpha_y must be equal" in window.refusals[0]
    assert state.alpha_x == 0.3 and state.alpha_y == 0.3
    assert slider.value() == home and editor.spin.value() == pytest.approx(0.3)


def test_alpha_y_lock_agrees_with_the_state_after_refusal_and_acceptance(qtbot):
    # Blinn-Phong's NDF is isotropic: α_x = α_y = 0.5 is allowed, α_y = None (the roughness, 0.3) is not.
    state = AppState(model="cook-torrance", ndf="blinn-phong")
    state.update(alpha_x=0.5, alpha_y=0.5)
    panel, window = _panel(qtbot, state)
    editor = panel.widget("alpha_y")
    lock = editor.none_box
    _scroll_to(panel, lock)
    assert lock.text() == "α_y = roughness" and not lock.isChecked() and editor.slider.isEnabled()
    click_box(qtbot, lock)
    assert window.requests[-1] == ({"alpha_y": None}, False) and len(window.refusals) == 1
    assert state.alpha_y == 0.5 and not lock.isChecked() and editor.slider.isEnabled()
    assert editor.spin.value() == pytest.approx(0.5)
    # With GGX the same click is accepted: the box is checked, the slider greyed at the roughness it stands for.
    ndf = panel.widget("ndf")
    ndf.setCurrentIndex(ndf.findData("ggx"))
    assert state.ndf == "ggx"
    click_box(qtbot, lock)
    assert state.alpha_y is None and lock.isChecked() and not editor.slider.isEnabled()
    assert editor.spin.value() == pytest.approx(0.3) and not editor.spin.isEnabled()
    # Released again: α_y takes the value it stood for, so the lobe does not jump.
    click_box(qtbot, lock)
    assert window.requests[-1] == ({"alpha_y": 0.3}, False)
    assert state.alpha_y == 0.3 and not lock.isChecked() and editor.spin.isEnabled()
    assert len(window.refusals) == 1


def test_ward_lock_releases_to_alpha_x(qtbot):
    state = AppState(model="ward", alpha_x=0.05)
    panel, window = _panel(qtbot, state)
    lock = panel.widget("alpha_y").none_box
    _scroll_to(panel, lock)
    assert panel.widget("alpha_y").spin.value() == pytest.approx(0.05)  # what None stands for, shown greyed
    click_box(qtbot, lock)
    assert window.requests[-1] == ({"alpha_y": 0.05}, False) and state.alpha_y == 0.05


def test_none_rows_show_what_none_stands_for(qtbot):
    state = AppState(model="cook-torrance", roughness=0.2)
    panel, window = _panel(qtbot, state)
    meanings = {n: panel.widget(n).none_box.text() for n in ("alpha_x", "alpha_y", "eta", "k")}
    assert meanings == {"alpha_x": "α_x = roughness", "alpha_y": "α_y = roughness",
                        "eta": "eta = f0's η or the metal's", "k": "k = 0 or the metal's"}  # fmt: skip
    assert panel.widget("alpha_x").spin.value() == pytest.approx(0.2)  # the roughness
    assert panel.widget("k").spin.value() == 0.0  # "0 or the metal's"
    assert all(not panel.widget(n).spin.isEnabled() for n in meanings)
    lock = panel.widget("k").none_box
    _scroll_to(panel, lock)
    click_box(qtbot, lock)  # k applies to a conductor's Fresnel only: refused, the box stays checked
    assert window.requests[-1] == ({"k": 0.0}, False) and len(window.refusals) == 1
    assert state.k is None and lock.isChecked() and not panel.widget("k").spin.isEnabled()
    fresnel = panel.widget("fresnel")
    fresnel.setCurrentIndex(fresnel.findData("conductor"))
    click_box(qtbot, lock)
    assert window.requests[-1] == ({"k": 0.0}, False) and len(window.refusals) == 1
    assert state.k == 0.0 and not lock.isChecked() and panel.widget("k").spin.isEnabled()


# ------------------------------------------------------------------ layout
def _visible_leaves(root):
    kinds = (QtWidgets.QLabel, QtWidgets.QAbstractSlider, QtWidgets.QAbstractSpinBox, QtWidgets.QComboBox,
             QtWidgets.QAbstractButton)  # fmt: skip
    return [w for w in root.findChildren(QtWidgets.QWidget) if isinstance(w, kinds) and w.isVisibleTo(root)]


def _rect_in(w, root):
    return QtCore.QRect(w.mapTo(root, QtCore.QPoint(0, 0)), w.size())


def _text_fits(w) -> bool:
    """Whether a label's, check box's or combo box's text is shown whole, or its tooltip holds it whole."""
    if isinstance(w, QtWidgets.QLabel):
        text, rect = w.text(), w.contentsRect()
        if not text:
            return True
        flags = int(w.alignment().value) | (int(QtCore.Qt.TextFlag.TextWordWrap.value) if w.wordWrap() else 0)
        need = w.fontMetrics().boundingRect(QtCore.QRect(0, 0, rect.width(), 10**6), flags, text)
        shown = need.width() <= rect.width() and need.height() <= rect.height()
    elif isinstance(w, QtWidgets.QCheckBox):
        text = w.text()
        shown = w.sizeHint().width() <= w.width()
    elif isinstance(w, QtWidgets.QComboBox):
        text = w.currentText()
        shown = False  # a combo box may be narrower than its item: its tooltip must name it
    else:
        return True
    return shown or text in w.toolTip()


@pytest.mark.parametrize("width", [300, 340, 380, 420])
@pytest.mark.parametrize("model", ["cook-torrance", "ward", "disney"])
def test_no_overlap_and_no_cut_text(qtbot, width, model):
    state = AppState(model=model, light="spot", environment="studio")
    panel, _ = _panel(qtbot, state, width=width, height=700)
    inner = panel.widget()
    # The panel is never narrower than its rows (no sideways scrolling), and 300 px hold them.
    assert inner.minimumSizeHint().width() + panel.verticalScrollBar().sizeHint().width() <= panel.minimumWidth() <= 300
    assert inner.minimumSizeHint().width() <= panel.viewport().width()
    assert not panel.horizontalScrollBar().isVisible()
    leaves = _visible_leaves(inner)
    assert len(leaves) > 80
    rects = [(w, _rect_in(w, inner)) for w in leaves]
    for w, r in rects:
        assert r.left() >= 0 and r.right() < inner.width(), (w, r)
        assert _text_fits(w), (type(w).__name__, getattr(w, "text", lambda: "")(), width)
    for i, (a, ra) in enumerate(rects):
        for b, rb in rects[i + 1 :]:
            if a.isAncestorOf(b) or b.isAncestorOf(a):
                continue
            assert not ra.intersects(rb), (type(a).__name__, ra, type(b).__name__, rb)


def test_show_section_unfolds_and_scrolls(qtbot):
    panel, _ = _panel(qtbot, AppState(model="cook-torrance"), height=300)
    section = panel.sections["Environment"]
    section.header.click()
    assert section.body.isHidden()
    panel.show_section("env_rotation")
    QtWidgets.QApplication.processEvents()
    assert not section.body.isHidden()
    top = section.mapTo(panel.widget(), QtCore.QPoint(0, 0)).y() - panel.verticalScrollBar().value()
    assert 0 <= top < panel.viewport().height()
    with pytest.raises(ValueError, match="section must be one of"):
        panel.show_section("Lights")


# ------------------------------------------------------------------ comparison list
class FakeCompareWindow:
    """Carries out the Compare panel's requests on a list and syncs the panel at once, inside the click."""

    def __init__(self, state, panel, compare):
        self.state, self.panel, self.compare = state, panel, compare
        panel.action_requested.connect(self.act)

    def _index(self, key):
        return next(i for i, e in enumerate(self.compare) if e.key == key)

    def act(self, action, arg):
        if action == "pin":
            self.compare.add(self.state.brdf(), pin_label(self.state))
        elif action == "remove":
            self.compare.remove(self._index(arg))
        elif action == "visible":
            self.compare.set_visible(self._index(arg[0]), arg[1])
        elif action == "solo":
            self.compare.set_solo(None if arg is None else self._index(arg))
        self.panel.sync(self.compare)


def _compare_panel(qtbot, state, width=300):
    compare = BRDFList(max_entries=6)
    panel = ComparePanel(compare)
    qtbot.addWidget(panel)
    panel.resize(width, 500)
    panel.show()
    qtbot.waitExposed(panel)
    return panel, FakeCompareWindow(state, panel, compare), compare


def test_two_pins_of_different_shininess_read_differently_and_whole(qtbot):
    state = AppState(model="blinn-phong", shininess=32.0)
    panel, _, compare = _compare_panel(qtbot, state)
    assert panel.hint.isVisibleTo(panel)
    qtbot.mouseClick(panel.pin_button, LEFT)
    state.shininess = 100.0
    qtbot.mouseClick(panel.pin_button, LEFT)
    QtWidgets.QApplication.processEvents()
    assert [e.label for e in compare] == ["Blinn-Phong e=32 k_s=0.5", "Blinn-Phong e=100 k_s=0.5"]
    texts = [row.label.text() for row in panel.rows]
    assert texts == [e.label for e in compare] and texts[0] != texts[1]
    assert not panel.hint.isVisibleTo(panel)
    for row in panel.rows:
        assert _text_fits(row.label) and row.label.toolTip() == row.label.text()


def test_remove_button_removes_its_row_without_crashing(qtbot):
    state = AppState(model="blinn-phong")
    panel, _, compare = _compare_panel(qtbot, state)
    labels = []
    for e in (5, 20, 80, 320, 1280):
        state.shininess = float(e)
        labels.append(pin_label(state))
        qtbot.mouseClick(panel.pin_button, LEFT)
    assert len(panel.rows) == 5 and len(set(labels)) == 5
    for n in range(4):
        row = panel.rows[0]  # a fresh row each time: the list was rebuilt by the previous click
        gone = compare[0].label
        qtbot.mouseClick(row.remove, LEFT)
        assert shiboken6.isValid(row) and not row.isVisible()  # the clicked row outlives its own click, hidden
        assert len(compare) == 4 - n and gone not in [e.label for e in compare]
        assert [r.label.text() for r in panel.rows] == [e.label for e in compare]
        qtbot.waitUntil(lambda row=row: not shiboken6.isValid(row))  # deleted later, after its own click
    assert [e.label for e in compare] == labels[-1:] and [r.label.text() for r in panel.rows] == labels[-1:]


def test_visible_and_solo_boxes(qtbot):
    state = AppState(model="blinn-phong")
    panel, _, compare = _compare_panel(qtbot, state)
    for e in (10, 100):
        state.shininess = float(e)
        qtbot.mouseClick(panel.pin_button, LEFT)
    first, second = panel.rows
    click_box(qtbot, first.shown)
    assert compare[0].visible is False and compare.shown() == [compare[1]]
    click_box(qtbot, second.solo)
    assert compare.solo == 1 and panel.rows[1].solo.isChecked() and not panel.rows[0].solo.isChecked()
    click_box(qtbot, panel.rows[1].solo)
    assert compare.solo is None
    requests = []
    panel.action_requested.connect(lambda a, arg: requests.append((a, arg)))
    qtbot.mouseClick(panel.fit_button, LEFT)
    assert requests == [("fit", None)]


# ------------------------------------------------------------------ lights
class FakeLightsWindow:
    def __init__(self, state, panel):
        self.state, self.panel, self.requests = state, panel, []
        panel.change_requested.connect(self.apply)

    def apply(self, changes, live):
        self.requests.append((changes, live))
        self.state.update(**changes)
        self.panel.sync(self.state)


def _lights_panel(qtbot, state):
    panel = LightsPanel(state)
    qtbot.addWidget(panel)
    panel.resize(320, 640)
    panel.show()
    qtbot.waitExposed(panel)
    return panel, FakeLightsWindow(state, panel)


def _rows(panel):
    return [panel.list.item(i).text() for i in range(panel.list.count())]


def test_lights_list_add_edit_remove(qtbot):
    from explorer.app.lights import EXTRA_LIGHT_TYPES, LIGHT_FIELDS, light_label

    state = AppState(environment="studio")
    panel, window = _lights_panel(qtbot, state)
    assert _rows(panel) == ["ambient I_a = 0.08", "key: directional", "environment: studio"]
    assert [a.text() for a in panel.add_menu.actions()] == list(EXTRA_LIGHT_TYPES)
    assert not panel.remove_button.isEnabled()
    sections = []
    panel.section_requested.connect(sections.append)
    panel.list.setCurrentRow(2)
    panel.list.setCurrentRow(0)
    assert sections == ["Environment", "Light"]
    next(a for a in panel.add_menu.actions() if a.text() == "rect").trigger()
    assert len(state.scene_lights) == 1 and state.scene_lights[0]["type"] == "rect"
    assert _rows(panel)[3] == light_label(state.scene_lights[0])
    assert panel.selected_light() == 0 and panel.remove_button.isEnabled() and panel.fields.isVisibleTo(panel)
    assert set(panel._field_editors) == {f.name for f in LIGHT_FIELDS["rect"]}
    # Typing a new intensity: the light and its row follow.
    line = panel.field_editor("intensity").spin.lineEdit()
    line.selectAll()
    qtbot.keyClicks(line, "7")
    qtbot.keyClick(line, QtCore.Qt.Key.Key_Return)
    assert state.scene_lights[0]["intensity"] == 7.0
    assert _rows(panel)[3].endswith("intensity 7")
    # A refused value: the message under the list names the field, the editor shows the state's value.
    before = len(window.requests)
    panel.set_field(0, "edge_u", (0.0, 0.0, 0.0))
    assert len(window.requests) == before and "scene_lights[0].edge_u" in panel.message.text()
    assert panel.field_editor("edge_u").value() == tuple(float(x) for x in state.scene_lights[0]["edge_u"])
    qtbot.mouseClick(panel.remove_button, LEFT)
    assert state.scene_lights == () and _rows(panel) == ["ambient I_a = 0.08", "key: directional",
                                                          "environment: studio"]  # fmt: skip
    assert not panel.fields.isVisibleTo(panel)


@pytest.mark.parametrize("width", [300, 420])
@pytest.mark.parametrize("kind", ["opengl", "spot", "rect"])
def test_light_fields_do_not_overlap(qtbot, width, kind):
    from explorer.app.lights import LIGHT_FIELDS, field_value, new_light

    state = AppState()
    state.scene_lights = (new_light(kind, state),)
    panel, _ = _lights_panel(qtbot, state)
    panel.resize(width, 900)
    panel.list.setCurrentRow(2)
    _settle()
    assert panel.selected_light() == 0 and panel.fields.title() == f"light 1: {kind}"
    for f in LIGHT_FIELDS[kind]:
        shown = panel.field_editor(f.name).value()
        want = field_value(state.scene_lights[0], f.name)
        assert shown == (pytest.approx(want) if f.kind != "bool" else want), f.name
    leaves = _visible_leaves(panel.fields)
    rects = [(w, _rect_in(w, panel.fields)) for w in leaves]
    for w, r in rects:
        assert r.left() >= 0 and r.right() < panel.fields.width(), (w, r)
        assert _text_fits(w), (type(w).__name__, getattr(w, "text", lambda: "")(), width)
    for i, (a, ra) in enumerate(rects):
        for b, rb in rects[i + 1 :]:
            if not (a.isAncestorOf(b) or b.isAncestorOf(a)):
                assert not ra.intersects(rb), (type(a).__name__, ra, type(b).__name__, rb)

"""The explorer window's metal controls, driven through its widgets: a metal picked under a sky, and its picture.

Slow: it builds the explorer window (seconds).  A student picks Cook–Torrance, the daylight sky and then each
named metal from the Material section's combo boxes; the window must take the pick (no refusal), show the
conductor Fresnel term and the metal's index in the other rows, drop the diffuse layer, and paint a sphere
whose colour is the metal's: gold and copper warm, silver and aluminium neutral.
"""

from __future__ import annotations

import os

import pytest

pytestmark = pytest.mark.slow  # the explorer window

if not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY"):
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
pytest.importorskip("PySide6")
pytest.importorskip("pyvistaqt")
pytest.importorskip("pytestqt")

import numpy as np  # noqa: E402
from PySide6 import QtCore, QtGui  # noqa: E402
from qt_window_support import click_box  # noqa: E402
from test_qt_window import current, make_window, qapp  # noqa: E402, F401 (qapp: the explorer's QApplication)

from lighting.models.fresnel import METALS, metal_index  # noqa: E402

#: A folder where the pictures are also kept, for a person to look at (none unless the variable names one).
SCREENS = os.environ.get("LIGHTING_EXPLORER_SCREENS", "")


def _choose(window, name, value):
    combo = window.controls.widget(name)
    index = combo.findData(value)
    assert index >= 0, (name, value)
    combo.setCurrentIndex(index)  # what a click on the item does: the editor reports the edit
    current(window)


def _sphere_pixels(window, image):
    canvas = window.sphere_panel.canvas
    r = canvas.image_rect().toRect().translated(canvas.mapTo(window, QtCore.QPoint(0, 0)))
    region = image[r.top() : r.bottom(), r.left() : r.right()].astype(np.float64)
    h, w = region.shape[:2]
    y, x = np.mgrid[0:h, 0:w]
    inside = (x - w / 2) ** 2 + (y - h / 2) ** 2 < (0.4 * min(h, w)) ** 2  # well inside the sphere's disc
    return region[inside]


def test_each_metal_is_taken_shown_and_painted_in_its_colour(qtbot, tmp_path):
    window = make_window(size=(1280, 768))
    qtbot.addWidget(window)
    panel = window.controls
    _choose(window, "model", "cook-torrance")
    _choose(window, "environment", "daylight")
    assert window.state.kd == 0.8
    colour = {}
    for metal in METALS:
        _choose(window, "metal", metal)
        state = window.state
        assert window.last_error in (None, ""), window.last_error  # taken, not refused
        assert {k: state.params[k] for k in ("fresnel", "metal", "eta", "k")} == {
            "fresnel": "conductor", "metal": metal, "eta": None, "k": None}  # fmt: skip
        assert panel.widget("fresnel").currentData() == "conductor"
        assert panel.widget("kd").spin.value() == 0.0 and state.kd == 0.0
        eta, k = metal_index(metal)
        assert panel.widget("eta").spin.value() == pytest.approx(eta.max(), abs=1e-4)  # greyed: the metal's
        assert panel.widget("k").spin.value() == pytest.approx(k.max(), abs=1e-3)
        assert panel.widget("eta").none_box.isChecked() and not panel.widget("eta").spin.isEnabled()
        path = tmp_path / f"explorer-{metal}-daylight.png"
        window.screenshot(str(path))
        assert QtGui.QImage(str(path)).size() == QtCore.QSize(1280, 768)
        colour[metal] = _sphere_pixels(window, window.image()).mean(axis=0)
        if SCREENS:
            os.makedirs(SCREENS, exist_ok=True)
            with open(os.path.join(SCREENS, path.name), "wb") as fh:
                fh.write(path.read_bytes())
    # 8-bit sRGB means over the sphere: warm metals have red well above blue; the neutral ones reflect the sky
    # (bluish above, the ground below) with their channels within a tenth of each other.
    for metal, most in (("gold", 0.85), ("copper", 0.92)):  # copper's F0 (0.92, 0.60, 0.55): pink under a blue sky
        r, _, b = colour[metal]
        assert b < most * r, (metal, colour[metal])
    for metal in ("silver", "aluminium"):
        assert np.ptp(colour[metal]) < 0.12 * colour[metal].max(), (metal, colour[metal])
    silver = colour["silver"][2] / colour["silver"][0]
    assert colour["gold"][2] / colour["gold"][0] < silver - 0.15
    assert colour["copper"][2] / colour["copper"][0] < silver - 0.1
    # Released, the η lock keeps the look: η and k take gold's index per channel, the metal is left.
    _choose(window, "metal", "gold")
    before = np.array(window.model.views["sphere"].image, copy=True)
    lock = panel.widget("eta").none_box
    window.controls.ensureWidgetVisible(lock)
    click_box(qtbot, lock)
    current(window)
    eta, k = metal_index("gold")
    params = window.state.params
    assert window.last_error in (None, "") and not lock.isChecked()
    assert (params["metal"], params["fresnel"]) == ("none", "conductor")
    assert params["eta"] == tuple(eta) and params["k"] == tuple(k)
    np.testing.assert_array_equal(window.model.views["sphere"].image, before)
    # Back to Schlick: the metal and its index are left, nothing refused.
    _choose(window, "fresnel", "schlick")
    assert window.last_error in (None, "")
    assert window.state.params["fresnel"] == "schlick"
    assert (window.state.params["metal"], window.state.params["eta"], window.state.params["k"]) == ("none", None, None)
    window.close()

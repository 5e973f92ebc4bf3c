"""The comparison drawn in the explorer window: overlays, hide and solo, the blitted angle plots, the albedo panel;
and a MERL file opened by ``--brdf`` (slow set; the comparison's state and values: test_app_compare.py)."""

import math

import numpy as np
import pytest

# ruff: noqa: E402
pytest.importorskip("pyvista")
pytest.importorskip("PySide6")
pytest.importorskip("pytestqt")

from qt_window_support import flush, open_window, pixels, reset, settle
from test_app_compare import _FakeWindow, pairs

from explorer import app as app_mod
from explorer.app.command import main
from explorer.app.comparing import ALBEDO_ANGLES_DEG
from explorer.qt.keys import do_key
from lighting import Lambert

pytestmark = pytest.mark.slow  # the explorer window drawn by Qt, Matplotlib and VTK off-screen; a MERL table tabulated

SIZE = (1200, 720)


@pytest.fixture(scope="module")
def app():
    window = open_window(SIZE)
    yield window
    window.close()


@pytest.fixture
def fresh(app, qtbot):
    reset(app)
    yield app
    reset(app)


def _drawn(lines):
    return [(line.get_color(), line.get_ydata().copy()) for line in lines if line.get_visible()]


def _rows(app):
    """The Compare panel's rows once its rebuild (after the action's signal returns) has run."""
    settle()
    return app.compare_panel.rows


def test_hide_and_solo_change_what_is_drawn(fresh):
    app = fresh
    app.set_control("model", "phong")
    for e in (10.0, 60.0, 400.0):
        app.set_control("params", {"shininess": e})
        app.compare_action("pin")
    app.set_control("params", {"shininess": 2.0})
    flush(app)
    colours = [e.colour for e in app.model.compare]
    assert len(set(colours)) == 3
    polar, angles = app.polar_canvas.plot, app.angle_canvas.plot
    drawn = _drawn(polar.overlay_lines)
    assert [c for c, _ in drawn] == colours
    for (_, y), o in zip(drawn, app.model.views["polar"].overlays, strict=True):
        np.testing.assert_array_equal(y, o.values)
    # Hidden: the curve goes, the colour stays with its entry.
    rows = _rows(app)
    assert [r.key for r in rows] == [e.key for e in app.model.compare]
    rows[1].shown.click()  # a click on the row's box
    flush(app)
    assert not app.model.compare[1].visible
    assert [c for c, _ in _drawn(polar.overlay_lines)] == [colours[0], colours[2]]
    for lines in angles.overlay_lines:
        assert [c for c, _ in _drawn(lines)] == [colours[0], colours[2]]
    # Solo: that one alone, even if hidden; then back to the boxes.
    _rows(app)[1].solo.click()
    flush(app)
    assert app.model.compare.solo == 1
    assert [c for c, _ in _drawn(polar.overlay_lines)] == [colours[1]]
    np.testing.assert_array_equal(_drawn(angles.overlay_lines[0])[0][1],
                                  app.model.views["theta_v"].overlays[0].values)  # fmt: skip
    solo = _rows(app)[1].solo
    assert solo.isChecked()
    solo.click()
    flush(app)
    assert app.model.compare.solo is None
    assert [c for c, _ in _drawn(polar.overlay_lines)] == [colours[0], colours[2]]
    # Remove: its row's ×.
    _rows(app)[0].remove.click()
    flush(app)
    assert [e.colour for e in app.model.compare] == colours[1:]
    assert [c for c, _ in _drawn(polar.overlay_lines)] == [colours[2]]
    assert len(_rows(app)) == 2


def test_the_angle_plots_show_each_blit_and_the_pin_key(fresh):
    """After a full Matplotlib draw the angle plots show later blits too."""
    app = fresh
    app.set_control("model", "cook-torrance")
    app.set_control("params", {"roughness": 0.1})
    flush(app)

    def crop():
        return pixels(app, app.angle_canvas).astype(int)

    do_key(app, "pin")
    assert app.flush() >= {"polar", "theta_v"} and len(app.model.compare) == 1  # the views the pin changed
    app.set_control("params", {"roughness": 0.5})
    flush(app)
    a = crop()
    blits = app.angle_canvas.plot.blits
    app.set_control("params", {"roughness": 0.3})
    flush(app)
    b = crop()
    assert app.angle_canvas.plot.blits == blits + 1  # no axis changed: only the curves were drawn
    assert int((np.abs(a - b).sum(-1) > 30).sum()) > 500


def test_albedo_panel_draws_each_curve_and_its_flags(fresh):
    app = fresh
    app.set_control("model", "cook-torrance")
    app.set_control("params", {"roughness": 1e-6, "f0": 1.0})
    app.compare_action("pin")
    app.set_control("params", {"roughness": 0.3})
    do_key(app, "panel")
    flush(app)
    assert app.state.panel == "albedo" and app.stack_plots.currentWidget() is app.albedo_canvas
    curves = app.model.views["albedo"].curves
    plot = app.albedo_canvas.plot
    lines = [line for line in plot.lines if line.get_visible()]
    assert len(lines) == len(curves) == 2
    for line, c in zip(lines, curves, strict=True):
        np.testing.assert_array_equal(line.get_ydata(), c.value)
    flags = curves[1].unconverged
    assert flags.any() and not curves[0].unconverged.any()
    np.testing.assert_allclose(plot.flags.get_xdata(), ALBEDO_ANGLES_DEG[flags], atol=1e-12)
    assert "unconverged" in app.angles_panel.caption.text()
    do_key(app, "panel")
    flush(app)
    assert app.state.panel == "angles" and app.stack_plots.currentWidget() is app.angle_canvas


# ----------------------------------------------------------------------------- files from the command line
def test_brdf_option_opens_merl_data(tmp_path, monkeypatch):
    from lighting.files.merl import tabulate_merl, write_merl

    path = tmp_path / "grey.binary"
    write_merl(path, tabulate_merl(Lambert(0.5)))
    monkeypatch.setattr(app_mod, "ExplorerApp", _FakeWindow)
    _FakeWindow.made.clear()
    assert main(["--brdf", str(path), "--screenshot", str(tmp_path / "shot.png")]) == 0
    state = _FakeWindow.made[0].state
    assert state.model == "grey" and getattr(app_mod.state.model_variants()["grey"][0], "file_path", None)
    n, l, v = pairs(50)
    got = state.brdf().eval(n, l, v)
    lit = (l[:, 2] > 0) & (v[:, 2] > 0)
    np.testing.assert_allclose(got[lit], 0.5 / math.pi, rtol=1e-6)  # a constant table: every lookup is 0.5/π

"""The comparison drawn in the explorer window: overlays, hide and solo, the blit chart, the albedo panel (slow set;
the comparison's state and values: test_app_compare.py)."""

import numpy as np
import pytest

from explorer import app as app_mod
from explorer.app.comparing import ALBEDO_ANGLES_DEG
from explorer.app.layout import ANGLES

pv = pytest.importorskip("pyvista")

pytestmark = pytest.mark.slow  # the explorer window, rendered off-screen by VTK

SIZE = (1200, 720)


@pytest.fixture(scope="module")
def app():
    old = pv.OFF_SCREEN
    pv.OFF_SCREEN = True
    a = app_mod.ExplorerApp(window_size=SIZE, off_screen=True)
    yield a
    a.close()
    pv.OFF_SCREEN = old


@pytest.fixture
def fresh(app):
    app.reset()
    while len(app.model.compare):
        app.remove_entry(0)
    app.set_solo(None)
    yield app
    app.reset()
    while len(app.model.compare):
        app.remove_entry(0)


def _drawn(lines):
    return [(line.get_color(), line.get_ydata().copy()) for line in lines if line.get_visible()]


def test_hide_and_solo_change_what_is_drawn(fresh):
    app = fresh
    app.set_control("model", "phong")
    for e in (10.0, 60.0, 400.0):
        app.set_control("params", {"shininess": e})
        app.pin()
    app.set_control("params", {"shininess": 2.0})
    colours = [e.colour for e in app.model.compare]
    assert len(set(colours)) == 3
    drawn = _drawn(app.polar_plot.overlay_lines)
    assert [c for c, _ in drawn] == colours
    for (_, y), o in zip(drawn, app.model.views["polar"].overlays, strict=True):
        np.testing.assert_array_equal(y, o.values)
    # Hidden: the curve goes, the colour stays with its entry.
    box = app.compare_boxes[1]["show"]
    box.GetRepresentation().SetState(0)
    box.InvokeEvent("StateChangedEvent")  # as a click on the row's coloured box
    assert not app.model.compare[1].visible
    assert [c for c, _ in _drawn(app.polar_plot.overlay_lines)] == [colours[0], colours[2]]
    for lines in app.angle_plots.overlay_lines:
        assert [c for c, _ in _drawn(lines)] == [colours[0], colours[2]]
    # Solo: that one alone, even if hidden; then back to the boxes.
    app.set_solo(1)
    assert [c for c, _ in _drawn(app.polar_plot.overlay_lines)] == [colours[1]]
    np.testing.assert_array_equal(_drawn(app.angle_plots.overlay_lines[0])[0][1],
                                  app.model.views["theta_v"].overlays[0].values)  # fmt: skip
    solo = app.compare_boxes[1]["solo"]
    assert solo.GetRepresentation().GetState() == 1
    solo.GetRepresentation().SetState(0)
    solo.InvokeEvent("StateChangedEvent")
    assert app.model.compare.solo is None
    assert [c for c, _ in _drawn(app.polar_plot.overlay_lines)] == [colours[0], colours[2]]
    # Remove: its row's ×.
    remove = app.compare_boxes[0]["remove"]
    remove.GetRepresentation().SetState(1)
    remove.InvokeEvent("StateChangedEvent")
    assert [e.colour for e in app.model.compare] == colours[1:]
    assert [c for c, _ in _drawn(app.polar_plot.overlay_lines)] == [colours[2]]


def test_the_chart_shows_each_blit_and_the_pin_key(fresh):
    """After a full Matplotlib draw the chart shows later blits too (ChartMPL replaced the chart's image)."""
    app = fresh
    app.set_control("model", "cook-torrance")
    app.set_control("params", {"roughness": 0.1})

    def crop():
        img = app.image()
        x0, y0, x1, y1 = app.panel_viewport(ANGLES)
        h, w = img.shape[:2]
        return img[int((1 - y1) * h) + 3 : int((1 - y0) * h) - 3, int(x0 * w) + 3 : int(x1 * w) - 3].astype(int)

    assert app.on_key("p") >= {"polar", "theta_v"} and len(app.model.compare) == 1
    app.set_control("params", {"roughness": 0.5})
    a = crop()
    blits = app.angle_plots.blits
    app.set_control("params", {"roughness": 0.3})
    b = crop()
    assert app.angle_plots.blits == blits + 1  # no axis changed: only the curves were drawn
    assert int((np.abs(a - b).sum(-1) > 30).sum()) > 500


def test_albedo_panel_draws_each_curve_and_its_flags(fresh):
    app = fresh
    app.set_control("model", "cook-torrance")
    app.set_control("params", {"roughness": 1e-6, "f0": 1.0})
    app.pin()
    app.set_control("params", {"roughness": 0.3})
    app.on_key("a")
    assert app.state.panel == "albedo"
    curves = app.model.views["albedo"].curves
    lines = [line for line in app.albedo_plot.lines if line.get_visible()]
    assert len(lines) == len(curves) == 2
    for line, c in zip(lines, curves, strict=True):
        np.testing.assert_array_equal(line.get_ydata(), c.value)
    flags = curves[1].unconverged
    assert flags.any() and not curves[0].unconverged.any()
    np.testing.assert_allclose(app.albedo_plot.flags.get_xdata(), ALBEDO_ANGLES_DEG[flags], atol=1e-12)
    assert "unconverged" in app.captions["angles_peak"].GetInput()
    app.on_key("a")
    assert app.state.panel == "angles"

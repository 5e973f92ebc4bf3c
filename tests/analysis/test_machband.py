"""The Mach-band measure (:func:`lighting.analysis.machband.edge_jump_metric`): values it must take.

* exactly 0 on a constant image and on an image linear across every edge (any dtype);
* the closed form ``e'(I) · |slope jump| · 255`` on a single kink, growing with it;
* a step of the shading beside an edge (a spot's rim) is no kink at the edge;
* on the explorer's coarse sphere Gouraud scores above Phong interpolation, under the default
  directional light and under the spot light, and an ambient-only sphere scores 0 in both.
"""

from __future__ import annotations

import numpy as np
import pytest

from explorer.app.state import AppState
from explorer.app.views import ExplorerModel
from lighting.analysis.machband import KINK_SCALE, edge_jump_metric

H, W = 24, 96


def _triangles(h=H, w=W, size=16):
    """Triangle ids of a grid of squares ``size`` px wide, each cut along its diagonal."""
    y, x = np.mgrid[0:h, 0:w]
    square = (y // size) * (w // size + 1) + x // size
    upper = (x % size) > (y % size)
    return (2 * square + upper).astype(np.int64)


def _srgb_slope(i):
    return 12.92 if i <= 0.0031308 else 1.055 / 2.4 * i ** (1 / 2.4 - 1)


def _kinked_row(jump, level=0.3, edge=48, w=W):
    """A V about the edge between pixels ``edge − 1`` and ``edge``: slope ``−jump/2`` before it, ``+jump/2`` after."""
    x = np.arange(w, dtype=np.float64)
    return level + 0.5 * jump * np.abs(x - (edge - 0.5))


def _two_triangles(h=H, w=W, edge=48):
    return np.where(np.arange(w) < edge, 0, 1)[None, :].repeat(h, axis=0).astype(np.int64)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_a_constant_image_scores_exactly_zero(dtype):
    tid = _triangles()
    for value in (0.0, 0.0064, 0.5, 1.0, 3.0):
        assert edge_jump_metric(np.full((H, W, 3), value, dtype=dtype), tid) == 0.0
    assert edge_jump_metric(np.full((H, W, 3), (0.2, 0.05, 0.9), dtype=dtype), tid, channel="g") == 0.0


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_an_image_linear_across_the_edges_scores_zero(dtype):
    # I = a + b x + c y in linear light: no slope changes anywhere, whatever the triangles.
    y, x = np.mgrid[0:H, 0:W].astype(np.float64)
    plane = 0.05 + 0.008 * x + 0.003 * y
    rgb = np.stack([plane, 0.5 * plane, 0.9 - 0.8 * plane / plane.max()], axis=-1).astype(dtype)
    for tid in (_triangles(), _triangles(size=11), _two_triangles()):
        for channel in ("luminance", "r", "g", "b"):
            assert edge_jump_metric(rgb, tid, channel=channel) == 0.0


def test_a_single_kink_scores_its_display_slope_jump_and_grows_with_it():
    tid = _two_triangles()
    jumps = [1e-4, 1e-3, 3e-3, 1e-2, 2e-2]
    got = []
    for jump in jumps:
        row = _kinked_row(jump)
        image = np.tile(row, (H, 1))
        level = row[47]  # the two pixels beside the edge hold the same value
        assert row[48] == level
        expect = _srgb_slope(level) * jump / KINK_SCALE
        got.append(edge_jump_metric(image, tid))
        assert got[-1] == pytest.approx(expect, rel=1e-9)
    assert np.all(np.diff(got) > 0)


def test_the_measure_reads_display_units_not_slope_ratios():
    # The same linear slope jump reads larger in the darks, where sRGB spreads linear values further apart,
    # and 0 where the display clips to white.
    tid = _two_triangles()
    dark, bright = (edge_jump_metric(np.tile(_kinked_row(1e-3, level), (H, 1)), tid) for level in (0.01, 0.6))
    assert dark > 2 * bright > 0
    assert edge_jump_metric(np.tile(_kinked_row(1e-3, 1.5), (H, 1)), tid) == 0.0


def test_a_step_of_the_shading_beside_an_edge_is_no_kink_at_the_edge():
    # A spot's rim (a value jump) three pixels from the edge of a linear ramp: the edge itself has no kink.
    tid = _two_triangles()
    x = np.arange(W, dtype=np.float64)
    row = 0.1 + 0.002 * x + np.where(x >= 51, 0.2, 0.0)
    assert edge_jump_metric(np.tile(row, (H, 1)), tid) == 0.0


def _metrics(**controls):
    model = ExplorerModel(AppState(**controls))
    model.update()
    p = model.views["profile"]
    return p.metric_gouraud, p.metric_phong


@pytest.mark.parametrize("controls", [{}, {"light": "spot"}], ids=["directional", "spot"])
def test_gouraud_scores_above_phong_on_the_explorers_coarse_sphere(controls):
    # Measured at the explorer's defaults: Gouraud about 60 times Phong (directional), several hundred (spot).
    gouraud, phong = _metrics(**controls)
    assert gouraud > 10 * phong > 0


@pytest.mark.parametrize("controls", [{"elevation": -90.0}, {"elevation": -90.0, "light": "spot"}])
def test_an_ambient_only_sphere_scores_zero_in_both(controls):
    # The light behind the sphere: only ambient, one colour; float32 interpolation wobbles are no kinks.
    assert _metrics(**controls) == (0.0, 0.0)

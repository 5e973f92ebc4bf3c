"""The ``ibl_error`` figure's measured numbers and error map; the split sum's error by model in ``accuracy_ibl``."""

from __future__ import annotations

import numpy as np
import pytest

from explorer.figures import figure_names, make_figure
from lighting.validation import accuracy


@pytest.fixture(scope="module")
def drawn():
    fig, spec, params, q, measured = make_figure("ibl_error", quick=True)
    return fig, spec, params, measured


def test_ibl_error_is_registered_after_the_rendering_and_accuracy_figures():
    names = figure_names()
    assert "ibl_error" in names and names.index("ibl_error") > names.index("rendering_equation")
    assert names.index("ibl_error") > names.index("accuracy_ibl")


def test_ibl_error_measures_what_its_caption_states(drawn):
    fig, spec, params, m = drawn
    assert params["alpha"] == 0.2 and m["spp"] == 32
    assert 0 < m["median_error"] <= m["p95_error"]
    assert m["reference_error"] > 0 and m["fast_ms"] > 0 and m["mc_s"] > 0
    # A 48² quick sphere: the pixels are the sphere_camera disc.
    assert 1000 < m["pixels"] < 48 * 48 * np.pi / 4 * 1.01
    # The grey pixels are exactly those the error leaves out (the study's lit threshold).
    assert 0 < m["lit_pixels"] < m["pixels"]
    assert m["unlit_percent"] == pytest.approx(100 * (1 - m["lit_pixels"] / m["pixels"]))
    assert m["lit_percent"] == 100 * accuracy.IBL_LIT_FRACTION
    caption = spec.caption.format(**m)
    assert f"{m['median_error']:.1%}" in caption and f"{m['unlit_percent']:.0f} %" in caption
    assert tuple(fig.get_size_inches()) == spec.size_in == (10.0, 7.5)


def test_the_error_map_shows_unlit_pixels_in_one_flat_colour_and_no_black(drawn):
    import matplotlib.colors

    from explorer.figures.ibl import UNLIT_COLOUR

    fig, _, _, m = drawn
    error_ax = next(ax for ax in fig.axes if ax.get_title().startswith("relative difference"))
    err, unlit = (im.get_array() for im in error_ax.get_images())
    # The colour-mapped layer holds a value for the lit pixels only; the grey layer covers exactly the others.
    assert int(np.ma.count(err)) == m["lit_pixels"]
    grey = np.asarray(unlit)[..., 3] == 1.0
    assert int(grey.sum()) == m["pixels"] - m["lit_pixels"]
    assert not np.any(grey & ~np.ma.getmaskarray(err))
    assert np.allclose(np.asarray(unlit)[grey][:, :3], matplotlib.colors.to_rgb(UNLIT_COLOUR))
    # Masked pixels are transparent in the colour map (they show the grey layer or the white ground).
    assert error_ax.get_images()[0].get_cmap().get_bad()[3] == 0.0

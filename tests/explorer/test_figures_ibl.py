"""explorer.figures.ibl: the ``ibl_error`` figure's measured numbers, against the study they come from."""

from __future__ import annotations

import numpy as np
import pytest

from explorer.figures import figure_names, make_figure


@pytest.fixture(scope="module")
def drawn():
    fig, spec, params, q, measured = make_figure("ibl_error", quick=True)
    return spec, params, measured


def test_ibl_error_is_registered_after_the_rendering_figures():
    names = figure_names()
    assert "ibl_error" in names and names.index("ibl_error") > names.index("rendering_equation")


def test_ibl_error_measures_what_its_caption_states(drawn):
    spec, params, m = drawn
    assert params["alphas"] == (0.05, 0.2, 0.5) and m["spp"] == 32 and m["ref_spp"] == 256
    assert 0 < m["median_error"] <= m["p95_error"]
    assert m["reference_error"] > 0 and m["fast_ms"] > 0 and m["mc_s"] > 0
    # A 48² quick sphere: the pixels are the sphere_camera disc.
    assert 1000 < m["pixels"] < 48 * 48 * np.pi / 4 * 1.01
    assert list(m["split_by_alpha"]) == ["α = 0.05", "α = 0.2", "α = 0.5"]
    assert all(np.isfinite(v) and v > 0 for v in m["split_by_alpha"].values())
    # SH9 against the pixelized map's exact irradiance: a smooth function, a few percent at most.
    assert 0 < m["sh9_error"] < 0.1
    caption = spec.caption.format(**m)
    assert f"{m['median_error']:.1%}" in caption and f"{m['sh9_error']:.2%}" in caption
    assert m["split_errors"] in caption

"""The IBL accuracy figure drawn from the study it measures (slow set; fast: test_figures_ibl.py)."""

import numpy as np
import pytest

from explorer.figures import make_figure

pytestmark = pytest.mark.slow  # measures the IBL study's quick settings while drawing


def test_accuracy_ibl_shows_the_split_sum_and_sh9_errors_of_the_study():
    # The split sum's error by model and SH9's against the exact irradiance, as the study measured them
    # (here its quick settings, measured while drawing with this test run's empty or filled cache).
    fig, spec, params, q, m = make_figure("accuracy_ibl", quick=True)
    assert m["environments"] >= 2 and m["models"] >= 3
    for env, by_model in m["split_sum"].items():
        assert len(by_model) == m["models"]
        assert all(np.isfinite(v) and 0 < v < 1 for v in by_model.values()), env
    # SH9 against the pixelized map's exact irradiance: a smooth function, a few percent at most.
    assert set(m["sh9"]) == set(m["split_sum"]) and all(0 < v < 0.1 for v in m["sh9"].values())
    caption = spec.caption.format(**m)
    assert "{" not in caption and m["line_models"] in caption

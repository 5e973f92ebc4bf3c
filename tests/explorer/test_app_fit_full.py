"""Fitting a model to a BRDF file opened in the explorer (slow set: the fit is a least-squares search over the
file's slices, seconds of work; the comparison's state and values: test_app_compare.py)."""

import pytest
from test_app_compare import GGX, small_model

pytestmark = pytest.mark.slow  # a least-squares fit


def test_fit_recovers_the_roughness_of_a_ggx_file_and_the_split_sphere_shows_both(tmp_path):
    path = tmp_path / "ggx.brdf"
    path.write_text(GGX)
    m = small_model()
    name = m.open_brdf(path)
    assert m.state.model == name and m.state.params == {"ks": (1.0, 1.0, 1.0), "roughness": 0.25,
                                                        "f0": (0.9, 0.6, 0.3)}  # fmt: skip
    m.state.update(params={"roughness": 0.4})
    entry, result = m.fit()
    assert abs(result.parameters["roughness"] / 0.4 - 1) < 0.03 and result.relative_rms < 0.01
    assert entry.label.startswith("GGX fit α=0.4") and "rel. rms" in entry.label

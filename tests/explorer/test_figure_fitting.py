"""The figure of analytic models fitted to (stand-in) measured data: what it shows, measured."""

from __future__ import annotations

import pytest

from explorer.figures import make_figure

pytestmark = pytest.mark.slow  # fits three models to a tabulated MERL table


@pytest.fixture(scope="module")
def measured():
    fig, _, _, _, values = make_figure("fit_to_measured", quick=True)
    return values


def test_the_microfacet_fit_recovers_the_data_s_own_lobe(measured):
    # The data are Disney's metallic lobe: GGX with α = roughness² and F0 = the base colour. The fitted
    # Cook–Torrance GGX finds both, within the 3 % noise and the 5 % missing bins (MERL's nearest-bin
    # and interpolation errors included).
    assert measured["ct_roughness"] == pytest.approx(measured["disney_alpha"], rel=0.05)
    assert measured["params_cook_torrance"]["f0"] == pytest.approx((0.9, 0.6, 0.3), rel=0.05)


def test_the_residuals_rank_the_models_and_the_best_is_near_the_noise(measured):
    rel = [measured[f"rel_{k}"] for k in ("cook_torrance", "ward", "blinn_phong_normalized")]
    assert rel == sorted(rel)
    assert rel[0] < measured["noise_percent"] / 100
    assert rel[2] > 0.5  # normalized Blinn–Phong has no Fresnel and no 1/(n·v): it misses the grazing lobe

"""The explorer's views say and show what is computed: albedo above 1, the split sphere's divider, skies' exposure,
the fit of a model with a diffuse part, a file model's name and its k_d control, one name per environment."""

import math

import numpy as np
import pytest

from explorer.app.comparing import FIT_MODELS, fit_model, has_diffuse, restrict
from explorer.app.encode import encode8
from explorer.app.environment import auto_exposure
from explorer.app.state import AppState
from explorer.app.views import ExplorerModel, split_angle, split_mask
from lighting.analysis.fit import fit_brdf
from lighting.analysis.machband import LUMA
from lighting.integrate import directional_albedo
from lighting.lights import SKIES


def _model(state, size=64):
    model = ExplorerModel(state, sphere_size=size, mesh_size=32, lobe_resolution=8)
    model.update()
    return model


# ------------------------------------------------------------------ albedo above 1
@pytest.mark.parametrize(
    "controls, albedo",
    [
        ({"model": "ward", "ks": 1.0}, 1.365),
        ({"model": "blinn-phong", "shininess": 1.0}, 1.187),
        ({"model": "cook-torrance", "roughness": 1.0, "f0": 1.0}, 1.068),
    ],
)
def test_albedo_above_one_is_flagged(controls, albedo):
    av = _model(AppState(**controls), size=32).views["albedo"]
    assert av.value == pytest.approx(albedo, abs=5e-4)
    assert av.value - 2 * av.error > 1 and av.above_one


def test_albedo_of_the_default_model_is_not_flagged():
    av = _model(AppState(), size=32).views["albedo"]
    assert av.value == pytest.approx(0.5103, abs=1e-4)
    assert not av.above_one and av.channels_above_one == ()


# ------------------------------------------------------------------ the split sphere's divider
def test_split_mask_halves_and_sides():
    for angle in (0.0, 30.0, 90.0, 135.0, -60.0):
        mask = split_mask((64, 64), angle)
        assert mask.sum() == pytest.approx(64 * 64 / 2, abs=64)  # a line through the centre halves the image
        a = math.radians(angle)
        # The current half lies on the counter-clockwise side: the point at +90° from the divider is in it.
        px, py = 20 * math.cos(a + math.pi / 2), 20 * math.sin(a + math.pi / 2)
        assert mask[int(32 - py), int(32 + px)]
    assert split_mask((4, 4), 90.0)[:, :2].all() and not split_mask((4, 4), 90.0)[:, 2:].any()


def test_split_divider_follows_the_light_and_both_halves_show_the_highlight():
    state = AppState()
    model = _model(state, size=96)
    full = model.views["sphere"].image.astype(np.float64) @ LUMA
    model.pin()  # the same model on the other half: the split image is the full one
    state.split = True
    model.update()
    sv = model.views["sphere"]
    assert sv.split_angle == split_angle(state) == 135.0
    np.testing.assert_array_equal(sv.image, model.views["sphere"].image)
    y = sv.image.astype(np.float64) @ LUMA
    near_peak = y >= 0.95 * full.max()
    mask = sv.split_mask
    assert near_peak[mask].any() and near_peak[~mask].any()
    # A vertical divider (the old split) leaves the right half without any of the highlight.
    vertical = split_mask(y.shape, 90.0)
    assert not near_peak[~vertical].any()


def test_split_halves_follow_the_mask():
    state = AppState(model="phong", shininess=5.0)
    model = _model(state, size=48)
    state.model = "lambert"
    model.pin()
    state.model = "phong"
    state.split = True
    state.azimuth = 30.0
    model.update()
    sv = model.views["sphere"]
    lambert = AppState(model="lambert", azimuth=30.0)
    other = _model(lambert, size=48).views["sphere"].image
    alone = _model(AppState(model="phong", shininess=5.0, azimuth=30.0), size=48).views["sphere"].image
    mask = split_mask(sv.image.shape[:2], 30.0)
    np.testing.assert_array_equal(sv.image[mask], alone[mask])
    np.testing.assert_array_equal(sv.image[~mask], other[~mask])


# ------------------------------------------------------------------ skies in the classic form: the exposure
@pytest.mark.slow  # seconds of work: the full run has it, the fast loop leaves it out
@pytest.mark.parametrize("sky", sorted(SKIES))
def test_every_sky_switched_on_clips_at_most_five_percent(sky):
    state = AppState()
    model = _model(state, size=96)
    state.environment = sky
    model.update()
    sv = model.views["sphere"]
    covered = int(sv.coverage.sum())
    before = sv.clipped / covered
    model.apply_auto_exposure()
    sv = model.views["sphere"]
    assert state.form == "classic" and state.exposure == sv.auto_exposure
    assert sv.clipped / covered <= 0.05
    # What the front ends apply is what auto_exposure says of the image, and a tenth of a stop more clips more.
    assert sv.auto_exposure == auto_exposure(sv.image, sv.coverage)
    _, brighter = encode8(sv.image, sv.coverage, state.exposure + 0.1)
    assert brighter >= sv.clipped
    if sky == "uniform":  # the white furnace: π k_d in the classic form, most of the sphere above 1 unadjusted
        assert before > 0.8


@pytest.mark.slow  # seconds of work: the full run has it, the fast loop leaves it out
def test_switching_the_environment_off_restores_the_exposure():
    state = AppState(exposure=0.5)
    model = _model(state, size=32)
    state.environment = "daylight"
    model.apply_auto_exposure()
    auto = state.exposure
    assert auto == model.views["sphere"].auto_exposure and auto < 0
    state.environment = "sunset"  # from sky to sky: the exposure follows, the user's is kept for later
    model.apply_auto_exposure()
    state.environment = "none"
    model.apply_auto_exposure()
    assert state.exposure == 0.5 and model.views["sphere"].auto_exposure is None


# ------------------------------------------------------------------ the fit of a model with a diffuse part
def _albedo(brdf, theta_deg):
    return float(directional_albedo(brdf, math.radians(theta_deg), samples=4096, method="quadrature") @ LUMA)


def test_fit_recovers_lambert_and_the_lobe_when_the_family_holds_the_target():
    # The explorer's Blinn-Phong, normalized, beside its Lambert(k_d × colour): the "blinn-phong" fit's family.
    state = AppState(normalized=True, fit="blinn-phong")
    target = state.brdf()
    assert has_diffuse(target)
    result = fit_model("blinn-phong", target)
    assert result.relative_rms < 1e-4
    np.testing.assert_allclose(result.parameters["kd"], state.diffuse_albedo, rtol=1e-4)
    assert result.parameters["shininess"] == pytest.approx(32.0, rel=1e-4)
    for theta in (0.0, 45.0):
        assert _albedo(result.model, theta) == pytest.approx(_albedo(target, theta), rel=0.02)


@pytest.mark.slow  # seconds of work: the full run has it, the fast loop leaves it out
def test_fit_of_the_default_model_keeps_its_diffuse_albedo():
    # The default surface: Lambert(0.8 × colour) + the classic Blinn-Phong (k_s 0.5, e 32), fitted by GGX.
    state = AppState()
    model = ExplorerModel(state, sphere_size=16, mesh_size=16, lobe_resolution=8)
    target = state.brdf()
    alone = fit_brdf(*FIT_MODELS["ggx"][:1], target, fixed=dict(FIT_MODELS["ggx"][1]))
    entry, result = model.fit()
    assert entry.label.startswith("GGX fit α=") and " + Lambert (rel. rms " in entry.label
    np.testing.assert_allclose(result.parameters["kd"], state.diffuse_albedo, atol=0.015)
    # A specular lobe alone stands for the diffuse part too: a broad lobe, which the term switches cannot take
    # apart.  Beside Lambert the lobe is the highlight's, and the residual halves.  The classic Blinn-Phong's
    # 1/(n·l) is no microfacet lobe's shape: that much residual stays.
    assert alone.parameters["roughness"] > 0.5 > 0.4 > result.parameters["roughness"]
    specular = _albedo(restrict(target, ("specular",)), 0.0)
    assert _albedo(restrict(alone.model, ("specular",)), 0.0) > 3 * specular
    assert _albedo(restrict(result.model, ("specular",)), 0.0) == pytest.approx(specular, rel=0.1)
    assert _albedo(result.model, 0.0) == pytest.approx(_albedo(target, 0.0), rel=0.02)
    assert _albedo(result.model, 45.0) == pytest.approx(_albedo(target, 45.0), rel=0.06)
    assert result.relative_rms < 0.6 * alone.relative_rms


def test_a_target_without_diffuse_is_fitted_by_the_model_alone():
    state = AppState(terms=("specular",), normalized=True)
    target = state.plot_brdf()
    assert not has_diffuse(target)
    result = fit_model("blinn-phong", target)
    assert "kd" not in result.parameters and result.relative_rms < 1e-4

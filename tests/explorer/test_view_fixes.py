"""The explorer's views say and show what is computed: albedo above 1, the split sphere's divider, skies' exposure,
the fit of a model with a diffuse part, a file model's name and its k_d control, one name per environment."""

import math

import numpy as np
import pytest

from explorer.app.state import AppState
from explorer.app.views import ExplorerModel, split_angle, split_mask
from lighting.analysis.machband import LUMA


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

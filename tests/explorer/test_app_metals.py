"""The explorer's metal controls without Qt: a named metal, the conductor Fresnel term, k_d, and the sphere."""

from __future__ import annotations

import numpy as np
import pytest

from explorer.app.params import conductor_none_value, implied_parameters, parameter_table
from explorer.app.state import AppState
from lighting.models.fresnel import METALS, conductor_f0, eta_from_f0, metal_index


def _fresnel_rows(state):
    return {k: state.params[k] for k in ("fresnel", "metal", "eta", "k")}


@pytest.mark.parametrize("model", ["cook-torrance", "mirror"])
@pytest.mark.parametrize("metal", list(METALS))
def test_picking_a_metal_turns_the_fresnel_term_to_the_conductor_and_kd_to_zero(model, metal):
    state = AppState(model=model)
    assert state.params["fresnel"] != "conductor" and state.kd == 0.8
    assert state.set_param("metal", metal) == {"params", "kd"}
    assert _fresnel_rows(state) == {"fresnel": "conductor", "metal": metal, "eta": None, "k": None}
    assert state.kd == 0.0
    assert np.all(state.diffuse_albedo == 0)  # the explorer's Lambert part reflects nothing
    (part,) = state.specular_model().parts
    assert part.metal == metal
    np.testing.assert_array_equal(part.eta, metal_index(metal)[0])
    np.testing.assert_array_equal(part.k, metal_index(metal)[1])


def test_kd_follows_only_the_first_metal_and_never_a_request_that_sets_it():
    state = AppState(model="cook-torrance")
    state.set_param("metal", "gold")
    state.kd = 0.3  # the student adds a diffuse layer back
    state.set_param("metal", "silver")  # metal to metal: k_d stays as set
    assert state.kd == 0.3 and state.params["metal"] == "silver"
    assert AppState(model="cook-torrance", metal="copper", kd=0.5).kd == 0.5
    assert AppState(model="cook-torrance", metal="copper").kd == 0.0


def test_another_fresnel_term_leaves_the_metal_and_its_index():
    state = AppState(model="cook-torrance", metal="gold")
    assert state.set_param("fresnel", "schlick") == {"params"}
    assert _fresnel_rows(state) == {"fresnel": "schlick", "metal": "none", "eta": None, "k": None}
    state.set_param("fresnel", "conductor")
    state.update(eta=0.4, k=2.0)
    state.set_param("fresnel", "dielectric")
    assert _fresnel_rows(state) == {"fresnel": "dielectric", "metal": "none", "eta": None, "k": None}


@pytest.mark.parametrize(("row", "other"), [("eta", "k"), ("k", "eta")])
def test_moving_eta_or_k_leaves_the_metal_and_keeps_its_other_index(row, other):
    state = AppState(model="cook-torrance", metal="gold")
    state.set_param(row, 0.7)
    rows = _fresnel_rows(state)
    assert rows["metal"] == "none" and rows["fresnel"] == "conductor" and rows[row] == 0.7
    gold = dict(zip(("eta", "k"), metal_index("gold"), strict=True))
    assert rows[other] == tuple(gold[other])
    (part,) = state.specular_model().parts
    np.testing.assert_array_equal(part.eta if row == "eta" else part.k, np.full(3, 0.7))
    np.testing.assert_array_equal(part.k if row == "eta" else part.eta, gold[other])


def test_a_contradictory_request_is_still_refused_and_changes_nothing():
    state = AppState(model="cook-torrance")
    before = state.to_dict()
    with pytest.raises(ValueError, match=r"^metal applies to fresnel 'conductor' only"):
        state.update(params={"fresnel": "schlick", "metal": "gold"})
    with pytest.raises(ValueError, match=r"^metal='gold' sets eta and k"):
        state.update(params={"metal": "gold", "eta": 0.5})
    assert state.to_dict() == before


def test_eta_and_k_alone_still_need_the_conductor():
    state = AppState(model="cook-torrance")
    with pytest.raises(ValueError, match=r"^k applies to fresnel 'conductor' only"):
        state.set_param("k", 1.0)
    assert implied_parameters(parameter_table("phong"), {"shininess": 10.0}, {"shininess": 10.0}) == {}


def test_what_a_none_index_stands_for():
    assert conductor_none_value("eta", {"metal": "none", "f0": 0.04}) == pytest.approx(1.5, rel=1e-12)
    assert conductor_none_value("eta", {"metal": "none", "f0": (0.04, 0.5, 0.2)}) == pytest.approx(
        float(eta_from_f0(0.5)), rel=1e-12)  # fmt: skip
    assert conductor_none_value("k", {"metal": "none", "f0": 0.04}) == 0.0
    for metal, (eta, k) in METALS.items():
        assert conductor_none_value("eta", {"metal": metal}) == max(eta)
        assert conductor_none_value("k", {"metal": metal}) == max(k)
    assert conductor_none_value("roughness", {"metal": "gold"}) is None


@pytest.mark.slow  # seconds of work: the full run has it, the fast loop leaves it out
def test_the_engines_sphere_under_a_sky_takes_each_metals_colour():
    """Gold and copper reflect red most and blue least, silver and aluminium nearly grey (their F0's order)."""
    from explorer.app.views import ExplorerModel

    means = {}
    for metal in METALS:
        state = AppState(model="cook-torrance", metal=metal, environment="uniform", light="ambient", ambient=0.0)
        view = ExplorerModel(state, sphere_size=48, mesh_size=32, lobe_resolution=8).compute()["sphere"]
        image = np.asarray(view.image, dtype=np.float64)
        means[metal] = image[view.coverage].mean(axis=0)
    for metal, rgb in means.items():
        f0 = conductor_f0(*metal_index(metal))
        assert list(np.argsort(rgb)) == list(np.argsort(f0)) or np.ptp(f0) < 0.02, (metal, rgb, f0)
        # Under a uniform white sky each pixel's colour is F averaged over its lobe: F0 where the sphere faces
        # the viewer, toward 1 at its rim, so the blue-to-red ratio lies between F0's and 1.
        b_over_r = rgb[2] / rgb[0]
        assert f0[2] / f0[0] - 0.01 <= b_over_r <= max(1.0, f0[2] / f0[0]) + 0.01, (metal, rgb, f0)
    assert means["gold"][2] / means["gold"][0] < 0.75 and means["copper"][2] / means["copper"][0] < 0.8
    for metal in ("silver", "aluminium", "chromium"):
        assert np.ptp(means[metal]) / means[metal].max() < 0.03, (metal, means[metal])

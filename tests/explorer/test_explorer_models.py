"""The explorer finds its models in the registry: a model defined and registered in this file is listed,
selectable, drawn with the engine's values, and read back from a material, with no edit anywhere else."""

from __future__ import annotations

import math

import numpy as np
import pytest

from explorer.app.command import build_parser
from explorer.app.scenes import _apply_material
from explorer.app.state import CONTROLS, MODEL_LABELS, MODELS, AppState, model_choices
from explorer.app.views import ExplorerModel
from explorer.app.widgets import SliderSpec
from lighting import Lambert, Material
from lighting.analysis import lobe_mesh, reciprocity_pair
from lighting.integrate import directional_albedo
from lighting.models import BRDF, Parameter, model_variants, register_model
from lighting.models.protocol import unregister_model
from lighting.render import AnalyticSphere, Renderer, sphere_camera
from lighting.vec import spherical_direction

NAME = "test-explorer-backscatter"


class Backscatter(BRDF):
    """A toy back-scattering lobe, ``f_r = k_s/π · max(l·v, 0)^(s·e)``: peaks toward the light.

    ``ks`` and ``shininess`` are explorer controls; ``scale`` (``s``) is not, so the explorer leaves it
    at its default; the variant ``-sharp`` fixes it at 1.
    """

    name = NAME
    parameters = (
        Parameter("ks", "color", 0.5, slider=(0.0, 1.0), description="lobe strength"),
        Parameter("shininess", "float", 10.0, slider=(0.0, 1e6), log=True, description="exponent e"),
        Parameter("scale", "float", 0.25, low=0.0, high=4.0, description="exponent scale s"),
    )
    variants = {NAME + "-sharp": {"scale": 1.0}}

    def __init__(self, ks=0.5, shininess=10.0, scale=0.25):
        self.ks = np.broadcast_to(np.asarray(ks, dtype=np.float64), (3,)).copy()
        self.shininess = float(shininess)
        self.scale = float(scale)

    def _params(self):
        return {"ks": self.ks, "shininess": self.shininess, "scale": self.scale}

    def _f_cos(self, g):
        lv = np.clip(g._dot(g.l, g.v), 0.0, 1.0).astype(np.float64)
        nl = np.clip(g.n_dot_l, 0.0, 1.0).astype(np.float64)
        s = np.where(g.above, nl * lv ** (self.scale * self.shininess) / math.pi, 0.0)
        return (s[..., None] * self.ks).astype(g.dtype)


@pytest.fixture
def backscatter():
    register_model(Backscatter)
    yield Backscatter
    unregister_model(NAME)


def test_the_model_list_is_the_registry(backscatter):
    assert NAME in MODELS and NAME + "-sharp" in MODELS
    assert model_choices()[-2:] == (NAME, NAME + "-sharp")  # registration order, variants after their model
    assert MODEL_LABELS[NAME + "-sharp"] == "Test-Explorer-Backscatter sharp"
    assert NAME in CONTROLS["model"].choices
    assert SliderSpec("model", "model", choices=MODELS).hi == len(model_choices()) - 1
    assert build_parser().parse_args(["--model", NAME]).model == NAME
    state = AppState()
    state.model = NAME.upper().replace("-", "_")  # choices accept any case and _ for -
    assert state.model == NAME
    # The built-in models: the slides' five first, in the lectures' order, then the registry's others.
    unregister_model(NAME)
    assert model_choices()[:5] == ("lambert", "phong", "blinn-phong", "blinn-phong-normalized", "cook-torrance")
    assert model_choices() == tuple(model_variants())
    assert NAME not in MODELS


@pytest.mark.parametrize("variant", ["", "-sharp"])
def test_the_views_of_a_registered_model_are_the_engines(backscatter, variant):
    state = AppState(model=NAME + variant, ks=0.7, shininess=12.0, elevation=50.0, azimuth=160.0)
    spec = state.specular_model()
    assert type(spec) is Backscatter
    assert (spec.shininess, spec.scale) == (12.0, 1.0 if variant else 0.25)  # no slider for scale: its default
    np.testing.assert_array_equal(spec.ks, [0.7, 0.7, 0.7])

    model = ExplorerModel(state, sphere_size=48, mesh_size=48, lobe_resolution=8)
    views = model.compute()
    assert set(views) == {"sphere", "coarse", "profile", "lobe", "polar", "theta_v", "theta_h", "theta_d",
                          "halfdiff", "albedo"}  # fmt: skip

    # The same BRDF built here, from the class, without the explorer.
    brdf = Lambert(state.diffuse_albedo) + Backscatter(0.7, 12.0, scale=1.0 if variant else 0.25)
    sphere = Renderer(AnalyticSphere(), sphere_camera(48), dtype=np.float32)
    image = sphere.render(Material(brdf), state.lights(), mode="phong", form=state.form, terms=state.terms)
    assert np.array_equal(views["sphere"].image, image)
    assert views["sphere"].image.max() > 0

    theta = state.theta_l
    a, b = reciprocity_pair(brdf, theta, n=361, **state.plot_options())
    assert np.array_equal(views["polar"].light_fixed, a.values) and np.array_equal(views["polar"].view_fixed, b.values)

    lobe = lobe_mesh(brdf, spherical_direction(theta, math.pi), resolution=8, cosine=False, channel="luminance")
    assert np.array_equal(views["lobe"].values, lobe.values.astype(np.float64))

    est = directional_albedo(brdf, theta, samples=4096, method="quadrature", return_error=True)
    assert np.array_equal(views["albedo"].rgb, np.asarray(est.value, dtype=np.float64))
    assert np.isfinite(views["albedo"].value) and views["albedo"].value > 0


def test_a_material_with_the_model_maps_back_onto_the_controls(backscatter):
    state = AppState()
    _apply_material(state, Material(Lambert((0.4, 0.2, 0.1)) + Backscatter((0.3, 0.6, 0.2), 7.0)), "test")
    assert (state.model, state.ks, state.shininess) == (NAME, 0.6, 7.0)  # a colour by its largest channel
    assert state.kd == 0.4 and state.color == (1.0, 0.5, 0.25)
    _apply_material(state, Material(Lambert(0.5) + Backscatter(0.2, 3.0, scale=1.0)), "test")
    assert (state.model, state.ks, state.shininess) == (NAME + "-sharp", 0.2, 3.0)  # the variant's fixed value


def test_an_unregistered_model_is_refused_by_name():
    state = AppState()
    with pytest.raises(ValueError, match="cannot show the model Backscatter"):
        _apply_material(state, Material(Lambert(0.5) + Backscatter()), "scene.toml")
    with pytest.raises(ValueError, match="model must be one of lambert, phong"):
        state.model = NAME

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
    assert build_parser().parse_args(["--model", NAME]).model == NAME
    state = AppState()
    state.model = NAME.upper().replace("-", "_")  # choices accept any case and _ for -
    assert state.model == NAME
    # The built-in models: the slides' five first, in the lectures' order, then the registry's others.
    unregister_model(NAME)
    assert model_choices()[:5] == ("lambert", "phong", "blinn-phong", "blinn-phong-normalized", "cook-torrance")
    assert model_choices() == tuple(model_variants())
    assert NAME not in MODELS


def test_the_windows_model_box_lists_a_registered_model(backscatter, qtbot):
    pytest.importorskip("PySide6")
    from explorer.qt.app import qt_application
    from explorer.qt.controls import ControlPanel

    qt_application()
    panel = ControlPanel(AppState())
    qtbot.addWidget(panel)
    box = panel.widget("model")
    # One item per entry of the registry, in its order, the new model and its variant included.
    assert [box.itemData(k) for k in range(box.count())] == list(MODELS)
    assert box.findData(NAME) >= 0 and box.findData(NAME + "-sharp") >= 0
    requests = []
    panel.change_requested.connect(lambda changes, live: requests.append((changes, live)))
    box.setCurrentIndex(box.findData(NAME + "-sharp"))  # chosen: the panel asks for it, the state takes it
    assert requests == [({"model": NAME + "-sharp"}, False)]
    state = AppState()
    assert state.update(**requests[0][0]) and state.model == NAME + "-sharp"


@pytest.mark.parametrize("variant", ["", "-sharp"])
def test_the_views_of_a_registered_model_are_the_engines(backscatter, variant):
    state = AppState(model=NAME + variant, ks=0.7, shininess=12.0, elevation=50.0, azimuth=160.0)
    spec = state.specular_model()
    assert type(spec) is Backscatter
    assert (spec.shininess, spec.scale) == (12.0, 1.0 if variant else 0.25)  # scale: its default, or the variant's
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
    assert (state.model, state.ks, state.shininess) == (NAME, (0.3, 0.6, 0.2), 7.0)  # a colour keeps its channels
    assert state.kd == 0.4 and state.color == (1.0, 0.5, 0.25)
    _apply_material(state, Material(Lambert(0.5) + Backscatter(0.2, 3.0, scale=1.0)), "test")
    assert (state.model, state.ks, state.shininess) == (NAME + "-sharp", 0.2, 3.0)  # the variant's fixed value


def test_an_unregistered_model_is_refused_by_name():
    state = AppState()
    with pytest.raises(ValueError, match="cannot show the model Backscatter"):
        _apply_material(state, Material(Lambert(0.5) + Backscatter()), "scene.toml")
    with pytest.raises(ValueError, match="model must be one of lambert, phong"):
        state.model = NAME


# ----------------------------------------------------------------------------- generated controls
def test_the_controls_are_the_parameter_table_and_persist_per_model(backscatter):
    from explorer.app.params import offered_parameters

    assert [p.name for p in offered_parameters(NAME)] == ["ks", "shininess", "scale"]
    assert [p.name for p in offered_parameters(NAME + "-sharp")] == ["ks", "shininess"]  # the variant fixes scale
    state = AppState(model=NAME)
    state.set_param("scale", 2.0)
    assert state.model_brdf().scale == 2.0
    state.model = "phong"
    state.shininess = 300.0
    state.model = NAME
    assert state.params == {"ks": 0.5, "shininess": 10.0, "scale": 2.0}  # its own values, not Phong's
    state.model = "phong"
    assert state.shininess == 300.0
    before = state.to_dict()
    for bad in (-1.0, float("nan"), "2", None, True):
        with pytest.raises(ValueError, match="^shininess must be "):
            state.shininess = bad
    with pytest.raises(ValueError, match="^scale must be a parameter of the model phong"):
        state.update(scale=1.0)
    with pytest.raises(ValueError, match="^shininess must be "):
        state.update(model=NAME, params={"shininess": -3})  # the model does not change either
    assert state.to_dict() == before


def test_a_none_default_means_the_linked_value():
    state = AppState(model="ward", params={"alpha_x": 0.1})
    assert state.param("alpha_y") is None and state.model_brdf().alpha_y == 0.1  # = α_x: isotropic
    state.set_param("alpha_y", 0.4)
    assert state.model_brdf().alpha_y == 0.4
    state.set_param("alpha_y", None)
    assert state.model_brdf().alpha_y == 0.1


# ----------------------------------------------------------------------------- the diffuse part
def _centre(model, **params):
    state = AppState(model=model, elevation=90.0, ambient=0.0, params=params)  # light from the viewer
    return ExplorerModel(state, sphere_size=33, mesh_size=32, lobe_resolution=8).compute()["sphere"].image[16, 16]


def test_a_model_with_its_own_diffuse_replaces_the_explorers_lambert():
    lam = _centre("lambert")
    # Facing pixel, light and view along n: classic I = k_d (n·l) = k_d × colour, once.
    np.testing.assert_allclose(lam, AppState().diffuse_albedo, rtol=2e-6)
    np.testing.assert_allclose(_centre("oren-nayar", sigma=0.0), lam, rtol=2e-6)  # σ = 0 is Lambert: not twice it
    state = AppState(model="oren-nayar")
    assert [type(p).__name__ for p in state.brdf().parts] == ["OrenNayar"]
    np.testing.assert_array_equal(state.model_brdf().kd, state.diffuse_albedo)  # k_d × colour fills the facets' k_d
    for model, colour in (("disney", "base_color"), ("ashikhmin-shirley", "rd")):
        state = AppState(model=model)
        assert [type(p).__name__ for p in state.brdf().parts] == [type(state.model_brdf()).__name__]
        np.testing.assert_array_equal(getattr(state.model_brdf(), colour), state.diffuse_albedo)
    # A specular model keeps the explorer's Lambert part.
    assert [type(p).__name__ for p in AppState(model="phong").brdf().parts] == ["Lambert", "Phong"]


# ----------------------------------------------------------------------------- an ideal mirror
class _Delta(BRDF):
    """A test-local ideal mirror: ``f_r`` a Dirac delta about R_l reflecting ``k_s (0.2 + 0.8 cos θ)``."""

    name = "test-explorer-delta"
    is_delta = True
    parameters = (Parameter("ks", "color", 1.0, slider=(0.0, 1.0), description="reflectance"),)

    def __init__(self, ks=1.0):
        self.ks = np.broadcast_to(np.asarray(ks, dtype=np.float64), (3,)).copy()

    def reflectance(self, cos_theta):
        return self._reflectance(np.asarray(cos_theta, dtype=np.float64))

    def _reflectance(self, cos_theta):  # what the engine's integrators ask of a delta part
        return (0.2 + 0.8 * np.asarray(cos_theta, dtype=np.float64))[..., None] * self.ks

    def _f_cos(self, g):
        return np.zeros(g.n_dot_l.shape + (3,), dtype=g.dtype)


@pytest.fixture
def delta():
    register_model(_Delta)
    yield _Delta
    unregister_model(_Delta.name)


def test_an_ideal_mirror_is_a_spike_of_its_reflectance(delta):
    state = AppState(model=_Delta.name, elevation=30.0, params={"ks": 0.5}, channel="r")
    views = ExplorerModel(state, sphere_size=32, mesh_size=32, lobe_resolution=8).compute()
    theta = math.radians(60.0)
    expect = 0.5 * (0.2 + 0.8 * math.cos(theta))
    assert views["polar"].spike == pytest.approx(expect, rel=1e-12)
    assert views["polar"].spike_angle == pytest.approx(theta, abs=1e-12)  # at the mirror direction
    lobe = views["lobe"]
    assert lobe.spike == pytest.approx(expect, rel=1e-12)
    np.testing.assert_allclose(lobe.spike_direction, [math.sin(theta), 0.0, math.cos(theta)], atol=1e-12)
    # Under the view lock the mirror sends light back only at the normal: the spike stands there, with R(0°).
    state.lock = True
    views = ExplorerModel(state, sphere_size=32, mesh_size=32, lobe_resolution=8).compute()
    assert (views["polar"].spike, views["polar"].spike_angle) == (pytest.approx(0.5), 0.0)
    # Below the horizon nothing is reflected: no spike.
    state.update(lock=False, elevation=-5.0)
    views = ExplorerModel(state, sphere_size=32, mesh_size=32, lobe_resolution=8).compute()
    assert views["polar"].spike == 0.0 and views["lobe"].spike == 0.0


def test_anisotropic_vertex_colours_are_the_ones_the_gouraud_image_interpolates():
    """The window draws the coarse sphere's vertex colours; the engine's Gouraud image interpolates its own.
    With an anisotropic model both must be oriented by the mesh's tangents: every Gouraud pixel lies between
    the colours of its triangle's three vertices."""
    from explorer.app.views import ExplorerModel

    model = ExplorerModel()
    model.state.model = "ward"
    model.state.set_param("alpha_x", 0.4)
    model.state.set_param("alpha_y", 0.05)
    coarse = model.compute()["coarse"]
    tri = coarse.triangle_id[coarse.coverage]
    corners = coarse.vertex_colors[coarse.faces[tri]]  # (P, 3 vertices, 3 channels)
    pixels = coarse.gouraud[coarse.coverage]
    slack = 1e-5 * corners.max()
    assert np.all(pixels >= corners.min(axis=1) - slack)
    assert np.all(pixels <= corners.max(axis=1) + slack)

"""A model that defines only its value works everywhere: the protocol's defaults, against closed forms.

``Constant`` defines ``_f(g) = ρ/π`` and nothing else (no flags, no lobe, no sampler, no separable
forms), so every answer below comes from a default of :class:`~lighting.models.base.BRDF`:

    eval = ρ/π,    eval_cos = ρ/π cos θ_l,    classic = ρ cos θ_l,    ρ(θ_v) = ∫ f_r (n·l) dω_l = ρ.

``Cosine`` is the other way round: it defines only ``_f_cos(g) = ρ/π cos θ_l``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from sphere_scene import one_sphere

from lighting.models import BRDF, Parameter, register_model
from lighting.models.base import BRDFFlags
from lighting.models.lambert import CosineSampler
from lighting.models.protocol import unregister_model

RHO = np.array([0.6, 0.3, 0.9])


class Constant(BRDF):
    """``f_r = ρ/π``: Lambert's value, written as the minimal model."""

    name = "test-minimal-constant"
    parameters = (Parameter("rho", "color", 0.5, description="albedo"),)

    def __init__(self, rho=0.5):
        self.rho = np.broadcast_to(np.asarray(rho, dtype=np.float64), (3,)).copy()

    def _params(self):
        return {"rho": self.rho}

    def _f(self, g):
        return np.where(g.above[..., None], self.rho / math.pi, 0.0).astype(g.dtype)


class Cosine(BRDF):
    """``f_r (n·l) = ρ/π cos θ_l``: the same model through the other value method."""

    def __init__(self, rho):
        self.rho = np.asarray(rho, dtype=np.float64)

    def _f_cos(self, g):
        return np.where(g.above[..., None], self.rho / math.pi * g.n_dot_l[..., None], 0.0).astype(g.dtype)


class Nothing(BRDF):
    """Defines no value method at all."""


N = np.array([0.0, 0.0, 1.0])
THETA = np.radians([0.0, 20.0, 45.0, 70.0, 89.0])
L = np.stack([np.sin(THETA), np.zeros_like(THETA), np.cos(THETA)], axis=-1)
V = np.array([0.3, -0.2, 0.9])


@pytest.fixture
def registered():
    register_model(Constant)
    yield Constant
    unregister_model(Constant.name)


@pytest.mark.parametrize("model", [Constant(RHO), Cosine(RHO)], ids=["f", "f_cos"])
def test_values_are_the_closed_forms(model):
    cos = np.cos(THETA)[:, None]
    np.testing.assert_allclose(model.eval(N, L, V), np.broadcast_to(RHO / math.pi, (5, 3)), rtol=1e-12)
    np.testing.assert_allclose(model.eval_cos(N, L, V), RHO / math.pi * cos, rtol=1e-12)
    np.testing.assert_allclose(model.classic(N, L, V), RHO * cos, rtol=1e-12)
    below = np.array([0.0, 0.6, -0.8])
    for form in (model.eval, model.eval_cos, model.classic):
        assert form(N, below, V).tolist() == [0.0, 0.0, 0.0]
        assert form(*(x.astype(np.float32) for x in (N, L, V))).dtype == np.float32


def test_a_model_without_a_value_says_so():
    with pytest.raises(NotImplementedError, match=r"Nothing must define _f\(g\).*or _f_cos\(g\)"):
        Nothing().eval_cos(N, L, V)
    with pytest.raises(NotImplementedError, match="Nothing must define"):
        Nothing().classic(N, L, V)
    with pytest.raises(NotImplementedError, match="Nothing must define"):
        Nothing().eval(N, L, V)


def test_the_description_defaults():
    m = Constant(RHO)
    assert m.flags == BRDFFlags.SPECULAR and m.term == "specular"
    assert not (m.lambertian or m.own_diffuse or m.is_delta)
    assert m.lobe() is None and m.microfacet() is None
    assert m.parts == (m,) and m.diffuse_albedo.tolist() == [0.0, 0.0, 0.0]
    assert m.summary() == repr(m) == "Constant(rho=(0.6, 0.3, 0.9))"
    # Only the cosine-weighted sampler: its density is cos θ / π.
    s = m.sampler()
    assert isinstance(s, CosineSampler)
    np.testing.assert_allclose(s.pdf(L, np.broadcast_to(N, L.shape)), np.cos(THETA) / math.pi, rtol=1e-12)


def test_scene_file_form_round_trips(registered):
    m = Constant(RHO)
    assert m.to_dict() == {"model": "test-minimal-constant", "rho": [0.6, 0.3, 0.9]}
    assert Constant.from_dict(m.to_dict()).to_dict() == m.to_dict()
    with pytest.raises(ValueError, match="no scene-file form for the model Cosine"):
        Cosine(RHO).to_dict()


@pytest.mark.parametrize("model", [Constant(RHO), Cosine(RHO)], ids=["f", "f_cos"])
def test_the_directional_albedo_is_rho(model):
    from lighting.integrate import directional_albedo

    np.testing.assert_allclose(directional_albedo(model, np.radians([0.0, 40.0, 80.0])), np.tile(RHO, (3, 1)),
                               rtol=1e-9)  # fmt: skip
    mc = directional_albedo(model, 0.5, samples=4096, method="importance", seed=3, return_error=True)
    # The cosine sampler is exact importance sampling for a constant f_r: every sample weighs ρ.
    np.testing.assert_allclose(mc.value, RHO, rtol=1e-12)


def test_shading_falls_back_to_the_channels():
    from lighting.lights import DirectionalLight
    from lighting.shading import Material, shade
    from lighting.shading.separable import is_separable, stacks, terms

    m = Constant(RHO)
    assert not is_separable(m) and not stacks(m)
    lights = [DirectionalLight(direction=(0.0, 0.6, 0.8), intensity=2.0),
              DirectionalLight(direction=(0.8, 0.0, 0.6), intensity=1.0)]  # fmt: skip
    normals = np.array([[0.0, 0.0, 1.0], [0.0, 0.6, 0.8], [0.0, -1.0, 0.0]])
    material = Material(m, ambient=0.0)
    cos = np.clip(normals @ np.array([[0.0, 0.6, 0.8], [0.8, 0.0, 0.6]]).T, 0.0, None)
    exact = (2.0 * cos[:, :1] + 1.0 * cos[:, 1:]) * RHO  # classic: I ρ cos θ_l per light
    for form, scale in (("classic", 1.0), ("physical", 1.0 / math.pi)):
        out = shade(None, normals, material, lights, view_dir=(0.0, 0.0, 1.0), form=form)
        np.testing.assert_allclose(out, exact * scale, rtol=1e-12, atol=1e-15)
    from lighting.models.geometry import Geometry

    g = Geometry(N, L, V)
    fields = terms(m, g, "classic")
    assert [c.tolist() for _, c in fields] == np.eye(3).tolist()
    np.testing.assert_allclose(np.stack([s for s, _ in fields], axis=-1), RHO * np.cos(THETA)[:, None], rtol=1e-12)


def test_a_scene_renders_it_as_lambert(registered):
    from lighting.scene import parse_scene, render_scene

    minimal = parse_scene(one_sphere('{model = "test-minimal-constant", rho = [0.6, 0.3, 0.9]}'))
    lambert = parse_scene(one_sphere('{model = "lambert", kd = [0.6, 0.3, 0.9]}'))
    image, reference = np.asarray(render_scene(minimal)[0]), np.asarray(render_scene(lambert)[0])
    assert reference.max() > 0.1 and np.count_nonzero(reference.max(axis=-1) > 0) > 100
    np.testing.assert_allclose(image, reference, rtol=1e-12, atol=1e-15)

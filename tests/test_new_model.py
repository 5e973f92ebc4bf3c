"""Adding a reflectance model is one module and one registration: a model defined in this file is found everywhere.

Minnaert's darkening law (Minnaert 1941, "The reciprocity principle in lunar photometry"),

    f_r = k_d/π · ((n·l)(n·v))^(k−1),      k >= 1,

is reciprocal, equals Lambert at ``k = 1``, and has the directional albedo at normal view

    ρ(0) = ∫ k_d/π (n·l)^k dω_l = 2 k_d / (k + 1).

Nothing outside this file (and ``test_new_model_full.py``, its slow companion) names the class: sampling, albedo,
the audit, polar slices and lobes, scene files and the explorer's model list find it through the registry and the
model protocol.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from sphere_scene import one_sphere

from lighting.models import BRDF, Lobe, Parameter, register_model
from lighting.models.protocol import unregister_model


class Minnaert(BRDF):
    """Minnaert's limb-darkening BRDF, ``k_d/π ((n·l)(n·v))^(k−1)`` (Minnaert 1941)."""

    name = "test-minnaert"
    term = "diffuse"
    parameters = (
        Parameter("kd", "color", 0.5, slider=(0.0, 1.0), description="albedo at k = 1"),
        Parameter("k", "float", 2.0, low=1.0, high=8.0, description="darkening exponent"),
    )

    def __init__(self, kd=0.5, k=2.0):
        self.kd = np.broadcast_to(np.asarray(kd, dtype=np.float64), (3,)).copy()
        if not 1.0 <= float(k) <= 8.0:
            raise ValueError(f"k must be in [1, 8]; got {k!r}")
        self.k = float(k)

    def _params(self):
        return {"kd": self.kd, "k": self.k}

    def lobe(self):
        return Lobe("normal")

    def _f_cos(self, g):
        nl = np.clip(g.n_dot_l, 0, 1).astype(np.float64)
        nv = np.clip(g.n_dot_v, 0, 1).astype(np.float64)
        s = np.where(g.above, nl**self.k * nv ** (self.k - 1) / math.pi, 0.0)
        return (s[..., None] * self.kd).astype(g.dtype)


@pytest.fixture
def minnaert():
    register_model(Minnaert)
    yield Minnaert
    unregister_model(Minnaert.name)


def test_registry_finds_it(minnaert):
    from lighting.models import create_model, model_class, model_names

    assert "test-minnaert" in model_names()
    assert model_class("test-minnaert") is Minnaert
    m = create_model("test-minnaert", kd=0.4, k=3.0)
    assert m.to_dict() == {"model": "test-minnaert", "kd": [0.4, 0.4, 0.4], "k": 3.0}
    assert Minnaert.from_dict(m.to_dict()).to_dict() == m.to_dict()


def test_albedo_by_quadrature_and_by_sampling(minnaert):
    from lighting.integrate import directional_albedo, importance_sampler, sample_brdf

    m = Minnaert(0.6, 3.0)
    exact = 2 * 0.6 / (3.0 + 1)
    q = directional_albedo(m, 0.0)
    np.testing.assert_allclose(q, exact, rtol=1e-9)
    mc = directional_albedo(m, 0.0, samples=20000, method="importance", seed=1, return_error=True)
    assert np.all(np.abs(mc.value - exact) <= 4 * mc.error + 1e-12)
    # Its own sampler (the protocol's default, cosine-weighted) and a mixture with a built-in model.
    s = sample_brdf(m, np.array([0.0, 0.0, 1.0]), 256, seed=2)
    np.testing.assert_allclose(s.pdf, s.directions[:, 2] / math.pi, rtol=1e-12)
    from lighting import Phong

    assert len(importance_sampler(m + Phong(0.3, 20)).samplers) == 2


def test_audit_tells_the_truth(minnaert):
    from lighting.analysis.audit import AuditCase, audit

    table = audit([AuditCase("Minnaert k=2", Minnaert(1.0, 2.0), "")], samples=1024)
    (row,) = table.rows
    assert row.params == repr(Minnaert(1.0, 2.0))  # the protocol's default summary
    assert row.positive and row.reciprocal and row.energy
    np.testing.assert_allclose(row.albedo_normal, 2 * 1.0 / 3.0, rtol=1e-6)


def test_polar_slice_and_lobe(minnaert):
    from lighting.analysis import lobe_mesh, lobe_peak, lobe_width, polar_slice

    m = Minnaert(0.5, 2.0)
    ps = polar_slice(m, math.radians(30.0), n=91)
    nl, nv = math.cos(math.radians(30.0)), np.cos(np.asarray(ps.angles, dtype=np.float64))
    expect = np.where(nv > 0, 0.5 / math.pi * (nl * np.clip(nv, 0, 1)) ** (2.0 - 1), 0.0)
    np.testing.assert_allclose(
        np.asarray(ps.values, dtype=np.float64), expect[:, None] * [1, 1, 1], rtol=1e-9, atol=1e-15
    )
    assert lobe_width(m, 0.3) == math.inf  # a lobe about the normal: no narrow lobe to follow
    l = np.array([math.sin(0.3), 0.0, math.cos(0.3)])  # noqa: E741
    peak = lobe_peak(m, l)
    np.testing.assert_allclose(peak.value, 0.5 / math.pi * math.cos(0.3), rtol=1e-9)
    mesh = lobe_mesh(m, l, resolution=24)
    assert np.all(np.isfinite(mesh.vertices)) and mesh.vertices.shape[-1] == 3


def test_scene_file_loads_renders_and_writes_it_back(minnaert):
    from lighting.scene import parse_scene, render_scene, scene_to_toml

    scene = parse_scene(one_sphere('{model = "test-minnaert", kd = 0.7, k = 1.0}', size=32))
    lambert = parse_scene(one_sphere('{model = "lambert", kd = 0.7}', size=32))
    image, reference = np.asarray(render_scene(scene)[0]), np.asarray(render_scene(lambert)[0])
    assert reference.max() > 0.1
    # Minnaert at k = 1 is Lambert: the same image, pixel for pixel (to rounding).
    np.testing.assert_allclose(image, reference, rtol=1e-12, atol=1e-15)
    again = parse_scene(scene_to_toml(scene))
    assert scene_to_toml(again) == scene_to_toml(scene)
    assert '"test-minnaert"' in scene_to_toml(scene)


def test_explorer_lists_and_shows_it(minnaert):
    pytest.importorskip("matplotlib")
    from explorer.app.state import AppState, model_choices
    from explorer.app.views import ExplorerModel

    assert "test-minnaert" in model_choices()
    state = AppState(model="test-minnaert")
    model = ExplorerModel(state)
    views = model.compute()
    assert views  # every panel computed


def _smallest_text_pt(fig):
    from matplotlib.text import Text

    return min(t.get_fontsize() for t in fig.findobj(Text) if t.get_visible() and t.get_text().strip())


def test_the_model_gallery_shows_it_on_one_readable_slide(minnaert):
    pytest.importorskip("matplotlib")
    from explorer.figures import make_figure
    from explorer.figures.base import SLIDE_SIZES
    from explorer.figures.zoo import card_grid, gallery_entries

    fig, _, _, _, m = make_figure("model_gallery_normal_mirror", quick=True)
    names = [name for name, _ in gallery_entries("normal")]
    assert "test-minnaert" in names and list(m["models"]) == names
    # Its card measures Minnaert's albedo at normal view, 2 k_d / (k + 1), with the default k_d = 0.5, k = 2.
    assert m["models"]["test-minnaert"]["rho0"] == pytest.approx(2 * 0.5 / 3, rel=1e-9)
    # One more card still fits one 16:9 slide, every card drawn, no text below 10 px at 1280 px across.
    assert tuple(fig.get_size_inches()) == pytest.approx(SLIDE_SIZES["16:9"])
    rows, cols = card_grid(len(names))
    assert len(fig.subfigs) == rows * cols >= len(names)
    assert sum(1 for sub in fig.subfigs if sub.axes) == len(names)
    assert _smallest_text_pt(fig) * 1280 / (72 * fig.get_figwidth()) >= 10

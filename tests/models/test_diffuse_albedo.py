"""``BRDF.diffuse_albedo``: one meaning for every model — the diffuse reflectance at normal incidence.

``diffuse_albedo = ρ_d(v = n) = ∫ f_d (n·l) dω_l`` for the part ``f_d`` of ``f_r`` that carries the
surface's diffuse colour; the ambient term's default ``k_a`` (``Material(brdf).ambient``).  Each model
is checked against a closed form and against the engine's quadrature of the model itself at ``θ_v = 0``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from lighting.integrate import directional_albedo
from lighting.models import create_model, model_names
from lighting.models.ashikhmin_shirley import AshikhminShirley
from lighting.models.disney import Disney
from lighting.models.lambert import Lambert
from lighting.models.oren_nayar import OrenNayar
from lighting.shading.material import Material

KD = np.array([0.9, 0.5, 0.1])


def test_lambert_is_kd():
    np.testing.assert_array_equal(Lambert(KD).diffuse_albedo, KD)
    np.testing.assert_allclose(directional_albedo(Lambert(KD), 0.0), KD, rtol=3e-14)  # measured 2e-15 (R), 2e-15 (B)


@pytest.mark.parametrize("sigma", [0.0, 0.2, 0.5, 1.0])
@pytest.mark.parametrize("form", ["qualitative", "full"])
def test_oren_nayar_at_normal_incidence(sigma, form):
    # v = n: β = 0, so f_r = k_d A/π (+ k_d² R/π in the full form), A = 1 − σ²/(2(σ² + 0.33)), R = 0.17 σ²/(σ² + 0.13).
    m = OrenNayar(KD, sigma, form=form)
    s2 = sigma * sigma
    want = KD * (1 - 0.5 * s2 / (s2 + 0.33)) + (KD * KD * 0.17 * s2 / (s2 + 0.13) if form == "full" else 0.0)
    np.testing.assert_allclose(m.diffuse_albedo, want, rtol=1e-15)
    np.testing.assert_allclose(directional_albedo(m, 0.0), want, rtol=1e-12)
    if sigma == 0.0:
        np.testing.assert_array_equal(m.diffuse_albedo, KD)  # Lambert's


@pytest.mark.parametrize("rs", [0.0, 0.05, (0.04, 0.3, 1.0)])
def test_ashikhmin_shirley_diffuse_term_at_normal_incidence(rs):
    # ρ_d(v) = R_d (1 − R_s) (1 − (1 − n·v/2)⁵): 31/32 R_d (1 − R_s) at the normal.
    m = AshikhminShirley(rd=KD, rs=rs, nu=300, nv=20)
    want = KD * (1 - np.asarray(rs, dtype=float)) * 31 / 32
    np.testing.assert_allclose(m.diffuse_albedo, want, rtol=1e-15)
    specular = AshikhminShirley(rd=KD, rs=rs, nu=300, nv=20, diffuse=False)
    np.testing.assert_allclose(directional_albedo(m, 0.0) - directional_albedo(specular, 0.0), want, atol=2e-12)
    np.testing.assert_array_equal(specular.diffuse_albedo, np.zeros(3))


@pytest.mark.parametrize("roughness", [0.0, 0.3, 0.5, 1.0])
@pytest.mark.parametrize("metallic", [0.0, 0.6])
def test_disney_diffuse_at_normal_incidence_closed_form(roughness, metallic):
    # v = n: F_V = 0, cos²θ_d = (1 + μ)/2, so π f_d = 1 + (r (1 + μ) − 1/2)(1 − μ)⁵ and
    # 2 ∫ π f_d μ dμ = 1 + 2 ((r − 1/2) B(2, 6) + r B(3, 6)) = 1 + (r − 1/2)/21 + r/84.
    m = Disney(base_color=KD, metallic=metallic, roughness=roughness)
    want = (1 - metallic) * KD * (1 + (roughness - 0.5) / 21 + roughness / 84)
    np.testing.assert_allclose(m.diffuse_albedo, want, rtol=1e-14)


@pytest.mark.parametrize("subsurface", [0.0, 0.5, 1.0])
def test_disney_diffuse_against_the_quadrature(subsurface):
    # The base-colour terms are what changes between a white and a black base (dielectric, untinted):
    # the difference of the two models' albedos at θ_v = 0 (the specular parts cancel on the same nodes).
    kw = {"roughness": 0.7, "subsurface": subsurface, "sheen": 0.5, "sheen_tint": 0.0, "clearcoat": 0.3}
    white, black = Disney(base_color=1.0, **kw), Disney(base_color=0.0, **kw)
    # 100 000 nodes: the clearcoat's α_c = 0.001 spike leaves 1.3e-10 at 20 000; measured 7e-15 here.
    got = directional_albedo(white, 0.0, 100_000) - directional_albedo(black, 0.0, 100_000)
    np.testing.assert_allclose(white.diffuse_albedo, got, rtol=1e-13)
    np.testing.assert_array_equal(Disney(base_color=KD, **kw).diffuse_albedo, KD * white.diffuse_albedo)


@pytest.mark.parametrize("name", ["phong", "blinn-phong", "cook-torrance", "ward", "mirror"])
def test_specular_models_have_none(name):
    if name not in model_names():
        pytest.skip(f"{name} is not registered")
    np.testing.assert_array_equal(create_model(name).diffuse_albedo, np.zeros(3))


def test_sums_add_and_material_ambient_defaults_to_it():
    m = Lambert(0.2) + OrenNayar(0.5, 0.3) + AshikhminShirley(rd=0.4) + Disney(base_color=0.6)
    parts = sum(p.diffuse_albedo for p in m.parts)
    np.testing.assert_allclose(m.diffuse_albedo, parts, rtol=1e-15)
    np.testing.assert_allclose(Material(m).ambient, parts, rtol=1e-15)
    assert math.isclose(float(Material(Lambert(0.3)).ambient[0]), 0.3)

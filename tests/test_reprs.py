"""Models and lights print one short line: exact strings, no arrays, and the line rebuilds the object."""

from __future__ import annotations

import numpy as np
import pytest

from lighting import AmbientLight, DirectionalLight, Material, PointLight
from lighting.lights import DiskLight, RectLight, SpotLight
from lighting.models import model_variants
from lighting.models.ashikhmin_shirley import AshikhminShirley
from lighting.models.blinn_phong import BlinnPhong
from lighting.models.cook_torrance import CookTorrance
from lighting.models.disney import Disney
from lighting.models.lambert import Lambert
from lighting.models.mirror import Mirror
from lighting.models.oren_nayar import OrenNayar
from lighting.models.phong import Phong
from lighting.models.ward import Ward

MODELS = [
    (Phong(), "Phong(ks=0.5, shininess=32)"),
    (Phong(0.25, 200), "Phong(ks=0.25, shininess=200)"),
    (Lambert((0.8, 0.2, 0.1)), "Lambert(kd=(0.8, 0.2, 0.1))"),
    (BlinnPhong(0.3, 40, normalized=True), "BlinnPhong(ks=0.3, shininess=40, normalized=True)"),
    (CookTorrance(), "CookTorrance(ks=1, roughness=0.3, f0=0.04)"),
    (
        CookTorrance(roughness=0.1, ndf="ggx", geometry="smith"),
        "CookTorrance(ks=1, roughness=0.1, f0=0.04, ndf='ggx', geometry='smith')",
    ),
    (OrenNayar(sigma=0.5), "OrenNayar(kd=0.8, sigma=0.5)"),
    (Ward(1.0, 0.1, 0.4), "Ward(ks=1, alpha_x=0.1, alpha_y=0.4)"),
    (AshikhminShirley(), "AshikhminShirley(rd=0.5, rs=0.05, nu=200, nv=20)"),
    (Disney(), "Disney(base_color=0.8)"),
    (Disney(roughness=0.2, metallic=1.0), "Disney(base_color=0.8, metallic=1, roughness=0.2)"),
    (Mirror(0.9), "Mirror(ks=0.9, f0=0.04)"),
    (Lambert(0.5) + Phong(0.3, 1 / 3), "Lambert(kd=0.5) + Phong(ks=0.3, shininess=0.333333)"),
]

LIGHTS = [
    (PointLight((2, 2, 3), intensity=20), "PointLight(position=(2, 2, 3), intensity=20)"),
    (PointLight((0, 0, 4.0), attenuation=(0, 0, 1)),
     "PointLight(position=(0, 0, 4), intensity=1, attenuation=(0, 0, 1))"),
    (DirectionalLight((0, 0, 2.0), color=(1, 0.5, 0.25)),
     "DirectionalLight(direction=(0, 0, 1), color=(1, 0.5, 0.25), intensity=1)"),
    (DirectionalLight((1, 1, 1)), "DirectionalLight(direction=(0.57735, 0.57735, 0.57735), intensity=1)"),
    (AmbientLight(0.1), "AmbientLight(color=0.1, intensity=0.2)"),
    (
        SpotLight(position=(0, 0, 5), direction=(0, 0, -1), cutoff_deg=20, exponent=8),
        "SpotLight(position=(0, 0, 5), direction=(0, 0, -1), cutoff_deg=20, intensity=1, exponent=8)",
    ),
    (
        RectLight(center=(0, 2, 1), samples=64, two_sided=True),
        "RectLight(center=(0, 2, 1), edge_u=(1, 0, 0), edge_v=(0, -1, 0), intensity=1, samples=64, two_sided=True)",
    ),
    (DiskLight(radius=0.25, seed=3),
     "DiskLight(center=(0, 0, 5), normal_dir=(0, 0, -1), radius=0.25, intensity=1, seed=3)"),
]  # fmt: skip

NAMESPACE = {c.__name__: c for c in (Phong, Lambert, BlinnPhong, CookTorrance, OrenNayar, Ward, AshikhminShirley,
                                     Disney, Mirror, PointLight, DirectionalLight, AmbientLight, SpotLight, RectLight,
                                     DiskLight)}  # fmt: skip


@pytest.mark.parametrize(("obj", "text"), MODELS + LIGHTS, ids=lambda x: x if isinstance(x, str) else "")
def test_exact_repr(obj, text):
    assert repr(obj) == text
    assert "array" not in text and "\n" not in text


@pytest.mark.parametrize(("obj", "text"), [m for m in MODELS if "+" not in m[1]] + LIGHTS,
                         ids=lambda x: x if isinstance(x, str) else "")  # fmt: skip
def test_repr_rebuilds_an_equal_object(obj, text):
    # The line is a constructor call: evaluated, it gives an object that behaves the same (to 6 digits).
    again = eval(text, NAMESPACE)  # noqa: S307 - our own repr strings
    assert type(again) is type(obj) and repr(again) == text
    if hasattr(obj, "eval"):
        n, l, v = np.array([0, 0, 1.0]), np.array([0.3, 0.1, 0.9]), np.array([-0.2, 0.2, 0.95])
        l, v = l / np.linalg.norm(l), v / np.linalg.norm(v)
        np.testing.assert_allclose(again.eval(n, l, v), obj.eval(n, l, v), rtol=1e-12)
    else:
        np.testing.assert_allclose(again.radiant, obj.radiant, rtol=1e-12)


def test_every_registered_model_prints_one_short_line():
    for name, (cls, fixed) in model_variants().items():
        text = repr(cls(**fixed))
        assert text.startswith(cls.__name__ + "(") and "\n" not in text and "array" not in text, name
        assert len(text) <= 80, (name, text)


@pytest.mark.parametrize(
    ("material", "text"),
    [
        (lambda: Material(Lambert(0.8) + Phong(0.5, 32)), "Material(Lambert(kd=0.8) + Phong(ks=0.5, shininess=32))"),
        (lambda: Material(Phong(0.5, 32), ambient=0.1, emission=(1, 0, 0)),
         "Material(Phong(ks=0.5, shininess=32), ambient=0.1, emission=(1, 0, 0))"),
        (lambda: Material(Lambert((0.8, 0.2, 0.1)), ambient=(0.8, 0.2, 0.1)), "Material(Lambert(kd=(0.8, 0.2, 0.1)))"),
    ],
)
def test_material_repr_leaves_out_its_defaults_and_rebuilds_it(material, text):
    m = material()
    assert repr(m) == text
    again = eval(text, {"Material": Material, "Lambert": Lambert, "Phong": Phong})  # noqa: S307 - our own repr
    np.testing.assert_array_equal(again.ambient, m.ambient)
    np.testing.assert_array_equal(again.emission, m.emission)
    assert repr(again.brdf) == repr(m.brdf)

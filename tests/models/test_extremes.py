"""The numerical contract: finite in, finite out, in float32 and float64, no warnings.

Warnings are errors for the whole suite (pyproject.toml), so any NumPy
floating-point warning raised here fails the test.
"""

import itertools
import math

import numpy as np
import pytest

from lighting import (
    AmbientLight,
    BlinnPhong,
    CookTorrance,
    DirectionalLight,
    Lambert,
    Material,
    Phong,
    PointLight,
    RectLight,
    SpotLight,
    shade,
)

MODELS = [
    Lambert(1.0),
    Phong(1.0, 0.0),
    Phong(1.0, 1.0),
    Phong(1.0, 1e6),
    BlinnPhong(1.0, 0.0),
    BlinnPhong(1.0, 1e6),
    BlinnPhong(1.0, 0.0, normalized=True),
    BlinnPhong(1.0, 1e6, normalized=True),
    # Exponents that round to 0 or overflow in float32, and a huge colour.
    Phong(1.0, 1e-300),
    Phong(1.0, 1e300),
    BlinnPhong(1.0, 1e-300),
    BlinnPhong(1.0, 1e-300, normalized=True),
    BlinnPhong(1.0, 1e39),
    BlinnPhong(1.0, 1e300, normalized=True),
    BlinnPhong((1e300, 0.0, 1e-300), 1e7, normalized=True),
]
for ndf, geo, fr, den in itertools.product(
    ("beckmann", "ggx", "blinn-phong"), ("v-cavity", "smith"), ("schlick", "dielectric", "none"), ("4", "pi")
):
    for alpha in (1e-6, 1e-3, 1.0, 3.0):
        MODELS.append(CookTorrance(1.0, alpha, 0.04, ndf=ndf, geometry=geo, fresnel=fr, denominator=den))


def _dir(theta, phi=0.0):
    return [math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)]


def _directions():
    """Hard directions: the normal, grazing to 1e-8 and 1e-30 rad, exactly horizontal, below, tiny/huge length."""
    out = [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, -1.0]]
    for d in (1e-3, 1e-8, 1e-12, 1e-30):
        out += [[1.0, 0.0, d], [-1.0, 0.0, d], [0.0, 1.0, d], [math.cos(0.3), math.sin(0.3), d]]
    out += [_dir(t, p) for t in (0.2, 0.8, 1.4) for p in (0.0, 1.0, math.pi)]
    out += [[0.0, 0.0, 1e-30], [3e-25, 0.0, 4e-25], [1e30, 0.0, 1e30], [0.0, 0.0, 0.0]]
    return np.array(out)


D = _directions()
L_ALL, V_ALL = (a.reshape(-1, 3) for a in np.meshgrid(np.arange(len(D)), np.arange(len(D)), indexing="ij"))
NORMALS = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 7.5], [0.0, 0.0, 1e-20], [0.0, 0.0, 0.0], [1e-3, 0.0, 1.0]])


@pytest.mark.slow  # seconds of work: the full run has it, the fast loop leaves it out
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("model", MODELS, ids=repr)
def test_every_model_is_finite_and_nonnegative_on_hard_inputs(model, dtype):
    li = np.arange(len(D)).repeat(len(D))
    vi = np.tile(np.arange(len(D)), len(D))
    l, v = D[li].astype(dtype), D[vi].astype(dtype)  # noqa: E741
    # l = v, l = -v and l = v = n are all in this product set.
    for n in NORMALS.astype(dtype):
        for f in (model.eval(n, l, v), model.eval_cos(n, l, v), model.classic(n, l, v)):
            assert f.dtype == dtype
            assert np.all(np.isfinite(f)), f"non-finite values for n={n}"
            assert np.all(f >= 0)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_phong_brdf_division_by_n_dot_l_stays_finite(dtype):
    # The slides' Phong BRDF divides by n·l; at n·l = 1e-30 its value exceeds float32, and saturates.
    n = np.array([0, 0, 1], dtype)
    l = np.array([1, 0, 1e-30], dtype)  # noqa: E741
    v = np.array([-1, 0, 1e-30], dtype)
    f = Phong(1.0, 0.0).eval(n, l, v)
    assert np.all(np.isfinite(f)) and np.all(f > 1e20)
    # The cosine-weighted form never divides and is exactly k_s/π.
    np.testing.assert_allclose(Phong(1.0, 0.0).eval_cos(n, l, v), 1 / math.pi, rtol=1e-6)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_shininess_million_lobe_keeps_its_shape(dtype):
    # exp(e·log1p(−(1−cos))) keeps the digits of 1 − cos that a millionth power amplifies.
    e = 1e6
    eps = np.array([0.0, 1e-4, 1e-3, 2e-3], dtype=np.float64)
    l = np.stack([np.sin(0.5 + eps), np.zeros(4), np.cos(0.5 + eps)], -1).astype(dtype)  # noqa: E741
    v = np.array([-math.sin(0.5), 0.0, math.cos(0.5)], dtype=dtype)
    got = Phong(1.0, e).classic(np.array([0, 0, 1], dtype), l, v)[:, 0]
    expected = np.cos(eps) ** e
    tol = 1e-9 if dtype is np.float64 else 0.5  # float32: the input angles themselves round at 6e-8
    np.testing.assert_allclose(got, expected, rtol=tol, atol=1e-300)
    assert np.all(np.diff(got) <= 0)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_shading_extreme_lights_is_finite(dtype):
    pts = np.array([[0, 0, 0], [0, 0, 2 - 1e-12], [1e-30, 0, 2], [0, 0, -1e12], [5, 5, 0]], dtype=dtype)
    nrm = np.array([[0, 0, 1], [0, 0, 1], [0, 0, 0], [1e-3, 0, 1], [0, 1e-20, 1e-20]], dtype=dtype)
    lights = [
        AmbientLight(intensity=1e30),
        DirectionalLight((1.0, 0.0, 1e-8), intensity=1e-30),
        PointLight((0, 0, 2.0), intensity=1e30),
        PointLight((0, 0, 0.0), attenuation=(0, 0, 1)),
        SpotLight((0, 0, 2.0), direction=(0, 0, -1.0), cutoff_deg=0),
        SpotLight((0, 0, 2.0), direction=(0, 0, -1.0), cutoff_deg=90, exponent=1e6),
        SpotLight((0, 0, 2.0), direction=(0, 0, -1.0), cutoff_deg=180),
        RectLight((0, 0, 2.0), (1, 0, 0), (0, -1, 0), intensity=1e20, samples=4),
    ]
    for model in (Lambert(1.0) + Phong(1.0, 1e6), CookTorrance(1.0, 1e-6, 1.0), BlinnPhong(1.0, 0.0)):
        for form in ("classic", "physical"):
            out = shade(pts, nrm, Material(model), lights, eye=(0, 0, 1e12), form=form)
            assert out.dtype == dtype
            assert np.all(np.isfinite(out)) and np.all(out >= 0)

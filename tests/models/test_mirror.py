"""The ideal mirror (a delta BRDF): its reflectance in closed form, its zero function part, its sampler.

Measured here (float64): ``reflectance`` equals Schlick's polynomial and the exact dielectric (vs
50-digit mpmath) to 2 ulp; the dielectric at ``cos θ = 1e-9`` is within 1e-8 of 1.  The integrals
(albedo, environment radiance, the limits of the glossy models) are in tests/integrate/test_delta.py.
"""

from __future__ import annotations

import math
import tomllib

import mpmath
import numpy as np
import pytest

from lighting.analysis.lobes import lobe_width
from lighting.analysis.meshes import lobe_mesh
from lighting.integrate import importance_sampler, sample_brdf
from lighting.models import Lobe, create_model, model_class, model_names
from lighting.models.brdf import Lambert, Phong
from lighting.models.fresnel import f0_from_eta
from lighting.models.mirror import Mirror, MirrorSampler
from lighting.scene import load_scene
from lighting.scene.renderer import SceneRenderer

COS = np.array([1.0, 0.9, 0.5, 0.2, 1e-3, 1e-9])


def _mp_dielectric(c, eta):
    """Unpolarized Fresnel reflectance at 50 digits (Born & Wolf), light arriving from outside."""
    with mpmath.workdps(50):
        c, eta = mpmath.mpf(c), mpmath.mpf(eta)
        ct = mpmath.sqrt(1 - (1 - c * c) / (eta * eta))
        rs = (c - eta * ct) / (c + eta * ct)
        rp = (eta * c - ct) / (eta * c + ct)
        return float((rs * rs + rp * rp) / 2)


def test_registered_and_round_trips():
    assert "mirror" in model_names() and model_class("mirror") is Mirror
    m = create_model("mirror", ks=[0.9, 0.8, 0.7], f0=0.5, fresnel="schlick")
    assert m.to_dict() == {"model": "mirror", "ks": [0.9, 0.8, 0.7], "f0": [0.5, 0.5, 0.5], "fresnel": "schlick"}
    assert m.is_delta is True and Lambert(0.5).is_delta is False
    assert m.summary() == "mirror ks=(0.9,0.8,0.7) schlick f0=0.5"


def test_reflectance_without_fresnel_is_ks_above_the_horizon_and_0_below():
    r = Mirror((0.9, 0.5, 0.1)).reflectance([1.0, 0.3, 1e-12, 0.0, -0.5])
    np.testing.assert_array_equal(r, [[0.9, 0.5, 0.1]] * 3 + [[0.0, 0.0, 0.0]] * 2)


def test_reflectance_schlick_closed_form():
    f0 = np.array([0.04, 0.5, 0.95])
    got = Mirror(0.8, f0, "schlick").reflectance(COS)
    want = 0.8 * (f0 + (1 - f0) * (1 - COS[:, None]) ** 5)
    np.testing.assert_allclose(got, want, rtol=4e-16, atol=0)
    assert got[0, 0] == pytest.approx(0.8 * 0.04, rel=1e-15)  # F0 at normal incidence
    np.testing.assert_allclose(got[-1], 0.8, rtol=1e-8)  # grazing: F → 1


@pytest.mark.parametrize("eta", [1.333, 1.5, 2.4])
def test_reflectance_dielectric_against_mpmath(eta):
    f0 = float(f0_from_eta(eta))
    got = Mirror(1.0, f0, "dielectric").reflectance(COS)[:, 0]
    want = np.array([_mp_dielectric(c, eta) for c in COS])
    # η is recovered from F0 (as Cook–Torrance does): the rounding of F0 = ((η − 1)/(η + 1))² is all that differs.
    np.testing.assert_allclose(got, want, rtol=2e-15, atol=0)
    assert got[0] == pytest.approx(((eta - 1) / (eta + 1)) ** 2, rel=1e-15)  # normal incidence
    assert 1 - got[-1] < 1e-8  # grazing: total reflection in the limit


def test_reflectance_keeps_float32_and_shapes():
    m = Mirror(0.7, 0.04, "dielectric")
    c32 = np.linspace(-1, 1, 24, dtype=np.float32).reshape(2, 3, 4)
    r = m.reflectance(c32)
    assert r.dtype == np.float32 and r.shape == (2, 3, 4, 3)
    np.testing.assert_allclose(r, m.reflectance(c32.astype(np.float64)), rtol=6e-8)
    assert m.reflectance(0.5).shape == (3,) and m.reflectance(0.5).dtype == np.float64
    big = Mirror(1e300).reflectance(np.float32(0.5))  # saturated, not inf
    assert np.all(big == np.finfo(np.float32).max)


@pytest.mark.parametrize(
    "kwargs, name",
    [({"ks": -0.1}, "ks"), ({"f0": 1.5}, "f0"), ({"fresnel": "metallic"}, "fresnel"), ({"ks": math.nan}, "ks")],
)
def test_bad_parameters_name_themselves(kwargs, name):
    with pytest.raises(ValueError, match=name):
        Mirror(**kwargs)


@pytest.mark.parametrize("bad", [1.5, -1.2, math.nan, math.inf])
def test_bad_cosines_are_refused(bad):
    with pytest.raises(ValueError, match="cos_theta"):
        Mirror().reflectance(bad)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_eval_is_zero_even_on_the_exact_mirror_pair(dtype):
    # The delta is not a function: a point light seen exactly along R_l still gives 0.
    n = np.array([[0.0, 0.0, 1.0], [0.0, 0.6, 0.8]], dtype=dtype)
    l = np.array([[0.6, 0.0, 0.8], [0.0, 0.0, 1.0]], dtype=dtype)  # noqa: E741
    v = 2 * n * np.sum(n * l, axis=-1, keepdims=True) - l
    m = Mirror(1.0)
    for f in (m.eval(n, l, v), m.eval_cos(n, l, v), m.classic(n, l, v)):
        assert f.dtype == dtype and f.shape == (2, 3)
        np.testing.assert_array_equal(f, 0.0)
    np.testing.assert_array_equal((Lambert(0.5) + m).eval(n, l, v), Lambert(0.5).eval(n, l, v))


def test_sampler_returns_the_mirror_direction_with_the_reflectance_as_weight():
    m = Mirror((0.9, 0.6, 0.3), 0.04, "schlick")
    s = m.sampler()
    assert isinstance(s, MirrorSampler) and s.delta is True
    rng = np.random.default_rng(1)
    v = rng.normal(size=(50, 3))
    v[:, 2] = np.abs(v[:, 2])
    u = rng.random((50, 2))
    out = s.sample(u, 3.0 * v)  # not unit: normalized
    unit = v / np.linalg.norm(v, axis=-1, keepdims=True)
    np.testing.assert_allclose(out.directions, unit * [-1, -1, 1], rtol=0, atol=4e-16)
    np.testing.assert_array_equal(out.pdf, 1.0)
    np.testing.assert_allclose(s.weight(v), m.reflectance(unit[:, 2]), rtol=1e-15)
    np.testing.assert_array_equal(s.pdf(out.directions, v), 0.0)
    np.testing.assert_array_equal(s.weight([[0.6, 0.0, -0.8], [0.0, 0.0, 0.0]]), 0.0)  # below the horizon, zero v


def test_importance_sampler_of_sums_leaves_the_delta_to_the_integrators():
    assert repr(importance_sampler(Lambert(0.5) + Mirror(0.5))) == "CosineSampler()"
    assert repr(importance_sampler(Mirror(0.5) + Phong(0.5, 20))) == "PhongSampler(20.0)"
    both = importance_sampler(Mirror(0.25) + Mirror(0.5, 0.04, "schlick"))
    assert both.delta is True
    np.testing.assert_allclose(both.weight([0.0, 0.0, 1.0]), 0.25 + 0.5 * 0.04, rtol=1e-15)
    d = sample_brdf(Mirror(), np.array([0.6, 0.0, 0.8]), 16, seed=2).directions
    np.testing.assert_allclose(d, np.broadcast_to([-0.6, 0.0, 0.8], (16, 3)), rtol=0, atol=1e-16)


def test_lobe_has_no_width_to_divide_by_and_plots_show_the_smooth_part():
    assert Mirror().lobe() == Lobe()
    assert lobe_width(Mirror()) == math.inf
    assert lobe_width(Phong(1.0, 100) + Mirror()) == pytest.approx(0.1)
    with_mirror = lobe_mesh(Lambert(0.5) + Mirror(0.9), (0.6, 0.0, 0.8), resolution=16)
    alone = lobe_mesh(Lambert(0.5), (0.6, 0.0, 0.8), resolution=16)
    np.testing.assert_array_equal(with_mirror.vertices, alone.vertices)


SCENE = """
[camera]
eye = [0.0, 0.0, 6.0]
target = [0.0, 0.0, 0.0]
fov_y_deg = 30.0

[image]
width = 48
height = 32
background = [0.0, 0.0, 0.0]

[materials.silver]
parts = [{{model = "mirror", ks = 0.9, fresnel = "schlick", f0 = 0.9}}]
ambient = {ambient}

[materials.glazed]
parts = [{{model = "lambert", kd = 0.5}}, {{model = "mirror", ks = 0.3}}]

[materials.matte]
parts = [{{model = "lambert", kd = 0.5}}]

[[objects]]
type = "sphere"
center = [-1.1, 0.0, 0.0]
radius = 0.8
material = "silver"

[[objects]]
type = "sphere"
center = [1.1, 0.0, 0.0]
radius = 0.8
material = "{right}"

[[lights]]
type = "ambient"
intensity = 0.2

[[lights]]
type = "point"
position = [0.0, 2.0, 4.0]
intensity = 5.0

[[lights]]
type = "directional"
direction = [0.3, 0.5, 1.0]
intensity = 1.0
"""


def _render(tmp_path, **fields):
    path = tmp_path / "mirror.toml"
    path.write_text(SCENE.format(**fields))
    tomllib.loads(path.read_text())  # the text is valid TOML before the loader sees it
    image, _ = SceneRenderer(load_scene(path)).render()
    return image


def test_scene_file_mirror_is_black_under_point_lights_plus_its_ambient(tmp_path):
    image = _render(tmp_path, ambient="[0.25, 0.5, 1.0]", right="glazed")
    left = image[16, 12]  # the centre of the mirror sphere
    # Only I_a k_a: the point and directional lights have no image in an ideal mirror.
    np.testing.assert_allclose(left, 0.2 * np.array([0.25, 0.5, 1.0]), rtol=1e-6)
    silver = image[6:26, 2:22]
    assert np.all((silver == 0) | np.isclose(silver, left, rtol=1e-6))  # sphere or background, nothing else
    # Lambert + mirror renders exactly as Lambert alone under these lights.
    matte = _render(tmp_path, ambient="0.0", right="matte")
    np.testing.assert_array_equal(image[:, 24:], matte[:, 24:])
    assert np.all(matte[:, :24] == 0)  # the mirror without ambient: black

"""All directional lights at once: StackedGeometry against one Geometry per light, and its helpers."""

import math

import mpmath
import numpy as np
import pytest

from lighting import AmbientLight, DirectionalLight, Material, PointLight
from lighting.models.brdf import BlinnPhong, CookTorrance, Geometry, Lambert, Phong
from lighting.numerics import log1p
from lighting.render.camera import Camera
from lighting.render.mesh import sphere_for_triangles
from lighting.render.renderer import Renderer
from lighting.shading.equation import shade
from lighting.shading.stacked import StackedGeometry

MODELS = [
    Lambert(0.7),
    BlinnPhong(0.5, 40.0),
    BlinnPhong(0.5, 1e4, normalized=True),
    BlinnPhong(0.5, 0.0),
    Phong(0.3, 20.0),
    CookTorrance(1.0, 0.2, 0.04, geometry="smith"),
    CookTorrance(1.0, 0.05, 0.5, ndf="ggx", fresnel="dielectric"),
    CookTorrance(1.0, 0.1, 0.9, ndf="blinn-phong", fresnel="none", denominator="pi"),
]


def _unit(a):
    return a / np.linalg.norm(a, axis=-1, keepdims=True)


def _configurations(rng, dt):
    """Random points plus the hard ones: near-mirror views, light and viewer nearly opposite, grazing."""
    n = _unit(rng.normal(size=(3000, 3)))
    v = _unit(rng.normal(size=(3000, 3)))
    lights = _unit(rng.normal(size=(4, 3)))
    mirror = 2 * n[:1000] * (n[:1000] @ lights[0])[:, None] - lights[0]
    v[:1000] = _unit(mirror + 1e-3 * rng.normal(size=(1000, 3)))
    v[1000:1500] = _unit(-lights[1] + 1e-4 * rng.normal(size=(500, 3)))
    lights[2] = _unit(lights[2] - (lights[2] @ n[1600]) * n[1600] + 1e-6 * n[1600])  # grazing at point 1600
    return n.astype(dt), lights.astype(dt), v.astype(dt)


@pytest.mark.parametrize("distant", [False, True])
def test_stacked_geometry_is_as_accurate_as_one_geometry_per_light(distant):
    # float32 against the truth of the same rounded inputs in float64: the directions they
    # stand for, normalized in float64 (rounded to float32 they are unit only to rounding, and
    # with e = 1e4 a length 1 + 3e-8 changes (n·h)^e where the two paths differ).  The stacked
    # path may round differently from the per-light one, but not worse than it by more than a
    # few ulp of the brightest value.  (Both paths, in both dtypes, are also held to
    # 8 kappa u point by point against 80-digit references in the stability sweep.)
    dtype = np.float32
    rng = np.random.default_rng(7)
    n, lights, v = _configurations(rng, dtype)
    if distant:
        v = v[5]
    g = StackedGeometry(n, lights, v)
    eps = np.finfo(dtype).eps
    for model in MODELS:
        for form in ("classic", "cos"):
            fields = model.separable_classic(g) if form == "classic" else model.separable_cos(g)
            for k in range(len(lights)):
                g64 = Geometry(n.astype(np.float64), lights[k].astype(np.float64), v.astype(np.float64))
                g1 = Geometry(n, lights[k], v, unit=True, dtype=dtype)
                method = "classic_geometry" if form == "classic" else "eval_cos_geometry"
                truth = getattr(model, method)(g64)
                one = getattr(model, method)(g1).astype(np.float64)
                assert all(np.asarray(f).dtype == dtype for f, _ in fields)
                got = sum(np.broadcast_to(f, (len(lights), len(n)))[k][:, None] * c.astype(dtype) for f, c in fields)
                assert np.all(np.isfinite(got)) and np.all(got >= 0)
                scale = np.abs(truth).max()
                err_stacked = np.abs(got - truth).max() / scale
                err_one = np.abs(one - truth).max() / scale
                assert err_stacked <= 2 * err_one + 64 * eps, (model, form, k, err_stacked / eps, err_one / eps)


def test_stacked_geometry_quantities_match_the_definitions():
    n = _unit(np.array([[0.1, 0.2, 1.0], [0.0, 1.0, 0.3], [0.5, -0.5, 0.7]]))
    l = _unit(np.array([[0.3, 0.1, 1.0], [-1.0, 0.2, 0.4]]))  # noqa: E741
    v = _unit(np.array([[0.0, 0.0, 1.0], [0.2, 0.9, 0.1], [-0.3, 0.1, 0.9]]))
    g = StackedGeometry(n, l, v)
    for k in range(2):
        h = _unit(l[k] + v)
        np.testing.assert_allclose(g.n_dot_l[k], n @ l[k], rtol=1e-14)
        np.testing.assert_allclose(g.n_dot_h[k], np.sum(n * h, axis=1), rtol=1e-14)
        np.testing.assert_allclose(g.v_dot_h[k], np.sum(v * h, axis=1), rtol=1e-14)
        np.testing.assert_allclose(g.sin2_h[k], np.sum(np.cross(n, h) ** 2, axis=1), rtol=1e-13)
        np.testing.assert_allclose(g.one_minus_n_dot_h[k], 1 - np.sum(n * h, axis=1), rtol=1e-12)
        r = 2 * n * (n @ l[k])[:, None] - l[k]
        np.testing.assert_allclose(g.one_minus_r_dot_v[k], 1 - np.sum(r * v, axis=1), rtol=1e-12)
        np.testing.assert_allclose(g.sin2_l[k], np.sum(np.cross(n, l[k]) ** 2, axis=1), rtol=1e-13)
        lit = g.above[k]
        tan2 = np.sum(np.cross(n, h) ** 2, axis=1) / np.sum(n * h, axis=1) ** 2
        np.testing.assert_allclose(g.tan2_h[k][lit], tan2[lit], rtol=1e-13)
    np.testing.assert_array_equal(g.above, (g.n_dot_l > 0) & (np.sum(n * v, axis=1) > 0))
    assert g.delicate is None


@pytest.mark.parametrize("shininess", [0.5, 40.0])
def test_delicate_entries_take_the_half_vector_form(shininess):
    # Lit pairs where tan²θ_h = |n × s|²/(n·s)² is not used: light and viewer more than 120°
    # apart (|l + v| < 1), and a half vector 1e-21 rad above the horizon, where (n·s)² is
    # subnormal in float32 and the quotient would overflow.  Their lobes come from the n·h
    # form, and every lit value matches float64 evaluated on the same float32 vectors.
    n = np.array([[0, 0, 1.0]] * 3, dtype=np.float32)
    v = np.array([_unit(np.array([1, 0, 0.05])), [1, 0, 1e-21], _unit(np.array([0.3, 0.2, 1.0]))], dtype=np.float32)
    lights = np.array([_unit(np.array([-1, 0, 0.3])), [0, 1, 1e-21]], dtype=np.float32)
    g = StackedGeometry(n, lights, v)
    assert sorted(zip(*g.delicate, strict=True)) == [(0, 0), (0, 1), (1, 1)]  # (light, point)
    model = BlinnPhong(1.0, shininess)
    (field, _), = model.separable_classic(g)
    assert field.dtype == np.float32 and np.all(np.isfinite(field))
    for k in range(2):
        truth = model.classic(n.astype(np.float64), lights[k].astype(np.float64), v.astype(np.float64))[:, 0]
        np.testing.assert_allclose(field[k], truth, rtol=1e-5, atol=1e-38)
    if shininess < 1:
        assert field[1, 1] > 1e-11  # (n·h)^0.5 = 3.8e-11 at 1e-21 rad above the horizon


def test_light_exactly_opposite_the_viewer_gives_zero_not_nan():
    n = np.array([[0.0, 0.0, 1.0]])
    g = StackedGeometry(n, np.array([[1.0, 0.0, 0.0]]), np.array([[-1.0, 0.0, 0.0]]))
    assert g._len2.tolist() == [[0.0]]
    for model in MODELS:
        for f, _ in model.separable_classic(g):
            assert np.all(np.broadcast_to(f, (1, 1)) == 0)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_shading_with_stacked_lights_equals_the_per_light_sum(dtype):
    # shade() stacks the directional lights; lighting them one call at a time takes the per-light path.
    rng = np.random.default_rng(3)
    p = rng.normal(size=(500, 3)).astype(dtype)
    nrm = _unit(rng.normal(size=(500, 3))).astype(dtype)
    mat = Material(Lambert((0.7, 0.3, 0.2)) + BlinnPhong(0.5, 60.0), emission=0.01)
    lights = [AmbientLight(intensity=0.1), DirectionalLight((1, 1, 1.0), color=(1, 0.9, 0.8)),
              DirectionalLight((-1, 0.2, 0.5), intensity=0.5), PointLight((0, 3, 2.0))]  # fmt: skip
    both = shade(p, nrm, mat, lights, eye=(0, 0, 8.0))
    parts = [shade(p, nrm, mat, [lt], eye=(0, 0, 8.0), terms=("diffuse", "specular")) for lt in lights[1:]]
    single = shade(p, nrm, mat, [lights[0]], eye=(0, 0, 8.0), terms=("emission", "ambient")) + sum(parts)
    assert both.dtype == dtype
    np.testing.assert_allclose(both, single, rtol=64 * np.finfo(dtype).eps, atol=8 * np.finfo(dtype).eps)


def test_renderer_view_cache_is_reused_and_does_not_change_the_image():
    cam = Camera((0, 0, 6.0), (0, 0, 0), width=96, height=96)
    r = Renderer(sphere_for_triangles(800), cam, dtype=np.float32)
    mat = Material(Lambert(0.6) + BlinnPhong(0.4, 30.0))
    a = r.render(mat, [DirectionalLight((1, 1, 1.0))])
    cache = r._cache[("view terms", "phong")]
    assert any("n_dot_v" in part for part in cache.values())
    b = r.render(mat, [DirectionalLight((1, 1, 1.0))])
    fresh = Renderer(sphere_for_triangles(800), cam, dtype=np.float32).render(mat, [DirectionalLight((1, 1, 1.0))])
    np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(a, fresh)


def test_log1p_through_log_is_accurate_to_a_few_ulp():
    rng = np.random.default_rng(0)
    x = np.concatenate([-rng.random(20000), -(10.0 ** rng.uniform(-30, 0, 20000)), 10.0 ** rng.uniform(-30, 3, 20000)])
    x32 = x.astype(np.float32)
    ref32 = np.log1p(x32.astype(np.float64))  # float64 log1p is exact to far below a float32 ulp
    got32 = log1p(x32)
    assert got32.dtype == np.float32
    ulp32 = np.abs(got32 - ref32) / np.abs(ref32) / np.finfo(np.float32).eps
    assert ulp32.max() < 3  # measured 2.4 (in units of eps = 2u)
    sample = x[::300]
    ref64 = np.array([float(mpmath.log1p(mpmath.mpf(float(t)))) for t in sample])
    ulp64 = np.abs(log1p(sample) - ref64) / np.abs(ref64) / np.finfo(np.float64).eps
    assert ulp64.max() < 3
    assert log1p(np.float32(0.0)) == 0 and math.isinf(float(log1p(np.array(-1.0))))
    assert log1p(np.array([1e-30], dtype=np.float32))[0] == np.float32(1e-30)


def test_the_renderer_path_does_not_repeat_the_public_argument_checks(monkeypatch):
    # Arguments are checked once, at the public boundary (eval, eval_cos, classic and the
    # public microfacet/Fresnel functions); shading and rendering call the unchecked forms.
    import lighting.models.base as base_mod
    import lighting.models.fresnel as fresnel_mod
    import lighting.models.microfacet as mf_mod

    def forbidden(*args, **kwargs):
        raise AssertionError("a public argument check ran on the shading path")

    models = [Lambert(0.6) + BlinnPhong(0.4, 30.0, normalized=True), Phong(0.5, 20.0),
              CookTorrance(1.0, 0.2, 0.04, geometry="smith", fresnel="dielectric"),
              CookTorrance(1.0, 0.1, 0.5, ndf="blinn-phong"), CookTorrance(1.0, 0.3, ndf="ggx")]  # fmt: skip
    cam = Camera((0, 0, 6.0), (0, 0, 0), width=48, height=48)
    renderer = Renderer(sphere_for_triangles(300), cam, dtype=np.float32)
    lights = [DirectionalLight((1, 1, 1.0)), DirectionalLight((-1, 0.5, 1.0)), PointLight((0, 3, 3.0))]
    expected = [renderer.render(Material(m), lights) for m in models]
    monkeypatch.setattr(base_mod, "_public_geometry", forbidden)
    monkeypatch.setattr(mf_mod, "_public", forbidden)
    monkeypatch.setattr(mf_mod, "check_alpha", forbidden)
    monkeypatch.setattr(fresnel_mod, "_cosines", forbidden)
    for m, want in zip(models, expected, strict=True):
        np.testing.assert_array_equal(renderer.render(Material(m), lights), want)

import math
import re

import numpy as np
import pytest

from lighting import (
    AmbientLight,
    BlinnPhong,
    CookTorrance,
    DirectionalLight,
    DiskLight,
    Lambert,
    Material,
    Phong,
    PointLight,
    RectLight,
    SpotLight,
    shade,
    shade_terms,
    vec,
)

ORIGIN = np.zeros((1, 3))
UP = (0.0, 0.0, 1.0)


def irradiance(light, points):
    """Irradiance arriving on a surface facing each incidence direction (no n·l)."""
    return sum(inc.irradiance for inc in light.incident(np.asarray(points, dtype=float)))


def horizontal_irradiance(light, points):
    """Irradiance on an upward-facing surface: Σ E (n·l) with n = +z."""
    return sum(
        inc.irradiance * np.maximum(inc.direction[..., 2:3], 0)
        for inc in light.incident(np.asarray(points, dtype=float))
    )


# ------------------------------------------------------------------ lights
def test_directional_same_everywhere():
    light = DirectionalLight((1.0, 1.0, 1.0), color=(1.0, 0.5, 0.25), intensity=2.0)
    inc = next(light.incident(np.random.default_rng(0).normal(size=(10, 3))))
    np.testing.assert_allclose(inc.direction, np.ones(3) / math.sqrt(3))
    np.testing.assert_allclose(inc.irradiance, [2.0, 1.0, 0.5])


def test_point_light_falloff_formula():
    pts = np.array([[0, 0, 0.0], [0, 0, 1.0], [3.0, 0, 2.0]])
    light = PointLight((0, 0, 2.0), intensity=4.0, attenuation=(0.5, 0.25, 1.0))
    r = np.array([2.0, 1.0, 3.0])
    np.testing.assert_allclose(irradiance(light, pts)[:, 0], 4.0 / (0.5 * r**2 + 0.25 * r + 1.0), rtol=1e-15)
    # Default: the physical inverse-square law.
    np.testing.assert_allclose(irradiance(PointLight((0, 0, 2.0)), pts)[:, 0], 1 / r**2, rtol=1e-15)
    inc = next(light.incident(pts))
    np.testing.assert_allclose(inc.direction, vec.normalize(np.array([0, 0, 2.0]) - pts), atol=1e-16)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_point_light_at_extreme_distances_is_finite(dtype):
    pts = np.array([[0, 0, 0], [0, 0, 2 - 1e-12], [0, 0, 2 - 1e12], [0, 0, 2 - 1e-30]], dtype=dtype)
    inc = next(PointLight((0, 0, 2.0)).incident(pts))
    assert inc.irradiance.dtype == dtype
    assert np.all(np.isfinite(inc.irradiance)) and np.all(np.isfinite(inc.direction))
    # A point exactly at the light has no direction toward it and receives nothing.
    at = next(PointLight((0, 0, 0.0)).incident(np.zeros((1, 3), dtype)))
    assert at.irradiance.tolist() == [[0.0, 0.0, 0.0]] and at.direction.tolist() == [[0.0, 0.0, 0.0]]


def test_spot_light_cone_and_exponent():
    spot = SpotLight((0, 0, 1.0), direction=(0, 0, -1.0), cutoff_deg=45, exponent=2.0, attenuation=(0, 0, 1))
    angles = np.radians([0.0, 30.0, 44.9, 45.1, 80.0])
    pts = np.stack([np.tan(angles), np.zeros(5), np.zeros(5)], -1)
    got = irradiance(spot, pts)[:, 0]
    expected = np.where(angles <= np.radians(45), np.cos(angles) ** 2, 0.0)
    np.testing.assert_allclose(got, expected, rtol=1e-14, atol=0)
    # 180 means no cone at all; 90 is exactly the lower half-space; 0 only the axis.
    wide = SpotLight((0, 0, 1.0), direction=(0, 0, -1.0), cutoff_deg=180, attenuation=(0, 0, 1))
    np.testing.assert_allclose(irradiance(wide, pts)[:, 0], 1.0)
    half = SpotLight((0, 0, 0.0), direction=(0, 0, -1.0), cutoff_deg=90, attenuation=(0, 0, 1))
    np.testing.assert_array_equal(irradiance(half, [[1, 0, 0.0], [1, 0, -1e-9], [1, 0, 1e-9]])[:, 0], [1, 1, 0])
    pin = SpotLight((0, 0, 1.0), direction=(0, 0, -1.0), cutoff_deg=0, attenuation=(0, 0, 1))
    np.testing.assert_array_equal(irradiance(pin, [[0, 0, 0.0], [1e-3, 0, 0]])[:, 0], [1, 0])


def test_disk_light_matches_closed_form_and_converges():
    # On-axis irradiance of a Lambertian disk of radiance L, radius R, height h: π L R² / (h² + R²).
    h, radius, radiance = 1.5, 1.0, 2.0
    exact = math.pi * radiance * radius**2 / (h**2 + radius**2)
    errors = []
    for s in (4, 16, 64, 256, 1024, 4096):
        light = DiskLight((0, 0, h), (0, 0, -1.0), radius, intensity=radiance, samples=s)
        errors.append(abs(horizontal_irradiance(light, ORIGIN)[0, 0] - exact) / exact)
    assert errors[-1] < 1e-4
    assert errors[-1] < errors[0] / 1000  # low-discrepancy points: error falls about as 1/samples


def test_rect_light_tends_to_point_light():
    point = PointLight((0.3, -0.2, 2.0), intensity=1.0)
    pts = np.array([[0, 0, 0.0], [1.0, 0.5, 0.0]])
    n = np.array([0, 0, 1.0])
    mat = Material(Lambert(1.0))
    ref = shade(pts, n, mat, [point], view_dir=UP)
    for size, tol in ((0.2, 1e-2), (0.02, 1e-3)):  # the error shrinks with the light's size
        rect = RectLight(
            center=(0.3, -0.2, 2.0), edge_u=(size, 0, 0), edge_v=(0, -size, 0), intensity=1 / size**2, two_sided=True
        )
        # A face-on square: cosθ_e differs from 1 across it, so compare with the light's own facing factor.
        got = shade(pts, n, mat, [rect], view_dir=UP)
        cos_e = 2.0 / np.linalg.norm(np.array([0.3, -0.2, 2.0]) - pts, axis=-1)
        np.testing.assert_allclose(got, ref * cos_e[:, None], rtol=tol)


def test_area_light_seed_changes_pattern_and_stays_unbiased():
    h, radius = 1.0, 0.8
    exact = math.pi * radius**2 / (h**2 + radius**2)
    est = [
        horizontal_irradiance(DiskLight((0, 0, h), (0, 0, -1.0), radius, samples=8, seed=s), ORIGIN)[0, 0]
        for s in range(400)
    ]
    assert len(set(np.round(est, 12))) > 300
    assert np.mean(est) == pytest.approx(exact, abs=3 * np.std(est) / math.sqrt(len(est)) + 1e-12)


@pytest.mark.parametrize(
    "factory, match",
    [
        (lambda: PointLight(attenuation=(0, 0, 0)), "attenuation"),
        (lambda: PointLight(attenuation=(1, -1, 0)), "attenuation"),
        (lambda: PointLight(position=(0, float("nan"), 0)), "position"),
        (lambda: SpotLight(cutoff_deg=120), "cutoff_deg"),
        (lambda: SpotLight(cutoff_deg=-1), "cutoff_deg"),
        (lambda: SpotLight(exponent=-2), "exponent"),
        (lambda: DirectionalLight((0, 0, 0)), "direction"),
        (lambda: DirectionalLight(color=(1, 0)), "color"),
        (lambda: AmbientLight(intensity=-1), "intensity"),
        (lambda: DiskLight(samples=0), "samples"),
        (lambda: DiskLight(radius=0), "radius"),
        (lambda: RectLight(edge_u=(1, 0, 0), edge_v=(2, 0, 0)), "edge_u"),
    ],
)
def test_bad_light_parameters(factory, match):
    with pytest.raises(ValueError, match=match) as info:
        factory()
    assert "got" in str(info.value)


# ------------------------------------------------------------------ illumination equation
def test_red_light_on_green_surface_is_black():
    out = shade(ORIGIN, UP, Material(Lambert((0, 1, 0))), [DirectionalLight(UP, color=(1, 0, 0))], view_dir=UP)
    assert out.tolist() == [[0.0, 0.0, 0.0]]


def test_blue_light_on_white_and_red_surfaces():
    blue = [AmbientLight(color=(0, 0, 1), intensity=1.0)]
    white = shade(ORIGIN, UP, Material(Lambert(1.0)), blue, view_dir=UP)
    red = shade(ORIGIN, UP, Material(Lambert((1, 0, 0))), blue, view_dir=UP)
    assert white.tolist() == [[0.0, 0.0, 1.0]]
    assert red.tolist() == [[0.0, 0.0, 0.0]]


def test_classic_equation_by_hand():
    # I = I_a k_a + Σ_p I_p/A(d_p) (k_d n·l + k_s (r·v)^n), one point light with attenuation.
    p = np.array([0.2, -0.1, 0.0])
    n = vec.normalize(np.array([0.1, 0.2, 1.0]))
    eye = np.array([1.0, 2.0, 4.0])
    lp = np.array([-2.0, 1.0, 3.0])
    ka, kd, ks, e = np.array([0.1, 0.2, 0.3]), np.array([0.7, 0.5, 0.2]), np.array([0.4, 0.4, 0.4]), 15.0
    ia, ip = np.array([0.3, 0.3, 0.2]), np.array([1.0, 0.9, 0.8])
    a, b, c = 0.05, 0.1, 1.0
    l = vec.normalize(lp - p)  # noqa: E741
    v = vec.normalize(eye - p)
    r = 2 * n * (n @ l) - l
    d = np.linalg.norm(lp - p)
    expected = ia * ka + ip / (a * d * d + b * d + c) * (kd * (n @ l) + ks * max(r @ v, 0) ** e)
    mat = Material(Lambert(kd) + Phong(ks, e), ambient=ka)
    lights = [AmbientLight(ia, 1.0), PointLight(lp, ip, 1.0, attenuation=(a, b, c))]
    np.testing.assert_allclose(shade(p, n, mat, lights, eye=eye), expected, rtol=1e-13)
    # The UBC slide's d_p: distance to the light plus distance to the viewer.
    d2 = d + np.linalg.norm(eye - p)
    exp2 = ia * ka + ip / (a * d2 * d2 + b * d2 + c) * (kd * (n @ l) + ks * max(r @ v, 0) ** e)
    got2 = shade(p, n, mat, lights, eye=eye, attenuation_distance="light+viewer")
    np.testing.assert_allclose(got2, exp2, rtol=1e-13)


MODELS = [
    Lambert(0.6) + Phong(0.4, 30.0),
    Lambert(0.5) + BlinnPhong(0.5, 60.0),
    Lambert(0.3) + BlinnPhong(0.2, 60.0, normalized=True),
    Lambert(0.2) + CookTorrance(1.0, 0.2, 0.5, ndf="ggx", geometry="smith"),
]


def _scene(seed=0, k=200):
    rng = np.random.default_rng(seed)
    pts = rng.uniform(-1, 1, (k, 3))
    nrm = vec.normalize(rng.normal(size=(k, 3)))
    lights = [
        AmbientLight((0.2, 0.3, 0.4), 0.5),
        DirectionalLight((0.3, 0.4, 1.0), (1.0, 0.9, 0.8)),
        PointLight((2.0, 1.0, 3.0), (0.5, 0.5, 1.0), 9.0, attenuation=(1, 0.2, 0.1)),
        SpotLight((0, 0, 4.0), (1, 1, 1), 20.0, direction=(0.1, 0, -1.0), cutoff_deg=35, exponent=4),
        RectLight((1, -1, 3.0), (0.5, 0, 0), (0, -0.5, 0), intensity=4.0, samples=9),
    ]
    return pts, nrm, lights


@pytest.mark.parametrize("brdf", MODELS, ids=repr)
def test_physical_form_is_classic_over_pi(brdf):
    pts, nrm, lights = _scene()
    mat = Material(brdf, emission=(0.01, 0.0, 0.02))
    classic = shade(pts, nrm, mat, lights, eye=(0.5, 0.5, 5.0), form="classic")
    physical = shade(pts, nrm, mat, lights, eye=(0.5, 0.5, 5.0), form="physical")
    np.testing.assert_allclose(classic, math.pi * physical, rtol=1e-13, atol=1e-15)
    assert np.all(classic >= 0)


def test_light_is_linear_and_terms_add_up():
    pts, nrm, lights = _scene(seed=1)
    mat = Material(MODELS[0], emission=0.05)
    total = shade(pts, nrm, mat, lights, view_dir=UP)
    one_by_one = sum(shade(pts, nrm, mat, [lt], view_dir=UP) for lt in lights) - 4 * 0.05  # emission once
    np.testing.assert_allclose(total, one_by_one, rtol=1e-13, atol=1e-14)
    terms = shade_terms(pts, nrm, mat, lights, view_dir=UP)
    assert set(terms) == {"emission", "ambient", "diffuse", "specular"}
    np.testing.assert_allclose(sum(terms.values()), total, rtol=1e-15)
    only = shade_terms(pts, nrm, mat, lights, view_dir=UP, terms=["specular"])
    assert set(only) == {"specular"}
    np.testing.assert_array_equal(only["specular"], terms["specular"])


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_shade_keeps_dtype(dtype):
    pts, nrm, lights = _scene(seed=2)
    out = shade(pts.astype(dtype), nrm.astype(dtype), Material(MODELS[1]), lights, view_dir=UP)
    assert out.dtype == dtype
    ref = shade(pts, nrm, Material(MODELS[1]), lights, view_dir=UP)
    np.testing.assert_allclose(out, ref, rtol=2e-4, atol=2e-6)


def test_shade_errors():
    with pytest.raises(ValueError, match="exactly one of eye"):
        shade(ORIGIN, UP, Material(Lambert(1.0)), [DirectionalLight()])
    with pytest.raises(ValueError, match="form"):
        shade(ORIGIN, UP, Material(Lambert(1.0)), [], view_dir=UP, form="pbr")
    with pytest.raises(ValueError, match="brdf"):
        Material("lambert")


# ------------------------------------------------------------------------------------ finite in, finite out
BIG = {np.float32: float(np.finfo(np.float32).max), np.float64: float(np.finfo(np.float64).max)}


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_overflowing_falloff_times_zero_spot_factor_is_zero(dtype):
    # 1 / (1e-300 r²) at r = 1e-5 is 1e310: beyond float64.  Outside the cone the spot factor is 0, and
    # the light must deliver exactly 0 there (it was inf · 0 = NaN); on the axis it saturates.
    away = SpotLight((0, 0, 1e-5), direction=(0, 0, 1.0), cutoff_deg=30, attenuation=(1e-300, 0, 0))
    toward = SpotLight((0, 0, 1e-5), direction=(0, 0, -1.0), cutoff_deg=30, attenuation=(1e-300, 0, 0))
    pts = np.zeros((1, 3), dtype)
    assert next(away.incident(pts)).irradiance.tolist() == [[0.0, 0.0, 0.0]]
    assert next(toward.incident(pts)).irradiance.tolist() == [[BIG[dtype]] * 3]
    n = np.array([0, 0, 1.0], dtype)
    got = shade(pts, n, Material(Lambert(1.0) + Phong(1.0, 10)), [away, toward], view_dir=UP)
    assert got.dtype == dtype and got.tolist() == [[BIG[dtype]] * 3]
    assert shade(pts, n, Material(Lambert(1.0)), [away], view_dir=UP).tolist() == [[0.0, 0.0, 0.0]]


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_point_light_beyond_the_float_range_is_exact_and_quiet(dtype):
    # 1e300 away: r² overflows float64, the falloff is 0 (it raised an overflow warning).
    far = PointLight((0, 0, 1e300))
    inc = next(far.incident(np.zeros((1, 3), dtype)))
    assert inc.direction.tolist() == [[0.0, 0.0, 1.0]] and inc.irradiance.tolist() == [[0.0, 0.0, 0.0]]
    # Without falloff the light still arrives, with the right direction, however far it is; even the
    # difference of the two positions overflows here (1e308 − (−1e308)).
    flat = PointLight((0, 0, 1e308), attenuation=(0, 0, 1))
    inc = next(flat.incident(np.array([[0, 0, -1e308]], dtype=np.float64)))
    assert inc.direction.tolist() == [[0.0, 0.0, 1.0]] and inc.irradiance.tolist() == [[1.0, 1.0, 1.0]]
    # Linear falloff 1/(b r) at r = 2e308 (beyond float64; the distance saturates at 1.8e308): tiny, not NaN.
    lin = PointLight((0, 0, 1e308), attenuation=(0, 1, 0))
    assert irradiance(lin, [[0, 0, -1e308]]).tolist() == [[1 / BIG[np.float64]] * 3]
    out = shade(np.zeros((1, 3), dtype), np.array(UP, dtype), Material(Lambert(1.0)), [far, flat], view_dir=UP)
    assert out.dtype == dtype and out.tolist() == [[1.0, 1.0, 1.0]]


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_far_points_with_an_eye_give_unit_view_vectors(dtype):
    # float32 points near 1e30 with eye=: the squared distance overflows float32 (it warned).
    pts = np.array([[1e30, 0, 0], [0, 3e30, -4e30], [1.0, 2.0, 3.0]], dtype)
    n = np.array([[-1.0, 0, 0], [0, -0.6, 0.8], [0, 0, 1.0]], dtype)
    got = shade(pts, n, Material(Phong(1.0, 1.0)), [DirectionalLight((1, 0, 1.0))], eye=(0, 0, 0.0))
    assert got.dtype == dtype and np.all(np.isfinite(got))
    # Phong with e = 1 seen along the mirror direction: (R_l·v) = the cosine, computed from exact unit v.
    v = -pts[:2].astype(np.float64) / np.linalg.norm(pts[:2].astype(np.float64), axis=1)[:, None]
    l = vec.normalize(np.array([1, 0, 1.0]))  # noqa: E741
    nn = n[:2].astype(np.float64)
    r = 2 * nn * (nn @ l)[:, None] - l
    expected = np.maximum(np.sum(r * v, axis=1), 0) * ((nn @ l) > 0)
    np.testing.assert_allclose(got[:2, 0], expected, rtol=1e-6 if dtype == np.float32 else 1e-14, atol=1e-7)
    # Eye and point 2e308 apart (their difference overflows float64): v is still exact.
    far = shade([[0, 0, -1e308]], UP, Material(Phong(1.0, 1.0)), [DirectionalLight(UP)], eye=(0, 0, 1e308))
    assert far.tolist() == [[1.0, 1.0, 1.0]]


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_saturated_lights_and_coefficients_never_give_nan(dtype):
    # intensity × colour = 1e308 × 1e308 and k_d = 1e308: every product saturates, and a zero factor
    # (a normal facing away, a black channel) still gives exactly 0.
    hot = DirectionalLight(UP, color=(1e308, 0.0, 1e308), intensity=1e308)
    assert hot.radiant.tolist() == [BIG[np.float64], 0.0, BIG[np.float64]]
    n = np.array([[0, 0, 1.0], [0, 0, -1.0], [1, 0, 1e-30]], dtype)
    pts = np.zeros((3, 3), dtype)
    for brdf in (Lambert(1e308), Lambert(1.0) + Phong(1e308, 1e6)):
        got = shade(pts, n, Material(brdf, ambient=0.0), [hot, hot], view_dir=(1, 0, 1.0))
        assert got.dtype == dtype and np.all(np.isfinite(got)) and np.all(got >= 0)
        assert got[0].tolist() == [BIG[dtype], 0.0, BIG[dtype]]
        assert got[1].tolist() == [0.0, 0.0, 0.0]
    amb = shade(pts, n, Material(Lambert(1e308)), [AmbientLight(1e308, 1e308)] * 2, view_dir=UP)
    assert amb.tolist() == [[BIG[dtype]] * 3] * 3
    # Many saturated ambient lights on a surface reflecting none of it: 0, not inf · 0.
    dark = shade(pts, n, Material(Lambert(1.0), ambient=0.0), [AmbientLight(1e308, 1e308)] * 3, view_dir=UP,
                 terms=["ambient"])  # fmt: skip
    assert dark.tolist() == [[0.0, 0.0, 0.0]] * 3


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_area_light_sample_very_close_saturates_or_gives_zero(dtype):
    # A point 1e-170 from a sample (float64; 1e-30 in float32), in the emitter's plane: cos θ_e = 0 and
    # A/S / r² overflows, so the irradiance is 0; facing it, it saturates (r² underflowed to 0, and the
    # point was taken to sit on the sample, receiving nothing).
    tiny = 1e-170 if dtype == np.float64 else 1e-30
    from lighting.lights.area import _r2_sequence

    u0, u1 = _r2_sequence(1, None)[0] - 0.5
    rect = RectLight(center=(-u0, u1, 0.0), edge_u=(1.0, 0, 0), edge_v=(0, -1.0, 0), samples=1)
    y = rect.sample_points()[0]
    assert y.tolist() == [0.0, 0.0, 0.0]
    assert next(rect.incident(np.array([[tiny, 0, 0]], dtype))).irradiance.tolist() == [[0.0, 0.0, 0.0]]
    assert next(rect.incident(np.array([[0, 0, -tiny]], dtype))).irradiance.tolist() == [[BIG[dtype]] * 3]


# ------------------------------------------------------------------------------------ exact angles
def test_directions_from_angles_are_exact_at_right_angles():
    assert DirectionalLight.from_angles(0.0).direction.tolist() == [1.0, 0.0, 0.0]
    assert DirectionalLight.from_angles(90.0).direction.tolist() == [0.0, 0.0, 1.0]
    assert DirectionalLight.from_angles(0.0, 90.0).direction.tolist() == [0.0, 1.0, 0.0]
    assert DirectionalLight.from_angles(0.0, 180.0).direction.tolist() == [-1.0, 0.0, 0.0]
    assert DirectionalLight.from_angles(-90.0, 37.0).direction.tolist() == [0.0, 0.0, -1.0]
    # Overhead light on a wall facing +x: exactly grazing, so exactly nothing (was cos 90° = 6e-17 of it).
    overhead = [DirectionalLight.from_angles(90.0)]
    wall = shade(ORIGIN, (1.0, 0, 0), Material(Lambert(1.0)), overhead, view_dir=(1.0, 0, 0))
    assert wall.tolist() == [[0.0, 0.0, 0.0]]
    np.testing.assert_allclose(DirectionalLight.from_angles(30.0, 45.0).direction,
                               [math.cos(math.radians(30)) / math.sqrt(2)] * 2 + [0.5], rtol=1e-15)  # fmt: skip


def test_spot_cone_test_exact_at_0_and_90_degrees_and_resolves_tiny_cutoffs():
    from lighting.lights.punctual import _one_minus_cos_deg

    assert (_one_minus_cos_deg(0), _one_minus_cos_deg(90)) == (0.0, 1.0)
    assert _one_minus_cos_deg(60) == pytest.approx(0.5, rel=2.3e-16)
    assert _one_minus_cos_deg(1e-8) == pytest.approx(2 * math.sin(math.radians(1e-8) / 2) ** 2, rel=1e-15)
    half = SpotLight((0, 0, 0.0), direction=(0, 0, -1.0), cutoff_deg=90, attenuation=(0, 0, 1))
    assert half.spot_factor(np.array([0.0, -1e-300, 1.0])).tolist() == [1.0, 0.0, 1.0]
    # The cone's edge at 75° and at 1e-6°, within 1e-9 of the angle either way.
    for cutoff in (75.0, 1e-6):
        spot = SpotLight((0, 0, 1.0), direction=(0, 0, -1.0), cutoff_deg=cutoff, attenuation=(0, 0, 1))
        inside, outside = math.radians(cutoff * (1 - 1e-9)), math.radians(cutoff * (1 + 1e-9))
        pts = [[math.tan(inside), 0, 0], [math.tan(outside), 0, 0]]
        assert irradiance(spot, pts)[:, 0].tolist() == [1.0, 0.0]


# ------------------------------------------------------------------------------------- checked arguments
P2, N2 = np.zeros((2, 3)), np.array([[0, 0, 1.0], [0, 1.0, 0]])
MAT2 = Material(Lambert(0.5) + Phong(0.5, 10.0))
LIGHTS2 = [AmbientLight(), DirectionalLight(), PointLight((1, 2, 3.0))]


@pytest.mark.parametrize(
    "kwargs, param",
    [
        (dict(points=[[0, 0, float("nan")]] * 2), "points"),
        (dict(points=[[0, 0, 1j]] * 2), "points"),
        (dict(points=[["0", "0", "1"]] * 2), "points"),
        (dict(normals=[[0, 0, float("inf")]] * 2), "normals"),
        (dict(normals=b"001"), "normals"),
        (dict(view_dir=(0, float("nan"), 1.0)), "view_dir"),
        (dict(view_dir=(0, 0, 0)), "view_dir"),
        (dict(view_dir="up"), "view_dir"),
        (dict(view_dir=None, eye=5.0), "eye"),
        (dict(view_dir=None, eye=(0, 0, 1j)), "eye"),
        (dict(points=None), "points"),
        (dict(lights=[DirectionalLight(), "sun"]), "lights[1]"),
        (dict(lights=DirectionalLight()), "lights"),
        (dict(material=Lambert(0.5)), "material"),
        (dict(terms="diffuse"), "terms"),
        (dict(terms={"diffuse"}), "terms"),
    ],
)
def test_shade_refuses_each_illegal_argument_by_name(kwargs, param):
    args = dict(points=P2, normals=N2, material=MAT2, lights=LIGHTS2, view_dir=(0, 0, 1.0)) | kwargs
    options = {k: v for k, v in args.items() if k in ("eye", "view_dir", "terms")}
    for f in (shade, shade_terms):
        with pytest.raises(ValueError, match=rf"^{re.escape(param)}") as info:
            f(args["points"], args["normals"], args["material"], args["lights"], **options)
        assert "got" in str(info.value) or "PointLight" in str(info.value)
    if kwargs.get("points", 0) is None:  # the light that needs positions is named, not dropped
        assert "PointLight" in str(info.value)


def test_illegal_light_arguments_are_named_before_any_work():
    import time

    t0 = time.perf_counter()
    with pytest.raises(ValueError, match="^samples must be an integer in"):
        RectLight(samples=10**9)
    with pytest.raises(TypeError, match="^samples must be an integer"):
        DiskLight(samples=16.0)
    assert time.perf_counter() - t0 < 0.5  # refused, not allocated
    with pytest.raises(TypeError, match="^intensity must be a finite number >= 0; got str '1'"):
        PointLight(intensity="1")
    with pytest.raises(TypeError, match="^color must be"):
        AmbientLight(color=b"1")
    with pytest.raises(ValueError, match=r"^attenuation must be three finite numbers"):
        PointLight(attenuation=(float("nan"), 0, 1))
    with pytest.raises(TypeError, match="^two_sided must be True or False"):
        RectLight(two_sided=1)
    with pytest.raises(ValueError, match="^seed must be an integer >= 0"):
        DiskLight(seed=-1)
    with pytest.raises(ValueError, match=r"^cutoff_deg must be in \[0, 90\] degrees or exactly 180 \(no cone\); got 1"):
        SpotLight(cutoff_deg=120)
    with pytest.raises(ValueError, match="^elevation_deg must be a finite number"):
        DirectionalLight.from_angles(float("nan"))
    with pytest.raises(ValueError, match="^points must be"):
        next(PointLight().incident([[0, float("nan"), 0]]))


def test_a_view_dir_beyond_float32_is_still_a_direction():
    """A finite view_dir whose components overflow float32 is normalized before the cast (no inf, no error)."""
    kw = dict(normals=np.array([0.0, 0.0, 1.0], np.float32), material=Material(Lambert(0.5) + Phong(0.5, 10)),
              lights=[DirectionalLight((0.0, 0.0, 1.0))])  # fmt: skip
    huge = shade(points=np.zeros((1, 3), np.float32), view_dir=(1e300, 0.0, 1e300), **kw)
    unit = shade(points=np.zeros((1, 3), np.float32), view_dir=(1.0, 0.0, 1.0), **kw)
    assert huge.dtype == np.float32 and np.array_equal(huge, unit)

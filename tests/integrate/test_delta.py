"""Delta parts (the ideal mirror) in the integrators: exact albedo and environment radiance, and the limits.

Measured here (float64, the procedural sky ``SKY`` below, views 0°, 30°, 60°, 75° about ``n = ẑ``,
4096 quadrature nodes), the glossy models approach the mirror's ``R(cos θ_v) L(R_v)`` as:

* Phong with ``k_s (e + 1)/2``: relative error ``c/e``, ``c`` = 0.75, 0.37, 0.25, 0.15 at the four views
  (tenfold per decade of ``e``: 9.955–9.982 from 10³ to 10⁴, within 0.05 % above 10⁴);
* NDF-normalized Blinn–Phong with ``k_s/(4 cos²θ_v)``: ``c/e`` with ``c`` = 5.6, 4.1, 5.5, 36;
* Cook–Torrance GGX + Smith: ``c α² ln(1/α)`` with ``c`` from 8.1 to 9.2 for ``α`` = 10⁻² … 10⁻⁴
  (the GGX tail makes the lobe's variance ``α² ln(1/α)``, not ``α²``): 4.2e-3, 5.8e-5, 7.5e-7.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

from lighting.integrate import (
    RADIANCE_METHODS,
    albedo_curve,
    directional_albedo,
    hemispherical_albedo,
    importance_sampler,
    outgoing_radiance,
    point_light_limit,
)
from lighting.integrate.albedo import METHODS
from lighting.lights.environment import FunctionEnvironment, SmallPatchEnvironment
from lighting.models.brdf import BlinnPhong, CookTorrance, Lambert, Phong
from lighting.models.fresnel import f0_from_eta
from lighting.models.mirror import Mirror
from lighting.vec import reflect

MIRRORS = [Mirror(0.8), Mirror((0.9, 0.6, 0.3), 0.04, "schlick"), Mirror(1.0, float(f0_from_eta(1.5)), "dielectric")]
IDS = ["none", "schlick", "dielectric"]


def _sky(d):
    """A smooth, coloured sky over the whole sphere (bright zenith, a horizon band, dim ground)."""
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    return np.stack(
        [1.2 + 0.8 * z + 0.3 * x * y, 0.6 + 0.4 * np.sin(2 * x) + 0.2 * z * z, 0.3 + 0.5 * np.exp(-3 * (1 - z))], -1
    )


SKY = FunctionEnvironment(_sky)
THETA = np.radians([0.0, 30.0, 60.0, 75.0])
VIEWS = np.stack([np.sin(THETA), 0 * THETA, np.cos(THETA)], -1)
N = np.array([0.0, 0.0, 1.0])


def _frames(count=40, seed=4):
    """Random unit normals and views above their horizons (a tenth of them near grazing)."""
    rng = np.random.default_rng(seed)
    n = rng.normal(size=(count, 3))
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    v = rng.normal(size=(count, 3))
    v -= n * np.sum(n * v, axis=-1, keepdims=True)
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    mu = np.concatenate([rng.uniform(0.05, 1.0, count - count // 10), rng.uniform(1e-6, 1e-3, count // 10)])
    v = mu[:, None] * n + np.sqrt(1 - mu**2)[:, None] * v
    return n, v


def _exact(m, n, v):
    """``R(n·v) L_sky(R_v)`` from the definitions, in float64."""
    return m.reflectance(np.sum(n * v, axis=-1)) * _sky(reflect(v, n))


# --------------------------------------------------------------------------- albedo
@pytest.mark.parametrize("method", METHODS)
def test_albedo_of_mirror_plus_lambert_is_lambert_plus_the_reflectance(method):
    m = MIRRORS[1]
    theta = np.radians([0.0, 20.0, 45.0, 70.0, 89.0, 90.0])
    both = directional_albedo(Lambert(0.5) + m, theta, 256, method, seed=9, return_error=True)
    alone = directional_albedo(Lambert(0.5), theta, 256, method, seed=9, return_error=True)
    cos = np.where(theta < math.pi / 2, np.cos(theta), 0.0)
    np.testing.assert_array_equal(both.value, alone.value + m.reflectance(cos))  # the smooth part as before
    np.testing.assert_array_equal(both.error, alone.error)  # the delta adds no error
    assert both.samples == alone.samples


def test_albedo_curve_of_a_mirror_is_its_reflectance_with_zero_error():
    m = MIRRORS[2]
    c = albedo_curve(m)
    np.testing.assert_array_equal(c.albedo[:90], m.reflectance(np.cos(c.theta[:90])))
    np.testing.assert_array_equal(c.albedo[90], 0.0)  # θ_v = π/2 exactly: n·v = 0
    np.testing.assert_array_equal(c.error, 0.0)
    assert c.samples == 1 and not c.unconverged.any()


def test_albedo_keeps_float32():
    theta = np.float32([0.0, 1.0])
    est = directional_albedo(MIRRORS[1], theta, return_error=True)
    assert est.value.dtype == est.error.dtype == np.float32
    # Integrated in float64, rounded once.
    np.testing.assert_array_equal(
        est.value, MIRRORS[1].reflectance(np.cos(theta.astype(np.float64))).astype(np.float32)
    )


def test_hemispherical_albedo_of_mirrors():
    # Constant: any rule; Schlick: 2μ R(μ) has degree 6, exact from four Gauss nodes.
    assert hemispherical_albedo(Mirror(0.7), view_samples=1) == pytest.approx([0.7] * 3, rel=1e-15)
    for k in (4, 16):
        got = hemispherical_albedo(Mirror(1.0, 0.04, "schlick"), view_samples=k)
        np.testing.assert_allclose(got, 0.04 + 0.96 / 21, rtol=1e-14)
    # The dielectric (η = 1.5) against a 30-digit integral ∫ 2μ F(μ) dμ = 0.0917779593423512...
    with mpmath.workdps(30):
        eta = mpmath.mpf("1.5")

        def f(c):
            ct = mpmath.sqrt(1 - (1 - c * c) / eta**2)
            return ((c - eta * ct) ** 2 / (c + eta * ct) ** 2 + (eta * c - ct) ** 2 / (eta * c + ct) ** 2) / 2

        want = float(mpmath.quad(lambda mu: 2 * mu * f(mu), [0, 0.01, 0.1, 1]))
    for k in (4, 16, 64):
        est = hemispherical_albedo(MIRRORS[2], view_samples=k, return_error=True)
        assert abs(est.value[0] - want) <= 2 * est.error[0]  # honest
    assert est.value[0] == pytest.approx(want, rel=1e-13)  # 64 nodes: to rounding (16 already: 2e-16)


# --------------------------------------------------------------------------- environment
@pytest.mark.parametrize("method", RADIANCE_METHODS)
@pytest.mark.parametrize("m", MIRRORS, ids=IDS)
def test_environment_radiance_is_the_reflected_sky_exactly(m, method):
    n, v = _frames()
    est = outgoing_radiance(m, SKY, n, v, method=method, samples=64, seed=1, return_error=True)
    np.testing.assert_allclose(est.value, _exact(m, n, v), rtol=4e-15, atol=0)
    np.testing.assert_array_equal(est.error, 0.0)


def test_environment_radiance_float32_and_below_the_horizon():
    m = MIRRORS[1]
    n, v = _frames(count=12)
    got = outgoing_radiance(m, SKY, n.astype(np.float32), v.astype(np.float32))
    assert got.dtype == np.float32
    np.testing.assert_allclose(got, _exact(m, n, v), rtol=2e-6)
    # A viewer below the horizon, a zero normal, a zero view: 0.
    vv = np.array([[0.6, 0.0, -0.8], [0.6, 0.0, 0.8], [0.0, 0.0, 0.0]])
    nn = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    np.testing.assert_array_equal(outgoing_radiance(m, SKY, nn, vv), 0.0)


@pytest.mark.parametrize("method", RADIANCE_METHODS)
def test_environment_radiance_of_mirror_plus_lambert(method):
    m = MIRRORS[0]
    n, v = _frames(count=10)
    both = outgoing_radiance(Lambert(0.4) + m, SKY, n, v, method=method, samples=128, seed=5, return_error=True)
    alone = outgoing_radiance(Lambert(0.4), SKY, n, v, method=method, samples=128, seed=5, return_error=True)
    np.testing.assert_allclose(both.value, alone.value + _exact(m, n, v), rtol=4e-15, atol=0)
    np.testing.assert_array_equal(both.error, alone.error)


def test_small_patch_seen_in_a_mirror_keeps_its_radiance():
    # A point light has no image in a mirror; a patch of any size has one of radiance R L.
    m = Mirror(0.5)
    rows = point_light_limit(m, (0.0, 0.6, 0.8), view_dir=(0.0, -0.6, 0.8), radiance=2.0, solid_angles=(1e-2, 1e-5))
    for r in rows:
        np.testing.assert_allclose(r.patch, 1.0, rtol=1e-15)
        np.testing.assert_array_equal(r.point, 0.0)
    # Looking just outside the patch's mirror image: nothing.
    env = SmallPatchEnvironment((0.0, 0.6, 0.8), 1e-4, 2.0)
    np.testing.assert_array_equal(outgoing_radiance(m, env, N, (0.0, -0.5, 0.8)), 0.0)


# --------------------------------------------------------------------------- the limit of glossy models
def _relative(got, want):
    return np.max(np.abs(got - want), axis=-1) / np.max(want, axis=-1)


def test_phong_tends_to_the_mirror_as_1_over_e():
    ks = 0.8
    want = _exact(Mirror(ks), N, VIEWS)
    errors = []
    for e in (1e3, 1e4, 1e5):
        got = outgoing_radiance(Phong(ks * (e + 1) / 2, e), SKY, N, VIEWS, samples=4096)
        errors.append(_relative(got, want))
        assert np.all(errors[-1] * e < 0.8)  # measured 0.75 at normal incidence
    # First order in 1/e: tenfold per decade (measured 9.955–9.982 from 10³ to 10⁴, the 1/e² term's share).
    np.testing.assert_allclose(errors[0] / errors[1], 10.0, rtol=1e-2)
    np.testing.assert_allclose(errors[1] / errors[2], 10.0, rtol=1e-3)


def test_normalized_blinn_phong_tends_to_a_mirror_of_4_ks_cos2():
    ks = 0.8
    want = _exact(Mirror(ks), N, VIEWS)
    for e in (1e3, 1e5):
        got = np.stack(
            [
                outgoing_radiance(BlinnPhong(ks / (4 * c * c), e, normalized=True), SKY, N, v, samples=4096)
                for c, v in zip(np.cos(THETA), VIEWS, strict=True)
            ]
        )
        assert np.all(_relative(got, want) * e < 40.0)  # measured 5.6, 4.1, 5.5, 36


@pytest.mark.parametrize("fresnel", ["schlick", "dielectric", "none"])
def test_cook_torrance_ggx_tends_to_the_mirror_as_alpha_goes_to_0(fresnel):
    ks, f0 = 0.8, 0.04
    want = _exact(Mirror(ks, f0, fresnel), N, VIEWS)
    for a in (1e-2, 1e-3, 1e-4):
        ct = CookTorrance(ks, a, f0, ndf="ggx", geometry="smith", fresnel=fresnel)
        err = _relative(outgoing_radiance(ct, SKY, N, VIEWS, samples=4096), want)
        assert np.all(err < 10 * a * a * math.log(1 / a)), (a, err)  # measured up to 9.2 α² ln(1/α)


def test_huge_reflectances_saturate_without_a_warning():
    # Two mirrors of k_s = 1e308 overflow float64 when added: finite in, finite out (the largest value).
    m = Mirror(1e308) + Mirror(1e308)
    for theta in (np.array([0.0, 1.0]), np.float32([0.0, 1.0])):
        got = directional_albedo(m, theta)
        np.testing.assert_array_equal(got, np.finfo(got.dtype).max)
    np.testing.assert_array_equal(outgoing_radiance(m, 1e300, N, (0.6, 0.0, 0.8)), np.finfo(np.float64).max)
    sampler = importance_sampler(m)
    np.testing.assert_array_equal(sampler.weight([0.0, 0.0, 1.0]), np.finfo(np.float64).max)
    np.testing.assert_array_equal(sampler.source.reflectance(np.float32(0.5)), np.finfo(np.float32).max)

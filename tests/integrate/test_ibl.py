"""Image-based lighting: prefiltered environments, the split sum, SH9 and the progressive Monte-Carlo reference.

Each test checks a value: a closed form (the von Mises-Fisher mean of a linear sky, π L, SH9 of a quadratic
sky), a law (the white furnace, 1/√N), or the engine's own reference integrators.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from lighting.integrate import directional_albedo, outgoing_radiance, sh_irradiance
from lighting.integrate.ibl import ALBEDO_ANGLES, ProgressiveRadiance, lobe_albedo, lobe_sigma, split_sum_radiance
from lighting.integrate.prefilter import PREFILTER_SIGMAS, irradiance_map, latlong_sh, prefilter_environment
from lighting.lights.environment import ConstantEnvironment, FunctionEnvironment, LatLongEnvironment
from lighting.models.brdf import BlinnPhong, CookTorrance, Lambert, Phong
from lighting.models.mirror import Mirror


def _linear_sky(d):
    """``1 + 0.5 z + 0.3 x`` in every channel (scaled per channel): band-limited, positive."""
    base = 1 + 0.5 * d[..., 2:3] + 0.3 * d[..., 0:1]
    return base * np.array([1.0, 0.8, 0.6])


def _sunny_sky(d):
    z, x = d[..., 2:3], d[..., 0:1]
    sun = 20 * np.exp(30 * (0.6 * x + 0.8 * z - 1))
    return np.maximum(0.2 + 0.8 * z, 0.05) * np.array([0.5, 0.7, 1.0]) + sun * np.array([1.0, 0.9, 0.7])


def _unit(rng, count, upper=True):
    n = rng.normal(size=(count, 3))
    if upper:
        n[:, 2] = np.abs(n[:, 2])
    return n / np.linalg.norm(n, axis=1, keepdims=True)


@pytest.fixture(scope="module")
def sunny():
    env = LatLongEnvironment.from_function(_sunny_sky, 128)
    return env, prefilter_environment(env)


# ----------------------------------------------------------------------------- prefiltered levels
def test_a_constant_environment_stays_constant_at_every_width():
    pre = prefilter_environment(ConstantEnvironment([1.0, 2.0, 3.0]))
    d = _unit(np.random.default_rng(0), 50, upper=False)
    for s in (0.0, 0.01, 0.03, 0.3, 1.2, 5.0):
        np.testing.assert_allclose(pre.lookup(d, s), np.broadcast_to([1.0, 2.0, 3.0], (50, 3)), rtol=1e-6)


@pytest.mark.slow  # seconds of work: the full run has it, the fast loop leaves it out
@pytest.mark.parametrize("sigma", PREFILTER_SIGMAS[1:])
def test_the_lobe_average_of_a_linear_sky_is_the_von_mises_fisher_mean(sigma):
    # For K = exp(κ (r·l − 1)) the mean of l is A(κ) r, A = coth κ − 1/κ: a linear sky a + b·l averages to a + A b·r.
    pre = prefilter_environment(FunctionEnvironment(_linear_sky), height=256)
    kappa = 1 / sigma**2
    a = 1 / math.tanh(kappa) - 1 / kappa
    r = _unit(np.random.default_rng(1), 40, upper=False)
    expected = (1 + a * (0.5 * r[:, 2:3] + 0.3 * r[:, 0:1])) * np.array([1.0, 0.8, 0.6])
    got = pre.lookup(r, sigma)
    # Bilinear lookup between pixel centres of the level (8 pixels per σ) bends the linear sky by < 0.2 %;
    # within half a row of a pole the lookup reads the edge row (LatLongEnvironment's clamp): 0.21 % at σ = 1.6.
    np.testing.assert_allclose(got, expected, rtol=2.5e-3)


def test_prefiltering_keeps_energy_the_mean_radiance_over_the_sphere():
    # The kernel is symmetric, so averaging the level over the sphere gives the environment's mean radiance.
    env = LatLongEnvironment.from_function(_sunny_sky, 128)
    pre = prefilter_environment(env)
    mean = (env.image * env.solid_angles()[..., None]).sum(axis=(0, 1)) / (4 * math.pi)
    for k, level in enumerate(pre.levels):
        h = level.shape[0]
        omega = LatLongEnvironment(np.zeros((h, 2 * h, 3))).solid_angles()[..., None]
        np.testing.assert_allclose((level * omega).sum(axis=(0, 1)) / (4 * math.pi), mean, rtol=3e-3, err_msg=k)


def test_the_lookup_keeps_float32():
    pre = prefilter_environment(FunctionEnvironment(_linear_sky), height=32)
    d = _unit(np.random.default_rng(2), 10).astype(np.float32)
    assert pre.lookup(d, 0.2).dtype == np.float32 and pre.irradiance_sh(d).dtype == np.float32
    assert pre.lookup(d.astype(np.float64), 0.2).dtype == np.float64


@pytest.mark.parametrize("bad", [[0.1, 0.2], [0.0, 0.2, 0.1], [0.0, float("inf")], "wide"])
def test_bad_widths_are_one_line(bad):
    with pytest.raises((ValueError, TypeError), match="sigmas must"):
        prefilter_environment(1.0, sigmas=bad)


# ----------------------------------------------------------------------------- SH9
def test_latlong_sh_integrates_each_pixel_exactly():
    # Against a 48x supersampled centre rule of the same piecewise-constant image.
    from lighting.integrate.sh import sh_basis

    img = np.random.default_rng(3).random((8, 16, 3))
    k = 48
    fine = np.repeat(np.repeat(img, k, 0), k, 1)
    h = fine.shape[0]
    d = LatLongEnvironment.pixel_directions(h, 2 * h)
    omega = LatLongEnvironment(np.zeros((h, 2 * h, 3))).solid_angles()
    reference = np.einsum("hwj,hwk,hw->jk", sh_basis(d), fine, omega)
    np.testing.assert_allclose(latlong_sh(img), reference, atol=2e-5)


def test_sh9_is_the_exact_irradiance_of_a_band_limited_sky():
    # E(n) of 1 + 0.5 z + 0.3 x is π + (2π/3)(0.5 n_z + 0.3 n_x) (Ramamoorthi & Hanrahan's Â_0 = π, Â_1 = 2π/3).
    pre = prefilter_environment(FunctionEnvironment(_linear_sky), height=512)
    n = _unit(np.random.default_rng(4), 30, upper=False)
    exact = (math.pi + 2 * math.pi / 3 * (0.5 * n[:, 2:3] + 0.3 * n[:, 0:1])) * np.array([1.0, 0.8, 0.6])
    np.testing.assert_allclose(pre.irradiance_sh(n), exact, rtol=2e-5)  # the pixelized map: O(pixel²)
    np.testing.assert_allclose(pre.irradiance_sh(n), sh_irradiance(pre.sh, n), rtol=1e-12)


def test_the_irradiance_map_is_the_clamped_cosine_integral():
    # Constant sky: π L at every normal; a linear sky: its closed form, at the map's own pixel centres.
    flat = irradiance_map(ConstantEnvironment(2.0), height=8, source_height=64)
    np.testing.assert_allclose(flat.image, 2 * math.pi, rtol=1e-4)  # the midpoint rule's O(pixel²) at 64 rows
    finer = irradiance_map(ConstantEnvironment(2.0), height=8, source_height=256)
    assert np.abs(finer.image / (2 * math.pi) - 1).max() < np.abs(flat.image / (2 * math.pi) - 1).max() / 8
    e = irradiance_map(FunctionEnvironment(_linear_sky), height=32, source_height=256)
    d = LatLongEnvironment.pixel_directions(32, 64)
    exact = (math.pi + 2 * math.pi / 3 * (0.5 * d[..., 2:3] + 0.3 * d[..., 0:1])) * np.array([1.0, 0.8, 0.6])
    np.testing.assert_allclose(e.image, exact, rtol=3e-4)


# ----------------------------------------------------------------------------- the split sum
def test_white_furnace_lambert_is_exact_and_every_model_reflects_its_albedo():
    pre = prefilter_environment(ConstantEnvironment(1.0))
    rng = np.random.default_rng(5)
    n = _unit(rng, 64)
    v = _unit(rng, 64)
    cos_v = np.einsum("ij,ij->i", n, v)
    furnace = np.where(cos_v[:, None] > 0, 0.5, np.zeros((64, 3)))
    np.testing.assert_allclose(split_sum_radiance(Lambert(0.5), pre, n, v), furnace, atol=1e-7)
    models = [
        (Phong(0.5, 40), 1e-3),
        (BlinnPhong(0.5, 100), 1e-3),
        (CookTorrance(1.0, 0.3, 0.04, ndf="ggx", geometry="smith"), 1e-3),
        # F = 1: read from the E(μ, α) table, accurate to 1.8e-3 (energy.py), plus the interpolation in θ_v.
        (Lambert(0.3) + CookTorrance(1.0, 0.1, 1.0, fresnel="none", ndf="beckmann", geometry="smith"), 3e-3),
    ]
    seen = cos_v > 0.05
    theta = np.arccos(cos_v[seen])
    for model, tol in models:
        albedo = directional_albedo(model, theta, samples=8192)
        # The albedo table is linear in θ_v between 1.5° nodes: < 1e-3 off the directly integrated value.
        np.testing.assert_allclose(split_sum_radiance(model, pre, n[seen], v[seen]), albedo, atol=tol, err_msg=model)


def test_the_albedo_of_a_white_microfacet_is_the_engine_s_e_table():
    from lighting.models.energy import albedo_table

    model = CookTorrance(0.7, 0.25, 1.0, fresnel="none", ndf="ggx", geometry="smith")
    table = lobe_albedo(model)
    np.testing.assert_allclose(table[:, 0], 0.7 * albedo_table("ggx", "smith").E(np.cos(ALBEDO_ANGLES), 0.25),
                               rtol=1e-12)  # fmt: skip
    direct = directional_albedo(model, ALBEDO_ANGLES[:-4], samples=8192)[:, 0]
    np.testing.assert_allclose(table[:-4, 0], direct, atol=2e-3)  # the table's own accuracy (energy.py)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_a_grey_albedo_table_is_read_as_each_channel_would_be(dtype):
    # A grey lobe's table is interpolated once for its three equal channels: the numbers np.interp gives each channel
    # on its own, bit for bit; a coloured table (a gold conductor) channel by channel.
    from lighting.integrate.ibl import _albedo_at

    theta = np.random.default_rng(3).uniform(0.0, math.pi / 2, 1000).astype(dtype)
    for model, grey in ((CookTorrance(0.7, 0.25, 1.0, fresnel="none", ndf="ggx"), True),
                        (CookTorrance(1.0, 0.25, 1.0, fresnel="conductor", metal="gold"), False)):  # fmt: skip
        table = lobe_albedo(model)
        assert np.array_equal(table[:, 0], table[:, 2]) == grey
        out = _albedo_at(table, theta, dtype)
        want = np.stack([np.interp(theta, ALBEDO_ANGLES, table[:, c]) for c in range(3)], axis=-1).astype(dtype)
        assert out.dtype == dtype and out.shape == (1000, 3)
        np.testing.assert_array_equal(out, want)


def test_lobe_widths_follow_the_models_lobes():
    assert lobe_sigma(Lambert(0.5).lobe()) == math.inf
    assert lobe_sigma(Phong(1.0, 400).lobe()) == pytest.approx(1 / 20)
    assert lobe_sigma(BlinnPhong(1.0, 400).lobe()) == pytest.approx(2 / 20)
    assert lobe_sigma(CookTorrance(1.0, 0.2, ndf="beckmann").lobe()) == pytest.approx(2 * 0.2 / math.sqrt(2))
    assert lobe_sigma(None) == math.inf


def test_the_mirror_reflects_the_environment_exactly(sunny):
    env, pre = sunny
    rng = np.random.default_rng(6)
    n, v = _unit(rng, 40), _unit(rng, 40)
    exact = outgoing_radiance(Mirror(0.9), env, n, v)
    np.testing.assert_allclose(split_sum_radiance(Mirror(0.9), pre, n, v), exact, rtol=1e-5, atol=1e-9)


def test_a_narrow_phong_lobe_is_within_one_percent_of_the_reference(sunny):
    # Phong's (r·l)^e is the von Mises-Fisher kernel the levels are made of: the split sum is near exact.
    env, pre = sunny
    rng = np.random.default_rng(7)
    n = _unit(rng, 60)
    v = np.array([0.0, 0.0, 1.0])
    keep = n[:, 2] > 0.5  # away from grazing, where the horizon cuts the lobe
    model = Phong(0.5, 300)
    fast = split_sum_radiance(model, pre, n[keep], v)
    ref = outgoing_radiance(model, env, n[keep], v, samples=16384)
    rel = np.abs(fast - ref).sum(1) / ref.sum(1)
    assert np.median(rel) < 0.01 and rel.max() < 0.05


def test_float32_in_float32_out_and_no_light_behind(sunny):
    _, pre = sunny
    n = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]], dtype=np.float32)
    v = np.array([[0.0, 0.6, 0.8], [0.0, 0.6, -0.8]], dtype=np.float32)
    out = split_sum_radiance(Lambert(0.5) + Phong(0.5, 50), pre, n, v)
    assert out.dtype == np.float32 and np.all(out[0] > 0) and np.all(out[1] == 0)
    terms = split_sum_radiance(Lambert(0.5) + Phong(0.5, 50), pre, n, v, split_terms=True)
    np.testing.assert_allclose(terms["diffuse"] + terms["specular"], out, rtol=1e-6)


# ----------------------------------------------------------------------------- the progressive reference
@pytest.mark.slow  # seconds of work: the full run has it, the fast loop leaves it out
def test_progressive_error_is_honest_and_shrinks_as_one_over_root_n(sunny):
    env, _ = sunny
    rng = np.random.default_rng(8)
    n = _unit(rng, 400)
    v = np.array([0.0, 0.0, 1.0])
    model = Lambert(0.2) + CookTorrance(1.0, 0.2, 0.04, ndf="ggx", geometry="smith")
    truth = outgoing_radiance(model, env, n, np.broadcast_to(v, n.shape), samples=16384)
    run = ProgressiveRadiance(model, env, n, np.broadcast_to(v, n.shape), seed=3)
    for _ in range(8):
        run.add(8)
    first = np.median(run.error)
    inside = np.abs(run.value - truth) < 2 * run.error + 1e-12
    assert inside.mean() > 0.88  # two standard errors cover about 95 %; 88 % allows this seed's luck
    for _ in range(24):
        run.add(8)
    assert run.samples == 256
    assert np.median(run.error) / first == pytest.approx(0.5, rel=0.3)  # 4x the samples: half the error


def test_progressive_runs_are_reproducible_from_their_seed(sunny):
    env, _ = sunny
    n = _unit(np.random.default_rng(9), 20)
    v = np.broadcast_to([0.0, 0.0, 1.0], n.shape)
    a = ProgressiveRadiance(Phong(0.5, 20), env, n, v, seed=11).add(8).add(8)
    b = ProgressiveRadiance(Phong(0.5, 20), env, n, v, seed=11).add(8).add(8)
    np.testing.assert_array_equal(a.value, b.value)


# ----------------------------------------------------------------------------- GGX's long tails
@pytest.mark.parametrize("kernel", ["beckmann", "ggx"])
@pytest.mark.parametrize("sigma", [0.025, 0.1, 0.4])
def test_ndf_levels_are_their_kernel_s_average_of_the_map(sunny, sigma, kernel):
    # Brute force over every pixel of the map: Σ K L Ω / Σ K Ω, K = D(θ_h = ψ/2) max(cos ψ, 0) (n = v = r).
    env, pre = sunny
    alpha = sigma / math.sqrt(2)
    h = env.height
    d = LatLongEnvironment.pixel_directions(h, 2 * h).reshape(-1, 3)
    weight = np.broadcast_to(env.solid_angles(), (h, 2 * h)).reshape(-1)
    radiance = env.image.reshape(-1, 3)
    for r in ([0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.8, 0.0, -0.6], [-0.3, 0.5, 0.3]):
        r = np.asarray(r) / np.linalg.norm(r)
        c = d @ r
        cos2h = (1 + c) / 2
        if kernel == "ggx":
            ndf = 1 / (alpha**2 * cos2h + (1 - cos2h)) ** 2
        else:
            ndf = np.exp(-(1 - cos2h) / (cos2h * alpha**2)) / cos2h**2
        k = ndf * np.maximum(c, 0) * weight
        expected = (k[:, None] * radiance).sum(0) / k.sum()
        np.testing.assert_allclose(pre.lookup(r, sigma, kernel), expected, rtol=0.01, err_msg=str(r))


def test_ggx_lobes_use_the_long_tailed_levels():
    from lighting.integrate.prefilter import kernel_of_lobe

    assert kernel_of_lobe(CookTorrance(1.0, 0.2, ndf="ggx").lobe()) == "ggx"
    assert kernel_of_lobe(CookTorrance(1.0, 0.2, ndf="beckmann").lobe()) == "beckmann"
    assert kernel_of_lobe(Phong(1.0, 50).lobe()) == "mirror"
    assert CookTorrance(1.0, 0.2, ndf="ggx").lobe().tails == "ggx"
    assert CookTorrance(1.0, 0.2, ndf="beckmann").lobe().tails == "gaussian"
    assert BlinnPhong(1.0, 50).lobe().tails == "gaussian"
    from lighting.models.disney import Disney

    assert Disney().lobe().tails == "ggx"


def test_a_lookup_near_a_pole_is_continuous(sunny):
    # Across the zenith every column meets: the value is the edge row's mean there, not one column's.
    _, pre = sunny
    for s in (0.05, 0.4):
        around = [pre.lookup([math.cos(p) * 1e-6, math.sin(p) * 1e-6, 1.0], s) for p in np.linspace(0, 6, 7)]
        # 1e-6 rad from the pole the columns are weighted 2e-4 against the pole's mean (the clamp to the edge
        # row, before, spread them by the whole ring's variation).
        assert np.ptp(around, axis=0).max() < 1e-3 * float(np.max(around))


def test_an_image_prefiltered_again_shares_its_levels_and_its_dominant_lights():
    from lighting.integrate.dominant import dominant_environment, forget_environments

    image = np.random.default_rng(3).random((32, 64, 3)) + np.where(np.arange(64) == 9, 500.0, 0.0)[None, :, None]
    first, again = LatLongEnvironment(image), LatLongEnvironment(image.copy())
    a, b = prefilter_environment(first), prefilter_environment(again)
    assert b.environment is again and all(x is y for x, y in zip(a.levels, b.levels, strict=True))
    kept = dominant_environment(a)
    assert dominant_environment(b) is kept
    assert not a.levels[1].flags.writeable  # shared: nobody may write into it
    fresh = prefilter_environment(again, reuse=False)
    assert fresh.levels[1] is not a.levels[1]
    assert all(np.array_equal(x, y) for x, y in zip(a.levels, fresh.levels, strict=True))  # bit for bit
    other = prefilter_environment(LatLongEnvironment(image * 2))  # another image: its own levels
    assert other.levels[1] is not a.levels[1] and not np.array_equal(other.levels[1], a.levels[1])
    forget_environments()  # what a benchmark of a first frame does: the next sky is made afresh
    again_pre = prefilter_environment(first)
    assert again_pre.levels[1] is not a.levels[1] and dominant_environment(again_pre) is not kept

"""Environment lighting: lookups, orientation, sampling densities, the small-patch limit quantities."""

import math

import numpy as np
import pytest
from chi2 import chi2_sf

from lighting.lights.environment import (
    ConstantEnvironment,
    FunctionEnvironment,
    LatLongEnvironment,
    PointEnvironment,
    SmallPatchEnvironment,
    as_environment,
    latlong_angles,
    uniform_sphere,
)
from lighting.vec import spherical_direction


def _rand_dirs(k, seed):
    d = np.random.default_rng(seed).normal(size=(k, 3))
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


# ---------------------------------------------------------------- constant
def test_constant_environment_value_shape_and_dtype():
    env = ConstantEnvironment((0.5, 1.0, 2.0))
    d = _rand_dirs(7, 1).reshape(7, 1, 3)
    out = env.radiance(d)
    assert out.shape == (7, 1, 3)
    np.testing.assert_array_equal(out, np.broadcast_to([0.5, 1.0, 2.0], (7, 1, 3)))
    assert env.radiance(d.astype(np.float32)).dtype == np.float32


def test_as_environment_wraps_values_and_callables():
    assert isinstance(as_environment(2.0), ConstantEnvironment)
    assert isinstance(as_environment(lambda d: d[..., 2]), FunctionEnvironment)
    with pytest.raises(ValueError, match="environment"):
        as_environment("sky")


# ---------------------------------------------------------------- latitude-longitude images
def _coded_image(h=6, w=12):
    """Each pixel holds (row, column, 1) so lookups reveal which pixel they read."""
    i, j = np.meshgrid(np.arange(h, dtype=float), np.arange(w, dtype=float), indexing="ij")
    return np.stack([i, j, np.ones_like(i)], axis=-1)


def test_latlong_pixel_centres_return_pixel_values():
    img = _coded_image()
    env = LatLongEnvironment(img)
    d = LatLongEnvironment.pixel_directions(6, 12)
    np.testing.assert_allclose(env.radiance(d), img, atol=1e-12)


def test_latlong_orientation_matches_engine_spherical_coordinates():
    # Row i ↔ θ = (i + ½)π/H from +z; column j ↔ φ = π − (j + ½)2π/W from +x toward +y.
    h, w = 6, 12
    env = LatLongEnvironment(_coded_image(h, w))
    for i, j in [(0, 0), (2, 3), (5, 11), (3, 7)]:
        d = spherical_direction((i + 0.5) * math.pi / h, math.pi - (j + 0.5) * 2 * math.pi / w)
        np.testing.assert_allclose(env.radiance(d)[:2], [i, j], atol=1e-12)
    # Zenith reads the top row, nadir the bottom row.
    assert env.radiance(np.array([0.0, 0.0, 1.0]))[0] == 0.0
    assert env.radiance(np.array([0.0, 0.0, -1.0]))[0] == h - 1


def test_a_single_bright_pixel_lands_where_blender_and_mitsuba_put_it():
    # Row 9, column 21 of a 64 x 32 panorama.  Blender's equirectangular world (+z up) reads a direction d
    # at u = (π − atan2(d_y, d_x)) / 2π; Mitsuba 3's envmap, in its y-up frame, at u = atan2(x, −z) / 2π, and
    # made +z-up by to_world = rotate([1, 0, 0], 90) its frame's (x, y, z) is the world's (x, z, −y).
    h, w, i, j = 32, 64, 9, 21
    img = np.zeros((h, w, 3))
    img[i, j] = 1.0
    env = LatLongEnvironment(img)
    u, v = (j + 0.5) / w, (i + 0.5) / h
    # Where the engine puts the pixel: its brightest direction on a fine probe, and its samples.
    probe = LatLongEnvironment.pixel_directions(8 * h, 8 * w).reshape(-1, 3)
    d = probe[np.argmax(env.radiance(probe)[:, 0])]
    samples, _ = env.sample(np.random.default_rng(1).random((2000, 2)))
    # (The sampler draws where bilinear lookup reaches: within one pixel of the centre.)
    for (x, y, z), reach in ((d, 0.5), *((s, 1.0) for s in samples)):
        assert math.acos(z) / math.pi == pytest.approx(v, abs=reach / h)
        assert ((math.pi - math.atan2(y, x)) / (2 * math.pi)) % 1 == pytest.approx(u, abs=reach / w)  # Blender
        assert (math.atan2(x, y) / (2 * math.pi)) % 1 == pytest.approx((u - 0.25) % 1, abs=reach / w)  # Mitsuba
    # The pixel's centre, φ = 180° − 360° u = 59.06° (a mirrored layout would put it at 120.94°).
    assert math.degrees(math.atan2(d[1], d[0])) == pytest.approx(180 - 360 * u, abs=360 / (8 * w))
    # Not mirrored: seen from inside with +z up, looking along +x (the image's centre), +y is on the left.
    a_left = latlong_angles(np.array([0.0, 1.0, 0.0]))[1]
    a_centre = latlong_angles(np.array([1.0, 0.0, 0.0]))[1]
    assert a_left < a_centre and a_centre == pytest.approx(math.pi, abs=1e-15)


def test_latlong_bilinear_and_wraps_in_phi():
    img = np.zeros((2, 4, 3))
    img[:, 0] = 1.0  # column 0 centred at φ = π − π/4; column 3 at φ = π − 7π/4
    img[:, 3] = 3.0
    env = LatLongEnvironment(img)
    # φ = π (both edges of the image) lies halfway between the centres of columns 3 and 0 (across the seam).
    assert env.radiance(spherical_direction(math.pi / 4, math.pi))[0] == pytest.approx(2.0, abs=1e-12)
    # A quarter of the way from column 0's centre toward column 1's.
    assert env.radiance(spherical_direction(math.pi / 4, math.pi - (math.pi / 4 + math.pi / 8)))[0] == pytest.approx(
        0.75
    )
    # Linear in θ between the two row centres (θ = π/4 and 3π/4); clamped beyond them.
    img2 = np.zeros((2, 4, 3))
    img2[1] = 4.0
    env2 = LatLongEnvironment(img2)
    assert env2.radiance(spherical_direction(math.pi / 2, 1.0))[0] == pytest.approx(2.0, abs=1e-12)
    assert env2.radiance(spherical_direction(0.1, 1.0))[0] == 0.0


def test_latlong_solid_angles_sum_to_four_pi_and_from_function():
    env = LatLongEnvironment.from_function(lambda d: 1.0 + d[..., 2:3] * np.array([1.0, 0.0, -1.0]), 16)
    assert env.image.shape == (16, 32, 3)
    om = env.solid_angles()
    assert om.sum() == pytest.approx(4 * math.pi, rel=1e-14)
    # Exact per-row solid angle: (cos θ_top − cos θ_bottom) 2π/W.
    assert om[0, 0] == pytest.approx((1 - math.cos(math.pi / 16)) * 2 * math.pi / 32, rel=1e-14)


def test_latlong_sampling_density_is_consistent_and_covers_the_radiance():
    rng = np.random.default_rng(3)
    img = rng.random((8, 16, 3)) * (rng.random((8, 16, 1)) > 0.7)  # mostly black, a few lit pixels
    env = LatLongEnvironment(img)
    d, p = env.sample(rng.random((4000, 2)))
    np.testing.assert_allclose(np.linalg.norm(d, axis=-1), 1.0, atol=1e-12)
    np.testing.assert_allclose(env.pdf(d), p, rtol=1e-12)
    # The density integrates to one: over each half-pixel cell (the pixels of a 16 x 32 image) it is bilinear in
    # (cos θ, φ), so its mean there is its value at the cell's middle in cos θ and φ.
    omega = LatLongEnvironment(np.zeros((16, 32, 3))).solid_angles()
    c = np.cos(np.linspace(0, math.pi, 17))
    z = 0.5 * (c[:-1] + c[1:])[:, None]
    phi = math.pi - (np.arange(32) + 0.5) * (2 * math.pi / 32)
    r = np.sqrt(1 - z * z)
    middles = np.stack(np.broadcast_arrays(r * np.cos(phi), r * np.sin(phi), z), axis=-1)
    assert np.sum(env.pdf(middles) * omega) == pytest.approx(1.0, rel=1e-12)
    # Wherever bilinear lookup returns light, the density is positive (no bias in environment sampling).
    probe = _rand_dirs(20000, 4)
    lit = env.radiance(probe).max(axis=-1) > 0
    assert np.all(env.pdf(probe)[lit] > 0)


def test_latlong_sampling_chi_square_over_pixels():
    rng = np.random.default_rng(5)
    img = rng.random((6, 12, 3)) ** 3
    env = LatLongEnvironment(img)
    n = 60000
    d, _ = env.sample(rng.random((n, 2)))
    theta = np.arccos(np.clip(d[:, 2], -1, 1))
    a = latlong_angles(d)[1]  # the column angle 2πu
    i = np.minimum((theta / math.pi * 6).astype(int), 5)
    j = np.minimum((a / (2 * math.pi) * 12).astype(int), 11)
    counts = np.bincount(i * 12 + j, minlength=72)
    expected = n * env._pixel_probabilities().ravel()
    keep = expected >= 5
    chi2 = np.sum((counts[keep] - expected[keep]) ** 2 / expected[keep])
    assert chi2_sf(chi2, keep.sum() - 1) > 1e-3


@pytest.mark.parametrize(
    "image, match",
    [
        (np.zeros((4, 8)), "shape"),
        (np.zeros((4, 8, 4)), "shape"),
        (-np.ones((2, 4, 3)), ">= 0"),
        (np.full((2, 4, 3), np.nan), "finite"),
    ],
)
def test_latlong_rejects_bad_images(image, match):
    with pytest.raises(ValueError, match=match):
        LatLongEnvironment(image)


# ---------------------------------------------------------------- function environments
def test_function_environment_scalar_and_rgb():
    env = FunctionEnvironment(lambda d: 1.0 + d[..., 2])
    np.testing.assert_allclose(env.radiance(np.array([[0, 0, 1.0], [0, 0, -2.0]])), [[2.0] * 3, [0.0] * 3])
    rgb = FunctionEnvironment(lambda d: np.abs(d))
    np.testing.assert_allclose(rgb.radiance(np.array([0.6, 0.0, 0.8])), [0.6, 0.0, 0.8])


def test_function_environment_errors():
    with pytest.raises(ValueError, match="callable"):
        FunctionEnvironment(3.0)
    with pytest.raises(ValueError, match="shape"):
        FunctionEnvironment(lambda d: np.ones(d.shape[:-1] + (2,))).radiance(np.zeros((4, 3)) + 1)
    with pytest.raises(ValueError, match="finite"):
        FunctionEnvironment(lambda d: d[..., 0] * np.nan).radiance(np.ones((2, 3)))


def test_uniform_sphere_is_uniform():
    rng = np.random.default_rng(6)
    d, p = uniform_sphere(rng.random((200000, 2)))
    np.testing.assert_allclose(p, 1 / (4 * math.pi))
    # Mean of z and of z² for a uniform sphere: 0 and 1/3.
    assert abs(d[:, 2].mean()) < 4 * math.sqrt(1 / 3 / 200000)
    assert d[:, 2].var() == pytest.approx(1 / 3, abs=4 * math.sqrt(4 / 45 / 200000))


# ---------------------------------------------------------------- small patch ("light at one point")
@pytest.mark.parametrize("omega", [1e-12, 1e-6, 1e-2, 1.0, 4 * math.pi])
def test_small_patch_cap_boundary_is_its_solid_angle(omega):
    c = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    env = SmallPatchEnvironment(c, omega, 7.0)
    gamma = env.half_angle
    # Ω = 2π (1 − cos γ), computed without cancellation.
    assert 4 * math.pi * math.sin(gamma / 2) ** 2 == pytest.approx(omega, rel=1e-12)
    t = np.cross(c, [0.0, 0.0, 1.0])
    t /= np.linalg.norm(t)

    def at(angle):
        return math.cos(angle) * c + math.sin(angle) * t

    assert env.radiance(c)[0] == 7.0
    if gamma < math.pi:
        assert env.radiance(at(gamma * (1 - 1e-6)))[0] == 7.0
        assert env.radiance(at(min(gamma * (1 + 1e-6), math.pi)))[0] == 0.0


def test_small_patch_sampling_uniform_in_cap():
    env = PointEnvironment((0.0, 0.0, 1.0), 0.05, 1.0)
    d, p = env.sample(np.random.default_rng(7).random((100000, 2)))
    np.testing.assert_allclose(p, 1 / 0.05)
    assert np.all(env.radiance(d)[:, 0] == 1.0)
    np.testing.assert_allclose(env.pdf(d), 1 / 0.05)
    # Uniform on the cap: 1 − cos ψ is uniform on [0, Ω/2π], mean Ω/4π.
    omc = 1 - d[:, 2]
    assert omc.mean() == pytest.approx(0.05 / (4 * math.pi), rel=4 * math.sqrt(1 / 3 / 100000))
    assert env.pdf(np.array([1.0, 0.0, 0.0])) == 0.0


def test_small_patch_irradiance_quantities():
    env = SmallPatchEnvironment((0, 0, 1.0), 0.3, (1.0, 2.0, 3.0))
    np.testing.assert_allclose(env.irradiance_limit, [0.3, 0.6, 0.9])
    gamma = env.half_angle
    np.testing.assert_allclose(env.irradiance_normal, math.pi * math.sin(gamma) ** 2 * np.array([1, 2, 3.0]))


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(direction=(0, 0, 0)), "direction"),
        (dict(solid_angle=0.0), "solid_angle"),
        (dict(solid_angle=13.0), "solid_angle"),
        (dict(radiance=-1.0), "radiance"),
    ],
)
def test_small_patch_rejects_bad_parameters(kwargs, match):
    with pytest.raises(ValueError, match=match):
        SmallPatchEnvironment(**kwargs)


# ----------------------------------------------------------------------------------- bad input, a named error
@pytest.mark.parametrize(
    "directions, exc",
    [
        ((float("nan"), 0.0, 1.0), ValueError),
        ((float("inf"), 0.0, 1.0), ValueError),
        ((1j, 0.0, 1.0), TypeError),
        ("0 0 1", TypeError),
        (b"1", TypeError),
        ((1.0, 2.0), ValueError),
    ],
)
def test_lookups_refuse_non_finite_complex_and_text_directions(directions, exc):
    # Old code: NaN directions gave radiance NaN or 0 silently, strings were parsed as numbers.
    for env in (ConstantEnvironment(1.0), SmallPatchEnvironment((0, 0, 1.0), 1e-3, 1.0)):
        with pytest.raises(exc, match="^directions must be finite real vectors"):
            env.radiance(directions)
        with pytest.raises(exc, match="^directions"):
            env.pdf(directions)


@pytest.mark.parametrize("u", [(1.5, 0.5), (-0.1, 0.5), (float("nan"), 0.5), (0.5, 0.5, 0.5), "0.5 0.5"])
def test_sample_refuses_points_outside_the_unit_square(u):
    with pytest.raises(ValueError, match=r"^u must be points of the unit square"):
        SmallPatchEnvironment((0, 0, 1.0), 1e-3, 1.0).sample(u)


def test_image_checks_are_named_and_one_line():
    bad = np.full((2, 4, 3), np.nan)
    with pytest.raises(ValueError, match=r"^image must be .*got 24 NaN or infinite values$"):
        LatLongEnvironment(bad)
    with pytest.raises(TypeError, match="image .* dtype complex128"):
        LatLongEnvironment(np.ones((2, 4, 3)) * 1j)
    with pytest.raises(ValueError, match="height/width needs about .* over the memory budget"):
        LatLongEnvironment.from_function(np.abs, 2, 10**9)
    with pytest.raises(TypeError, match="^width must be an integer"):
        LatLongEnvironment.pixel_directions(2, None)

"""Procedural skies: values, the furnace, the figures' skies unchanged (SH9 exactness for the band-limited sky:
test_skies_full.py)."""

import math

import numpy as np
import pytest

from lighting import CookTorrance, Lambert
from lighting.integrate import directional_albedo, outgoing_radiance
from lighting.lights.environment import FunctionEnvironment, LatLongEnvironment
from lighting.lights.skies import SKIES, sky, sky_names


def _rand_dirs(k, seed):
    d = np.random.default_rng(seed).normal(size=(k, 3))
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def _sphere_grid(n_t=400, n_p=800):
    z = np.linspace(-1, 1, n_t)
    phi = np.linspace(0, 2 * math.pi, n_p, endpoint=False)
    r = np.sqrt(1 - z * z)
    return np.stack(np.broadcast_arrays(r[:, None] * np.cos(phi), r[:, None] * np.sin(phi), z[:, None]), axis=-1)


@pytest.mark.parametrize("name", list(SKIES))
def test_every_sky_is_finite_nonnegative_and_keeps_the_dtype(name):
    grid = _sphere_grid()
    env = sky(name)
    out64 = env.radiance(grid)
    assert out64.shape == grid.shape and out64.dtype == np.float64
    assert np.all(np.isfinite(out64)) and np.all(out64 >= 0) and out64.max() > 0
    # float32 in, float32 out: the float64 values at the same (float32) directions, rounded once.
    g32 = grid.astype(np.float32)
    out32 = env.radiance(g32)
    assert out32.dtype == np.float32
    np.testing.assert_array_equal(out32, env.radiance(g32.astype(np.float64)).astype(np.float32))
    # The registry's function takes float32 directly and answers in float32 too.
    assert SKIES[name](grid[:2, :3].astype(np.float32)).dtype == np.float32
    assert SKIES[name].description and sky_names()[list(SKIES).index(name)] == name


def test_uniform_sky_is_the_white_furnace():
    n = _rand_dirs(5, 1)
    v = n + 0.4 * _rand_dirs(5, 2)
    np.testing.assert_allclose(outgoing_radiance(Lambert(0.7), sky("uniform"), n, v), 0.7, rtol=1e-12)
    # A glossy model returns its directional albedo (the engine's integrator on the furnace).
    ct = CookTorrance(1.0, 0.3, 0.9)
    theta_v = 0.6
    v1 = np.array([math.sin(theta_v), 0.0, math.cos(theta_v)])
    lo = outgoing_radiance(ct, sky("uniform", value=2.0), np.array([0.0, 0.0, 1.0]), v1, samples=16384)
    np.testing.assert_allclose(lo, 2.0 * directional_albedo(ct, theta_v, samples=16384), rtol=1e-6)


def test_daylight_sky_is_the_rendering_figures_formula_bit_for_bit():
    from explorer.figures.rendering import _CAM_TO_ENV, _sky

    def old_sky(sun_env):  # the figure's formula before it moved into lighting.lights.skies
        s = np.asarray(sun_env, dtype=np.float64) / np.linalg.norm(sun_env)

        def radiance(d):
            z = d[..., 2]
            up = np.clip(z, 0.0, 1.0)[..., None]
            zenith = np.array([0.18, 0.35, 0.85])
            horizon = np.array([0.85, 0.85, 0.8])
            ground = np.array([0.2, 0.15, 0.1])
            sky_ = horizon + (zenith - horizon) * np.sqrt(up)
            t = np.clip(0.5 + 4.0 * z, 0.0, 1.0)[..., None]
            base = ground + (sky_ - ground) * t
            c = np.clip(d @ s, 0.0, 1.0)[..., None]
            glow = np.array([3.0, 2.6, 2.0]) * c**64 + np.array([0.6, 0.45, 0.3]) * c**6
            return base + glow

        return radiance

    sun = _CAM_TO_ENV @ (np.array([-0.45, 0.55, 0.7]) / np.linalg.norm([-0.45, 0.55, 0.7]))
    for h in (48, 192):  # the figure's quick and full environment images
        new = LatLongEnvironment.from_function(_sky(sun), h).image
        old = LatLongEnvironment.from_function(old_sky(sun), h).image
        np.testing.assert_array_equal(new, old)


def test_glow_sky_is_the_accuracy_reports_formula_bit_for_bit():
    from lighting.validation.accuracy import _glow_sky

    d = _rand_dirs(1000, 8)
    s = np.array([0.5, 0.3, 0.81])
    s = s / np.linalg.norm(s)
    old = np.array([0.25, 0.3, 0.4]) + np.multiply.outer(np.clip(d @ s, 0.0, None) ** 8, np.array([2.0, 1.8, 1.5]))
    np.testing.assert_array_equal(_glow_sky(d), old)
    np.testing.assert_array_equal(SKIES["glow"](d), old)
    np.testing.assert_allclose(sky("glow").radiance(d), old, rtol=1e-13)  # after the environment's normalization


def test_bad_names_and_parameters():
    with pytest.raises(ValueError, match=r"unknown sky 'sun-set' \(did you mean 'sunset'\?\); allowed: uniform"):
        sky("sun-set")
    with pytest.raises(ValueError, match=r"unknown sky 'xyz'; allowed"):
        sky("xyz")
    with pytest.raises(TypeError, match="sky name must be one of"):
        sky(3)
    with pytest.raises(ValueError, match=r"sky 'daylight' has no parameter 'sun_elevation_deg'; allowed: sun"):
        sky("daylight", sun_elevation_deg=10)
    with pytest.raises(ValueError, match="sun must be finite real vectors.*non-zero length"):
        sky("glow", sun=(0, 0, 0))
    with pytest.raises(ValueError, match="sun_elevation_deg"):
        sky("sunset", sun_elevation_deg=120.0)
    for name, p in (("uniform", "value"), ("studio", "background"), ("band-limited", "scale")):
        with pytest.raises(ValueError, match=p):
            sky(name, **{p: -1.0})
    assert isinstance(sky("Band_Limited", scale=2.0), FunctionEnvironment)
    np.testing.assert_allclose(
        sky("band-limited", scale=2.0).radiance([0.0, 0.0, 1.0]), 2 * sky("band-limited").radiance([0.0, 0.0, 1.0])
    )

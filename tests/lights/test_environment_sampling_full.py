"""Environment sampling against fine references, and a one-pixel sun found by one sample per pixel of a 256 x 256
render (slow set; the fast checks: test_environment_sampling.py)."""

import math

import numpy as np
import pytest
from test_environment_sampling import (
    COLOUR,
    H,
    W,
    _DilatedPixels,
    _exact_irradiance,
    _lum,
    _one_pixel,
    _sphere,
    _sunny_image,
)

from lighting.integrate.ibl import ProgressiveRadiance
from lighting.lights.environment import LatLongEnvironment
from lighting.models.brdf import Lambert
from lighting.sampling import environment as envmod

pytestmark = pytest.mark.slow  # irradiance on a 24x finer grid; 1024-spp references, 65,536 samples of a one-pixel sun


@pytest.mark.parametrize("where", [(20, 40), (30, 0), (17, 127), (0, 64), (63, 5)])
def test_a_one_pixel_sun_is_found_at_one_sample_per_pixel(where):
    # One environment sample per pixel of a 256 x 256 render (jittered): every one lands in the sun's light.
    img = _one_pixel(64, 128, *where, 3000.0)
    env = LatLongEnvironment(img)
    g = (np.stack(np.meshgrid(np.arange(256), np.arange(256), indexing="ij"), axis=-1).reshape(-1, 2)
         + np.random.default_rng(14).random((65536, 2))) / 256  # fmt: skip
    d, p = env.sample(g)
    assert np.all(env.radiance(d)[:, 0] > 0)
    # The estimate of the sun's power from those samples alone: ∫ L dω within 0.5 %.
    power = envmod._cell_masses_reference(_lum(img)).sum()
    assert np.mean(env.radiance(d)[:, 0] / p) == pytest.approx(power, rel=5e-3)


def test_the_exact_irradiance_is_the_lookup_s_integral():
    # Against a brute-force midpoint rule on a 24x finer grid of the lookup (its own error about 1e-6).
    env = LatLongEnvironment(_sunny_image())
    n, _, sun = _sphere()
    k = 24
    d = LatLongEnvironment.pixel_directions(H * k, W * k)
    omega = LatLongEnvironment(np.zeros((H * k, W * k, 3))).solid_angles()
    radiance = env.radiance(d.reshape(-1, 3))[:, 0].reshape(H * k, W * k)
    for normal in (sun, n[0], n[len(n) // 2], np.array([0.0, 0.0, -1.0])):
        brute = float(np.sum(radiance * omega * np.maximum(d @ normal, 0.0)))
        assert _exact_irradiance(normal) == pytest.approx(brute, rel=2e-6)


def test_the_reference_under_a_one_pixel_sun_is_honest_and_needs_a_quarter_of_the_samples():
    img = _sunny_image()
    n, v, sun = _sphere()
    views = np.broadcast_to(v, n.shape)
    kd = 0.8
    exact = np.array([_exact_irradiance(m) for m in n])[:, None] * COLOUR * (kd / math.pi)

    def reference(env, spp, normals, seed):
        run = ProgressiveRadiance(Lambert(kd), env, normals, views[: len(normals)], seed=seed)
        for _ in range(8):
            run.add(spp // 8)
        return run

    new = reference(LatLongEnvironment(img), 1024, n, 1)
    # Honest: the exact value within two of the run's own standard errors for nearly every pixel.
    assert np.mean(np.abs(new.value - exact) < 2 * new.error) > 0.88
    # Where the sun lights the sphere, a quarter of the old sampler's samples reach its error.
    lit = n @ sun > 0.05
    old = reference(_DilatedPixels(img), 4096, n[lit], 1)
    assert np.mean(np.abs(old.value - exact[lit]) < 2 * old.error) > 0.88
    err_new, err_old = np.abs(new.value[lit] - exact[lit]) / exact[lit], np.abs(old.value - exact[lit]) / exact[lit]
    assert np.median(err_new) < np.median(err_old)
    assert np.median(new.error[lit] / exact[lit]) < np.median(old.error / exact[lit])

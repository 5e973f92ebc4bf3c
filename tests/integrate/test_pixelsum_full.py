"""The pixel sum against the engine's Monte-Carlo reference under a sun and under the studio's boxes."""

import numpy as np
import pytest

from lighting.integrate.ibl import ProgressiveRadiance
from lighting.integrate.pixelsum import environment_sum_radiance
from lighting.models.brdf import CookTorrance, Lambert
from lighting.validation.accuracy import ibl_environment, ibl_front_pixels

pytestmark = pytest.mark.slow  # 32 Monte-Carlo passes per model, two skies

MODELS = [Lambert(0.8)] + [CookTorrance(1.0, a, 1.0, ndf="ggx", fresnel="none") for a in (0.05, 0.2, 0.5)]


@pytest.mark.parametrize("sky", ["sun-gradient", "studio"])
def test_the_pixel_sum_is_the_monte_carlo_references_mean(sky):
    n, v = ibl_front_pixels(32, 12, min_cos=0.05)
    env = ibl_environment(sky, 64)
    z = []
    for m in MODELS:
        exact = environment_sum_radiance(m, env, n, v)
        assert np.all(exact.error <= 1e-4 * exact.value.max(axis=-1, keepdims=True)), m
        mc = ProgressiveRadiance(m, env, n, v, seed=5)
        for _ in range(32):  # the spread of 32 passes: an error estimate with 31 degrees of freedom
            mc.add(512)
        z.append((exact.value - mc.value) / np.hypot(mc.error, exact.error))
    z = np.abs(np.concatenate(z).ravel())
    # |t| with 31 degrees of freedom exceeds 3 with probability 0.5 %: of these 144 values, one or two may.
    assert np.mean(z > 3) <= 0.03 and z.max() < 5, (np.sort(z)[-5:], np.mean(z**2))
    # No bias: the squared deviations average about one (the mean of 144 values of a t²: 1.07 ± 0.2).
    assert 0.6 < np.mean(z**2) < 1.6, np.mean(z**2)

"""The pixel sum against the engine's Monte-Carlo reference under a sun and under the studio's boxes, and the IBL
study's fast methods judged against it."""

import math

import numpy as np
import pytest

from lighting.integrate.ibl import ProgressiveRadiance
from lighting.integrate.pixelsum import environment_sum_radiance
from lighting.models.brdf import CookTorrance, Lambert
from lighting.validation.accuracy import ibl_environment, ibl_front_pixels

pytestmark = pytest.mark.slow  # 32 Monte-Carlo passes per model, two skies; the IBL study's points at a small size

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


def test_the_ibl_study_judges_the_fast_methods_against_the_pixel_sum():
    from lighting.validation import accuracy

    cfg = accuracy._settings(True) | {"ibl_exact_pixels": 4, "ibl_size": 16, "ibl_pixels": 16, "ibl_env_height": 32,
                                      "ibl_reference_spp": 64, "ibl_spp": [8]}  # fmt: skip
    cfg["ibl_environments"] = dict(list(accuracy.IBL_ENVIRONMENTS.items())[:1])
    points = accuracy._ibl_points(cfg, lambda *a: None)
    judged = {(p.case, p.method): p for p in points if p.method.endswith(" · pixel sum")}
    models = [label for label, _ in cfg["ibl_models"] if label in accuracy.IBL_EXACT_MODELS]
    assert models and len(judged) == 3 * len(models)  # the split sum, the dominant lights, those on the normal grid
    for p in judged.values():
        assert p.reference_error <= accuracy.IBL_EXACT_RTOL and math.isfinite(p.error) and p.error_p95 >= p.error
        assert "on 4 of the 16 pixels" in p.reference
    lambert = [p for (case, _), p in judged.items() if case.startswith("Lambert")]
    split = next(p for p in lambert if p.method.startswith("split sum"))
    dominant = [p for p in lambert if p.method.startswith("dominant lights")]
    # The dominant lights shade a Lambertian part by the map's exact irradiance (read at each pixel or from the grid
    # of normals); the split sum by SH9.
    assert len(dominant) == 2 and all(p.error < split.error / 10 for p in dominant)

"""The pixel sum: reflected radiance of a lat-long environment by adaptive Gauss–Legendre over its cells.

Checked against what is known exactly: the furnace (a uniform sky reflects ``k_d L`` from a Lambertian surface)
and the directional albedo (a uniform sky of radiance 1 reflects ``ρ(v)``), with the error it reports covering
the true error; ``tests/integrate/test_pixelsum_full.py`` holds it to the Monte-Carlo reference under a sun, and
runs the IBL study that judges the fast methods against it.
"""

import math

import numpy as np
import pytest

from lighting.integrate import directional_albedo
from lighting.integrate.pixelsum import environment_sum_radiance
from lighting.lights.environment import ConstantEnvironment, LatLongEnvironment
from lighting.models.brdf import CookTorrance, Lambert, Phong
from lighting.models.mirror import Mirror

#: Views from normal incidence to 2.6° above the horizon.
VIEWS = [0.0, 1.0, 1.4, 1.525]


def _view(theta):
    return np.array([math.sin(theta), 0.0, math.cos(theta)])


def _tilted(theta, normal):
    """The view at ``theta`` from ``normal``, and ``normal``, both turned so that the normal is off the axes."""
    n = np.asarray(normal, dtype=np.float64)
    n /= np.linalg.norm(n)
    t = np.cross(n, [0.0, 0.0, 1.0]) if abs(n[2]) < 0.9 else np.cross(n, [1.0, 0.0, 0.0])
    t /= np.linalg.norm(t)
    return n, n * math.cos(theta) + t * math.sin(theta)


@pytest.mark.parametrize("theta", VIEWS)
def test_the_furnace_to_its_own_error(theta):
    sky = LatLongEnvironment(np.full((16, 32, 3), 1.5))
    n, v = _tilted(theta, (0.3, -0.4, 0.866))
    est = environment_sum_radiance(Lambert(0.6), sky, n, v)
    truth = 0.6 * 1.5
    assert np.all(np.abs(est.value - truth) <= est.error), (est.value - truth, est.error)
    assert np.all(est.error <= 1e-4 * truth)  # rtol: the rules' differences left over are within 1e-4


@pytest.mark.parametrize("theta", VIEWS)
@pytest.mark.parametrize("model", [CookTorrance(1.0, a, 1.0, ndf="ggx", fresnel="none") for a in (0.05, 0.2, 0.5)]
                         + [Phong(1.0, 500.0)], ids=["ggx-0.05", "ggx-0.2", "ggx-0.5", "phong-500"])  # fmt: skip
def test_a_uniform_sky_reflects_the_directional_albedo(model, theta):
    sky = LatLongEnvironment(np.ones((32, 64, 3)))
    est = environment_sum_radiance(model, sky, (0.0, 0.0, 1.0), _view(theta))
    albedo = directional_albedo(model, theta, return_error=True)
    value, err = float(est.value[0]), float(est.error[0])
    ref, ref_err = float(np.ravel(albedo.value)[0]), float(np.ravel(albedo.error)[0])
    assert abs(value - ref) <= err + ref_err, (value, ref, err, ref_err)
    assert err <= 1e-4 * value


def test_pixels_facing_away_are_zero_and_every_dtype_is_read_as_float64():
    sky = LatLongEnvironment(np.ones((8, 16, 3)))
    n = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]], dtype=np.float32)
    v = np.array([[0.0, 0.6, 0.8], [0.0, 0.6, -0.8]], dtype=np.float32)
    est = environment_sum_radiance(Lambert(0.5), sky, n, v)
    assert est.value.dtype == np.float64 and est.value.shape == (2, 3)
    assert np.all(est.value[1] == 0) and np.all(est.error[1] == 0)
    assert np.allclose(est.value[0], 0.5, rtol=1e-4, atol=0)
    assert est.method == "pixel sum" and est.samples > 0


def test_refusals_name_what_is_allowed():
    sky = LatLongEnvironment(np.ones((8, 16, 3)))
    up = (0.0, 0.0, 1.0)
    with pytest.raises(ValueError, match="brdf must have no delta part"):
        environment_sum_radiance(Mirror(), sky, up, up)
    with pytest.raises(TypeError, match="environment must be a LatLongEnvironment; got ConstantEnvironment"):
        environment_sum_radiance(Lambert(0.5), ConstantEnvironment(1.0), up, up)
    with pytest.raises(ValueError, match="rtol must be a finite number >= 1e-06 and <= 0.01; got 0.5"):
        environment_sum_radiance(Lambert(0.5), sky, up, up, rtol=0.5)

"""The χ² helper's fast density over the cells (:mod:`chi2`) gives its readable reference's numbers, bit for bit."""

import numpy as np
import pytest
from chi2 import _setup
from grazing_cases import anisotropic, registered, view

SAMPLERS = [pytest.param(s, id=name) for name, s, _ in registered() if s is not None][::4] + [
    pytest.param(s, id=name) for name, s in anisotropic()
][:2]


@pytest.mark.parametrize("theta_v", [0.0, 60.0, 89.0])
@pytest.mark.parametrize("sampler", SAMPLERS)
def test_the_column_by_column_density_is_the_reference_bit_for_bit(sampler, theta_v):
    v = view(theta_v, 20.0)
    q = _setup(sampler, v / np.linalg.norm(v), 16, 32, 7, 2000)[1]
    g = np.random.default_rng(11).normal(size=(3000, 3))
    g[:, 2] = np.abs(g[:, 2])
    g /= np.linalg.norm(g, axis=-1, keepdims=True)
    np.testing.assert_array_equal(q(g), q.reference(g))

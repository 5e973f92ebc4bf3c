"""A constant environment prefilters to itself, exactly and without convolving anything."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lighting.integrate import prefilter
from lighting.lights.environment import ConstantEnvironment
from lighting.lights.skies import sky


@pytest.mark.parametrize("env", [ConstantEnvironment((2.5, 1.0, 0.25)), sky("uniform")], ids=["constant", "uniform"])
def test_every_level_of_a_constant_environment_is_the_constant(env, monkeypatch):
    def never(*args, **kwargs):
        raise AssertionError("a constant environment needs no convolution")

    for name in ("_prefilter_levels", "_convolve_rows", "_convolve_rows_fast", "_ggx_level"):
        monkeypatch.setattr(prefilter, name, never)
    pre = prefilter.prefilter_environment(env)
    value = np.asarray(env.radiance(np.array([0.0, 0.0, 1.0])), dtype=np.float64)
    d = np.random.default_rng(3).normal(size=(500, 3))
    widths = np.random.default_rng(4).uniform(0.0, 2.0, size=500)
    for kernel in ("mirror", "beckmann", "ggx"):
        np.testing.assert_array_equal(pre.lookup(d, widths, kernel=kernel), np.broadcast_to(value, (500, 3)))
    # SH9 irradiance of a constant radiance L is π L at every normal.
    n = d / np.linalg.norm(d, axis=-1, keepdims=True)
    np.testing.assert_allclose(pre.irradiance_sh(n), np.broadcast_to(math.pi * value, (500, 3)), rtol=1e-12)

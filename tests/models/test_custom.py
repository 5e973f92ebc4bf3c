"""Models defined in Python (:func:`lighting.models.define_brdf`): found everywhere a built-in model is."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lighting.models import CosineSampler, Parameter, define_brdf, model_class
from lighting.models.protocol import unregister_model


def _minnaert(n, l, v, *, kd, k):  # noqa: E741
    """Minnaert (1941): ``k_d/π ((n·l)(n·v))^(k−1)``."""
    nl = np.sum(n * l, axis=-1, keepdims=True)
    nv = np.sum(n * v, axis=-1, keepdims=True)
    return kd / np.pi * (nl * nv) ** (k - 1)


TABLE = [
    Parameter("kd", "color", 0.5, high=1.0, description="albedo at k = 1"),
    Parameter("k", "float", 1.0, low=1.0, high=8.0, description="limb darkening"),
]


@pytest.fixture
def minnaert():
    cls = define_brdf("py-minnaert", _minnaert, TABLE, term="diffuse")
    yield cls
    unregister_model("py-minnaert")


def _pairs(rng, count):
    def hemi(size):
        d = rng.normal(size=(size, 3))
        d[:, 2] = np.abs(d[:, 2]) + 1e-3
        return d / np.linalg.norm(d, axis=-1, keepdims=True)

    return np.broadcast_to([0.0, 0.0, 1.0], (count, 3)), hemi(count), hemi(count)


def test_values_are_the_closed_form_in_both_dtypes(minnaert):
    n, l, v = _pairs(np.random.default_rng(1), 500)  # noqa: E741
    m = minnaert(kd=(0.2, 0.5, 0.8), k=2.5)
    want = np.array([0.2, 0.5, 0.8]) / math.pi * ((l[:, 2] * v[:, 2]) ** 1.5)[:, None]
    np.testing.assert_allclose(m.eval(n, l, v), want, rtol=1e-13)
    np.testing.assert_allclose(m.eval_cos(n, l, v), want * l[:, 2:3], rtol=1e-13)
    got32 = m.eval(n.astype(np.float32), l.astype(np.float32), v.astype(np.float32))
    assert got32.dtype == np.float32
    np.testing.assert_allclose(got32, want, rtol=2e-6)
    # Below the horizon: 0, whatever the function would give there.
    below = l * [1, 1, -1]
    assert np.all(m.eval(n, below, v) == 0)


def test_registered_like_a_built_in_model(minnaert):
    assert model_class("py-minnaert") is minnaert
    m = minnaert(kd=0.7, k=3.0)
    assert m.to_dict() == {"model": "py-minnaert", "kd": [0.7, 0.7, 0.7], "k": 3.0}
    again = model_class("py-minnaert").from_dict(m.to_dict())
    np.testing.assert_array_equal(again.kd, m.kd)
    assert m.summary() == "py-minnaert kd=0.7 k=3 (Python function; cosine sampling)"


def test_albedo_and_the_cosine_sampler_it_falls_back_to(minnaert):
    from lighting.integrate import directional_albedo, sample_brdf

    m = minnaert(kd=0.6, k=3.0)
    # ρ(0) = 2 k_d/(k + 1) for Minnaert at normal view.
    np.testing.assert_allclose(directional_albedo(m, 0.0), 2 * 0.6 / 4.0, rtol=1e-9)
    assert m.lobe() is None and isinstance(m.sampler(), CosineSampler)
    s = sample_brdf(m, np.array([0.0, 0.0, 1.0]), 256, seed=2)
    np.testing.assert_allclose(s.pdf, s.directions[:, 2] / math.pi, rtol=1e-12)


def test_scene_file_renders_it_and_at_k_1_it_is_lambert(minnaert):
    from lighting.scene import parse_scene, render_scene

    scene = """
[camera]
eye = [0.0, 0.0, 4.0]
[image]
width = 24
height = 24
[materials.m]
parts = [PART]
[[objects]]
type = "sphere"
material = "m"
[[lights]]
type = "directional"
direction = [0.3, 0.5, 1.0]
"""
    mine = render_scene(parse_scene(scene.replace("PART", '{model = "py-minnaert", kd = 0.7, k = 1.0}')))[0]
    lambert = render_scene(parse_scene(scene.replace("PART", '{model = "lambert", kd = 0.7}')))[0]
    assert lambert.max() > 0.1
    np.testing.assert_allclose(mine, lambert, rtol=1e-12, atol=1e-15)


def test_bad_values_and_bad_functions_are_named(minnaert):
    with pytest.raises(ValueError, match=r"k must be a number in \[1, 8\]; got 9"):
        minnaert(k=9)
    with pytest.raises(ValueError, match="unknown parameter 'sigma'; allowed: kd, k"):
        minnaert(sigma=0.3)
    negative = define_brdf("py-negative", lambda n, l, v: -np.ones(np.shape(n)), register=False)
    with pytest.raises(ValueError, match="py-negative: the function returned negative or non-finite f_r at 1 dir"):
        negative().eval([0, 0, 1], [0, 0, 1], [0, 0, 1])
    shaped = define_brdf("py-shape", lambda n, l, v: np.ones(7), register=False)
    with pytest.raises(ValueError, match=r"py-shape: the function must return f_r of shape \(\.\.\., 3\)"):
        shaped().eval([0, 0, 1], [0, 0, 1], [0, 0, 1])
    with pytest.raises(ValueError, match="already"):
        define_brdf("lambert", _minnaert, TABLE)
    with pytest.raises(ValueError, match="Parameter rows"):
        define_brdf("py-x", _minnaert, [("kd", 0.5)], register=False)


def test_a_huge_value_saturates_in_float32_without_a_warning():
    huge = define_brdf("py-huge", lambda n, l, v: np.full(np.shape(n), 1e300), register=False)
    one = np.array([0.0, 0.0, 1.0], dtype=np.float32)
    got = huge().eval(one, one, one)
    assert got.dtype == np.float32 and np.all(got == np.finfo(np.float32).max)
    assert np.all(huge().eval([0, 0, 1.0], [0, 0, 1.0], [0, 0, 1.0]) == 1e300)

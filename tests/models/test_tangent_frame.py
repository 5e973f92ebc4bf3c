"""The shading frame ``(t, b, n)`` that anisotropic models orient their lobes by (``eval(..., tangent=...)``)."""

import numpy as np
import pytest

from lighting import Lambert, Phong
from lighting.models.geometry import Geometry


def _frame(n, tangent=None, dtype=np.float64):
    g = Geometry(np.asarray(n, dtype), np.asarray((0.0, 0.0, 1.0), dtype), np.asarray((0.0, 0.0, 1.0), dtype),
                 tangent=None if tangent is None else np.asarray(tangent, dtype))  # fmt: skip
    return g.t, g.b, g.n


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_default_frame_is_orthonormal_right_handed_and_follows_the_azimuth(dtype):
    rng = np.random.default_rng(5)
    n = rng.normal(size=(2000, 3))
    t, b, nn = _frame(n, dtype=dtype)
    assert t.dtype == dtype and b.dtype == dtype
    eps = 8 * np.finfo(dtype).eps
    np.testing.assert_allclose(np.sum(t * t, -1), 1, atol=eps)
    np.testing.assert_allclose(np.sum(b * b, -1), 1, atol=eps)
    np.testing.assert_allclose(np.sum(t * nn, -1), 0, atol=eps)
    np.testing.assert_allclose(np.cross(t, b), nn, atol=4 * eps)
    # t = ẑ × n / |ẑ × n|: horizontal, along increasing azimuth φ of n.
    phi = np.arctan2(nn[:, 1], nn[:, 0])
    np.testing.assert_allclose(t, np.stack([-np.sin(phi), np.cos(phi), 0 * phi], -1), atol=16 * eps)


def test_local_frame_and_the_poles():
    t, b, _ = _frame((0.0, 0.0, 1.0))
    assert t.tolist() == [1.0, 0.0, 0.0] and b.tolist() == [0.0, 1.0, 0.0]  # φ from +x toward +y
    t, b, _ = _frame((0.0, 0.0, -1.0))
    assert t.tolist() == [1.0, 0.0, 0.0] and b.tolist() == [0.0, -1.0, 0.0]


def test_a_given_tangent_is_made_perpendicular_and_a_parallel_one_falls_back():
    t, b, _ = _frame((0.0, 0.0, 1.0), tangent=(1.0, 1.0, 5.0))
    np.testing.assert_allclose(t, [2**-0.5, 2**-0.5, 0.0], rtol=1e-15)
    t, _, _ = _frame((0.0, 0.0, 1.0), tangent=(0.0, 0.0, 3.0))
    assert t.tolist() == [1.0, 0.0, 0.0]


def test_isotropic_models_ignore_the_tangent_bit_for_bit():
    rng = np.random.default_rng(2)
    n, l, v, tan = (rng.normal(size=(500, 3)) for _ in range(4))  # noqa: E741
    for m in (Lambert(0.7), Phong(0.5, 30)):
        assert np.array_equal(m.eval(n, l, v, tangent=tan), m.eval(n, l, v))
        assert np.array_equal(m.classic(n, l, v, tangent=tan), m.classic(n, l, v))


def test_a_bad_tangent_is_named():
    with pytest.raises(ValueError, match="tangent"):
        Lambert(0.5).eval((0, 0, 1.0), (0, 0, 1.0), (0, 0, 1.0), tangent=(1.0, np.nan, 0.0))
    with pytest.raises(ValueError, match="tangent"):
        Lambert(0.5).eval(np.tile([0, 0, 1.0], (4, 1)), (0, 0, 1.0), (0, 0, 1.0), tangent=np.ones((2, 3)))

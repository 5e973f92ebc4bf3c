"""The engine's frame builders at the normal that points straight down, and a hair off it.

Frisvad's branch-free frame (2012) divides by ``1 + n_z`` and is singular at ``n = −z``; the engine's frames are
Duff et al.'s revision (JCGT 6(1), 2017: the sign of ``n_z`` chooses the pole) or the documented default tangent
``ẑ × n / |ẑ × n|`` (``x̂`` at ±z).  Each must give a finite right-handed orthonormal frame there, in float32 and
float64; Duff's must also be continuous through ``n = −z``.
"""

from __future__ import annotations

import numpy as np
import pytest

from lighting.lights.environment import _basis
from lighting.render.tangents import default_tangents
from lighting.vec import orthonormal_basis

OFFSETS = [(0.0, 0.0), (1e-8, 0.0), (-1e-8, 0.0), (0.0, 1e-8), (0.0, -1e-8), (1e-8, -1e-8)]


def _normals(dtype):
    n = np.array([[x, y, -1.0] for x, y in OFFSETS])
    return (n / np.linalg.norm(n, axis=-1, keepdims=True)).astype(dtype)


def _check_frame(t, b, n, dtype):
    eps = 4 * float(np.finfo(dtype).eps)
    assert t.dtype == b.dtype == dtype and np.all(np.isfinite(t)) and np.all(np.isfinite(b))
    for a, c in ((t, t), (b, b), (n, n)):
        np.testing.assert_allclose(np.sum(a.astype(np.float64) * c, axis=-1), 1.0, atol=eps)
    for a, c in ((t, b), (t, n), (b, n)):
        np.testing.assert_allclose(np.sum(a.astype(np.float64) * c, axis=-1), 0.0, atol=eps)
    np.testing.assert_allclose(np.cross(t.astype(np.float64), b), n, atol=eps)  # right-handed: t × b = n


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_duffs_frame_is_orthonormal_and_continuous_through_the_south_pole(dtype):
    n = _normals(dtype)
    t, b = orthonormal_basis(n)
    _check_frame(t, b, n, dtype)
    # At n = −z: t = x̂, b = −ŷ; 1e-8 off it the frame moves by about 1e-8, not by a turn.
    np.testing.assert_array_equal(t[0], [1.0, 0.0, 0.0])
    np.testing.assert_array_equal(b[0], [0.0, -1.0, 0.0])
    assert np.max(np.abs(t - t[0])) <= 2e-8 and np.max(np.abs(b - b[0])) <= 2e-8
    # The environment's copy of the construction agrees with it (float64 axes).
    for row in n.astype(np.float64):
        te, be = _basis(row)
        np.testing.assert_allclose(te, orthonormal_basis(row)[0], atol=1e-15)
        np.testing.assert_allclose(be, orthonormal_basis(row)[1], atol=1e-15)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_the_default_tangent_is_its_documented_formula_at_the_south_pole(dtype):
    n = _normals(dtype)
    t = default_tangents(n)
    b = np.cross(n.astype(np.float64), t).astype(dtype)
    _check_frame(t, b, n, dtype)
    np.testing.assert_array_equal(t[0], [1.0, 0.0, 0.0])  # x̂ exactly on the axis
    # Off the axis it is ẑ × n / |ẑ × n|: it turns with the direction of the offset (a documented discontinuity;
    # no tangent field is continuous over the whole sphere).
    for row, ti in zip(n[1:].astype(np.float64), t[1:], strict=True):
        z_cross_n = np.array([-row[1], row[0], 0.0])
        np.testing.assert_allclose(ti, z_cross_n / np.linalg.norm(z_cross_n), atol=4 * float(np.finfo(dtype).eps))

"""The lat-long layout's and the environment sampler's fast paths against their readable forms, bit for bit.

``latlong_lookup`` (channel by channel) against ``_latlong_lookup_reference``; ``latlong_angles`` against the
``mod 2π`` it stands for; and the helpers of ``LatLongEnvironment``'s draws and densities
(:mod:`lighting.sampling.environment`) against their forms as first written, spelled out here.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from lighting.lights.environment import LatLongEnvironment
from lighting.lights.latlong import (
    _latlong_lookup_reference,
    _pixel_rows,
    latlong_angles,
    latlong_azimuth,
    latlong_lookup,
)
from lighting.sampling import environment as envmod


def _same(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def _directions(dtype, count=3000, seed=0):
    """Random directions and the layout's edges: both sides of the seam (``y = ±0``), the poles, zero, and
    directions an ulp from the seam and from row and column boundaries."""
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(count, 3))
    edges = [[-1.0, -0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [0.0, 0.0, 0.0],
             [-1.0, -1e-300, 0.2], [-1.0, 1e-300, -0.2], [1.0, 0.0, 0.0], [0.0, -0.0, 1.0],
             [-0.0, -0.0, -1.0]]  # fmt: skip
    d[: len(edges)] = edges
    d[20:40] = [-1.0, 0.0, 0.0] + rng.normal(size=(20, 3)) * 1e-15
    return d.astype(dtype)


def _angles_by_mod(d):
    phi = np.arctan2(d[..., 1], d[..., 0])
    return np.arctan2(np.hypot(d[..., 0], d[..., 1]), d[..., 2]), np.mod(math.pi - phi, 2 * math.pi)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_the_column_angle_is_pi_minus_phi_mod_two_pi_bit_for_bit(dtype):
    d = _directions(dtype)
    for got, want in zip(latlong_angles(d), _angles_by_mod(d), strict=True):
        assert _same(got, want)
    for got, want in zip(latlong_angles(d[1]), _angles_by_mod(d[1]), strict=True):  # one direction: NumPy scalars
        assert type(got) is type(want) and _same(got, want)
    nan = np.array([[np.nan, 0.0, 1.0], [0.0, np.nan, 1.0]], dtype=dtype)
    assert np.all(np.isnan(latlong_angles(nan)[1]))


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("image_dtype", [np.float64, np.float32])
def test_the_lookup_channel_by_channel_is_the_reference_bit_for_bit(dtype, image_dtype):
    rng = np.random.default_rng(1)
    d = _directions(dtype)
    for h, w, channels in ((8, 16, 3), (5, 7, 1), (1, 3, 4), (2, 1, 3), (16, 32, 2)):
        flat = (rng.random((h * w, channels)) ** 3).astype(image_dtype)
        for poles in (None, (rng.random(channels), rng.random(channels))):
            assert _same(latlong_lookup(flat, h, w, d, poles), _latlong_lookup_reference(flat, h, w, d, poles))
            assert _same(latlong_lookup(flat, h, w, d[3], poles), _latlong_lookup_reference(flat, h, w, d[3], poles))
            angles = latlong_angles(d.reshape(50, -1, 3))
            assert _same(latlong_lookup(flat, h, w, None, poles, angles=angles),
                         _latlong_lookup_reference(flat, h, w, None, poles, angles=angles))  # fmt: skip
        # A strided image (one channel of a wider array) reads the same.
        wide = rng.random((h * w, 6)).astype(image_dtype)[:, ::2]
        assert _same(latlong_lookup(wide, h, w, d), _latlong_lookup_reference(wide, h, w, d))


def _images():
    rng = np.random.default_rng(11)
    sparse = rng.random((8, 16, 3)) * (rng.random((8, 16, 1)) > 0.8)
    seam = np.zeros((8, 16, 3))
    seam[5, 15] = 1.0
    rows = rng.random((6, 10, 3))
    rows[2:4] = 0.0
    return {"random 6x12": rng.random((6, 12, 3)) ** 3, "random 5x7": rng.random((5, 7, 3)), "sparse 8x16": sparse,
            "1x1": np.full((1, 1, 3), 2.0), "1x3": rng.random((1, 3, 3)), "seam 8x16": seam, "black rows 6x10": rows,
            "black 4x8": np.zeros((4, 8, 3)), "random 9x40": rng.random((9, 40, 3)) ** 6}  # fmt: skip


def _corner_values_as_written(corners, q, s):
    n = corners.shape[1]
    flat = corners.reshape(-1)
    k = q * n + s
    return flat[k], flat[k + n], flat[k + 1], flat[k + n + 1]


def _cell_direction_as_written(q, s, fz, fa, h, w):
    c = _pixel_rows(2 * h)
    z = np.clip(c[q] + (c[q + 1] - c[q]) * fz, c[q + 1], c[q])
    r = np.sqrt(np.clip((1 - z) * (1 + z), 0.0, None))
    phi = latlong_azimuth((s + fa) * (math.pi / w))
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1)


def _cell_of_as_written(d, h, w):
    theta, a = latlong_angles(d)
    half = math.pi / (2 * h)
    q = np.clip(np.floor(theta * (2 * h / math.pi)).astype(np.int64), 0, 2 * h - 1)
    xa = a * (w / math.pi)
    s = np.clip(np.floor(xa).astype(np.int64), 0, 2 * w - 1)
    tq = q * half
    fz = np.sin(0.5 * (theta + tq)) * np.sin(0.5 * (theta - tq)) / (np.sin(tq + 0.5 * half) * math.sin(0.5 * half))
    return q, s, np.clip(fz, 0.0, 1.0), np.clip(xa - s, 0.0, 1.0)


@pytest.mark.parametrize("name", list(_images()))
def test_the_sampler_helpers_are_their_readable_forms_bit_for_bit(name):
    env = LatLongEnvironment(_images()[name])
    h, w = env.height, env.width
    rng = np.random.default_rng(2)
    u = rng.random((4000, 2))
    u[:40], u[40:80] = 0.0, 1.0
    u[80:120, 1] = env._cols_cdf[rng.integers(0, 2 * h, 40), rng.integers(0, 2 * w, 40)]  # on a table's entries
    q, uz = envmod._pick(env._rows_cdf, u[:, 0])
    s, ua = envmod._pick_in_rows(env._cols_cdf, env._last_col, q, u[:, 1], env._cols_search)
    s_ref, ua_ref = envmod._pick_in_rows_reference(env._cols_cdf, env._last_col, q, u[:, 1])
    assert _same(s, s_ref) and _same(ua, ua_ref)
    for got in envmod._pick_in_rows(env._cols_cdf, env._last_col, q, u[:, 1]), (s, ua):  # the table made there
        assert _same(got[0], s_ref) and _same(got[1], ua_ref)
    one = envmod._pick(env._rows_cdf, u[7, 0])[0]  # a single draw: NumPy scalars, as the readable form gives
    for got, want in zip(envmod._pick_in_rows(env._cols_cdf, env._last_col, one, u[7, 1], env._cols_search),
                         envmod._pick_in_rows_reference(env._cols_cdf, env._last_col, one, u[7, 1]),
                         strict=True):  # fmt: skip
        assert type(got) is type(want) and _same(got, want)
    corners = envmod._corner_values(env._corners, q, s)
    for got, want in zip(corners, _corner_values_as_written(env._corners, q, s), strict=True):
        assert _same(got, want)
    fz, fa = rng.random(q.shape), rng.random(q.shape)
    fz[:10], fa[:10], fz[10:20], fa[10:20] = 0.0, 0.0, 1.0, 1.0
    assert _same(envmod._cell_direction(q, s, fz, fa, h, w), _cell_direction_as_written(q, s, fz, fa, h, w))
    d = np.concatenate([_cell_direction_as_written(q, s, fz, fa, h, w), _directions(np.float64)])
    d /= np.where(np.any(d != 0, axis=-1), np.linalg.norm(d, axis=-1), 1.0)[:, None]
    for cell in (envmod._cell_of(d, h, w, None, env._row_scales), envmod._cell_of(d, h, w)):
        for got, want in zip(cell, _cell_of_as_written(d, h, w), strict=True):
            assert _same(got, want)


def test_the_search_table_is_padded_to_a_power_of_two_with_infinities():
    cdf = np.linspace(0.0, 1.0, 12).reshape(2, 6)
    table = envmod._search_table(cdf)
    assert table.shape == (2, 8) and np.array_equal(table[:, :6], cdf) and np.all(table[:, 6:] == np.inf)
    square = np.ones((3, 8))
    assert envmod._search_table(square) is square
    assert envmod._search_table(np.ones((2, 1))).shape == (2, 1)

"""The grid of normals of the dominant-light method (lighting.integrate._normalgrid): geometry, interpolation bounds,
the furnace and when it is used."""

import math

import numpy as np
import pytest

from lighting.integrate._normalgrid import (
    GRID_SHARE,
    MAX_SPACING,
    MIN_COLUMNS,
    NormalGrid,
    grid_points,
    grid_spacing,
)
from lighting.integrate.dominant import dominant_radiance
from lighting.integrate.ibl import ALBEDO_ANGLES, lobe_albedo
from lighting.integrate.prefilter import prefilter_environment
from lighting.lights.environment import ConstantEnvironment
from lighting.models.brdf import CookTorrance, Lambert

VIEW = np.array([0.48, -0.6, 0.64])


def _facing(view, count, seed=0):
    """``count`` random unit normals facing ``view`` (``n·v >= 0``), grazing ones included."""
    rng = np.random.default_rng(seed)
    n = rng.normal(size=(count, 3))
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    n = np.where((n @ view < 0)[:, None], -n, n)
    return n


@pytest.fixture(scope="module")
def daylight():
    """The daylight sky as a 64-row map, prefiltered (its dominant lights and residual made once, for every test)."""
    from lighting.validation.accuracy import ibl_environment

    return prefilter_environment(ibl_environment("daylight", 64))


def test_the_grid_is_polar_about_the_view_from_the_view_to_the_silhouette():
    g = NormalGrid(VIEW, math.radians(2.0))
    assert g.normals.shape == (g.size, 3) and g.size == g.columns.sum() == grid_points(g.spacing)
    assert g.columns.shape == (g.rows + 1,) and g.columns[0] == 1 and g.columns[1:].min() >= MIN_COLUMNS
    np.testing.assert_array_equal(g.starts, np.cumsum(g.columns) - g.columns)
    np.testing.assert_allclose(np.linalg.norm(g.normals, axis=-1), 1.0, atol=1e-15)
    np.testing.assert_allclose(g.normals[0], VIEW, atol=1e-15)
    silhouette = g.normals[g.starts[-1] :]
    assert len(silhouette) == g.columns[-1]
    np.testing.assert_allclose(silhouette @ VIEW, 0.0, atol=1e-15)
    # Rings evenly in θ (whole rings to π/2, no wider than asked), each ring's points evenly in ψ.
    ring_of = np.repeat(np.arange(g.rows + 1), g.columns)
    theta = np.arccos(np.clip(g.normals @ VIEW, -1, 1))
    np.testing.assert_allclose(theta, ring_of * g.d_theta, atol=1e-7)
    assert g.d_theta <= math.radians(2.0) and g.rows * g.d_theta == pytest.approx(math.pi / 2)
    for i in (1, g.rows // 3, g.rows):
        ring = g.normals[g.starts[i] : g.starts[i] + g.columns[i]]
        step = np.sum(ring * np.roll(ring, -1, axis=0), -1)
        np.testing.assert_allclose(step, step[0], atol=1e-14)
        # The turn between neighbours is 2π/c_i about the view: the chord of that angle on a circle of radius sin θ.
        chord = 2 * math.sin(i * g.d_theta) * math.sin(math.pi / g.columns[i])
        np.testing.assert_allclose(np.linalg.norm(ring - np.roll(ring, -1, axis=0), axis=-1), chord, rtol=1e-12)
    # The fewest points with the azimuth's error within the polar angle's: Δψ_i² sin θ_i <= Δθ², and one point
    # fewer on any ring (above the floor of MIN_COLUMNS) would break it.
    sin_t = np.sin(np.arange(1, g.rows + 1) * g.d_theta)
    d_psi = 2 * math.pi / g.columns[1:]
    assert np.all(d_psi**2 * sin_t <= g.d_theta**2 * (1 + 1e-12))
    fewer = g.columns[1:] - 1
    assert np.all((fewer < MIN_COLUMNS) | ((2 * math.pi / fewer) ** 2 * sin_t > g.d_theta**2))
    # The silhouette's columns evenly spaced on every ring would cost about π/2 ÷ ∫₀^{π/2} √(sin θ) dθ = 1.31 times as
    # many points.
    assert (g.rows + 1) * g.columns[-1] / g.size == pytest.approx(1.31, abs=0.02)


def test_grid_spacing_is_a_sixth_of_the_lobe_at_most_the_cap():
    assert grid_spacing(0.06) == pytest.approx(0.01)
    assert grid_spacing(0.6) == MAX_SPACING and grid_spacing(math.inf) == MAX_SPACING


def test_interpolation_is_exact_along_theta_and_within_the_bilinear_bound():
    g = NormalGrid(VIEW, math.radians(3.0))
    n = _facing(VIEW, 5000).astype(np.float32)
    theta = np.arccos(np.clip(n @ VIEW, 0, 1))
    # A function linear in θ is read exactly (float32 arithmetic).
    at_grid = (np.repeat(np.arange(g.rows + 1), g.columns) * g.d_theta)[:, None]
    np.testing.assert_allclose(g.interpolate(at_grid, n)[:, 0], theta, atol=2e-6)
    # f(n) = exp(n·d): linear in ψ on each ring and in θ between them errs by at most
    # (Δθ² max|f_θθ| + max_i Δψ_i² max|f_ψψ on ring i|)/8, with |f_θθ| ≤ 2e and |f_ψψ| ≤ 2e sin θ_i (|∂²n/∂θ²| = 1,
    # |∂n/∂ψ| = |∂²n/∂ψ²| = sin θ, |n·d| ≤ 1: f'' = (n''·d + (n'·d)²) f).
    d = np.array([0.2, 0.9, -0.3])
    d /= np.linalg.norm(d)
    values = np.exp(g.normals @ d)[..., None]
    got = g.interpolate(values, n)[:, 0]
    ring_psi = np.max((2 * math.pi / g.columns[1:]) ** 2 * np.sin(np.arange(1, g.rows + 1) * g.d_theta))
    bound = (g.d_theta**2 + ring_psi) * 2 * math.e / 8
    err = np.abs(got - np.exp(n.astype(np.float64) @ d))
    assert err.max() <= bound + 1e-5, (err.max(), bound)
    assert err.max() > bound / 20  # the bound is near what is met: the test would see a coarser read


@pytest.mark.parametrize("view", [VIEW, np.array([0.0, 0.0, 1.0]), np.array([0.0, 0.0, -1.0]), np.array([1.0, 0, 0])])
def test_every_read_weighs_its_four_taps_to_one_at_the_view_the_silhouette_and_across_the_seam(view):
    # Values that differ from point to point and a constant: the constant is read exactly wherever the normal is
    # (the view itself, the silhouette, ψ just below 2π, where the first column follows the last), and no read leaves
    # the values' range.
    g = NormalGrid(view, math.radians(2.5))
    e1, e2 = g.e1, g.e2
    psi = np.array([0.0, 1e-7, math.pi, 2 * math.pi - 1e-7, -1e-9, 1.0])
    theta = np.array([0.0, 1e-7, g.d_theta, math.pi / 4, math.pi / 2 - 1e-7, math.pi / 2])
    tt, pp = (a.ravel() for a in np.meshgrid(theta, psi))
    n = np.sin(tt)[:, None] * (np.cos(pp)[:, None] * e1 + np.sin(pp)[:, None] * e2) + np.cos(tt)[:, None] * view
    n = np.concatenate([n, _facing(view, 2000, seed=5)]).astype(np.float32)
    values = np.stack([np.full(g.size, 0.7), np.random.default_rng(6).random(g.size)], axis=-1)
    got = g.interpolate(values, n)
    np.testing.assert_allclose(got[:, 0], 0.7, rtol=1e-6)
    assert got[:, 1].min() >= values[:, 1].min() - 1e-6 and got[:, 1].max() <= values[:, 1].max() + 1e-6
    # At a grid point itself the read is that point's value, within its float32 coordinates (measured 2.1e-5 of a
    # unit step between neighbours).
    at = g.interpolate(values, g.normals.astype(np.float32))[:, 1]
    np.testing.assert_allclose(at, values[:, 1], atol=1e-4)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_the_white_furnace_on_the_grid_gives_each_part_its_albedo(dtype):
    # A uniform sky: every grid point holds L (E/π and every lobe's normalized mean), so the pixels read L exactly
    # and each part reflects its albedo times L, as pixel by pixel.
    pre = prefilter_environment(ConstantEnvironment(1.5), height=32)
    n = _facing(VIEW, 400, seed=2)
    v = np.broadcast_to(VIEW, n.shape)
    ggx = CookTorrance(1.0, 0.3, 1.0, ndf="ggx", fresnel="none")
    out = dominant_radiance(Lambert(0.6) + ggx, pre, n.astype(dtype), v.astype(dtype), split_terms=True,
                            normal_grid=True)  # fmt: skip
    assert out["diffuse"].dtype == dtype
    lit = n @ VIEW > 0
    np.testing.assert_allclose(out["diffuse"][lit], 0.9, rtol=1e-5)
    rho = np.interp(np.arccos(np.clip(n @ VIEW, 0, 1)), ALBEDO_ANGLES, lobe_albedo(ggx)[:, 0])
    np.testing.assert_allclose(out["specular"][lit, 0], 1.5 * rho[lit], rtol=2e-5)


def test_the_grid_is_used_for_one_view_and_enough_pixels_only(daylight):
    from lighting.validation.accuracy import ibl_sphere

    pre = daylight
    m = Lambert(0.4) + CookTorrance(1.0, 0.4, 1.0, ndf="ggx", fresnel="none")
    _, n, v = ibl_sphere(200)  # 26,932 pixels: more than four times the grid's 4,041 points
    n, v = n.astype(np.float32), v.astype(np.float32)
    assert NormalGrid(v[0], grid_spacing(math.inf)).size <= GRID_SHARE * n.shape[0]
    auto, on, off = (dominant_radiance(m, pre, n, v, normal_grid=g) for g in (None, True, False))
    np.testing.assert_array_equal(auto, on)
    assert not np.array_equal(on, off)
    # The grid reads what the pixels compute within the interpolation's error on this smooth sky.
    rel = np.max(np.abs(on - off), -1) / np.max(off, -1)
    assert np.median(rel) < 1e-3 and np.percentile(rel, 95) < 5e-3, (np.median(rel), np.percentile(rel, 95))
    # Too few pixels for the grid to pay: pixel by pixel.
    np.testing.assert_array_equal(dominant_radiance(m, pre, n[:2000], v[:2000]), off[:2000])
    # Views that differ: pixel by pixel, and the grid asked for is refused in one line.
    turned = v.copy()
    turned[0] = n[0]
    np.testing.assert_array_equal(dominant_radiance(m, pre, n, turned)[1:], off[1:])
    with pytest.raises(ValueError, match="normal_grid=True needs every pixel to share one view direction"):
        dominant_radiance(m, pre, n, turned, normal_grid=True)
    with pytest.raises(TypeError, match="normal_grid"):
        dominant_radiance(m, pre, n, v, normal_grid="yes")


def test_a_view_and_spacing_met_again_reuse_their_grid_and_its_irradiance(daylight):
    # An explorer's sphere re-shaded under a moving light: the same view makes the same grid once, and the residual's
    # irradiance at its points once per environment; another view makes its own. The values are those made anew.
    from lighting.integrate.dominant import _grid_for, dominant_environment

    view = np.array([[0.0, 0.0, 1.0]])
    first, again = (_grid_for([grid_spacing(0.5)], True, 10, view) for _ in range(2))
    assert again is first and not first.normals.flags.writeable
    other = _grid_for([grid_spacing(0.5)], True, 10, np.array([[0.0, 0.6, 0.8]]))
    assert other is not first
    np.testing.assert_array_equal(other.normals, NormalGrid((0.0, 0.6, 0.8), grid_spacing(0.5)).normals)
    dom = dominant_environment(daylight)
    e = dom.grid_irradiance(first)
    assert dom.grid_irradiance(first) is e and not e.flags.writeable
    np.testing.assert_array_equal(e, dom.irradiance.radiance(first.normals) / math.pi)
    assert dom.grid_irradiance(other).shape == (other.size, 3)

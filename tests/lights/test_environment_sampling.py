"""Importance sampling of lat-long environment images: the density's laws and its error under a one-pixel sun.

The sampler (``LatLongEnvironment._sample``/``_pdf``) picks a half-pixel cell with probability its integral of
the bilinear lookup, then a direction bilinear in ``(cos θ, a)`` between the lookup's values at the cell's
corners.  Each test checks a value: the cell masses against the lookup integrated by quadrature, χ² of the
samples over pixels and inside cells against probabilities computed here from the lookup, ``pdf`` of the
samples, the mass of the density, its support against the lookup's, and the Monte-Carlo reference's error
under a small sun against an exact irradiance.
"""

from __future__ import annotations

import math

import chi2  # tests/chi2.py: the χ² p-value and the Šidák level of a family of χ² tests
import numpy as np
import pytest

from lighting.lights.environment import LatLongEnvironment, latlong_angles, latlong_azimuth, latlong_lookup
from lighting.sampling import environment as envmod


def _one_pixel(h, w, i, j, value=1.0):
    img = np.zeros((h, w, 3))
    img[i, j] = value
    return img


def _images():
    """Named test images: random, sparse, odd sizes, one pixel (inside, at the seam, at both poles), black."""
    rng = np.random.default_rng(11)
    sparse = rng.random((8, 16, 3)) * (rng.random((8, 16, 1)) > 0.8)
    return {
        "random 6x12": rng.random((6, 12, 3)) ** 3,
        "random 5x7": rng.random((5, 7, 3)) * np.array([1.0, 0.2, 3.0]),
        "sparse 8x16": sparse,
        "1x1": np.full((1, 1, 3), 2.0),
        "1x3": rng.random((1, 3, 3)),
        "pixel 8x16": _one_pixel(8, 16, 3, 6),
        "seam 8x16": _one_pixel(8, 16, 5, 15),
        "zenith 8x16": _one_pixel(8, 16, 0, 0),
        "nadir 8x16": _one_pixel(8, 16, 7, 9),
        "black 4x8": np.zeros((4, 8, 3)),
    }


IMAGES = _images()


def _lum(img):
    return img.mean(axis=2)


def _cell_probabilities(img):
    """The sampler's cell probabilities computed from the lookup itself (uniform over the sphere if black)."""
    h, w = img.shape[:2]
    mass = envmod._cell_masses_reference(_lum(img))
    if not mass.sum() > 0:
        mass = envmod._cell_masses_reference(np.ones((h, w)))
    return mass / mass.sum()


def _chi2_p(counts, expected):
    """χ² p-value, the sparsest bins pooled into one of at least 50 expected; no count where none is expected."""
    assert np.sum(counts[expected == 0]) == 0, "samples where the density is zero"
    order = np.argsort(expected)
    e, c = expected[order], counts[order]
    small = np.cumsum(e) < 50
    e = np.r_[e[small].sum(), e[~small]]
    c = np.r_[c[small].sum(), c[~small]]
    keep = e > 0
    if keep.sum() < 2:
        return 1.0
    return float(chi2.chi2_sf(np.sum((c[keep] - e[keep]) ** 2 / e[keep]), keep.sum() - 1))


# ---------------------------------------------------------------------------------------------- the masses
@pytest.mark.parametrize("name", list(IMAGES))
def test_cell_masses_are_the_lookup_integrated_over_each_cell(name):
    lum = _lum(IMAGES[name])
    fast, reference = envmod._cell_masses(lum), envmod._cell_masses_reference(lum)
    np.testing.assert_allclose(fast, reference, rtol=1e-12, atol=1e-15 * max(reference.max(), 1e-300))
    # A constant image's masses are the cells' solid angles (4π in all).
    ones = envmod._cell_masses(np.ones_like(lum))
    h, w = lum.shape
    np.testing.assert_allclose(ones, np.broadcast_to(envmod._cell_solid_angles(h, w)[:, None], ones.shape), rtol=1e-13)
    assert ones.sum() == pytest.approx(4 * math.pi, rel=1e-14)


def test_a_pixel_s_value_counts_three_quarters_in_its_column_and_an_eighth_in_each_neighbour():
    lum = _lum(_one_pixel(8, 16, 3, 6))
    per_column = envmod._cell_masses(lum).reshape(16, 16, 2).sum(axis=(0, 2))
    np.testing.assert_allclose(per_column[5:8] / per_column.sum(), [1 / 8, 3 / 4, 1 / 8], rtol=1e-13)
    assert np.all(per_column[:5] == 0) and np.all(per_column[8:] == 0)
    # Across the seam: column 15's neighbours are 14 and 0.
    seam = envmod._cell_masses(_lum(_one_pixel(8, 16, 3, 15))).reshape(16, 16, 2).sum(axis=(0, 2))
    np.testing.assert_allclose(seam[[14, 15, 0]] / seam.sum(), [1 / 8, 3 / 4, 1 / 8], rtol=1e-13)


def test_cell_corners_are_the_lookup_at_the_corners():
    for name in ("random 5x7", "seam 8x16", "zenith 8x16", "1x3"):
        lum = _lum(IMAGES[name])
        h, w = lum.shape
        theta = (np.arange(2 * h + 1) * (math.pi / (2 * h)))[:, None]
        a = (np.arange(2 * w + 1) * (math.pi / w))[None, :]
        t, aa = np.broadcast_arrays(theta, a)
        looked = latlong_lookup(lum.reshape(-1, 1), h, w, None, angles=(t, np.mod(aa, 2 * math.pi)))[..., 0]
        np.testing.assert_allclose(envmod._cell_corners(lum), looked, rtol=1e-12, atol=1e-14, err_msg=name)


def test_bisection_in_rows_is_searchsorted_per_row():
    env = LatLongEnvironment(IMAGES["sparse 8x16"])
    rng = np.random.default_rng(3)
    rows = rng.integers(0, 16, 4000)
    u = rng.random(4000)
    u[:50], u[50:100] = 0.0, 1.0
    k, _ = envmod._pick_in_rows(env._cols_cdf, env._last_col, rows, u)
    readable = [
        min(np.searchsorted(env._cols_cdf[r], x, side="right"), env._last_col[r]) for r, x in zip(rows, u, strict=True)
    ]
    np.testing.assert_array_equal(k, readable)
    # Never a cell of zero probability, even at u = 0 and u = 1.
    assert np.all(env._cell_probabilities()[rows, k] > 0)


# ---------------------------------------------------------------------------------------------- χ²
def test_chi_square_over_pixels_against_the_lookup_s_integrals():
    names = list(IMAGES)
    level = chi2.sidak(0.01, len(names))
    n = 100_000
    for k, name in enumerate(names):
        img = IMAGES[name]
        h, w = img.shape[:2]
        env = LatLongEnvironment(img)
        d, _ = env.sample(np.random.default_rng(100 + k).random((n, 2)))
        theta, a = latlong_angles(d)
        i = np.minimum((theta * (h / math.pi)).astype(int), h - 1)
        j = np.minimum((a * (w / (2 * math.pi))).astype(int), w - 1)
        counts = np.bincount(i * w + j, minlength=h * w).astype(float)
        expected = n * _cell_probabilities(img).reshape(h, 2, w, 2).sum(axis=(1, 3)).ravel()
        np.testing.assert_allclose(env._pixel_probabilities().ravel(), expected / n, rtol=1e-12, atol=1e-300)
        assert _chi2_p(counts, expected) > level, name


def test_chi_square_inside_cells_against_the_corner_bilinear():
    # 4 x 4 sub-cells per cell, in cos θ and in a; the density is bilinear in both there, so a sub-cell's
    # share of its cell is the bilinear of the lookup's corner values at the sub-cell's middle over their mean.
    cases = {"random 4x8": np.random.default_rng(5).random((4, 8, 3)), "pixel 4x8": _one_pixel(4, 8, 1, 7),
             "zenith 3x6": _one_pixel(3, 6, 0, 2), "black 3x6": np.zeros((3, 6, 3))}  # fmt: skip
    level = chi2.sidak(0.01, len(cases))
    n, k = 300_000, 4
    for m, (name, img) in enumerate(cases.items()):
        h, w = img.shape[:2]
        env = LatLongEnvironment(img)
        d, _ = env.sample(np.random.default_rng(200 + m).random((n, 2)))
        q, s, fz, fa = envmod._cell_of(d, h, w)
        sub = np.minimum((fz * k).astype(int), k - 1) * k + np.minimum((fa * k).astype(int), k - 1)
        counts = np.bincount((q * 2 * w + s) * k * k + sub, minlength=4 * h * w * k * k).astype(float)
        lum = _lum(img) if img.any() else np.ones((h, w))
        theta = (np.arange(2 * h + 1) * (math.pi / (2 * h)))[:, None]
        a = np.mod(np.arange(2 * w + 1) * (math.pi / w), 2 * math.pi)[None, :]
        corners = latlong_lookup(lum.reshape(-1, 1), h, w, None, angles=np.broadcast_arrays(theta, a))[..., 0]
        v00, v10, v01, v11 = corners[:-1, :-1], corners[1:, :-1], corners[:-1, 1:], corners[1:, 1:]
        x = (np.arange(k) + 0.5) / k
        bz, ba = x[:, None], x[None, :]
        shape = [(v00[..., None, None] * (1 - ba) + v01[..., None, None] * ba) * (1 - bz)
                 + (v10[..., None, None] * (1 - ba) + v11[..., None, None] * ba) * bz]  # fmt: skip
        mean = (v00 + v10 + v01 + v11)[..., None, None] / 4
        share = np.divide(shape[0], mean, out=np.zeros_like(shape[0]), where=mean > 0) / (k * k)
        expected = n * (_cell_probabilities(img)[..., None, None] * share).ravel()
        assert expected.sum() == pytest.approx(n, rel=1e-12)
        assert _chi2_p(counts, expected) > level, name


# ---------------------------------------------------------------------------------------------- pdf and mass
@pytest.mark.parametrize("name", list(IMAGES))
def test_pdf_of_the_samples_is_the_returned_density_and_the_density_has_mass_one(name):
    img = IMAGES[name]
    h, w = img.shape[:2]
    env = LatLongEnvironment(img)
    d, p = env.sample(np.random.default_rng(7).random((20_000, 2)))
    np.testing.assert_allclose(np.linalg.norm(d, axis=-1), 1.0, atol=1e-12)
    assert np.all(p > 0)
    np.testing.assert_allclose(env.pdf(d), p, rtol=1e-12)
    # Exactly: the cells' probabilities sum to one; per cell, 2 x 2 Gauss–Legendre in (cos θ, a) is exact
    # for the bilinear density.
    assert env._cell_probabilities().sum() == pytest.approx(1.0, rel=1e-13)
    x, wx = np.polynomial.legendre.leggauss(2)
    c = np.cos(np.linspace(0.0, math.pi, 2 * h + 1))
    z = (0.5 * (c[:-1, None] + c[1:, None]) + 0.5 * (c[1:, None] - c[:-1, None]) * x).ravel()
    wz = (0.5 * (c[:-1, None] - c[1:, None]) * wx).ravel()
    a = ((np.arange(2 * w)[:, None] + 0.5 + 0.5 * x) * (math.pi / w)).ravel()
    wa = np.tile(wx * 0.5 * math.pi / w, 2 * w)
    r = np.sqrt(1 - z * z)[:, None]
    phi = latlong_azimuth(a)[None, :]
    grid = np.stack(np.broadcast_arrays(r * np.cos(phi), r * np.sin(phi), z[:, None]), axis=-1)
    assert np.sum(env.pdf(grid) * wz[:, None] * wa[None, :]) == pytest.approx(1.0, rel=1e-12)
    # And a midpoint rule on a grid that ignores the cells.
    zz = 1 - (np.arange(800) + 0.5) / 400
    ph = (np.arange(1600) + 0.5) * (2 * math.pi / 1600)
    rr = np.sqrt(1 - zz * zz)[:, None]
    fine = np.stack(np.broadcast_arrays(rr * np.cos(ph), rr * np.sin(ph), zz[:, None]), axis=-1)
    assert np.sum(env.pdf(fine)) * (2 / 800) * (2 * math.pi / 1600) == pytest.approx(1.0, abs=2e-3)


def test_a_black_image_is_sampled_uniformly():
    env = LatLongEnvironment(np.zeros((4, 8, 3)))
    d, p = env.sample(np.random.default_rng(8).random((1000, 2)))
    np.testing.assert_allclose(p, 1 / (4 * math.pi), rtol=1e-12)
    np.testing.assert_allclose(env.pdf(np.random.default_rng(9).normal(size=(100, 3))), 1 / (4 * math.pi), rtol=1e-12)


# ---------------------------------------------------------------------------------------------- support
def _near(h, w, i, j, count, seed):
    """Random directions within two pixels of pixel (i, j)'s centre (and across the pole or seam from it)."""
    rng = np.random.default_rng(seed)
    theta = np.clip((i + 0.5 + rng.uniform(-2, 2, count)) * (math.pi / h), 0.0, math.pi)
    a = (j + 0.5 + rng.uniform(-2, 2, count)) * (2 * math.pi / w)
    phi = latlong_azimuth(a)
    return np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], axis=-1)


@pytest.mark.parametrize("name", ["sparse 8x16", "pixel 8x16", "seam 8x16", "zenith 8x16", "nadir 8x16", "random 5x7"])
def test_the_density_is_positive_exactly_where_the_lookup_returns_light(name):
    img = IMAGES[name]
    h, w = img.shape[:2]
    env = LatLongEnvironment(img)
    d = np.random.default_rng(12).normal(size=(20_000, 3))
    lit = np.argwhere(img.max(axis=2) > 0)
    d = np.concatenate([d] + [_near(h, w, i, j, 4000, 13 + k) for k, (i, j) in enumerate(lit[:4])])
    light = env.radiance(d).max(axis=-1) > 0
    assert light.sum() > 1000
    np.testing.assert_array_equal(env.pdf(d) > 0, light)


# ---------------------------------------------------------------------------------------------- the error
H, W, SUN, SUN_RADIANCE = 64, 128, (20, 40), 3000.0
COLOUR = np.array([1.0, 0.9, 0.8])


def _sky_rows(h):
    """A dusk gradient, one value per row: 0.35 at the zenith down to 0.05 at the horizon and below."""
    theta = (np.arange(h) + 0.5) * (math.pi / h)
    return 0.05 + 0.3 * np.maximum(np.cos(theta), 0.0)


def _sunny_image():
    img = np.repeat(_sky_rows(H)[:, None], W, axis=1)
    img[SUN] = SUN_RADIANCE
    return img[..., None] * COLOUR


def _ring(theta, n):
    """``∫ max(n·l, 0) da`` over the ring of directions ``l`` at polar angle ``θ`` (closed form)."""
    big_a, big_b = np.cos(theta) * n[2], np.sin(theta) * math.hypot(n[0], n[1])
    cut = big_b > np.abs(big_a)
    r = np.where(cut, -big_a / np.where(cut, big_b, 1.0), 0.0)
    psi = np.arccos(np.clip(r, -1.0, 1.0))
    return np.where(cut, 2 * (big_a * psi + big_b * np.sqrt(1 - r * r)), 2 * math.pi * np.maximum(big_a, 0.0))


def _exact_irradiance(n):
    """``∫ lookup · max(n·l, 0) dω`` of the sunny image, per unit of ``COLOUR``, exact to rounding.

    The sky's rows are constant, so its lookup depends on θ alone: Gauss–Legendre in θ between the kinks (row
    centres, the horizon's tangent points) of the ring integral.  The sun adds its excess over the sky times
    the hat of its pixel: Gauss–Legendre on the hat's four bilinear patches.
    """
    x, wx = np.polynomial.legendre.leggauss(24)
    tn = math.acos(float(np.clip(n[2], -1, 1)))
    kinks = np.r_[0.0, math.pi, (np.arange(H) + 0.5) * (math.pi / H), abs(math.pi / 2 - tn), math.pi / 2 + tn]
    b = np.unique(np.clip(kinks, 0.0, math.pi))
    theta = (b[:-1, None] + (b[1:, None] - b[:-1, None]) * (x + 1) / 2).ravel()
    weight = ((b[1:, None] - b[:-1, None]) * wx / 2).ravel()
    sky = latlong_lookup(_sky_rows(H).repeat(W)[:, None], H, W, None, angles=(theta, np.zeros_like(theta)))[:, 0]
    total = float(np.sum(weight * sky * np.sin(theta) * _ring(theta, n)))
    x, wx = np.polynomial.legendre.leggauss(48)
    x, wx = (x + 1) / 2, wx / 2
    dt, da = math.pi / H, 2 * math.pi / W
    tc, ac = (SUN[0] + 0.5) * dt, (SUN[1] + 0.5) * da
    for t0 in (tc - dt, tc):
        for a0 in (ac - da, ac):
            t, a = np.meshgrid(t0 + dt * x, a0 + da * x, indexing="ij")
            hat = (1 - np.abs(t - tc) / dt) * (1 - np.abs(a - ac) / da)
            phi = latlong_azimuth(a)
            ln = np.sin(t) * np.cos(phi) * n[0] + np.sin(t) * np.sin(phi) * n[1] + np.cos(t) * n[2]
            f = hat * np.maximum(ln, 0) * np.sin(t)
            total += (SUN_RADIANCE - _sky_rows(H)[SUN[0]]) * float(np.einsum("i,j,ij->", wx * dt, wx * da, f))
    return total


class _DilatedPixels(LatLongEnvironment):
    """The sampler this one replaced, for comparison: pixels with probability their 3 x 3 neighbourhood's
    largest mean channel value times their solid angle, uniform inside."""

    _sampling_tables = frozenset({"_prob", "_cdf", "_dens"})

    def _build_sampling(self):
        lum = _lum(self.image)
        h, w = lum.shape
        padded = np.pad(np.pad(lum, ((0, 0), (1, 1)), mode="wrap"), ((1, 1), (0, 0)), mode="edge")
        weight = np.max([padded[a : a + h, b : b + w] for a in range(3) for b in range(3)], axis=0)
        prob = weight * self.solid_angles()
        self._prob = (prob / prob.sum()).ravel()
        self._cdf = np.cumsum(self._prob)
        self._cdf[-1] = 1.0
        self._dens = (self._prob.reshape(h, w) / self.solid_angles()).ravel()

    def _sample(self, u):
        h, w = self.height, self.width
        k = np.minimum(np.searchsorted(self._cdf, u[..., 0], side="right"), h * w - 1)
        prev = np.where(k > 0, self._cdf[np.maximum(k - 1, 0)], 0.0)
        v = np.clip((u[..., 0] - prev) / self._prob[k], 0.0, 1.0)
        i, j = np.divmod(k, w)
        c = np.cos(np.linspace(0.0, math.pi, h + 1))
        z = c[i] + (c[i + 1] - c[i]) * v
        r = np.sqrt(np.clip((1 - z) * (1 + z), 0.0, None))
        phi = latlong_azimuth((j + u[..., 1]) * (2 * math.pi / w))
        return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1), self._dens[k]

    def _pdf(self, d):
        theta, a = latlong_angles(d)
        i = np.clip(np.floor(theta * (self.height / math.pi)).astype(np.int64), 0, self.height - 1)
        j = np.clip(np.floor(a * (self.width / (2 * math.pi))).astype(np.int64), 0, self.width - 1)
        return self._dens[i * self.width + j]


def _sphere(px=24):
    """Normals of a small sphere seen orthographically from ``v`` (its terminator in view), and ``v``."""
    sun = np.array(envmod._cell_direction(2 * SUN[0] + 1, 2 * SUN[1] + 1, 0.0, 0.0, H, W))
    v = np.array([sun[0], -sun[1], 0.3])
    v /= np.linalg.norm(v)
    t = np.cross([0.0, 0.0, 1.0], v)
    t /= np.linalg.norm(t)
    b = np.cross(v, t)
    g = (np.arange(px) + 0.5) / px * 2 - 1
    x, y = (c[np.add.outer(g * g, g * g) < 1] for c in np.meshgrid(g, g, indexing="ij"))
    return x[:, None] * t + y[:, None] * b + np.sqrt(1 - x * x - y * y)[:, None] * v, v, sun


def test_the_sampling_tables_are_made_on_first_use_and_the_same_as_made_before():
    # A map only looked up or prefiltered (the dominant lights' residual) holds no sampling tables; the first
    # sample makes them, and a map made afresh draws and weighs the same directions.
    img = _sunny_image()
    env = LatLongEnvironment(img)
    env.radiance(np.array([[0.0, 0.0, 1.0]]))
    assert not {"_rows_cdf", "_density", "_corners"} & set(vars(env))
    u = np.random.default_rng(3).random((500, 2))
    d, p = env.sample(u)
    assert {"_rows_cdf", "_cols_cdf", "_last_col", "_density", "_corners"} <= set(vars(env))
    other = LatLongEnvironment(img)
    np.testing.assert_allclose(other.pdf(d), p, rtol=1e-12)  # tables made by pdf first: the same density
    d2, p2 = other.sample(u)
    assert np.array_equal(d2, d) and np.array_equal(p2, p)
    with pytest.raises(AttributeError, match="no attribute '_nothing'"):
        env._nothing  # noqa: B018


def test_radiance_and_density_read_together_are_each_read_alone_bit_for_bit():
    # Multiple importance sampling asks the environment for both at the directions a BRDF drew; a lat-long map
    # finds both from one set of angles, a turned one turns the directions once. A subclass with its own density
    # (the replaced sampler above) is asked for its own.
    from lighting.lights.envfiles import TransformedEnvironment
    from lighting.lights.environment import ConstantEnvironment, FunctionEnvironment

    img = _sunny_image()
    d = np.random.default_rng(5).normal(size=(400, 3))
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    envs = [LatLongEnvironment(img), _DilatedPixels(img), ConstantEnvironment(0.5),
            FunctionEnvironment(lambda x: 1.0 + x[..., 2]), TransformedEnvironment(LatLongEnvironment(img), 2.0, 40.0),
            TransformedEnvironment(_DilatedPixels(img), 0.5, -15.0)]  # fmt: skip
    for env in envs:
        radiance, density = env._radiance_and_pdf(d)
        assert np.array_equal(radiance, env._radiance(d)) and np.array_equal(density, env._pdf(d)), env
    dilated = _DilatedPixels(img)
    assert not np.array_equal(dilated._radiance_and_pdf(d)[1], LatLongEnvironment(img)._pdf(d))

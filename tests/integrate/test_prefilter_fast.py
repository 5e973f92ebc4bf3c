"""The fast row convolution of the prefilter against its readable reference, :func:`_convolve_rows`.

The fast path evaluates one row pair in four (the kernel is symmetric in the two rows and under the mirror
θ → π − θ), sums over source rows with batched matrix products, drops frequencies below the FFTs' rounding
and runs the levels on the shading threads; each of these must leave the sums as the reference makes them.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from lighting.integrate import prefilter, rowconv
from lighting.integrate.prefilter import PREFILTER_SIGMAS, _beckmann_kernel, _ggx_kernel, _prefilter_levels
from lighting.integrate.rowconv import _convolve_rows, _convolve_rows_fast


def _hdr_map(h):
    """A positive map with a smooth sky, noise, and one pixel 10⁴ times brighter (a small sun)."""
    rng = np.random.default_rng(h)
    theta = (np.arange(h) + 0.5) * math.pi / h
    img = (0.5 + 0.4 * np.cos(theta))[:, None, None] + 0.2 * rng.random((h, 2 * h, 3))
    img[h // 3, h // 2] = 1e4
    return img


def _ggx_tail(alpha, x1):
    kernel = _ggx_kernel(alpha)
    return lambda x: kernel(np.maximum(x, x1))


def _ggx_core(alpha, x1):
    kernel = _ggx_kernel(alpha)
    return lambda x: kernel(x) - kernel(np.maximum(x, x1))


# (name, height, kernel, support): narrow supports on 64 rows take the banded blocks, wide ones the dense
# products; the von Mises-Fisher lobes drop frequencies, the kinked kernels (GGX's split, the clamped cosine)
# keep them all.
CASES = [
    ("vmf narrow", 64, lambda x: np.exp(-(1 / 0.05**2) * x), 6 * 0.05),
    ("vmf wide", 64, lambda x: np.exp(-(1 / 0.4**2) * x), 6 * 0.4),
    ("vmf 16 rows", 16, lambda x: np.exp(-(1 / 1.6**2) * x), 6 * 1.6),
    ("beckmann", 64, _beckmann_kernel(0.1 / math.sqrt(2)), 6 * 0.1 + math.pi / 64),
    ("ggx core", 64, _ggx_core(0.1 / math.sqrt(2), 1 - math.cos(0.6)), 0.6 + math.pi / 64),
    ("ggx tail", 32, _ggx_tail(0.1 / math.sqrt(2), 1 - math.cos(0.6)), math.pi / 2 + math.pi / 32),
    ("clamped cosine", 32, lambda x: np.maximum(1.0 - x, 0.0), math.pi / 2 + math.pi / 32),
]


@pytest.mark.parametrize("name, h, kernel, support", CASES, ids=[c[0] for c in CASES])
def test_the_fast_row_convolution_is_the_reference_to_rounding(name, h, kernel, support):
    img = _hdr_map(h)
    conv, norm = _convolve_rows(img, kernel, support)
    fast_conv, fast_norm = _convolve_rows_fast(img, kernel, support)
    assert fast_conv.shape == conv.shape and fast_norm.shape == norm.shape
    np.testing.assert_allclose(fast_norm, norm, rtol=1e-13)
    # Each pixel's sum to the rounding of the reference's own FFTs, which is relative to the whole row's light
    # (the sun's): 1e-13 of the brightest sum, and every level value (conv / norm) to 1e-9 where it is dark.
    np.testing.assert_allclose(fast_conv, conv, rtol=1e-12, atol=1e-13 * np.abs(conv).max())
    np.testing.assert_allclose(fast_conv / fast_norm[:, None, None], conv / norm[:, None, None], rtol=1e-9)


def test_the_banded_products_and_the_dropped_frequencies_are_exercised():
    # The narrow von Mises-Fisher case must take the banded blocks (B + 2R source rows < H) and drop frequencies;
    # otherwise the tests above would not check those paths.
    h, support, sigma = 128, 6 * 0.1, 0.1
    reach = math.ceil(support / (math.pi / h))
    assert rowconv._ROW_BLOCK + 2 * reach < h
    img = _hdr_map(h)
    spectra = rowconv._RowSpectra(img)
    # An equatorial pair's kernel row is about a Gaussian of σ = 0.1 rad in Δφ: its spectrum falls below 1e-14
    # of its sum before the last frequency, so frequencies are left out.
    row = np.exp(-(1 / sigma**2) * 2 * np.sin(np.arange(2 * h) * math.pi / (2 * h)) ** 2)
    spectrum = np.abs(np.fft.rfft(row))
    assert spectrum[-1] < rowconv._SPECTRUM_TOL * spectrum[0]
    conv, norm = _convolve_rows_fast(img, lambda x: np.exp(-(1 / sigma**2) * x), support, spectra)
    ref_conv, ref_norm = _convolve_rows(img, lambda x: np.exp(-(1 / sigma**2) * x), support)
    np.testing.assert_allclose(conv / norm[:, None, None], ref_conv / ref_norm[:, None, None], rtol=1e-9)


@pytest.mark.parametrize("h0", [32, 64])
def test_every_fast_level_is_the_reference_level(h0):
    base = _hdr_map(h0)
    fast = _prefilter_levels(base, PREFILTER_SIGMAS, h0)
    reference = _prefilter_levels(base, PREFILTER_SIGMAS, h0, fast=False)
    for family in ("mirror", "beckmann", "ggx"):
        for k, (a, b) in enumerate(zip(fast[family], reference[family], strict=True)):
            assert a.dtype == b.dtype == np.float32 and a.shape == b.shape
            # float32 levels: equal to within a float32 rounding (the joined GGX level sums in another order).
            np.testing.assert_allclose(a, b, rtol=3e-7, err_msg=f"{family} {k}")


def test_fast_levels_are_the_same_bits_on_one_thread_and_on_several(monkeypatch):
    base = _hdr_map(64)
    threaded = _prefilter_levels(base, PREFILTER_SIGMAS, 64)
    again = _prefilter_levels(base, PREFILTER_SIGMAS, 64)
    monkeypatch.setattr(prefilter, "_run_all", lambda fns: [fn() for fn in fns])
    serial = _prefilter_levels(base, PREFILTER_SIGMAS, 64)
    for family in ("mirror", "beckmann", "ggx"):
        for a, b, c in zip(threaded[family], again[family], serial[family], strict=True):
            np.testing.assert_array_equal(a, b)
            np.testing.assert_array_equal(a, c)


def test_run_all_returns_every_result_in_order_and_raises_a_failure():
    assert prefilter._run_all([lambda k=k: k * k for k in range(9)]) == [k * k for k in range(9)]

    def fail():
        raise ValueError("kernel")

    with pytest.raises(ValueError, match="kernel"):
        prefilter._run_all([lambda: 1, fail, lambda: 3])


@pytest.mark.parametrize("h_in, h", [(16, 32), (16, 64), (64, 256), (128, 256)])
def test_the_separable_upsampling_is_the_bilinear_lookup_at_the_pixel_centres(h_in, h):
    from lighting.lights.environment import LatLongEnvironment
    from lighting.lights.latlong import latlong_lookup

    img = np.random.default_rng(h_in + h).random((h_in, 2 * h_in, 4))
    expected = latlong_lookup(img.reshape(-1, 4), h_in, 2 * h_in, LatLongEnvironment.pixel_directions(h, 2 * h))
    # The lookup reads its coordinates back from directions (arctan2): rounding of 1e-16 rad per pixel row.
    np.testing.assert_allclose(prefilter._upsample(img, h), expected, rtol=1e-12, atol=1e-13)


@pytest.mark.slow  # the full run has it, the fast loop leaves it out
def test_the_reference_convolution_of_some_rows_gives_those_rows_bits_and_nan_elsewhere():
    img = _hdr_map(32)
    kernel = lambda x: np.maximum(1.0 - x, 0.0)  # noqa: E731
    conv, norm = _convolve_rows(img, kernel, math.pi / 2 + math.pi / 32)
    rows = np.array([0, 1, 6, 7, 15, 30, 31])
    part, part_norm = _convolve_rows(img, kernel, math.pi / 2 + math.pi / 32, rows=rows)
    assert np.array_equal(part[rows].view(np.uint64), conv[rows].view(np.uint64))
    assert np.array_equal(part_norm[rows].view(np.uint64), norm[rows].view(np.uint64))
    assert np.isnan(np.delete(part, rows, axis=0)).all() and np.isnan(np.delete(part_norm, rows)).all()


@pytest.mark.slow
@pytest.mark.parametrize(("height", "source"), [(8, 64), (16, 64), (32, 64), (64, 64), (16, 32)])
def test_the_irradiance_map_convolves_only_the_rows_it_reads_with_the_same_bits(height, source):
    # The reference path (sources over 256 rows): each output pixel is read bilinearly from two source rows, and
    # those alone are convolved; the map is the one the whole source grid gives, bit for bit.  The map of a
    # smaller source (the fast convolution of every row) is that map to float64 rounding.
    from lighting.lights.environment import LatLongEnvironment
    from lighting.lights.latlong import latlong_lookup

    env = LatLongEnvironment(_hdr_map(source))
    got = prefilter._irradiance_reference(env.image, height, math.pi / 2 + math.pi / source)
    conv, _ = _convolve_rows(env.image, lambda x: np.maximum(1.0 - x, 0.0), math.pi / 2 + math.pi / source)
    full = np.maximum(conv, 0.0)
    want = full if height == source else latlong_lookup(
        full.reshape(-1, 3), source, 2 * source, prefilter._pixel_directions(height, 2 * height))
    assert np.array_equal(got.view(np.uint64), want.view(np.uint64))
    fast = prefilter.irradiance_map(env, height).image
    np.testing.assert_allclose(fast, want, rtol=1e-12, atol=1e-13 * np.abs(want).max())
    assert not np.array_equal(fast, want)  # the fast path was taken (its sums round differently)

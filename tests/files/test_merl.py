"""MERL ``.binary`` files: format, lookup, missing bins, bad files (lighting.files.merl)."""

from __future__ import annotations

import os

import numpy as np
import pytest

import lighting
from lighting.analysis.halfdiff import half_diff_to_dirs
from lighting.brdf import BlinnPhong, Lambert
from lighting.files.merl import (
    BINS,
    DIMS,
    MerlBRDF,
    bin_centres,
    read_merl,
    tabulate_merl,
    write_merl,
)

N = (0.0, 0.0, 1.0)
SIZE = 12 + 8 * 3 * BINS
# Reciprocal models only: the table folds φ_d by π, i.e. stores f(l, v) = f(v, l).  (The slides'
# unnormalized Blinn–Phong divides by n·l and is not reciprocal.)
BLINN = Lambert(0.5) + BlinnPhong(0.4, 30, normalized=True)


@pytest.fixture(scope="module")
def blinn_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("merl") / "blinn.binary"
    table = tabulate_merl(BLINN)
    write_merl(path, table)
    return path, table


def _directions(rng, count, min_z):
    x = rng.normal(size=(count, 3))
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    x[:, 2] = np.abs(x[:, 2])
    return x[x[:, 2] > min_z]


def _pairs(seed, count=20_000, min_z=0.35):
    rng = np.random.default_rng(seed)
    l, v = _directions(rng, count, min_z), _directions(rng, count, min_z)  # noqa: E741
    m = min(len(l), len(v))
    return l[:m], v[:m]


# -- format and round trips --------------------------------------------------------------------


def test_load_brdf_reads_binary_with_options(blinn_file):
    path, _ = blinn_file
    m = lighting.load_brdf(str(path), interpolation="linear")
    assert isinstance(m, MerlBRDF) and m.interpolation == "linear" and m.name is None
    with pytest.raises(ValueError, match=r"blinn\.binary.*no parameter 'roughness'"):
        lighting.load_brdf(str(path), roughness=0.2)


# -- lookup ------------------------------------------------------------------------------------


def _centre_directions(step=7):
    th, td, pd = (a[::step, ::step, ::step] for a in bin_centres())
    l, v = half_diff_to_dirs(th, 0.3, td, pd)  # noqa: E741  (any φ_h: the table is isotropic)
    keep = (l[..., 2] > 1e-3) & (v[..., 2] > 1e-3)
    idx = np.argwhere(keep) * step
    return l[keep], v[keep], idx


@pytest.mark.parametrize("interpolation", ["nearest", "linear"])
def test_bin_centres_give_the_stored_values(blinn_file, interpolation):
    path, table = blinn_file
    m = read_merl(path, interpolation=interpolation)
    l, v, idx = _centre_directions()  # noqa: E741
    got = m.eval(N, l, v)
    stored = m.table[:, idx[:, 0], idx[:, 1], idx[:, 2]].T
    if interpolation == "nearest":
        np.testing.assert_array_equal(got, stored)
    else:  # at a node, the trilinear weights are 1 and 0 up to the angles' rounding
        np.testing.assert_allclose(got, stored, rtol=1e-9)
    np.testing.assert_allclose(stored, BLINN.eval(N, l, v), rtol=1e-12)


@pytest.mark.parametrize("interpolation", ["nearest", "linear"])
def test_reciprocity(blinn_file, interpolation):
    m = read_merl(blinn_file[0], interpolation=interpolation)
    l, v = _pairs(3, min_z=0.0)  # noqa: E741
    a, b = m.eval(N, l, v), m.eval(N, v, l)
    if interpolation == "nearest":  # a bin edge within rounding of a random pair has probability ~1e-12
        np.testing.assert_array_equal(a, b)
    else:
        np.testing.assert_allclose(a, b, rtol=1e-9)


def test_horizon_dtype_and_cos(blinn_file):
    m = read_merl(blinn_file[0], interpolation="linear")
    l, v = _pairs(4)  # noqa: E741
    below = l * np.array([1, 1, -1])
    assert np.all(m.eval(N, below, v) == 0) and np.all(m.eval(N, l, below) == 0)
    assert np.all(m.eval(N, (0, 0, 0), v) == 0)
    f64 = m.eval(N, l, v)
    f32 = m.eval(np.float32(N), l.astype(np.float32), v.astype(np.float32))
    assert f64.dtype == np.float64 and f32.dtype == np.float32
    np.testing.assert_allclose(f32, f64, rtol=1e-4)
    np.testing.assert_allclose(m.eval_cos(N, l, v), f64 * l[:, 2:3], rtol=1e-14)
    np.testing.assert_allclose(m.classic(N, l, v), np.pi * f64 * l[:, 2:3], rtol=1e-12)
    # Broadcasting: one normal and light, many views.
    assert m.eval(N, l[0], v[:5]).shape == (5, 3)


# -- bad files ---------------------------------------------------------------------------------


def _header(dims=DIMS):
    return np.asarray(dims, dtype="<i4").tobytes()


def _one_error(path, match):
    with pytest.raises(ValueError, match=match) as info:
        read_merl(path)
    assert os.fspath(path) in str(info.value)
    assert info.value.__cause__ is None and not isinstance(info.value, TypeError)


@pytest.mark.parametrize(
    ("name", "content", "match"),
    [
        ("empty", b"", r"byte 0: the file ends inside the 12-byte header"),
        ("short_header", b"\x5a\x00\x00\x00\x5a", r"byte 5: the file ends inside the 12-byte header"),
        ("zero_dim", _header((90, 0, 180)), r"byte 4: dimension 0"),
        ("negative_dim", _header((-90, -90, 180)), r"byte 0: dimension -90"),
        ("product", _header((90, 90, 90)), r"product 729000"),
        ("order", _header((180, 90, 90)), r"dimensions \(180, 90, 90\); allowed: 90 90 180"),
        ("header_only", _header(), r"byte 12: the file is truncated"),
        ("truncated", _header() + bytes(8 * 1000 + 3), r"byte 8015: the file is truncated"),
    ],
)
def test_bad_headers_and_sizes(tmp_path, name, content, match):
    path = tmp_path / f"{name}.binary"
    path.write_bytes(content)
    _one_error(path, match)


def test_extra_bytes_nan_inf(tmp_path, blinn_file):
    good = blinn_file[0].read_bytes()
    extra = tmp_path / "extra.binary"
    extra.write_bytes(good + b"\x00")
    _one_error(extra, rf"byte {SIZE}: 1 extra bytes")
    for bad, label in ((np.nan, "nan"), (np.inf, "inf"), (-np.inf, "inf")):
        data = bytearray(good)
        at = 12 + 8 * (BINS + 5 + 180 * 3)  # green, θ_h bin 0, θ_d bin 3, φ_d bin 5
        data[at : at + 8] = np.float64(bad).tobytes()
        path = tmp_path / f"{label}.binary"
        path.write_bytes(bytes(data))
        _one_error(path, rf"byte {at}: value -?{label} \(channel G, θ_h bin 0, θ_d bin 3, φ_d bin 5\)")


def test_missing_file_and_directory(tmp_path):
    _one_error(tmp_path / "nope.binary", "no such file")
    folder = tmp_path / "dir.binary"
    folder.mkdir()
    _one_error(folder, "directory|not a regular file")


def test_budget_is_checked_before_reading(blinn_file):
    from lighting._budget import set_memory_budget

    old = set_memory_budget(10_000_000)
    try:
        with pytest.raises(ValueError, match="over the memory budget"):
            read_merl(blinn_file[0])
    finally:
        set_memory_budget(old)


        # Anything else propagates and fails the test.


def test_table_argument_checks():
    with pytest.raises(ValueError, match="shape"):
        MerlBRDF(np.zeros((3, 10)))
    with pytest.raises(ValueError, match="finite"):
        MerlBRDF(np.full((3, *DIMS), np.nan))
    with pytest.raises(ValueError, match="interpolation"):
        MerlBRDF(np.zeros((3, *DIMS)), interpolation="cubic")


@pytest.mark.slow
@pytest.mark.parametrize("fraction", [0.01, 0.05, 0.5, 0.99])
def test_missing_bins_are_filled_as_the_reference_fills_them_bit_for_bit(fraction):
    # The binary search among the good entries picks the neighbour the three-copy search picks (ties to the earlier
    # azimuth, across the seam of a row, 0 for a row with none), so the filled table is the same bits.
    from lighting.files.merl import _fill_missing, _fill_missing_reference

    rng = np.random.default_rng(int(fraction * 100))
    for shape in [(3, 300, 180), (2, 40, 7), (6, 1), (3, 2)]:
        rows = rng.random(shape)
        rows[rng.random(shape) < fraction] = -1.0
        rows[0, ...] = -1.0  # rows with no good entry
        got, want = _fill_missing(rows), _fill_missing_reference(rows)
        assert np.array_equal(got.view(np.uint64), want.view(np.uint64)), shape
        assert not (got < 0).any()
    tie = np.array([[3.0, -1, -1, -1, 4.0, -1, -1], [-1, 5.0, -1, -2, -1, 6.0, -1]])
    assert _fill_missing(tie).tolist() == [[3, 3, 3, 4, 4, 4, 3], [5, 5, 5, 5, 6, 6, 6]]
    assert _fill_missing(np.full((2, 3), -1.0)).tolist() == [[0, 0, 0], [0, 0, 0]]

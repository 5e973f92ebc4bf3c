"""MERL files: a Lambert table written and read, a round trip bit for bit, missing bins filled, tables of two models
against the models, and the reader fuzzed (slow set; fast: test_merl.py)."""

import os

import numpy as np
import pytest
from test_merl import BLINN, SIZE, N, _pairs

from lighting.brdf import CookTorrance, Lambert
from lighting.files.merl import BINS, DIMS, SCALE, MerlBRDF, read_merl, tabulate_merl, write_merl

pytestmark = pytest.mark.slow  # full-size tables tabulated, written and read, and forty corrupted ones read

#: A second reciprocal model beside test_merl.py's BLINN (the table stores f(l, v) = f(v, l)).
COOK = CookTorrance((0.5, 0.4, 0.3), 0.3, 0.04) + Lambert(0.3)


@pytest.fixture(scope="module")
def blinn_table():
    """BLINN tabulated once: the table written to the file and the one compared with the model."""
    return tabulate_merl(BLINN)


@pytest.fixture(scope="module")
def blinn_file(tmp_path_factory, blinn_table):
    path = tmp_path_factory.mktemp("merl") / "blinn.binary"
    write_merl(path, blinn_table)
    return path, blinn_table


# -- format and round trips --------------------------------------------------------------------


def test_lambert_table_is_kd_over_pi_after_the_scales(tmp_path):
    kd = np.array([0.8, 0.5, 0.2])
    path = tmp_path / "lambert.binary"
    write_merl(path, tabulate_merl(Lambert(kd)))
    assert os.path.getsize(path) == SIZE
    data = path.read_bytes()
    assert np.frombuffer(data[:12], "<i4").tolist() == [90, 90, 180]
    raw = np.frombuffer(data[12:], "<f8").reshape(3, BINS)
    above = raw[0] != 0  # centres below the horizon are 0
    assert above.mean() > 0.5
    for c in range(3):
        np.testing.assert_allclose(raw[c][above], kd[c] / np.pi / SCALE[c], rtol=1e-15)
    m = read_merl(path)
    l, v = _pairs(1)  # noqa: E741
    np.testing.assert_allclose(m.eval(N, l, v), np.broadcast_to(kd / np.pi, (len(l), 3)), rtol=1e-15)


def test_round_trip_is_bitwise(blinn_file, tmp_path):
    path, table = blinn_file
    m = read_merl(path)
    np.testing.assert_array_equal(m.raw, (table.reshape(3, BINS) / SCALE[:, None]).reshape(3, *DIMS))
    np.testing.assert_allclose(m.table, table, rtol=2e-16, atol=0)
    again = tmp_path / "again.binary"
    write_merl(again, m)
    assert again.read_bytes() == path.read_bytes()
    assert not [p for p in os.listdir(tmp_path) if p.endswith(".tmp")]  # the temporary file is gone


# -- missing bins ------------------------------------------------------------------------------


def test_missing_bins_take_the_nearest_measured_phi_d():
    table = np.zeros((3, *DIMS))
    table[:, :, :, :] = np.arange(DIMS[2])[None, None, None, :] + 1.0  # value = φ_d bin + 1
    table[:, 5, 7, 10:14] = -1.0  # 10, 11 take bin 9 (value 10); 12, 13 take bin 14 (value 15)
    table[:, 5, 8, [178, 179, 0]] = -1.0  # across the wrap: 178 ← 177; 179 a tie (177 or 1) → 177; 0 ← 1
    table[1, 6, 9, :] = -1.0  # a whole row missing: 0
    m = MerlBRDF(table)
    assert m.missing == 3 * 4 + 3 * 3 + 180
    lut = m._lut.reshape(*DIMS, 3)
    np.testing.assert_allclose(lut[5, 7, 10:14, 0], [10.0, 10.0, 15.0, 15.0], rtol=1e-15)
    np.testing.assert_allclose(lut[5, 8, [178, 179, 0], 0], [178.0, 178.0, 2.0], rtol=1e-15)
    assert np.all(lut[6, 9, :, 1] == 0) and np.all(lut[6, 9, :, 0] > 0)
    np.testing.assert_allclose(m.table, table, rtol=3e-16)  # the table as given keeps its marks


# -- tables against their models ---------------------------------------------------------------


@pytest.mark.parametrize(("model", "tol_nearest", "tol_linear"), [(BLINN, 0.07, 3e-3), (COOK, 0.07, 4e-3)])
def test_random_directions_match_the_model(model, tol_nearest, tol_linear, request):
    # BLINN's table is the module's (the file's); a table is a function of the model alone.
    table = request.getfixturevalue("blinn_table") if model is BLINN else tabulate_merl(model)
    l, v = _pairs(2)  # noqa: E741
    ref = model.eval(N, l, v)
    got = {}  # each lookup's values at the pairs, for its bound and then for the medians below
    for interpolation, tol in (("nearest", tol_nearest), ("linear", tol_linear)):
        got[interpolation] = MerlBRDF(table, interpolation=interpolation).eval(N, l, v)
        err = np.max(np.abs(got[interpolation] - ref) / ref)
        assert err < tol, (interpolation, err)
    # Linear is the better estimate: an order of magnitude on the median.
    lin = np.median(np.abs(got["linear"] - ref) / ref)
    near = np.median(np.abs(got["nearest"] - ref) / ref)
    assert lin < near / 10


# -- bad files ---------------------------------------------------------------------------------


def test_fuzz_only_value_errors(tmp_path, blinn_file):
    rng = np.random.default_rng(17)
    good = blinn_file[0].read_bytes()
    path = tmp_path / "fuzz.binary"
    for trial in range(40):
        kind = trial % 4
        if kind == 0:  # random bytes of random length
            data = rng.bytes(int(rng.integers(0, 200)))
        elif kind == 1:  # a good file truncated anywhere
            data = good[: int(rng.integers(0, SIZE))]
        elif kind == 2:  # random header on a right-sized body
            data = rng.bytes(12) + good[12:]
        else:  # random bytes of exactly the right size (NaNs or infinities are nearly certain)
            data = good[:12] + rng.bytes(SIZE - 12)
        path.write_bytes(data)
        try:
            read_merl(path)
        except ValueError as e:
            assert str(path) in str(e)

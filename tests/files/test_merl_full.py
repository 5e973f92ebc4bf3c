"""MERL files: tables of two models against the models, and the reader fuzzed (slow set; fast: test_merl.py)."""

import numpy as np
import pytest
from test_merl import BLINN, SIZE, N, _pairs

from lighting.brdf import CookTorrance, Lambert
from lighting.files.merl import MerlBRDF, read_merl, tabulate_merl, write_merl

pytestmark = pytest.mark.slow  # two models tabulated whole, and forty corrupted full-size tables written and read

#: A second reciprocal model beside test_merl.py's BLINN (the table stores f(l, v) = f(v, l)).
COOK = CookTorrance((0.5, 0.4, 0.3), 0.3, 0.04) + Lambert(0.3)


@pytest.fixture(scope="module")
def blinn_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("merl") / "blinn.binary"
    table = tabulate_merl(BLINN)
    write_merl(path, table)
    return path, table


@pytest.mark.parametrize(("model", "tol_nearest", "tol_linear"), [(BLINN, 0.07, 3e-3), (COOK, 0.07, 4e-3)])
def test_random_directions_match_the_model(model, tol_nearest, tol_linear):
    table = tabulate_merl(model)
    l, v = _pairs(2)  # noqa: E741
    ref = model.eval(N, l, v)
    for interpolation, tol in (("nearest", tol_nearest), ("linear", tol_linear)):
        got = MerlBRDF(table, interpolation=interpolation).eval(N, l, v)
        err = np.max(np.abs(got - ref) / ref)
        assert err < tol, (interpolation, err)
    # Linear is the better estimate: an order of magnitude on the median.
    lin = np.median(np.abs(MerlBRDF(table, interpolation="linear").eval(N, l, v) - ref) / ref)
    near = np.median(np.abs(MerlBRDF(table).eval(N, l, v) - ref) / ref)
    assert lin < near / 10


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

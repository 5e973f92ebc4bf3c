"""MERL files: the reader fuzzed (slow set; fast: test_merl.py)."""

import numpy as np
import pytest
from test_merl import BLINN, SIZE

from lighting.files.merl import read_merl, tabulate_merl, write_merl

pytestmark = pytest.mark.slow  # forty corrupted full-size tables written and read


@pytest.fixture(scope="module")
def blinn_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("merl") / "blinn.binary"
    table = tabulate_merl(BLINN)
    write_merl(path, table)
    return path, table


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

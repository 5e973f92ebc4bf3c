"""The stability sweep's general table in MPFR (gmpy2) and in mpmath alone: the same floats, bit for bit (slow set).

``lighting.validation.general.general_table`` computes each model at each input in MPFR and computes it again in
mpmath where MPFR's exponent range ends.  Here the same inputs also go through mpmath alone (no gmpy2 context), and
every value, remainder, condition number and logarithm the sweep keeps must be the same float, both for inputs
where MPFR suffices and for the tiny-roughness, grazing inputs where it does not.  ``test_mpfr.py`` has the quick
checks of the arithmetic itself.
"""

import numpy as np
import pytest
from test_mpfr import _general_columns

from lighting.validation import general
from lighting.validation.cases import brdf_cases
from lighting.validation.mpfr import MPFRContext
from lighting.validation.stability import REFERENCE_DPS
from lighting.validation.summary import _binary

pytestmark = pytest.mark.slow  # the general table at 80 digits in pure-Python mpmath, every model, two dtypes

gmpy2 = pytest.importorskip("gmpy2")


def _inputs(dt, every=15):
    """Every ``every``-th case of the quick sweep, rounded to ``dt`` (nine of them: normal, grazing and peak sweeps)."""
    cases = brdf_cases(True)[::every]
    return [(_binary(c.n, dt), _binary(c.l, dt), _binary(c.v, dt), bool(c.sweep)) for c in cases]


@pytest.mark.parametrize("dt", [np.float32, np.float64])
def test_the_general_table_in_mpfr_is_the_table_in_mpmath(dt, monkeypatch):
    specs, cols = _general_columns()
    inputs = _inputs(dt)
    redone = []
    cells = general._cells

    def counted(mp, *args):
        if not isinstance(mp, MPFRContext):
            redone.append(args[1])
        return cells(mp, *args)

    monkeypatch.setattr(general, "_cells", counted)
    fast = general.general_table(specs, cols, inputs, REFERENCE_DPS)
    monkeypatch.setattr(general, "mpfr_context", lambda: None)
    redone_in_the_fast_run = len(redone)
    slow = general.general_table(specs, cols, inputs, REFERENCE_DPS)
    # Some inputs left MPFR's range and were computed again in mpmath; most were not.
    assert 0 < redone_in_the_fast_run < len(redone) - redone_in_the_fast_run
    assert fast["nz"].sum() > 1000
    for key in ("hi", "lo", "nz", "kappa", "logref"):
        assert np.array_equal(fast[key], slow[key], equal_nan=True), key



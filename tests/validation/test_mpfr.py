"""The general references in MPFR (gmpy2) against the same formulas in mpmath, at 80 digits.

The frame, a conductor's Fresnel factor, ``erfc`` and ``atan2`` agree to 1e-78; a model's value rounds to the same
double; a value beyond MPFR's exponent range raises its flags.  The whole general table of the stability sweep,
computed both ways bit for bit, is in ``test_mpfr_full.py``.
"""

import math

import mpmath
import pytest

from lighting.validation import general
from lighting.validation.model_references import arithmetic, conductor_fresnel, frame, model_value
from lighting.validation.mpfr import mpfr_context
from lighting.validation.stability import brdf_specs
from lighting.validation.tables import _brdf_forms, _columns

gmpy2 = pytest.importorskip("gmpy2")


def _general_columns():
    specs = brdf_specs()
    return specs, [(si, form) for si, form in _columns(specs, _brdf_forms) if specs[si].general]


def test_mpfr_arithmetic_agrees_with_mpmath_at_80_digits():
    ctx = mpfr_context()
    mp = mpmath.mp
    n, l, v = (0.3, -0.2, 0.93), (0.6, 0.1, 0.35), (-0.5, 0.4, 0.77)  # noqa: E741
    with ctx.workdps(80), arithmetic(ctx):
        q_fast = frame(n, l, v)
        fresnel_fast = conductor_fresnel(q_fast["vh"], 0.2, 3.0)
        erfc_fast, atan2_fast = ctx.erfc(ctx.mpf("0.7")), ctx.atan2(ctx.mpf(-1), ctx.mpf("1e-40"))
        assert ctx.prec == 269 and not ctx.exceptional()
    with mp.workdps(80):
        q_slow = frame(n, l, v)
        fresnel_slow = conductor_fresnel(q_slow["vh"], 0.2, 3.0)
        erfc_slow, atan2_slow = mp.erfc(mp.mpf("0.7")), mp.atan2(-1, mp.mpf("1e-40"))
        for key in ("nl", "nv", "nh", "vh", "P", "sl", "ht", "hb", "lt", "vb"):
            assert abs(mp.mpf(str(q_fast[key])) - q_slow[key]) <= mp.mpf("1e-78") * abs(q_slow[key]), key
        for fast, slow in ((fresnel_fast, fresnel_slow), (erfc_fast, erfc_slow), (atan2_fast, atan2_slow)):
            assert abs(mp.mpf(str(fast)) - slow) <= mp.mpf("1e-78") * abs(slow)


def test_a_value_beyond_mpfrs_exponent_range_is_flagged_and_mpmath_has_it():
    ctx = mpfr_context()
    with ctx.workdps(80):
        assert ctx.exp(ctx.mpf(-1e10)) == 0 and ctx.exceptional()
        ctx.clear_flags()
        assert not ctx.exceptional()
    with mpmath.mp.workdps(80):
        assert float(mpmath.log10(mpmath.exp(-1e10))) == pytest.approx(-1e10 / math.log(10), rel=1e-15)


def test_a_model_computed_in_either_arithmetic_is_the_same_double():
    # A Cook–Torrance model value at a tilted frame: the double nearest each 80-digit value is the same.
    specs, _ = _general_columns()
    model = next(s.model for s in specs if s.general and type(s.model).__name__ == "CookTorrance")
    prm = general.model_parameters(model)
    n, l, v = (0.0, 0.1, 1.0), (0.5, -0.2, 0.8), (-0.3, 0.25, 0.9)  # noqa: E741
    ctx = mpfr_context()
    with ctx.workdps(80), arithmetic(ctx):
        fast = model_value(model, frame(n, l, v), {k: ctx.mpf(x) for k, x in prm.items()})
    with mpmath.mp.workdps(80):
        slow = model_value(model, frame(n, l, v), {k: mpmath.mpf(x) for k, x in prm.items()})
    assert float(fast) == float(slow) > 0

"""The conductor Fresnel term at the extremes: cos θ = 0 and 1, indices from 1e-300 to the largest float.

Each value is compared, in float32 and float64, with the 80-digit reference of the stability sweep
(:func:`lighting.validation.model_references.conductor_fresnel`) computed from the same binary inputs, under the
sweep's bound: relative error <= 8 max(κ, 1) u, κ the condition number of F in its three inputs.
"""

from __future__ import annotations

import itertools

import mpmath
import numpy as np
import pytest

from lighting.fresnel import conductor
from lighting.validation.model_references import conductor_fresnel

COSINES = (0.0, 5e-324, 1e-300, 1e-200, 1e-20, 1e-8, 1e-4, 0.1, 0.5, 0.9, 1 - 1e-8, 1.0)
ETAS = (1e-300, 1e-8, 1e-3, 0.2, 1.0, 1.5, 1e8, 1e200, 1.7e308)
KS = (0.0, 1e-300, 1e-3, 3.0, 1e4, 1e200, 1.7e308)
DELTA = mpmath.mpf("1e-30")


def _reference_and_kappa(c: float, eta: float, k: float):
    """F at 80 digits and κ = Σ_x |∂ln F/∂ln x| over c, η, k (one-sided differences of relative size 1e-30)."""
    with mpmath.workdps(80):
        x = [mpmath.mpf(c), mpmath.mpf(eta), mpmath.mpf(k)]
        f = conductor_fresnel(*x)
        if f == 0:  # η = 1, k = 0: no interface, F = 0 at every angle but grazing
            return 0.0, 0.0
        kappa = mpmath.mpf(0)
        for i in range(3):
            if x[i] == 0 or (i == 0 and x[0] == 1):
                continue  # a zero input stays 0 under relative perturbations; cos θ = 1 is not exceeded
            y = list(x)
            y[i] = x[i] * (1 - DELTA)
            kappa += abs(conductor_fresnel(*y) - f) / (f * DELTA)
        return float(f), float(kappa)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize(("eta", "k"), list(itertools.product(ETAS, KS)))
def test_within_the_sweeps_bound_of_an_80_digit_reference(dtype, eta, k):
    c = np.array(COSINES, dtype=dtype)
    with np.errstate(all="raise"):
        got = conductor(c, eta, k)
    assert got.dtype == dtype and np.all(np.isfinite(got)) and np.all((got >= 0) & (got <= 1))
    u = float(np.finfo(dtype).eps) / 2
    tiny = float(np.finfo(dtype).tiny)
    for ci, fi in zip(c.astype(np.float64), got.astype(np.float64), strict=True):
        ref, kappa = _reference_and_kappa(float(ci), eta, k)
        if ref == 0:
            assert fi == 0
            continue
        if ref < tiny:  # below the normal range (F = 0 at η = 1, k = 0 near normal incidence): within tiny
            assert abs(fi - ref) <= 8 * max(kappa, 1) * u * ref + tiny
            continue
        bound = 8 * max(kappa, 1) * u
        assert abs(fi - ref) <= bound * ref, (ci, fi, ref, kappa, abs(fi - ref) / (ref * u))


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_grazing_incidence_reflects_everything_and_normal_incidence_is_the_closed_form(dtype):
    for eta, k in itertools.product(ETAS, KS):
        assert conductor(np.zeros(1, dtype), eta, k)[0] == 1
        with mpmath.workdps(80):
            e, kk = mpmath.mpf(eta), mpmath.mpf(k)
            f0 = float(((e - 1) ** 2 + kk**2) / ((e + 1) ** 2 + kk**2))
        got = float(conductor(np.ones(1, dtype), eta, k)[0])
        assert got == pytest.approx(f0, rel=8 * float(np.finfo(dtype).eps), abs=float(np.finfo(dtype).tiny))


def test_a_huge_real_index_reflects_half_at_its_pseudo_brewster_angle():
    # η = 1e200: r_par = (η c − cos θ_t)/(η c + cos θ_t) vanishes at c = 1/η, where r_perp² = 1 to 1e-200.
    # ñ² overflows there, and F used to be taken as its grazing limit 1.
    assert float(conductor(1e-200, 1e200, 0.0)) == 0.5
    # ñ = 1e300 (1 + i) at c = 1e-300: r_par = (2i − (1 + i))/(2i + (1 + i)), |r_par|² = 1/5, F = 3/5.
    assert float(conductor(1e-300, 1e300, 1e300)) == pytest.approx(0.6, rel=1e-15)
    # Either side of it F rises back toward 1.
    f = conductor(np.array([1e-203, 1e-200, 1e-197]), 1e200, 0.0)
    assert f[0] > 0.99 and f[2] > 0.99 and f[1] == 0.5

"""The exact Fresnel reflectance of a conductor, against its closed forms and an 80-digit reference."""

from __future__ import annotations

import itertools

import mpmath
import numpy as np
import pytest

from lighting.fresnel import conductor, dielectric

# (η, k) from dielectrics (k = 0) through the metals' range (η well below 1, k of a few) to extremes.
INDICES = [(1.5, 0.0), (1.0, 0.0), (0.2, 3.1), (0.27, 2.78), (1.45, 1.9), (1.2, 7.3), (0.05, 0.5), (3.0, 0.01)]


def _reference(c, eta, k, dps=80):
    """F by the textbook formula in mpmath: cos θ_t from Snell's law with the complex index."""
    if c == 0:
        return 1.0  # grazing incidence (for η = 1, k = 0 the formula is 0/0: 1 by the engine's convention)
    with mpmath.workdps(dps):
        c = mpmath.mpf(c)
        n = mpmath.mpc(eta, k)
        s2 = 1 - c * c
        ct = mpmath.sqrt(1 - s2 / (n * n))
        r_perp = (c - n * ct) / (c + n * ct)
        r_par = (n * c - ct) / (n * c + ct)
        return float((abs(r_perp) ** 2 + abs(r_par) ** 2) / 2)


@pytest.mark.parametrize(("eta", "k"), INDICES)
def test_normal_incidence_is_the_closed_form(eta, k):
    expected = ((eta - 1) ** 2 + k**2) / ((eta + 1) ** 2 + k**2)
    assert float(conductor(1.0, eta, k)) == pytest.approx(expected, rel=1e-15, abs=1e-17)


@pytest.mark.parametrize(("eta", "k"), INDICES)
def test_against_an_80_digit_reference_down_to_grazing(eta, k):
    cosines = np.array([1.0, 0.9, 0.5, 0.1, 1e-2, 1e-3, 1e-5, 1e-7, 1e-9, 1e-12, 0.0])
    got = conductor(cosines, eta, k)
    ref = np.array([_reference(c, eta, k) for c in cosines])
    # A few units in the last place of F (and so of 1 - F near grazing, where F -> 1).
    np.testing.assert_allclose(got, ref, rtol=2e-15, atol=4e-16)
    assert got[-1] == 1.0  # grazing incidence reflects everything


def test_k_zero_is_the_dielectric_seen_from_outside():
    c = np.linspace(0.0, 1.0, 201)
    for eta in (0.5, 1.0 / 1.33, 1.0, 1.33, 1.5, 2.4, 40.0):
        np.testing.assert_allclose(conductor(c, eta, 0.0), dielectric(c, eta), rtol=1e-13, atol=1e-16)


def test_a_conductor_is_lit_from_outside_whatever_the_cosines_sign():
    c = np.linspace(0.0, 1.0, 11)
    np.testing.assert_array_equal(conductor(-c, 0.2, 3.0), conductor(c, 0.2, 3.0))


def test_rgb_triples_broadcast_per_channel_and_keep_float32():
    eta, k = (0.2, 0.4, 1.4), (3.1, 2.5, 1.9)
    c = np.linspace(0.0, 1.0, 7, dtype=np.float32).reshape(7, 1)
    f = conductor(c, eta, k)
    assert f.shape == (7, 1, 3) and f.dtype == np.float32
    for ch in range(3):
        np.testing.assert_allclose(f[..., ch], conductor(c, eta[ch], k[ch]), rtol=0)
    np.testing.assert_array_equal(conductor(0.5, 1.3, (0.0, 1.0, 2.0))[..., 0], conductor(0.5, 1.3, 0.0))


def test_finite_in_finite_out_at_extreme_indices():
    values = (1e-300, 1e-150, 1e-8, 1.0, 1e8, 1e150, 1e300)
    cosines = {dt: np.array([0.0, np.finfo(dt).tiny, 1e-8, 0.5, 1.0], dtype=dt) for dt in (np.float32, np.float64)}
    with np.errstate(all="raise"):
        for eta, k in itertools.product(values, (0.0, *values)):
            for dt, c in cosines.items():
                f = conductor(c, eta, k)
                assert f.dtype == dt
                assert np.all(np.isfinite(f)) and np.all((f >= 0) & (f <= 1)), (eta, k, f)


def test_extreme_indices_approach_their_limits():
    # |n| -> infinity or -> 0 is a perfect reflector; n = 1 is no interface at all.
    assert np.all(conductor([0.3, 1.0], 1e300, 0.0) == 1.0)
    assert np.all(conductor([0.3, 1.0], 1e-300, 0.0) == 1.0)
    assert float(conductor(1.0, 1.0, 0.0)) == 0.0


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [({"eta": 0.0, "k": 1.0}, "eta"), ({"eta": -1.0, "k": 1.0}, "eta"), ({"eta": float("nan"), "k": 1.0}, "eta"),
     ({"eta": 1.0, "k": -0.1}, "k"), ({"eta": 1.0, "k": float("inf")}, "k"), ({"eta": (1, 2), "k": 0.0}, "eta")],
)  # fmt: skip
def test_bad_parameters_are_named(kwargs, name):
    with pytest.raises(ValueError, match=rf"^{name} must be"):
        conductor(0.5, **kwargs)
    with pytest.raises(ValueError, match=r"^cos_theta_i must be"):
        conductor(1.5, 1.0, 0.0)

"""Oren–Nayar (lighting.models.oren_nayar): the formula against its 80-digit reference, the laws, the energy.

* σ = 0 is Lambert, value for value (``assert_array_equal``: bit for bit, where ``−0.0 == 0.0``),
  in ``eval``, ``eval_cos`` and ``classic``, both forms, float32 and float64;
* ``eval`` and ``eval_cos`` against the 80-digit reference of the paper's formulas
  (:mod:`lighting.validation.model_references`), ordinary and grazing (1e-6 rad) inputs,
  tiny and large σ, both dtypes: relative error <= ``K · eps · κ`` with the condition estimate
  ``κ = (Σ |terms| / |Σ terms|) · (1 + 1/(n·l) + 1/(n·v))``;
* reciprocity (bit for bit);
* directional albedo: the qualitative model's closed form, mpmath quadrature of both forms, the
  engine's ``directional_albedo`` against them, and the bounds ``ρ <= k_d (A + B/2)``;
* the sampler (the cosine hemisphere): bounded weights (its χ² at 0° to 90° − 1e-4°: test_sampler_grazing_full.py);
* finite in, finite out on hard inputs (warnings are errors for the suite).
"""

from __future__ import annotations

import functools
import math

import mpmath
import numpy as np
import pytest
from exact_frames import exact_frame

from lighting.integrate import directional_albedo
from lighting.models import create_model, model_class, model_names
from lighting.models.lambert import CosineSampler, Lambert
from lighting.models.oren_nayar import OrenNayar
from lighting.models.protocol import Lobe
from lighting.validation import model_references as mr

pytestmark = pytest.mark.slow  # 80-digit references, quadratures, grazing χ²; fast: test_contract.py

FORMS = ("qualitative", "full")


def _unit(a):
    return a / np.linalg.norm(a, axis=-1, keepdims=True)


def _local(theta, phi):
    return np.stack(np.broadcast_arrays(np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)), -1)


def _frame(n):
    """Rows t, b, n of an orthonormal frame about ``n`` (float64)."""
    n = _unit(np.asarray(n, dtype=np.float64))
    t = _unit(np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0]))
    return np.stack([t, np.cross(n, t), n])


def _AB(sigma):
    s2 = sigma * sigma
    return 1 - 0.5 * s2 / (s2 + 0.33), 0.45 * s2 / (s2 + 0.09)


# =========================================================================== the 80-digit reference
def _mp_reference(N, L, V, sigma, form, kd):
    """``(f_r, κ, n·l)`` as mpf at 80 digits, from the raw inputs (exact binary values).

    ``f_r`` is :func:`lighting.validation.model_references.oren_nayar` (the paper's formula, angles from
    ``atan2``, ``cos Δφ`` from the tangent-plane projections); κ is this test's condition estimate
    ``(Σ |terms| / |Σ terms|) · (1 + 1/(n·l) + 1/(n·v))`` over the summands of
    :func:`~lighting.validation.model_references.oren_nayar_terms`.  Below the horizon ``(0, 1, 0)``.
    """
    mp = mpmath.mp
    with mp.workdps(80):
        q = exact_frame(*([float(c) for c in x] for x in (N, L, V)))
        if not q["above"]:
            return mp.mpf(0), mp.mpf(1), mp.mpf(0)
        kd, sigma = mp.mpf(kd), mp.mpf(sigma)
        terms, inter = mr.oren_nayar_terms(q, sigma, form)
        f = mr.oren_nayar(q, kd, sigma, form)
        direct = max(mp.fsum(terms), 0)
        spread = (kd * mp.fsum(abs(t) for t in terms) + kd * kd * inter) / (kd * direct + kd * kd * inter)
        return f, spread * (1 + 1 / q["nl"] + 1 / q["nv"]), q["nl"]


def _mp_value(N, L, V, sigma, form, kd):
    """The ``f_r`` of :func:`_mp_reference` alone (0 below the horizon): what the albedo quadratures integrate,
    without the condition estimate they do not use."""
    mp = mpmath.mp
    with mp.workdps(80):
        q = exact_frame(*([float(c) for c in x] for x in (N, L, V)))
        if not q["above"]:
            return mp.mpf(0)
        return mr.oren_nayar(q, mp.mpf(kd), mp.mpf(sigma), form)


def _mp_inputs(dtype):
    """Raw (n, l, v) triples: two normals, polar angles from 0 to 1e-6 rad below the horizon, five azimuths."""
    thetas = (0.0, 0.3, 1.0, math.pi / 2 - 1e-3, math.pi / 2 - 1e-6)
    phis = (0.0, 0.7, math.pi / 2, 2.5, math.pi)
    rows = []
    for n in ((0.0, 0.0, 1.0), (0.3, -0.5, 0.8)):
        frame = _frame(n)
        for tl in thetas:
            for tv in thetas:
                for p in phis:
                    l = _local(tl, 0.0) @ frame  # noqa: E741
                    v = _local(tv, p) @ frame
                    rows.append((frame[2], l, v))
    n, l, v = (np.array([r[i] for r in rows]).astype(dtype) for i in range(3))  # noqa: E741
    return n, l, v


SIGMAS_MP = (1e-8, 0.3, 1.0, math.pi / 2, 100.0)
#: The bound's multiple of eps·κ, with the measured worst case (max err / (eps κ)) noted in the test.
K_BOUND = 4


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("form", FORMS)
def test_eval_and_eval_cos_match_the_80_digit_transcription(form, dtype):
    kd = 0.7
    n, l, v = _mp_inputs(dtype)  # noqa: E741
    eps = float(np.finfo(dtype).eps)
    worst = 0.0
    for sigma in SIGMAS_MP:
        model = OrenNayar(kd, sigma, form)
        f, fc = model.eval(n, l, v)[:, 0], model.eval_cos(n, l, v)[:, 0]
        assert f.dtype == fc.dtype == dtype
        for i in range(len(n)):
            ref, kappa, cl = _mp_reference(n[i], l[i], v[i], sigma, form, kd)
            if ref == 0:
                assert f[i] == 0 and fc[i] == 0
                continue
            for got, want in ((f[i], ref), (fc[i], ref * cl)):
                err = abs(mpmath.mpf(float(got)) - want) / want
                ratio = float(err / (eps * kappa))
                worst = max(worst, ratio)
                assert ratio <= K_BOUND, (sigma, i, float(got), float(want), float(kappa))
    # Measured (this machine): worst err/(eps κ) = 0.37 (qualitative) and 0.54 (full) in float64,
    # 0.38 and 0.41 in float32.  Printed with -s.
    print(f"\n{form} {np.dtype(dtype).name}: max relative error / (eps κ) = {worst:.3g}")


def test_the_transcription_at_hand_values():
    # l = v = n: A/π.  l, v at 45° on the same azimuth: (A + B sin45° tan45°)/π.  Opposite azimuths: A/π.
    A, B = _AB(0.5)
    m = OrenNayar(1.0, 0.5)
    n = (0, 0, 1.0)
    assert m.eval(n, n, n)[0] == pytest.approx(A / math.pi, rel=1e-15)
    assert m.eval(n, (1.0, 0, 1.0), (1.0, 0, 1.0))[0] == pytest.approx((A + B * math.sqrt(0.5)) / math.pi, rel=1e-14)
    assert m.eval(n, (1.0, 0, 1.0), (-1.0, 0, 1.0))[0] == pytest.approx(A / math.pi, rel=1e-15)
    # Perpendicular azimuths: cos Δφ = 0, the B term vanishes (qualitative), the full model keeps C3 and C1.
    assert m.eval(n, (1.0, 0, 1.0), (0, 1.0, 1.0))[0] == pytest.approx(A / math.pi, rel=1e-15)


# =========================================================================== σ = 0 is Lambert
def _hard_directions():
    out = [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, -1.0]]
    for d in (1e-3, 1e-6, 1e-8, 1e-30):
        out += [[1.0, 0.0, d], [-1.0, 0.0, d], [0.0, 1.0, d], [math.cos(0.3), math.sin(0.3), d]]
    out += [list(_local(t, p)) for t in (0.2, 0.8, 1.4) for p in (0.0, 1.0, math.pi)]
    out += [[0.0, 0.0, 1e-30], [3e-25, 0.0, 4e-25], [1e30, 0.0, 1e30], [0.0, 0.0, 0.0]]
    return np.array(out)


HARD = _hard_directions()
HARD_NORMALS = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 7.5], [0.0, 0.0, 1e-20], [0.0, 0.0, 0.0], [1e-3, 0.0, 1.0]])


def _pairs(dtype):
    li = np.arange(len(HARD)).repeat(len(HARD))
    vi = np.tile(np.arange(len(HARD)), len(HARD))
    rng = np.random.default_rng(16)
    rl, rv = _unit(rng.normal(size=(500, 3))), _unit(rng.normal(size=(500, 3)))
    return np.concatenate([HARD[li], rl]).astype(dtype), np.concatenate([HARD[vi], rv]).astype(dtype)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("form", FORMS)
@pytest.mark.parametrize("kd", [0.8, (0.9, 0.5, 0.1), (1e300, 0.0, 1e-300)])
def test_sigma_zero_is_lambert_bit_for_bit(kd, form, dtype):
    on, lam = OrenNayar(kd, 0.0, form), Lambert(kd)
    l, v = _pairs(dtype)  # noqa: E741
    rng = np.random.default_rng(3)
    normals = np.concatenate([HARD_NORMALS, _unit(rng.normal(size=(3, 3)))]).astype(dtype)
    for n in normals:
        for method in ("eval", "eval_cos", "classic"):
            a, b = getattr(on, method)(n, l, v), getattr(lam, method)(n, l, v)
            assert a.dtype == b.dtype == dtype
            np.testing.assert_array_equal(a, b, err_msg=f"{method} n={n}")


# =========================================================================== reciprocity
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("form", FORMS)
@pytest.mark.parametrize("sigma", [0.1, 0.5, math.pi / 2, 1e3])
def test_reciprocity_bit_for_bit(sigma, form, dtype):
    m = OrenNayar((0.9, 0.5, 0.1), sigma, form)
    l, v = _pairs(dtype)  # noqa: E741
    for n in np.concatenate([HARD_NORMALS, [[0.3, -0.5, 0.8]]]).astype(dtype):
        np.testing.assert_array_equal(m.eval(n, l, v), m.eval(n, v, l))
        # classic = π f_r (n·l): swapping l and v swaps the cosine only, so classic/(n·l) is symmetric too.
        np.testing.assert_array_equal(m.classic(n, l, v) == 0, m.classic(n, v, l) == 0)


# =========================================================================== energy
def _closed_albedo(sigma, theta_v):
    """The qualitative model's directional albedo per unit k_d, in closed form (Notes of the class)."""
    A, B = _AB(sigma)
    t = theta_v
    J = math.sin(t) * (t / 2 - math.sin(2 * t) / 4)
    if t < math.pi / 2:
        J += math.tan(t) * (1 - math.sin(t) ** 3) / 3
    return A + 2 * B / math.pi * J


def _mp_albedo_2d(sigma, form, theta_v, kd=1.0, dps=15):
    """``∫ f_r cos θ_l dω_l`` of the transcription by 2-D mpmath quadrature, split at its kinks."""
    mp = mpmath.mp
    with mp.workdps(dps):
        tv = mp.mpf(theta_v)
        n, v = (0.0, 0.0, 1.0), (float(mp.sin(tv)), 0.0, float(mp.cos(tv)))

        def g(t, p):
            lvec = (float(mp.sin(t) * mp.cos(p)), float(mp.sin(t) * mp.sin(p)), float(mp.cos(t)))
            f = _mp_value(n, lvec, v, sigma, form, kd)
            return f * mp.cos(t) * mp.sin(t)

        # Every kink is a panel edge (θ_l = θ_v, cos φ = 0), so the integrand is smooth on each panel, where
        # Gauss–Legendre (its degree doubled until its error estimate is met) needs far fewer nodes than
        # tanh-sinh; the test asserts agreement with the closed form and the 1-D reduction to 1e-12.
        return 2 * mp.quad(g, [0, tv, mp.pi / 2], [0, mp.pi / 2, mp.pi], method="gauss-legendre")


def _mp_albedo_1d(sigma, form, theta_v, kd=1.0, dps=30):
    """The same integral with the azimuth done in closed form (for the full model: where its direct term is >= 0).

    qualitative: ∫ max(0, cos φ) dφ = 2; full: ∫ cos φ C2 dφ = 2 B (2β/π)³, ∫ (1 − |cos φ|) dφ = 2π − 4,
    ∫ cos φ dφ = 0 (the interreflection term integrates to 0.17 σ²/(σ² + 0.13) k_d²).
    """
    mp = mpmath.mp
    with mp.workdps(dps):
        s = mp.mpf(sigma)
        s2 = s * s
        rho = kd * _mp_direct_albedo_1d(sigma, form, theta_v, dps)
        if form == "full":
            rho += kd * kd * mp.mpf("0.17") * s2 / (s2 + mp.mpf("0.13"))
        return rho


@functools.cache
def _mp_direct_albedo_1d(sigma, form, theta_v, dps):
    """``A + ∫ …`` of :func:`_mp_albedo_1d`, per unit k_d: independent of k_d, one integral serves every channel."""
    mp = mpmath.mp
    with mp.workdps(dps):
        s = mp.mpf(sigma)
        s2 = s * s
        A = 1 - s2 / (2 * (s2 + mp.mpf("0.33")))
        B = mp.mpf("0.45") * s2 / (s2 + mp.mpf("0.09"))
        C3 = mp.mpf("0.125") * s2 / (s2 + mp.mpf("0.09"))
        tv = mp.mpf(theta_v)

        def g(t):
            a, b = max(t, tv), min(t, tv)
            if form == "qualitative":
                x = 2 * B * mp.sin(a) * mp.tan(b)
            else:
                x = 2 * B * (2 * b / mp.pi) ** 3 * mp.tan(b)
                x += (2 * mp.pi - 4) * C3 * (4 * a * b / mp.pi**2) ** 2 * mp.tan((a + b) / 2)
            return x * mp.cos(t) * mp.sin(t) / mp.pi

        return A + mp.quad(g, [0, tv, mp.pi / 2])


def _mp_albedo_full_nested(sigma, theta_v, dps=15):
    """The full model's albedo (k_d = 1) by nested 1-D mpmath quadrature in angles, the clamp's kinks breakpoints.

    For ``cos φ < 0`` the direct term is linear in ``c = cos φ`` (``1 − |c| = 1 + c``), so it crosses 0
    at one ``c₀`` (if any): the inner rule splits there.  The inner integral as a function of ``θ_l`` has a
    kink of its own where the clamp starts to act (``c₀ = −1``, the root of ``slope = A + c₃ tan θ_m``): the
    outer rule splits there too (found by a scan of 256 steps per panel and ``findroot``).  Without that
    breakpoint the outer rule is 8.2e-8 high at σ = π/2, θ_v = 1.5 (QUADPACK, adaptive in float64, agrees
    with the split rule by tanh-sinh to 1e-15).  Between the breakpoints both integrands are smooth, and both
    rules here are mpmath's Gauss–Legendre, which raises its degree until two degrees agree to the working
    precision: over the thirteen cases of this file it is within 1.4e-13 of the split rule by tanh-sinh at 22
    digits (σ = π/2, θ_v = 1.5), and within 2e-16 at every θ_v <= 1.2.
    """
    mp = mpmath.mp
    with mp.workdps(dps):
        s2 = mp.mpf(sigma) ** 2
        A = 1 - s2 / (2 * (s2 + mp.mpf("0.33")))
        B = mp.mpf("0.45") * s2 / (s2 + mp.mpf("0.09"))
        C3s = mp.mpf("0.125") * s2 / (s2 + mp.mpf("0.09"))
        R = mp.mpf("0.17") * s2 / (s2 + mp.mpf("0.13"))
        tv = mp.mpf(theta_v)

        def parts(t):
            a, b = max(t, tv), min(t, tv)
            tb, tm = mp.tan(b), mp.tan((a + b) / 2)
            c3 = C3s * (4 * a * b / mp.pi**2) ** 2
            # c < 0: direct = (A + c3 tm) + c (B (sin a − (2b/π)³) tb + c3 tm)
            slope = B * (mp.sin(a) - (2 * b / mp.pi) ** 3) * tb + c3 * tm
            return a, b, tb, tm, c3, slope

        def clamped(t):
            """Positive where the direct term is clamped somewhere in ``cos φ < 0``."""
            tm, c3, slope = parts(t)[3:]
            return slope - (A + c3 * tm)

        def inner(t):
            a, b, tb, tm, c3, slope = parts(t)

            def f(p):
                c = mp.cos(p)
                c2 = B * mp.sin(a) if c >= 0 else B * (mp.sin(a) - (2 * b / mp.pi) ** 3)
                direct = A + c * c2 * tb + (1 - abs(c)) * c3 * tm
                return max(direct, 0) + R * (1 - c * (2 * b / mp.pi) ** 2)

            pts = [0, mp.pi / 2, mp.pi]
            if slope > 0 and (A + c3 * tm) / slope < 1:
                pts = [0, mp.pi / 2, mp.acos(-(A + c3 * tm) / slope), mp.pi]
            return mp.quad(f, pts, method="gauss-legendre")

        outer = [mp.mpf(0), tv, mp.pi / 2]
        kinks = []
        for lo, hi in zip(outer[:-1], outer[1:], strict=True):
            grid = [lo + (hi - lo) * k / 256 for k in range(256)] + [hi]
            sign = [clamped(x) > 0 for x in grid]
            for i in range(256):
                if sign[i] != sign[i + 1]:
                    kinks.append(mp.findroot(clamped, (grid[i], grid[i + 1]), solver="anderson"))
        return 2 / mp.pi * mp.quad(lambda t: inner(t) * mp.cos(t) * mp.sin(t), sorted(outer + kinks),
                                   method="gauss-legendre")


def test_the_albedo_references_agree():
    # The closed form, the 1-D reduction, the nested rule and the brute-force 2-D quadrature of the transcription.
    for sigma, tv in ((0.5, 1.2), (0.2, 0.6)):
        assert float(_mp_albedo_1d(sigma, "qualitative", tv)) == pytest.approx(_closed_albedo(sigma, tv), rel=1e-14)
    assert float(_mp_albedo_2d(0.5, "qualitative", 1.2)) == pytest.approx(_closed_albedo(0.5, 1.2), rel=1e-12)
    # The full model at σ = 0.5 (direct term >= 0 everywhere: the azimuth reduction holds).
    full = float(_mp_albedo_1d(0.5, "full", 1.2))
    assert float(_mp_albedo_2d(0.5, "full", 1.2)) == pytest.approx(full, rel=1e-12)
    assert float(_mp_albedo_full_nested(0.5, 1.2)) == pytest.approx(full, rel=1e-12)


def test_full_model_albedo_where_the_clamp_acts():
    # σ = π/2, θ_v = 1.5: the direct term is clamped at 0 over part of the forward half; the unclamped
    # 1-D reduction is 0.854549, the clamped model's albedo 0.8562902503 by the nested rule with the clamp's
    # onset (θ_l = 1.10178) a breakpoint, and by QUADPACK in float64 (a rule that does not break there
    # gives 0.8562903318, 8.2e-8 high).
    want = float(_mp_albedo_full_nested(math.pi / 2, 1.5))
    assert want == pytest.approx(0.8562902503, abs=1e-9)
    assert float(_mp_albedo_1d(math.pi / 2, "full", 1.5)) == pytest.approx(0.8545490018, abs=1e-9)
    est = directional_albedo(OrenNayar(1.0, math.pi / 2, "full"), 1.5, samples=262144, return_error=True)
    assert abs(est.value[0] - want) <= 2 * est.error[0] + 1e-12  # measured: 1.1e-7 off, estimate 3.6e-6


ALBEDO_CASES = [(s, t) for s in (0.2, 0.5, 1.0) for t in (0.0, 0.6, 1.2, 1.5, math.pi / 2 - 1e-3)]


@pytest.mark.parametrize("sigma, theta_v", ALBEDO_CASES)
@pytest.mark.parametrize("form", FORMS)
def test_directional_albedo_matches_the_references(form, sigma, theta_v):
    kd = np.array([1.0, 0.6, 0.2])
    m = OrenNayar(kd, sigma, form)
    if form == "qualitative":
        want = kd * _closed_albedo(sigma, theta_v)
    elif sigma < 0.6646:  # the direct term is never clamped: the azimuth reduction is exact
        want = np.array([float(_mp_albedo_1d(sigma, form, theta_v, k)) for k in kd])
    else:  # k_d = 1 only: the nested rule (the clamp's kink a breakpoint)
        kd = np.ones(3)
        m = OrenNayar(1.0, sigma, form)
        want = float(_mp_albedo_full_nested(sigma, theta_v)) * kd
    est = directional_albedo(m, theta_v, samples=262144, return_error=True)
    err = np.abs(est.value - want)
    # The quadrature's own error estimate is honest here (measured: |error| <= 1.3 of it, at most 1.8e-6), and small.
    assert np.all(err <= 2 * est.error + 1e-12), (err, est.error)
    assert np.all(err <= 5e-6 * kd), err


@pytest.mark.parametrize("sigma", [0.05, 0.199, 0.326, 0.5, 1.0, math.pi / 2, 10.0])
def test_qualitative_albedo_stays_below_kd_times_a_plus_b_over_2(sigma):
    # ρ(θ_v) rises from k_d A at the normal to k_d (A + B/2) at grazing (closed form), never above it.
    A, B = _AB(sigma)
    kd = np.array([0.9, 0.5, 0.1])
    thetas = np.linspace(0, math.pi / 2, 41)
    rho = np.array([_closed_albedo(sigma, t) for t in thetas])
    assert np.all(np.diff(rho) >= -1e-15)  # monotone in θ_v
    assert rho[0] == pytest.approx(A, rel=1e-15) and rho[-1] == pytest.approx(A + B / 2, rel=1e-15)
    got = directional_albedo(OrenNayar(kd, sigma), thetas[:-1] + 0.0, samples=65536)
    assert np.all(got <= kd * (A + B / 2) * (1 + 1e-5))
    # Where A + B/2 <= 1 (σ >= 0.326) that is the physical bound ρ <= k_d; below, the model's own excess.
    if sigma >= 0.3262:
        assert A + B / 2 <= 1
    else:
        assert 1 < A + B / 2 <= 1.0152


@pytest.mark.parametrize("sigma", [0.1, 0.15, 0.2, 0.5, 1.0, math.pi / 2])
def test_full_albedo_stays_below_its_kd_scaled_bound(sigma):
    # ρ_full = k_d D + k_d² R: the direct part D (per unit k_d) stays below the qualitative model's A + B/2,
    # the interreflection part is exactly R = 0.17 σ²/(σ² + 0.13).  Measured: D peaks at 1.0035 (σ = 0.15,
    # grazing), so for k_d = 1 the full model reflects up to 4.0 % more than it receives (σ = 0.2: 1.0401).
    A, B = _AB(sigma)
    R = 0.17 * sigma**2 / (sigma**2 + 0.13)
    kd = np.array([1.0, 0.5, 0.1])
    thetas = np.linspace(0, math.pi / 2 - 1e-3, 12)
    got = directional_albedo(OrenNayar(kd, sigma, "full"), thetas, samples=65536)
    direct = (got - kd**2 * R) / kd
    assert np.all(direct <= A + B / 2), direct.max(axis=0)
    assert np.all(direct[:, 0] <= 1.0036)
    np.testing.assert_allclose(direct, direct[:, :1] * np.ones(3), rtol=1e-9)  # linear in k_d, R in k_d²


def test_the_excess_over_kd_is_the_formula_s():
    # max over σ of A + B/2: 1.01518 at σ = 0.1985; above 1 exactly for 0 < σ < 0.32613.
    s = np.linspace(1e-4, 2, 200001)
    A, B = _AB(s)
    g = A + B / 2
    assert g.max() == pytest.approx(1.015179, abs=1e-6)
    assert s[g.argmax()] == pytest.approx(0.1985, abs=1e-3)
    assert s[g > 1].max() == pytest.approx(0.32613, abs=1e-4)


# =========================================================================== the sampler
def test_lobe_and_sampler():
    for form in FORMS:
        m = OrenNayar(0.8, 0.4, form)
        assert m.lobe() == Lobe("normal")
        assert isinstance(m.sampler(), CosineSampler)


@pytest.mark.parametrize("form", FORMS)
@pytest.mark.parametrize("sigma", [0.3, 1.0])
@pytest.mark.parametrize("theta_v", [0.0, 0.8, 1.4])
def test_cosine_sampling_weights_are_bounded(sigma, theta_v, form):
    # Weight f_r (n·l) / p = π f_r: at most k_d (A + B tan θ_v) for the qualitative model; Monte Carlo with
    # it reproduces the albedo.
    m = OrenNayar(1.0, sigma, form)
    v = np.array([math.sin(theta_v), 0.0, math.cos(theta_v)])
    s = m.sampler().sample(np.random.default_rng(7).random((200_000, 2)), v)
    ok = s.pdf > 0
    w = m.eval_cos((0, 0, 1.0), s.directions[ok], v)[:, 0] / s.pdf[ok]
    A, B = _AB(sigma)
    if form == "qualitative":
        assert w.max() <= (A + B * math.tan(theta_v)) * (1 + 1e-12)
        want = _closed_albedo(sigma, theta_v)
    else:
        want = float(_mp_albedo_full_nested(sigma, theta_v))
    assert np.isfinite(w).all()
    se = w.std() / math.sqrt(len(w))
    assert abs(w.mean() - want) <= 4 * se + 1e-12
    assert w.std() / w.mean() < 0.6  # relative spread per sample (measured: at most 0.46, σ = 1, θ_v = 1.4, full)


# =========================================================================== the contract, numerics, table
SIGMAS_HARD = (0.0, 1e-300, 1e-8, 0.3, 0.665, math.pi / 2, 1e3, 1e300)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("form", FORMS)
def test_finite_in_finite_out_on_hard_inputs(form, dtype):
    l, v = _pairs(dtype)  # noqa: E741
    for sigma in SIGMAS_HARD:
        for kd in (0.0, 1.0, (1e300, 0.0, 1e-300)):
            m = OrenNayar(kd, sigma, form)
            for n in HARD_NORMALS.astype(dtype):
                for f in (m.eval(n, l, v), m.eval_cos(n, l, v), m.classic(n, l, v)):
                    assert f.dtype == dtype
                    assert np.all(np.isfinite(f)) and np.all(f >= 0), (sigma, kd, n)


@pytest.mark.parametrize("form", FORMS)
def test_grazing_values_saturate_not_overflow(form):
    # l = v, 1e-30 rad from the horizon: f_r = (A + B/(n·l))/π ≈ 1.05e29, in float32 still; at 1e-40 (a
    # float32 subnormal) 1e39 exceeds float32 and saturates at its largest value.
    A, B = _AB(0.5)
    n = np.array([0, 0, 1.0], np.float32)
    l = np.array([1.0, 0.0, 1e-30], np.float32)  # noqa: E741
    # cos Δφ = 1: the full model's C3 term vanishes and its interreflection term is ~1e-30: the same value.
    want = (A + B * (1 - 1e-60) / 1e-30) / math.pi
    f = OrenNayar(1.0, 0.5, form).eval(n, l, l)
    assert f.dtype == np.float32
    np.testing.assert_allclose(f, want, rtol=2e-7)
    l = np.array([1.0, 0.0, 1e-40], np.float32)  # noqa: E741
    assert np.all(OrenNayar(1.0, 0.5, form).eval(n, l, l) == np.finfo(np.float32).max)
    # f_r (n·l) stays bounded: k_d (A + B)/π for the qualitative model.
    A, B = _AB(0.5)
    fc = OrenNayar(1.0, 0.5, "qualitative").eval_cos(n, l, l)
    assert np.all(fc <= (A + B) / math.pi)


def test_full_direct_term_is_clamped_at_zero():
    # σ = π/2, forward scattering (cos Δφ = −1), both 1e-4 rad from the horizon: C1 − C2 tan β < 0.
    s2 = (math.pi / 2) ** 2
    A, Bp = _AB(math.pi / 2)
    assert A - 6 / math.pi * Bp < 0
    m = OrenNayar(0.5, math.pi / 2, "full")
    n = (0, 0, 1.0)
    l, v = (1.0, 0.0, 1e-4), (-1.0, 0.0, 1e-4)  # noqa: E741
    inter = 0.17 * s2 / (s2 + 0.13) * (1 - (2 * math.atan2(1.0, 1e-4) / math.pi) ** 2 * -1)
    assert m.eval(n, l, v)[0] == pytest.approx(0.25 * inter / math.pi, rel=1e-9)
    # The threshold σ ≈ 0.665 where C1 = (6/π) 0.45 σ²/(σ²+0.09).
    A, Bp = _AB(0.6646)
    assert abs(A - 6 / math.pi * Bp) < 1e-3


def test_registry_table_summary_and_errors():
    assert "oren-nayar" in model_names() and model_class("oren-nayar") is OrenNayar
    m = create_model("oren-nayar", kd=(0.8, 0.2, 0.1), sigma=0.4, form="full")
    assert m.to_dict() == {"model": "oren-nayar", "kd": [0.8, 0.2, 0.1], "sigma": 0.4, "form": "full"}
    assert m.summary() == "kd=(0.8,0.2,0.1) σ=0.4 full"
    assert OrenNayar().summary() == "kd=0.8 σ=0.3"
    assert m.term == "diffuse" and not m.lambertian and not m.stackable
    # The diffuse reflectance at normal incidence, ρ(0) = k_d A + k_d² R (full form; the closed form of
    # _closed_albedo at θ_v = 0 plus the interreflection's 0.17 σ²/(σ² + 0.13)), the default ambient k_a.
    kd = np.array([0.8, 0.2, 0.1])
    A, _ = _AB(0.4)
    want = kd * A + kd**2 * 0.17 * 0.4**2 / (0.4**2 + 0.13)
    np.testing.assert_allclose(m.diffuse_albedo, want, rtol=1e-15)
    np.testing.assert_allclose(OrenNayar(kd, 0.4).diffuse_albedo, kd * A, rtol=1e-15)
    from lighting.shading.material import Material

    np.testing.assert_allclose(Material(m).ambient, want, rtol=1e-15)
    table = {p.name: p for p in OrenNayar.parameters}
    assert table["sigma"].unit == "rad" and table["sigma"].control_range == (0.0, math.pi / 2)
    assert table["form"].choices == FORMS
    for bad in (-0.1, math.nan, math.inf):
        with pytest.raises(ValueError, match="sigma"):
            OrenNayar(sigma=bad)
    for bad in ("rough", None, 1j):
        with pytest.raises(ValueError, match="sigma"):
            OrenNayar(sigma=bad)
    with pytest.raises(ValueError, match="form"):
        OrenNayar(form="exact")
    with pytest.raises(ValueError, match="kd"):
        OrenNayar(kd=-1)


def test_component_angles_equal_the_stacked_reference_bit_for_bit():
    """_angles/_cos_dphi on component tuples are the stacked reference's arithmetic, element by element."""
    from lighting.models.geometry import Geometry
    from lighting.models.oren_nayar import _angles, _angles_reference, _cos_dphi, _cos_dphi_reference

    rng = np.random.default_rng(5)
    l, v = rng.normal(size=(2, 300, 3))  # noqa: E741
    v[:20] = l[:20]
    v[20:40] = -l[20:40]
    l[40:50] = 0
    l[50:60] = (0, 0, 1)
    for n in (np.array([0.0, 0.0, 1.0]), rng.normal(size=(300, 3))):
        for dt in (np.float64, np.float32):
            g = Geometry(n.astype(dt), l.astype(dt), v.astype(dt))
            new, ref = _angles(g), _angles_reference(g)
            for a, b in zip(new[:5], ref[:5], strict=True):
                assert np.array_equal(a, b) and a.dtype == b.dtype
            xl, sl, xv, sv = new[5]
            assert np.array_equal(np.stack(xl, -1), ref[5][0]) and np.array_equal(np.stack(xv, -1), ref[5][2])
            for a, b in zip(_cos_dphi(*new[5]), _cos_dphi_reference(*ref[5]), strict=True):
                assert np.array_equal(a, b)

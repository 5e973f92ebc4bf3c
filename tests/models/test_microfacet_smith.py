"""Smith masking–shadowing: Λ, the height-correlated G2 (``geometry="smith-correlated"``), visible-normal sampling.

References: E. Heitz, "Understanding the masking-shadowing function in microfacet-based BRDFs",
JCGT 3(2), 2014 (Λ, eqs. 72 and 86; G2 = 1/(1 + Λ(v) + Λ(l)), eq. 99); E. Heitz, "Sampling the GGX
distribution of visible normals", JCGT 7(4), 2018.
"""

from __future__ import annotations

import math
import warnings

import mpmath
import numpy as np
import pytest
from quadrature import direction, hemisphere
from scipy import stats

from lighting.integrate import directional_albedo
from lighting.models import microfacet as mf
from lighting.models.cook_torrance import CookTorrance
from lighting.models.geometry import Geometry
from lighting.models.microfacet_sampling import MicrofacetSampler, VisibleNormalSampler

N = np.array([0.0, 0.0, 1.0])
NDFS = ("beckmann", "ggx")


# --------------------------------------------------------------------------- 80-digit references
def _mp_lambda(ndf, c, s2, alpha):
    """Λ from the (exact) cosine and squared sine, in 80 digits; erfc, not erf − 1, which cancels."""
    c, s, al = mpmath.mpf(c), mpmath.sqrt(mpmath.mpf(s2)), mpmath.mpf(alpha)
    if s == 0:
        return mpmath.mpf(0)
    if ndf == "ggx":
        return (-1 + mpmath.sqrt(1 + al**2 * s**2 / c**2)) / 2
    a = c / (al * s)
    return -mpmath.erfc(a) / 2 + mpmath.exp(-a * a) / (2 * a * mpmath.sqrt(mpmath.pi))


def _mp_ndf(ndf, c, s2, al):
    c, s2, al = mpmath.mpf(c), mpmath.mpf(s2), mpmath.mpf(al)
    if c <= 0:
        return mpmath.mpf(0)
    if ndf == "ggx":
        return al**2 / (mpmath.pi * (s2 + al**2 * c**2) ** 2)
    return mpmath.exp(-s2 / (al * c) ** 2) / (mpmath.pi * al**2 * c**4)


def _mp_eval(ndf, alpha, l, v):  # noqa: E741
    """``D G2 / (4 (n·v)(n·l))`` (F = 1, n = z) from the given float vectors taken as exact, normalized in 80 digits."""
    lv = [mpmath.matrix([mpmath.mpf(float(x)) for x in d]) for d in (l, v)]
    lv = [d / mpmath.norm(d) for d in lv]
    l, v = lv  # noqa: E741
    nl, nv = l[2], v[2]
    if nl <= 0 or nv <= 0:
        return mpmath.mpf(0)
    h = l + v
    h = h / mpmath.norm(h)
    s2h = h[0] ** 2 + h[1] ** 2
    lam_v = _mp_lambda(ndf, nv, v[0] ** 2 + v[1] ** 2, alpha)
    lam_l = _mp_lambda(ndf, nl, l[0] ** 2 + l[1] ** 2, alpha)
    return _mp_ndf(ndf, h[2], s2h, alpha) / (1 + lam_v + lam_l) / (4 * nv * nl)


def _condition(ndf, alpha, l, v, f0, eps):  # noqa: E741
    """A condition estimate: the largest relative change of the 80-digit value per relative input change ``eps``."""
    rng = np.random.default_rng(1)
    worst = 1.0
    for _ in range(4):
        dl = np.asarray(l, float) * (1 + eps * rng.choice([-1, 1], 3))
        dv = np.asarray(v, float) * (1 + eps * rng.choice([-1, 1], 3))
        f1 = _mp_eval(ndf, alpha, dl, dv)
        worst = max(worst, float(abs(f1 - f0) / abs(f0)) / eps if f0 != 0 else 1.0)
    return worst


def _dir(theta, phi=0.0):
    return np.array([math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)])


GRAZE = math.pi / 2 - 1e-6
CASES = [  # (θ_l, φ_l, θ_v, φ_v)
    (0.3, 0.0, 0.5, math.pi),
    (0.7, 1.0, 0.2, 2.5),
    (1.2, 0.0, 1.3, math.pi),
    (GRAZE, 0.0, 0.4, math.pi),
    (0.4, 0.3, GRAZE, math.pi),
    (GRAZE, 0.0, GRAZE, math.pi),
    (GRAZE, 0.0, GRAZE, 0.5),
    (0.0, 0.0, 0.0, 0.0),
    (1.0, 0.0, 1.0, math.pi),
]
ALPHAS = (1e-6, 1e-3, 0.1, 0.5, 1.0, 3.0, 100.0)


@pytest.mark.parametrize("ndf", NDFS)
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_lambda_matches_80_digits(ndf, dtype):
    # Λ from the float cosine and sine as given; relative error ≤ 8 eps (1 + 2a²) (a = cot θ/α: exp(−a²)
    # amplifies a's rounding by 2a²; GGX has no exponential and stays within 8 eps).
    fn = mf.smith_lambda_ggx if ndf == "ggx" else mf.smith_lambda_beckmann
    eps = np.finfo(dtype).eps
    worst = 0.0
    with mpmath.workdps(80):
        for alpha in ALPHAS:
            for c in (1e-300, 1e-30, 1e-6, 0.01, 0.2, 0.5, 0.8, 0.99, 0.999999, 1.0):
                c = float(dtype(c))
                if c == 0:
                    continue
                s2 = float(dtype((1 - mpmath.mpf(c)) * (1 + mpmath.mpf(c))))
                got = fn(np.asarray(c, dtype), alpha, np.asarray(s2, dtype))
                assert got.dtype == dtype and np.isfinite(got)
                ref = _mp_lambda(ndf, c, s2, alpha)
                big = float(np.finfo(dtype).max)
                if ref > big:
                    assert float(got) == big
                    continue
                if ref < np.finfo(dtype).tiny:  # below the dtype's normal range: an absolute bound
                    assert abs(float(got) - float(ref)) <= np.finfo(dtype).tiny
                    continue
                a = 0 if s2 == 0 else float(c / (alpha * mpmath.sqrt(s2)))
                cond = 1 + (2 * a * a if ndf == "beckmann" else 0)
                err = float(abs(mpmath.mpf(float(got)) - ref) / ref)
                worst = max(worst, err / (eps * cond))
                assert err <= 8 * eps * cond, (alpha, c, float(got), float(ref))
    print(f"Λ_{ndf} {np.dtype(dtype).name}: max error {worst:.2f} eps·(1 + 2a²)")


@pytest.mark.parametrize("ndf", NDFS)
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_correlated_eval_matches_80_digits(ndf, dtype):
    # f_r = D G2 / (4 (n·v)(n·l)) with F = 1, against the 80-digit value from the same float vectors;
    # relative error ≤ 64 eps × (condition estimate) or, where the value underflows the dtype, ≤ tiny.
    eps = float(np.finfo(dtype).eps)
    worst = 0.0
    with mpmath.workdps(80):
        for alpha in ALPHAS:
            ct = CookTorrance(1.0, alpha, 1.0, ndf=ndf, geometry="smith-correlated", fresnel="none")
            for tl, pl, tv, pv in CASES:
                l, v = _dir(tl, pl).astype(dtype), _dir(tv, pv).astype(dtype)  # noqa: E741
                with warnings.catch_warnings():
                    warnings.simplefilter("error")
                    got = ct.eval(N.astype(dtype), l, v)
                assert got.dtype == dtype and np.all(np.isfinite(got)) and got[0] == got[1] == got[2]
                ref = _mp_eval(ndf, alpha, l, v)
                big = float(np.finfo(dtype).max)
                if ref >= big:
                    assert float(got[0]) == big
                    continue
                if ref < np.finfo(dtype).tiny / eps:
                    assert abs(float(got[0]) - float(ref)) <= np.finfo(dtype).tiny / eps
                    continue
                cond = _condition(ndf, alpha, l, v, ref, 2.0**-60)
                err = float(abs(mpmath.mpf(float(got[0])) - ref) / ref)
                worst = max(worst, err / (eps * cond))
                assert err <= 64 * eps * cond, (alpha, (tl, pl, tv, pv), float(got[0]), float(ref), cond)
    print(f"{ndf} smith-correlated {np.dtype(dtype).name}: max error {worst:.2f} eps × condition")


@pytest.mark.parametrize("ndf", NDFS)
def test_correlated_g2_between_product_and_minimum(ndf):
    # G1(v) G1(l) <= G2 <= min(G1(v), G1(l)): 1 + Λv + Λl <= (1 + Λv)(1 + Λl), and >= 1 + max(Λv, Λl).
    rng = np.random.default_rng(21)
    l = np.abs(rng.normal(size=(4000, 3))) * [1, 1, 1]  # noqa: E741
    v = rng.normal(size=(4000, 3))
    v[:, 2] = np.abs(v[:, 2])
    l[:1000, 2] *= 1e-6  # grazing
    for alpha in (1e-3, 0.1, 0.5, 1.0, 3.0):
        corr = CookTorrance(1.0, alpha, 1.0, ndf=ndf, geometry="smith-correlated")
        sep = CookTorrance(1.0, alpha, 1.0, ndf=ndf, geometry="smith")
        g = Geometry(N, l, v)
        g2 = corr.G(g)
        g1v = (mf.smith_g1_ggx if ndf == "ggx" else mf.smith_g1_beckmann)(g.n_dot_v, alpha, g.sin2_v)
        g1l = (mf.smith_g1_ggx if ndf == "ggx" else mf.smith_g1_beckmann)(g.n_dot_l, alpha, g.sin2_l)
        tol = 4 * np.finfo(float).eps
        assert np.all(g2 >= sep.G(g) * (1 - tol))
        assert np.all(g2 <= np.minimum(g1v, g1l) * (1 + tol))
        assert np.all((g2 >= 0) & (g2 <= 1))


def _albedo_normal_incidence_mp(ndf, alpha, geometry):
    """ρ(0) with F = 1: v = n, l at 2θ_h, dω_l = 4 (n·h) dω_h; Λ(v) = 0, so G2 = G1(l) = G1(v) G1(l)."""
    a = mpmath.mpf(alpha)

    def integrand(t):
        c, s2 = mpmath.cos(t), mpmath.sin(t) ** 2
        nl = mpmath.cos(2 * t)
        lam_l = _mp_lambda(ndf, nl, mpmath.sin(2 * t) ** 2, a)
        g = 1 / (1 + lam_l) if geometry == "smith-correlated" else 1 / (1 + lam_l)
        return 2 * mpmath.pi * _mp_ndf(ndf, c, s2, a) * g * c * mpmath.sin(t)

    pts = sorted({0, min(a / 4, mpmath.pi / 4), min(a, mpmath.pi / 4), mpmath.pi / 4})
    return mpmath.quad(integrand, pts)


def test_correlated_ggx_albedo_at_normal_incidence_alpha_one_is_one_minus_ln2():
    # Issue 16 asks for 1 − ln 2 exactly.  It holds: at θ_v = 0, Λ(v) = 0, so G2 = G1(l) (the same as the
    # separable form), and with α = 1 GGX's D = 1/π, G1(l) = 2 cos 2θ_h / (1 + cos 2θ_h) = cos 2θ_h / cos²θ_h:
    # ρ = ∫_0^{π/4} (1/π) (cos 2θ/cos²θ) cos θ 2π sin θ dθ = ∫_{1/√2}^{1} 2 (2c² − 1)/c dc = 1 − ln 2.
    with mpmath.workdps(40):
        exact = _albedo_normal_incidence_mp("ggx", 1.0, "smith-correlated")
        assert abs(exact - (1 - mpmath.log(2))) < mpmath.mpf(10) ** -30
    ct = CookTorrance(1.0, 1.0, 1.0, ndf="ggx", geometry="smith-correlated", fresnel="none")
    assert directional_albedo(ct, 0.0)[0] == pytest.approx(1 - math.log(2), rel=1e-12)
    v = direction(0.0)
    assert hemisphere(lambda l: ct.eval_cos(N, l, v)[..., 0]) == pytest.approx(1 - math.log(2), rel=1e-9)


@pytest.mark.parametrize("ndf", NDFS)
@pytest.mark.parametrize("alpha", [0.05, 0.3, 1.0, 2.0])
def test_correlated_albedo_is_at_most_one_and_above_the_separable(ndf, alpha):
    corr = CookTorrance(1.0, alpha, 1.0, ndf=ndf, geometry="smith-correlated", fresnel="none")
    sep = CookTorrance(1.0, alpha, 1.0, ndf=ndf, geometry="smith", fresnel="none")
    for tv in (0.0, 0.7, 1.3, 1.5, 1.57):
        a, b = directional_albedo(corr, tv)[0], directional_albedo(sep, tv)[0]
        assert a <= 1.0 + 1e-6  # quadrature error near 1 for the sharp lobes: ~1e-8
        assert a >= b * (1 - 1e-9)
        if tv == 0.0:
            assert a == pytest.approx(b, rel=1e-10)  # Λ(v) = 0 at the normal: the two forms agree


@pytest.mark.parametrize("ndf", NDFS)
def test_correlated_reciprocity(ndf):
    rng = np.random.default_rng(7)
    d = rng.normal(size=(2, 500, 3))
    d[..., 2] = np.abs(d[..., 2]) + 1e-3
    l, v = d  # noqa: E741
    ct = CookTorrance(1.0, 0.4, 0.3, ndf=ndf, geometry="smith-correlated", fresnel="dielectric")
    np.testing.assert_allclose(ct.eval(N, l, v), ct.eval(N, v, l), rtol=1e-13, atol=0)


@pytest.mark.parametrize("ndf", (*NDFS, "blinn-phong"))
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_correlated_finite_at_extremes(ndf, dtype):
    rng = np.random.default_rng(3)
    d = rng.normal(size=(3, 300, 3))
    d[0, :50] = 0.0  # zero normals
    d[1, 50:100] = [1.0, 0.0, 0.0]  # light on the horizon
    d[2, 100:150] = [-1.0, 0.0, 1e-30]  # viewer a hair above it
    d[1, 150:200] = -d[2, 150:200]  # l = −v
    d = d.astype(dtype)
    for alpha in (1e-6, 1e-3, 1.0, 1e3):
        ct = CookTorrance(1.0, alpha, 0.04, ndf=ndf, geometry="smith-correlated")
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            for f in (ct.eval(*d), ct.eval_cos(*d), ct.classic(*d), ct.G(Geometry(*d))):
                assert f.dtype == dtype and np.all(np.isfinite(f)) and np.all(f >= 0)
        assert np.all(ct.eval(*d)[:50] == 0)


def test_parameter_table_and_lobe():
    ct = CookTorrance(geometry="smith-correlated")
    row = next(p for p in CookTorrance.parameters if p.name == "geometry")
    assert "smith-correlated" in row.choices and row.choices == CookTorrance.GEOMETRIES
    assert ct.lobe().horizon == "smith"
    assert "smith-correlated" in ct.summary()
    assert CookTorrance.from_dict(ct.to_dict()).geometry == "smith-correlated"


# --------------------------------------------------------------------------- visible-normal sampling
VIEWS_DEG = (0.0, 40.0, 75.0, 85.0, 89.0)
SAMPLER_CASES = [(ndf, a) for ndf in NDFS for a in (0.1, 0.5, 1.0)]


def _view(theta_deg, phi=0.0):
    return _dir(math.radians(theta_deg), phi)


def _chi2_pvalue(sampler, v, count=100_000, seed=2024, na=24, nph=32, order=32):
    """χ² of ``sample`` against ``pdf`` (Mitsuba's test) on cells that follow the lobe, sparse cells pooled.

    The cells are polar about the mirror direction ``R_v`` (where the microfacet lobe is), with
    ``ψ = π a²`` for ``a`` in ``na`` equal steps (fine near the axis, where a narrow lobe lives) and
    ``φ`` in ``nph`` steps: uniform ``cos θ`` cells cannot resolve a lobe of ``α = 0.1`` squeezed
    against the horizon at grazing views.  Each cell's expected count is the density integrated by
    ``order × order`` Gauss–Legendre points with the Jacobian ``dω = sin ψ dψ dφ`` (32: the density jumps
    to 0 where ``v·h`` does, and 10 points per cell left a bias that 400 000 samples at 89° detect).
    """
    axis = np.array([-v[0], -v[1], v[2]])
    t = np.cross(axis, [0.0, 1.0, 0.0] if abs(axis[1]) < 0.9 else [1.0, 0.0, 0.0])
    t /= np.linalg.norm(t)
    b = np.cross(axis, t)
    d = sampler.sample(np.random.default_rng(seed).random((count, 2)), v).directions
    psi = np.arctan2(np.linalg.norm(np.cross(d, axis), axis=-1), d @ axis)
    ai = np.minimum((np.sqrt(psi / math.pi) * na).astype(int), na - 1)
    pj = np.minimum((np.mod(np.arctan2(d @ b, d @ t), 2 * math.pi) / (2 * math.pi) * nph).astype(int), nph - 1)
    counts = np.bincount(ai * nph + pj, minlength=na * nph).astype(float)
    x, w = np.polynomial.legendre.leggauss(order)
    a_edges = np.arange(na + 1) / na
    p_edges = np.arange(nph + 1) * 2 * math.pi / nph
    ac = (a_edges[:-1, None] + a_edges[1:, None]) / 2 + (a_edges[1:, None] - a_edges[:-1, None]) / 2 * x
    pc = (p_edges[:-1, None] + p_edges[1:, None]) / 2 + (p_edges[1:, None] - p_edges[:-1, None]) / 2 * x
    aa, pp = ac[:, None, :, None], pc[None, :, None, :]
    ps = math.pi * aa**2
    jac = np.sin(ps) * 2 * math.pi * aa  # dω = sin ψ dψ dφ, dψ = 2π a da
    dirs = (np.cos(ps)[..., None] * axis + (np.sin(ps) * np.cos(pp))[..., None] * t
            + (np.sin(ps) * np.sin(pp))[..., None] * b)
    dens = sampler.pdf(dirs, v) * jac
    cell = (1 / na) * (2 * math.pi / nph) / 4
    expected = count * np.sum(dens * w[:, None] * w[None, :], axis=(-2, -1)).ravel() * cell
    order_ = np.argsort(expected)
    e_sorted, c_sorted = expected[order_], counts[order_]
    small = np.cumsum(e_sorted) < 50
    e_bins = np.r_[e_sorted[small].sum(), e_sorted[~small]]
    c_bins = np.r_[c_sorted[small].sum(), c_sorted[~small]]
    keep = e_bins > 0
    chi2 = np.sum((c_bins[keep] - e_bins[keep]) ** 2 / e_bins[keep])
    return float(stats.chi2.sf(chi2, keep.sum() - 1)), float(expected.sum() / count)


@pytest.mark.parametrize("ndf, alpha", SAMPLER_CASES)
@pytest.mark.parametrize("theta_v", VIEWS_DEG)
def test_visible_normal_sampler_chi_square(ndf, alpha, theta_v):
    p, mass = _chi2_pvalue(VisibleNormalSampler(ndf, alpha), _view(theta_v, 0.3))
    print(f"χ² {ndf} α={alpha} θ_v={theta_v}°: p = {p:.3g}, binned mass {mass:.6f}")
    assert mass == pytest.approx(1.0, abs=3e-3)  # the density's integral, by the cells' quadrature
    assert p > 1e-3


def _density_integral(sampler, v, alpha):
    """``∫ p(l) dω_l`` over the sphere, as ``∫ p(l(h)) 4 (v·h) dω_h`` over the normals that reflect ``v`` to ``l``.

    Every ``l ≠ −v`` is ``2 (v·h) h − v`` for exactly one ``h`` with ``n·h > 0``; where that ``h`` has
    ``v·h <= 0`` the density is 0, a jump in ``l``.  In ``h`` the integrand vanishes linearly there, and for
    each ``θ_h`` the ``φ`` interval with ``v·h > 0`` (``cos(φ − φ_v) > −cot θ_v cot θ_h``) is integrated by
    Gauss–Legendre, so no node straddles the cut.
    """
    from quadrature import theta_nodes

    th, wt = theta_nodes(scale=alpha * 1e-3, panels=60, order=24)
    tv, pv = math.acos(v[2]), math.atan2(v[1], v[0])
    with np.errstate(divide="ignore"):
        lim = np.clip(-np.cos(tv) * np.cos(th) / (np.sin(tv) * np.sin(th)), -1, 1) if tv > 0 else -np.ones_like(th)
    half = np.arccos(lim)  # the half-width of the φ interval with v·h > 0
    x, w = np.polynomial.legendre.leggauss(96)
    ph = pv + half[:, None] * x
    wp = half[:, None] * w
    h = np.stack(np.broadcast_arrays(np.sin(th)[:, None] * np.cos(ph), np.sin(th)[:, None] * np.sin(ph),
                                     np.cos(th)[:, None]), -1)
    vh = h @ v
    l = 2 * vh[..., None] * h - v  # noqa: E741
    f = sampler.pdf(l, v) * 4 * np.maximum(vh, 0)
    return float(np.sum(f * wp * (wt * np.sin(th))[:, None]))


@pytest.mark.parametrize("ndf, alpha", SAMPLER_CASES)
@pytest.mark.parametrize("theta_v", VIEWS_DEG)
def test_visible_normal_density_integrates_to_one(ndf, alpha, theta_v):
    v = _view(theta_v, 0.7)
    # Measured: within 1.2e-7 of 1 (the quadrature's own error where the cut meets the φ interval's ends).
    assert _density_integral(VisibleNormalSampler(ndf, alpha), v, alpha) == pytest.approx(1.0, abs=1e-6)


@pytest.mark.parametrize("ndf", NDFS)
def test_visible_normal_density_formula_and_weights(ndf):
    # p(l) = G1(v) D(h) max(0, v·h) / (n·v) / (4 v·h), and the weight f (n·l)/p = F G1(l) (separable) <= F.
    rng = np.random.default_rng(5)
    alpha = 0.35
    s = VisibleNormalSampler(ndf, alpha)
    g1 = mf.smith_g1_ggx if ndf == "ggx" else mf.smith_g1_beckmann
    d = mf.ggx_ndf if ndf == "ggx" else mf.beckmann_ndf
    for tv in (0.0, 30.0, 70.0, 89.0):
        v = _view(tv, 1.1)
        smp = s.sample(rng.random((4000, 2)), v)
        l = smp.directions  # noqa: E741
        h = (l + v) / np.linalg.norm(l + v, axis=-1, keepdims=True)
        vh = h @ v
        want = g1(v[2], alpha) * d(h[:, 2], alpha) * np.maximum(vh, 0) / v[2] / (4 * vh)
        np.testing.assert_allclose(smp.pdf, want, rtol=1e-10)
        np.testing.assert_allclose(s.pdf(l, v), smp.pdf, rtol=1e-12)
        assert np.all(vh > 0) and np.all(h[:, 2] > 0)
        up = l[:, 2] > 1e-9
        for geometry in ("smith", "smith-correlated"):
            ct = CookTorrance(1.0, alpha, 1.0, ndf=ndf, geometry=geometry, fresnel="none")
            assert isinstance(ct.sampler(), VisibleNormalSampler)
            w = ct.eval_cos(N, l[up], v)[:, 0] / smp.pdf[up]
            assert np.all(w <= 1 + 1e-12)
            if geometry == "smith":
                np.testing.assert_allclose(w, g1(l[up, 2], alpha), rtol=1e-9, atol=1e-300)


def test_samplers_of_the_other_settings_are_unchanged():
    assert type(CookTorrance(geometry="v-cavity", ndf="ggx").sampler()) is MicrofacetSampler
    assert type(CookTorrance(geometry="smith", ndf="blinn-phong").sampler()) is MicrofacetSampler
    assert repr(CookTorrance(geometry="smith", ndf="beckmann", roughness=0.2).sampler()) == (
        "VisibleNormalSampler('beckmann', alpha=0.2)")


@pytest.mark.parametrize("ndf", NDFS)
def test_visible_normal_sampler_below_the_horizon_falls_back(ndf):
    s, m = VisibleNormalSampler(ndf, 0.4), MicrofacetSampler(ndf, 0.4)
    v = np.array([0.6, 0.0, -0.8])
    u = np.random.default_rng(2).random((100, 2))
    a, b = s.sample(u, v), m.sample(u, v)
    np.testing.assert_array_equal(a.directions, b.directions)
    np.testing.assert_array_equal(a.pdf, b.pdf)
    np.testing.assert_array_equal(s.pdf(a.directions, v), m.pdf(a.directions, v))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for vv in ([0.0, 0.0, 1.0], [1.0, 0.0, 1e-300], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]):
            out = s.sample(u, vv)
            assert np.all(np.isfinite(out.directions)) and np.all(np.isfinite(out.pdf)) and np.all(out.pdf >= 0)
            assert np.all(np.isfinite(s.pdf(out.directions, vv)))
        # extreme roughness
        for al in (1e-6, 1e3):
            out = VisibleNormalSampler(ndf, al).sample(u, [0.3, 0.0, 0.9])
            assert np.all(np.isfinite(out.directions)) and np.all(np.isfinite(out.pdf))


@pytest.mark.parametrize("ndf", NDFS)
@pytest.mark.parametrize("geometry", ["smith", "smith-correlated"])
def test_importance_sampled_albedo_matches_quadrature(ndf, geometry):
    ct = CookTorrance(1.0, 0.4, 1.0, ndf=ndf, geometry=geometry, fresnel="none")
    for tv in (0.3, 1.45):
        ref = directional_albedo(ct, tv)[0]
        est = directional_albedo(ct, tv, 8192, "importance", seed=4, return_error=True)
        assert abs(est.value[0] - ref) <= 4 * est.error[0] + 1e-12

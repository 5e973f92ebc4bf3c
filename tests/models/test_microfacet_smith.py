"""Smith masking–shadowing: Λ, the height-correlated G2 (``geometry="smith-correlated"``), visible-normal sampling.

References: E. Heitz, "Understanding the masking-shadowing function in microfacet-based BRDFs",
JCGT 3(2), 2014 (Λ, eqs. 72 and 86; G2 = 1/(1 + Λ(v) + Λ(l)), eq. 99); E. Heitz, "Sampling the GGX
distribution of visible normals", JCGT 7(4), 2018.

The 80-digit values are :mod:`lighting.validation.model_references`'s (Λ, D and the Cook–Torrance value).
The visible-normal samplers' χ² (isotropic and anisotropic, 0° to 89°) is in test_sampler_grazing_full.py;
here their densities, formulas and weights.
"""

from __future__ import annotations

import math
import warnings

import mpmath
import numpy as np
import pytest
from quadrature import direction, evaluate, half_vector_integral, half_vector_nodes, half_vector_sum, hemisphere

from lighting.integrate import directional_albedo
from lighting.models import microfacet as mf
from lighting.models.base import BRDFFlags
from lighting.models.cook_torrance import CookTorrance
from lighting.models.geometry import Geometry
from lighting.sampling.microfacet import MicrofacetSampler, VisibleNormalSampler
from lighting.shading.separable import stacks
from lighting.validation import model_references as mr

pytestmark = pytest.mark.slow  # 80-digit references, quadratures, grazing χ²; fast: test_contract.py

N = np.array([0.0, 0.0, 1.0])
NDFS = ("beckmann", "ggx")


# --------------------------------------------------------------------------- 80-digit references
# The formulas' one home is lighting.validation.model_references; these wrappers take the tests' arguments.
def _mp(x):
    return x if isinstance(x, mpmath.mpf) else mpmath.mpf(float(x))


def _mp_lambda(ndf, c, s2, alpha):
    """Λ from the (exact) cosine and squared sine at the working precision (erfc, not erf − 1, which cancels)."""
    a = _mp(alpha)
    return mr.smith_lambda(ndf, mpmath.sqrt(_mp(s2)), mpmath.mpf(0), _mp(c), a, a)


def _mp_ndf(ndf, c, s2, al):
    """``D`` of the isotropic NDF at ``cos θ_h = c``, ``sin²θ_h = s2``."""
    a = _mp(al)
    return mr.microfacet_ndf(ndf, mpmath.sqrt(_mp(s2)), mpmath.mpf(0), _mp(c), a, a)


def _mp_eval_aniso(ndf, ax, ay, geometry, l, v, t=None):  # noqa: E741
    """``D G / (4 (n·v)(n·l))`` (F = 1, n = z, tangent ``t``) from the given vectors taken as exact, at the
    working precision."""
    q = mr.frame((0, 0, 1), [_mp(x) for x in l], [_mp(x) for x in v], None if t is None else [_mp(x) for x in t])
    if not q["above"]:
        return mpmath.mpf(0)
    one = mpmath.mpf(1)
    return mr.microfacet(q, one, ndf, _mp(ax), _mp(ay), geometry, "none", one)


def _mp_eval(ndf, alpha, l, v):  # noqa: E741
    """``D G2 / (4 (n·v)(n·l))`` (height-correlated, F = 1, n = z) from the given vectors taken as exact."""
    return _mp_eval_aniso(ndf, alpha, alpha, "smith-correlated", l, v)


def _condition(ndf, alpha, l, v, f0, eps):  # noqa: E741
    """A condition estimate: the largest relative change of the 80-digit value per relative input change ``eps``."""
    rng = np.random.default_rng(1)
    worst = 1.0
    for _ in range(4):  # the perturbation in 80 digits (1 + 2⁻⁶⁰ is 1 in float64)
        dl = [_mp(x) * (1 + eps * int(sg)) for x, sg in zip(l, rng.choice([-1, 1], 3), strict=True)]
        dv = [_mp(x) * (1 + eps * int(sg)) for x, sg in zip(v, rng.choice([-1, 1], 3), strict=True)]
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
    # The closed form is 1 − ln 2 exactly.  It holds: at θ_v = 0, Λ(v) = 0, so G2 = G1(l) (the same as the
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


def _density_integral(sampler, v, alpha):
    """``∫ p(l) dω_l`` over the sphere, as ``∫ p(l(h)) 4 (v·h) dω_h`` over the normals that reflect ``v`` to ``l``.

    Every ``l ≠ −v`` is ``2 (v·h) h − v`` for exactly one ``h`` with ``n·h > 0``; where that ``h`` has
    ``v·h <= 0`` the density is 0, a jump in ``l``.  In ``h`` the integrand vanishes linearly there, and
    :func:`quadrature.half_vector_integral` integrates each ``θ_h``'s ``φ`` interval with ``v·h > 0`` by
    Gauss–Legendre, so no node straddles the cut.
    """

    def integrand(h):
        vh = h @ v
        return sampler.pdf(2 * vh[..., None] * h - v, v) * 4 * np.maximum(vh, 0)

    return half_vector_integral(integrand, alpha, v)


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
        "VisibleNormalSampler('beckmann', alpha=0.2)"
    )


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


# --------------------------------------------------------------------------- anisotropic GGX and Beckmann
ANISO = [(0.1, 0.5), (0.05, 1.0), (1.0, 0.3), (0.3, 0.3 * (1 + 2**-40))]


def _d_aniso(ndf, h, ax, ay):
    f = mf._ggx_ndf_aniso if ndf == "ggx" else mf._beckmann_ndf_aniso
    return f(h[..., 0], h[..., 1], h[..., 2], ax, ay, np.float64)


def _g1_aniso(ndf, w, ax, ay):
    lc = mf._smith_lambda_cos_aniso(ndf, w[..., 0], w[..., 1], w[..., 2], ax, ay)
    c = np.maximum(w[..., 2], 0.0)
    return np.where(c > 0, c / np.where(c > 0, c + lc, 1.0), 0.0)


def _ndf_and_g1(ndf, ax, ay):
    """``D(h)`` and ``G1(ω)`` for an NDF: isotropic (the public functions) or anisotropic (the model's)."""
    if ax == ay:
        d = {"ggx": mf.ggx_ndf, "beckmann": mf.beckmann_ndf}[ndf]
        g1 = {"ggx": mf.smith_g1_ggx, "beckmann": mf.smith_g1_beckmann}[ndf]

        def dfun(h):
            return d(h[..., 2], ax, np.clip(h[..., 0] ** 2 + h[..., 1] ** 2, 0, 1))

        def gfun(w):
            return g1(w[..., 2], ax, np.clip(w[..., 0] ** 2 + w[..., 1] ** 2, 0, 1))

        return dfun, gfun
    return (lambda h: _d_aniso(ndf, h, ax, ay)), (lambda w: _g1_aniso(ndf, w, ax, ay))


@pytest.mark.parametrize("ndf", NDFS)
@pytest.mark.parametrize("ax, ay", [(a, a) for a in (1e-3, 0.1, 0.5, 1.0, 2.0)] + ANISO)
def test_ndf_normalization_and_projected_area(ndf, ax, ay):
    # ∫ D(h)(n·h) dω_h = 1, and ∫ G1(v) max(0, v·h) D(h) dω_h = n·v (the projected area of the visible
    # microsurface equals that of the macrosurface; Heitz 2014 eq. 12), for views up to 89° at several azimuths.
    dfun, gfun = _ndf_and_g1(ndf, ax, ay)
    a = min(ax, ay)
    # The whole circle's nodes (the normalization's, and the normal view's: v·h > 0 on every ring), with D on
    # them evaluated once; each integral the same products at every node, summed as half_vector_integral sums it.
    whole = half_vector_nodes(a)
    d_whole = evaluate(dfun, whole[0])
    assert half_vector_sum(d_whole * whole[0][..., 2], whole) == pytest.approx(1.0, abs=1e-9)
    for tv, pv in ((0.0, 0.0), (0.6, 0.4), (1.2, 2.0), (1.5, -0.9), (math.radians(89), 0.8)):
        v = _dir(tv, pv)
        g1v = gfun(v)  # the view's masking, the same at every node
        if v[2] >= 1:  # half_vector_integral's whole circle
            masked = evaluate(lambda h, v=v, g1v=g1v: g1v * np.maximum(h @ v, 0), whole[0])
            got = half_vector_sum(masked * d_whole, whole)
        else:
            got = half_vector_integral(lambda h, v=v, g1v=g1v: g1v * np.maximum(h @ v, 0) * dfun(h), a, v)
        assert got == pytest.approx(v[2], rel=1e-7, abs=1e-12), (tv, pv)


def test_blinn_phong_ndf_normalization():
    # The third NDF: (e + 2)/(2π) (n·h)^e with e = 2/α² − 2 (its Smith G1 is Beckmann's of the same α, an
    # approximation, so the projected-area identity holds only approximately and is not asserted).
    for alpha in (0.05, 0.3, 1.0):
        ct = CookTorrance(1.0, alpha, 1.0, ndf="blinn-phong")
        total = half_vector_integral(lambda h, e=ct._exponent: mf.blinn_phong_ndf(h[..., 2], e) * h[..., 2], alpha)
        assert total == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize("ndf", (*NDFS, "blinn-phong"))
@pytest.mark.parametrize("geometry", CookTorrance.GEOMETRIES)
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_equal_alphas_are_the_isotropic_model_bit_for_bit(ndf, geometry, dtype):
    rng = np.random.default_rng(8)
    n, l, v = (rng.normal(size=(400, 3)).astype(dtype) for _ in range(3))  # noqa: E741
    t = rng.normal(size=(400, 3)).astype(dtype)
    for alpha in (1e-6, 0.2, 1.0):
        iso = CookTorrance(0.8, alpha, 0.3, ndf=ndf, geometry=geometry, fresnel="dielectric")
        same = CookTorrance(
            0.8, 0.77, 0.3, ndf=ndf, geometry=geometry, fresnel="dielectric", alpha_x=alpha, alpha_y=alpha
        )
        assert not same.anisotropic and same.stackable and iso.stackable
        for form in ("eval", "eval_cos", "classic"):
            want = getattr(iso, form)(n, l, v)
            np.testing.assert_array_equal(getattr(same, form)(n, l, v), want)
            np.testing.assert_array_equal(getattr(same, form)(n, l, v, tangent=t), want)
        assert repr(same.sampler()) == repr(iso.sampler())


@pytest.mark.parametrize("ndf", NDFS)
@pytest.mark.parametrize("geometry", CookTorrance.GEOMETRIES)
def test_anisotropic_code_at_nearly_equal_alphas_matches_isotropic(ndf, geometry):
    # α_y = α_x (1 + 2⁻⁴⁰) takes the anisotropic code: it agrees with the isotropic model to 2⁻⁴⁰ times the
    # α-sensitivity (|∂ ln f/∂ ln α| <= 6 + 4X, X = tan²θ_h/α² for Beckmann, 0 for GGX) plus rounding 64 eps (1 + X).
    rng = np.random.default_rng(9)
    l, v = rng.normal(size=(2, 600, 3))  # noqa: E741
    l[:, 2], v[:, 2] = np.abs(l[:, 2]), np.abs(v[:, 2])
    for alpha in (0.05, 0.3, 1.0):
        iso = CookTorrance(1.0, alpha, 1.0, ndf=ndf, geometry=geometry, fresnel="none")
        an = CookTorrance(
            1.0, alpha, 1.0, ndf=ndf, geometry=geometry, fresnel="none", alpha_x=alpha, alpha_y=alpha * (1 + 2**-40)
        )
        assert an.anisotropic and not an.stackable
        a, b = iso.eval(N, l, v)[:, 0], an.eval(N, l, v)[:, 0]
        g = Geometry(N, l, v)
        x = (g.sin2_h / np.maximum(g.n_dot_h, 1e-300) ** 2) / alpha**2
        x = x if ndf == "beckmann" else 0 * x
        bound = 2.0**-40 * (6 + 4 * x) + 64 * np.finfo(float).eps * (1 + x)
        rel = np.abs(a - b) / np.maximum(a, 1e-300)
        assert np.all((rel <= bound) | (a < 1e-290)), float(np.max(rel / bound))


@pytest.mark.parametrize("ndf", NDFS)
@pytest.mark.parametrize("geometry", ["smith", "smith-correlated"])
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_anisotropic_eval_matches_80_digits(ndf, geometry, dtype):
    # Relative error ≤ 64 eps × (a condition estimate: 1 + the 80-digit value's relative change per relative
    # change of the tangent's angle and of the components of l and v); below tiny/eps of the dtype, absolute.
    eps = float(np.finfo(dtype).eps)
    rng = np.random.default_rng(12)
    worst = 0.0
    with mpmath.workdps(80):
        for ax, ay in ((0.1, 0.5), (0.02, 0.3), (1.0, 0.2), (1e-4, 1e-2), (3.0, 0.7)):
            ct = CookTorrance(1.0, 0.5, 1.0, ndf=ndf, geometry=geometry, fresnel="none", alpha_x=ax, alpha_y=ay)
            for tl, pl, tv, pv in CASES:
                phi_t = float(rng.uniform(0, 2 * math.pi))
                t = np.array([math.cos(phi_t), math.sin(phi_t), 0.0]).astype(dtype)
                l, v = _dir(tl, pl).astype(dtype), _dir(tv, pv).astype(dtype)  # noqa: E741
                with warnings.catch_warnings():
                    warnings.simplefilter("error")
                    got = float(ct.eval(N.astype(dtype), l, v, tangent=t)[0])
                ref = _mp_eval_aniso(ndf, ax, ay, geometry, l, v, t)
                if ref >= np.finfo(dtype).max:
                    assert got == float(np.finfo(dtype).max)
                    continue
                if ref < np.finfo(dtype).tiny / eps:
                    assert abs(got - float(ref)) <= np.finfo(dtype).tiny / eps
                    continue
                # condition: relative change per relative change of the tangent's angle and the directions
                d = 2.0**-60
                t2 = [_mp(t[0]) - d * _mp(t[1]), _mp(t[1]) + d * _mp(t[0]), 0]  # turned by d, in 80 digits
                c1 = abs(_mp_eval_aniso(ndf, ax, ay, geometry, l, v, t2) - ref) / ref / d
                c3 = 0.0
                for sl, sv in (([1, -1, -1], [0, 0, 0]), ([0, 0, 0], [-1, 1, -1]), ([-1, 1, 1], [1, 1, -1])):
                    dl = [_mp(x) * (1 + d * k) for x, k in zip(l, sl, strict=True)]
                    dv = [_mp(x) * (1 + d * k) for x, k in zip(v, sv, strict=True)]
                    c3 = max(c3, float(abs(_mp_eval_aniso(ndf, ax, ay, geometry, dl, dv, t) - ref) / ref / d))
                cond = 1 + float(c1) + c3
                err = float(abs(mpmath.mpf(got) - ref) / ref)
                worst = max(worst, err / (eps * cond))
                assert err <= 64 * eps * cond, (ax, ay, (tl, pl, tv, pv), got, float(ref), cond)
    print(f"anisotropic {ndf} {geometry} {np.dtype(dtype).name}: max error {worst:.2f} eps × condition")


@pytest.mark.parametrize("ndf", NDFS)
def test_anisotropic_tangent_rotation_swaps_the_alphas_and_reciprocity(ndf):
    rng = np.random.default_rng(13)
    l, v = rng.normal(size=(2, 500, 3))  # noqa: E741
    l[:, 2], v[:, 2] = np.abs(l[:, 2]) + 1e-3, np.abs(v[:, 2]) + 1e-3
    n = np.array([0.2, -0.3, 1.0])
    t = np.cross(n, [0.3, 1.0, 0.1])
    a = CookTorrance(1.0, 0.5, 0.2, ndf=ndf, geometry="smith-correlated", alpha_x=0.1, alpha_y=0.6)
    b = CookTorrance(1.0, 0.5, 0.2, ndf=ndf, geometry="smith-correlated", alpha_x=0.6, alpha_y=0.1)
    bt = np.cross(n / np.linalg.norm(n), t / np.linalg.norm(t))
    np.testing.assert_allclose(a.eval(n, l, v, tangent=t), b.eval(n, l, v, tangent=bt), rtol=1e-10, atol=1e-300)
    np.testing.assert_allclose(a.eval(n, l, v, tangent=t), a.eval(n, v, l, tangent=t), rtol=1e-12, atol=0)
    # −t is the same frame up to φ → φ + π, under which D and Λ are even.
    np.testing.assert_allclose(a.eval(n, l, v, tangent=t), a.eval(n, l, v, tangent=-t), rtol=1e-12, atol=1e-300)
    # The default frame (no tangent) is t = ẑ × n / |ẑ × n|.
    tz = np.cross([0.0, 0.0, 1.0], n)
    # (the two frames differ in the last bits of t, which Beckmann's exponent X <= 700 amplifies)
    np.testing.assert_allclose(a.eval(n, l, v), a.eval(n, l, v, tangent=tz), rtol=1e-10, atol=1e-300)


@pytest.mark.parametrize("ndf", NDFS)
@pytest.mark.parametrize("geometry", CookTorrance.GEOMETRIES)
def test_anisotropic_albedo_at_most_one(ndf, geometry):
    ct = CookTorrance(1.0, 0.5, 1.0, ndf=ndf, geometry=geometry, fresnel="none", alpha_x=0.08, alpha_y=0.6)
    for tv in (0.0, 0.8, 1.4, 1.55):
        assert directional_albedo(ct, tv)[0] <= 1.0 + 1e-6


@pytest.mark.parametrize("ndf", NDFS)
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_anisotropic_finite_at_extremes(ndf, dtype):
    rng = np.random.default_rng(3)
    d = rng.normal(size=(4, 300, 3))
    d[0, :50] = 0.0
    d[1, 50:100] = [1.0, 0.0, 0.0]
    d[2, 100:150] = [-1.0, 0.0, 1e-30]
    d[1, 150:200] = -d[2, 150:200]
    d[3, 200:250] = d[0, 200:250]  # tangent along n: the default frame
    d[3, 250:] = 0.0  # zero tangent
    d = d.astype(dtype)
    for ax, ay in ((1e-6, 1e-3), (1e-3, 1e3), (1.0, 0.01)):
        for geometry in CookTorrance.GEOMETRIES:
            ct = CookTorrance(1.0, 0.5, 0.04, ndf=ndf, geometry=geometry, alpha_x=ax, alpha_y=ay)
            with warnings.catch_warnings():
                warnings.simplefilter("error")
                for form in (ct.eval, ct.eval_cos, ct.classic):
                    f = form(*d[:3], tangent=d[3])
                    assert f.dtype == dtype and np.all(np.isfinite(f)) and np.all(f >= 0)


def test_anisotropic_parameters_and_stackable():
    # Stackable is the separable extension's answer per instance: every isotropic model, no anisotropic one.
    assert CookTorrance().stackable is True and stacks(CookTorrance())
    assert CookTorrance(alpha_x=0.3, alpha_y=0.3).stackable is True
    an = CookTorrance(alpha_x=0.1, alpha_y=0.4, ndf="ggx", geometry="smith")
    assert an.stackable is False and an.anisotropic and not stacks(an)
    assert BRDFFlags.ANISOTROPIC in an.flags and BRDFFlags.ANISOTROPIC not in CookTorrance().flags
    assert "αx=0.1 αy=0.4" in an.summary()
    assert CookTorrance.from_dict(an.to_dict()).to_dict() == an.to_dict()
    assert "alpha_x" not in CookTorrance().to_dict()
    assert CookTorrance(alpha_x=0.2).anisotropic  # α_y defaults to roughness 0.3
    assert repr(an.sampler()) == "VisibleNormalSampler('ggx', alpha=0.1, alpha_y=0.4)"
    with pytest.raises(ValueError, match="alpha_x"):
        CookTorrance(alpha_x=-1.0)
    with pytest.raises(ValueError, match="blinn-phong"):
        CookTorrance(ndf="blinn-phong", alpha_x=0.1, alpha_y=0.2)


@pytest.mark.parametrize("ndf", NDFS)
@pytest.mark.parametrize("ax, ay", [(0.1, 0.5), (1.0, 0.2)])
@pytest.mark.parametrize("theta_v, phi_v", [(0.0, 0.0), (50.0, 0.7), (85.0, 2.0), (89.0, -1.0)])
def test_anisotropic_sampler_density(ndf, ax, ay, theta_v, phi_v):
    # (Its χ², anisotropic lobes along and across the tangent at 0° to 89°: test_sampler_grazing_full.py.)
    s = VisibleNormalSampler(ndf, ax, alpha_y=ay)
    v = _view(theta_v, phi_v)
    assert _density_integral(s, v, min(ax, ay)) == pytest.approx(1.0, abs=1e-6)
    # The density is G1(v) D(h) / (4 n·v) with the anisotropic D and G1.
    smp = s.sample(np.random.default_rng(3).random((2000, 2)), v)
    h = smp.directions + v
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    want = _g1_aniso(ndf, v, ax, ay) * _d_aniso(ndf, h, ax, ay) / (4 * v[2])
    np.testing.assert_allclose(smp.pdf, want, rtol=1e-10)

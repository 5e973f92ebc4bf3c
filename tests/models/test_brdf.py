import math

import numpy as np
import pytest
from quadrature import direction, hemisphere

from lighting import vec
from lighting.models.brdf import BlinnPhong, CookTorrance, Lambert, Phong

N = np.array([0.0, 0.0, 1.0])


def albedo(model, theta_v, **quad):
    """Directional albedo ρ(v) = ∫ f_r (n·l) dω_l by independent quadrature (channel 0)."""
    v = direction(theta_v)
    return hemisphere(lambda l: model.eval_cos(N, l, v)[..., 0], **quad)


@pytest.mark.parametrize("theta_v", [0.0, 0.5, 1.2, 1.55])
def test_lambert_albedo_is_kd(theta_v):
    assert albedo(Lambert(0.7), theta_v) == pytest.approx(0.7, rel=1e-12)


def test_lambert_value_and_rgb():
    f = Lambert((0.2, 0.4, 0.6)).eval(N, direction(0.3), direction(1.0))
    np.testing.assert_allclose(f, np.array([0.2, 0.4, 0.6]) / math.pi, rtol=1e-15)


@pytest.mark.parametrize("e", [0.0, 1.0, 10.0, 100.0])
def test_phong_albedo_at_normal_incidence(e):
    # Slides: "too much energy".  With k_s = 1 the albedo at normal incidence is 2/(e+1).
    got = albedo(Phong(1.0, e), 0.0, scale=1e-2 / math.sqrt(e + 1))
    assert got == pytest.approx(2 / (e + 1), rel=1e-9)


@pytest.mark.parametrize("e", [1.0, 20.0, 500.0])
def test_normalized_blinn_phong_ndf_integrates_to_one(e):
    # (e+2)/(2π) (n·h)^e is a normalized NDF: ∫ D (n·h) dω_h = 1.
    def d_cos(h):
        return (e + 2) / (2 * math.pi) * h[..., 2] ** e * h[..., 2]

    assert hemisphere(d_cos, scale=1e-2 / math.sqrt(e)) == pytest.approx(1.0, rel=1e-10)


def _literal_normalized_bp_albedo(e):
    a, b = 2 ** (-(e + 4) / 2), 2 ** (-(e + 2) / 2)
    return 4 * (e + 2) * (2 / (e + 4) - 1 / (e + 2) - 2 * a / (e + 4) + b / (e + 2))


@pytest.mark.parametrize("e", [0.0, 1.0, 30.0, 1000.0])
def test_normalized_blinn_phong_albedo_closed_form(e):
    # The slide's (e+2)/(2π)(n·h)^e used directly as a BRDF: albedo 1 at e = 0, toward 4 for sharp lobes.
    got = albedo(BlinnPhong(1.0, e, normalized=True), 0.0, scale=1e-2 / math.sqrt(e + 1))
    assert got == pytest.approx(_literal_normalized_bp_albedo(e), rel=1e-9)


@pytest.mark.parametrize("alpha", [0.05, 0.3, 0.8])
def test_blinn_phong_ndf_inside_cook_torrance_conserves_energy(alpha):
    ct = CookTorrance(1.0, alpha, 1.0, ndf="blinn-phong", fresnel="none")
    for tv in (0.0, 0.7, 1.3, 1.5):
        assert albedo(ct, tv, scale=alpha * 1e-2) <= 1.0


def test_normalized_blinn_phong_matches_formula():
    m = BlinnPhong(1.0, 30.0, normalized=True)
    rng = np.random.default_rng(5)
    l = vec.normalize(rng.normal(size=(50, 3)) * [1, 1, 0] + [0, 0, 1.5])  # noqa: E741
    v = vec.normalize(rng.normal(size=(50, 3)) * [1, 1, 0] + [0, 0, 1.5])
    h = vec.halfway(l, v)
    np.testing.assert_allclose(m.eval(N, l, v)[:, 1], 32 / (2 * math.pi) * h[:, 2] ** 30, rtol=1e-12)


def _pairs(k=300, seed=7):
    rng = np.random.default_rng(seed)
    d = vec.normalize(rng.normal(size=(2, k, 3)))
    d[..., 2] = np.abs(d[..., 2]) + 0.05
    return vec.normalize(d[0]), vec.normalize(d[1])


RECIPROCAL = [
    Lambert(0.5),
    BlinnPhong(0.5, 40.0, normalized=True),
    CookTorrance(1.0, 0.3, 0.04),
    CookTorrance(1.0, 0.2, 0.5, ndf="ggx", geometry="smith", fresnel="dielectric"),
    CookTorrance(1.0, 0.5, 0.9, ndf="beckmann", geometry="smith", denominator="pi"),
]


@pytest.mark.parametrize("model", RECIPROCAL, ids=repr)
def test_reciprocity_holds(model):
    l, v = _pairs()  # noqa: E741
    np.testing.assert_allclose(model.eval(N, l, v), model.eval(N, v, l), rtol=1e-12, atol=0)


@pytest.mark.parametrize("model", [Phong(1.0, 10.0), BlinnPhong(1.0, 10.0)], ids=repr)
def test_reciprocity_broken_by_division_by_n_dot_l(model):
    l, v = _pairs()  # noqa: E741
    a, b = model.eval(N, l, v)[:, 0], model.eval(N, v, l)[:, 0]
    lit = a > 1e-6
    # The numerator is symmetric (R_l·v = R_v·l, n·h); only 1/(n·l) differs.
    np.testing.assert_allclose(a[lit] / b[lit], v[lit, 2] / l[lit, 2], rtol=1e-10)
    assert np.max(np.abs(a - b) / np.maximum(a, b).clip(1e-300)) > 0.5


def test_phong_classic_term_is_the_slides_formula():
    rng = np.random.default_rng(8)
    l, v = _pairs(seed=9)  # noqa: E741
    ks, e = np.array([0.9, 0.5, 0.1]), 12.0
    r = vec.reflect(l, N)
    expected = ks * np.maximum(np.sum(r * v, -1), 0)[:, None] ** e
    np.testing.assert_allclose(Phong(ks, e).classic(N, l, v), expected, rtol=1e-10, atol=1e-15)
    # And its BRDF form divides by π (n·l).
    np.testing.assert_allclose(Phong(ks, e).eval(N, l, v), expected / (math.pi * l[:, 2:3]), rtol=1e-10, atol=1e-15)
    del rng


def test_blinn_phong_raw_classic_and_mirror_values():
    l, v = direction(0.4, 0.0), direction(0.4, math.pi)  # mirror pair: h = n
    assert BlinnPhong(0.8, 1000.0).classic(N, l, v)[0] == pytest.approx(0.8, rel=1e-14)
    assert Phong(0.8, 1000.0).classic(N, l, v)[0] == pytest.approx(0.8, rel=1e-14)
    hv = vec.halfway(direction(0.4), direction(0.9, 2.0))
    assert BlinnPhong(0.8, 7.0).classic(N, direction(0.4), direction(0.9, 2.0))[0] == pytest.approx(
        0.8 * hv[2] ** 7, rel=1e-12
    )


@pytest.mark.parametrize("model", RECIPROCAL + [Phong(0.5, 3.0), BlinnPhong(0.5, 3.0)], ids=repr)
def test_classic_equals_pi_eval_cos_equals_pi_eval_times_cos(model):
    l, v = _pairs(seed=11)  # noqa: E741
    fc = model.eval_cos(N, l, v)
    np.testing.assert_allclose(model.classic(N, l, v), math.pi * fc, rtol=1e-14, atol=1e-300)
    np.testing.assert_allclose(model.eval(N, l, v) * l[:, 2:3], fc, rtol=1e-13, atol=1e-300)


# ---------------------------------------------------------------- Cook–Torrance facts
@pytest.mark.parametrize("alpha, expected", [(0.1, 1.000), (0.5, 0.892), (1.0, 0.453)])
def test_cook_torrance_beckmann_vcavity_albedo(alpha, expected):
    ct = CookTorrance(1.0, alpha, 1.0, fresnel="none")
    assert albedo(ct, 0.0, scale=alpha * 1e-2) == pytest.approx(expected, abs=6e-4)


def test_cook_torrance_ggx_smith_albedo_is_one_minus_ln2():
    ct = CookTorrance(1.0, 1.0, 1.0, ndf="ggx", geometry="smith", fresnel="none")
    assert albedo(ct, 0.0) == pytest.approx(1 - math.log(2), rel=1e-9)


def test_pi_denominator_reflects_four_over_pi_more():
    a = CookTorrance(1.0, 0.3, 0.04, denominator="4")
    b = CookTorrance(1.0, 0.3, 0.04, denominator="pi")
    l, v = _pairs(seed=12)  # noqa: E741
    np.testing.assert_allclose(b.eval(N, l, v), 4 / math.pi * a.eval(N, l, v), rtol=1e-13)
    assert albedo(b, 0.0, scale=1e-3) == pytest.approx(4 / math.pi * albedo(a, 0.0, scale=1e-3), rel=1e-12)


def test_cook_torrance_terms_compose():
    from lighting.models.brdf import Geometry

    ct = CookTorrance((1.0, 0.5, 0.25), 0.25, (0.9, 0.6, 0.3), ndf="ggx", geometry="v-cavity")
    l, v = _pairs(seed=13)  # noqa: E741
    g = Geometry(N, l, v)
    expected = ct.D(g)[:, None] * ct.G(g)[:, None] * ct.F(g) * np.array([1.0, 0.5, 0.25])
    expected /= 4 * l[:, 2:3] * v[:, 2:3]
    np.testing.assert_allclose(ct.eval(N, l, v), expected, rtol=1e-12)


def test_sum_decomposes():
    m = Lambert(0.5) + Phong(0.3, 20.0) + BlinnPhong(0.1, 5.0)
    assert [p.term for p in m.parts] == ["diffuse", "specular", "specular"]
    l, v = _pairs(seed=14)  # noqa: E741
    total = sum(p.eval(N, l, v) for p in m.parts)
    np.testing.assert_allclose(m.eval(N, l, v), total, rtol=1e-15)
    np.testing.assert_allclose(m.diffuse_albedo, [0.5, 0.5, 0.5])


def test_below_horizon_is_zero():
    for m in RECIPROCAL + [Phong(1.0, 0.0), BlinnPhong(1.0, 0.0)]:
        assert np.all(m.eval(N, direction(1.7), direction(0.3)) == 0)
        assert np.all(m.eval(N, direction(0.3), direction(1.7)) == 0)


@pytest.mark.parametrize(
    "factory, match",
    [
        (lambda: Lambert(-0.1), "kd"),
        (lambda: Lambert(float("nan")), "kd"),
        (lambda: Lambert((1, 2)), "kd"),
        (lambda: Phong(0.5, -1), "shininess"),
        (lambda: BlinnPhong(0.5, float("inf")), "shininess"),
        (lambda: CookTorrance(1.0, 0.0), "roughness"),
        (lambda: CookTorrance(1.0, -0.2), "roughness"),
        (lambda: CookTorrance(1.0, 0.2, 1.5), "f0"),
        (lambda: CookTorrance(1.0, 0.2, ndf="phong"), "ndf"),
        (lambda: CookTorrance(1.0, 0.2, geometry="none"), "geometry"),
        (lambda: CookTorrance(1.0, 0.2, fresnel="metallic"), "fresnel"),
        (lambda: CookTorrance(1.0, 0.2, denominator="2"), "denominator"),
    ],
)
def test_bad_parameters_raise_clear_errors(factory, match):
    with pytest.raises(ValueError, match=match) as info:
        factory()
    assert "got" in str(info.value)


# -------------------------------------------------------------- extreme exponents and finite results
def _stacked_fields(model, n, l, v, form):  # noqa: E741
    """The image path: ``separable_cos``/``separable_classic`` on a one-light :class:`StackedGeometry`."""
    from lighting.shading.stacked import StackedGeometry

    unit = [x / np.linalg.norm(x.astype(np.float64)).astype(x.dtype) for x in (n, l, v)]
    g = StackedGeometry(unit[0][None], unit[1][None], unit[2][None])
    fields = model.separable_cos(g) if form == "eval_cos" else model.separable_classic(g)
    return sum(s[..., None] * c.astype(s.dtype) for s, c in fields)[0, 0]


# l = −v (the reported case), the half vector zero; h exactly on the horizon; light at the normal, view opposite.
_HORIZON_CASES = [
    ((0, 0, 1.0), (0.6, 0, 0.8), (-0.6, 0, -0.8)),
    ((0, 0, 1.0), (1.0, 0, 0), (-1.0, 0, 0)),
    ((0, 0, 1.0), (1.0, 0, 0), (0, 1.0, 0)),
    ((0, 0, 1.0), (0.8, 0, 0.6), (-0.8, 0, -0.6)),
]


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("normalized", [False, True])
@pytest.mark.parametrize("e", [1e-300, 1e-45, 5e-324, 1e-40])
def test_blinn_phong_subnormal_exponent_with_l_opposite_v_is_zero(e, normalized, dtype):
    # Item 7: e rounded to 0 in float32, and exp(0 · log 0) = exp(0 · −∞) was NaN.
    # Below the horizon the lobe is 0; every path (eval, eval_cos, classic, the stacked image path) says so.
    m = BlinnPhong(1.0, e, normalized=normalized)
    for n, l, v in _HORIZON_CASES:  # noqa: E741
        n, l, v = (np.array(x, dtype) for x in (n, l, v))  # noqa: E741
        for form in ("eval", "eval_cos", "classic"):
            out = getattr(m, form)(n, l, v)
            assert out.dtype == dtype
            assert out.tolist() == [0.0, 0.0, 0.0], (form, l, v)
        for form in ("eval_cos", "classic"):
            assert _stacked_fields(m, n, l, v, form).tolist() == [0.0, 0.0, 0.0], (form, l, v)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("e", [1e-300, 1e-40, 1e39, 1e300])
def test_blinn_phong_exponents_beyond_the_dtype_give_the_limit_lobe(e, dtype):
    # Item 7's mechanism at the other end: e = 1e39 was inf in float32, and inf · log(1) = NaN at the peak.
    # The lobe (n·h)^e is 1 for any n·h > 0 when e is tiny, and 1 at the peak, 0 off it when e is huge.
    n = np.array([0, 0, 1.0], dtype)
    l = np.array([[0, 0, 1.0], [0.6, 0, 0.8], [math.sin(1.5), 0, math.cos(1.5)]], dtype)  # noqa: E741
    expected = [1.0, 1.0, 1.0] if e < 1 else [1.0, 0.0, 0.0]
    m = BlinnPhong(1.0, e)
    got = m.classic(n, l, n)[:, 0]
    assert got.dtype == dtype and got.tolist() == expected
    assert _stacked_fields(m, n, l[0], n, "classic").tolist() == [1.0] * 3
    p = Phong(1.0, e).classic(n, l, n)[:, 0]
    assert p.tolist() == (expected if e < 1 else [1.0, 0.0, 0.0])


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("target", [1.2e-38, 3e-39, 1e-41, 1e-30])
def test_normalized_blinn_phong_keeps_its_digits_near_the_bottom_of_the_range(target, dtype):
    # Item 9: (e+2)/(2π) · (n·h)^e multiplied a subnormal (n·h)^e (digits already lost): 7 % off at
    # 1.2e-38 in float32 for e = 1e7.  The factor now goes into the exponent.  Reference: mpmath at the
    # rounded inputs.  The result itself may be subnormal (3e-39, 1e-41): then it is held to its spacing.
    import mpmath

    e = 1e7
    th = math.acos(math.exp(math.log(target / ((e + 2) / (2 * math.pi))) / e))  # h at θ_h from n
    n = np.array([0, 0, 1.0], dtype)
    l = np.array([math.sin(2 * th), 0, math.cos(2 * th)], dtype)  # noqa: E741
    m = BlinnPhong(1.0, e, normalized=True)
    with mpmath.workdps(40):
        lm = [mpmath.mpf(float(x)) for x in l]
        s = [lm[0], lm[1], lm[2] + mpmath.sqrt(sum(x * x for x in lm))]  # l/|l| + n, scaled by |l|
        nh = s[2] / mpmath.sqrt(sum(x * x for x in s))
        ref = (e + 2) / (2 * mpmath.pi) * nh**e
        nl = lm[2] / mpmath.sqrt(sum(x * x for x in lm))
    tiny = float(np.finfo(dtype).smallest_subnormal)
    for got, want in ((m.eval(n, l, n)[0], ref), (m.eval_cos(n, l, n)[0], ref * nl),
                      (_stacked_fields(m, n, l, n, "eval_cos")[0], ref * nl)):
        assert got.dtype == dtype
        want = float(want)
        # float32: exp of an argument near −87 carries ~87 ulp of it (1e-5); float64 the same in its own ulp.
        rel = 2e-5 if dtype is np.float32 else 1e-13
        assert abs(float(got) - want) <= rel * want + 2 * tiny, (float(got), want)


# --------------------------------------------------------------------------- checked arguments (found by the probe)
def test_public_eval_keeps_the_dtype_of_arrays_with_tuples_weak():
    # The boundary check converts every vector, but decides the dtype on the arguments as given.
    n = np.array([0, 0, 1.0], np.float32)
    for form in ("eval", "eval_cos", "classic"):
        out = getattr(BlinnPhong(0.5, 10), form)(n, (0.6, 0, 0.8), [0, 0, 1])
        assert out.dtype == np.float32


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_zero_colour_channel_times_saturated_lobe_is_zero_not_nan(dtype):
    # Phong's f_r divides by a subnormal n·l: the float64 quotient overflowed to inf, and a zero k_s channel
    # times inf was NaN.  The quotient saturates first; the zero channel stays 0, the others saturate.
    n = np.array([0, 0, 1.0], dtype)
    l = np.array([1.0, 0, 1e-320 if dtype is np.float64 else 1e-45], dtype)  # noqa: E741
    v = np.array([-1.0, 0, 1e-3], dtype)
    f = Phong((1e-40, 0.0, 1e-8), 0.5).eval(n, l, v)
    assert f.dtype == dtype and f[1] == 0 and np.all(np.isfinite(f)) and f[2] > 0


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_sum_of_saturated_models_saturates_without_warning(dtype):
    # Each term is finite (or saturated alone); their sum overflowed with a warning and gave inf.
    big = float(np.finfo(dtype).max)
    n = np.array([0, 0, 1.0], dtype)
    assert (Lambert(1e308) + Lambert(1e308)).classic(n, n, n).tolist() == [big] * 3
    l = np.array([1.0, 0, 1e-3], dtype)  # noqa: E741
    v = np.array([-1.0, 0, 1e-3], dtype)
    assert (Phong(1e308, 0.0) + Phong(1e308, 0.0)).eval(n, l, v).tolist() == [big] * 3


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("e", [3.0, 80.0, 1e6, 1e7])
def test_normalized_blinn_phong_peak_is_its_normalization_to_the_last_bit(e, dtype):
    """At h = n the lobe is exactly (e + 2)/(2π), rounded once: the factor is multiplied, not exp(log(.))."""
    n = np.array([0.0, 0.0, 1.0], dtype)
    peak = BlinnPhong(1.0, e, normalized=True).eval(n, n, n)
    assert peak.dtype == dtype and np.all(peak == dtype((e + 2) / (2 * math.pi)))


@pytest.mark.parametrize("geometry", ["smith", "smith-correlated", "v-cavity"])
def test_stacked_classic_saturates_without_a_warning_at_a_subnormal_grazing_pair(geometry):
    # Found by the models probe: l = v at 5e-324 above the horizon makes the separable field the largest
    # float64; times π it must saturate there, not warn.
    from lighting.shading.stacked import StackedGeometry

    m = CookTorrance(ks=(1e-8, 1e30, 0), roughness=0.136, f0=(0.5, 0, 0.04), ndf="ggx", geometry=geometry)
    d = np.array([[1.0, 0.0, 5e-324]])
    g = StackedGeometry(np.array([[0.0, 0.0, 1.0]]), d, d)
    for s, _ in m.separable_classic(g):
        assert np.all(np.isfinite(s)) and np.all(s >= 0)

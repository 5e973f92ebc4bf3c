"""The Ashikhmin–Shirley anisotropic Phong BRDF (JGT 2000): its 80-digit reference, its laws and its sampler.

Measured (this file's cases; see the report in the commit message):

* vs mpmath at 80 digits, float64 and float32, ordinary and extreme inputs (grazing 1e-6 rad,
  h within 1e-8 rad of n, l = v, exponents 0 … 1e12): relative error <= 8 eps κ, with the
  condition estimate κ = 1 + |E log(n·h)| + √(2 E_max |E log(n·h)|) + 1/(n·l) + 1/(n·v) + 1/(v·h)
  (the last three: absolute rounding of the cosines; the second and third: an absolute error
  eps in the angle of h, multiplied by the exponent); the worst measured ratio is about 3.
* the diffuse term's albedo is exactly R_d (1 − R_s)(1 − (1 − μ/2)⁵);
* directional albedo <= 1 for R_d + R_s <= 1 (numbers printed by ``-s``);
* the sampler: the paper's half-vector density and azimuth warp, the density of ``l`` integrating to 1;
  its χ² at 0° to 89.9° is in test_sampler_grazing_full.py.
"""

from __future__ import annotations

import functools
import math

import mpmath as mp
import numpy as np
import pytest
from exact_frames import exact_frame
from quadrature import hemisphere

from lighting.integrate import directional_albedo
from lighting.models import create_model
from lighting.models.ashikhmin_shirley import AshikhminShirley, AshikhminShirleySampler
from lighting.models.lambert import CosineSampler
from lighting.validation import model_references as mr

pytestmark = pytest.mark.slow  # 80-digit references, quadratures, grazing χ²; fast: test_contract.py


# --------------------------------------------------------------------------- the 80-digit reference
def _reference(n, l, v, tangent, rd, rs, nu, nv, *, diffuse=True, cos=False):  # noqa: E741
    """:func:`lighting.validation.model_references.ashikhmin_shirley` (the paper's formula) at 80 digits, from
    the exact values of the (float) inputs, per channel of ``rd``, ``rs``; RGB list of mpf."""
    with mp.workdps(80):
        exact = (None if x is None else tuple(float(c) for c in x) for x in (n, l, v, tangent, rd, rs))
        q, fr = _reference_fr(*exact, float(nu), float(nv), diffuse)
        if not q["above"]:
            return [mp.mpf(0)] * 3
        return [f * q["nl"] if cos else f for f in fr]


@functools.cache
def _reference_fr(n, l, v, tangent, rd, rs, nu, nv, diffuse):  # noqa: E741
    """``(frame, f_r per channel)`` of :func:`_reference` at 80 digits (``None`` below the horizon), from floats
    and tuples of floats: one ``f_r`` for ``eval`` and for ``eval_cos``, which multiplies it by ``n·l``."""
    with mp.workdps(80):
        q = exact_frame(n, l, v, tangent)
        if not q["above"]:
            return q, None
        nu, nv = mp.mpf(nu), mp.mpf(nv)
        return q, tuple(mr.ashikhmin_shirley(q, mp.mpf(rd[c]), mp.mpf(rs[c]), nu, nv, diffuse) for c in range(3))


def _unit(a):
    return a / np.linalg.norm(a, axis=-1, keepdims=True)


def _elev(e, phi):
    """Local direction at elevation ``e`` above the horizon, azimuth ``phi``."""
    return np.array([math.cos(e) * math.cos(phi), math.cos(e) * math.sin(phi), math.sin(e)])


def _cases():
    """(n, l, v, tangent): random ones (above the surface), grazing ones, near-peak ones, l = v."""
    rng = np.random.default_rng(1)
    out = []
    for _ in range(40):
        n, l, v, t = (_unit(rng.normal(size=3)) for _ in range(4))  # noqa: E741
        out.append((n, l * np.sign(l @ n), v * np.sign(v @ n), t))
    z = np.array([0.0, 0.0, 1.0])
    for e in (1e-6, 1e-3):
        out.append((z, _elev(e, 0.3), _elev(e, 0.3 + math.pi), None))  # opposite, both grazing: h ≈ n
        out.append((z, _elev(e, 0.3), _elev(0.7, 2.0), None))
        out.append((z, _elev(e, 0.3), _elev(e, 0.3), None))  # l = v grazing
        out.append((z, _elev(e, 0.3), _elev(e, 1.9), None))
    for d in (1e-8, 1e-5, 1e-3):  # h within d of n, in two azimuths
        for phi in (0.4, 1.3):
            out.append((z, _elev(math.pi / 2 - 0.6, phi), _elev(math.pi / 2 - 0.6 + 2 * d, phi + math.pi), None))
    out.append((z, z, z, None))
    out.append((_unit(np.array([0.3, -0.2, 0.9])), z, z, np.array([1.0, 1.0, 0.0])))
    return out


CASES = _cases()
EXPONENTS = [(200.0, 20.0), (10.0, 10.0), (0.0, 0.0), (1e-8, 1e6), (1e4, 1e4), (1e12, 3.0), (0.5, 3e3)]


def _kappa(n, l, v, nu, nv):  # noqa: E741
    """The condition estimate of the module docstring (float64, from the inputs)."""
    n, l, v = (_unit(np.asarray(x, dtype=np.float64)) for x in (n, l, v))  # noqa: E741
    h = _unit(l + v)
    th = math.atan2(np.linalg.norm(np.cross(h, n)), h @ n)
    e = max(nu, nv)
    log_lobe = e * th * th / 2
    return 1 + log_lobe + math.sqrt(2 * e * log_lobe) + 1 / (n @ l) + 1 / (n @ v) + 1 / (v @ h)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("nu, nv", EXPONENTS)
def test_matches_the_80_digit_transcription(dtype, nu, nv):
    rd, rs = (0.5, 0.2, 0.9), (0.04, 0.5, 1.0)
    model = AshikhminShirley(rd=rd, rs=rs, nu=nu, nv=nv)
    eps, tiny, big = np.finfo(dtype).eps, np.finfo(dtype).tiny, float(np.finfo(dtype).max)
    worst = 0.0
    for n, l, v, t in CASES:  # noqa: E741
        args = [x.astype(dtype) for x in (n, l, v)]
        tan = None if t is None else t.astype(dtype)
        kappa = _kappa(*args, nu, nv)
        for cos in (False, True):
            got = (model.eval_cos if cos else model.eval)(*args, tangent=tan)
            assert got.dtype == dtype
            want = _reference(*args, tan, model.rd, model.rs, nu, nv, cos=cos)
            for c in range(3):
                w = min(float(want[c]), big)  # saturated where the true value exceeds the dtype
                err = abs(float(got[c]) - w) / max(w, tiny / eps)
                worst = max(worst, err / (eps * kappa))
    assert worst <= 8.0, worst


def test_the_specular_only_form_and_the_default_frame_match_the_transcription():
    model = AshikhminShirley(rd=0.7, rs=0.1, nu=300, nv=7, diffuse=False)
    rng = np.random.default_rng(8)
    for _ in range(30):
        n, l, v = (_unit(rng.normal(size=3)) for _ in range(3))  # noqa: E741
        l, v = l * np.sign(l @ n), v * np.sign(v @ n)  # noqa: E741
        got = model.eval(n, l, v)
        want = [float(x) for x in _reference(n, l, v, None, model.rd, model.rs, 300, 7, diffuse=False)]
        np.testing.assert_allclose(got, want, rtol=8 * np.finfo(float).eps * _kappa(n, l, v, 300, 7), atol=1e-300)


# --------------------------------------------------------------------------- closed forms and laws
def test_normal_incidence_closed_form():
    z = (0.0, 0.0, 1.0)
    for nu, nv in ((0.0, 0.0), (100.0, 100.0), (1e4, 3.0)):
        m = AshikhminShirley(rd=(0.5, 0.2, 0.0), rs=(0.04, 0.5, 1.0), nu=nu, nv=nv)
        spec = math.sqrt((nu + 1) * (nv + 1)) / (8 * math.pi) * m.rs
        diff = 28 / (23 * math.pi) * m.rd * (1 - m.rs) * (31 / 32) ** 2
        np.testing.assert_allclose(m.eval(z, z, z), spec + diff, rtol=4e-16)
        np.testing.assert_allclose(m.eval(np.float32(z), z, z), spec + diff, rtol=4e-7)


def test_below_the_horizon_and_zero_vectors_give_zero():
    m = AshikhminShirley()
    z, down, zero = np.array([0, 0, 1.0]), np.array([0.3, 0, -1.0]), np.zeros(3)
    for n, l, v in ((z, down, z), (z, z, down), (zero, z, z), (z, zero, z), (z, z, zero), (z, _elev(0, 0), z)):  # noqa: E741
        for f in (m.eval, m.eval_cos, m.classic):
            assert f(n, l, v).tolist() == [0.0, 0.0, 0.0]


def _rot_z(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def test_isotropic_case_is_symmetric_under_rotation_about_the_normal():
    rng = np.random.default_rng(3)
    l = _unit(rng.normal(size=(400, 3)) * [1, 1, 0.5] + [0, 0, 0.6])  # noqa: E741
    v = _unit(rng.normal(size=(400, 3)) * [1, 1, 0.5] + [0, 0, 0.6])
    n = np.array([0.0, 0.0, 1.0])
    for e in (0.0, 8.0, 150.0, 5e3):
        m = AshikhminShirley(rd=0.4, rs=(0.05, 0.3, 0.9), nu=e, nv=e)
        base = m.eval(n, l, v)
        for a in (0.3, 1.0, 2.5):
            # The tangent turned: the same values (to rounding).
            np.testing.assert_allclose(m.eval(n, l, v, tangent=_rot_z(a)[:, 0]), base, rtol=1e-11, atol=1e-300)
            # l and v turned together about n: the same values.
            r = _rot_z(a)
            np.testing.assert_allclose(m.eval(n, l @ r.T, v @ r.T), base, rtol=1e-11, atol=1e-300)


def test_anisotropic_lobe_follows_the_tangent():
    rng = np.random.default_rng(4)
    l = _unit(rng.normal(size=(300, 3)) * [1, 1, 0.5] + [0, 0, 0.6])  # noqa: E741
    v = _unit(rng.normal(size=(300, 3)) * [1, 1, 0.5] + [0, 0, 0.6])
    n = np.array([0.0, 0.0, 1.0])
    a, b = AshikhminShirley(nu=300, nv=12, diffuse=False), AshikhminShirley(nu=12, nv=300, diffuse=False)
    # Swapping the exponents is turning the tangent by 90°.
    np.testing.assert_allclose(b.eval(n, l, v, tangent=(0.0, 1.0, 0.0)), a.eval(n, l, v), rtol=1e-11, atol=1e-300)
    # Turning everything (n, l, v, tangent) by one rotation changes nothing.
    r = _unit(rng.normal(size=3))
    q, _ = np.linalg.qr(np.c_[r, rng.normal(size=(3, 2))])
    q = q * np.sign(np.linalg.det(q))
    got = a.eval(n @ q.T, l @ q.T, v @ q.T, tangent=np.array([1.0, 0, 0]) @ q.T)
    np.testing.assert_allclose(got, a.eval(n, l, v), rtol=1e-10, atol=1e-300)
    # Anisotropic: the highlight is narrower along t (the larger exponent) than along b.
    # l = v, so h = l: tilted by 0.2 rad along t, or along b.
    lt = _unit(np.array([0.2, 0.0, 1.0]))
    lb = _unit(np.array([0.0, 0.2, 1.0]))
    assert a.eval(n, lt, lt)[0] * 50 < a.eval(n, lb, lb)[0]


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_reciprocity(dtype):
    rng = np.random.default_rng(6)
    n, l, v, t = (_unit(rng.normal(size=(2000, 3))).astype(dtype) for _ in range(4))  # noqa: E741
    for m in (AshikhminShirley(), AshikhminShirley(rd=(0.9, 0.1, 0.4), rs=(0.0, 0.3, 1.0), nu=5e3, nv=0.5)):
        np.testing.assert_allclose(m.eval(n, l, v, tangent=t), m.eval(n, v, l, tangent=t),
                                   rtol=8 * np.finfo(dtype).eps, atol=0)  # fmt: skip


@pytest.mark.parametrize("theta_deg", [0.0, 30.0, 60.0, 80.0, 89.0])
def test_the_diffuse_terms_albedo_is_the_closed_form(theta_deg):
    # ∫ 28/(23π) (1 − (1 − μ/2)⁵) μ dω = 1, so ρ_d(v) = R_d (1 − R_s) (1 − (1 − n·v/2)⁵).
    rd, rs = np.array([0.8, 0.5, 0.2]), np.array([0.04, 0.3, 1.0])
    with_d = AshikhminShirley(rd=rd, rs=rs, nu=40, nv=4)
    without = AshikhminShirley(rd=rd, rs=rs, nu=40, nv=4, diffuse=False)
    th = math.radians(theta_deg)
    got = directional_albedo(with_d, th) - directional_albedo(without, th)
    want = rd * (1 - rs) * (1 - (1 - math.cos(th) / 2) ** 5)
    np.testing.assert_allclose(got, want, atol=2e-6)


def _albedo_any_azimuth(model, theta_v, phi_v):
    """``∫ f_r (n·l) dω`` for a viewer at (θ_v, φ_v) (tests/quadrature, nodes graded toward the mirror direction)."""
    v = np.array([math.sin(theta_v) * math.cos(phi_v), math.sin(theta_v) * math.sin(phi_v), math.cos(theta_v)])
    n = np.array([0.0, 0.0, 1.0])
    return hemisphere(lambda d: model.eval_cos(n, d, v), scale=1e-4, panels=48, order=24, n_phi=512)


_EXPONENT_PAIRS = ((0.0, 0.0), (1.0, 1.0), (10.0, 10.0), (100.0, 10.0), (1000.0, 1000.0), (1e4, 100.0))
ENERGY = [(rs, nu, nv) for rs in (0.0, 0.05, 0.5, 1.0) for nu, nv in _EXPONENT_PAIRS]


@pytest.mark.parametrize("rs, nu, nv", ENERGY)
def test_directional_albedo_at_most_one_when_rd_plus_rs_at_most_one(rs, nu, nv):
    model = AshikhminShirley(rd=1.0 - rs, rs=rs, nu=nu, nv=nv)
    thetas = np.radians([0.0, 30.0, 60.0, 75.0, 85.0, 89.0])
    along_t = directional_albedo(model, thetas, samples=65536)[:, 0]
    # The viewer along b instead of t (the same model where ν_u = ν_v).
    swapped = AshikhminShirley(rd=1.0 - rs, rs=rs, nu=nv, nv=nu)
    along_b = along_t if nu == nv else directional_albedo(swapped, thetas, samples=65536)[:, 0]
    rho = np.concatenate([along_t, along_b])
    print(f"rs={rs} nu={nu:g} nv={nv:g}: albedo along t {np.round(rho[:6], 4).tolist()} "
          f"along b {np.round(rho[6:], 4).tolist()}")  # fmt: skip
    assert np.all(rho <= 1.0 + 1e-6), rho.max()
    assert np.all(rho > 0)


def test_directional_albedo_agrees_with_an_independent_quadrature_off_the_axes():
    model = AshikhminShirley(rd=0.6, rs=0.2, nu=120, nv=8)
    for theta in (0.3, 1.2):
        for phi in (0.0, 0.7, math.pi / 2):
            rho = _albedo_any_azimuth(model, theta, phi)
            assert np.all(rho <= 1.0)
            if phi == 0.0:
                along_t = rho  # the quadrature at φ_v = 0, compared below
        # φ_v = 0 is what directional_albedo computes.
        np.testing.assert_allclose(along_t, directional_albedo(model, theta), rtol=5e-5)


# --------------------------------------------------------------------------- finite in, finite out
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_extremes_are_finite_and_nonnegative(dtype):
    rng = np.random.default_rng(9)
    n = _unit(rng.normal(size=(500, 3)))
    l = _unit(rng.normal(size=(500, 3)))  # noqa: E741
    v = _unit(rng.normal(size=(500, 3)))
    graze = np.array([_elev(e, p) for e in (0.0, 1e-300, 1e-30, 1e-6) for p in (0.0, 1.0, math.pi)])
    n = np.r_[n, np.tile([0, 0, 1.0], (len(graze) ** 2, 1)), np.zeros((1, 3))]
    l = np.r_[l, np.repeat(graze, len(graze), 0), [[0, 0, 1.0]]]  # noqa: E741
    v = np.r_[v, np.tile(graze, (len(graze), 1)), [[0, 0, 1.0]]]
    for nu, nv in ((0.0, 0.0), (1e-300, 1e300), (1e308, 1e308), (1e6, 0.0), (1e4, 1e4)):
        for rd, rs in ((0.0, 0.0), (1.0, 1.0), (1e300, 0.5)):
            m = AshikhminShirley(rd=rd, rs=rs, nu=nu, nv=nv)
            for f in (m.eval, m.eval_cos, m.classic):
                out = f(n.astype(dtype), l.astype(dtype), v.astype(dtype))
                assert out.dtype == dtype
                assert np.all(np.isfinite(out)) and np.all(out >= 0)
                assert out[-1].tolist() == [0.0, 0.0, 0.0]


def test_bad_parameters_are_named():
    for kwargs, name in (({"rs": 1.5}, "rs"), ({"rs": -0.1}, "rs"), ({"rd": -1}, "rd"), ({"nu": -1}, "nu"),
                         ({"nv": math.nan}, "nv"), ({"nu": math.inf}, "nu"), ({"diffuse": 1}, "diffuse")):  # fmt: skip
        with pytest.raises(ValueError, match=name):
            AshikhminShirley(**kwargs)


def test_registry_table_summary_and_lobe():
    m = create_model("ashikhmin-shirley", nu=100, nv=4)
    assert isinstance(m, AshikhminShirley) and not m.stackable
    assert m.summary() == "rd=0.5 rs=0.05 nu=100 nv=4"
    assert AshikhminShirley(diffuse=False).summary().endswith("specular only")
    lobe = m.lobe()
    assert lobe.axis == "half"
    assert lobe.width == pytest.approx(1 / math.sqrt(20))  # 1/√(geometric mean of the exponents)
    assert lobe.rule_width == pytest.approx(1 / math.sqrt(101))
    assert AshikhminShirley(nu=0, nv=0).lobe().width == 1.0
    assert [p.name for p in m.parameters] == ["rd", "rs", "nu", "nv", "diffuse"]


# --------------------------------------------------------------------------- the sampler
def test_sampler_choice():
    assert repr(AshikhminShirley(diffuse=False).sampler()) == "AshikhminShirleySampler(nu=200.0, nv=20.0)"
    assert repr(AshikhminShirley(rd=0.0).sampler()) == "AshikhminShirleySampler(nu=200.0, nv=20.0)"
    mix = AshikhminShirley(rd=0.5, rs=0.05).sampler()
    assert isinstance(mix.samplers[0], CosineSampler) and isinstance(mix.samplers[1], AshikhminShirleySampler)
    w = mix.weights(np.array([[0, 0, 1.0], [1.0, 0, 1e-9]]))
    np.testing.assert_allclose(w.sum(-1), 1.0)
    assert np.all(w >= 0.1 - 1e-15) and np.all(w <= 0.9 + 1e-15)
    assert w[1, 1] > w[0, 1]  # more specular samples at grazing views (Fresnel)


def test_half_vector_density_is_the_papers_and_integrates_to_one():
    for nu, nv in ((0.0, 0.0), (10.0, 10.0), (300.0, 4.0), (1.0, 2e3)):
        s = AshikhminShirleySampler(nu, nv)
        total = hemisphere(s._normal_pdf, scale=1e-4, n_phi=2048)
        assert float(total) == pytest.approx(1.0, abs=1e-6)
        u = np.random.default_rng(1).random((1000, 2))
        h = s.sample_normals(u)
        np.testing.assert_allclose(np.linalg.norm(h.directions, axis=-1), 1.0, rtol=1e-15)
        # p(h) = √((n_u+1)(n_v+1))/(2π) cos^E θ with cos θ = (1 − u₁)^{1/(E+1)}: (1 − u₁)^{E/(E+1)}.
        c, sn = h.directions[:, 0], h.directions[:, 1]
        e = (nu * c * c + nv * sn * sn) / np.maximum(c * c + sn * sn, 1e-300)
        want = math.sqrt((nu + 1) * (nv + 1)) / (2 * math.pi) * (1 - u[:, 1]) ** (e / (e + 1))
        np.testing.assert_allclose(h.pdf, want, rtol=1e-12)


def test_azimuth_warp_is_the_papers_in_every_quadrant():
    nu, nv = 50.0, 5.0
    s = AshikhminShirleySampler(nu, nv)
    r = np.linspace(0.01, 0.99, 7)
    k = math.sqrt((nu + 1) / (nv + 1))
    for q in range(4):
        u = np.stack([(q + r) / 4, np.full_like(r, 0.5)], -1)
        h = s.sample_normals(u).directions
        phi = np.mod(np.arctan2(h[:, 1], h[:, 0]), 2 * math.pi)
        rr = r if q in (0, 2) else 1 - r
        phi0 = np.arctan(k * np.tan(math.pi * rr / 2))
        want = {0: phi0, 1: math.pi - phi0, 2: math.pi + phi0, 3: 2 * math.pi - phi0}[q]
        np.testing.assert_allclose(phi, want, rtol=1e-13)


def _view(theta_deg, phi_deg=0.0):
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return np.array([math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)])


def _frame_about(a):
    """Rows: two unit tangents and the unit axis ``a`` (a right-handed frame)."""
    a = _unit(np.asarray(a, dtype=float))
    t = np.cross(a, [1.0, 0.0, 0.0] if abs(a[0]) < 0.9 else [0.0, 1.0, 0.0])
    t /= np.linalg.norm(t)
    return np.stack([t, np.cross(a, t), a])


def _sphere_integral(func, axis):
    """``∫ func dω`` over the sphere: the hemispheres about ``axis`` and ``−axis`` (nodes graded toward both)."""
    total = 0.0
    for a in (axis, -axis):
        frame = _frame_about(a)
        total += float(hemisphere(lambda d, frame=frame: func(d @ frame), scale=1e-5, panels=48, order=24,
                                  n_phi=1024))  # fmt: skip
    return total


@pytest.mark.parametrize("nu, nv", [(0.0, 0.0), (5.0, 5.0), (200.0, 20.0), (3.0, 800.0)])
@pytest.mark.parametrize("theta_deg", [0.0, 60.0, 89.0])
def test_direction_density_integrates_to_one_over_the_sphere(nu, nv, theta_deg):
    s = AshikhminShirleySampler(nu, nv)
    v = _view(theta_deg, 25.0)
    # About −v, where p(l) = p(h)/(4 |v·h|) has its integrable 1/|l + v| point.
    assert _sphere_integral(lambda d: s.pdf(d, v), -v) == pytest.approx(1.0, abs=1e-4)


def test_sampled_densities_equal_pdf_and_importance_estimates_agree_with_quadrature():
    for model in (AshikhminShirley(rd=0.6, rs=0.1, nu=300, nv=30), AshikhminShirley(rd=0.0, rs=0.9, nu=5, nv=5000)):
        sampler = model.sampler()
        for theta in (0.2, 1.0, 1.5):
            v = _view(math.degrees(theta))
            u = np.random.default_rng(7).random((200_000, 2))
            s = sampler.sample(u, v)
            # Recomputing h = (l + v)/|l + v| costs an angle of eps/|l + v|, which (n·h)^E turns into a
            # relative error E eps / (|l + v| n·h).
            again = sampler.pdf(s.directions, v)
            lv = np.linalg.norm(s.directions + v, axis=-1)
            hn = np.abs(s.directions[:, 2] + v[2]) / lv
            bound = 64 * np.finfo(float).eps * (1 + max(model.nu, model.nv)) / (lv * hn)
            assert np.all(np.abs(again - s.pdf) <= bound * s.pdf)
            f = model.eval_cos(np.array([0, 0, 1.0]), s.directions, v)
            w = np.where(s.pdf[:, None] > 0, f / np.where(s.pdf > 0, s.pdf, 1)[:, None], 0)
            est, se = w.mean(0), w.std(0) / math.sqrt(len(w))
            # The integrator's star rule is isotropic in azimuth: a 1000:1 lobe needs more nodes than its default.
            ref = directional_albedo(model, theta, samples=65536)
            assert np.all(np.abs(est - ref) <= 5 * se + 1e-4), (est, ref, se)

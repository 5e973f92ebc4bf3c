"""The Disney principled BRDF (lighting.models.disney): the explorer's shader against its 80-digit reference
(lighting.validation.model_references), the laws its parts obey, its energy at the defaults and its sampler.

Measured numbers (this machine):

* eval vs the 80-digit mpmath reference: the relative error divided by ``eps (1 + κ)`` (κ the
  condition number of ``f_r`` in the components of n, l, v and the tangent, from 80-digit differences)
  is at most 4.8 (ordinary inputs) and 5.9 (extremes) in float64, 1.6 and 2.9 in float32; the extremes
  are 1e-6 rad from the horizon, the GTR2 peak at α = 0.001, mirror pairs grazing on opposite sides,
  parameters 1e-300 and 1 − 1e-16.  The tests assert 16.
* χ² p-values in cells of l (100 000 samples) at θ_v = 0 and 40°: default 0.32, 0.20; metal-aniso 0.66,
  0.19; clearcoat-satin 0.005 (seeds 0–7: 0.02 to 0.96), 0.39; sheen 0.65, 0.61.  The half-vector cells
  that follow the lobe, 0° to 89°, are in test_sampler_grazing_full.py.
* directional albedo at the defaults (quadrature, converged to 1e-13) at θ_v = 0, 15, 30, 45, 60, 70, 80,
  85, 89, 89.9°: 0.8414 0.8412 0.8409 0.8433 0.8622 0.8975 0.9523 0.9783 0.9888 0.9887 — below 1.
  (A white base at roughness 1 is not: 1.048 at the normal, 1.60 at 89.9°.)
"""

from __future__ import annotations

import math
import warnings

import mpmath as mp
import numpy as np
import pytest
from chi2 import chi2_sf
from exact_frames import exact_frame
from quadrature import hemisphere

from lighting.integrate import directional_albedo
from lighting.models import create_model, model_names
from lighting.models.disney import Disney, DisneySampler, gtr1, gtr2_aniso, smooth_cosine_pdf
from lighting.validation import model_references as mr

pytestmark = pytest.mark.slow  # 80-digit references, quadratures, grazing χ²; fast: test_contract.py


# --------------------------------------------------------------------------- the 80-digit reference
def _mpvec(x):
    return [mp.mpf(float(c)) for c in x]


def ref_disney(p, n, l, v, t=None):  # noqa: E741
    """:func:`lighting.validation.model_references.disney` (the shader disney.brdf of BRDF Explorer, without
    mon2lin) at the working precision (the callers set 80 digits), RGB; p: the model's parameters (floats);
    n, l, v, t: mpf vectors, the documented frame (t made ⊥ n, else ẑ × n, else x̂)."""
    q = exact_frame(n, l, v, t)
    if not q["above"]:
        return [mp.mpf(0)] * 3
    prm = {k: mp.mpf(float(x)) for k, x in p.items() if k != "base_color"}
    return mr.disney(q, prm, [mp.mpf(float(c)) for c in np.broadcast_to(p["base_color"], 3)])


def _params(model):
    return {p.name: getattr(model, p.name) for p in model.parameters}


def _kappa(p, n, l, v, t, f0):  # noqa: E741
    """Σ_i |x_i ∂f/∂x_i| / |f| per channel over the components of n, l, v (and t): 80-digit central differences."""
    vecs = [_mpvec(n), _mpvec(l), _mpvec(v)] + ([_mpvec(t)] if t is not None else [])
    delta = mp.mpf("1e-30")
    acc = [mp.mpf(0)] * 3
    for k in range(len(vecs)):
        for i in range(3):
            if vecs[k][i] == 0:
                continue
            plus = [list(x) for x in vecs]
            minus = [list(x) for x in vecs]
            plus[k][i] *= 1 + delta
            minus[k][i] *= 1 - delta
            fp = ref_disney(p, *plus[:3], plus[3] if t is not None else None)
            fm = ref_disney(p, *minus[:3], minus[3] if t is not None else None)
            for c in range(3):
                acc[c] += abs(fp[c] - fm[c]) / (2 * delta)
    return [float(acc[c] / f0[c]) if f0[c] > 0 else 0.0 for c in range(3)]


def _worst_ratio(model, n, l, v, t, dtype):  # noqa: E741
    """max over points and channels of |eval − ref| / (ref · eps (1 + κ)); errors below the dtype's tiny pass."""
    n, l, v = (np.asarray(x, dtype=dtype) for x in (n, l, v))  # noqa: E741
    t = None if t is None else np.asarray(t, dtype=dtype)
    got = model.eval(n, l, v, tangent=t)
    assert got.dtype == dtype and np.all(np.isfinite(got))
    eps = float(np.finfo(dtype).eps)
    tiny = float(np.finfo(dtype).tiny)
    p = _params(model)
    worst = 0.0
    with mp.workdps(80):
        for k in range(len(n)):
            tk = None if t is None else t[k]
            want = ref_disney(p, _mpvec(n[k]), _mpvec(l[k]), _mpvec(v[k]), None if tk is None else _mpvec(tk))
            if all(w == 0 for w in want):
                assert np.all(got[k] == 0), (k, got[k])
                continue
            kap = _kappa(p, n[k], l[k], v[k], tk, want)
            for c in range(3):
                err = abs(mp.mpf(float(got[k, c])) - want[c])
                if err <= tiny:  # below the dtype's normal range (a base colour of 1e-300 in float32): absolute
                    continue
                worst = max(worst, float(err / want[c]) / (eps * (1 + kap[c])))
    return worst


SETTINGS = {
    "default": {},
    "metal-aniso": dict(base_color=(0.9, 0.6, 0.3), metallic=1.0, roughness=0.3, anisotropic=0.8),
    "everything": dict(
        base_color=(0.2, 0.5, 0.8),
        metallic=0.3,
        subsurface=0.7,
        specular=0.9,
        roughness=0.6,
        specular_tint=0.6,
        anisotropic=0.5,
        sheen=1.0,
        sheen_tint=0.8,
        clearcoat=1.0,
        clearcoat_gloss=0.4,
    ),
    "smooth": dict(roughness=0.0, anisotropic=1.0, clearcoat=1.0),
    "rough-white": dict(base_color=1.0, roughness=1.0, subsurface=1.0, sheen=0.5),
}


def _random_directions(seed, count):
    rng = np.random.default_rng(seed)

    def unit(a):
        return a / np.linalg.norm(a, axis=-1, keepdims=True)

    n = unit(rng.normal(size=(count, 3)))
    l = unit(rng.normal(size=(count, 3)))  # noqa: E741
    v = unit(rng.normal(size=(count, 3)))
    l = np.where(np.sum(n * l, -1, keepdims=True) < 0, -l, l)  # noqa: E741
    v = np.where(np.sum(n * v, -1, keepdims=True) < 0, -v, v)
    q = count // 3  # a third near the mirror direction, where the specular peak lives
    mirror = 2 * n[:q] * np.sum(n[:q] * l[:q], -1, keepdims=True) - l[:q]
    v[:q] = unit(mirror + 0.05 * rng.normal(size=(q, 3)))
    t = rng.normal(size=(count, 3))
    return n, l, v, t


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("setting", list(SETTINGS))
def test_eval_matches_the_80_digit_shader_at_ordinary_inputs(setting, dtype):
    model = Disney(**SETTINGS[setting])
    n, l, v, t = _random_directions(7, 24)  # noqa: E741
    assert _worst_ratio(model, n, l, v, t, dtype) <= 16
    # Without a tangent: the documented default frame t = ẑ × n / |ẑ × n|.
    assert _worst_ratio(model, n[:8], l[:8], v[:8], None, dtype) <= 16


def _grazing_cases():
    """n = ẑ (exact components), directions 1e-6 rad from the horizon, peaks and near-opposite pairs."""
    e = 1e-6
    ce, se = math.cos(e), math.sin(e)
    z = (0.0, 0.0, 1.0)
    up = (0.0, 0.0, 1.0)
    d45 = (math.sqrt(0.5), 0.0, math.sqrt(0.5))
    rows = [
        (z, (ce, 0.0, se), (ce, 0.0, se)),  # both grazing, same side (retro)
        (z, (ce, 0.0, se), (-ce, 0.0, se)),  # both grazing, mirror pair: h = n, cos θ_d = sin e
        (z, (ce, 0.0, se), (0.0, ce, se)),  # both grazing, at right angles
        (z, (ce, 0.0, se), up),  # grazing light, viewer at the normal
        (z, up, (0.6 * ce, 0.8 * ce, se)),  # grazing viewer
        (z, (ce, 0.0, se), d45),
        (z, up, up),  # the normal itself
        (z, (math.sin(1e-4), 0.0, math.cos(1e-4)), (-math.sin(2e-4), 1e-5, math.cos(2e-4))),  # near the peak
        (z, (0.6, 0.0, 0.8), (-0.6, 3e-7, 0.8)),  # 1e-7-ish off the mirror direction
        (z, (ce, 1e-7, se), (-ce, 0.0, se)),  # the mirror pair, slightly turned
    ]
    n, l, v = (np.array([r[i] for r in rows]) for i in range(3))  # noqa: E741
    return n, l, v


EXTREME = {
    "default": {},
    "smooth-aniso": dict(roughness=0.0, anisotropic=1.0, metallic=1.0, base_color=(1.0, 0.5, 1e-300)),
    "tiny": dict(
        base_color=1e-300,
        metallic=1e-300,
        subsurface=1e-300,
        specular=1e-300,
        roughness=1e-300,
        specular_tint=1e-300,
        anisotropic=1e-300,
        sheen=1e-300,
        sheen_tint=1e-300,
        clearcoat=1e-300,
        clearcoat_gloss=1e-300,
    ),
    "nearly-one": dict(
        base_color=1.0,
        metallic=1 - 1e-16,
        subsurface=1 - 1e-16,
        specular=1.0,
        roughness=1.0,
        specular_tint=1.0,
        anisotropic=1.0,
        sheen=1.0,
        sheen_tint=1.0,
        clearcoat=1.0,
        clearcoat_gloss=1.0,
    ),
    "subsurface-sheen": dict(subsurface=1.0, sheen=1.0, roughness=1.0, clearcoat=1.0, clearcoat_gloss=0.0),
}


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("setting", list(EXTREME))
def test_eval_matches_the_80_digit_shader_at_extreme_inputs(setting, dtype):
    model = Disney(**EXTREME[setting])
    n, l, v = _grazing_cases()  # noqa: E741
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert _worst_ratio(model, n, l, v, None, dtype) <= 16
        # eval_cos and classic stay finite and consistent there too.
        fc = model.eval_cos(n.astype(dtype), l.astype(dtype), v.astype(dtype))
        assert fc.dtype == dtype and np.all(np.isfinite(fc)) and np.all(fc >= 0)


def test_degenerate_vectors_give_zero_without_warnings():
    m = Disney(**SETTINGS["everything"])
    n = np.array([[0, 0, 1.0], [0, 0, 1.0], [0, 0, 0.0], [0, 0, 1.0], [0, 0, 1.0]])
    l = np.array([[0, 0, 0.0], [1.0, 0, 0], [0, 0, 1.0], [1.0, 0, 1e-300], [0.6, 0, 0.8]])  # noqa: E741
    v = np.array([[0, 0, 1.0], [-1.0, 0, 0], [0, 0, 1.0], [-1.0, 0, 1e-300], [-0.6, 0, -0.8]])
    for dt in (np.float32, np.float64):
        out = m.eval(n.astype(dt), l.astype(dt), v.astype(dt), tangent=np.zeros(3, dt))
        assert np.all(np.isfinite(out))
        assert np.all(out[[0, 1, 2, 4]] == 0)


def test_registered_and_parameters_checked():
    assert "disney" in model_names()
    assert isinstance(create_model("disney", roughness=0.2), Disney)
    for name in ("metallic", "roughness", "clearcoat_gloss"):
        for bad in (-0.1, 1.5, float("nan")):
            with pytest.raises(ValueError, match=name):
                Disney(**{name: bad})
    with pytest.raises(ValueError, match="base_color"):
        Disney(base_color=(0.5, 1.2, 0.1))
    assert Disney().summary() == "base=0.8 metallic=0 r=0.5 specular=0.5"
    lobe = Disney(roughness=0.3, anisotropic=0.5).lobe()
    assert lobe.axis == "half" and lobe.width == pytest.approx(0.09 / math.sqrt(2))


# --------------------------------------------------------------------------- laws
@pytest.mark.parametrize("setting", list(SETTINGS))
def test_reciprocity(setting):
    # Every part is symmetric in l and v: the diffuse (F_L F_V product, 1/(n·l + n·v)), sheen, specular
    # (D(h), separable G, F(θ_d)) and clearcoat.  The half vector is l + v = v + l, so bit for bit.
    m = Disney(**SETTINGS[setting])
    n, l, v, t = _random_directions(3, 400)  # noqa: E741
    for dt in (np.float64, np.float32):
        a = m.eval(n.astype(dt), l.astype(dt), v.astype(dt), tangent=t.astype(dt))
        b = m.eval(n.astype(dt), v.astype(dt), l.astype(dt), tangent=t.astype(dt))
        np.testing.assert_allclose(a, b, rtol=4 * np.finfo(dt).eps, atol=0)


def _ndf_integral(d_of_h, scale):
    return float(hemisphere(lambda h: d_of_h(h) * h[..., 2], scale=scale, panels=80, order=24, n_phi=1024))


@pytest.mark.parametrize("ax, ay", [(0.25, 0.25), (0.001, 0.001), (0.7, 0.07), (0.0285, 0.285), (1.0, 1.0)])
def test_gtr2_is_normalized(ax, ay):
    got = _ndf_integral(lambda h: gtr2_aniso(h, ax, ay), min(ax, ay) / 10)
    assert got == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize("a", [0.001, 0.01, 0.1, 0.5, 0.999, 1.0])
def test_gtr1_is_normalized(a):
    def d(h):
        return gtr1(h[..., 2], h[..., 0] ** 2 + h[..., 1] ** 2, a)

    assert _ndf_integral(d, a / 10) == pytest.approx(1.0, abs=1e-9)
    # The shader's own form (1 + (α² − 1) cos²θ_h) at a moderate angle, and its peak.
    if a < 1:
        c = 0.7
        want = (a * a - 1) / (math.pi * math.log(a * a) * (1 + (a * a - 1) * c * c))
        assert float(gtr1(c, 1 - c * c, a)) == pytest.approx(want, rel=1e-13)


@pytest.mark.parametrize("roughness", [0.0, 0.05, 0.1])
def test_metal_reflects_its_base_color_at_normal_incidence(roughness):
    base = np.array([0.95, 0.64, 0.54])  # copper-ish
    m = Disney(base_color=base, metallic=1.0, roughness=roughness)
    a = max(0.001, roughness**2)
    # At n = l = v: F_H = 0, so F = C_spec0 = base; D = 1/(π α²), G1/(2 n·ω) = 1/2 each.
    z = (0, 0, 1.0)
    np.testing.assert_allclose(m.eval(z, z, z), base / (4 * math.pi * a * a), rtol=1e-14)
    # And the directional albedo at normal view is F(0) = base, up to G and F over the narrow lobe.
    rho = directional_albedo(m, 0.0, samples=20000)
    np.testing.assert_allclose(rho, base, rtol=2e-3)


ALBEDO_THETAS_DEG = (0, 15, 30, 45, 60, 70, 80, 85, 89, 89.9)


def test_default_albedo_is_at_most_one():
    rho = directional_albedo(Disney(), np.radians(ALBEDO_THETAS_DEG), samples=20000)
    grey = rho[:, 0]
    assert np.all(grey <= 1.0)
    assert np.all(grey > 0.8)
    # The measured curve (reported in the module docstring).
    want = [0.8414, 0.8412, 0.8409, 0.8433, 0.8622, 0.8975, 0.9523, 0.9783, 0.9888, 0.9887]
    np.testing.assert_allclose(grey, want, atol=1e-4)


def test_albedo_quadrature_agrees_with_the_sampler_estimate():
    m = Disney(**SETTINGS["everything"])
    for th in (0.3, 1.2):
        q = directional_albedo(m, th, samples=20000)
        est = directional_albedo(m, th, samples=200_000, method="importance", seed=4, return_error=True)
        assert np.all(np.abs(q - est.value) <= 4 * est.error + 1e-4)


# --------------------------------------------------------------------------- the sampler
def _chi_square_p(sampler, v, count=100_000, seed=2024, gauss=8):
    d = sampler.sample(np.random.default_rng(seed).random((count, 2)), v).directions
    nt, nph = 24, 48
    ti = np.minimum(((1 - d[:, 2]) / 2 * nt).astype(int), nt - 1)
    pj = np.minimum((np.mod(np.arctan2(d[:, 1], d[:, 0]), 2 * math.pi) / (2 * math.pi) * nph).astype(int), nph - 1)
    counts = np.bincount(ti * nph + pj, minlength=nt * nph).astype(float)
    x, w = np.polynomial.legendre.leggauss(gauss)
    z_edges = 1 - 2 * np.arange(nt + 1) / nt
    p_edges = np.arange(nph + 1) * 2 * math.pi / nph
    zc = (z_edges[:-1, None] + z_edges[1:, None]) / 2 + (z_edges[1:, None] - z_edges[:-1, None]) / 2 * x
    pc = (p_edges[:-1, None] + p_edges[1:, None]) / 2 + (p_edges[1:, None] - p_edges[:-1, None]) / 2 * x
    zz, pp = zc[:, None, :, None], pc[None, :, None, :]
    r = np.sqrt(np.clip(1 - zz**2, 0, None))
    dirs = np.stack(np.broadcast_arrays(r * np.cos(pp), r * np.sin(pp), zz), -1)
    dens = sampler.pdf(dirs, v)
    cell = (2 / nt) * (2 * math.pi / nph) / 4
    expected = count * np.sum(dens * w[:, None] * w[None, :], axis=(-2, -1)).ravel() * cell
    order = np.argsort(expected)
    e_sorted, c_sorted = expected[order], counts[order]
    small = np.cumsum(e_sorted) < 50
    e_bins = np.r_[e_sorted[small].sum(), e_sorted[~small]]
    c_bins = np.r_[c_sorted[small].sum(), c_sorted[~small]]
    keep = e_bins > 0
    chi2 = np.sum((c_bins[keep] - e_bins[keep]) ** 2 / e_bins[keep])
    return float(chi2_sf(chi2, keep.sum() - 1)), float(expected.sum() / count)


SAMPLER_SETTINGS = {
    "default": {},
    "metal-aniso": dict(metallic=1.0, roughness=0.5, anisotropic=1.0, base_color=(0.9, 0.6, 0.3)),
    "clearcoat-satin": dict(roughness=0.8, clearcoat=1.0, clearcoat_gloss=0.0, base_color=0.2),
    "sheen": dict(sheen=1.0, roughness=0.9, base_color=(0.5, 0.1, 0.1)),
}


@pytest.mark.parametrize("theta_deg", [0.0, 40.0])
@pytest.mark.parametrize("setting", list(SAMPLER_SETTINGS))
def test_sampler_chi_square_in_cells_of_l(setting, theta_deg):
    # In l itself, where the cells' quadrature resolves the density: an independent check of the half-vector
    # cells of test_sampler_grazing_full.py (which tests these settings from 0° to 89°).
    s = Disney(**SAMPLER_SETTINGS[setting]).sampler()
    t = math.radians(theta_deg)
    v = np.array([math.sin(t) * math.cos(0.4), math.sin(t) * math.sin(0.4), math.cos(t)])
    p, mass = _chi_square_p(s, v, seed=99, gauss=24)
    assert mass == pytest.approx(1.0, rel=5e-3)  # the contract's: a sharp lobe at −v loses a little here
    assert p > 1e-3


def test_sampler_components_are_exact():
    # Each component alone (weights (1,0,0), (0,1,0), (0,0,1)) against its own density, with sharp lobes too.
    v = np.array([math.sin(0.7), 0.0, math.cos(0.7)])
    for s in (
        DisneySampler(0.3, 0.3, 0.1, diffuse=1.0, specular0=0.0),
        DisneySampler(0.6, 0.06, 0.1, diffuse=0.0, specular0=1.0),
        DisneySampler(0.3, 0.3, 0.05, diffuse=0.0, specular0=0.0, clearcoat=1.0),
        DisneySampler(0.3, 0.3, 0.5, diffuse=0.0, specular0=0.0, clearcoat=1.0),
    ):
        p, mass = _chi_square_p(s, v, seed=11)
        assert p > 1e-3, s
        assert mass == pytest.approx(1.0, rel=5e-3), s


def test_sampler_pdf_is_the_returned_density_and_the_half_vector_densities_integrate_to_one():
    s = Disney(**SETTINGS["everything"]).sampler()
    v = np.array([0.3, 0.2, math.sqrt(1 - 0.13)])
    out = s.sample(np.random.default_rng(1).random((1000, 2)), v)
    np.testing.assert_allclose(out.pdf, s.pdf(out.directions, v), rtol=1e-12)
    assert np.all(np.isfinite(out.directions)) and np.all(out.pdf > 0)
    # The diffuse component's density and its smoothness at the horizon.
    assert float(hemisphere(lambda d: smooth_cosine_pdf(d[..., 2]))) == pytest.approx(31 / 32, abs=1e-12)
    assert float(hemisphere(lambda d: smooth_cosine_pdf(-d[..., 2]))) == pytest.approx(1 / 32, abs=1e-12)
    # Weights: documented estimates; a zero model falls back to the diffuse component.
    w = DisneySampler(0.1, 0.1, 0.1, diffuse=0.0, specular0=0.0).weights(np.array([0, 0, 1.0]))
    np.testing.assert_array_equal(w, [1.0, 0.0, 0.0])


@pytest.mark.parametrize("theta_deg", [0.0, 60.0, 89.9])
def test_importance_estimate_has_bounded_weights_for_the_default(theta_deg):
    # f cos / p over many samples stays moderate: the mixture covers each lobe.
    m = Disney()
    s = m.sampler()
    t = math.radians(theta_deg)
    v = np.array([math.sin(t), 0.0, math.cos(t)])
    out = s.sample(np.random.default_rng(5).random((50_000, 2)), v)
    n = np.broadcast_to([0, 0, 1.0], out.directions.shape)
    fc = m.eval_cos(n, out.directions, np.broadcast_to(v, out.directions.shape))[:, 0]
    w = np.where(out.pdf > 0, fc / np.where(out.pdf > 0, out.pdf, 1), 0)
    assert np.max(w) < 5.0

r"""The importance sampler of MERL tables (lighting.sampling.merl): χ², mass, albedo, variance.

The χ² test uses :mod:`tests.chi2`'s half-vector cells, adaptive cell integrals and pooling, with one change:
the cells' edges are edges of the sampler's own ``(θ_h, φ_h)`` bins (grouped), not pilot quantiles.  Its
density over ``h`` is piecewise constant, and a cell edge crossing a jump of it would never let the adaptive
rule converge (chi2.py's 1e-7 relative tolerance); on bin-aligned cells the tabulated part is constant per
cell and only the cosine part's horizon kink is left to resolve, as for the cosine sampler.
"""

from __future__ import annotations

import math
import os
import sys

import numpy as np
import pytest

from lighting.brdf import BlinnPhong, CookTorrance, Lambert
from lighting.files.merl import MerlBRDF, tabulate_merl
from lighting.integrate import directional_albedo
from lighting.models.lambert import CosineSampler
from lighting.sampling.merl import MerlSampler

pytestmark = pytest.mark.slow  # the MERL table sampler's χ², variance and mass checks

sys.path.insert(0, os.path.dirname(os.path.dirname(__file__)))
import chi2  # noqa: E402  (tests/chi2.py, shared by the model tests)

N = np.array([0.0, 0.0, 1.0])
VIEWS_DEG = (0, 40, 70, 85)


@pytest.fixture(scope="module")
def glossy():
    # GGX α = 0.1 with Smith shadowing over a dim Lambert: a sharp lobe the cosine samples badly.
    return MerlBRDF(tabulate_merl(CookTorrance((0.6, 0.5, 0.4), 0.1, 0.04, ndf="ggx", geometry="smith") + Lambert(0.2)))


@pytest.fixture(scope="module")
def blinn():
    return MerlBRDF(tabulate_merl(BlinnPhong(0.6, 60, normalized=True)))


def _view(deg, phi=0.0):
    t = math.radians(deg)
    return np.array([math.sin(t) * math.cos(phi), math.sin(t) * math.sin(phi), math.cos(t)])


def _bin_cells(sampler, v, rings=16, sectors=24):
    """chi2._Cells whose edges are the sampler's bin edges: rings at the θ_h marginal's quantiles (φ_v = 0)."""
    tab = sampler.table(int(sampler._view(v)[1]))
    idx = np.unique(np.searchsorted(tab.marginal, np.arange(1, rings) / rings))
    idx = idx[(idx > 0) & (idx < sampler.theta_h_bins)]
    theta = np.concatenate([[0.0], sampler._theta_edges[idx], [math.pi / 2]])
    step = sampler.phi_h_bins // sectors
    phi = np.arange(0, sampler.phi_h_bins + 1, step) * sampler._dphi
    phi[-1] = 2 * math.pi
    cells = chi2._Cells.__new__(chi2._Cells)
    cells.theta, cells.rings, cells.sectors = theta, len(theta) - 1, len(phi) - 1
    cells.phi = np.tile(phi, (cells.rings, 1))
    return cells


def _binned_chi2(sampler, v, count=100_000, seed=2024, mass_tol=1e-5):
    """chi2.chi2_test's statistic on bin-aligned cells (module docstring); returns (p, mass).

    A cell's mass is the cosine part's by chi2's adaptive rule plus the tabulated part's, taken from
    ``sampler.pdf`` at every bin centre times the bin's solid angle: exact, that part being constant per bin.
    """
    assert abs(v[1]) < 1e-15 and v[0] >= 0, "the cells assume φ_v = 0"
    cells = _bin_cells(sampler, v)
    a = sampler.cosine_weight

    def to_l(h):
        vh = h @ v
        return 2 * vh[..., None] * h - v, np.abs(vh)

    def q_cos(h):
        l, vh = to_l(h)  # noqa: E741
        return a * 4 * vh * np.maximum(l[..., 2], 0) / math.pi

    ct = 0.5 * (sampler._cos_edges[:-1] + sampler._cos_edges[1:])
    st = np.sqrt(1 - ct**2)
    ph = (np.arange(sampler.phi_h_bins) + 0.5) * sampler._dphi
    hc = np.stack(np.broadcast_arrays(st[:, None] * np.cos(ph), st[:, None] * np.sin(ph), ct[:, None]), -1)
    hc = hc.reshape(-1, 3)
    l_c, vh_c = to_l(hc)
    q_tab = sampler.pdf(l_c, v) * 4 * vh_c - q_cos(hc)
    tab_mass = q_tab * np.repeat(sampler._solid, sampler.phi_h_bins)
    l = sampler.sample(np.random.default_rng(seed).random((count, 2)), v).directions  # noqa: E741
    h = chi2._half_vectors(l, v)
    assert np.all(np.isfinite(h))
    counts = np.bincount(cells.index(h), minlength=cells.rings * cells.sectors).astype(float)
    masses, unresolved = chi2._cell_masses(q_cos, cells)
    masses += np.bincount(cells.index(hc), weights=tab_mass, minlength=masses.size)
    mass = float(masses.sum())
    assert unresolved <= mass_tol
    assert mass == pytest.approx(1.0, abs=mass_tol)
    expected = count * masses
    order = np.argsort(expected)
    e, c = expected[order], counts[order]
    small = np.cumsum(e) < 50
    e_bins, c_bins = np.r_[e[small].sum(), e[~small]], np.r_[c[small].sum(), c[~small]]
    keep = e_bins > 0
    assert np.sum(c_bins[~keep]) == 0, "samples in cells of zero density"
    stat = float(np.sum((c_bins[keep] - e_bins[keep]) ** 2 / e_bins[keep]))
    return float(chi2.chi2_sf(stat, keep.sum() - 1)), mass


@pytest.mark.parametrize("which", ["glossy", "blinn"])
@pytest.mark.parametrize("deg", VIEWS_DEG)
def test_chi2_and_mass(which, deg, request):
    brdf = request.getfixturevalue(which)
    p, mass = _binned_chi2(brdf.sampler(), _view(deg))
    # 8 tests at family-wise level 1 %; the mass (∫ pdf dω over the sphere) is 1 within 1e-5.
    assert p > chi2.sidak(0.01, 8), f"χ² p = {p:.3g} at θ_v = {deg}°"
    assert mass == pytest.approx(1.0, abs=1e-5)


def test_sample_pdf_equal_and_positive_above_horizon(glossy):
    s = glossy.sampler()
    assert s is glossy.sampler()  # one sampler per table: its view tables are built once
    rng = np.random.default_rng(3)
    v = np.stack([_view(d, p) for d, p in zip(rng.uniform(0, 89, 500), rng.uniform(0, 6.3, 500), strict=True)])
    out = s.sample(rng.random((500, 2)), v)
    np.testing.assert_allclose(out.pdf, s.pdf(out.directions, v), rtol=1e-12)
    # Defensive mixture: every direction above the horizon has at least 15 % of the cosine density.
    l = rng.normal(size=(500, 3))  # noqa: E741
    l /= np.linalg.norm(l, axis=-1, keepdims=True)
    p = s.pdf(l, v)
    assert np.all(p >= 0.15 * np.maximum(l[:, 2], 0) / math.pi * (1 - 1e-12))
    assert np.all(np.isfinite(p))


def test_rotation_invariance(blinn):
    """Isotropy: turning the view about the normal turns the samples and keeps the density."""
    s = blinn.sampler()
    u = np.random.default_rng(4).random((2000, 2))
    a = 1.234
    rot = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
    v0 = _view(55)
    s0, s1 = s.sample(u, v0), s.sample(u, rot @ v0)
    # The tabulated part (u₀ >= cosine_weight) turns with the view; the cosine part does not depend on it.
    tab = u[:, 0] >= s.cosine_weight
    np.testing.assert_allclose(s1.directions[tab], s0.directions[tab] @ rot.T, atol=1e-9)
    np.testing.assert_allclose(s1.directions[~tab], s0.directions[~tab])
    np.testing.assert_allclose(s.pdf(s0.directions @ rot.T, rot @ v0), s0.pdf, rtol=1e-9)


def test_view_below_horizon_is_cosine(glossy):
    s, c = glossy.sampler(), CosineSampler()
    u = np.random.default_rng(5).random((100, 2))
    v = np.array([0.6, 0.0, -0.8])
    np.testing.assert_allclose(s.sample(u, v).directions, c.sample(u, v).directions)
    np.testing.assert_allclose(s.pdf(s.sample(u, v).directions, v), c.pdf(c.sample(u, v).directions, v))


def test_black_table_falls_back_to_cosine():
    s = MerlBRDF(np.zeros((3, 90, 90, 180))).sampler()
    v, u = _view(30), np.random.default_rng(6).random((100, 2))
    out = s.sample(u, v)
    np.testing.assert_allclose(out.pdf, np.maximum(out.directions[:, 2], 0) / math.pi)


def _mc(brdf, sampler, v, count, seed):
    o = sampler.sample(np.random.default_rng(seed).random((count, 2)), v)
    f = brdf.eval(N, o.directions, v) * np.maximum(o.directions[:, 2], 0)[:, None]
    w = np.where(o.pdf[:, None] > 0, f / np.where(o.pdf > 0, o.pdf, 1.0)[:, None], 0.0)
    return w.mean(axis=0), w.std(axis=0) / math.sqrt(count)


@pytest.mark.parametrize("deg", [40, 85])
def test_albedo_and_variance(glossy, deg):
    v = _view(deg)
    ref = directional_albedo(glossy, math.radians(deg), samples=2_000_000, return_error=True)
    mean, sigma = _mc(glossy, glossy.sampler(), v, 200_000, 11)
    assert np.all(np.abs(mean - ref.value) <= 4 * np.hypot(sigma, ref.error)), (mean, ref)
    _, sigma_cos = _mc(glossy, CosineSampler(), v, 200_000, 11)
    # Measured variance ratios cosine / this sampler: 37 at 40°, 6700 at 85° (17 at 0°, 820 at 70°).
    assert np.all((sigma_cos / sigma) ** 2 > {40: 20, 85: 1000}[deg])


def test_argument_errors(glossy):
    with pytest.raises(ValueError, match="cosine_weight"):
        MerlSampler(glossy, cosine_weight=0.0)
    with pytest.raises(ValueError, match="theta_h_bins"):
        MerlSampler(glossy, theta_h_bins=0)
    with pytest.raises(TypeError, match="BRDF"):
        MerlSampler("not a brdf")
    with pytest.raises(ValueError, match="u"):
        glossy.sampler().sample(np.array([[1.5, 0.2]]), _view(10))

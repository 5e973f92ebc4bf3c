"""The χ² test of a sampler against its density (Mitsuba style), shared by the model tests."""

import math

import numpy as np
import pytest
from scipy import stats


def chi2_pvalue(sampler, v, count=60_000, nt=16, nph=32, seed=2024):
    """p-value of ``count`` samples at view ``v`` over (cos θ, φ) cells of the sphere, against the density.

    The density is integrated over each cell with 6 × 6 Gauss–Legendre points; the sparsest cells are
    pooled into one bin of at least 50 expected samples.  Also asserts that the density integrates to 1
    over the cells (to 0.5 %).
    """
    d = sampler.sample(np.random.default_rng(seed).random((count, 2)), v).directions
    ti = np.minimum(((1 - d[:, 2]) / 2 * nt).astype(int), nt - 1)
    pj = np.minimum((np.mod(np.arctan2(d[:, 1], d[:, 0]), 2 * math.pi) / (2 * math.pi) * nph).astype(int), nph - 1)
    counts = np.bincount(ti * nph + pj, minlength=nt * nph).astype(float)
    x, w = np.polynomial.legendre.leggauss(6)
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
    assert expected.sum() == pytest.approx(count, rel=5e-3)
    return stats.chi2.sf(chi2, keep.sum() - 1)

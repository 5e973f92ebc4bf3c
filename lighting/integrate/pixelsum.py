"""Reflected radiance under a lat-long environment by deterministic quadrature: the precise reference.

A lat-long environment (:class:`~lighting.lights.environment.LatLongEnvironment`) is bilinear between its pixel
centres (:func:`lighting.lights.latlong.latlong_lookup`).  Cut along the rows and columns of pixel centres (and
the two polar caps, where a direction reads its edge row), the sphere falls into ``(H + 1) × W`` cells, and inside
each the integrand of ``L_o(v) = ∫ L(l) f_r(v, l) max(n·l, 0) dω_l = Σ_cells ∬ L f_r max(n·l, 0) sin θ dθ da``
is smooth but where the horizon crosses the cell.  Each cell is integrated by tensor Gauss–Legendre in ``(θ, a)``
(``a = 2π u``, the image's column angle), adaptively: every cell above the horizon gets the one-node rule and the
2 × 2 rule; the cells the horizon may cross (a kink of ``max(n·l, 0)``, where two low rules can agree by chance)
and those whose two rules differ most are done again with 4 × 4 and 8 × 8 nodes, and split in quarters where
those differ, until the differences left add up to ``rtol`` of the pixel's largest channel.  The error reported
is the sum of those differences: ``|S₂ − S₁|`` for a cell kept at 2 × 2, ``|S₈ − S₄|`` for a refined piece (each
bounds the better rule's error with room to spare where the integrand is smooth).

Monte Carlo needs a hundred times the samples for ten times the precision, and the engine's MIS reference
(:class:`~lighting.integrate.ibl.ProgressiveRadiance`) at thousands of samples per pixel is as noisy as the errors
of the fast methods it judges (``report accuracy --only ibl`` prints its own error beside them).  This sum reaches
``rtol`` (1e-4 by default) with a few hundred thousand BRDF evaluations per pixel:
:mod:`lighting.validation.accuracy` judges the fast methods against it too.
"""

from __future__ import annotations

import math
import time

import numpy as np

from .._budget import check_budget
from .._validate import check_range, check_vectors
from ..sampling.brdf import _check_brdf
from ._delta import split_delta
from .estimate import Estimate

__all__ = ["environment_sum_radiance"]

#: Gauss–Legendre nodes per axis of the first two rules and the refinements.
_COARSE, _FINE, _FINER, _FINEST = 1, 2, 4, 8
#: Times a refined cell may be split in four (a 64th of a pixel a side at the deepest).
_MAX_DEPTH = 6
#: Rectangles refined at once at most (80 BRDF evaluations each); beyond it the rules' difference is the error.
_MAX_RECTS = 1 << 16


def _nodes(lo: np.ndarray, hi: np.ndarray, k: int):
    """Gauss–Legendre nodes and weights of ``k`` points on each interval ``[lo, hi]``: ``(n, k)`` each."""
    x, w = np.polynomial.legendre.leggauss(k)
    half = (hi - lo)[:, None] / 2
    return (lo + hi)[:, None] / 2 + half * x, half * w


def _cell_edges(height: int, width: int):
    """``θ`` edges (``H + 2``: the poles and the rows of pixel centres) and column-angle edges (``W + 1``)."""
    theta = np.concatenate([[0.0], (np.arange(height) + 0.5) * (math.pi / height), [math.pi]])
    a = (np.arange(width + 1) + 0.5) * (2 * math.pi / width)  # the last cell wraps past 2π back to the first column
    return theta, a


class _Rule:
    """The nodes of one tensor rule over rectangles ``[t0, t1] × [a0, a1]`` of ``(θ, a)``: unit directions,
    ``sin θ dθ da`` weights and the environment's radiance times them; ``k`` nodes per axis."""

    def __init__(self, env, t0, t1, a0, a1, k):
        th, wt = _nodes(t0, t1, k)
        a, wa = _nodes(a0, a1, k)
        st = np.sin(th)
        phi = math.pi - a  # the column angle looks along φ = π − a (lighting.lights.latlong)
        # Node (i, j) of a rectangle: θ_i, a_j.
        self.dirs = np.stack([
            (st[:, :, None] * np.cos(phi)[:, None, :]).reshape(-1),
            (st[:, :, None] * np.sin(phi)[:, None, :]).reshape(-1),
            np.broadcast_to(np.cos(th)[:, :, None], (len(t0), k, k)).reshape(-1),
        ], axis=-1)  # fmt: skip
        self.weights = ((wt * st)[:, :, None] * wa[:, None, :]).reshape(-1)
        self.radiance = np.asarray(env.radiance(self.dirs), dtype=np.float64) * self.weights[:, None]
        self.k = k

    def sums(self, brdf, n, v, select=None):
        """``Σ L f_r max(n·l, 0) w`` per rectangle (``(R, 3)``), over all or the ``select``-ed ones."""
        k2 = self.k * self.k
        if select is None:
            dirs, lw = self.dirs, self.radiance
        else:
            idx = (select[:, None] * k2 + np.arange(k2)).reshape(-1)
            dirs, lw = self.dirs[idx], self.radiance[idx]
        cos = dirs @ n
        up = cos > 0
        out = np.zeros((lw.shape[0], 3))
        if np.any(up):
            f = np.asarray(brdf.eval(n, dirs[up], v), dtype=np.float64)
            out[up] = f * (cos[up, None] * lw[up])
        return out.reshape(-1, k2, 3).sum(axis=1)


def _refine(env, brdf, n, v, rects, budget):
    """``(sum, error, evaluations)`` of rectangles ``(t0, t1, a0, a1)`` by the 4 × 4 and 8 × 8 rules, split in four
    where they differ, until what is left adds up to ``budget`` (half of what remains at each depth)."""
    total, err, evaluations = np.zeros(3), np.zeros(3), 0
    for depth in range(_MAX_DEPTH + 1):
        if not rects[0].size:
            break
        s4 = _Rule(env, *rects, _FINER).sums(brdf, n, v)
        s8 = _Rule(env, *rects, _FINEST).sums(brdf, n, v)
        evaluations += rects[0].size * (_FINER**2 + _FINEST**2)
        diff = np.abs(s8 - s4)
        worst = diff.max(axis=1)
        order = np.argsort(worst, kind="stable")
        last = depth == _MAX_DEPTH or rects[0].size * 4 > _MAX_RECTS
        # The smallest differences are accepted while they fit in half the budget left; the rest are split.
        accept = np.zeros(worst.size, dtype=bool)
        accept[order[: int(np.searchsorted(np.cumsum(worst[order]), budget / 2, side="right"))]] = True
        if last:
            accept[:] = True
        total += s8[accept].sum(axis=0)
        err += diff[accept].sum(axis=0)
        budget = max(budget - float(worst[accept].sum()), 0.0)
        t0, t1, a0, a1 = (r[~accept] for r in rects)
        tm, am = (t0 + t1) / 2, (a0 + a1) / 2
        rects = (np.concatenate([t0, tm, t0, tm]), np.concatenate([tm, t1, tm, t1]),
                 np.concatenate([a0, a0, am, am]), np.concatenate([am, am, a1, a1]))  # fmt: skip
    return total, err, evaluations


def environment_sum_radiance(brdf, environment, normals, view_dirs, *, rtol: float = 1e-4) -> Estimate:
    r"""Reflected radiance of a lat-long environment by adaptive Gauss–Legendre over its cells (module notes).

    Parameters
    ----------
    brdf : BRDF
        Any model without a delta part (a mirror's reflection is a lookup, not an integral).
    environment : LatLongEnvironment
        The image, bilinear between its pixel centres as every method reads it.
    normals, view_dirs : array_like, (P, 3) or (3,)
        Unit normals and unit directions toward the viewer (broadcast together; the world frame of the image).
    rtol : float, optional
        The differences of the rules left unrefined, relative to each pixel's largest channel (1e-6 to 1e-2).

    Returns
    -------
    Estimate
        ``value`` and ``error`` ``(P, 3)`` float64 (0 where ``n·v <= 0``); ``samples`` the largest number of
        BRDF evaluations one pixel took; ``method`` ``"pixel sum"``.

    Examples
    --------
    >>> from lighting.lights.environment import LatLongEnvironment
    >>> from lighting.models.brdf import Lambert
    >>> sky = LatLongEnvironment(np.full((8, 16, 3), 2.0))
    >>> est = environment_sum_radiance(Lambert(0.5), sky, (0.0, 0.0, 1.0), (0.0, 0.6, 0.8))
    >>> est.value.round(6).tolist(), bool(est.error.max() < 1e-4)  # the furnace: k_d L
    ([1.0, 1.0, 1.0], True)
    """
    from ..lights.environment import LatLongEnvironment

    t0 = time.perf_counter()
    brdf = _check_brdf(brdf)
    if split_delta(brdf)[1]:
        raise ValueError(f"brdf must have no delta part (a mirror is a lookup, not an integral); got {brdf!r}")
    if not isinstance(environment, LatLongEnvironment):
        raise TypeError(f"environment must be a LatLongEnvironment; got {type(environment).__name__}")
    rtol = check_range("rtol", rtol, 1e-6, 1e-2)
    n = check_vectors("normals", normals).astype(np.float64)
    v = check_vectors("view_dirs", view_dirs).astype(np.float64)
    shape = np.broadcast_shapes(n.shape, v.shape)
    n = np.broadcast_to(n, shape).reshape(-1, 3)
    v = np.broadcast_to(v, shape).reshape(-1, 3)
    h, w = environment.height, environment.width
    cells = (h + 1) * w
    # The 1- and 2-node rules' directions, weights and radiance, kept for every pixel: 5 nodes × 7 float64 per cell.
    check_budget("environment", cells * 5 * 7 * 8 * 3, what=f"the cells of a {w}x{h} environment")
    theta_edges, a_edges = _cell_edges(h, w)
    rows, cols = np.divmod(np.arange(cells), w)
    bounds = (theta_edges[rows], theta_edges[rows + 1], a_edges[cols], a_edges[cols + 1])
    coarse = _Rule(environment, *bounds, _COARSE)
    fine = _Rule(environment, *bounds, _FINE)
    # A cell lies wholly below the horizon when its centre is farther below it than the cell's half-diagonal.
    reach = math.sin(min(math.pi / 2, 1.5 * math.pi / h))
    value = np.zeros((n.shape[0], 3))
    error = np.zeros((n.shape[0], 3))
    evaluations = np.zeros(n.shape[0], dtype=np.int64)

    def pixel(p):
        if n[p] @ v[p] <= 0:
            return
        cos_centre = coarse.dirs @ n[p]
        lit = np.flatnonzero(cos_centre > -reach)
        s1 = coarse.sums(brdf, n[p], v[p], lit)
        s2 = fine.sums(brdf, n[p], v[p], lit)
        differ = np.abs(s2 - s1)
        diff = differ.max(axis=1)
        scale = max(float(np.max(s2.sum(axis=0))), np.finfo(np.float64).tiny)
        # The cells with the largest differences are refined, until those left add up to half of rtol of the sum;
        # the cells the horizon may cross first of all (a kink of max(n·l, 0) inside a cell: two low rules can
        # agree there by chance).
        crossing = np.abs(cos_centre[lit]) < reach
        order = np.lexsort((-diff, ~crossing))
        left = np.cumsum(diff[order][::-1])[::-1]  # what stays unrefined if refining stops at each index
        count = max(int(np.searchsorted(-left, -0.5 * rtol * scale)), int(crossing.sum()))
        keep = np.ones(lit.size, dtype=bool)
        keep[order[:count]] = False
        total, err = s2[keep].sum(axis=0), differ[keep].sum(axis=0)
        chosen = lit[~keep]
        more, more_err, spent = _refine(environment, brdf, n[p], v[p], tuple(b[chosen] for b in bounds),
                                        max(rtol * scale - float(err.max()), 0.0))  # fmt: skip
        value[p], error[p] = total + more, err + more_err
        evaluations[p] = lit.size * (_COARSE**2 + _FINE**2) + spent

    # Pixels are independent and each is costly: the shading threads share them out (NumPy's kernels release the
    # interpreter), each thread's run of them spread over the image, so that no thread gets all the costly ones.
    from ..shading.batch import each_chunk

    spread = np.argsort(np.arange(n.shape[0]) % 8, kind="stable")
    each_chunk(n.shape[0], lambda rows: [pixel(p) for p in spread[rows]], min_rows=1)
    most = int(evaluations.max(initial=0))
    return Estimate(value.reshape(shape), error.reshape(shape), most, time.perf_counter() - t0, "pixel sum")

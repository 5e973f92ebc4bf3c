"""Importance sampling of a latitude–longitude image (:class:`~lighting.lights.environment.LatLongEnvironment`).

Private helpers of the environment's ``_build_sampling``, ``_sample`` and ``_pdf``: a piecewise density over
half-pixel cells that follows the bilinear lookup exactly where it is zero and closely where it is not.
"""

from __future__ import annotations

import math

import numpy as np

from ..lights.latlong import _pixel_rows, latlong_angles, latlong_azimuth, latlong_lookup
from ..numerics import safe_div

# The image's half-pixel cells: row i and column j cut at the pixel centre into 2 x 2 cells, half row
# q = 2i (upper) or 2i + 1 (lower) between θ = q π/(2H) and (q + 1) π/(2H), half column s = 2j (left) or
# 2j + 1 (right) between a = s π/W and (s + 1) π/W (a = 2π u, latlong_angles).  On each cell the bilinear
# lookup blends the same four pixels: it is bilinear in (θ, a) between its values at the cell's corners,
# and zero on the whole cell exactly when those are.
#
# The density: a cell with probability its mass, the lookup's mean channel value integrated over the
# cell's solid angle (summed over a pixel's four cells, a pixel's own value counts 3/4 per axis and each
# neighbour's 1/8); inside it, bilinear in (cos θ, a) between the lookup's values at the four corners
# (the lookup's own shape, with cos θ for θ so that it is a density over solid angle).  So the density is
# positive exactly where the lookup returns light (no bias; under a one-pixel sun every sample lands in
# its light) and close to proportional to it (a sun's hat is followed inside its pixel, not averaged).

#: Gauss–Legendre nodes and weights on [0, 1]: exact to rounding for (linear in θ) · sin θ on a half row.
_GL_X, _GL_W = (lambda x, w: ((x + 1) / 2, w / 2))(*np.polynomial.legendre.leggauss(8))


def _half_row_weights(h: int):
    """The rows the lookup blends on each of the ``2h`` half rows, and their weights there.

    Returns ``(ra, rb, wa, wb)``, each ``(2h,)``: on half row ``q`` the lookup is ``(1 − t) L[ra] + t L[rb]``
    with ``t`` linear in ``θ``, and ``wa = ∫ (1 − t) sin θ dθ``, ``wb = ∫ t sin θ dθ`` over the half row.
    Within half a row of a pole the lookup holds the edge row (``ra = rb``, ``t = 0``).
    """
    q = np.arange(2 * h)
    half = math.pi / (2 * h)
    theta = (q * half)[:, None] + half * _GL_X
    ra = q // 2 - (q % 2 == 0)  # the row centre above the half row: its own row's for a lower half
    rb = ra + 1
    t = theta * (h / math.pi) - 0.5 - ra[:, None]  # the lookup's fy − i0
    ra, rb = np.clip(ra, 0, h - 1), np.clip(rb, 0, h - 1)
    t = np.where((ra == rb)[:, None], 0.0, t)
    weight = np.sin(theta) * (_GL_W * half)
    return ra, rb, np.sum((1 - t) * weight, axis=1), np.sum(t * weight, axis=1)


def _cell_masses(lum: np.ndarray) -> np.ndarray:
    """``∫ lookup(lum) dω`` over each half-pixel cell, ``(2H, 2W)``, in closed form (the fast path).

    The lookup is separable: linear in ``a`` between column centres (a half column of width ``π/W`` holds
    its own column's value at weight 3/8 and its outer neighbour's at 1/8, times the column width ``2π/W``,
    wrapping round the seam), linear in ``θ`` between row centres (:func:`_half_row_weights`).
    :func:`_cell_masses_reference` integrates the lookup itself.
    """
    h, w = lum.shape
    left, right = np.roll(lum, 1, axis=1), np.roll(lum, -1, axis=1)  # columns j − 1 and j + 1, wrapped
    cols = np.empty((h, 2 * w))
    cols[:, 0::2] = 0.125 * left + 0.375 * lum
    cols[:, 1::2] = 0.375 * lum + 0.125 * right
    ra, rb, wa, wb = _half_row_weights(h)
    out = cols[ra]
    out *= wa[:, None] * (2 * math.pi / w)
    below = cols[rb]
    below *= wb[:, None] * (2 * math.pi / w)
    out += below
    return out


def _cell_masses_reference(lum: np.ndarray, nodes: int = 8) -> np.ndarray:
    """:func:`_cell_masses` by its definition: Gauss–Legendre over each cell of :func:`latlong_lookup` itself.

    The readable reference of the fast path (tests hold them equal): ``nodes`` × ``nodes`` lookups per cell;
    the lookup is bilinear in ``(θ, a)`` on a cell and ``sin θ`` smooth, so 8 nodes are exact to rounding.
    """
    h, w = lum.shape
    x, wx = np.polynomial.legendre.leggauss(nodes)
    x, wx = (x + 1) / 2, wx / 2
    dt, da = math.pi / (2 * h), math.pi / w
    theta = ((np.arange(2 * h) * dt)[:, None] + dt * x).reshape(-1)  # (2H · nodes,)
    a = ((np.arange(2 * w) * da)[:, None] + da * x).reshape(-1)
    tt, aa = np.meshgrid(theta, a, indexing="ij")
    values = latlong_lookup(lum.reshape(-1, 1), h, w, None, angles=(tt, aa))[..., 0]
    weights = np.sin(tt) * np.tile(wx * dt, 2 * h)[:, None] * np.tile(wx * da, 2 * w)[None, :]
    return (values * weights).reshape(2 * h, nodes, 2 * w, nodes).sum(axis=(1, 3))


def _cell_solid_angles(h: int, w: int) -> np.ndarray:
    """Solid angle of one cell in each of the ``2h`` half rows: ``(cos θ_q − cos θ_{q+1}) π/W``, no cancellation."""
    half = math.pi / (2 * h)
    mid = (np.arange(2 * h) + 0.5) * half
    return 2 * np.sin(mid) * math.sin(half / 2) * (math.pi / w)


def _tables(mass: np.ndarray, omega: np.ndarray):
    """Marginal CDF over half rows, conditional CDFs over half columns, last drawable columns, density.

    Each CDF reaches exactly 1 at its last cell of positive mass, so a draw ``u <= 1`` never picks a cell
    of zero mass; rows of zero mass get a uniform conditional (never drawn).
    """
    rows = mass.sum(axis=1)
    total = float(rows.sum())
    rows_cdf = _cdf(rows / total)
    n = mass.shape[1]
    cond = mass / np.where(rows > 0, rows, 1.0)[:, None]
    cond[rows <= 0] = 1.0 / n
    last_col = n - 1 - np.argmax(cond[:, ::-1] > 0, axis=1)
    cols_cdf = np.cumsum(cond, axis=1, out=cond)
    cols_cdf[np.arange(n) >= last_col[:, None]] = 1.0
    density = mass / total
    density /= omega[:, None]
    return rows_cdf, cols_cdf, last_col, density.ravel()


def _cdf(p: np.ndarray) -> np.ndarray:
    """Cumulative sums of the probabilities ``p``, exactly 1 from the last positive one on."""
    c = np.cumsum(p)
    c[np.flatnonzero(p > 0)[-1] :] = 1.0
    return c


def _pick(cdf: np.ndarray, u: np.ndarray):
    """Bin ``k`` with ``cdf[k − 1] <= u < cdf[k]`` (``u = 1``: the last drawable bin) and ``u`` remapped in it."""
    last = int(np.searchsorted(cdf, 1.0))  # the first bin at 1: the last one of positive probability
    k = np.minimum(np.searchsorted(cdf, u, side="right"), last)
    lo = np.where(k > 0, cdf[np.maximum(k - 1, 0)], 0.0)
    return k, _remap(u, lo, cdf[k])


def _search_table(cdf: np.ndarray) -> np.ndarray:
    """The conditional CDFs ``(R, n)`` padded with ``+inf`` to a power-of-two width, for :func:`_pick_in_rows`."""
    rows, n = cdf.shape
    width = 1 << max(n - 1, 0).bit_length()
    if width == n:
        return cdf
    out = np.full((rows, width), np.inf)
    out[:, :n] = cdf
    return out


def _pick_in_rows(cdf: np.ndarray, last: np.ndarray, rows: np.ndarray, u: np.ndarray, search=None):
    """:func:`_pick` in row ``rows`` of the table ``cdf`` for each ``u``: a branchless bisection, O(log W).

    ``search`` is :func:`_search_table` of ``cdf`` (made here when not given): its power-of-two rows need no bound
    check at each step; the count reached is capped at ``width − 1 >= n − 1``, and the row's last drawable column
    (``<= n − 1``) caps it further either way.  The readable form is ``np.searchsorted(cdf[row], u, side="right")``
    per sample, vectorized in :func:`_pick_in_rows_reference` (tests hold them equal).
    """
    search = _search_table(cdf) if search is None else search
    n, width = cdf.shape[1], search.shape[1]
    table = search.reshape(-1)
    start = rows * width
    pos = np.array(start)  # a copy, and an array for a single draw too
    step = width >> 1
    while step:
        pos += (table.take(pos + (step - 1)) <= u) * step
        step >>= 1
    k = np.minimum(pos - start, last.take(rows))
    return k, _remap_in_row(cdf, rows * n, k, u)


def _pick_in_rows_reference(cdf: np.ndarray, last: np.ndarray, rows: np.ndarray, u: np.ndarray):
    """:func:`_pick_in_rows` as a bisection over the unpadded rows, each step bounded by the row's length."""
    n = cdf.shape[1]
    flat = cdf.reshape(-1)
    base = rows * n
    k = np.zeros(rows.shape, dtype=np.int64)  # the count of entries <= u, found bit by bit
    step = 1 << (n.bit_length() - 1)
    while step:
        reach = np.minimum(k + step, n)
        k = np.where((k + step <= n) & (flat[base + reach - 1] <= u), k + step, k)
        step >>= 1
    k = np.minimum(k, last[rows])
    return k, _remap_in_row(cdf, base, k, u)


def _remap_in_row(cdf, base, k, u):
    """:func:`_remap` of ``u`` in bin ``k`` of the rows starting at flat index ``base`` of ``cdf``."""
    flat = cdf.reshape(-1)
    lo = np.where(k > 0, flat.take(base + np.maximum(k - 1, 0)), 0.0)
    return _remap(u, lo, flat.take(base + k))


def _remap(u, lo, hi):
    """``(u − lo) / (hi − lo)`` in ``[0, 1]``: where in its bin a draw fell (a fresh uniform inside the bin)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.clip(np.where(hi > lo, (u - lo) / (hi - lo), 0.5), 0.0, 1.0)


def _cell_corners(lum: np.ndarray) -> np.ndarray:
    """The lookup of ``lum`` at the corners of the half-pixel cells, ``(2H + 1, 2W + 1)``.

    A corner is a pixel centre (its value), the middle of a pixel's edge (the mean of the two pixels
    across it) or a pixel's corner (the mean of four); the pole rows hold the edge rows (the lookup's
    clamp) and the last column repeats the first (the seam).
    """
    h, w = lum.shape
    rows = np.empty((2 * h + 1, w))
    rows[1::2] = lum
    rows[2:-1:2] = 0.5 * (lum[:-1] + lum[1:])
    rows[0], rows[-1] = lum[0], lum[-1]
    out = np.empty((2 * h + 1, 2 * w + 1))
    out[:, 1::2] = rows
    out[:, 2:-1:2] = 0.5 * (rows[:, :-1] + rows[:, 1:])
    out[:, 0] = out[:, -1] = 0.5 * (rows[:, -1] + rows[:, 0])
    return out


def _corner_values(corners: np.ndarray, q, s):
    """``(v00, v10, v01, v11)`` of cells ``(q, s)``: the first index down (``θ``), the second across (``a``)."""
    n = corners.shape[1]
    flat = corners.reshape(-1)
    k = q * n + s
    below = k + n
    return flat.take(k), flat.take(below), flat.take(k + 1), flat.take(below + 1)


def _bilinear_shape(values, fz, fa):
    """The bilinear function of corner ``values`` at fractions ``(fz, fa)`` over its mean on the cell (0 if 0)."""
    v00, v10, v01, v11 = values
    b = (v00 * (1 - fa) + v01 * fa) * (1 - fz) + (v10 * (1 - fa) + v11 * fa) * fz
    return safe_div(b, 0.25 * (v00 + v10 + v01 + v11))


def _sample_linear(u, a, b):
    """``x ∈ [0, 1]`` with density ``∝ (1 − x) a + x b`` (``a, b >= 0``) for uniform ``u``: the inverse CDF,
    written without cancellation (pbrt-v4's ``SampleLinear``); uniform where ``a = b = 0``."""
    root = np.sqrt(np.maximum((1 - u) * a * a + u * b * b, 0.0))
    x = safe_div(u * (a + b), a + root)
    return np.clip(np.where(a + b > 0, x, u), 0.0, 1.0)


def _cell_direction(q, s, fz, fa, h: int, w: int) -> np.ndarray:
    """The direction at fractions ``fz`` (in ``cos θ``) and ``fa`` (in ``a``) across cell ``(q, s)`` (uniform
    fractions: uniform in solid angle inside the cell)."""
    c = _pixel_rows(2 * h)
    top, bottom = c.take(q), c.take(q + 1)
    z = np.clip(top + (bottom - top) * fz, bottom, top)
    r = np.sqrt(np.clip((1 - z) * (1 + z), 0.0, None))
    phi = latlong_azimuth((s + fa) * (math.pi / w))
    out = np.empty(z.shape + (3,))
    np.multiply(r, np.cos(phi), out=out[..., 0])
    np.multiply(r, np.sin(phi), out=out[..., 1])
    out[..., 2] = z
    return out


def _half_row_scales(h: int) -> np.ndarray:
    """``sin(θ_q + half/2) sin(half/2)`` of each of the ``2h`` half rows: :func:`_cell_of`'s denominators."""
    half = math.pi / (2 * h)
    tq = np.arange(2 * h, dtype=np.int64) * half
    return np.sin(tq + 0.5 * half) * math.sin(0.5 * half)


def _cell_of(d, h: int, w: int, angles=None, scales=None):
    """The half-pixel cell ``(q, s)`` of directions ``d`` ``(..., 3)`` and the fractions ``(fz, fa)`` across it
    (the inverse of :func:`_cell_direction`); ``angles``: :func:`latlong_angles` of ``d``, when the caller has them;
    ``scales``: :func:`_half_row_scales` of ``h`` (made here when not given)."""
    theta, a = latlong_angles(d) if angles is None else angles
    scales = _half_row_scales(h) if scales is None else scales
    half = math.pi / (2 * h)
    q = np.clip(np.floor(theta * (2 * h / math.pi)).astype(np.int64), 0, 2 * h - 1)
    xa = a * (w / math.pi)
    s = np.clip(np.floor(xa).astype(np.int64), 0, 2 * w - 1)
    # cos θ_q − cos θ over cos θ_q − cos θ_{q+1}, as products of sines (no cancellation near the poles).
    tq = q * half
    fz = np.sin(0.5 * (theta + tq)) * np.sin(0.5 * (theta - tq)) / scales.take(q)
    return q, s, np.clip(fz, 0.0, 1.0), np.clip(xa - s, 0.0, 1.0)

r"""A glossy lobe's smooth terms shaded once per normal of a grid, when every pixel sees the object from one direction.

Under a distant environment and one view direction ``v`` (an orthographic camera: the explorer's spheres, the
accuracy study, the bench), what a pixel reflects depends on its normal alone.  The terms of the dominant-light
method that a lobe of width ``σ`` blurs — the areas of light cell by cell and the filtered samples of the residual
(:mod:`lighting.integrate.dominant`) — vary over the normals no faster than the lobe's width, so they are computed
at the points of a grid over the normals facing ``v`` and read bilinearly at each pixel: a 512² sphere's 176,000
normals need a few thousand points for a wide lobe.  The dominant lights (sharp where the lobe is narrow) and the
lobe's albedo (steep at grazing views) stay per pixel.

The grid is polar about ``v``: rings at ``θ_i = i Δθ`` from ``v`` (ring 0 is ``v`` itself, one point; the last
ring the silhouette, ``θ = π/2``), ``Δθ`` = ``σ`` / :data:`GRID_DENSITY` and at most :data:`MAX_SPACING`, each ring
``c_i`` points evenly in the azimuth ``ψ`` about ``v`` (wrapping), ``Δψ_i = 2π / c_i``.  A pixel between rings
``i`` and ``i + 1`` is read linearly in ``ψ`` on each ring and linearly in ``θ`` between them (four taps).

How many points a ring needs follows from the interpolation's error.  Reading ``f`` linearly in ``θ`` errs by at
most ``Δθ² max|f_θθ| / 8``, and in ``ψ`` on ring ``i`` by ``Δψ_i² max|f_ψψ| / 8``.  Along a ring the normal moves
as ``sin θ`` (``|∂n/∂ψ| = |∂²n/∂ψ²| = sin θ``), so for a function smooth on the sphere ``|f_ψψ|`` is of the order
of ``sin θ`` times its derivatives, and the ``ψ`` error is within the ``θ`` one when ``Δψ_i² sin θ_i <= Δθ²``:
``c_i = ⌈2π √(sin θ_i) / Δθ⌉`` (at least 8).  Columns evenly spaced as at the silhouette on every ring would take
``π/2 ÷ ∫ √(sin θ) dθ`` ≈ 1.31 times as many points for the same bound.

Bilinear interpolation of a function that varies on the scale ``σ`` errs by about ``(Δθ/σ)² / 8`` of its
curvature there: a fraction of a percent at 6 points per ``σ``.  How far the grid moves the method's values from
those shaded pixel by pixel is measured by ``lighting-explorer report accuracy --only ibl`` (the ``normal grid``
rows).
"""

from __future__ import annotations

import math

import numpy as np

from ..shading.batch import in_blocks

#: Grid rows per lobe width ``σ``.
GRID_DENSITY = 6
#: The coarsest grid spacing (radians), whatever the lobe's width: the cells' horizon and grazing views.
MAX_SPACING = math.radians(2.5)
#: The grid is used by default when it has at most this fraction of the pixels' count of points.
GRID_SHARE = 0.25


def grid_spacing(sigma: float, density: float = GRID_DENSITY) -> float:
    """``Δθ`` (radians) of the grid of a lobe ``σ`` wide at ``density`` rows per ``σ`` (before rounding to a whole
    number of rows to π/2)."""
    return min(sigma / density, MAX_SPACING)


#: Values (pixels times channels) read per block by :meth:`NormalGrid.interpolate`: a block of 65,536 pixels of six
#: channels, the dominant method's finish block read at once (shading threads making many short NumPy passes wait on
#: each other for the interpreter between them); fewer pixels of more channels, so that a tap's values and their sum
#: (float64: 16 bytes a value) stay within 6 MiB.
READ_VALUES = 6 << 16
#: The fewest points of a ring other than the view's own.
MIN_COLUMNS = 8


def _shape(spacing: float) -> tuple[int, np.ndarray]:
    """``(rows, columns)`` of the grid of spacing at most ``spacing``: ``rows + 1`` rings from the view to π/2, ring
    ``i`` of ``columns[i]`` points (module notes: ``Δψ_i² sin θ_i <= Δθ²``)."""
    rows = max(2, math.ceil((math.pi / 2) / spacing))
    d_theta = (math.pi / 2) / rows
    reach = np.sqrt(np.sin(np.arange(rows + 1) * d_theta))
    columns = np.maximum(np.ceil(2 * math.pi * reach / d_theta), MIN_COLUMNS).astype(np.int64)
    columns[0] = 1  # the view itself
    return rows, columns


def grid_points(spacing: float) -> int:
    """The number of points of :class:`NormalGrid` ``(view, spacing)`` (without making it)."""
    return int(_shape(spacing)[1].sum())


class NormalGrid:
    """The normals facing one view direction on a polar grid about it, and bilinear reads of values at them.

    Parameters
    ----------
    view : array_like, (3,)
        The unit direction toward the viewer that every pixel shares.
    spacing : float
        Largest ``Δθ`` (radians); the rows divide ``π/2`` evenly.

    Attributes
    ----------
    rows : int
        Rings after the view's own: ring ``i`` at ``θ = i Δθ``, ``i = 0 … rows``.
    columns : ndarray of int64, (rows + 1,)
        The points of each ring (1 for ring 0), evenly in ``ψ`` from ``ψ = 0``.
    starts : ndarray of int64, (rows + 1,)
        Each ring's first point in :attr:`normals`.
    normals : ndarray, (size, 3) float64
        The unit normals, ring after ring.
    """

    def __init__(self, view, spacing: float):
        from ..vec import orthonormal_basis

        self.view = np.asarray(view, dtype=np.float64)
        self.view = self.view / np.linalg.norm(self.view)
        #: The spacing asked for (the rows' ``Δθ`` is at most this).
        self.spacing = float(spacing)
        self.rows, self.columns = _shape(spacing)
        self.starts = np.concatenate([[0], np.cumsum(self.columns)[:-1]])
        self.d_theta = (math.pi / 2) / self.rows
        e1, e2 = (np.asarray(a, dtype=np.float64) for a in orthonormal_basis(self.view))
        self.e1, self.e2 = e1, e2
        ring = np.repeat(np.arange(self.rows + 1), self.columns)
        theta = (ring * self.d_theta)[:, None]
        psi = ((np.arange(ring.size) - self.starts[ring]) * (2 * math.pi / self.columns[ring]))[:, None]
        n = np.sin(theta) * (np.cos(psi) * e1 + np.sin(psi) * e2) + np.cos(theta) * self.view
        self.normals = n / np.linalg.norm(n, axis=-1, keepdims=True)
        self.normals.setflags(write=False)  # a grid is kept and shared by the re-shades of its view

    @property
    def size(self) -> int:
        """The number of grid points."""
        return int(self.columns.sum())

    def interpolate(self, values: np.ndarray, normals: np.ndarray) -> np.ndarray:
        """``values`` at the grid points ``(size, K)`` read at unit ``normals`` (P, 3): (P, K).

        Linear in ``ψ`` on the two rings around each normal, linear in ``θ`` between them.  The normals face the
        view (``n·v >= 0``); the coordinates in float32, the weighted sum in float64, the result in float32.  The
        values are read in float64, the dtype of the weights (whose fractions an integer part promotes), so that each
        product reads them as they are: a caller that reads one grid in several calls converts it once (C-contiguous
        float64 values are used as they are).
        """
        k = values.shape[-1]
        # Each grid point's K values as one item, so that a tap is one gather.
        values = np.ascontiguousarray(values, dtype=np.float64).reshape(-1, k)
        texels = values.view(np.dtype((np.void, 8 * k)))[:, 0]
        n = normals.astype(np.float32, copy=False)
        view, e1, e2 = (a.astype(np.float32) for a in (self.view, self.e1, self.e2))
        columns, starts = self.columns.astype(np.int32), self.starts.astype(np.int32)
        out = np.empty((n.shape[0], k), dtype=np.float32)
        one = np.float32(1)

        def ring(i, turn):
            """The two taps of ring ``i`` at the fraction ``turn`` of a whole turn: ``(index, index, fraction)``."""
            c = np.take(columns, i)
            fj = turn * c
            j = np.minimum(fj.astype(np.int32), c - 1)  # turn < 1, but float32 may round fj up to c
            start = np.take(starts, i)
            return start + j, start + np.where(j == c - 1, 0, j + 1), fj - j

        def tap(index, weight):
            value = np.take(texels, index).view(np.float64).reshape(-1, k)
            value *= weight[:, None]
            return value

        def block(s):
            nn = n[s]
            fi = np.arccos(np.clip(nn @ view, 0, 1)) * np.float32(1 / self.d_theta)
            i = np.minimum(fi.astype(np.int32), self.rows - 1)
            ti = fi - i
            turn = np.arctan2(nn @ e2, nn @ e1) * np.float32(1 / (2 * math.pi))
            turn = np.where(turn < 0, turn + one, turn)
            a0, a1, ta = ring(i, turn)
            b0, b1, tb = ring(i + 1, turn)
            total = tap(a0, (one - ti) * (one - ta))
            total += tap(a1, (one - ti) * ta)
            total += tap(b0, ti * (one - tb))
            total += tap(b1, ti * tb)
            out[s] = total

        # A multiple of 64 rows per block: each pixel gets the bits of one pass over all of them (in_blocks).
        in_blocks(n.shape[0], max(64, READ_VALUES // k // 64 * 64), block)
        return out

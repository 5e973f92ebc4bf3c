r"""A glossy lobe's smooth terms shaded once per normal of a grid, when every pixel sees the object from one direction.

Under a distant environment and one view direction ``v`` (an orthographic camera: the explorer's spheres, the
accuracy study, the bench), what a pixel reflects depends on its normal alone.  The terms of the dominant-light
method that a lobe of width ``σ`` blurs — the areas of light cell by cell and the filtered samples of the residual
(:mod:`lighting.integrate.dominant`) — vary over the normals no faster than the lobe's width, so they are computed
at the points of a grid over the normals facing ``v`` and read bilinearly at each pixel: a 512² sphere's 176,000
normals need a few thousand points for a wide lobe.  The dominant lights (sharp where the lobe is narrow) and the
lobe's albedo (steep at grazing views) stay per pixel.

The grid is polar about ``v``: rows at ``θ_i = i Δθ`` from ``v`` (row 0 is ``v`` itself, the last row the
silhouette, ``θ = π/2``), columns evenly in the azimuth ``ψ`` about ``v`` (wrapping), ``Δθ`` = ``σ`` /
:data:`GRID_DENSITY` and at most :data:`MAX_SPACING`.  Bilinear interpolation of a function that varies on the
scale ``σ`` errs by about ``(Δθ/σ)² / 8`` of its curvature there: a fraction of a percent at 6 points per
``σ``.  How far the grid moves the method's values from those shaded pixel by pixel is measured by
``lighting-explorer report accuracy --only ibl`` (the ``normal grid`` rows).
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


def _shape(spacing: float) -> tuple[int, int]:
    """``(rows, cols)`` of the grid of spacing at most ``spacing``: ``rows + 1`` rows from the view to π/2."""
    rows = max(2, math.ceil((math.pi / 2) / spacing))
    return rows, max(8, math.ceil(2 * math.pi / ((math.pi / 2) / rows)))


def grid_points(spacing: float) -> int:
    """The number of points of :class:`NormalGrid` ``(view, spacing)`` (without making it)."""
    rows, cols = _shape(spacing)
    return (rows + 1) * cols


class NormalGrid:
    """The normals facing one view direction on a polar grid about it, and bilinear reads of values at them.

    Parameters
    ----------
    view : array_like, (3,)
        The unit direction toward the viewer that every pixel shares.
    spacing : float
        Largest ``Δθ`` (radians); the rows divide ``π/2`` evenly.
    """

    def __init__(self, view, spacing: float):
        from ..vec import orthonormal_basis

        self.view = np.asarray(view, dtype=np.float64)
        self.view = self.view / np.linalg.norm(self.view)
        #: The spacing asked for (the rows' ``Δθ`` is at most this).
        self.spacing = float(spacing)
        self.rows, self.cols = _shape(spacing)
        self.d_theta = (math.pi / 2) / self.rows
        self.d_psi = 2 * math.pi / self.cols
        e1, e2 = (np.asarray(a, dtype=np.float64) for a in orthonormal_basis(self.view))
        self.e1, self.e2 = e1, e2
        theta = (np.arange(self.rows + 1) * self.d_theta)[:, None, None]
        psi = (np.arange(self.cols) * self.d_psi)[None, :, None]
        n = np.sin(theta) * (np.cos(psi) * e1 + np.sin(psi) * e2) + np.cos(theta) * self.view
        #: (rows + 1, cols, 3) unit normals; row 0 is the view direction, the last row is perpendicular to it.
        self.normals = n / np.linalg.norm(n, axis=-1, keepdims=True)

    @property
    def size(self) -> int:
        """The number of grid points."""
        return (self.rows + 1) * self.cols

    def interpolate(self, values: np.ndarray, normals: np.ndarray) -> np.ndarray:
        """``values`` at the grid points ``(rows + 1, cols, K)`` read bilinearly at unit ``normals`` (P, 3): (P, K).

        The normals face the view (``n·v >= 0``); the coordinates in float32, the weighted sum in float64, the
        result in float32.  The values are read in float64, the dtype of the bilinear weights (whose fractions an
        integer part promotes), so that each product reads them as they are: a caller that reads one grid in
        several calls converts it once (C-contiguous float64 values are used as they are).
        """
        k = values.shape[-1]
        # Each grid point's K values as one item, so that a tap is one gather.
        values = np.ascontiguousarray(values, dtype=np.float64).reshape(-1, k)
        texels = values.view(np.dtype((np.void, 8 * k)))[:, 0]
        n = normals.astype(np.float32, copy=False)
        view, e1, e2 = (a.astype(np.float32) for a in (self.view, self.e1, self.e2))
        out = np.empty((n.shape[0], k), dtype=np.float32)
        one = np.float32(1)

        def block(s):
            nn = n[s]
            fi = np.arccos(np.clip(nn @ view, 0, 1)) * np.float32(1 / self.d_theta)
            i = np.minimum(fi.astype(np.int32), self.rows - 1)
            ti = fi - i
            fj = np.mod(np.arctan2(nn @ e2, nn @ e1) * np.float32(1 / self.d_psi), np.float32(self.cols))
            j = np.minimum(fj.astype(np.int32), self.cols - 1)  # fj < cols, but float32 may round up to it
            tj = fj - j
            j1 = np.where(j == self.cols - 1, 0, j + 1)
            a = i * self.cols
            b = a + self.cols

            def tap(index, weight):
                value = np.take(texels, index).view(np.float64).reshape(-1, k)
                value *= weight[:, None]
                return value

            total = tap(a + j, (one - ti) * (one - tj))
            total += tap(a + j1, (one - ti) * tj)
            total += tap(b + j, ti * (one - tj))
            total += tap(b + j1, ti * tj)
            out[s] = total

        in_blocks(n.shape[0], 1 << 14, block)
        return out

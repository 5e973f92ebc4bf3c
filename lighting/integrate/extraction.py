"""The dominant lights and the areas of light of a lat-long map: what the dominant-light method takes out of it.

:func:`find_dominant_lights` finds the small, very bright regions (a sun) and replaces each by a disk light of the
same power, direction and solid angle; :func:`find_area_cells` cuts what is still bright (a studio's soft boxes, a
sky's glow) into the cells of a coarse lat-long grid.  Each region is filled with its surroundings' level, so that
what is left (the residual) is smooth enough to prefilter.  :mod:`lighting.integrate.dominant` shades the lights
and cells with the BRDF and reads the residual through its prefiltered levels.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = [
    "DOMINANT_THRESHOLD",
    "DOMINANT_MAX_LIGHTS",
    "DOMINANT_MAX_SOLID_ANGLE",
    "AREA_THRESHOLD",
    "AREA_CELL_ROWS",
    "DiskLights",
    "find_dominant_lights",
    "find_area_cells",
]

#: A pixel belongs to a dominant light when its luminance is above this many times the map's mean radiance.
DOMINANT_THRESHOLD = 16.0
#: At most this many dominant lights (the most powerful).
DOMINANT_MAX_LIGHTS = 4
#: A bright region larger than this (steradians; a cap of about 7°) stays in the residual: it is no small source.
DOMINANT_MAX_SOLID_ANGLE = 0.05
#: A pixel of the map without its dominant lights belongs to an area of light (shaded cell by cell for wide lobes)
#: when its luminance is above this many times that map's mean.
AREA_THRESHOLD = 4.0
#: The cells of the areas of light: the pixels of a lat-long grid of this many rows.
AREA_CELL_ROWS = 16


@dataclass(frozen=True)
class DiskLights:
    """Disk lights at infinity: what :func:`find_dominant_lights` takes out of a map.

    Attributes
    ----------
    directions : ndarray, (K, 3)
        Unit directions toward each disk's centre (the map's frame).
    solid_angles : ndarray, (K,)
        ``Ω`` of each disk, steradians.
    radiance : ndarray, (K, 3)
        Radiance inside each disk (RGB): its power over its solid angle.
    """

    directions: np.ndarray
    solid_angles: np.ndarray
    radiance: np.ndarray

    @property
    def power(self) -> np.ndarray:
        """``L Ω`` of each disk, ``(K, 3)``: its irradiance on a surface facing it, in the small-disk limit."""
        return self.radiance * self.solid_angles[:, None]

    @property
    def half_angles(self) -> np.ndarray:
        """Angular radius ``γ`` of each disk, ``Ω = 2π (1 − cos γ)``, radians."""
        return 2.0 * np.arcsin(np.sqrt(np.clip(self.solid_angles / (4 * math.pi), 0.0, 1.0)))

    def __len__(self):
        return int(self.solid_angles.shape[0])


def _pixel_geometry(h: int, w: int):
    """Pixel-centre unit directions ``(h, w, 3)`` and solid angles ``(h, w)`` of an ``h × w`` lat-long map."""
    from ..lights.environment import _pixel_directions

    d = _pixel_directions(h, w)  # the size of a map that exists: nothing to check or budget
    c = np.cos(np.arange(h + 1) * (math.pi / h))
    omega = np.broadcast_to(((c[:-1] - c[1:]) * (2 * math.pi / w))[:, None], (h, w))
    return d, omega


def _label_wrapped(mask: np.ndarray):
    """Connected regions of ``mask`` (8-neighbours), joined across the azimuth seam: ``(labels, count)``."""
    from scipy import ndimage

    labels, count = ndimage.label(mask, structure=np.ones((3, 3), dtype=bool))
    if count == 0:
        return labels, 0
    parent = np.arange(count + 1)

    def root(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    h = mask.shape[0]
    for i in range(h):  # the first and last columns touch (the map wraps in azimuth)
        a = labels[i, -1]
        if not a:
            continue
        for di in (-1, 0, 1):
            if 0 <= i + di < h and labels[i + di, 0]:
                ra, rb = root(a), root(labels[i + di, 0])
                if ra != rb:
                    parent[max(ra, rb)] = min(ra, rb)
    roots = np.array([root(a) for a in range(count + 1)])
    _, compact = np.unique(roots, return_inverse=True)
    return compact[labels], int(compact.max())


def find_dominant_lights(image, *, threshold=DOMINANT_THRESHOLD, max_lights=DOMINANT_MAX_LIGHTS,
                         max_solid_angle=DOMINANT_MAX_SOLID_ANGLE):  # fmt: skip
    """The small, very bright regions of a lat-long map as disk lights, and the map without them.

    Parameters
    ----------
    image : array_like, (H, W, 3)
        Linear RGB radiance, rows and columns as :class:`~lighting.lights.environment.LatLongEnvironment`.
    threshold : float > 0
        A pixel is bright when its luminance (the mean of the channels) is above ``threshold`` times the
        map's mean luminance (over solid angle).
    max_lights : int >= 0
        The most powerful regions kept.
    max_solid_angle : float > 0
        Regions larger than this (steradians) stay in the map.

    Returns
    -------
    lights : DiskLights
        One disk per region taken out: its power the region's radiance above the fill level times solid
        angle, its direction the power-weighted mean of its pixels', its solid angle the power over the
        brightest pixel's excess radiance (the disk's own for a uniform disk, not counting the partly
        covered pixels of its rim twice).
    residual : ndarray, (H, W, 3)
        Float64: the map with each region's pixels set to the fill level, the mean radiance of the pixels
        within two pixels around the region (its surroundings).

    Examples
    --------
    >>> img = np.ones((32, 64, 3)); img[10, 20] = 1000.0  # one pixel of 1000 on a uniform sky of 1
    >>> lights, rest = find_dominant_lights(img)
    >>> pixel = (math.cos(10 * math.pi / 32) - math.cos(11 * math.pi / 32)) * 2 * math.pi / 64  # its solid angle
    >>> len(lights), float(rest.max()), round(float(lights.power[0, 0] / (999 * pixel)), 12)
    (1, 1.0, 1.0)
    """
    from scipy import ndimage

    img = np.asarray(image, dtype=np.float64)
    h, w = img.shape[:2]
    d, omega = _pixel_geometry(h, w)
    lum = img.mean(axis=-1)
    mean = float(np.sum(lum * omega) / (4 * math.pi))
    empty = DiskLights(np.zeros((0, 3)), np.zeros(0), np.zeros((0, 3)))
    if not mean > 0 or max_lights == 0:
        return empty, img.copy()
    labels, count = _label_wrapped(lum > threshold * mean)
    if count == 0:
        return empty, img.copy()
    index = np.arange(1, count + 1)
    area = ndimage.sum_labels(omega, labels, index)
    found = []
    residual = img.copy()
    for k in index[area <= max_solid_angle]:
        region = labels == k
        fill = _fill_level(img, region, labels, omega)  # its surroundings' level
        excess = np.maximum(img[region] - fill, 0.0)
        om = omega[region]
        power = (excess * om[:, None]).sum(axis=0)
        weight = excess.mean(axis=-1) * om
        centre = (d[region] * weight[:, None]).sum(axis=0)
        norm = float(np.linalg.norm(centre))
        if not norm > 0 or not power.max() > 0:
            continue
        # The disk's solid angle: its power over its brightest pixel's excess — exact for a uniform disk with one
        # whole pixel inside, where the region itself also counts the partly covered pixels of its rim.
        size = min(float(weight.sum() / excess.mean(axis=-1).max()), float(om.sum()))
        found.append((float(power.mean()), centre / norm, size, power, region))
        residual[region] = np.minimum(img[region], fill)
    found.sort(key=lambda f: -f[0])
    kept = found[:max_lights]
    for f in found[max_lights:]:  # the regions not kept go back into the map as they were
        residual[f[4]] = img[f[4]]
    if not kept:
        return empty, residual
    dirs = np.array([f[1] for f in kept])
    om = np.array([f[2] for f in kept])
    rad = np.array([f[3] for f in kept]) / om[:, None]
    return DiskLights(dirs, om, rad), residual


def find_area_cells(image, *, threshold=AREA_THRESHOLD, cell_rows=AREA_CELL_ROWS):
    """The bright regions of a lat-long map as small cells of light, and the map without them.

    Parameters
    ----------
    image : array_like, (H, W, 3)
        Linear RGB radiance (the map without its dominant lights).
    threshold : float > 0
        A pixel is bright when its luminance is above ``threshold`` times the map's mean luminance.
    cell_rows : int
        The cells are the pixels of a ``cell_rows × 2 cell_rows`` lat-long grid (at most ``H`` rows).

    Returns
    -------
    directions : ndarray, (C, 3)
        The power-weighted mean direction of each cell's bright pixels.
    power : ndarray, (C, 3)
        Their radiance above the fill level times solid angle (RGB).
    residual : ndarray, (H, W, 3)
        The map with every bright region's pixels set to its fill level (as :func:`find_dominant_lights`).
    """
    img = np.asarray(image, dtype=np.float64)
    h, w = img.shape[:2]
    d, omega = _pixel_geometry(h, w)
    lum = img.mean(axis=-1)
    mean = float(np.sum(lum * omega) / (4 * math.pi))
    none = np.zeros((0, 3))
    if not mean > 0:
        return none, none, img.copy()
    labels, count = _label_wrapped(lum > threshold * mean)
    if count == 0:
        return none, none, img.copy()
    residual = img.copy()
    excess = np.zeros_like(img)
    for k in range(1, count + 1):
        region = labels == k
        fill = _fill_level(img, region, labels, omega)
        excess[region] = np.maximum(img[region] - fill, 0.0)
        residual[region] = np.minimum(img[region], fill)
    rows = max(1, min(int(cell_rows), h))
    cell = (np.arange(h) * rows // h)[:, None] * (2 * rows) + (np.arange(w) * (2 * rows) // w)[None, :]
    lit = labels > 0
    ids = cell[lit]
    pw = excess[lit] * omega[lit][:, None]
    wt = pw.mean(axis=-1)
    n_cells = 2 * rows * rows
    power = np.stack([np.bincount(ids, pw[:, c], n_cells) for c in range(3)], axis=-1)
    centre = np.stack([np.bincount(ids, wt * d[lit][:, c], n_cells) for c in range(3)], axis=-1)
    norm = np.linalg.norm(centre, axis=-1)
    keep = (norm > 0) & (power.max(axis=-1) > 0)
    return centre[keep] / norm[keep, None], power[keep], residual


def _fill_level(img, region, labels, omega):
    """The mean radiance (over solid angle) of the pixels within two pixels of ``region`` and in no region."""
    from scipy import ndimage

    grown = ndimage.binary_dilation(np.pad(region, ((0, 0), (2, 2)), mode="wrap"), iterations=2)[:, 2:-2]
    ring = grown & (labels == 0)
    return (img[ring] * omega[ring, None]).sum(axis=0) / omega[ring].sum() if ring.any() else np.zeros(3)

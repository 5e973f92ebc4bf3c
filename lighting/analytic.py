"""Ray-cast analytic sphere: exact per-pixel positions and normals.

The ground truth that tessellated renderings are measured against.  This first
version looks down ``-z`` with an orthographic camera; the viewer is at
``+z`` infinity (``v = (0, 0, 1)``).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .illumination import Material, shade

__all__ = ["SphereBuffer", "sphere_buffer", "render_sphere"]


class SphereBuffer(NamedTuple):
    """Per-pixel geometry of a unit sphere seen from +z: positions, normals, coverage."""

    points: np.ndarray  # (H, W, 3), zero outside the sphere
    normals: np.ndarray  # (H, W, 3), zero outside the sphere
    mask: np.ndarray  # (H, W) bool


def sphere_buffer(size: int = 256, *, margin: float = 1.08, dtype=np.float64) -> SphereBuffer:
    """Ray-cast a unit sphere centred at the origin into a ``size × size`` image.

    Pixel ``(i, j)`` (row ``i`` from the top) looks at ``x = (j + ½)·s − m``,
    ``y = m − (i + ½)·s`` with ``s = 2m/size``: image right is +x, image up is +y.
    """
    if isinstance(size, bool) or not isinstance(size, (int, np.integer)) or size < 1:
        raise ValueError(f"size must be an integer >= 1; got {size!r}")
    s = 2 * margin / size
    c = (np.arange(size) + 0.5) * s - margin
    x, y = np.meshgrid(c, -c)
    r2 = x * x + y * y
    mask = r2 < 1
    z = np.sqrt(np.where(mask, 1 - r2, 0))
    pts = np.stack([x, y, z], -1) * mask[..., None]
    return SphereBuffer(pts.astype(dtype), pts.astype(dtype), mask)


def render_sphere(material: Material, lights, *, size: int = 256, form: str = "classic", background=0.0):
    """Linear RGB image ``(size, size, 3)`` of the lit unit sphere (viewer at +z infinity)."""
    buf = sphere_buffer(size)
    img = np.empty((size, size, 3))
    img[...] = background
    col = shade(buf.points[buf.mask], buf.normals[buf.mask], material, lights, view_dir=(0, 0, 1.0), form=form)
    img[buf.mask] = col
    return img

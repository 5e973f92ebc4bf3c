"""The rasterizer's tight column spans against whole bounding-box rows, on a sphere and a soup of slivers (slow set;
fast: test_render.py)."""

import numpy as np
import pytest

from lighting.render.camera import Camera
from lighting.render.mesh import TriangleMesh, icosphere

pytestmark = pytest.mark.slow  # two meshes rasterized at 300 × 260 four times each, one a soup of 300 random triangles


def test_tight_span_columns_change_nothing_but_the_work(monkeypatch):
    """The per-row column bounds only spare candidates: whole bounding-box rows give the same buffer."""
    import lighting.render.raster as raster

    rng = np.random.default_rng(7)
    # A sphere, and a soup of random triangles including slivers and nearly horizontal edges.
    soup = rng.normal(size=(300, 3, 3)) * [1.5, 1.5, 0.3]
    soup[:100, 1, 1] = soup[:100, 0, 1] + rng.normal(size=100) * 1e-7  # nearly horizontal edges
    soup[100:150, 2] = soup[100:150, 0] + (soup[100:150, 1] - soup[100:150, 0]) * 0.5 + 1e-6  # slivers
    meshes = [icosphere(4), TriangleMesh(soup.reshape(-1, 3), np.arange(900).reshape(-1, 3))]
    cam = Camera((0.2, 0.1, 5.0), (0, 0, 0), fov_y_deg=40, width=300, height=260)
    for mesh in meshes:
        for cull in (True, False):
            tight = raster.rasterize(mesh, cam, cull_backfaces=cull)
            with monkeypatch.context() as mp:
                mp.setattr(raster, "_span_columns", lambda j0, j1, *args: (j0, j1))
                whole = raster.rasterize(mesh, cam, cull_backfaces=cull)
            assert tight.coverage.sum() > 1000
            for name in ("triangle_id", "barycentric", "depth", "overdraw", "coverage", "front_facing"):
                np.testing.assert_array_equal(getattr(tight, name), getattr(whole, name), err_msg=name)

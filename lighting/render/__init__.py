"""Images: meshes, cameras, the rasterizer, flat / Gouraud / Phong-interpolated rendering, plans, image files."""

from __future__ import annotations

from . import camera, image, mesh, plan, raster, renderer, sphere
from .camera import *  # noqa: F403
from .image import *  # noqa: F403
from .mesh import *  # noqa: F403
from .plan import *  # noqa: F403
from .raster import *  # noqa: F403
from .renderer import *  # noqa: F403
from .sphere import *  # noqa: F403

__all__ = [
    "image",
    "mesh",
    "camera",
    "raster",
    "renderer",
    "sphere",
    "plan",
    *image.__all__,
    *mesh.__all__,
    *camera.__all__,
    *raster.__all__,
    *renderer.__all__,
    *sphere.__all__,
    *plan.__all__,
]

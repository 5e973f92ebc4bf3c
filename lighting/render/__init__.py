"""Images: meshes, cameras, the geometry buffer, the rasterizer, the ray-cast sphere, flat / Gouraud /
Phong-interpolated rendering, plans, image files."""

from __future__ import annotations

from . import camera, gbuffer, image, linear_image, mesh, plan, raster, raycast, renderer, sphere
from .camera import *  # noqa: F403
from .gbuffer import *  # noqa: F403
from .image import *  # noqa: F403
from .linear_image import *  # noqa: F403
from .mesh import *  # noqa: F403
from .plan import *  # noqa: F403
from .raster import *  # noqa: F403
from .raycast import *  # noqa: F403
from .renderer import *  # noqa: F403
from .sphere import *  # noqa: F403

__all__ = list(
    dict.fromkeys(
        [
            "image",
            "linear_image",
            "mesh",
            "camera",
            "gbuffer",
            "raster",
            "raycast",
            "renderer",
            "sphere",
            "plan",
            *image.__all__,
            *linear_image.__all__,
            *mesh.__all__,
            *camera.__all__,
            *gbuffer.__all__,
            *raster.__all__,
            *raycast.__all__,
            *renderer.__all__,
            *sphere.__all__,
            *plan.__all__,
        ]
    )
)

"""Images: meshes, cameras, the rasterizer, flat / Gouraud / Phong-interpolated rendering, plans, image files."""

from __future__ import annotations

from . import camera, image, mesh, plan, raster, renderer, sphere
from .camera import (  # noqa: F401
    MAX_IMAGE_SIDE,
    Camera,
)
from .image import (  # noqa: F401
    EncodeReport,
    encode_srgb8,
    file_mode,
    linear_to_srgb,
    read_png,
    srgb_to_linear,
    write_png,
)
from .mesh import (  # noqa: F401
    TriangleMesh,
    icosphere,
    load_mesh,
    sphere_for_triangles,
    uv_sphere,
)
from .plan import (  # noqa: F401
    Plan,
    Skip,
    bounding_sphere,
    compile_plan,
    evaluate_full,
)
from .raster import (  # noqa: F401
    GBuffer,
    rasterize,
    raycast_sphere,
)
from .renderer import (  # noqa: F401
    SHADING_MODES,
    AnalyticSphere,
    Renderer,
    render,
)
from .sphere import (  # noqa: F401
    render_sphere,
    sphere_camera,
)

__all__ = [
    "image",
    "mesh",
    "camera",
    "raster",
    "renderer",
    "sphere",
    "plan",
    "EncodeReport",
    "linear_to_srgb",
    "srgb_to_linear",
    "encode_srgb8",
    "write_png",
    "read_png",
    "file_mode",
    "TriangleMesh",
    "uv_sphere",
    "icosphere",
    "sphere_for_triangles",
    "load_mesh",
    "Camera",
    "MAX_IMAGE_SIDE",
    "GBuffer",
    "rasterize",
    "raycast_sphere",
    "SHADING_MODES",
    "AnalyticSphere",
    "Renderer",
    "render",
    "sphere_camera",
    "render_sphere",
    "Plan",
    "Skip",
    "compile_plan",
    "evaluate_full",
    "bounding_sphere",
]

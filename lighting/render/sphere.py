"""The analytic sphere of the lecture slides, ready to render.

:func:`sphere_camera` frames a sphere of radius 1 at the origin for an
orthographic view from +z (image right is +x, image up is +y, the viewer at +z
infinity, so ``v = (0, 0, 1)`` everywhere), and :func:`render_sphere` lights it per
pixel with exact normals (ray casting, :func:`lighting.render.raster.raycast_sphere`).
"""

from __future__ import annotations

from .._budget import check_budget
from .._validate import check_count, check_positive
from ..shading.equation import Material
from .camera import MAX_IMAGE_SIDE, Camera
from .renderer import RENDER_BYTES_PER_PIXEL, AnalyticSphere, Renderer

__all__ = ["sphere_camera", "render_sphere"]


def sphere_camera(size: int = 256, *, margin: float = 1.08) -> Camera:
    """A ``size × size`` camera on +z looking at a unit sphere at the origin, ``margin`` × its radius in view.

    Parameters
    ----------
    size : int in [1, 65536]
        Image width and height in pixels.
    margin : float > 0
        Half the view height, in sphere radii (default 1.08: a thin border around the disc).

    Returns
    -------
    Camera
        Orthographic, at ``(0, 0, 10)`` looking at the origin, ``ortho_height = 2 * margin``.
    """
    size = check_count("size", size, 1, MAX_IMAGE_SIDE)
    margin = check_positive("margin", margin)
    return Camera((0, 0, 10.0), (0, 0, 0), projection="orthographic", ortho_height=2 * margin, width=size, height=size)


def render_sphere(material: Material, lights, *, size: int = 256, form: str = "classic", background=0.0):
    """Linear RGB image ``(size, size, 3)`` of the lit unit sphere, per-pixel exact (viewer at +z infinity).

    Parameters
    ----------
    material : Material
    lights : sequence of lights
    size : int in [1, 65536]
        Image width and height in pixels; refused (``BudgetError``, a ValueError) when the image would
        need more than the memory budget.
    form : {"classic", "physical"}
    background : scalar or RGB >= 0

    Returns
    -------
    LinearImage
        ``(size, size, 3)`` linear RGB, ``float64``; pixels off the sphere hold ``background``.  An
        ``ndarray`` that shows itself sRGB-encoded in Jupyter (``np.asarray(img)``: the plain array).
    """
    size = check_count("size", size, 1, MAX_IMAGE_SIDE)
    check_budget("size", size * size * RENDER_BYTES_PER_PIXEL, what=f"a {size}x{size} image")
    return Renderer(AnalyticSphere(), sphere_camera(size)).render(material, lights, form=form, background=background)

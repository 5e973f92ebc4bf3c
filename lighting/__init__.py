"""lighting — a standalone local-illumination engine for teaching (NumPy only).

The subpackages follow the lectures:

=========== ==============================================================================
vec         vectors: normalize, dot, reflect, halfway, frames
models      reflectance models: Lambert, Phong, Blinn–Phong, Cook–Torrance, microfacet and
            Fresnel terms, the model protocol and its registry
lights      ambient, directional, point, spot and area lights; environments
shading     the illumination equation (classic and physical), plans, the OpenGL mode
render      meshes, cameras, the rasterizer, flat / Gouraud / Phong images, image files
integrate   the rendering equation: sampling, quadrature, albedo, SH irradiance
analysis    BRDFs as data: slices, lobes, the plausibility audit, Mach bands
files       BRDFs read from files: ``load_brdf`` (MERL ``.binary``, BRDF Explorer ``.brdf``)
scene       scene files (TOML) and the example scenes
validation  the accuracy and stability studies (not loaded by ``import lighting``)
=========== ==============================================================================

Importing this package loads NumPy and nothing heavier.  The module paths of the
public contract (``lighting.brdf``, ``lighting.microfacet``, ``lighting.fresnel``,
``lighting.gl``, ``lighting.sampling``, ``lighting.integrate``, ``lighting.vec``) keep
working; the first five are re-export modules.
"""

import importlib

from . import files, lights, models, render, shading, vec
from .files import load_brdf
from .lights import AmbientLight, DirectionalLight, DiskLight, PointLight, RectLight, SpotLight, environment  # noqa: F401
from .models import BlinnPhong, CookTorrance, Lambert, Phong, brdf, fresnel, microfacet  # noqa: F401
from .render import camera, mesh, raster  # noqa: F401
from .shading import Material, shade, shade_terms
from .shading import equation as illumination  # noqa: F401

__version__ = "0.1.0"

#: Imported on first use (PEP 562): the rendering equation and the BRDF analysis are not needed to
#: shade or render an image, and their import is a large share of a short ``render`` command.
_LAZY = {
    "analysis": "lighting.analysis",
    "integrate": "lighting.integrate",
    "audit": "lighting.analysis.audit",
    "machband": "lighting.analysis.machband",
    "sampling": "lighting.sampling.brdf",
}


def __getattr__(name):
    if name in _LAZY:
        module = importlib.import_module(_LAZY[name])
        globals()[name] = module
        return module
    raise AttributeError(f"module 'lighting' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))

__all__ = [
    "vec",
    "models",
    "lights",
    "shading",
    "render",
    "integrate",
    "analysis",
    "files",
    "Lambert",
    "Phong",
    "BlinnPhong",
    "CookTorrance",
    "AmbientLight",
    "DirectionalLight",
    "PointLight",
    "SpotLight",
    "RectLight",
    "DiskLight",
    "Material",
    "shade",
    "shade_terms",
    "load_brdf",
]

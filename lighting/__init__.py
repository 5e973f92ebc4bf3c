"""lighting — a standalone local-illumination engine for teaching (NumPy only).

Modules
-------
vec         vectors: normalize, dot, reflect, halfway
brdf        reflectance models: Lambert, Phong, BlinnPhong, CookTorrance, sums
microfacet  NDFs (Beckmann, GGX) and shadowing–masking (V-cavity, Smith)
fresnel     Schlick and exact dielectric Fresnel
lights      ambient, directional, point, spot and area lights
illumination the illumination equation, classic and physical form
gl          the OpenGL 1.x/2.1 fixed-function lighting equation, exactly
image       linear float images → sRGB 8-bit PNG
mesh        triangle meshes: UV sphere, icosphere, files through trimesh (lazily)
camera      look-at cameras, perspective and orthographic
raster      NumPy rasterizer (geometry buffer) and the ray-cast analytic sphere
render      flat / Gouraud / Phong-interpolated images; re-shading a cached buffer
machband    scan-line profiles and the Mach band metric
analysis    BRDF plots as data: polar slices, half/difference-angle views, 3D lobes
environment environment lighting: constant, lat-long image, function, small bright patch
sampling    hemisphere and BRDF importance sampling
integrate   albedo and the rendering equation: quadrature, Monte Carlo, SH irradiance
audit       the plausibility audit: positive, reciprocal, energy conserving

Importing this package loads NumPy and nothing heavier.
"""

from . import (
    analysis,
    audit,
    brdf,
    camera,
    environment,
    fresnel,
    illumination,
    integrate,
    lights,
    machband,
    mesh,
    microfacet,
    raster,
    render,
    sampling,
    vec,
)
from .brdf import BlinnPhong, CookTorrance, Lambert, Phong
from .illumination import Material, shade, shade_terms
from .lights import AmbientLight, DirectionalLight, DiskLight, PointLight, RectLight, SpotLight

__version__ = "0.1.0"

__all__ = [
    "analysis",
    "audit",
    "brdf",
    "camera",
    "environment",
    "integrate",
    "machband",
    "mesh",
    "raster",
    "render",
    "sampling",
    "fresnel",
    "lights",
    "microfacet",
    "illumination",
    "vec",
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
]

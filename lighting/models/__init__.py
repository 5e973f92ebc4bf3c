"""Reflectance models: the BRDF protocol, Lambert, Phong, Blinn–Phong, Cook–Torrance, microfacet terms, Fresnel."""

from __future__ import annotations

from . import brdf, fresnel, microfacet, protocol
from .brdf import (  # noqa: F401
    BRDF,
    BlinnPhong,
    BRDFSum,
    CookTorrance,
    Geometry,
    Lambert,
    Phong,
    StackedGeometry,
    cos_power,
)
from .fresnel import (  # noqa: F401
    dielectric,
    eta_from_f0,
    f0_from_eta,
    schlick,
)
from .microfacet import (  # noqa: F401
    beckmann_ndf,
    blinn_phong_exponent,
    blinn_phong_ndf,
    check_alpha,
    ggx_ndf,
    smith_g1_beckmann,
    smith_g1_ggx,
    vcavity_g,
)
from .protocol import (  # noqa: F401
    Lobe,
    Parameter,
    create_model,
    model_class,
    model_names,
    model_variants,
    register_model,
)

__all__ = [
    "protocol",
    "Lobe",
    "Parameter",
    "create_model",
    "model_class",
    "model_names",
    "model_variants",
    "register_model",
    "protocol",
    "Lobe",
    "Parameter",
    "create_model",
    "model_class",
    "model_names",
    "model_variants",
    "register_model",
    "microfacet",
    "fresnel",
    "brdf",
    "beckmann_ndf",
    "ggx_ndf",
    "blinn_phong_ndf",
    "blinn_phong_exponent",
    "smith_g1_beckmann",
    "smith_g1_ggx",
    "vcavity_g",
    "check_alpha",
    "schlick",
    "dielectric",
    "f0_from_eta",
    "eta_from_f0",
    "Geometry",
    "StackedGeometry",
    "BRDF",
    "Lambert",
    "Phong",
    "BlinnPhong",
    "CookTorrance",
    "BRDFSum",
    "cos_power",
]

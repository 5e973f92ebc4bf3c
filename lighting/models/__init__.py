"""Reflectance models: the BRDF protocol, Lambert, Phong, Blinn–Phong, Cook–Torrance, microfacet terms, Fresnel."""

from __future__ import annotations

from . import brdf, fresnel, microfacet, protocol
from .brdf import *  # noqa: F403
from .fresnel import *  # noqa: F403
from .microfacet import *  # noqa: F403
from .protocol import *  # noqa: F403

__all__ = [
    "protocol",
    "microfacet",
    "fresnel",
    "brdf",
    *protocol.__all__,
    *microfacet.__all__,
    *fresnel.__all__,
    *brdf.__all__,
]

"""The illumination equation: materials, shade, and the OpenGL fixed-function mode."""

from __future__ import annotations

from . import equation, opengl
from .equation import (  # noqa: F401
    FORMS,
    TERMS,
    Material,
    shade,
    shade_prepared,
    shade_terms,
    view_vectors,
)
from .opengl import (  # noqa: F401
    GL_MAX_SHININESS,
    GL_MAX_SPOT_EXPONENT,
    Light,
    shade_vertices,
)

__all__ = [
    "equation",
    "opengl",
    "Material",
    "shade",
    "shade_terms",
    "shade_prepared",
    "view_vectors",
    "TERMS",
    "FORMS",
    "Light",
    "shade_vertices",
    "GL_MAX_SHININESS",
    "GL_MAX_SPOT_EXPONENT",
]

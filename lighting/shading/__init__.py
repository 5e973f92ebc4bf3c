"""The illumination equation: materials, shade, and the OpenGL fixed-function mode."""

from __future__ import annotations

from . import equation, opengl
from .equation import *  # noqa: F403

# The OpenGL mode's names (its own Material and Light) stay under lighting.shading.opengl (lighting.gl).

__all__ = [
    "equation",
    "opengl",
    *equation.__all__,
]

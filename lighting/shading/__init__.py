"""The illumination equation: materials, shade, the reference loop, the fast path, and the OpenGL mode."""

from __future__ import annotations

from . import batch, equation, inputs, material, opengl, reference  # noqa: F401  (listed in __all__ below)
from .batch import *  # noqa: F403
from .equation import *  # noqa: F403
from .material import *  # noqa: F403
from .reference import *  # noqa: F403

# The OpenGL mode's names (its own Material and Light) stay under lighting.shading.opengl (lighting.gl).

__all__ = list(
    dict.fromkeys(
        [
            "material",
            "inputs",
            "equation",
            "reference",
            "batch",
            "opengl",
            *material.__all__,
            *equation.__all__,
            *reference.__all__,
            *batch.__all__,
        ]
    )
)

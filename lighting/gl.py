"""``lighting.gl``: the contract's import path for the OpenGL 1.x / 2.1 fixed-function lighting.

The code lives in :mod:`lighting.shading.opengl`; this module re-exports its public names (its ``__all__``), the
same objects.
"""

from .shading.opengl import *  # noqa: F403
from .shading.opengl import __all__  # noqa: F401

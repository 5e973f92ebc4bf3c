"""``lighting.gl``: the contract's import path, kept; the code lives in :mod:`lighting.shading.opengl`.

Importing this path gives that very module (not a copy), so ``lighting.gl is lighting.shading.opengl``.
"""

import sys

from .shading import opengl as _module

sys.modules[__name__] = _module

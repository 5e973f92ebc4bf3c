"""``lighting.fresnel``: the contract's import path, kept; the code lives in :mod:`lighting.models.fresnel`.

Importing this path gives that very module (not a copy), so ``lighting.fresnel is lighting.models.fresnel``.
"""

import sys

from .models import fresnel as _module

sys.modules[__name__] = _module

"""``lighting.brdf``: the contract's import path, kept; the code lives in :mod:`lighting.models.brdf`.

Importing this path gives that very module (not a copy), so ``lighting.brdf is lighting.models.brdf``.
"""

import sys

from .models import brdf as _module

sys.modules[__name__] = _module

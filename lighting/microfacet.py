"""``lighting.microfacet``: the contract's import path, kept; the code lives in :mod:`lighting.models.microfacet`.

Importing this path gives that very module (not a copy), so ``lighting.microfacet is lighting.models.microfacet``.
"""

import sys

from .models import microfacet as _module

sys.modules[__name__] = _module

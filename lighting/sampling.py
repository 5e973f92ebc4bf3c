"""``lighting.sampling``: the contract's import path, kept; the code lives in :mod:`lighting.integrate.sampling`.

Importing this path gives that very module (not a copy), so ``lighting.sampling is lighting.integrate.sampling``.
"""

import sys

from .integrate import sampling as _module

sys.modules[__name__] = _module

"""``lighting.brdf``: the contract's import path for the reflectance models.

The code lives in :mod:`lighting.models.brdf`; this module re-exports its public names (its ``__all__``), the
same objects.
"""

from .models.brdf import *  # noqa: F403
from .models.brdf import __all__  # noqa: F401

"""``lighting.fresnel``: the contract's import path for the Fresnel reflectances.

The code lives in :mod:`lighting.models.fresnel`; this module re-exports its public names (its ``__all__``), the
same objects.
"""

from .models.fresnel import *  # noqa: F403
from .models.fresnel import __all__  # noqa: F401

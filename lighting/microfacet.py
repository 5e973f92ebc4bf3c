"""``lighting.microfacet``: the contract's import path for the microfacet distributions and shadowing.

The code lives in :mod:`lighting.models.microfacet`; this module re-exports its public names (its ``__all__``), the
same objects.
"""

from .models.microfacet import *  # noqa: F403
from .models.microfacet import __all__  # noqa: F401

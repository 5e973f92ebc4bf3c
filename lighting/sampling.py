"""``lighting.sampling``: the contract's import path for the importance samplers.

The code lives in :mod:`lighting.integrate.sampling`; this module re-exports its public names (its ``__all__``), the
same objects.
"""

from .integrate.sampling import *  # noqa: F403
from .integrate.sampling import __all__  # noqa: F401

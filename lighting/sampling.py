"""``lighting.sampling``: the contract's import path, kept; the code lives in :mod:`lighting.integrate.sampling`.

Importing this path gives that very module (not a copy), so ``lighting.sampling is lighting.integrate.sampling``.
The contract's sampler classes are all importable from it, the visible-normal sampler of the Smith
microfacet models (:class:`~lighting.models.microfacet_sampling.VisibleNormalSampler`, what
``CookTorrance(geometry="smith").sampler()`` returns) among them.
"""

import sys

from .integrate import sampling as _module
from .models.microfacet_sampling import VisibleNormalSampler as _VisibleNormalSampler

if "VisibleNormalSampler" not in _module.__all__:
    # Exported beside MicrofacetSampler, the sampler it refines (pbrt's TrowbridgeReitz Sample_wm).
    _module.VisibleNormalSampler = _VisibleNormalSampler
    _module.__all__ = [*_module.__all__, "VisibleNormalSampler"]

sys.modules[__name__] = _module

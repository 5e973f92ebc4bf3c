"""``lighting.sampling``: the contract's import path, kept; the code lives in :mod:`lighting.integrate.sampling`.

Importing this path gives that very module (not a copy), so ``lighting.sampling is lighting.integrate.sampling``.
The contract's sampler classes are all importable from it, the visible-normal sampler of the Smith
microfacet models (:class:`~lighting.models.microfacet_sampling.VisibleNormalSampler`, what
``CookTorrance(geometry="smith").sampler()`` returns) and the ideal mirror's delta sampler among them.
"""

import sys

from .integrate import sampling as _module

sys.modules[__name__] = _module

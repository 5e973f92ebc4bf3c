"""Reflectance models: the BRDF protocol, Lambert, Phong, Blinn–Phong, Cook–Torrance, microfacet terms, Fresnel.

One module per topic: ``protocol`` (parameters, lobes, the registry), ``geometry`` (the shading
directions), ``base`` (the BRDF base class and sums), ``sampler`` (the sampler protocol), one
module per model family (each registers its model and defines its sampler), ``microfacet`` and
``fresnel`` (the factors), and ``brdf`` (every model under the contract's name ``lighting.brdf``).
The import order below is the registry's order: lambert, phong, blinn-phong, cook-torrance, then
oren-nayar, ward, ashikhmin-shirley, disney.
"""

from __future__ import annotations

# isort: off
# The order of these imports is the registry's order (each model's module registers its model).
from . import protocol, microfacet, fresnel, geometry, base
from ..sampling import base as sampler
from . import lambert, phong, blinn_phong, cook_torrance, brdf
from ..sampling import microfacet as microfacet_sampling
# Beyond the slides, in the order lecturers compare them: diffuse, then glossy, then the principled model.
from . import oren_nayar, ward, ashikhmin_shirley, disney, mirror  # noqa: F401  (mirror: registers "mirror")
from . import custom
from .custom import define_brdf

# isort: on
from ..sampling.base import *  # noqa: F403
from ..sampling.microfacet import *  # noqa: F403
from .brdf import *  # noqa: F403
from .fresnel import *  # noqa: F403
from .lambert import *  # noqa: F403
from .microfacet import *  # noqa: F403
from .phong import *  # noqa: F403
from .protocol import *  # noqa: F403

__all__ = [
    "protocol",
    "microfacet",
    "fresnel",
    "geometry",
    "base",
    "sampler",
    "lambert",
    "phong",
    "microfacet_sampling",
    "blinn_phong",
    "cook_torrance",
    "brdf",
    "oren_nayar",
    "ward",
    "ashikhmin_shirley",
    "disney",
    "mirror",
    "custom",
    "define_brdf",
    *protocol.__all__,
    *microfacet.__all__,
    *fresnel.__all__,
    *sampler.__all__,
    *[name for name in lambert.__all__ if name != "Lambert"],
    *[name for name in phong.__all__ if name != "Phong"],
    *microfacet_sampling.__all__,
    *brdf.__all__,
]

"""BRDFs as data: slices, lobes, the plausibility audit, Mach bands.

==========  ==========================================================================
quantity    what every plot plots (f_r, × cosine, channel, log) and the shared options
slices      polar slices, one direction fixed, and the reciprocity pair
halfdiff    Rusinkiewicz's half/difference angles and the image over them
curves      the BRDF against θ_h, θ_d or the view angle
lobes       a lobe's width and its peak
meshes      the 3D lobe surface
audit       positivity, reciprocity and energy conservation, measured
machband    Mach bands measured on scan lines
==========  ==========================================================================
"""

from __future__ import annotations

from . import audit as _audit_module
from . import curves, halfdiff, lobes, machband, meshes, quantity, slices
from .audit import *  # noqa: F403
from .curves import *  # noqa: F403
from .halfdiff import *  # noqa: F403
from .lobes import *  # noqa: F403
from .machband import *  # noqa: F403
from .meshes import *  # noqa: F403
from .quantity import *  # noqa: F403
from .slices import *  # noqa: F403

#: ``lighting.analysis.audit`` is the module (as its import path says); the function is ``audit.audit``.
audit = _audit_module

_MODULES = (quantity, slices, halfdiff, curves, lobes, meshes, audit, machband)

__all__ = [
    "quantity",
    "slices",
    "halfdiff",
    "curves",
    "lobes",
    "meshes",
    "audit",
    "machband",
    *[n for m in _MODULES for n in m.__all__ if n != "audit"],
]

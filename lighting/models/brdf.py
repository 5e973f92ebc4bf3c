"""The reflectance models under one name: ``lighting.brdf`` (the contract's path) is this module.

The code lives one module per topic: :mod:`.geometry` (:class:`Geometry`), :mod:`.base`
(:class:`BRDF`, :class:`BRDFSum`, :func:`cos_power`), :mod:`.lambert`, :mod:`.phong`,
:mod:`.blinn_phong` and :mod:`.cook_torrance`.  The fast path's all-lights geometry is
:class:`lighting.shading.stacked.StackedGeometry`.
"""

from __future__ import annotations

from .base import BRDF, BRDFFlags, BRDFSum, MicrofacetLobe, cos_power
from .blinn_phong import BlinnPhong
from .cook_torrance import CookTorrance
from .geometry import Geometry
from .lambert import Lambert
from .phong import Phong

__all__ = [
    "Geometry",
    "BRDF",
    "BRDFFlags",
    "MicrofacetLobe",
    "Lambert",
    "Phong",
    "BlinnPhong",
    "CookTorrance",
    "BRDFSum",
    "cos_power",
]

"""BRDFs as data: slices, lobes, the plausibility audit, Mach bands."""

from __future__ import annotations

from . import analysis, machband
from . import audit as _audit_module
from .analysis import *  # noqa: F403
from .audit import *  # noqa: F403
from .machband import *  # noqa: F403

#: ``lighting.analysis.audit`` is the module (as its import path says); the function is ``audit.audit``.
audit = _audit_module

__all__ = [
    "analysis",
    "audit",
    "machband",
    *[n for n in (*analysis.__all__, *audit.__all__, *machband.__all__) if n != "audit"],
]

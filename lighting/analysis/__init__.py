"""BRDFs as data: slices, lobes, the plausibility audit, Mach bands."""

from __future__ import annotations

from . import analysis, audit, machband
from .analysis import (  # noqa: F401
    LUMINANCE,
    AngleCurve,
    HalfDiffImage,
    LobeMesh,
    LobePeak,
    PolarSlice,
    dirs_to_half_diff,
    half_diff_image,
    half_diff_to_dirs,
    lobe_mesh,
    lobe_peak,
    lobe_width,
    polar_slice,
    reciprocity_pair,
    theta_d_curve,
    theta_h_curve,
    theta_v_curve,
)
from .audit import (  # noqa: F401
    AuditCase,
    AuditRow,
    AuditTable,
    default_cases,
    direction_pairs,
)
from .machband import (  # noqa: F401
    Profile,
    edge_jump_metric,
    luminance,
    scanline_profile,
)

__all__ = [
    "analysis",
    "audit",
    "machband",
    "LUMINANCE",
    "PolarSlice",
    "AngleCurve",
    "HalfDiffImage",
    "LobeMesh",
    "LobePeak",
    "polar_slice",
    "reciprocity_pair",
    "half_diff_to_dirs",
    "dirs_to_half_diff",
    "theta_h_curve",
    "theta_d_curve",
    "theta_v_curve",
    "half_diff_image",
    "lobe_width",
    "lobe_peak",
    "lobe_mesh",
    "AuditCase",
    "AuditRow",
    "AuditTable",
    "default_cases",
    "direction_pairs",
    "Profile",
    "luminance",
    "scanline_profile",
    "edge_jump_metric",
]

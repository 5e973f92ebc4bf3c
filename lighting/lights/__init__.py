"""Light sources: ambient, directional, point, spot, area lights and environments."""

from __future__ import annotations

from . import environment, punctual
from .environment import (  # noqa: F401
    ConstantEnvironment,
    Environment,
    FunctionEnvironment,
    LatLongEnvironment,
    PointEnvironment,
    SmallPatchEnvironment,
    as_environment,
    uniform_sphere,
    uniform_sphere_pdf,
)
from .punctual import (  # noqa: F401
    AmbientLight,
    AreaLight,
    DirectionalLight,
    DiskLight,
    Incidence,
    Light,
    PointLight,
    RectLight,
    SpotLight,
    check_attenuation,
    check_cutoff,
)

__all__ = [
    "punctual",
    "environment",
    "Incidence",
    "Light",
    "AmbientLight",
    "DirectionalLight",
    "PointLight",
    "SpotLight",
    "AreaLight",
    "RectLight",
    "DiskLight",
    "check_attenuation",
    "check_cutoff",
    "Environment",
    "ConstantEnvironment",
    "LatLongEnvironment",
    "FunctionEnvironment",
    "SmallPatchEnvironment",
    "PointEnvironment",
    "uniform_sphere",
    "uniform_sphere_pdf",
    "as_environment",
]

"""Light sources: ambient, directional, point and spot lights (punctual), area lights and environments."""

from __future__ import annotations

from . import area, environment, punctual
from .area import *  # noqa: F403
from .envfiles import TransformedEnvironment, load_environment, read_environment_image, write_hdr
from .environment import *  # noqa: F403
from .envlight import ENVIRONMENT_METHODS, EnvironmentLight, split_environment_lights
from .punctual import *  # noqa: F403
from .skies import SKIES, sky

__all__ = [
    "punctual",
    "area",
    "environment",
    *punctual.__all__,
    *area.__all__,
    *environment.__all__,
    "load_environment",
    "read_environment_image",
    "write_hdr",
    "TransformedEnvironment",
    "SKIES",
    "sky",
    "EnvironmentLight",
    "ENVIRONMENT_METHODS",
    "split_environment_lights",
]

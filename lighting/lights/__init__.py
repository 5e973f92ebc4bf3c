"""Light sources: ambient, directional, point, spot, area lights and environments."""

from __future__ import annotations

from . import environment, punctual
from .environment import *  # noqa: F403
from .punctual import *  # noqa: F403

__all__ = ["punctual", "environment", *punctual.__all__, *environment.__all__]

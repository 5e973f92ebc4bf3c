"""Scene files: schema, loading, saving and rendering; example scenes in ``examples/``."""

from __future__ import annotations

from . import scene
from .scene import *  # noqa: F403

__all__ = ["scene", *scene.__all__]

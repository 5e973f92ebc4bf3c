"""The rendering equation over the hemisphere: sampling, quadrature, albedo, radiance, SH irradiance."""

from __future__ import annotations

from . import integrate, sampling
from .integrate import *  # noqa: F403
from .sampling import *  # noqa: F403

__all__ = ["sampling", "integrate", *sampling.__all__, *integrate.__all__]

"""A surface for the illumination equation: a reflectance model plus ``k_a`` and ``k_e``."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._text import quote
from .._validate import ArgumentTypeError, check_color
from ..models.base import BRDF

__all__ = ["Material"]


@dataclass(frozen=True, repr=False)
class Material:
    """A surface: a reflectance model plus the slides' ambient and emission coefficients.

    Parameters
    ----------
    brdf : BRDF
        The reflectance model (``Lambert(kd) + Phong(ks, e)`` is the slides' surface).
    ambient : scalar or RGB, optional
        ``k_a``, the fraction of ambient light reflected.  Defaults to the
        model's diffuse albedo (``k_a = k_d``), which is the usual choice: ambient
        light then shows the object's own colour.
    emission : scalar or RGB
        ``k_e``, light the surface gives off itself (classic units).
    """

    brdf: BRDF
    ambient: object = None
    emission: object = 0.0

    def __post_init__(self):
        if not isinstance(self.brdf, BRDF):
            raise ArgumentTypeError(
                f"brdf must be a lighting.models.brdf model (Lambert, Phong, ...); got {type(self.brdf).__name__} "
                f"{quote(self.brdf)}"
            )
        ka = self.brdf.diffuse_albedo if self.ambient is None else self.ambient
        object.__setattr__(self, "ambient", check_color("ambient", ka))
        object.__setattr__(self, "emission", check_color("emission", self.emission))

    def __repr__(self) -> str:
        """One line: the model, then ``ambient`` and ``emission`` only where they differ from their defaults.

        ``Material(Lambert(kd=0.8) + Phong(ks=0.5, shininess=32))``; ``ambient`` defaults to the model's
        diffuse albedo, ``emission`` to 0.
        """
        from ..models.base import _short

        fields = [repr(self.brdf)]
        default = np.broadcast_to(np.asarray(self.brdf.diffuse_albedo, dtype=np.float64), (3,))
        if not np.array_equal(self.ambient, default):
            fields.append(f"ambient={_short(self.ambient)}")
        if np.any(self.emission != 0):
            fields.append(f"emission={_short(self.emission)}")
        return f"Material({', '.join(fields)})"


def check_material(material) -> Material:
    """``material`` itself if it is a :class:`Material`, else an ``ArgumentTypeError`` naming what was given.

    Parameters
    ----------
    material : Material

    Returns
    -------
    Material
        The same object.
    """
    if not isinstance(material, Material):
        raise ArgumentTypeError(
            f"material must be a lighting.Material; got {type(material).__name__} {quote(material)}")
    return material

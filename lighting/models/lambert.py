r"""Lambert's ideal diffuse reflection and its sampler, the cosine-weighted hemisphere.

    f_r = k_d / π,        classic term k_d (n·l),        p(l) = cos θ / π
"""

from __future__ import annotations

import math

import numpy as np

from ..sampling.base import Samples, _directions, _unit_square, _ViewIndependentSampler
from .base import BRDFFlags, SeparableBRDF, _color, _color_text, _rgb
from .protocol import Lobe, Parameter, register_model

__all__ = ["Lambert", "CosineSampler", "square_to_cosine_hemisphere", "cosine_hemisphere_pdf"]


class Lambert(SeparableBRDF):
    r"""Ideal diffuse (Lambertian, "matte") reflection.

        f_r = k_d / π                (BRDF constant)
        classic term: k_d (n·l)      (Lambert's cosine law)

    ``kd`` is the albedo: a Lambertian surface reflects the fraction ``k_d`` of
    the light it receives, in every direction alike.

    Parameters
    ----------
    kd : float or RGB triple, >= 0
        Diffuse albedo (the surface colour).

    References
    ----------
    J. H. Lambert, *Photometria, sive de mensura et gradibus luminis, colorum et umbrae*, 1760.

    Examples
    --------
    >>> Lambert(1.0).eval((0, 0, 1.0), (0, 0, 1.0), (0, 0, 1.0)).round(6).tolist()
    [0.31831, 0.31831, 0.31831]
    """

    name = "lambert"
    flags = BRDFFlags.DIFFUSE | BRDFFlags.LAMBERTIAN
    stackable = True
    parameters = (
        Parameter("kd", "color", 0.8, slider=(0.0, 1.0), description="diffuse albedo k_d (the surface colour)"),
    )

    def __init__(self, kd=0.8):
        self.kd = _color("kd", kd)

    @property
    def is_black(self):
        return not np.any(self.kd > 0)

    def lobe(self):
        """``Lobe("normal")``: spread over the hemisphere about ``n``."""
        return Lobe("normal")

    def sampler(self):
        """``CosineSampler``: exact importance sampling for ``f_r (n·l) ∝ n·l``."""
        return CosineSampler()

    def summary(self):
        """``"kd=0.8"``, or ``"kd=(0.8,0.2,0.1)"`` for a coloured albedo."""
        return f"kd={_color_text(self.kd)}"

    def _params(self):
        return {"kd": self.kd}

    @property
    def diffuse_albedo(self):
        return self.kd

    def _f(self, g):
        return _rgb(np.where(g.above, 1 / math.pi, 0).astype(g.dtype), self.kd)

    def separable_cos(self, g):
        """One term ``(n·l / π, kd)``: the scalar field is 0 below the horizon, in the dtype of ``g``."""
        return [(np.where(g.above, g.n_dot_l / g.dtype(math.pi), 0).astype(g.dtype), self.kd)]

    def separable_classic(self, g):
        """One term ``(n·l, kd)``: the scalar field is 0 below the horizon, in the dtype of ``g``."""
        return [((g.n_dot_l * g.above_mask).astype(g.dtype, copy=False), self.kd)]



def _concentric_disk(u: np.ndarray):
    r"""Shirley–Chiu concentric map of the square onto the unit disk (area preserving, low distortion).

    With ``a = 2 u₀ − 1`` and ``b = 2 u₁ − 1``:

        |a| > |b|:  r = a,  φ = (π/4) (b/a)
        otherwise:  r = b,  φ = π/2 − (π/4) (a/b)        (φ = 0 at a = b = 0)
        (x, y) = (r cos φ, r sin φ)

    P. Shirley and K. Chiu, "A low distortion map between disk and square", Journal of
    Graphics Tools 2(3), 1997.

    Parameters
    ----------
    u : ndarray, shape (..., 2)
        Points of the unit square (checked by the caller).

    Returns
    -------
    x, y : ndarray, shape (...)
        Points of the unit disk.
    """
    a = 2 * u[..., 0] - 1
    b = 2 * u[..., 1] - 1
    first = np.abs(a) > np.abs(b)
    r = np.where(first, a, b)
    # a, b lie in [−1, 1] and a zero divisor is replaced by 1: the quotients are finite.
    phi = np.where(
        first,
        (math.pi / 4) * (b / np.where(a != 0, a, 1.0)),
        (math.pi / 2) - (math.pi / 4) * (a / np.where(b != 0, b, 1.0)),
    )
    phi = np.where((a == 0) & (b == 0), 0.0, phi)
    return r * np.cos(phi), r * np.sin(phi)



def square_to_cosine_hemisphere(u) -> Samples:
    """Cosine-weighted directions (Malley's method): ``p = cos θ / π``.

    Points of the disk (:func:`_concentric_disk`) lifted to the hemisphere, ``z = √(1 − x² − y²)``.

    Parameters
    ----------
    u : array_like, shape (..., 2)
        Points of the unit square.

    Returns
    -------
    Samples
        Directions ``(..., 3)`` and their density ``(...)``.

    Examples
    --------
    >>> s = square_to_cosine_hemisphere(np.array([0.5, 0.5]))
    >>> s.directions.tolist(), round(float(s.pdf) * math.pi, 12)
    ([0.0, 0.0, 1.0], 1.0)
    """
    u = _unit_square("u", u)
    x, y = _concentric_disk(u)
    z = np.sqrt(np.clip(1 - x * x - y * y, 0.0, None))
    return Samples(np.stack([x, y, z], axis=-1), z / math.pi)


def cosine_hemisphere_pdf(d) -> np.ndarray:
    """``max(cos θ, 0) / π``.

    Parameters
    ----------
    d : array_like, shape (..., 3)
        Directions in the local frame.

    Returns
    -------
    ndarray, shape (...)
    """
    d = _directions("d", d)
    return np.maximum(d[..., 2], 0.0) / math.pi



class CosineSampler(_ViewIndependentSampler):
    """Cosine-weighted over the hemisphere (ignores ``v``): exact importance sampling for Lambert."""

    name = "cosine"
    _warp = staticmethod(square_to_cosine_hemisphere)
    _density = staticmethod(cosine_hemisphere_pdf)



register_model(Lambert)

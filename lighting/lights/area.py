r"""Area lights: lights with an extent (rectangle, disk), integrated by sampling.

An area light is a Lambertian emitter of radiance ``L_e = intensity × color``.
The irradiance it delivers at a point ``x`` is

    E(x) = ∫ L_e cos θ_e / r² dA,

estimated with ``S`` sample points ``y_k`` on the emitter: each sample is one
:class:`~lighting.lights.punctual.Incidence` with

    direction = (y_k − x)/|y_k − x|,   irradiance = L_e (A / S) cos θ_e / r².

The sample points come from the R2 low-discrepancy sequence (Roberts 2018),
shifted at random (Cranley–Patterson rotation) when a seed is given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._budget import check_budget
from .._text import quote
from .._validate import check_bool, check_color, check_count, check_nonnegative, check_positive
from ..models.lambert import _concentric_disk
from ..numerics import as_float, saturate_to
from ..vec import length, normalize, orthonormal_basis
from .punctual import _BIG64, Incidence, Light, _directions_and_distances, _vector3

__all__ = ["AreaLight", "RectLight", "DiskLight"]

#: Most sample points an area light may take (each is one incidence, i.e. one shading pass, per point).
MAX_AREA_SAMPLES = 1 << 16


def _r2_sequence(n: int, seed: int | None) -> np.ndarray:
    """``n`` points of the R2 low-discrepancy sequence in [0, 1)² (Roberts 2018).

    A seed applies a random toroidal shift (Cranley–Patterson rotation), which
    keeps the low discrepancy and makes the estimate unbiased over seeds.
    """
    g = 1.32471795724474602596  # plastic number
    a = np.array([1 / g, 1 / (g * g)])
    k = np.arange(1, n + 1)[:, None]
    shift = np.full(2, 0.5) if seed is None else np.random.default_rng(seed).random(2)
    return (shift + k * a) % 1.0


@dataclass(frozen=True, kw_only=True, repr=False)
class AreaLight(Light):
    r"""Base of lights with an extent, integrated by sampling.

    The emitter is Lambertian with radiance ``L_e = intensity × color`` on the side
    its normal faces (both sides with ``two_sided=True``).  The irradiance it
    delivers is ``E = ∫ L_e cos θ_e / r² dA``; with ``samples`` points ``y_k`` on
    it, each sample is an incidence with

        direction = (y_k − x)/|y_k − x|,   irradiance = L_e (A / S) cos θ_e / r².

    As the light shrinks (``L_e A`` fixed) this tends to a point light of
    intensity ``L_e A``.  ``samples`` trades accuracy for time: points come
    from a low-discrepancy (R2) pattern, shifted by ``seed`` when one is given.
    """

    color: object = 1.0
    intensity: float = 1.0
    samples: int = 16
    seed: int | None = None
    two_sided: bool = False

    def _check_common(self):
        object.__setattr__(self, "color", check_color("color", self.color))
        object.__setattr__(self, "intensity", check_nonnegative("intensity", self.intensity))
        samples = check_count("samples", self.samples, 1, MAX_AREA_SAMPLES)
        # The sample points are made at once (3 float64 each, plus the pattern's temporaries).
        check_budget("samples", samples * 8 * 12, what=f"{samples} area-light sample points")
        object.__setattr__(self, "samples", samples)
        if self.seed is not None:
            object.__setattr__(self, "seed", check_count("seed", self.seed, 0))
        object.__setattr__(self, "two_sided", check_bool("two_sided", self.two_sided))

    # Subclasses provide the geometry.
    def area(self) -> float:
        """The emitter's area ``A``.

        Returns
        -------
        float
        """
        raise NotImplementedError

    def normal(self) -> np.ndarray:
        """The unit normal of the emitter's lit side.

        Returns
        -------
        numpy.ndarray, (3,)
        """
        raise NotImplementedError

    def sample_points(self) -> np.ndarray:
        """``(samples, 3)`` points on the emitter, equal-area distributed.

        Returns
        -------
        numpy.ndarray, (samples, 3)
            From the R2 sequence (shifted by ``seed`` when one is given).
        """
        raise NotImplementedError

    def _incident(self, points, *, dtype, extra_distance=None):
        dt = dtype
        p = as_float(points, dt)
        ne = self.normal()
        weight = self.area() / self.samples
        radiant = saturate_to(self.radiant, dt)
        for y in self.sample_points():
            l, dist = _directions_and_distances(y, p)  # noqa: E741
            cos_e = -(l @ ne)
            cos_e = np.abs(cos_e) if self.two_sided else np.maximum(cos_e, 0.0)
            # The geometric factor A/S / r² saturates before the emitter's cosine (in [0, 1]) multiplies
            # it, so a sample seen edge-on (cos = 0) from 1e-170 away gives 0, not inf · 0.
            with np.errstate(divide="ignore", over="ignore", invalid="ignore", under="ignore"):
                inv = np.minimum(weight / np.where(dist > 0, dist, 1.0) / np.where(dist > 0, dist, 1.0), _BIG64)
            g = np.where(dist > 0, cos_e * inv, 0.0)
            yield Incidence(l.astype(dt), saturate_to(g, dt), radiant)


@dataclass(frozen=True, repr=False)
class RectLight(AreaLight):
    """A rectangular area light: ``center ± edge_u/2 ± edge_v/2``, facing ``edge_u × edge_v``.

    Examples
    --------
    >>> light = RectLight(center=(0, 0, 1.0), edge_u=(0.01, 0, 0), edge_v=(0, -0.01, 0),
    ...                   intensity=1e4, samples=4)
    >>> round(float(sum(i.irradiance[0, 0] for i in light.incident(np.zeros((1, 3))))), 4)
    1.0
    """

    center: object = (0.0, 0.0, 5.0)
    edge_u: object = (1.0, 0.0, 0.0)
    edge_v: object = (0.0, -1.0, 0.0)

    def __post_init__(self):
        self._check_common()
        object.__setattr__(self, "center", _vector3("center", self.center))
        u = _vector3("edge_u", self.edge_u)
        v = _vector3("edge_v", self.edge_v)
        with np.errstate(over="ignore", under="ignore", invalid="ignore"):
            c = np.cross(u, v)
            area = float(length(c)) if np.all(np.isfinite(c)) else math.inf
        if not 0 < area < math.inf:
            raise ValueError(
                "edge_u and edge_v must span a rectangle (non-parallel, non-zero, its area |edge_u × edge_v| "
                f"inside the float64 range); got edge_u={quote(u)}, edge_v={quote(v)}"
            )
        object.__setattr__(self, "edge_u", u)
        object.__setattr__(self, "edge_v", v)
        object.__setattr__(self, "_area", area)
        object.__setattr__(self, "_normal", normalize(c))

    def area(self):
        """``|edge_u × edge_v|`` (see :meth:`AreaLight.area`).

        Returns
        -------
        float
            The rectangle's area, finite and > 0.
        """
        return self._area

    def normal(self):
        """``normalize(edge_u × edge_v)`` (see :meth:`AreaLight.normal`).

        Returns
        -------
        numpy.ndarray
            ``(3,)`` ``float64`` unit vector.
        """
        return self._normal

    def sample_points(self):
        """Points of the R2 pattern on the rectangle (see :meth:`AreaLight.sample_points`).

        Returns
        -------
        numpy.ndarray
            ``(samples, 3)`` ``float64`` points inside the rectangle.
        """
        uv = _r2_sequence(self.samples, self.seed) - 0.5
        return self.center + uv[:, :1] * self.edge_u + uv[:, 1:] * self.edge_v


@dataclass(frozen=True, repr=False)
class DiskLight(AreaLight):
    """A disk-shaped area light of ``radius`` at ``center``, facing ``normal_dir``."""

    center: object = (0.0, 0.0, 5.0)
    normal_dir: object = (0.0, 0.0, -1.0)
    radius: float = 0.5

    def __post_init__(self):
        self._check_common()
        object.__setattr__(self, "center", _vector3("center", self.center))
        object.__setattr__(self, "normal_dir", normalize(_vector3("normal_dir", self.normal_dir, nonzero=True)))
        r = check_positive("radius", self.radius)
        area = math.pi * r * r  # floats: 1e200² is inf, not an OverflowError
        if not 0 < area < math.inf:
            raise ValueError(f"radius must be a finite number > 0 whose disk area π r² is inside the float64 range "
                             f"(about 1e-161 to 7e153); got {quote(self.radius)}")  # fmt: skip
        object.__setattr__(self, "radius", r)

    def area(self):
        """``π r²`` (see :meth:`AreaLight.area`).

        Returns
        -------
        float
            The disk's area, finite and > 0.
        """
        return math.pi * self.radius * self.radius

    def normal(self):
        """``normal_dir`` (see :meth:`AreaLight.normal`).

        Returns
        -------
        numpy.ndarray
            ``(3,)`` ``float64`` unit vector.
        """
        return self.normal_dir

    def sample_points(self):
        """Points of the R2 pattern mapped onto the disk (see :meth:`AreaLight.sample_points`).

        Returns
        -------
        numpy.ndarray
            ``(samples, 3)`` ``float64`` points inside the disk.
        """
        # Shirley–Chiu concentric map (equal-area, low distortion): the one the cosine sampler uses.
        x, y = _concentric_disk(_r2_sequence(self.samples, self.seed))
        t, bt = orthonormal_basis(self.normal_dir)
        return self.center + self.radius * (x[:, None] * t + y[:, None] * bt)

r"""Punctual light sources: ambient, directional, point and spot lights.

"Light is linear": a scene's lights simply add.  Every light answers one
question for a set of surface points — from which direction does light arrive,
and how strongly — through :meth:`Light.incident`, which yields
:class:`Incidence` records ``(direction, irradiance)``:

* ``direction`` — unit vector ``l`` from the point toward the light, ``(..., 3)``
  (or ``(3,)`` for a directional light, shared by every point);
* ``irradiance`` — the RGB light arriving, measured on a surface facing the
  light: ``I_p / A(d_p)`` in the slides' notation, shape ``(..., 3)`` or ``(3,)``.

Shading then adds ``f_r (n·l) · irradiance`` over incidences (physical form),
or ``π`` times that (classic form, :mod:`lighting.shading.equation`).  A point or spot
light yields one incidence, an area light (:mod:`lighting.lights.area`) one per sample.

Units: ``intensity × color`` is the irradiance a directional light delivers at
normal incidence, and the irradiance a point light delivers at unit distance.
Quantities too large for the working dtype (a point light at distance 1e-20 in
float32) saturate at its largest finite value; a point exactly at a light's
position receives nothing, because no direction toward the light exists there.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, fields
from functools import cache
from typing import NamedTuple

import numpy as np

from .._text import quote
from .._validate import (
    check_choice,
    check_color,
    check_finite,
    check_float_dtype,
    check_nonnegative,
    check_range,
    check_vectors,
    real_array,
)
from ..numerics import as_float, cos_sin_deg, saturate_to, working_dtype
from ..vec import _one_minus_cos_between, direction_from_elevation, normalize

__all__ = [
    "Incidence",
    "Light",
    "AmbientLight",
    "DirectionalLight",
    "PointLight",
    "SpotLight",
    "ATTENUATIONS",
    "falloff",
    "attenuation_polynomial",
    "check_attenuation",
    "check_cutoff",
]


class Incidence(NamedTuple):
    """Light arriving at surface points from one direction (see module docs).

    The irradiance is kept factored as ``scale × radiant``: a scalar field
    (falloff, spot factor, emitter cosine) times the light's RGB colour, so a
    shading pass can apply colours once per light rather than once per pixel.
    """

    direction: np.ndarray
    scale: np.ndarray
    radiant: np.ndarray

    @property
    def irradiance(self) -> np.ndarray:
        """``scale × radiant``: RGB irradiance on a surface facing the light, ``(..., 3)`` or ``(3,)``."""
        with np.errstate(over="ignore"):
            # Both factors are finite and >= 0, so the product is finite or +inf (never NaN): clamp it.
            e = np.asarray(self.scale)[..., None] * self.radiant
        return np.minimum(e, np.finfo(e.dtype).max)


def _vector3(name: str, value, *, nonzero: bool = False) -> np.ndarray:
    arr = check_vectors(name, value, dtype=np.float64, nonzero=nonzero)
    if arr.shape != (3,):
        raise ValueError(f"{name} must be one finite 3-vector; got shape {arr.shape}: {quote(value)}")
    return arr


def check_attenuation(value) -> tuple[float, float, float]:
    """Validate ``(a, b, c)`` of the falloff ``1 / (a r² + b r + c)``.

    Parameters
    ----------
    value : sequence of 3 numbers
        Each finite and >= 0, not all zero.

    Returns
    -------
    tuple of float
        ``(a, b, c)``.
    """
    allowed = "three finite numbers (a, b, c) >= 0, not all zero, for 1/(a r² + b r + c)"
    arr = check_finite("attenuation", value, shape_hint=allowed)
    if arr.shape != (3,) or np.any(arr < 0) or not np.any(arr > 0):
        raise ValueError(f"attenuation must be {allowed}; got {quote(value)}")
    return tuple(float(x) for x in arr)


def check_cutoff(value, name: str = "cutoff_deg") -> float:
    """A spot cutoff in degrees: within [0, 90], or exactly 180 (no spot), as in OpenGL.

    Parameters
    ----------
    value : float
        The cutoff in degrees.
    name : str
        The argument's name in error messages.

    Returns
    -------
    float
    """
    c = check_range(name, value)
    if not (0 <= c <= 90 or c == 180):
        raise ValueError(f"{name} must be in [0, 90] degrees or exactly 180 (no cone); got {quote(value)}")
    return c


def _one_minus_cos_deg(deg: float) -> float:
    """``1 − cos(deg°)`` without cancellation: ``2 sin²(deg°/2)`` while ``cos > 1/2``, ``1 − cos`` beyond.

    Both branches take their sine and cosine from :func:`lighting.numerics.cos_sin_deg`, exact at
    multiples of 90° (so 0 at 0° and exactly 1 at 90°); ``1 − cos`` is exact for ``cos <= 1/2``
    (Sterbenz), ``2 sin²`` keeps the digits of a tiny cutoff (1e-8°) that ``1 − cos`` would lose.
    """
    c = float(cos_sin_deg(deg)[0])
    if c <= 0.5:
        return 1.0 - c
    return 2.0 * float(cos_sin_deg(deg / 2)[1]) ** 2


def _cos_deg(deg: float) -> float:
    """``cos(deg°)`` as a float, from :func:`lighting.numerics.cos_sin_deg` (exact at multiples of 90°)."""
    return float(cos_sin_deg(deg)[0])


def _radiant(color: np.ndarray, intensity: float) -> np.ndarray:
    """``intensity × color`` in float64, saturated at its largest finite value (1e300 × 1e300 is not inf)."""
    with np.errstate(over="ignore"):
        return np.minimum(color * intensity, np.finfo(np.float64).max)


_BIG64 = float(np.finfo(np.float64).max)

def _real_array_nonneg(name: str, value) -> np.ndarray:
    """Finite real numbers >= 0 as a float64 array."""
    arr = real_array(name, value, allowed="finite real numbers >= 0", dtype=np.float64)
    if np.any(arr < 0):
        raise ValueError(f"{name} must be finite real numbers >= 0; got {quote(value)}")
    return arr


def _real_array_any(name: str, value, dtype=None) -> np.ndarray:
    """Finite real numbers as an array (float64 unless a NumPy float dtype is given)."""
    return real_array(name, value, dtype=dtype)


#: Fields a light's repr always shows (where it is and how strong); the others only when not at their default.
_ALWAYS_SHOWN = ("position", "center", "direction", "normal_dir", "edge_u", "edge_v", "radius", "cutoff_deg")


@cache
def _default_light(cls):
    return cls()


def _repr_value(name: str, value) -> str:
    if isinstance(value, (bool, np.bool_)) or value is None:
        return repr(value if value is None else bool(value))
    if isinstance(value, (int, float, np.integer, np.floating)):
        return f"{float(value):.6g}"
    a = np.asarray(value, dtype=np.float64).reshape(-1)
    if name == "color" and a.size and np.all(a == a[0]):
        return f"{a[0]:.6g}"  # a grey light: one number, as the constructor takes it
    return "(" + ", ".join(f"{x:.6g}" for x in a) + ")"


def light_repr(light) -> str:
    """One short line for a light: ``PointLight(position=(2, 2, 3), intensity=20)``.

    Where the light is (position, direction, extent, spot cutoff) first, then its intensity and every
    other field that differs from its default, in the constructor's order; numbers to 6 significant
    digits, a grey colour as one number.

    Parameters
    ----------
    light : AmbientLight or Light
        A light dataclass.

    Returns
    -------
    str
    """
    cls = type(light)
    default = _default_light(cls)
    names = [f.name for f in fields(cls)]
    shown = [n for n in names if n in _ALWAYS_SHOWN]  # where the light is, first
    for n in names:
        if n in shown:
            continue
        v, d = getattr(light, n), getattr(default, n)
        same = v == d if v is None or d is None or isinstance(v, (bool, int)) else np.array_equal(v, d)
        if n == "intensity" or not same:
            shown.append(n)
    text = ", ".join(f"{n}={_repr_value(n, getattr(light, n))}" for n in shown)
    return f"{cls.__name__}({text})"


class Light:
    """Base class of lights that arrive from directions (everything but ambient)."""

    color: np.ndarray
    intensity: float

    @property
    def radiant(self) -> np.ndarray:
        """``intensity × color`` (float64 RGB, saturated at the largest finite float64)."""
        return _radiant(self.color, self.intensity)

    @property
    def is_black(self) -> bool:
        """True when this light contributes nothing anywhere (zero colour or intensity)."""
        return not np.any(self.radiant > 0)

    def incident(self, points, *, dtype=None, extra_distance=None) -> Iterator[Incidence]:
        """Yield the :class:`Incidence` records of this light at ``points`` ``(..., 3)``.

        Parameters
        ----------
        points : array_like, (..., 3)
            Finite surface positions; their float dtype is kept.
        dtype : {numpy.float32, numpy.float64}, optional
            Working dtype of the records (default: that of ``points``).
        extra_distance : array_like, optional
            Non-negative distance added to the light's distance in the falloff
            (the slides' "distance to the light plus distance to the viewer").

        Returns
        -------
        iterator of Incidence
            One record for a directional, point or spot light, one per sample for an area light.
        """
        points = check_vectors("points", points)
        dt = check_float_dtype(dtype).type if dtype is not None else working_dtype(points)
        if extra_distance is not None:
            extra_distance = _real_array_nonneg("extra_distance", extra_distance)
        return self._incident(points, dtype=dt, extra_distance=extra_distance)

    def _incident(self, points, *, dtype, extra_distance=None) -> Iterator[Incidence]:
        """:meth:`incident` on checked inputs (the shading loop's path: no per-call validation)."""
        raise NotImplementedError

    def __repr__(self) -> str:
        return light_repr(self)


@dataclass(frozen=True, repr=False)
class AmbientLight:
    """Ambient light: the slides' ``I_a``, the same everywhere and from everywhere.

    A stand-in for light bounced off other objects.  Its term is ``I_a k_a``:
    light, surface angle and viewer positions do not matter.  Physically it is
    a uniform irradiance ``I_a`` over the hemisphere (a constant sky of radiance
    ``I_a / π``), so a Lambertian surface of albedo ``k_a`` returns ``k_a I_a / π``.
    """

    color: object = 1.0
    intensity: float = 0.2

    def __post_init__(self):
        object.__setattr__(self, "color", check_color("color", self.color))
        object.__setattr__(self, "intensity", check_nonnegative("intensity", self.intensity))

    @property
    def radiant(self) -> np.ndarray:
        """``intensity × color`` (float64 RGB, saturated at the largest finite float64)."""
        return _radiant(self.color, self.intensity)

    @property
    def is_black(self) -> bool:
        return not np.any(self.radiant > 0)

    def __repr__(self) -> str:
        return light_repr(self)


@dataclass(frozen=True, repr=False)
class DirectionalLight(Light):
    """Parallel light from infinitely far away (OpenGL's position ``(x, y, z, 0)``).

    Every point sees the same ``l`` and the same irradiance ``intensity × color``:
    surface angle matters, light and viewer position do not.

    Parameters
    ----------
    direction : 3-vector
        Direction **toward** the light (normalized on construction).
    color : scalar or RGB, >= 0
    intensity : float >= 0

    Examples
    --------
    >>> light = DirectionalLight((0, 0, 2.0))
    >>> inc = next(light.incident(np.zeros((1, 3))))
    >>> inc.direction.tolist(), inc.irradiance.tolist()
    ([0.0, 0.0, 1.0], [1.0, 1.0, 1.0])
    """

    direction: object = (0.0, 0.0, 1.0)
    color: object = 1.0
    intensity: float = 1.0

    def __post_init__(self):
        d = _vector3("direction", self.direction, nonzero=True)
        object.__setattr__(self, "direction", normalize(d))
        object.__setattr__(self, "color", check_color("color", self.color))
        object.__setattr__(self, "intensity", check_nonnegative("intensity", self.intensity))

    @classmethod
    def from_angles(cls, elevation_deg: float, azimuth_deg: float = 0.0, **kwargs) -> DirectionalLight:
        """Light at ``elevation_deg`` above the xy-plane and ``azimuth_deg`` from +x toward +y...

        ...with +z as "up"; the slides' "Lambertian sphere from several lighting
        angles" is a sweep of ``elevation_deg`` from 90 (overhead) to 0.

        Parameters
        ----------
        elevation_deg, azimuth_deg : float
            Degrees; exact at multiples of 90°.
        **kwargs
            ``color``, ``intensity``.

        Returns
        -------
        DirectionalLight
        """
        el = check_range("elevation_deg", elevation_deg)
        az = check_range("azimuth_deg", azimuth_deg)
        # Exact at multiples of 90°: an elevation of 0 is on the horizon, not cos(π/2) = 6e-17 above it.
        return cls(direction=direction_from_elevation(el, az), **kwargs)

    def _incident(self, points, *, dtype, extra_distance=None):
        yield Incidence(self.direction.astype(dtype), np.ones((), dtype=dtype), saturate_to(self.radiant, dtype))


#: Named falloff triples ``(a, b, c)`` of ``1 / (a d² + b d + c)`` (what the explorer's menu offers).
ATTENUATIONS = {"none": (0.0, 0.0, 1.0), "linear": (0.0, 1.0, 0.0), "inverse-square": (1.0, 0.0, 0.0)}


def falloff(distance, attenuation=(1.0, 0.0, 0.0)) -> np.ndarray:
    r"""The slides' distance falloff ``1 / A(d) = 1 / (a d² + b d + c)``.

    The one home of the attenuation formula of the point and spot lights (the OpenGL mode,
    :mod:`lighting.shading.opengl`, keeps its own transcription of the specification on purpose).

    Parameters
    ----------
    distance : array_like
        Finite distances ``d >= 0``.
    attenuation : (a, b, c) or str
        Coefficients, each >= 0 and not all zero, in the order of ``a d² + b d + c``; or a name
        of :data:`ATTENUATIONS` (``"none"``, ``"linear"``, ``"inverse-square"``).

    Returns
    -------
    numpy.ndarray
        ``1 / (a d² + b d + c)`` in float64, 0 where the denominator is 0, saturated at the
        largest finite float64.

    Examples
    --------
    >>> falloff([1.0, 2.0]).tolist(), falloff(3.0, "none").tolist()
    ([1.0, 0.25], 1.0)
    """
    if isinstance(attenuation, str):
        attenuation = ATTENUATIONS[check_choice("attenuation", attenuation, tuple(ATTENUATIONS))]
    return _falloff(_real_array_nonneg("distance", distance), check_attenuation(attenuation))


def attenuation_polynomial(distance, attenuation):
    """The slides' attenuation ``A(d) = a d² + b d + c``, evaluated as ``(a d + b) d + c``.

    The one place the polynomial is written: :func:`falloff` is its reciprocal, and front ends
    that scale a light's intensity by ``A`` at some distance call it too.

    Parameters
    ----------
    distance : float or ndarray
        Distances ``d >= 0``, finite.
    attenuation : (a, b, c)
        Checked coefficients (see :func:`check_attenuation`).

    Returns
    -------
    float or ndarray
        ``A(d)``, finite or ``+inf`` (it overflows without a warning).
    """
    a, b, c = attenuation
    with np.errstate(over="ignore"):
        return (a * distance + b) * distance + c  # a, b, c >= 0 and d finite: finite or +inf


def _falloff(dist: np.ndarray, att: tuple[float, float, float]) -> np.ndarray:
    """:func:`falloff` on checked float64 distances and a checked triple (the lights' path).

    Saturated *here*, before any other factor multiplies it: a falloff of 1e310 (``a = 1e-300`` at
    ``d = 1e-5``) times a spot factor of 0 must be 0, not ``inf · 0 = NaN``.
    """
    den = attenuation_polynomial(dist, att)
    with np.errstate(divide="ignore", over="ignore"):
        f = np.where(den > 0, 1.0 / np.where(den > 0, den, 1.0), 0.0)
    return np.minimum(f, _BIG64)


def _directions_and_distances(position: np.ndarray, points: np.ndarray):
    """Unit vectors from ``points`` toward ``position`` and the distances, in float64 (finite, saturated).

    The direct ``sqrt(Σ d²)`` is used where ``Σ d²`` is safely inside the float64 range; elsewhere (a
    light 1e300 away, or 1e-200) the difference is scaled by its largest component first, and where even
    the difference of two finite positions overflows (1e308 − (−1e308)) it is formed from halves.  A
    distance beyond the float64 range saturates at its largest value.
    """
    p = points.astype(np.float64)
    with np.errstate(over="ignore", invalid="ignore"):
        d = position - p
        len2 = d[..., 0] ** 2 + d[..., 1] ** 2 + d[..., 2] ** 2
    fast = (len2 > 1e-290) & (len2 < 1e290)
    if np.all(fast):
        dist = np.sqrt(len2)
        return d / dist[..., None], dist
    dist = np.sqrt(np.where(fast, len2, 1.0))  # > 1e-145: the division cannot warn
    l = np.where(fast[..., None], d / dist[..., None], 0.0)  # noqa: E741
    slow = ~fast
    ds = d[slow]
    twice = ~np.all(np.isfinite(ds), axis=-1)
    if np.any(twice):  # the difference itself overflowed: form it from halves (exact for normal numbers)
        ds[twice] = 0.5 * position - 0.5 * p[slow][twice]
    m = np.max(np.abs(ds), axis=-1)
    s = np.where(m[..., None] > 0, ds / np.where(m > 0, m, 1.0)[..., None], 0.0)  # finite ds over its max |ds|
    len_s = np.sqrt(s[..., 0] ** 2 + s[..., 1] ** 2 + s[..., 2] ** 2)  # in [1, √3] where m > 0
    l[slow] = np.where(len_s[..., None] > 0, s / np.where(len_s > 0, len_s, 1.0)[..., None], 0.0)
    with np.errstate(over="ignore"):  # 2 m √3 overflows for distances near the largest float: saturated
        dist[slow] = np.minimum(np.where(twice, 2.0, 1.0) * m * len_s, _BIG64)
    return l, dist


@dataclass(frozen=True, repr=False)
class PointLight(Light):
    r"""Light from a point, falling off with distance.

        irradiance at distance r:  I_0 / (a r² + b r + c),   I_0 = intensity × color

    The default ``attenuation = (1, 0, 0)`` is the physical inverse-square law;
    other triples are the slides' (and OpenGL's) "non-quadratic falloff",
    e.g. ``(0, 0, 1)`` for no falloff at all.

    Parameters
    ----------
    position : 3-vector
    color : scalar or RGB, >= 0
    intensity : float >= 0
    attenuation : (a, b, c), each >= 0, not all zero

    Examples
    --------
    >>> light = PointLight((0, 0, 2.0), attenuation=(1, 0, 0))
    >>> next(light.incident(np.zeros((1, 3)))).irradiance.tolist()
    [[0.25, 0.25, 0.25]]
    """

    position: object = (0.0, 0.0, 5.0)
    color: object = 1.0
    intensity: float = 1.0
    attenuation: tuple = (1.0, 0.0, 0.0)

    def __post_init__(self):
        object.__setattr__(self, "position", _vector3("position", self.position))
        object.__setattr__(self, "color", check_color("color", self.color))
        object.__setattr__(self, "intensity", check_nonnegative("intensity", self.intensity))
        object.__setattr__(self, "attenuation", check_attenuation(self.attenuation))

    def _spot(self, l: np.ndarray) -> np.ndarray | None:  # noqa: E741
        return None

    def _incident(self, points, *, dtype, extra_distance=None):
        dt = dtype
        p = as_float(points, dt)
        l, dist = _directions_and_distances(self.position, p)  # noqa: E741
        if extra_distance is None:
            att_dist = dist
        else:
            with np.errstate(over="ignore"):
                att_dist = np.minimum(dist + np.asarray(extra_distance, np.float64), _BIG64)
        scale = _falloff(att_dist, self.attenuation)  # finite: at most the largest float64
        scale = np.where(dist > 0, scale, 0.0)
        spot = self._spot(l)
        if spot is not None:
            scale = scale * spot  # a factor in [0, 1] times a finite number: a zero spot factor wins
        yield Incidence(l.astype(dt), saturate_to(scale, dt), saturate_to(self.radiant, dt))


@dataclass(frozen=True, kw_only=True, repr=False)
class SpotLight(PointLight):
    r"""A point light restricted to a cone (OpenGL semantics).

        spot factor = max(−l·ŝ, 0)^exponent   if −l·ŝ >= cos(cutoff),  else 0

    ``ŝ`` is the spot ``direction`` (where the light points), ``−l`` the
    direction from the light to the surface point.  ``cutoff_deg = 180`` means
    no cone (a plain point light); otherwise it must lie in [0, 90].  With
    ``cutoff_deg = 0`` only points exactly on the axis are lit.

    Parameters
    ----------
    position, color, intensity, attenuation : as PointLight
    direction : 3-vector, nonzero
    cutoff_deg : float in [0, 90] or 180
    exponent : float >= 0
        Concentration of light toward the axis (``0^0 = 1``).

    Examples
    --------
    >>> s = SpotLight(position=(0, 0, 1.0), direction=(0, 0, -1.0), cutoff_deg=30, attenuation=(0, 0, 1))
    >>> next(s.incident(np.array([[0, 0, 0.0], [1, 0, 0.0]]))).irradiance[:, 0].tolist()
    [1.0, 0.0]
    """

    direction: object = (0.0, 0.0, -1.0)
    cutoff_deg: float = 30.0
    exponent: float = 0.0

    def __post_init__(self):
        super().__post_init__()
        object.__setattr__(self, "direction", normalize(_vector3("direction", self.direction, nonzero=True)))
        object.__setattr__(self, "cutoff_deg", check_cutoff(self.cutoff_deg))
        object.__setattr__(self, "exponent", check_nonnegative("exponent", self.exponent))

    def spot_factor(self, cos_angle, one_minus_cos=None) -> np.ndarray:
        r"""The slides' spot factor: ``(−l·ŝ)^e`` inside the cone, 0 outside.

            spot = max(−l·ŝ, 0)^e   if −l·ŝ >= cos(cutoff),   else 0      (0^0 = 1)

        The one home of the formula; the lights call it with both ``cos ψ = −l·ŝ`` and
        ``1 − cos ψ = |l + ŝ|²/2``, which keeps its digits near the axis where ``cos ψ`` rounds
        to 1: the cone test is then ``1 − cos ψ <= 1 − cos(cutoff) = 2 sin²(cutoff/2)`` (it
        resolves a cutoff of 1e-8 degrees), and the power is ``exp(e log1p(−(1 − cos ψ)))``
        while ``1 − cos ψ < 1/2`` (accurate for ``e = 1e4``), ``cos ψ^e`` beyond.  Given only
        ``cos_angle``, the cone test compares it with ``cos(cutoff)`` (exact at 0° and 90°) and
        ``1 − cos ψ`` is formed from it.

        Parameters
        ----------
        cos_angle : array_like
            ``cos ψ = −l·ŝ``, the cosine between the spot axis ``ŝ`` and the light→point direction.
        one_minus_cos : array_like, optional
            ``1 − cos ψ`` computed without cancellation (e.g. ``|l + ŝ|²/2``), >= 0.

        Returns
        -------
        numpy.ndarray
            The spot factor in [0, 1], float64, shaped like ``cos_angle``.

        Examples
        --------
        >>> SpotLight(cutoff_deg=60, exponent=2).spot_factor([1.0, 0.75, 0.25]).tolist()
        [1.0, 0.5625, 0.0]
        """
        c = _real_array_any("cos_angle", cos_angle, dtype=np.float64)
        om = None if one_minus_cos is None else _real_array_nonneg("one_minus_cos", one_minus_cos)
        return self._spot_factor(c, om)

    def _spot_factor(self, cos_a: np.ndarray, one_minus: np.ndarray | None) -> np.ndarray:
        """:meth:`spot_factor` on checked float64 arrays."""
        if self.cutoff_deg == 180:
            return np.ones_like(cos_a)
        if one_minus is None:
            inside = cos_a >= _cos_deg(self.cutoff_deg)
            one_minus = np.maximum(1.0 - cos_a, 0.0)  # cos_a finite: 1 − cos_a rounds, never overflows
        else:
            inside = one_minus <= _one_minus_cos_deg(self.cutoff_deg)
        if self.exponent == 0:
            p = np.ones_like(cos_a)
        else:
            with np.errstate(divide="ignore", over="ignore", under="ignore", invalid="ignore"):
                near = np.exp(self.exponent * np.log1p(-np.minimum(one_minus, 0.5)))
                far = np.power(np.maximum(cos_a, 0.0), self.exponent)
            p = np.where(one_minus < 0.5, near, far)
        return np.where(inside, p, 0.0)

    def _spot(self, l):  # noqa: E741
        """The spot factor at unit light vectors ``l`` (float64 ``(..., 3)``): :meth:`spot_factor`'s careful form."""
        if self.cutoff_deg == 180:
            return np.ones(l.shape[:-1])
        s = self.direction
        cos_a = -(l[..., 0] * s[0] + l[..., 1] * s[1] + l[..., 2] * s[2])
        # 1 − cos ψ between l and −ŝ, |l + ŝ|²/2 (l − (−ŝ) is l + ŝ exactly; the clip to [0, 2] only touches
        # values far outside any cone).
        one_minus = _one_minus_cos_between(l, -s)
        return self._spot_factor(cos_a, one_minus)




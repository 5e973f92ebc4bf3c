r"""Procedural skies: environments given by a formula, by name.

:data:`SKIES` maps a name to a :class:`Sky` (a one-line description, its parameters and their
defaults, and a factory making the radiance function), and :func:`sky` turns a name into a
:class:`~lighting.lights.environment.FunctionEnvironment`:

    >>> env = sky("daylight")
    >>> env.radiance((0.0, 0.0, 1.0)).round(3).tolist()   # the zenith: deep blue
    [0.197, 0.363, 0.858]

Every sky's radiance is a function of the direction alone, in the world frame of
:mod:`lighting.lights.environment` (``+z`` up, ``φ`` from ``+x`` toward ``+y``), linear RGB, finite
and ``>= 0`` everywhere, returned in the float dtype of the directions given (float32 in, float32
out; computed in float64).

=================  ==========================================================================
``uniform``        radiance 1 from everywhere: the white furnace (``L_o`` = albedo)
``daylight``       blue zenith, bright horizon, brown ground and a sun glow
``glow``           a uniform floor plus a broad glow around a sun (the accuracy report's sky)
``sunset``         a low warm sun, dark blue zenith, orange horizon, dark ground
``studio``         dark grey with two soft rectangular area lights (key and fill)
``band-limited``   a sum of real spherical harmonics of bands ``l <= 2``: SH9 is exact for it
=================  ==========================================================================
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .._text import quote
from .._validate import ArgumentTypeError, check_nonnegative, check_range, check_vectors
from ..numerics import working_dtype
from ..vec import direction_from_elevation
from .environment import FunctionEnvironment

__all__ = ["Sky", "SKIES", "sky", "sky_names"]


def _unit(name: str, v) -> np.ndarray:
    """A nonzero 3-vector as a float64 unit vector, or a ValueError naming ``name``."""
    c = check_vectors(name, v, dtype=np.float64, nonzero=True)
    if c.shape != (3,):
        raise ValueError(f"{name} must be a finite nonzero 3-vector; got shape {c.shape}")
    return c / np.linalg.norm(c)


def _as_dirs(d):
    """Directions as float64 and the dtype to return (the caller's float dtype, float64 otherwise)."""
    dt = working_dtype(d)
    return np.asarray(d, dtype=np.float64), dt


# --------------------------------------------------------------------------- the skies
def _uniform(value: float = 1.0):
    v = check_nonnegative("value", value)

    def radiance(d):
        d, dt = _as_dirs(d)
        return np.full(d.shape[:-1] + (3,), v, dtype=dt)

    return radiance


def _daylight(sun=(-0.45112924, -0.70175659, 0.55138018)):
    # The rendering-equation figure's sky (explorer.figures.rendering): its pixels depend on this
    # formula bit for bit, so the order of operations is kept.
    s = _unit("sun", sun)

    def radiance(d):
        d, dt = _as_dirs(d)
        z = d[..., 2]
        up = np.clip(z, 0.0, 1.0)[..., None]
        zenith = np.array([0.18, 0.35, 0.85])
        horizon = np.array([0.85, 0.85, 0.8])
        ground = np.array([0.2, 0.15, 0.1])
        sky_ = horizon + (zenith - horizon) * np.sqrt(up)
        t = np.clip(0.5 + 4.0 * z, 0.0, 1.0)[..., None]  # a soft horizon, about 15° wide
        base = ground + (sky_ - ground) * t
        c = np.clip(d @ s, 0.0, 1.0)[..., None]
        glow = np.array([3.0, 2.6, 2.0]) * c**64 + np.array([0.6, 0.45, 0.3]) * c**6
        return (base + glow).astype(dt, copy=False)

    return radiance


def _glow(sun=(0.5, 0.3, 0.81)):
    # The accuracy report's integration sky (lighting.validation.accuracy): smooth, so quadrature
    # converges fast and the Monte-Carlo estimators' errors are what the report measures.
    s = _unit("sun", sun)

    def radiance(d):
        d, dt = _as_dirs(d)
        c = np.clip(d @ s, 0.0, None)
        base = np.array([0.25, 0.3, 0.4])
        return (base + np.multiply.outer(c**8, np.array([2.0, 1.8, 1.5]))).astype(dt, copy=False)

    return radiance


def _sunset(sun_elevation_deg: float = 4.0, sun_azimuth_deg: float = 180.0):
    elevation = check_range("sun_elevation_deg", sun_elevation_deg, -90.0, 90.0)
    azimuth = check_range("sun_azimuth_deg", sun_azimuth_deg)
    s = np.asarray(direction_from_elevation(elevation, azimuth), dtype=np.float64)
    s_flat = np.array([s[0], s[1], 0.0])
    s_flat = s_flat / np.linalg.norm(s_flat) if np.any(s_flat) else np.array([1.0, 0.0, 0.0])
    zenith = np.array([0.02, 0.04, 0.16])
    horizon_warm = np.array([1.6, 0.7, 0.25])
    horizon_cool = np.array([0.35, 0.3, 0.4])
    ground = np.array([0.05, 0.04, 0.04])

    def radiance(d):
        d, dt = _as_dirs(d)
        z = d[..., 2]
        up = np.clip(z, 0.0, 1.0)[..., None]
        # Horizon colour: warm toward the sun's azimuth, cooler behind.
        toward = (0.5 + 0.5 * np.clip(d @ s_flat, -1.0, 1.0))[..., None] ** 2
        horizon = horizon_cool + (horizon_warm - horizon_cool) * toward
        sky_ = horizon + (zenith - horizon) * up ** (1.0 / 3.0)
        t = np.clip(0.5 + 8.0 * z, 0.0, 1.0)[..., None]  # a sharp horizon, about 7° wide
        base = ground + (sky_ - ground) * t
        c = np.clip(d @ s, 0.0, 1.0)[..., None]
        sun_ = np.array([40.0, 22.0, 8.0]) * c**2000 + np.array([1.2, 0.5, 0.15]) * c**16
        return (base + sun_).astype(dt, copy=False)

    return radiance


def _softbox(centre, width_deg, height_deg, radiance_rgb):
    """A soft rectangle of angular size ``width × height`` facing ``centre`` (a super-ellipse of order 8)."""
    c = _unit("centre", centre)
    # Horizontal edge along the horizon, vertical edge toward +z: a studio light's natural frame.
    t = np.cross([0.0, 0.0, 1.0], c)
    t = t / np.linalg.norm(t) if np.linalg.norm(t) > 1e-12 else np.array([1.0, 0.0, 0.0])
    b = np.cross(c, t)
    a_w = math.tan(math.radians(width_deg) / 2)
    a_h = math.tan(math.radians(height_deg) / 2)
    rgb = np.asarray(radiance_rgb, dtype=np.float64)

    def box(d):
        cz = d @ c
        front = cz > 1e-6
        safe = np.where(front, cz, 1.0)
        # Gnomonic coordinates: straight edges of a flat panel stay straight.
        u = np.abs(d @ t) / safe / a_w
        v = np.abs(d @ b) / safe / a_h
        r = np.minimum(u, 4.0) ** 8 + np.minimum(v, 4.0) ** 8  # at most 2 · 4⁸
        edge = np.clip((1.0 - r) / 0.6 + 0.5, 0.0, 1.0)
        soft = edge * edge * (3.0 - 2.0 * edge)  # smoothstep: no hard edge to alias
        return np.where(front, soft, 0.0)[..., None] * rgb

    return box


def _studio(background: float = 0.03):
    bg = check_nonnegative("background", background)
    key = _softbox((0.55, -0.55, 0.63), 40.0, 28.0, (12.0, 11.5, 10.5))
    fill = _softbox((-0.75, 0.45, 0.48), 30.0, 50.0, (3.0, 3.3, 3.8))

    def radiance(d):
        d, dt = _as_dirs(d)
        z = d[..., 2]
        # A floor a little lighter than the walls, so the ground reflection reads.
        floor = np.clip(-4.0 * z, 0.0, 1.0)[..., None] * 0.5 * bg
        return (bg + floor + key(d) + fill(d)).astype(dt, copy=False)

    return radiance


#: Per channel ``(a, b, c, e, f)`` of ``a + b·(x, y, z)-linear part + c·P2(z) + quadratic part`` (see
#: :func:`_band_limited`): the smallest value of each channel over the sphere is above 0.2.
_BAND_LIMITED = (
    # constant, (x, y, z) linear, P2(z) = (3z² − 1)/2, xy, xz
    (1.0, (0.3, 0.0, 0.5), 0.2, 0.0, 0.0),
    (0.8, (0.0, -0.2, 0.3), 0.15, 0.1, 0.0),
    (0.9, (0.1, 0.0, 0.6), 0.0, 0.0, 0.1),
)


def _band_limited(scale: float = 1.0):
    k = check_nonnegative("scale", scale)
    const = np.array([c[0] for c in _BAND_LIMITED])
    lin = np.array([c[1] for c in _BAND_LIMITED])  # (3 channels, xyz)
    p2 = np.array([c[2] for c in _BAND_LIMITED])
    xy = np.array([c[3] for c in _BAND_LIMITED])
    xz = np.array([c[4] for c in _BAND_LIMITED])

    def radiance(d):
        d, dt = _as_dirs(d)
        x, y, z = d[..., 0:1], d[..., 1:2], d[..., 2:3]
        out = const + d @ lin.T + p2 * (1.5 * z * z - 0.5) + xy * (x * y) + xz * (x * z)
        return (k * out).astype(dt, copy=False)

    return radiance


def band_limited_irradiance(normals, scale: float = 1.0) -> np.ndarray:
    r"""Exact irradiance of the ``"band-limited"`` sky on a surface of unit normal ``n``.

    By the Funk–Hecke theorem a harmonic of band ``l`` is multiplied by the clamped cosine's
    ``Â_l`` (``π``, ``2π/3``, ``π/4`` for ``l = 0, 1, 2``; Ramamoorthi & Hanrahan 2001), so

        E(n) = π a + (2π/3) b·n + (π/4) (c P2(n_z) + e n_x n_y + f n_x n_z).

    Parameters
    ----------
    normals : array_like, (..., 3)
        Unit normals (float64 is used).
    scale : float
        The sky's ``scale`` parameter.

    Returns
    -------
    ndarray, (..., 3)
        Irradiance per RGB channel, float64.

    Examples
    --------
    >>> band_limited_irradiance((0.0, 0.0, 1.0)).round(6).tolist()
    [4.34587, 3.259402, 4.08407]
    """
    n = np.asarray(normals, dtype=np.float64)
    const = np.array([c[0] for c in _BAND_LIMITED])
    lin = np.array([c[1] for c in _BAND_LIMITED])
    p2 = np.array([c[2] for c in _BAND_LIMITED])
    xy = np.array([c[3] for c in _BAND_LIMITED])
    xz = np.array([c[4] for c in _BAND_LIMITED])
    x, y, z = n[..., 0:1], n[..., 1:2], n[..., 2:3]
    quad = p2 * (1.5 * z * z - 0.5) + xy * (x * y) + xz * (x * z)
    return float(scale) * (math.pi * const + (2 * math.pi / 3) * (n @ lin.T) + (math.pi / 4) * quad)


# --------------------------------------------------------------------------- registry
@dataclass(frozen=True)
class Sky:
    """One named procedural sky.

    Attributes
    ----------
    name : str
        The registry key.
    description : str
        One line, for menus and ``--help``.
    make : callable
        ``make(**params)`` returns the radiance function ``directions (..., 3) -> RGB (..., 3)``.
    params : dict
        The parameters ``make`` takes and their defaults.
    """

    name: str
    description: str
    make: Callable[..., Callable[[np.ndarray], np.ndarray]] = field(repr=False)
    params: dict = field(default_factory=dict)

    @property
    def function(self) -> Callable[[np.ndarray], np.ndarray]:
        """The radiance function with the default parameters (what :class:`FunctionEnvironment` takes)."""
        return self.make()

    def __call__(self, directions) -> np.ndarray:
        """Radiance of the sky with its default parameters at ``directions`` ``(..., 3)`` (unit, world frame)."""
        return self.function(directions)


#: The procedural skies by name.
SKIES: dict[str, Sky] = {
    s.name: s
    for s in (
        Sky("uniform", "radiance 1 from every direction: the white furnace", _uniform, {"value": 1.0}),
        Sky(
            "daylight",
            "blue zenith, bright horizon, brown ground and a sun glow",
            _daylight,
            {"sun": (-0.45112924, -0.70175659, 0.55138018)},
        ),
        Sky("glow", "a uniform floor plus a broad glow around a sun", _glow, {"sun": (0.5, 0.3, 0.81)}),
        Sky(
            "sunset",
            "a low warm sun, dark blue zenith, orange horizon, dark ground",
            _sunset,
            {"sun_elevation_deg": 4.0, "sun_azimuth_deg": 180.0},
        ),
        Sky("studio", "dark grey with two soft rectangular area lights", _studio, {"background": 0.03}),
        Sky(
            "band-limited",
            "spherical harmonics of bands l <= 2 only, positive: SH9 is exact for it",
            _band_limited,
            {"scale": 1.0},
        ),
    )
}


def sky_names() -> tuple[str, ...]:
    """The names of :data:`SKIES`, in registry order.

    Returns
    -------
    tuple of str
    """
    return tuple(SKIES)


def _lookup(name) -> Sky:
    if not isinstance(name, str):
        raise ArgumentTypeError(f"sky name must be one of {', '.join(SKIES)}; got {type(name).__name__} {quote(name)}")
    key = name.strip().lower().replace("_", "-")
    if key in SKIES:
        return SKIES[key]
    near = difflib.get_close_matches(key, list(SKIES), n=1, cutoff=0.5)
    hint = f" (did you mean {near[0]!r}?)" if near else ""
    raise ValueError(f"unknown sky {quote(name)}{hint}; allowed: {', '.join(SKIES)}")


def sky(name: str, **params) -> FunctionEnvironment:
    """The procedural sky ``name`` as an environment.

    Parameters
    ----------
    name : str
        A key of :data:`SKIES` (case and ``_``/``-`` do not matter); a near miss is named in the error.
    **params
        The sky's parameters (:attr:`Sky.params` lists them with their defaults).

    Returns
    -------
    FunctionEnvironment
        Radiance from the sky's formula; tabulate it with
        :meth:`~lighting.lights.environment.LatLongEnvironment.from_function` for fast lookups.

    Raises
    ------
    ValueError
        An unknown name or parameter, or a parameter out of range (naming it and what is allowed).

    Examples
    --------
    >>> sky("uniform").radiance((0.3, 0.4, -0.5)).tolist()
    [1.0, 1.0, 1.0]
    >>> try:
    ...     sky("day-light")
    ... except ValueError as e:
    ...     print(str(e).split(";")[0])
    unknown sky 'day-light' (did you mean 'daylight'?)
    """
    s = _lookup(name)
    unknown = sorted(set(params) - set(s.params))
    if unknown:
        allowed = ", ".join(s.params) or "none"
        raise ValueError(f"sky {s.name!r} has no parameter {unknown[0]!r}; allowed: {allowed}")
    func = s.make(**params)
    func.__qualname__ = f"sky({s.name!r})"
    return FunctionEnvironment(func)

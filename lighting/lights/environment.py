r"""Environment lighting: the radiance ``L_i(l)`` arriving from every direction.

The rendering equation (CMSC 435 deck) integrates it against the BRDF:

    L_o(v) = ∫_Ω f_r(v, l) L_i(l) (n·l) dω(l).

An environment is a function of direction alone (light from infinitely far
away), in linear RGB radiance.  Every environment answers
:meth:`Environment.radiance` for directions of shape ``(..., 3)`` (need not be
unit length; world frame) with an ``(..., 3)`` array of the same float dtype,
and can draw directions from a distribution roughly shaped like itself
(:meth:`Environment.sample`, :meth:`Environment.pdf`, densities per unit solid
angle on the whole sphere), which :func:`lighting.integrate.outgoing_radiance` uses for
environment and multiple-importance sampling.  This module is the environment light's one home:
the integrators of :mod:`lighting.integrate` read an environment only through ``_radiance``,
``_sample``, ``_pdf`` (the checked-input forms of the three public methods) and ``support``.

The two cases of the deck's "Results" slide:

* "integrating full environment" — :class:`ConstantEnvironment`,
  :class:`LatLongEnvironment` (an image), :class:`FunctionEnvironment`;
* "light at one point, black elsewhere" — :class:`SmallPatchEnvironment`
  (alias :data:`PointEnvironment`): a cap of solid angle ``Ω`` and radiance
  ``L``; as ``Ω → 0`` it acts as a directional light of irradiance ``E = L Ω``.

World frame of the latitude–longitude image (the engine's spherical
coordinates, the same as the local shading frame and
:meth:`lighting.lights.punctual.DirectionalLight.from_angles`): ``+z`` is "up";
``θ`` is measured from ``+z``, ``φ`` from ``+x`` toward ``+y``.  Row ``i`` of an
``H × W`` image holds ``θ ∈ [iπ/H, (i+1)π/H]`` (row 0 the sky at the zenith,
the last row the ground at the nadir; pixel centres at ``θ = (i + ½)π/H``).
Columns run the other way round from ``φ``: the horizontal image coordinate
``u ∈ [0, 1)`` (``u = (j + ½)/W`` at the centre of column ``j``) looks along

    φ = π − 2π u,        u = (π − φ) / (2π)  (mod 1),

so the centre column looks along ``+x``, a quarter in from the left along ``+y``, and
both edges along ``−x``.  This is the common orientation of panoramas: seen from
inside the sphere with ``+z`` up, the world turns to the right as the columns grow, as
in a photograph, and Blender's equirectangular world texture (``+z`` up) shows the same
world at the same azimuths.  Mitsuba 3's ``envmap`` made ``+z``-up by
``to_world = rotate([1, 0, 0], 90)`` shows the same world turned about ``+z`` by −90°
(it looks along ``φ = π/2 − 2π u``).  :func:`latlong_angles` gives the column angle
``2π u``; :func:`latlong_azimuth` turns it back into ``φ``.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from .._budget import check_budget
from .._text import quote
from .._validate import ArgumentTypeError, check_color, check_count, check_range, check_vectors
from ..numerics import safe_div, working_dtype
from ..sampling.base import _unit_square as _checked_unit_square
from ..sampling.environment import (
    _bilinear_shape,
    _cell_corners,
    _cell_direction,
    _cell_masses,
    _cell_of,
    _cell_solid_angles,
    _corner_values,
    _half_row_scales,
    _pick,
    _pick_in_rows,
    _sample_linear,
    _search_table,
    _tables,
)
from .latlong import _pixel_rows, latlong_angles, latlong_azimuth, latlong_lookup

__all__ = [
    "Environment",
    "ConstantEnvironment",
    "LatLongEnvironment",
    "FunctionEnvironment",
    "SmallPatchEnvironment",
    "PointEnvironment",
    "uniform_sphere",
    "uniform_sphere_pdf",
    "as_environment",
    "latlong_lookup",
    "latlong_angles",
    "latlong_azimuth",
]

_INV_4PI = 1.0 / (4.0 * math.pi)


def _directions(directions) -> tuple[np.ndarray, type]:
    """Unit directions in float64 (zero vectors stay zero) and the caller's dtype.

    Text, complex, NaN or inf, or a shape other than ``(..., 3)`` is refused, naming ``directions``.
    """
    dt = working_dtype(directions)
    d = check_vectors("directions", directions, dtype=np.float64)
    # Not vec.normalize: that one rescales vectors whose squared length under- or overflows, which
    # this lookup has always mapped to zero (and the environments' results with it).
    length = np.sqrt(np.sum(d * d, axis=-1, keepdims=True))
    return safe_div(d, length), dt


#: Peak bytes per direction of an environment lookup or sample (for the estimate made before allocating).
BYTES_PER_DIRECTION = 256


def _unit_square(u) -> np.ndarray:
    """Points of the unit square ``(..., 2)`` (the samplers' check), float64, within the memory budget."""
    arr = _checked_unit_square("u", u)
    check_budget("u", arr.size // 2 * BYTES_PER_DIRECTION, what=f"{arr.size // 2} directions")
    return arr


def uniform_sphere(u) -> tuple[np.ndarray, np.ndarray]:
    """Map points of the unit square ``(..., 2)`` to uniformly distributed directions.

    ``z = 1 − 2u₀``, ``φ = 2π u₁``; the density is ``1/(4π)`` per steradian.

    Parameters
    ----------
    u : array_like, (..., 2)
        Points of the unit square, finite reals in ``[0, 1]``.

    Returns
    -------
    directions : ndarray, (..., 3)
        Unit directions, float64.
    pdf : ndarray, (...)
        Their density per steradian, ``1/(4π)``.

    Examples
    --------
    >>> d, p = uniform_sphere(np.array([0.5, 0.0]))
    >>> d.round(12).tolist(), round(float(p) * 4 * math.pi, 12)
    ([1.0, 0.0, 0.0], 1.0)
    """
    u = _unit_square(u)
    z = 1.0 - 2.0 * u[..., 0]
    r = np.sqrt(np.clip((1.0 - z) * (1.0 + z), 0.0, None))
    phi = 2.0 * math.pi * u[..., 1]
    d = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1)
    return d, np.full(z.shape, _INV_4PI)


def uniform_sphere_pdf(directions) -> np.ndarray:
    """Density ``1/(4π)`` of :func:`uniform_sphere`.

    Parameters
    ----------
    directions : array_like, (..., 3)
        Any finite directions.

    Returns
    -------
    ndarray, (...)
        ``1/(4π)`` per steradian, float64.
    """
    d, _ = _directions(directions)
    return np.full(d.shape[:-1], _INV_4PI)


class Environment:
    """Base class: radiance arriving from each direction (distant lighting).

    Subclasses implement ``_radiance(d)`` on float64 unit directions ``(..., 3)``.
    The default sampling strategy is uniform over the sphere.
    """

    #: A spherical cap outside which the radiance is zero: ``(axis, half_angle)``,
    #: or None when light may come from anywhere.  Deterministic integration uses
    #: it to put its nodes where the light is.
    support: tuple[np.ndarray, float] | None = None

    def radiance(self, directions) -> np.ndarray:
        """Radiance arriving from ``directions``.

        Parameters
        ----------
        directions : array_like, (..., 3)
            World-frame directions (need not be unit length; a zero vector looks nowhere).

        Returns
        -------
        ndarray, (..., 3)
            Linear RGB radiance, in the float dtype of ``directions``.
        """
        d, dt = _directions(directions)
        return self._radiance(d).astype(dt, copy=False)

    def _radiance(self, d: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def sample(self, u) -> tuple[np.ndarray, np.ndarray]:
        """Directions drawn from this environment's sampling density.

        Parameters
        ----------
        u : array_like, (..., 2)
            Points of the unit square, finite reals in ``[0, 1]`` (ValueError naming ``u`` otherwise).

        Returns
        -------
        directions : ndarray, (..., 3)
            Unit directions, world frame, float64.
        pdf : ndarray, (...)
            Their density per steradian on the whole sphere.
        """
        return self._sample(_unit_square(u))

    def pdf(self, directions) -> np.ndarray:
        """Density of :meth:`sample` at ``directions``.

        Parameters
        ----------
        directions : array_like, (..., 3)
            World-frame directions (need not be unit length).

        Returns
        -------
        ndarray, (...)
            Density per steradian, float64.
        """
        d, _ = _directions(directions)
        return self._pdf(d)

    # The integrators call these three on checked float64 unit directions and unit-square points.
    def _sample(self, u):
        return uniform_sphere(u)

    def _pdf(self, d):
        return np.full(d.shape[:-1], _INV_4PI)

    def _radiance_and_pdf(self, d):
        """``(_radiance(d), _pdf(d))``: what multiple importance sampling asks of the directions a BRDF drew; a
        subclass that finds both from one computation (the lat-long image's angles) does it once."""
        return self._radiance(d), self._pdf(d)


class ConstantEnvironment(Environment):
    r"""The same radiance ``L`` from every direction (the white furnace when ``L = 1``).

    Reflected radiance is ``L`` times the directional albedo, so a Lambertian
    surface returns ``k_d L``: the furnace test of energy conservation.

    Parameters
    ----------
    radiance : float or RGB triple, >= 0

    Examples
    --------
    >>> ConstantEnvironment((1.0, 0.5, 0.25)).radiance(np.array([[0.0, 0.0, 1.0]])).tolist()
    [[1.0, 0.5, 0.25]]
    """

    def __init__(self, radiance=1.0):
        self.value = check_color("radiance", radiance)

    def _radiance(self, d):
        return np.broadcast_to(self.value, d.shape[:-1] + (3,)).copy()

    def __repr__(self):
        return f"ConstantEnvironment({self.value.tolist()})"


def _image_size(height, width):
    """``(height, width)`` of an environment image (width defaults to ``2 height``), within the memory budget."""
    height = check_count("height", height, 1)
    width = 2 * height if width is None else check_count("width", width, 1)
    check_budget("height/width", height * width * 8 * 3 * 8, what=f"a {height}x{width} RGB image and its tables")
    return height, width


def _pixel_directions(height: int, width: int) -> np.ndarray:
    """:meth:`LatLongEnvironment.pixel_directions` for a checked size."""
    th = (np.arange(height) + 0.5) * (math.pi / height)
    ph = latlong_azimuth((np.arange(width) + 0.5) * (2 * math.pi / width))
    st, ct = np.sin(th)[:, None], np.cos(th)[:, None]
    return np.stack(np.broadcast_arrays(st * np.cos(ph), st * np.sin(ph), ct), axis=-1)


class LatLongEnvironment(Environment):
    r"""An equirectangular (latitude–longitude) radiance image.

    Pixel ``(i, j)`` of an ``(H, W, 3)`` image is centred on
    ``θ = (i + ½) π / H`` (from ``+z``) and ``φ = π − (j + ½) 2π / W`` (from
    ``+x`` toward ``+y``), i.e. :func:`lighting.vec.spherical_direction`
    of those angles: the common orientation of panoramas, not mirrored (see the module notes).

    Lookup is bilinear between pixel centres, wrapping around in ``φ`` and
    clamped to the first and last rows in ``θ`` (so within half a pixel of a pole
    the value is the edge row's, interpolated in ``φ``).

    :meth:`sample` draws a half-pixel cell (each pixel cut into 2 × 2 at its centre) with
    probability the integral over its solid angle of what the lookup returns there (the mean of
    the three channels): a half row from the marginal, a half column from the row's conditional
    (both by bisection of cumulative tables).  Inside the cell the direction's density is bilinear
    in ``cos θ`` and azimuth between the lookup's values at the cell's corners.  On each cell the
    lookup blends the same four pixels, so the density is positive exactly where the lookup
    returns light: no bias, and no sample wasted where the image is black (under a one-pixel sun
    every sample lands in the sun's light).  A black image is sampled uniformly.

    Parameters
    ----------
    image : array_like, (H, W, 3), finite and >= 0
        Linear RGB radiance.

    Examples
    --------
    >>> img = np.zeros((2, 4, 3)); img[0] = 1.0  # bright sky, black ground
    >>> env = LatLongEnvironment(img)
    >>> env.radiance(np.array([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]]))[:, 0].tolist()
    [1.0, 0.0]
    """

    def __init__(self, image):
        allowed = "an (H, W, 3) array of finite radiances >= 0"
        if image is None or isinstance(image, (str, bytes, bytearray, dict, set)):
            raise ArgumentTypeError(f"image must be {allowed}; got {type(image).__name__} {quote(image)}")
        try:
            raw = np.asarray(image)
        except (TypeError, ValueError):
            raise ArgumentTypeError(f"image must be {allowed}; got {type(image).__name__}") from None
        if raw.dtype.kind not in "fiu":
            raise ArgumentTypeError(f"image must be {allowed}; got an array of dtype {raw.dtype}")
        if raw.ndim != 3 or raw.shape[2] != 3 or raw.shape[0] < 1 or raw.shape[1] < 1:
            raise ValueError(f"image must be {allowed}; got shape {raw.shape}")
        check_budget("image", raw.size * 8 * 8, what=f"sampling tables of a {raw.shape[0]}x{raw.shape[1]} image")
        img = raw.astype(np.float64)
        bad = int(np.count_nonzero(~np.isfinite(img)))
        if bad:
            raise ValueError(f"image must be {allowed}; got {bad} NaN or infinite values")
        if np.any(img < 0):
            raise ValueError(f"image must hold radiances >= 0; got a minimum of {float(img.min())!r}")
        self.image = img
        self._flat = np.ascontiguousarray(img.reshape(-1, 3))
        h, w = img.shape[:2]
        self.height, self.width = h, w

    #: The attributes :meth:`_build_sampling` makes (a subclass that samples otherwise names its own).
    _sampling_tables = frozenset(
        {"_rows_cdf", "_cols_cdf", "_last_col", "_density", "_corners", "_cols_search", "_row_scales"}
    )

    def __getattr__(self, name):
        # The sampling tables are made on first use: a map that is only looked up or prefiltered (the dominant
        # lights' residual, a sky under the split sum) never holds them.  Made twice by two threads at once, they
        # are the same arrays either way.
        if name in type(self)._sampling_tables and "image" in self.__dict__:
            self._build_sampling()
            return self.__dict__[name]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def __repr__(self):
        return f"LatLongEnvironment(image of shape {self.image.shape})"

    @classmethod
    def from_function(cls, func: Callable[[np.ndarray], np.ndarray], height: int, width: int | None = None):
        """An environment image from ``func`` sampled at the pixel centres of an ``H × W`` image.

        Parameters
        ----------
        func : callable
            ``func(directions (H, W, 3)) → (H, W, 3)`` radiance (or anything broadcasting to it).
        height : int >= 1
        width : int >= 1, optional
            Default ``2 height``.

        Returns
        -------
        LatLongEnvironment
        """
        if not callable(func):
            raise ArgumentTypeError(f"func must be a callable directions (H, W, 3) -> radiance; got {quote(func)}")
        height, width = _image_size(height, width)
        d = _pixel_directions(height, width)
        vals = np.broadcast_to(np.asarray(func(d), dtype=np.float64), (height, width, 3))
        return cls(vals)

    @staticmethod
    def pixel_directions(height: int, width: int) -> np.ndarray:
        """Unit directions of the pixel centres of an ``height × width`` image.

        Parameters
        ----------
        height, width : int >= 1

        Returns
        -------
        ndarray, (height, width, 3)
            Float64 unit directions (see the class notes for the orientation).
        """
        if width is None:  # required here: refused with the message of any other bad width
            check_count("width", width, 1)
        return _pixel_directions(*_image_size(height, width))

    def solid_angles(self) -> np.ndarray:
        """Exact solid angle of each pixel: ``(cos θ_top − cos θ_bottom) 2π / W``; sums to 4π.

        Returns
        -------
        ndarray, (H, W)
            Steradians per pixel, float64.
        """
        c = _pixel_rows(self.height)
        return np.broadcast_to(((c[:-1] - c[1:]) * (2 * math.pi / self.width))[:, None], (self.height, self.width))

    # -- lookup ----------------------------------------------------------------------
    def _radiance(self, d):
        return latlong_lookup(self._flat, self.height, self.width, d)

    # -- sampling --------------------------------------------------------------------
    def _build_sampling(self):
        h, w = self.height, self.width
        peak = float(self.image.max())
        # Scaled by the brightest value: no overflow in the sums, no underflow of a dim pixel's mass.
        lum = sum(self.image[..., c] / peak for c in range(3)) / 3 if peak > 0 else np.ones((h, w))  # black: uniform
        tables = _tables(_cell_masses(lum), _cell_solid_angles(h, w))
        self._rows_cdf, self._cols_cdf, self._last_col, self._density = tables
        self._corners = _cell_corners(lum)
        self._cols_search = _search_table(self._cols_cdf)
        self._row_scales = _half_row_scales(h)

    def _cell_probabilities(self) -> np.ndarray:
        """The sampler's probability of each half-pixel cell, ``(2H, 2W)`` (rows and columns as the module notes)."""
        h, w = self.height, self.width
        return self._density.reshape(2 * h, 2 * w) * _cell_solid_angles(h, w)[:, None]

    def _pixel_probabilities(self) -> np.ndarray:
        """The sampler's probability of each pixel, ``(H, W)``: the sum over its four cells."""
        h, w = self.height, self.width
        return self._cell_probabilities().reshape(h, 2, w, 2).sum(axis=(1, 3))

    def _sample(self, u):
        h, w = self.height, self.width
        q, uz = _pick(self._rows_cdf, u[..., 0])
        s, ua = _pick_in_rows(self._cols_cdf, self._last_col, q, u[..., 1], self._cols_search)
        values = _corner_values(self._corners, q, s)
        v00, v10, v01, v11 = values
        fz = _sample_linear(uz, v00 + v01, v10 + v11)
        fa = _sample_linear(ua, v00 + (v10 - v00) * fz, v01 + (v11 - v01) * fz)
        d = _cell_direction(q, s, fz, fa, h, w)
        # The density of the cell drawn, at the fractions drawn: what pdf(d) finds from the direction's angles, to
        # rounding, without finding the cell again.
        return d, self._cell_density(q, s, fz, fa, values)

    def _pdf(self, d, angles=None):
        q, s, fz, fa = _cell_of(d, self.height, self.width, angles, self._row_scales)
        return self._cell_density(q, s, fz, fa, _corner_values(self._corners, q, s))

    def _cell_density(self, q, s, fz, fa, values):
        """The sampler's density at fractions ``(fz, fa)`` across half-pixel cells ``(q, s)`` whose corner values
        (:func:`~lighting.sampling.environment._corner_values`) are ``values``."""
        return self._density.take(q * (2 * self.width) + s) * _bilinear_shape(values, fz, fa)

    def _radiance_and_pdf(self, d):
        cls = type(self)
        if cls._radiance is not LatLongEnvironment._radiance or cls._pdf is not LatLongEnvironment._pdf:
            return super()._radiance_and_pdf(d)  # a subclass reads or samples its own way
        # The image's lookup and the sampler's cells both start from the directions' lat-long angles.
        angles = latlong_angles(d)
        return latlong_lookup(self._flat, self.height, self.width, d, angles=angles), self._pdf(d, angles)


class FunctionEnvironment(Environment):
    r"""Radiance given by a Python function of direction.

    Parameters
    ----------
    func : callable
        ``func(directions)`` with unit float64 directions ``(..., 3)`` returning
        RGB ``(..., 3)`` (or ``(...)``, used for all three channels).  It must
        return finite values; they are not checked for sign, so a signed test
        function (a spherical harmonic) may be integrated too.

    Examples
    --------
    >>> sky = FunctionEnvironment(lambda d: 1.0 + d[..., 2])  # linear: bright above, dark below
    >>> sky.radiance(np.array([0.0, 0.0, 1.0])).tolist()
    [2.0, 2.0, 2.0]
    """

    def __init__(self, func: Callable[[np.ndarray], np.ndarray]):
        if not callable(func):
            raise ArgumentTypeError(
                f"func must be a callable directions (..., 3) -> radiance (..., 3); "
                f"got {type(func).__name__} {quote(func)}"
            )
        self.func = func

    def __repr__(self):
        return f"FunctionEnvironment({self.func!r})"

    def _radiance(self, d):
        out = np.asarray(self.func(d), dtype=np.float64)
        if out.shape == d.shape[:-1]:
            out = out[..., None]
        try:
            out = np.broadcast_to(out, d.shape[:-1] + (3,))
        except ValueError:
            raise ValueError(
                f"func must return radiance of shape (..., 3) for directions of shape {d.shape}; got {out.shape}"
            ) from None
        if not np.all(np.isfinite(out)):
            raise ValueError(f"func must return finite radiance; {self.func!r} returned non-finite values")
        return out.copy()


class SmallPatchEnvironment(Environment):
    r"""Black everywhere but one bright cap: the deck's "light at one point, black elsewhere".

    The cap is centred on ``direction`` with half-angle ``γ``,
    ``Ω = 2π (1 − cos γ)``.  Radiance is ``L`` inside (``l·c >= cos γ``) and 0
    outside.  Its irradiance on a surface facing it is ``E = π sin²γ L =
    L Ω (1 − Ω/(4π))``, and for a surface at angle ``θ`` the reflected radiance
    tends to the point-light term of the rendering equation,

        L_o(v) → f_r(v, l_c) (n·l_c) E,   E = L Ω,   as Ω → 0,

    with an error of order ``Ω`` for BRDFs smooth across the cap.

    Parameters
    ----------
    direction : 3-vector, nonzero
        Direction toward the patch centre (world frame).
    solid_angle : float in (0, 4π]
        ``Ω`` in steradians.
    radiance : float or RGB triple, >= 0
        ``L`` inside the patch.

    Examples
    --------
    >>> sun = SmallPatchEnvironment((0, 0, 1.0), 1e-4, 100.0)
    >>> sun.radiance(np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]))[:, 0].tolist()
    [100.0, 0.0]
    >>> [round(float(x), 12) for x in sun.irradiance_limit]  # E = L Ω
    [0.01, 0.01, 0.01]
    """

    def __init__(self, direction=(0.0, 0.0, 1.0), solid_angle=1e-3, radiance=1.0):
        c = check_vectors("direction", direction, dtype=np.float64, nonzero=True)
        if c.shape != (3,):
            raise ValueError(f"direction must be a finite nonzero 3-vector; got shape {c.shape}")
        c = c / np.max(np.abs(c))  # no overflow in the length for huge components
        self.direction = c / np.sqrt(np.sum(c * c))
        self.solid_angle = check_range("solid_angle", solid_angle, 0.0, 4 * math.pi, lo_open=True)
        self.value = check_color("radiance", radiance)
        # 1 − cos γ = Ω / (2π), kept as given: for tiny caps cos γ itself rounds to 1.
        self.one_minus_cos = self.solid_angle / (2 * math.pi)
        self.half_angle = 2.0 * math.asin(min(1.0, math.sqrt(self.one_minus_cos / 2.0)))
        self.support = (self.direction, self.half_angle)

    def __repr__(self):
        return (
            f"SmallPatchEnvironment(direction={self.direction.tolist()}, solid_angle={self.solid_angle!r}, "
            f"radiance={self.value.tolist()})"
        )

    @property
    def irradiance_limit(self) -> np.ndarray:
        """``E = L Ω``: the directional light the patch becomes as ``Ω → 0`` (RGB)."""
        return self.value * self.solid_angle

    @property
    def irradiance_normal(self) -> np.ndarray:
        """Exact irradiance on a surface facing the patch: ``L π sin²γ = L Ω (1 − Ω/(4π))`` (RGB)."""
        return self.value * self.solid_angle * (1 - self.solid_angle / (4 * math.pi))

    def _inside(self, d):
        diff = d - self.direction
        # 1 − d·c = |d − c|²/2 for unit d: no cancellation for tiny caps.
        return 0.5 * np.sum(diff * diff, axis=-1) <= self.one_minus_cos

    def _radiance(self, d):
        inside = self._inside(d) & np.any(d != 0, axis=-1)
        return np.where(inside[..., None], self.value, 0.0)

    def _sample(self, u):
        """Uniform directions inside the cap (density ``1/Ω``)."""
        omc = u[..., 0] * self.one_minus_cos  # 1 − cos ψ, uniform in [0, 1 − cos γ]
        cos_psi = 1.0 - omc
        sin_psi = np.sqrt(np.clip(omc * (2.0 - omc), 0.0, None))
        phi = 2 * math.pi * u[..., 1]
        t, b = _basis(self.direction)
        d = (
            cos_psi[..., None] * self.direction
            + (sin_psi * np.cos(phi))[..., None] * t
            + (sin_psi * np.sin(phi))[..., None] * b
        )
        return d, np.full(omc.shape, 1.0 / self.solid_angle)

    def _pdf(self, d):
        return np.where(self._inside(d), 1.0 / self.solid_angle, 0.0)


#: The deck's name for the same environment.
PointEnvironment = SmallPatchEnvironment


def _basis(c: np.ndarray):
    """Two unit tangents completing a unit ``c`` to a right-handed frame (Duff et al. 2017).

    The construction of :func:`lighting.vec.orthonormal_basis`, applied to ``c`` as given:
    that function normalizes its input again, which moves the tangents (and the patch's samples)
    by an ulp in a third of directions.
    """
    sign = 1.0 if c[2] >= 0 else -1.0
    a = -1.0 / (sign + c[2])
    b = c[0] * c[1] * a
    t = np.array([1.0 + sign * c[0] ** 2 * a, sign * b, -sign * c[0]])
    bt = np.array([b, sign + c[1] ** 2 * a, -c[1]])
    return t, bt


def as_environment(env) -> Environment:
    """An :class:`Environment` from an environment, a scalar/RGB radiance, or a callable.

    Parameters
    ----------
    env : Environment, float, RGB triple or callable
        An environment (returned as is), a constant radiance (:class:`ConstantEnvironment`) or a
        function of direction (:class:`FunctionEnvironment`).

    Returns
    -------
    Environment
    """
    if isinstance(env, Environment):
        return env
    if callable(env):
        return FunctionEnvironment(env)
    allowed = "an Environment, a radiance (finite scalar or RGB triple >= 0) or a callable"
    try:
        return ConstantEnvironment(env)
    except ArgumentTypeError:
        raise ArgumentTypeError(f"environment must be {allowed}; got {type(env).__name__} {quote(env)}") from None
    except ValueError:
        raise ValueError(f"environment must be {allowed}; got {quote(env)}") from None

r"""BRDF plots as data: polar slices, half/difference-angle curves and images, 3D lobes.

The decks plot a BRDF three ways: a *polar plot of reflectance strength* ("for one
view direction, showing light directions; for one light direction, showing view
directions"), a *2D slice* and a *3D surface*.  This module computes what those
plots draw — angles, values, meshes — and never draws anything itself: the
front end hands the arrays to Matplotlib or PyVista.

Frame and conventions
---------------------
Everything is in the local shading frame: the normal is ``n = +z``, ``theta`` is
measured from ``n`` and ``phi`` from ``+x`` toward ``+y`` (conventions.md).
Values are the physical BRDF ``f_r`` (1/sr) of ``brdf.eval``, zero on and below
the horizon.  Options shared by every function:

``cosine``
    ``False`` (default): ``f_r``.  ``True`` or ``"light"``: ``f_r (n·l)``, the
    integrand of the reflection equation (the explorer's "× n·l" toggle),
    computed by ``brdf.eval_cos`` without dividing by ``n·l``.  ``"view"``:
    ``f_r (n·v)``, the radiant intensity of the lit patch seen from ``v`` (a
    Lambertian surface then plots as the familiar cosine circle/sphere).
``channel``
    ``None``: RGB, shape ``(..., 3)`` (the 3D lobe, which needs one radius per
    vertex, uses luminance instead); ``0``/``1``/``2`` or ``"r"``/``"g"``/``"b"``:
    one channel; ``"luminance"``: ``Y = 0.2126 R + 0.7152 G + 0.0722 B``
    (Rec. 709 primaries of linear sRGB).
``log``
    ``True`` plots ``log10(1 + x)`` (computed as ``log1p(x)/ln 10``): zero stays
    zero, and a highlight a million times brighter than the diffuse floor still
    fits on the same axes.
``dtype``
    Output float type; by default the dtype of the angle/direction inputs
    (float64 for Python numbers, float32 for NumPy float32 inputs).  Directions are
    built in float64 and rounded once.

Every result is finite (no NaN, no Inf, no NumPy warning) for finite inputs,
including shininess 1e6, roughness 1e-6 and grazing incidence.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .._numeric import (
    ArgumentTypeError,
    _fmt,
    check_bool,
    check_choice,
    check_count,
    check_float_dtype,
    check_vectors,
    cos_sin,
    real_array,
    working_dtype,
)
from ..models.brdf import BRDFSum
from ..vec import normalize, spherical_direction

__all__ = [
    "LUMINANCE",
    "PolarSlice",
    "AngleCurve",
    "HalfDiffImage",
    "LobeMesh",
    "LobePeak",
    "polar_slice",
    "reciprocity_pair",
    "half_diff_to_dirs",
    "dirs_to_half_diff",
    "theta_h_curve",
    "theta_d_curve",
    "theta_v_curve",
    "half_diff_image",
    "lobe_width",
    "lobe_peak",
    "lobe_mesh",
]

#: Rec. 709 luminance weights of linear sRGB: ``Y = 0.2126 R + 0.7152 G + 0.0722 B``.
LUMINANCE = (0.2126, 0.7152, 0.0722)

_HALF_PI = 0.5 * math.pi
#: Half/difference-angle samples with ``|z|`` below this are on the horizon.  Directions built
#: from angles are exact there (:func:`lighting._numeric.cos_sin`), but the two rotations of
#: :func:`half_diff_to_dirs` round each component by a few ulp: at ``φ_d = 0`` a pair with
#: ``θ_h + θ_d = π/2`` would otherwise land a rounding error above the horizon, where the
#: slides' Phong BRDF (``1/(n·l)``) is ~1e16.  Eight ulp of 1 bound that rounding.
_HORIZON_TOL = 8 * float(np.finfo(np.float64).eps)
#: Elevation (rad) of the rim of a lobe mesh: the rim shows the grazing limit of the BRDF, not its zero on the horizon.
_RIM_ELEVATION = 1e-6
#: Lobes at least this wide (rad) are meshed on a plain hemisphere grid about the normal.
_BROAD = 0.5
#: Ring spacing at the lobe centre, in lobe widths, and the number of widths meshed at that spacing.
_CORE_STEP = 1.0 / 6.0
_CORE_WIDTHS = 3.0
_MAX_RESOLUTION = 99  # 1 + 2·99² = 19603 vertices
_SQRT2 = math.sqrt(2.0)
_MIN_COS = 0.1


# --------------------------------------------------------------------------- results
@dataclass(frozen=True, eq=False)
class PolarSlice:
    """One planar slice of a BRDF, ready for a polar plot.

    Attributes
    ----------
    angles : ndarray (m,)
        Signed polar angle of the varying direction, ``-π/2 … π/2``, increasing
        (``m = n`` unless ``refine`` merged in samples across a narrow lobe).  In the
        incidence plane, **negative angles are on the fixed direction's side**
        (the fixed direction itself is at ``-theta_in``) and positive angles on
        the mirror side (the mirror direction is at ``+theta_in``).  In the
        perpendicular plane positive angles point toward azimuth ``phi_in + π/2``.
    values : ndarray (n, 3) or (n,)
        The plotted quantity (see the module notes on ``cosine``, ``channel``, ``log``).
    directions : ndarray (n, 3)
        The varying unit directions (``v`` for ``fixed="light"``, ``l`` for ``fixed="view"``).
    fixed_direction : ndarray (3,)
        The fixed unit direction (``l`` or ``v``), at polar angle ``theta_in``, azimuth ``phi_in``.
    mirror_direction : ndarray (3,)
        ``2 n (n·d) − d`` of the fixed direction ``d``.
    mirror_angle : float
        Signed angle of the point of the plotted plane nearest the mirror direction:
        ``theta_in`` in the incidence plane, ``0`` in the perpendicular plane.
    incident_angle : float
        Same for the fixed direction: ``-theta_in`` (incidence plane) or ``0``.
    fixed, plane, cosine, log, channel, theta_in, phi_in
        The options the slice was made with (``cosine`` normalized to ``None``, ``"light"`` or ``"view"``).
    """

    angles: np.ndarray
    values: np.ndarray
    directions: np.ndarray
    fixed_direction: np.ndarray
    mirror_direction: np.ndarray
    mirror_angle: float
    incident_angle: float
    fixed: str
    plane: str
    cosine: str | None
    log: bool
    channel: object
    theta_in: float
    phi_in: float

    @property
    def xy(self) -> np.ndarray:
        """Cartesian curve in the slice plane: ``values · (sin angle, cos angle)``, shape ``values.shape + (2,)``.

        ``x`` runs along the plane (positive on the mirror side), ``y`` along the normal.
        On Matplotlib polar axes, plot ``(angles, values)`` with
        ``set_theta_zero_location("N")`` and ``set_theta_direction(-1)`` instead.
        """
        s, c = np.sin(self.angles), np.cos(self.angles)
        if self.values.ndim == 2:
            s, c = s[:, None], c[:, None]
        return np.stack([self.values * s, self.values * c], axis=-1)


@dataclass(frozen=True, eq=False)
class AngleCurve:
    """A BRDF value plotted against one angle.

    Attributes
    ----------
    variable : str
        ``"theta_h"``, ``"theta_d"`` or ``"theta_v"``.
    angles : ndarray (n,)
        Abscissa in radians.
    values : ndarray (n, 3) or (n,)
        Plotted quantity; 0 where ``valid`` is False.
    l, v : ndarray (n, 3)
        The light and view directions of each sample.
    valid : ndarray (n,) bool
        Both directions strictly above the horizon.
    params : dict
        The fixed angles of the curve (e.g. ``{"theta_d": 0.0, "phi_d": π/2, "phi_h": 0.0}``).
    """

    variable: str
    angles: np.ndarray
    values: np.ndarray
    l: np.ndarray  # noqa: E741 - the slides' name
    v: np.ndarray
    valid: np.ndarray
    params: dict


@dataclass(frozen=True, eq=False)
class HalfDiffImage:
    """A BRDF over the half/difference angles ``(θ_h, θ_d)`` at fixed ``φ_d`` (and ``φ_h``).

    ``values[i, j]`` is at ``theta_d[i]``, ``theta_h[j]``: **rows are θ_d, columns θ_h**
    (``imshow(values, origin="lower")`` puts ``θ_h`` on the horizontal axis and ``θ_d``
    upward, the usual layout).  Where ``l`` or ``v`` is on or below the horizon the
    value is 0 and ``valid`` is False; there are no NaNs.
    """

    theta_h: np.ndarray  # (n_h,)
    theta_d: np.ndarray  # (n_d,)
    values: np.ndarray  # (n_d, n_h, 3) or (n_d, n_h)
    valid: np.ndarray  # (n_d, n_h) bool
    phi_d: float
    phi_h: float


@dataclass(frozen=True, eq=False)
class LobeMesh:
    """The "3D surface" BRDF plot: vertex ``= value × direction`` over the upper hemisphere.

    Attributes
    ----------
    vertices : ndarray (V, 3)
        ``values[:, None] * directions`` (the surface touches the origin where the value is 0).
    faces : ndarray (F, 3) int64
        Counter-clockwise seen from outside: every face's normal points away from
        the origin (``det(p0, p1, p2) > 0`` wherever its three values are > 0).
    values : ndarray (V,)
        Scalar radius: the chosen channel, luminance by default.
    directions : ndarray (V, 3)
        Unit view directions; the faces triangulate them without degenerate faces.
    rgb : ndarray (V, 3)
        The RGB quantity at each vertex, for colouring the surface.
    center : ndarray (3,)
        Pole of the polar grid (vertex 0): the lobe peak, or ``n`` for broad lobes.
    peak : ndarray (3,)
        Direction of the largest value found by :func:`lobe_peak`.
    light : ndarray (3,)
        The unit light direction.
    width : float
        Lobe width (rad) across the plane of incidence, used to grade the grid
        (``inf`` when there is no lobe).
    rings, segments : int
        Grid layout: vertex 0 is the centre, ring ``k = 1 … rings`` holds vertices
        ``1 + (k−1)·segments … k·segments``; the last ring is the rim.
    """

    vertices: np.ndarray
    faces: np.ndarray
    values: np.ndarray
    directions: np.ndarray
    rgb: np.ndarray
    center: np.ndarray
    peak: np.ndarray
    light: np.ndarray
    width: float
    rings: int
    segments: int


class LobePeak(NamedTuple):
    """Where a BRDF lobe peaks for a fixed light: ``direction`` (3,) and scalar ``value``."""

    direction: np.ndarray
    value: float


# --------------------------------------------------------------------------- validation
# Every public function checks its arguments here, once: a wrong type raises ArgumentTypeError (a
# TypeError and a ValueError), a bad value ValueError, each naming the parameter, the value given
# (abbreviated) and what is allowed.
def _check_brdf(brdf):
    if not (callable(getattr(brdf, "eval", None)) and callable(getattr(brdf, "eval_cos", None))):
        raise ArgumentTypeError(
            f"brdf must be a reflectance model with eval and eval_cos (e.g. lighting.Lambert); "
            f"got {type(brdf).__name__} {_fmt(brdf)}"
        )
    return brdf


_COSINE_ALLOWED = "False, True, 'light' or 'view'"


def _check_cosine(cosine):
    if cosine is None or cosine is False or (isinstance(cosine, np.bool_) and not cosine):
        return None
    if cosine is True or isinstance(cosine, np.bool_):
        return "light"
    if isinstance(cosine, str):
        key = cosine.strip().lower()
        if key in ("light", "view"):
            return key
        raise ValueError(f"cosine must be {_COSINE_ALLOWED}; got {_fmt(cosine)}")
    raise ArgumentTypeError(f"cosine must be {_COSINE_ALLOWED}; got {type(cosine).__name__} {_fmt(cosine)}")


_CHANNEL_NAMES = {"r": 0, "red": 0, "g": 1, "green": 1, "b": 2, "blue": 2, "luminance": "luminance", "y": "luminance"}
_CHANNEL_ALLOWED = "None, 0, 1, 2, 'r', 'g', 'b' or 'luminance'"


def _check_channel(channel, default):
    if channel is None:
        return default
    if isinstance(channel, (int, np.integer)) and not isinstance(channel, (bool, np.bool_)):
        if 0 <= int(channel) <= 2:
            return int(channel)
        raise ValueError(f"channel must be {_CHANNEL_ALLOWED}; got {_fmt(channel)}")
    if isinstance(channel, str):
        if channel.strip().lower() in _CHANNEL_NAMES:
            return _CHANNEL_NAMES[channel.strip().lower()]
        raise ValueError(f"channel must be {_CHANNEL_ALLOWED}; got {_fmt(channel)}")
    raise ArgumentTypeError(f"channel must be {_CHANNEL_ALLOWED}; got {type(channel).__name__} {_fmt(channel)}")


def _check_bool(name, value):
    return check_bool(name, value)


def _check_count(name, value, lo, hi):
    return check_count(name, value, lo, hi)


def _scalar_angle(name, value, allowed):
    arr = real_array(name, value, allowed=allowed, dtype=np.float64)
    if arr.ndim != 0:
        raise ValueError(f"{name} must be {allowed}, a scalar; got shape {arr.shape}: {_fmt(value)}")
    return float(arr)


def _check_angle(name, value, lo, hi):
    """A finite scalar angle in ``[lo, hi]``; float32 roundings of the ends (1e-6 rad) are clamped."""
    allowed = f"a finite angle in radians in [{lo:g}, {hi:g}]"
    x = _scalar_angle(name, value, allowed)
    if not lo - 1e-6 <= x <= hi + 1e-6:
        raise ValueError(f"{name} must be {allowed}; got {_fmt(value)}")
    return min(max(x, lo), hi)


def _check_phi(name, value):
    return _scalar_angle(name, value, "a finite angle in radians")


def _out_dtype(dtype, *inputs):
    return working_dtype(*inputs) if dtype is None else check_float_dtype(dtype).type

# --------------------------------------------------------------------------- evaluation
def _quantity_rgb(brdf, l, v, cosine, dt):  # noqa: E741
    """The plotted RGB quantity for unit ``l``, ``v`` (float64 arrays), in dtype ``dt``."""
    n = np.array([0.0, 0.0, 1.0], dtype=dt)
    l, v = np.asarray(l, dt), np.asarray(v, dt)  # noqa: E741
    if cosine == "light":
        f = brdf.eval_cos(n, l, v)
    else:
        f = brdf.eval(n, l, v)
        if cosine == "view":
            f = f * np.maximum(v[..., 2], 0)[..., None]
    return np.asarray(f, dtype=dt)


def _reduce(rgb, channel):
    if channel == "rgb":
        return rgb
    if channel == "luminance":
        w = np.asarray(LUMINANCE, dtype=rgb.dtype)
        return rgb[..., 0] * w[0] + rgb[..., 1] * w[1] + rgb[..., 2] * w[2]
    return rgb[..., channel]


def _log_scale(x, log):
    if not log:
        return x
    return (np.log1p(x) / x.dtype.type(math.log(10))).astype(x.dtype, copy=False)


def _plane_dirs(t, phi, plane):
    """Unit directions (float64) at signed angle ``t`` across a plane through ``n``.

    Built through :func:`lighting._numeric.cos_sin`, like every direction of this module, so
    ``|t| = π/2`` lands exactly on the horizon (z = 0), where every BRDF is 0.
    """
    c, s = cos_sin(np.asarray(t, dtype=np.float64))
    cp, sp = cos_sin(float(phi))
    if plane == "incidence":
        ax, ay = -cp, -sp  # positive t: away from the fixed direction's azimuth
    else:
        ax, ay = -sp, cp  # positive t: toward azimuth phi + π/2
    return np.stack(np.broadcast_arrays(s * ax, s * ay, c), axis=-1) + 0.0  # + 0.0: no signed zeros


def _sph(theta, phi):
    """Unit direction (float64) at polar angle ``theta``: :func:`lighting.vec.spherical_direction`.

    ``theta = π/2`` lies exactly on the horizon (z = 0), not at ``cos(π/2) = 6e-17`` above it,
    where the slides' Phong BRDF divides by it.
    """
    return spherical_direction(float(theta), float(phi), dtype=np.float64)


# --------------------------------------------------------------------------- polar slices
def polar_slice(
    brdf,
    theta_in,
    *,
    fixed="light",
    phi_in=0.0,
    n=361,
    plane="incidence",
    cosine=False,
    log=False,
    channel=None,
    refine=True,
    dtype=None,
) -> PolarSlice:
    r"""Polar plot of reflectance strength: one direction fixed, the other swept across a plane.

    ``fixed="light"`` fixes ``l`` at polar angle ``theta_in`` (azimuth ``phi_in``) and
    sweeps ``v``: "for one light direction, showing view directions".
    ``fixed="view"`` fixes ``v`` and sweeps ``l``: "for one view direction, showing light
    directions".  Reciprocity, ``f_r(l, v) = f_r(v, l)``, says the two slices agree;
    the slides' Phong BRDF ``k_s (R_l·v)^e / (π (n·l))`` breaks it, the two slices
    differing by exactly the factor ``(n·v)/(n·l)`` (see :func:`reciprocity_pair`).

    The swept direction at signed angle ``t`` is, in the incidence plane,
    ``d(t) = (−sin t cos φ_in, −sin t sin φ_in, cos t)``: the fixed direction sits at
    ``t = −theta_in`` and its mirror ``R = 2 n (n·d) − d`` at ``t = +theta_in``.  The
    ``n`` samples are ``t_k = −π/2 + π k/(n−1)``; the two ends lie exactly on the
    horizon, where the BRDF is 0, so the curve closes at the origin.  With
    ``refine=True`` (default), a lobe narrower than four sample spacings
    (:func:`lobe_width` ``w`` at ``theta_in``: shininess above ~1e4 at ``n = 361``) would
    fall between samples, so 129 more samples at spacing ``w/8`` are merged in across
    ``mirror_angle ± 8w``; ``angles`` stays sorted but is then not uniform.

    ``cosine=True`` (``"light"``) plots ``f_r (n·l)``: with ``fixed="light"`` that is the
    constant ``cos theta_in`` times ``f_r`` (and removes Phong's ``1/(n·l)``), with
    ``fixed="view"`` it is ``cos t`` times ``f_r``.  ``cosine="view"`` multiplies by
    ``n·v`` instead.

    Parameters
    ----------
    brdf : lighting.models.brdf.BRDF
    theta_in : float
        Polar angle of the fixed direction, in ``[0, π/2]``.
    fixed : {"light", "view"}
    phi_in : float
        Azimuth of the fixed direction.
    n : int
        Number of samples, 2 … 100001 (default 361: half-degree steps).
    plane : {"incidence", "perpendicular"}
        The plane containing ``n`` and the fixed direction, or the plane through ``n``
        perpendicular to it.
    cosine, log, channel, dtype
        See the module notes.
    refine : bool
        Add samples across a lobe too narrow for the uniform grid.

    Returns
    -------
    PolarSlice

    Examples
    --------
    >>> from lighting import Phong
    >>> s = polar_slice(Phong(1.0, 20), np.pi / 4, n=5, channel="r", refine=False)
    >>> s.angles.round(4).tolist()
    [-1.5708, -0.7854, 0.0, 0.7854, 1.5708]
    >>> float(s.angles[s.values.argmax()]) == s.mirror_angle  # the highlight is at the mirror direction
    True
    """
    _check_brdf(brdf)
    theta = _check_angle("theta_in", theta_in, 0.0, _HALF_PI)
    phi = _check_phi("phi_in", phi_in)
    fixed = check_choice("fixed", fixed, ("light", "view"))
    plane = check_choice("plane", plane, ("incidence", "perpendicular"))
    count = _check_count("n", n, 2, 100001)
    cos_mode = _check_cosine(cosine)
    log = _check_bool("log", log)
    ch = _check_channel(channel, "rgb")
    refine = _check_bool("refine", refine)
    dt = _out_dtype(dtype, theta_in)
    in_plane = plane == "incidence"

    t = _slice_angles(brdf, theta, phi, count, plane, refine, cos_mode, ch)
    sweep = _plane_dirs(t, phi, plane)
    d_fixed = _sph(theta, phi)
    mirror = np.array([-d_fixed[0], -d_fixed[1], d_fixed[2]])
    fixed_b = np.broadcast_to(d_fixed, sweep.shape)
    l, v = (fixed_b, sweep) if fixed == "light" else (sweep, fixed_b)  # noqa: E741
    values = _log_scale(_reduce(_quantity_rgb(brdf, l, v, cos_mode, dt), ch), log)
    return PolarSlice(
        angles=t.astype(dt),
        values=values,
        directions=sweep.astype(dt),
        fixed_direction=d_fixed.astype(dt),
        mirror_direction=mirror.astype(dt),
        mirror_angle=theta if in_plane else 0.0,
        incident_angle=-theta if in_plane else 0.0,
        fixed=fixed,
        plane=plane,
        cosine=cos_mode,
        log=log,
        channel=channel,
        theta_in=theta,
        phi_in=phi,
    )


def reciprocity_pair(brdf, theta_in, **kwargs) -> tuple[PolarSlice, PolarSlice]:
    """Both polar slices at ``theta_in``: ``(fixed="light", fixed="view")``.

    For a reciprocal BRDF (Lambert, normalized Blinn–Phong, Cook–Torrance) the two
    ``values`` arrays are equal; for the slides' Phong BRDF their ratio is
    ``light / view = (n·v)/(n·l) = cos t / cos theta_in``.  ``kwargs`` are those of
    :func:`polar_slice` (except ``fixed``).

    Examples
    --------
    >>> from lighting import BlinnPhong
    >>> a, b = reciprocity_pair(BlinnPhong(1.0, 50, normalized=True), 0.7, n=91)
    >>> bool(np.allclose(a.values, b.values, rtol=1e-12, atol=0))
    True
    """
    if "fixed" in kwargs:
        raise ValueError(f"fixed must not be given: reciprocity_pair makes both slices; got {_fmt(kwargs['fixed'])}")
    return polar_slice(brdf, theta_in, fixed="light", **kwargs), polar_slice(brdf, theta_in, fixed="view", **kwargs)


# --------------------------------------------------------------------------- half/difference angles
def _rot_y(x, y, z, c, s):
    """Rotation about +y by the angle with cosine ``c`` and sine ``s`` (takes +z toward +x)."""
    return x * c + z * s, y, z * c - x * s


def _rot_z(x, y, z, c, s):
    return x * c - y * s, x * s + y * c, z


def half_diff_to_dirs(theta_h, phi_h, theta_d, phi_d):
    r"""Light and view directions from Rusinkiewicz's half/difference angles.

    Rusinkiewicz, "A New Change of Variables for Efficient BRDF Representation"
    (EGWR 1998): the half vector ``h`` has spherical angles ``(θ_h, φ_h)``; the
    *difference* vector ``d`` is ``l`` seen from a frame whose pole is ``h``,
    ``d = rot_y(−θ_h) rot_z(−φ_h) l``, with spherical angles ``(θ_d, φ_d)``.  Hence::

        l = rot_z(φ_h) rot_y(θ_h) (sin θ_d cos φ_d, sin θ_d sin φ_d, cos θ_d)
        v = rot_z(φ_h) rot_y(θ_h) (−sin θ_d cos φ_d, −sin θ_d sin φ_d, cos θ_d)

    (``v`` is ``d`` mirrored about the pole ``h``), so ``h = (l + v)/|l + v|`` and
    ``cos θ_d = l·h = v·h``.  ``rot_y(θ)`` tips ``+z`` toward ``+x``.  Isotropic BRDFs
    do not depend on ``φ_h``.

    Parameters
    ----------
    theta_h, phi_h, theta_d, phi_d : array_like
        Angles in radians; they broadcast together.

    Returns
    -------
    l, v : ndarray (..., 3)
        Unit vectors (possibly below the horizon: no masking here), float dtype of the inputs.

    Examples
    --------
    >>> l, v = half_diff_to_dirs(0.0, 0.0, 0.5, 0.0)  # h = n: l and v mirror each other
    >>> l.round(4).tolist(), v.round(4).tolist()
    ([0.4794, 0.0, 0.8776], [-0.4794, -0.0, 0.8776])
    """
    names = ("theta_h", "phi_h", "theta_d", "phi_d")
    given = [real_array(k, a, allowed="finite angles in radians")
             for k, a in zip(names, (theta_h, phi_h, theta_d, phi_d), strict=True)]  # fmt: skip
    dt = working_dtype(theta_h, phi_h, theta_d, phi_d)  # Python numbers are weak: the arrays decide
    try:
        th, ph, td, pd = np.broadcast_arrays(*(a.astype(np.float64) for a in given))
    except ValueError:
        shapes = ", ".join(f"{k} {a.shape}" for k, a in zip(names, given, strict=True))
        raise ValueError(f"theta_h, phi_h, theta_d and phi_d must broadcast together; got shapes {shapes}") from None
    ct, st = cos_sin(td)  # exact at right angles: θ_d = π/2 with φ_d = π/2 is exactly on the horizon
    cpd, spd = cos_sin(pd)
    dx, dy, dz = st * cpd, st * spd, ct
    ch, sh = cos_sin(th)
    cp, sp = cos_sin(ph)
    out = []
    for x, y in ((dx, dy), (-dx, -dy)):
        a = _rot_z(*_rot_y(x, y, dz, ch, sh), cp, sp)
        out.append(np.stack(a, axis=-1).astype(dt))
    return out[0], out[1]


def dirs_to_half_diff(l, v):  # noqa: E741
    r"""Rusinkiewicz's half/difference angles ``(θ_h, φ_h, θ_d, φ_d)`` of direction pairs.

    The inverse of :func:`half_diff_to_dirs`:
    ``h = (l + v)/|l + v|``, ``θ_h = atan2(|h_xy|, h_z)``, ``φ_h = atan2(h_y, h_x)``,
    ``d = rot_y(−θ_h) rot_z(−φ_h) l``, ``θ_d = atan2(|d_xy|, d_z)``, ``φ_d = atan2(d_y, d_x)``.
    Angles come from ``atan2`` (accurate at 0 and π/2, unlike ``arccos``); ``φ`` lies in
    ``(−π, π]``.  Where an angle is undefined (``φ_h`` at ``θ_h = 0``, ``φ_d`` at
    ``θ_d = 0``) it is 0; ``l = −v`` (no half vector) gives ``θ_h = φ_h = 0`` and the angles of ``l``.

    Parameters
    ----------
    l, v : array_like (..., 3)
        Directions (normalized on entry); they broadcast together.

    Returns
    -------
    theta_h, phi_h, theta_d, phi_d : ndarray (...)
        Float dtype of the inputs.

    Examples
    --------
    >>> [round(float(a), 6) for a in dirs_to_half_diff((0.6, 0.0, 0.8), (-0.6, 0.0, 0.8))]
    [0.0, 0.0, 0.643501, 0.0]
    """
    allowed = "finite real vectors of shape (..., 3)"
    dt = working_dtype(l, v)
    l, v = real_array("l", l, allowed=allowed), real_array("v", v, allowed=allowed)  # noqa: E741
    if l.shape[-1:] != (3,) or v.shape[-1:] != (3,):
        raise ValueError(f"l and v must be {allowed}; got shapes {l.shape} and {v.shape}")
    l, v = check_vectors("l", l, nonzero=True), check_vectors("v", v, nonzero=True)  # noqa: E741
    try:
        np.broadcast_shapes(l.shape, v.shape)
    except ValueError:
        raise ValueError(f"l and v must broadcast together; got shapes {l.shape} and {v.shape}") from None
    a, b = normalize(l.astype(np.float64)), normalize(v.astype(np.float64))
    a, b = np.broadcast_arrays(a, b)
    h = normalize(a + b)
    theta_h = np.arctan2(np.hypot(h[..., 0], h[..., 1]), h[..., 2])
    phi_h = np.arctan2(h[..., 1], h[..., 0])
    # Build the rotations from h's components directly (no trig round trip).
    rxy = np.hypot(h[..., 0], h[..., 1])
    safe = rxy > 0
    cp = np.where(safe, h[..., 0] / np.where(safe, rxy, 1.0), 1.0)
    sp = np.where(safe, h[..., 1] / np.where(safe, rxy, 1.0), 0.0)
    x, y, z = _rot_z(a[..., 0], a[..., 1], a[..., 2], cp, -sp)
    degenerate = ~np.any(h != 0, axis=-1)
    ch = np.where(degenerate, 1.0, h[..., 2])
    x, y, z = _rot_y(x, y, z, ch, -rxy)
    theta_d = np.arctan2(np.hypot(x, y), z)
    phi_d = np.arctan2(y, x)
    return tuple(q.astype(dt) for q in (theta_h, phi_h, theta_d, phi_d))


def _curve(brdf, variable, angles, l, v, cosine, log, channel, dt, params):  # noqa: E741
    cos_mode = _check_cosine(cosine)
    log = _check_bool("log", log)
    ch = _check_channel(channel, "rgb")
    valid = (l[..., 2] > _HORIZON_TOL) & (v[..., 2] > _HORIZON_TOL)
    rgb = _quantity_rgb(brdf, l, v, cos_mode, dt)
    rgb = np.where(valid[..., None], rgb, 0).astype(dt, copy=False)
    values = _log_scale(_reduce(rgb, ch), log)
    return AngleCurve(variable, angles.astype(dt), values, l.astype(dt), v.astype(dt), valid, params)


def theta_h_curve(
    brdf,
    theta_d=0.0,
    phi_d=_HALF_PI,
    *,
    phi_h=0.0,
    n=181,
    cosine=False,
    log=False,
    channel=None,
    dtype=None,
) -> AngleCurve:
    """The BRDF against the half angle ``θ_h ∈ [0, π/2]`` at fixed ``θ_d``, ``φ_d`` (and ``φ_h``).

    At ``θ_d = 0`` (the default) ``l = v = h``: the backscatter curve, whose shape is
    the specular lobe's NDF.  Samples are ``θ_h = π/2 · k/(n−1)``; where ``l`` or ``v``
    is not above the horizon the value is 0 and ``valid`` is False.

    Examples
    --------
    >>> from lighting import BlinnPhong
    >>> c = theta_h_curve(BlinnPhong(1.0, 10, normalized=True), n=3, channel=0)
    >>> c.values.round(4).tolist()  # (e+2)/(2π) cos^e θ_h, 0 at the horizon
    [1.9099, 0.0597, 0.0]
    """
    _check_brdf(brdf)
    td = _check_angle("theta_d", theta_d, 0.0, _HALF_PI)
    pd, ph = _check_phi("phi_d", phi_d), _check_phi("phi_h", phi_h)
    count = _check_count("n", n, 2, 100001)
    dt = _out_dtype(dtype, theta_d, phi_d)
    th = np.linspace(0.0, _HALF_PI, count)
    l, v = half_diff_to_dirs(th, ph, td, pd)  # noqa: E741
    params = {"theta_d": td, "phi_d": pd, "phi_h": ph}
    return _curve(brdf, "theta_h", th, l, v, cosine, log, channel, dt, params)


def theta_d_curve(
    brdf,
    theta_h=0.0,
    phi_d=_HALF_PI,
    *,
    phi_h=0.0,
    n=181,
    cosine=False,
    log=False,
    channel=None,
    dtype=None,
) -> AngleCurve:
    """The BRDF against the difference angle ``θ_d ∈ [0, π/2]`` at fixed ``θ_h``, ``φ_d`` (and ``φ_h``).

    At ``θ_h = 0`` (the default) ``h = n``: ``l`` and ``v`` are mirror images at
    ``θ_d`` from the normal, so the curve shows how the specular peak changes toward
    grazing (Fresnel, shadowing).  Samples ``θ_d = π/2 · k/(n−1)``; 0 and
    ``valid = False`` where ``l`` or ``v`` is not above the horizon.

    Examples
    --------
    >>> from lighting import Lambert
    >>> theta_d_curve(Lambert(1.0), n=3, channel=0).values.round(6).tolist()
    [0.31831, 0.31831, 0.0]
    """
    _check_brdf(brdf)
    th = _check_angle("theta_h", theta_h, 0.0, _HALF_PI)
    pd, ph = _check_phi("phi_d", phi_d), _check_phi("phi_h", phi_h)
    count = _check_count("n", n, 2, 100001)
    dt = _out_dtype(dtype, theta_h, phi_d)
    td = np.linspace(0.0, _HALF_PI, count)
    l, v = half_diff_to_dirs(th, ph, td, pd)  # noqa: E741
    params = {"theta_h": th, "phi_d": pd, "phi_h": ph}
    return _curve(brdf, "theta_d", td, l, v, cosine, log, channel, dt, params)


def theta_v_curve(
    brdf,
    theta_l,
    *,
    phi_l=0.0,
    n=181,
    cosine=False,
    log=False,
    channel=None,
    refine=True,
    dtype=None,
) -> AngleCurve:
    """The BRDF against the view angle in the incidence plane, for a fixed light.

    The abscissa is the signed view angle ``θ_v ∈ [−π/2, π/2]`` of
    :func:`polar_slice` (``fixed="light"``): the light is at ``−theta_l`` and the
    mirror direction at ``+theta_l``; the ends are on the horizon (value 0).  This is
    the same data as the polar slice with the same ``n`` and ``refine``, drawn on
    Cartesian axes: with ``refine=True`` (default) the samples are the ``n`` uniform
    ones plus those where the lobe is, its peak included, so a highlight narrower than
    the grid or a hair above the horizon shows at the height :func:`lobe_peak` finds.

    Examples
    --------
    >>> from lighting import Phong
    >>> c = theta_v_curve(Phong(1.0, 10), 0.3, n=181, channel=0)
    >>> float(c.angles[c.values.argmax()])  # the mirror direction, off the 1° grid, is a sample
    0.3
    >>> c = theta_v_curve(Phong(1.0, 10), 0.3, n=181, channel=0, refine=False)
    >>> round(float(c.angles[c.values.argmax()]), 4)  # the grid alone: the nearest degree
    0.2967
    """
    _check_brdf(brdf)
    theta = _check_angle("theta_l", theta_l, 0.0, _HALF_PI)
    phi = _check_phi("phi_l", phi_l)
    count = _check_count("n", n, 2, 100001)
    refine = _check_bool("refine", refine)
    cos_mode = _check_cosine(cosine)
    dt = _out_dtype(dtype, theta_l)
    t = _slice_angles(brdf, theta, phi, count, "incidence", refine, cos_mode, _check_channel(channel, "rgb"))
    v = _plane_dirs(t, phi, "incidence")
    l = np.broadcast_to(_sph(theta, phi), v.shape)  # noqa: E741
    return _curve(brdf, "theta_v", t, l, v, cosine, log, channel, dt, {"theta_l": theta, "phi_l": phi})


def half_diff_image(
    brdf,
    phi_d=_HALF_PI,
    n_h=91,
    n_d=91,
    *,
    phi_h=0.0,
    theta_h_spacing="uniform",
    cosine=False,
    log=False,
    channel=None,
    dtype=None,
) -> HalfDiffImage:
    r"""The BRDF as an image over ``(θ_h, θ_d) ∈ [0, π/2]²`` at fixed ``φ_d`` — rows θ_d, columns θ_h.

    The usual "image slice" of BRDF tools: with the default ``φ_d = π/2`` both ``l``
    and ``v`` have ``z = cos θ_h cos θ_d``, so the whole open square is above the
    horizon; with ``φ_d = 0`` only ``θ_h + θ_d < π/2`` is.  Pixels where ``l`` or ``v``
    is on or below the horizon hold 0 and ``valid`` is False (no NaN).

    ``theta_h_spacing="sqrt"`` samples ``θ_h = π/2 · u²`` (``u`` uniform), the
    spacing of tabulated measured BRDFs, which puts more columns into the specular
    peak near ``θ_h = 0``; ``"uniform"`` samples ``θ_h = π/2 · u``.  ``θ_d`` is
    always uniform.  Axes include both ends.

    Parameters
    ----------
    brdf : lighting.models.brdf.BRDF
    phi_d : float
    n_h, n_d : int
        Columns and rows, 2 … 4096 each.
    phi_h : float
    theta_h_spacing : {"uniform", "sqrt"}
    cosine, log, channel, dtype
        See the module notes.

    Examples
    --------
    >>> from lighting import Lambert
    >>> im = half_diff_image(Lambert(1.0), phi_d=0.0, n_h=3, n_d=3, channel=0)
    >>> im.valid.tolist()  # rows θ_d = 0, π/4, π/2; columns θ_h = 0, π/4, π/2
    [[True, True, False], [True, False, False], [False, False, False]]
    """
    _check_brdf(brdf)
    pd, ph = _check_phi("phi_d", phi_d), _check_phi("phi_h", phi_h)
    nh = _check_count("n_h", n_h, 2, 4096)
    nd = _check_count("n_d", n_d, 2, 4096)
    spacing = check_choice("theta_h_spacing", theta_h_spacing, ("uniform", "sqrt"))
    cos_mode = _check_cosine(cosine)
    log = _check_bool("log", log)
    ch = _check_channel(channel, "rgb")
    dt = _out_dtype(dtype, phi_d)
    th = np.linspace(0.0, _HALF_PI, nh)
    if spacing == "sqrt":
        th = _HALF_PI * np.linspace(0.0, 1.0, nh) ** 2
    td = np.linspace(0.0, _HALF_PI, nd)
    l, v = half_diff_to_dirs(th[None, :], ph, td[:, None], pd)  # noqa: E741
    valid = (l[..., 2] > _HORIZON_TOL) & (v[..., 2] > _HORIZON_TOL)
    rgb = _quantity_rgb(brdf, l, v, cos_mode, dt)
    rgb = np.where(valid[..., None], rgb, 0).astype(dt, copy=False)
    values = _log_scale(_reduce(rgb, ch), log)
    return HalfDiffImage(th.astype(dt), td.astype(dt), values, valid, pd, ph)


# --------------------------------------------------------------------------- 3D lobe
def _part_widths(p, cos_l: float) -> tuple[float, float]:
    """``(across, along)``: the lobe's angular standard deviations across and along the plane of incidence."""
    lobe = p.lobe()
    if lobe is None:
        return math.nan, math.nan  # unknown lobe: measured numerically
    if lobe.axis == "normal":
        return math.inf, math.inf
    if lobe.axis == "mirror":
        # A cone about R: the same width in every direction.
        return lobe.width, lobe.width
    h_width = lobe.width
    # Half-vector lobes: |dv| = 2 |dh| along the plane of incidence, 2 cos θ_d |dh| across it (θ_d = θ_l at R_l).
    return h_width * 2.0 * max(cos_l, _MIN_COS), h_width * 2.0


def _lobe_widths(brdf, theta_l) -> tuple[float, float]:
    parts = brdf.parts if isinstance(brdf, BRDFSum) else (brdf,)
    widths = [_part_widths(p, math.cos(theta_l)) for p in parts]
    if any(math.isnan(w[0]) for w in widths):
        return math.nan, math.nan
    return min(widths)


def _numeric_width(brdf, l64, cosine, channel) -> float:
    """Half-width at half maximum of the in-plane slice, divided by 1.18 (a Gaussian's σ)."""
    theta, phi = _light_angles(l64)
    t = np.linspace(-_HALF_PI, _HALF_PI, 2881)[1:-1]
    v = _plane_dirs(t, phi, "incidence")
    f = _reduce(_quantity_rgb(brdf, np.broadcast_to(_sph(theta, phi), v.shape), v, cosine, np.float64), channel)
    k = int(np.argmax(f))
    if not f[k] > 0 or np.all(f >= 0.5 * f[k]):
        return math.inf
    below = np.flatnonzero(f < 0.5 * f[k])
    dist = np.abs(below - k).min() * (t[1] - t[0])
    return max(dist / 1.18, 1e-4)


def lobe_width(brdf, theta_l=0.0) -> float:
    r"""Angular width (rad) of the narrowest specular lobe of ``brdf`` over view directions; ``inf`` if none.

    A standard deviation estimated from the model's parameters, for a light at polar
    angle ``theta_l``:

    * Phong, ``(R_l·v)^e ≈ exp(−e ψ²/2)``: ``1/√e``, the same at every incidence;
    * half-vector lobes — Blinn–Phong ``(n·h)^e ≈ exp(−e θ_h²/2)`` (``θ_h`` width ``1/√e``)
      and Cook–Torrance (Beckmann ``exp(−θ_h²/α²)``, width ``α/√2``; GGX and the
      Blinn–Phong NDF are no wider at the peak) — map to view directions through
      ``|dv| = 2 cos θ_d |dh|`` across the plane of incidence (``θ_d = θ_l`` at the
      mirror direction), so their width is ``2 cos θ_l`` times the half-angle width
      (``cos θ_l`` clamped at 0.1: at grazing the lobe is a thin sliver); along the
      plane it is ``2`` times the half-angle width, and :func:`lobe_mesh` stretches its
      grid by that aspect ratio;
    * the minimum over the parts of a sum, ignoring parts whose coefficient is 0;
      Lambert and ``e = 0`` have no lobe (``inf``).

    ``nan`` for a model this module does not know (:func:`lobe_mesh` then measures
    the width numerically).

    Examples
    --------
    >>> from lighting import Lambert, Phong
    >>> lobe_width(Lambert(0.5) + Phong(0.5, 100))
    0.1
    """
    _check_brdf(brdf)
    return _lobe_widths(brdf, _check_angle("theta_l", theta_l, 0.0, _HALF_PI))[0]


def _polar(d) -> float:
    return min(math.atan2(math.hypot(d[0], d[1]), d[2]), _HALF_PI)


def _unit_light(l):  # noqa: E741
    arr = check_vectors("l", l, dtype=np.float64, nonzero=True)
    if arr.shape != (3,):
        raise ValueError(f"l must be one direction of shape (3,); got shape {arr.shape}: {_fmt(l)}")
    m = np.max(np.abs(arr))
    s = arr / m
    return s / math.sqrt(float(s @ s))


def _peak_t(brdf, theta, phi, cosine, channel, width, fixed="light", d_fixed=None):
    """Search the incidence plane for the largest value; returns ``(t, value)``, ``t`` the signed angle.

    The fixed direction (``l`` for ``fixed="light"``, else ``v``) is at polar angle ``theta``,
    azimuth ``phi``; the other is swept as in :func:`polar_slice`, so the mirror direction
    is at ``t = theta``.  Isotropic models are mirror-symmetric about the plane of incidence,
    and every model here peaks in it (at ``R_l``, or off-specular toward grazing for rough
    Cook–Torrance).  Candidates: the mirror direction first (so that a flat lobe such as
    Lambert's reports ``R_l``), a fine grid of ±8 widths around it, a quarter-degree grid
    across the plane; then five zooms around the best.
    """
    lim = _HALF_PI - 1e-9
    d_fixed = _sph(theta, phi) if d_fixed is None else d_fixed

    def value(t):
        sweep = _plane_dirs(t, phi, "incidence")
        fixed_b = np.broadcast_to(d_fixed, sweep.shape)
        l, v = (fixed_b, sweep) if fixed == "light" else (sweep, fixed_b)  # noqa: E741
        return _reduce(_quantity_rgb(brdf, l, v, cosine, np.float64), channel)

    coarse = np.linspace(-lim, lim, 721)
    coarse_step = coarse[1] - coarse[0]
    fine_step = width / 10 if math.isfinite(width) else coarse_step
    t = [np.array([min(theta, lim)]), coarse]
    steps = [np.array([min(fine_step, coarse_step)]), np.full(coarse.shape, coarse_step)]
    if math.isfinite(width):
        t.insert(1, np.clip(theta + width * np.linspace(-8.0, 8.0, 161), -lim, lim))
        steps.insert(1, np.full(161, fine_step))
    t, steps = np.concatenate(t), np.concatenate(steps)
    f = value(t)
    k = int(np.argmax(f))
    # Zoom on the best candidate with the spacing of the grid it came from.
    best_t, best_f, step = float(t[k]), float(f[k]), float(steps[k])
    for _ in range(5):
        tz = np.concatenate([[best_t], np.clip(best_t + step * np.linspace(-2.0, 2.0, 41), -lim, lim)])
        fz = value(tz)
        k = int(np.argmax(fz))
        if fz[k] > best_f:
            best_t, best_f = float(tz[k]), float(fz[k])
        step /= 10
    return best_t, best_f


def _slice_peaks(brdf, theta, phi, channel, width):
    """Signed angles of the in-plane peaks a slice must sample, whatever its ``fixed`` and ``cosine``.

    The same search as :func:`_peak_t` for four quantities at once: ``f`` and ``f (n·v)`` with the
    light fixed, ``f`` and ``f (n·l)`` with the view fixed (``f (n·l)`` with the light fixed is ``f``
    times a constant, and so on).  One BRDF evaluation per round serves all four, so a slice pays
    about one search for them; and the angles do not depend on the slice's options, so both
    slices of :func:`reciprocity_pair` and the "× n·l" toggle keep their samples.
    """
    lim = _HALF_PI - 1e-9
    d_fixed = _sph(theta, phi)
    variants = (("light", None), ("light", "view"), ("view", None), ("view", "light"))

    def values(ts):
        # ts: one array of angles per variant; returns their values, evaluated in one call.
        sizes = [len(t) for t in ts]
        sweep = _plane_dirs(np.concatenate(ts), phi, "incidence")
        role_light = np.concatenate([np.full(n, r == "light") for n, (r, _) in zip(sizes, variants, strict=True)])
        fixed_b = np.broadcast_to(d_fixed, sweep.shape)
        l = np.where(role_light[:, None], fixed_b, sweep)  # noqa: E741
        v = np.where(role_light[:, None], sweep, fixed_b)
        f = _reduce(_quantity_rgb(brdf, l, v, None, np.float64), channel)
        out, start = [], 0
        for n, (_, mode) in zip(sizes, variants, strict=True):
            part = f[start : start + n]
            rows = slice(start, start + n)
            if mode == "view":
                part = part * np.maximum(v[rows, 2], 0)
            elif mode == "light":
                part = part * np.maximum(l[rows, 2], 0)
            out.append(part)
            start += n
        return out

    coarse = np.linspace(-lim, lim, 721)
    coarse_step = coarse[1] - coarse[0]
    fine_step = min(width / 10, coarse_step) if math.isfinite(width) else coarse_step
    t = [np.array([min(theta, lim)]), coarse]
    steps = [np.array([fine_step]), np.full(coarse.shape, coarse_step)]
    if math.isfinite(width):
        t.insert(1, np.clip(theta + width * np.linspace(-8.0, 8.0, 161), -lim, lim))
        steps.insert(1, np.full(161, width / 10))
    t, steps = np.concatenate(t), np.concatenate(steps)
    best = []
    for f in values([t] * len(variants)):
        k = int(np.argmax(f))
        best.append([float(t[k]), float(f[k]), float(steps[k])])
    for _ in range(5):
        grids = [np.concatenate([[b[0]], np.clip(b[0] + b[2] * np.linspace(-2.0, 2.0, 41), -lim, lim)]) for b in best]
        for b, tz, fz in zip(best, grids, values(grids), strict=True):
            k = int(np.argmax(fz))
            if fz[k] > b[1]:
                b[0], b[1] = float(tz[k]), float(fz[k])
            b[2] /= 10
    return [b[0] for b in best]


def _light_angles(l64):
    """Polar angle and azimuth of a unit light direction (float64)."""
    return math.atan2(math.hypot(l64[0], l64[1]), l64[2]), math.atan2(l64[1], l64[0])


def _peak64(brdf, l64, cosine, channel, width):
    """The in-plane peak for the light ``l64``: ``(direction, value)`` in float64 (see :func:`_peak_t`)."""
    theta, phi = _light_angles(l64)
    t, f = _peak_t(brdf, theta, phi, cosine, channel, width, d_fixed=l64)
    return _plane_dirs(t, phi, "incidence"), f


def _slice_angles(brdf, theta, phi, count, plane, refine, cosine, channel):
    """Signed sample angles of a slice: the uniform grid, plus where the lobe is.

    With ``refine``: a lobe narrower than four grid spacings gets 129 samples at spacing
    ``w/8`` across ``±8 w`` about the mirror angle (the normal in the perpendicular plane);
    in the plane of incidence the peak of the lobe (:func:`_slice_peaks`: with the light
    fixed and with the view fixed, with and without the cosine factors, so that both slices
    of :func:`reciprocity_pair` and every ``cosine`` option share their angles) is a sample
    too.  A narrow highlight off the grid, or one a hair above the horizon (rough
    Cook–Torrance lit at grazing), is then drawn at its true height, the height
    :func:`lobe_peak` reports and :func:`lobe_mesh` draws.  Without a lobe
    (Lambert alone: width ``inf``) the grid's maximum is already the peak.
    """
    t = np.linspace(-_HALF_PI, _HALF_PI, count)
    if not refine:
        return t
    in_plane = plane == "incidence"
    scalar = "luminance" if channel == "rgb" else channel
    w = _lobe_widths(brdf, theta)[0]
    if math.isnan(w):
        w = _numeric_width(brdf, _sph(theta, phi), None, scalar)  # the options must not move the samples
    extra = []
    if w < 4 * math.pi / (count - 1):  # False for inf
        extra.append((theta if in_plane else 0.0) + w * np.linspace(-8.0, 8.0, 129))
    if in_plane and theta < _HALF_PI and math.isfinite(w):
        extra.append(_slice_peaks(brdf, theta, phi, scalar, w))
    if extra:
        extra = np.concatenate([np.asarray(e, dtype=np.float64) for e in extra])
        t = np.union1d(t, extra[np.abs(extra) < _HALF_PI])
    return t


def lobe_peak(brdf, l, *, cosine=False, channel=None) -> LobePeak:
    r"""Direction ``v`` where ``f_r(l, v)`` (or the chosen quantity) is largest, and that value.

    The search runs in the plane of incidence — isotropic models are mirror-symmetric
    about it, and every model of :mod:`lighting.models.brdf` peaks in it — over a quarter-degree
    grid plus ±8 lobe widths around ``R_l``, then zooms five times around the best
    sample, down to ~1e-6 of the grid spacing.  For Phong and Blinn–Phong the answer is the mirror
    direction ``R_l = 2 n (n·l) − l``; rough Cook–Torrance peaks off-specular, toward
    grazing.  Ties (a Lambertian lobe is flat) resolve to ``R_l``.  A light on or below
    the horizon gives ``(n, 0)``.

    Parameters
    ----------
    brdf : lighting.models.brdf.BRDF
    l : array_like (3,)
        Light direction in the local frame (``n = +z``); normalized on entry.
    cosine, channel
        See the module notes; ``channel=None`` means luminance.

    Returns
    -------
    LobePeak
        ``(direction, value)``: unit vector (3,) in the dtype of ``l`` and a float.

    Examples
    --------
    >>> from lighting import Phong
    >>> p = lobe_peak(Phong(1.0, 1000), (0.6, 0.0, 0.8))
    >>> p.direction.round(9).tolist()
    [-0.6, 0.0, 0.8]
    """
    _check_brdf(brdf)
    dt = working_dtype(l)
    l64 = _unit_light(l)
    cos_mode = _check_cosine(cosine)
    ch = _check_channel(channel, "luminance")
    if not l64[2] > 0:
        return LobePeak(np.array([0.0, 0.0, 1.0], dtype=dt), 0.0)
    w = _lobe_widths(brdf, _polar(l64))[0]
    if math.isnan(w):
        w = _numeric_width(brdf, l64, cos_mode, ch)
    d, f = _peak64(brdf, l64, cos_mode, ch, w)
    return LobePeak(d.astype(dt), f)


def _ring_profile(rho_ref: float, rings: int, delta0: float) -> np.ndarray:
    """Ring radii ``ρ_0 = 0 < ρ_1 < … < ρ_rings = rho_ref`` graded toward the pole.

    A core of ``Kc`` rings at spacing ``δ = min(δ0, rho_ref/rings)`` (``δ0`` a sixth of
    the lobe width, ``Kc`` rings covering three widths, at most half the rings), then a
    geometric progression ``δ q, δ q², …`` ending exactly at ``rho_ref``: ``q`` solves
    ``Σ_{j=1}^{N} q^j = rho_ref/δ − Kc`` (bisection on ``log q``).  With ``δ0 = inf``
    (or a lobe wider than the uniform spacing) every ring is uniform.
    """
    K = rings
    delta = min(delta0, rho_ref / K)
    Kc = min(math.ceil(_CORE_WIDTHS / _CORE_STEP), K // 2) if delta < rho_ref / K else 0
    N = K - Kc
    target = max(rho_ref / delta - Kc, N)

    def geo_sum(lq, m):
        with np.errstate(divide="ignore", invalid="ignore"):
            g = np.exp(lq) * np.expm1(m * lq) / np.expm1(lq)
        return np.where(lq > 0, g, m)

    lo, hi = 0.0, math.log(target) / N
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if geo_sum(mid, N) < target else (lo, mid)
    k = np.arange(K + 1, dtype=np.float64)
    rho = delta * (np.minimum(k, Kc) + geo_sum(0.5 * (lo + hi), np.maximum(k - Kc, 0)))
    rho[-1] = rho_ref
    return rho


def _fit_to_rim(rho: np.ndarray, rho_max: np.ndarray) -> np.ndarray:
    """Per azimuth, map the common radii ``rho`` (ending at ``rho[-1] >= rho_max``) onto ``[0, rho_max]``.

    The inner half, ``ρ <= b = rho_max/2``, is kept as is, so that neighbouring
    azimuths share their rings where the lobe is (no skewed triangles); beyond it
    ``b + λ log1p((ρ − b)/λ)`` compresses the rest onto the rim.  ``λ`` solves
    ``λ log1p((ρ_end − b)/λ) = rho_max − b`` (the map ends at ``rho_max``), which also
    makes it C¹ at ``b``; logarithmic compression of geometric rings spaces them
    evenly, so no rings pile up even where the rim is very close to the pole.
    """
    r_end = float(rho[-1])
    b = 0.5 * rho_max
    X, Y = r_end - b, rho_max - b
    same = Y >= X * (1 - 1e-12)
    Ys = np.where(same, 0.5 * X, Y)  # any Y < X: those columns are discarded below
    lo = np.log(Ys) - 80.0
    hi = np.log(X) + 80.0
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lam = np.exp(mid)
        small = lam * np.log1p(X / lam) < Ys
        lo, hi = np.where(small, mid, lo), np.where(small, hi, mid)
    lam = np.exp(0.5 * (lo + hi))
    r = rho[:, None]
    fitted = np.where(r <= b, r, b + lam * np.log1p(np.maximum(r - b, 0.0) / lam))
    out = np.where(same, np.minimum(r * (rho_max / r_end), rho_max), fitted)
    out[-1] = rho_max
    return out


def lobe_mesh(brdf, l, *, resolution=64, cosine=False, adaptive=True, channel=None) -> LobeMesh:
    r"""The "3D surface" plot of a BRDF: radius ``f_r(l, v)`` in every view direction ``v``.

    For the fixed light ``l`` the surface is ``{ f(v) · v : v in the upper hemisphere }``
    with ``f`` the BRDF (``cosine=False``), ``f_r (n·l)`` (``True``/``"light"``: for a
    fixed light a constant factor, except that Phong loses its ``1/(n·l)``) or
    ``f_r (n·v)`` (``"view"``: the radiant intensity, a sphere of diameter ``k_d/π``
    for Lambert).  Lambert with ``cosine=False`` is a hemisphere of radius ``k_d/π``.

    The grid is polar about a centre ``c``: vertex 0 is ``c``; ``rings`` rings of
    ``segments = 2·resolution`` vertices follow, ring ``k`` at radius ``ρ_k`` along
    ``segments`` evenly spaced azimuths; the last ring (the rim) runs ``1e-6`` rad above
    the horizon, so it shows the grazing limit of the BRDF rather than its 0 on the
    horizon.

    With ``adaptive=True`` and a lobe narrower than 0.5 rad (``w`` from
    :func:`lobe_width`: ``1/√e`` for Phong, ``2 cos θ_l/√e`` for Blinn–Phong,
    ``√2 α cos θ_l`` for Cook–Torrance):

    * ``c`` is the lobe peak (:func:`lobe_peak`), kept at least ``max(w/2, 1e-4)``
      above the horizon;
    * the rings are ellipses stretched along the plane of incidence by the lobe's
      aspect ratio (``1/cos θ_l`` for half-vector lobes, 1 for Phong);
    * their radii are graded on ``w``: 18 rings at spacing ``w/6`` (three widths, where
      neighbouring values differ by at most ``e^{1/2}`` for a Gaussian lobe), then a
      geometric progression out to the farthest rim;
    * within half the distance to the rim every azimuth shares these radii; beyond, a
      C¹ logarithmic map fits them to the rim, which may be very close on the horizon side.

    A shininess-1000 Phong lobe (``w ≈ 0.032``) thus gets ~900 vertices above half its
    peak, against 7 on a uniform grid (``adaptive=False``, or a broad lobe: ``c = n`` and
    uniform rings).  The finest spacing is at least 256 ulp of the output dtype, so
    float32 meshes stay valid for the narrowest lobes (which float32 cannot resolve).

    Vertex count ``1 + 2·resolution²`` (8193 by default, at most 19603), faces
    ``2·segments·(rings − ½)``.  Faces are counter-clockwise seen from outside.

    Parameters
    ----------
    brdf : lighting.models.brdf.BRDF
    l : array_like (3,)
        Light direction in the local frame (``n = +z``), normalized on entry.  A light
        on or below the horizon gives an all-zero lobe.
    resolution : int
        Number of rings, 4 … 99 (segments are twice that).
    cosine : bool or {"light", "view"}
    adaptive : bool
    channel : None, 0, 1, 2, "r", "g", "b" or "luminance"
        The radius; ``None`` means luminance.  ``rgb`` always holds all three channels.

    Returns
    -------
    LobeMesh
        In the dtype of ``l``.

    Examples
    --------
    >>> from lighting import Lambert
    >>> m = lobe_mesh(Lambert(1.0), (0.0, 0.0, 1.0), resolution=8)
    >>> m.vertices.shape, m.faces.shape
    ((129, 3), (240, 3))
    >>> bool(np.allclose(np.linalg.norm(m.vertices, axis=1), 1 / np.pi))
    True
    """
    _check_brdf(brdf)
    dt = working_dtype(l)
    l64 = _unit_light(l)
    K = _check_count("resolution", resolution, 4, _MAX_RESOLUTION)
    cos_mode = _check_cosine(cosine)
    adaptive = _check_bool("adaptive", adaptive)
    ch = _check_channel(channel, "luminance")
    S = 2 * K

    lit = l64[2] > 0
    width, along = math.inf, math.inf
    peak = np.array([0.0, 0.0, 1.0])
    if lit:
        width, along = _lobe_widths(brdf, _polar(l64))
        if math.isnan(width):
            width = along = _numeric_width(brdf, l64, cos_mode, ch)
        peak, _ = _peak64(brdf, l64, cos_mode, ch, width)
    narrow = adaptive and width < _BROAD
    theta_c, phi_c, stretch = 0.0, 0.0, 1.0
    rim_elevation = _RIM_ELEVATION
    # The adaptive grid holds the peak as a vertex (see below), so the lobe drawn reaches the
    # value lobe_peak reports and the slices show: its azimuth is the grid's χ = π ray, and a
    # peak closer to the horizon than the rim (rough Cook–Torrance lit at grazing) lowers the rim.
    snap = adaptive and lit
    if snap:
        phi_c = math.atan2(peak[1], peak[0])
        rim_elevation = min(rim_elevation, math.atan2(peak[2], math.hypot(peak[0], peak[1])))
    if narrow:
        gap = max(0.5 * width, 1e-4)
        theta_c = min(_polar(peak), _HALF_PI - gap)
        stretch = max(along / width, 1.0)
    c = _sph(theta_c, phi_c)
    a, s = math.cos(theta_c), math.sin(theta_c)
    # t1 points from c toward the normal (along the plane of incidence), t2 = c × t1.
    t1 = np.array([-a * math.cos(phi_c), -a * math.sin(phi_c), s])
    t2 = np.cross(c, t1)

    # Elliptic rings: parameter azimuth χ, true azimuth χ' about c, radius ψ = ρ e(χ).
    chi = 2 * math.pi * np.arange(S) / S
    ex, ey = stretch * np.cos(chi), np.sin(chi)
    e = np.hypot(ex, ey)
    cchi, schi = ex / e, ey / e  # cos χ', sin χ'
    # Along χ', z(ψ) = a cos ψ + s cos χ' sin ψ = R cos(ψ − δ); the rim is where z = sin(rim elevation).
    R = np.hypot(a, s * cchi)
    psi_max = np.arctan2(s * cchi, a) + np.arccos(np.minimum(math.sin(rim_elevation) / R, 1.0))
    rho_max = psi_max / e
    ulp_floor = 256 * float(np.finfo(dt).eps)
    delta0 = max(_CORE_STEP * width, ulp_floor) if narrow else math.inf
    rho = _ring_profile(float(rho_max.max()), K, delta0)
    psi = _fit_to_rim(rho, rho_max)[1:] * e  # (K, S)
    peak_vertex = None
    if snap:
        # The peak lies on the ray χ = π from c (away from the normal, at the peak's azimuth), at
        # ψ_p = θ_peak − θ_c.  The nearest vertex on that ray moves to it: it stays between its
        # ring neighbours on the ray, so no face flips.
        col = S // 2
        psi_p = max(_polar(peak) - theta_c, 0.0)
        along_ray = np.concatenate([[0.0], psi[:, col]])
        k_p = int(np.argmin(np.abs(along_ray - psi_p)))
        if k_p > 0:
            psi[k_p - 1, col] = psi_p
        peak_vertex = 0 if k_p == 0 else 1 + (k_p - 1) * S + col
    sp, cp = np.sin(psi), np.cos(psi)
    radial = cchi[:, None] * t1 + schi[:, None] * t2  # (S, 3)
    dirs = cp[..., None] * c + sp[..., None] * radial[None, :, :]
    dirs = np.concatenate([c[None, :], dirs.reshape(-1, 3)])
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    if peak_vertex is not None:
        dirs[peak_vertex] = peak  # the same rounding as lobe_peak's direction, not a rebuilt one

    j = np.arange(S)
    jn = (j + 1) % S
    fan = np.stack([np.zeros(S, dtype=np.int64), 1 + j, 1 + jn], axis=1)
    k = np.arange(K - 1)[:, None]
    ia, ib = 1 + k * S + j, 1 + k * S + jn  # inner ring
    oa, ob = ia + S, ib + S  # outer ring
    quads = np.concatenate([np.stack([ia, oa, ob], -1), np.stack([ia, ob, ib], -1)], axis=1).reshape(-1, 3)
    faces = np.concatenate([fan, quads]).astype(np.int64)

    d_out = dirs.astype(dt)
    if lit:
        rgb = _quantity_rgb(brdf, np.broadcast_to(l64, dirs.shape), d_out, cos_mode, dt)
    else:
        rgb = np.zeros(dirs.shape, dtype=dt)
    values = _reduce(rgb, ch).astype(dt, copy=False)
    return LobeMesh(
        vertices=values[:, None] * d_out,
        faces=faces,
        values=values,
        directions=d_out,
        rgb=rgb,
        center=c.astype(dt),
        peak=peak.astype(dt),
        light=l64.astype(dt),
        width=float(width),
        rings=K,
        segments=S,
    )

r"""Polar slices of a BRDF: one direction fixed, the other swept across a plane through the normal.

The decks' *polar plot of reflectance strength*: "for one light direction, showing view
directions" (``fixed="light"``) and "for one view direction, showing light directions"
(``fixed="view"``).  The two agree for a reciprocal BRDF; :func:`reciprocity_pair` makes
both.  Options (``cosine``, ``channel``, ``log``, ``dtype``) as in
:mod:`lighting.analysis.quantity`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._text import quote
from .._validate import check_bool, check_choice, check_count
from . import _display
from .lobes import _lobe_widths, _numeric_width, _peak_candidates, _zoom_grid
from .quantity import (
    _HALF_PI,
    _check_angle,
    _check_brdf,
    _check_channel,
    _check_cosine,
    _check_phi,
    _check_tangent,
    _log_scale,
    _out_dtype,
    _plane_dirs,
    _quantity_rgb,
    _reduce,
    _sph,
)

__all__ = ["PolarSlice", "polar_slice", "reciprocity_pair"]


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
        The plotted quantity (see :mod:`lighting.analysis.quantity` on ``cosine``, ``channel``, ``log``).
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
    fixed, plane, cosine, log, channel, theta_in, phi_in, lock, tangent
        The options the slice was made with (``cosine`` normalized to ``None``, ``"light"`` or ``"view"``;
        ``tangent`` ``None`` or the unit tangent used).
    model : str
        The model's short name (its one-line repr).

    Printed, a slice is one line with its key numbers; in a notebook it shows as a polar plot.
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
    lock: bool = False
    tangent: np.ndarray | None = None
    model: str = ""

    __repr__ = _display.slice_repr
    _repr_png_ = _display.slice_png

    @property
    def xy(self) -> np.ndarray:
        """Cartesian curve in the slice plane: ``values · (sin angle, cos angle)``, shape ``values.shape + (2,)``.

        ``x`` runs along the plane (positive on the mirror side), ``y`` along the normal.
        On Matplotlib polar axes, plot ``(angles, values)`` with
        ``set_theta_zero_location("N")`` and ``set_theta_direction(-1)`` instead.

        Returns
        -------
        ndarray
            ``(..., 2)``: the ``x`` and ``y`` of every value.
        """
        s, c = np.sin(self.angles), np.cos(self.angles)
        if self.values.ndim == 2:
            s, c = s[:, None], c[:, None]
        return np.stack([self.values * s, self.values * c], axis=-1)


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
    tangent=None,
    lock=False,
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
    (:func:`~lighting.analysis.lobes.lobe_width` ``w`` at ``theta_in``: shininess above ~1e4 at ``n = 361``) would
    fall between samples, so 129 more samples at spacing ``w/8`` are merged in across
    ``mirror_angle ± 8w``; ``angles`` stays sorted but is then not uniform.

    ``phi_in`` turns the plane of incidence about the normal.  It is measured from the
    tangent ``t`` (``+x`` unless ``tangent`` says otherwise), so for an anisotropic model
    (Ward, Ashikhmin–Shirley, anisotropic Cook–Torrance) ``phi_in = 0`` cuts the lobe along
    ``α_x`` and ``phi_in = π/2`` along ``α_y``; an isotropic model gives the same slice at
    every ``phi_in``.  An anisotropic lobe refines on its narrower axis, and its largest value
    may lie off the plane (:func:`~lighting.analysis.lobes.lobe_peak` finds it there): the slice,
    a cut, then peaks below it.

    ``lock=True`` is BRDF Explorer's *view lock*: the view follows the light,
    ``θ_v = θ_l`` and ``φ_v = φ_l``, and the swept direction ``d(t)`` is both ``l`` and
    ``v``.  The slice is then the **retro-reflection** curve ``f_r(d, d)`` across the plane
    (``theta_in`` and ``fixed`` only mark the current light); a specular lobe shows there as
    a peak at the normal (``R_d = d`` only at ``t = 0``), back-scattering (rough diffuse
    surfaces) as a rise toward grazing.

    ``cosine=True`` (``"light"``) plots ``f_r (n·l)``: with ``fixed="light"`` that is the
    constant ``cos theta_in`` times ``f_r`` (and removes Phong's ``1/(n·l)``), with
    ``fixed="view"`` it is ``cos t`` times ``f_r``.  ``cosine="view"`` multiplies by
    ``n·v`` instead.

    Parameters
    ----------
    brdf : lighting.models.brdf.BRDF
        The model.
    theta_in : float
        Polar angle of the fixed direction, in ``[0, π/2]``.
    fixed : {"light", "view"}
        Which direction is fixed; the other is swept.
    phi_in : float
        Azimuth of the fixed direction.
    n : int
        Number of samples, 2 … 100001 (default 361: half-degree steps).
    plane : {"incidence", "perpendicular"}
        The plane containing ``n`` and the fixed direction, or the plane through ``n``
        perpendicular to it.
    cosine, log, channel, dtype
        See :mod:`lighting.analysis.quantity`.
    refine : bool
        Add samples across a lobe too narrow for the uniform grid.
    tangent : array_like (3,), optional
        The surface tangent ``t`` in the local frame (its part in the plane ``z = 0``): the
        azimuth origin of anisotropic models.  Default: the models' own frame, ``t = +x``.
    lock : bool
        The view follows the light (retro-reflection slice, see above).

    Returns
    -------
    PolarSlice
        The angles, values and directions of the slice, with the options it was made with.

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
    count = check_count("n", n, 2, 100001)
    cos_mode = _check_cosine(cosine)
    log = check_bool("log", log)
    ch = _check_channel(channel, "rgb")
    refine = check_bool("refine", refine)
    dt = _out_dtype(dtype, theta_in)
    tan = _check_tangent(tangent)
    lock = check_bool("lock", lock)
    in_plane = plane == "incidence"

    if lock:
        t = _retro_angles(brdf, count, refine)
    else:
        t = _slice_angles(brdf, theta, phi, count, plane, refine, cos_mode, ch, tan)
    sweep = _plane_dirs(t, phi, plane)
    d_fixed = _sph(theta, phi)
    mirror = np.array([-d_fixed[0], -d_fixed[1], d_fixed[2]])
    fixed_b = np.broadcast_to(d_fixed, sweep.shape)
    if lock:
        l = v = sweep  # noqa: E741 - θ_v = θ_l, φ_v = φ_l
    else:
        l, v = (fixed_b, sweep) if fixed == "light" else (sweep, fixed_b)  # noqa: E741
    values = _log_scale(_reduce(_quantity_rgb(brdf, l, v, cos_mode, dt, tan), ch), log)
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
        lock=lock,
        tangent=tan,
        model=_display.model_label(brdf),
    )


def reciprocity_pair(brdf, theta_in, **kwargs) -> tuple[PolarSlice, PolarSlice]:
    """Both polar slices at ``theta_in``: ``(fixed="light", fixed="view")``.

    For a reciprocal BRDF (Lambert, normalized Blinn–Phong, Cook–Torrance) the two
    ``values`` arrays are equal; for the slides' Phong BRDF their ratio is
    ``light / view = (n·v)/(n·l) = cos t / cos theta_in``.  ``kwargs`` are those of
    :func:`polar_slice` (except ``fixed``).

    Parameters
    ----------
    brdf : lighting.models.brdf.BRDF
        The model.
    theta_in : float
        Polar angle of the fixed direction, in ``[0, π/2]``.
    **kwargs
        Options of :func:`polar_slice` other than ``fixed``.

    Returns
    -------
    (PolarSlice, PolarSlice)
        The slice with the light fixed, then the slice with the view fixed.

    Examples
    --------
    >>> from lighting import BlinnPhong
    >>> a, b = reciprocity_pair(BlinnPhong(1.0, 50, normalized=True), 0.7, n=91)
    >>> bool(np.allclose(a.values, b.values, rtol=1e-12, atol=0))
    True
    """
    if "fixed" in kwargs:
        raise ValueError(f"fixed must not be given: reciprocity_pair makes both slices; got {quote(kwargs['fixed'])}")
    return polar_slice(brdf, theta_in, fixed="light", **kwargs), polar_slice(brdf, theta_in, fixed="view", **kwargs)


def _retro_angles(brdf, count, refine):
    """Signed sample angles of a retro-reflection slice (``l = v = d(t)``): the grid, plus the normal's lobe.

    With ``l = v`` at polar angle ``t`` the mirror direction is ``2t`` away, so a specular lobe of
    width ``w`` (at normal incidence) shows as a peak of width ``w/2`` about ``t = 0``; below four grid
    spacings it gets 129 more samples across ``±8 · w/2``, as :func:`_slice_angles` does for the mirror.
    """
    t = np.linspace(-_HALF_PI, _HALF_PI, count)
    if not refine:
        return t
    w = 0.5 * _lobe_widths(brdf, 0.0)[0]
    if w < 4 * math.pi / (count - 1):  # False for inf and nan
        extra = w * np.linspace(-8.0, 8.0, 129)
        t = np.union1d(t, extra[np.abs(extra) < _HALF_PI])
    return t


def _slice_angles(brdf, theta, phi, count, plane, refine, cosine, channel, tangent=None):
    """Signed sample angles of a slice: the uniform grid, plus where the lobe is.

    With ``refine``: a lobe narrower than four grid spacings gets 129 samples at spacing
    ``w/8`` across ``±8 w`` about the mirror angle (the normal in the perpendicular plane);
    in the plane of incidence the peak of the lobe (:func:`_slice_peaks`: with the light
    fixed and with the view fixed, with and without the cosine factors, so that both slices
    of :func:`reciprocity_pair` and every ``cosine`` option share their angles) is a sample
    too.  A narrow highlight off the grid, or one a hair above the horizon (rough
    Cook–Torrance lit at grazing, Oren–Nayar's backscatter), is then drawn at its true height, the
    height :func:`~lighting.analysis.lobes.lobe_peak` reports and :func:`~lighting.analysis.meshes.lobe_mesh`
    draws.
    """
    t = np.linspace(-_HALF_PI, _HALF_PI, count)
    if not refine:
        return t
    in_plane = plane == "incidence"
    scalar = "luminance" if channel == "rgb" else channel
    w = _lobe_widths(brdf, theta)[0]
    if math.isnan(w):
        w = _numeric_width(brdf, _sph(theta, phi), None, scalar, tangent)  # the options must not move the samples
    extra = []
    if w < 4 * math.pi / (count - 1):  # False for inf
        extra.append((theta if in_plane else 0.0) + w * np.linspace(-8.0, 8.0, 129))
    if in_plane and theta < _HALF_PI:
        peaks = np.asarray(_slice_peaks(brdf, theta, phi, scalar, w, tangent))
        if not math.isfinite(w):
            # Without a lobe the grid holds the peak, except at the horizon's edge, which no grid sample reaches:
            # a broad model may peak there (Oren–Nayar's backscatter grows to grazing), as lobe_peak reports.
            peaks = peaks[np.abs(peaks) > abs(t[1])]
        extra.append(peaks)
    if extra:
        extra = np.concatenate([np.asarray(e, dtype=np.float64) for e in extra])
        t = np.union1d(t, extra[np.abs(extra) < _HALF_PI])
    return t


def _slice_peaks(brdf, theta, phi, channel, width, tangent=None):
    """Signed angles of the in-plane peaks a slice must sample, whatever its ``fixed`` and ``cosine``.

    The same search as :func:`lighting.analysis.lobes._peak_t` for four quantities at once: ``f`` and
    ``f (n·v)`` with the light fixed, ``f`` and ``f (n·l)`` with the view fixed (``f (n·l)`` with the
    light fixed is ``f`` times a constant, and so on).  One BRDF evaluation per round serves all four, so a slice pays
    about one search for them; and the angles do not depend on the slice's options, so both
    slices of :func:`reciprocity_pair` and the "× n·l" toggle keep their samples.
    """
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
        f = _reduce(_quantity_rgb(brdf, l, v, None, np.float64, tangent), channel)
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

    t, steps = _peak_candidates(theta, width)
    best = []
    for f in values([t] * len(variants)):
        k = int(np.argmax(f))
        best.append([float(t[k]), float(f[k]), float(steps[k])])
    for _ in range(5):
        grids = [_zoom_grid(b[0], b[2]) for b in best]
        for b, tz, fz in zip(best, grids, values(grids), strict=True):
            k = int(np.argmax(fz))
            if fz[k] > b[1]:
                b[0], b[1] = float(tz[k]), float(fz[k])
            b[2] /= 10
    return [b[0] for b in best]

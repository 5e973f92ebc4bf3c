r"""A BRDF's specular lobe over view directions: its width and where it peaks.

The width is read from the model's own lobe description (``brdf.lobe()``: axis and
angular width, :class:`lighting.models.protocol.Lobe`), or measured on the slice when
the model gives none; the peak is found by a search in the plane of incidence and, for an
anisotropic lobe (unequal ``widths`` along ``t`` and ``b``), over the whole hemisphere.  The
polar slices (:mod:`lighting.analysis.slices`) and the lobe mesh
(:mod:`lighting.analysis.meshes`) use both, so every view of one lobe shows the same peak (a
slice, a cut through the plane of incidence, shows the largest value in that plane).
Options (``cosine``, ``channel``) as in :mod:`lighting.analysis.quantity`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._text import quote
from .._validate import check_vectors
from ..numerics import working_dtype
from . import _display
from .quantity import (
    _HALF_PI,
    _check_angle,
    _check_brdf,
    _check_channel,
    _check_cosine,
    _check_tangent,
    _plane_dirs,
    _quantity_rgb,
    _reduce,
    _sph,
)

__all__ = ["LobePeak", "lobe_width", "lobe_peak"]

#: Half-vector lobes are ``2 cos θ_l`` times their half-angle width across the plane of incidence, ``cos θ_l``
#: clamped here: at grazing the lobe is a thin sliver.
_MIN_COS = 0.1
#: Peak searches stop this far (rad) above the horizon, where every BRDF is 0.
_PEAK_LIMIT = _HALF_PI - 1e-9


class LobePeak(NamedTuple):
    """Where a BRDF lobe peaks for a fixed light: ``direction`` (3,) and scalar ``value``."""

    direction: np.ndarray
    value: float

    __repr__ = _display.lobe_peak_repr


# --------------------------------------------------------------------------- width
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
    # An anisotropic lobe is as narrow as its narrower axis (its ``width`` is the axes' geometric mean).
    h_width = min(lobe.widths) if lobe.widths is not None and math.isfinite(lobe.width) else lobe.width
    # Half-vector lobes: |dv| = 2 |dh| along the plane of incidence, 2 cos θ_d |dh| across it (θ_d = θ_l at R_l).
    return h_width * 2.0 * max(cos_l, _MIN_COS), h_width * 2.0


def _lobe_widths(brdf, theta_l) -> tuple[float, float]:
    """``(across, along)`` of the narrowest lobe among ``brdf.parts``; ``nan`` if a part's lobe is unknown."""
    widths = [_part_widths(p, math.cos(theta_l)) for p in brdf.parts]
    if any(math.isnan(w[0]) for w in widths):
        return math.nan, math.nan
    return min(widths)


def _half_ellipse(brdf, theta_l, tangent=None):
    """The slopes of the narrowest lobe's half vectors per unit of its own width, if that lobe is anisotropic.

    A ``"half"`` lobe with ``widths = (w_t, w_b)`` is round in the stretched slopes ``u``: the half
    vector ``h ∝ (p, q, 1)`` has slopes ``(p, q) = A u`` with ``A = [w_t ê_t, w_b ê_b]`` (the axes
    ``ê_t``, ``ê_b`` in the plane ``z = 0``, turned by the lobe's ``orientation`` from the tangent), so
    one unit of ``u`` is one standard deviation along either axis (see
    :class:`lighting.models.protocol.Lobe`).  Returns ``A`` (2, 2), or ``None`` when the narrowest lobe
    (the one :func:`_lobe_widths` follows) is round, a mirror cone, unknown, or there is none.
    """
    cos_l = math.cos(theta_l)
    best, best_w = None, math.inf
    for part in brdf.parts:
        w = _part_widths(part, cos_l)[0]
        if math.isnan(w):
            return None
        if w < best_w:
            best, best_w = part, w
    if best is None:
        return None
    lobe = best.lobe()
    if lobe.axis != "half" or lobe.widths is None or lobe.widths[0] == lobe.widths[1]:
        return None
    t_az = 0.0 if tangent is None else math.atan2(tangent[1], tangent[0])
    az = t_az + lobe.orientation
    e_t = np.array([math.cos(az), math.sin(az)])
    e_b = np.array([-math.sin(az), math.cos(az)])
    return np.stack([lobe.widths[0] * e_t, lobe.widths[1] * e_b], axis=1)


def _reflect_slopes(s, l64):
    """View directions ``v = 2 (l·h) h − l`` for half vectors of slopes ``s`` (..., 2): ``h ∝ (p, q, 1)``."""
    h = np.concatenate([s, np.ones(s.shape[:-1] + (1,))], axis=-1)
    h = h / np.linalg.norm(h, axis=-1, keepdims=True)
    v = 2.0 * (h @ l64)[..., None] * h - l64
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _slopes_of(v, l64):
    """The slopes ``(p, q)`` of the half vector between ``l`` and the unit view ``v`` (both above the horizon)."""
    h = l64 + v
    return h[:2] / h[2]


def _numeric_width(brdf, l64, cosine, channel, tangent=None) -> float:
    """Half-width at half maximum of the in-plane slice, divided by 1.18 (a Gaussian's σ)."""
    theta, phi = _angles_of(l64)
    t = np.linspace(-_HALF_PI, _HALF_PI, 2881)[1:-1]
    v = _plane_dirs(t, phi, "incidence")
    l = np.broadcast_to(_sph(theta, phi), v.shape)  # noqa: E741
    f = _reduce(_quantity_rgb(brdf, l, v, cosine, np.float64, tangent), channel)
    k = int(np.argmax(f))
    if not f[k] > 0 or np.all(f >= 0.5 * f[k]):
        return math.inf
    below = np.flatnonzero(f < 0.5 * f[k])
    dist = np.abs(below - k).min() * (t[1] - t[0])
    return max(dist / 1.18, 1e-4)


def lobe_width(brdf, theta_l=0.0) -> float:
    r"""Angular width (rad) of the narrowest specular lobe of ``brdf`` over view directions; ``inf`` if none.

    A standard deviation estimated from the model's parameters (its ``lobe()``), for a
    light at polar angle ``theta_l``:

    * Phong, ``(R_l·v)^e ≈ exp(−e ψ²/2)``: ``1/√e``, the same at every incidence;
    * half-vector lobes — Blinn–Phong ``(n·h)^e ≈ exp(−e θ_h²/2)`` (``θ_h`` width ``1/√e``)
      and Cook–Torrance (Beckmann ``exp(−θ_h²/α²)``, width ``α/√2``; GGX and the
      Blinn–Phong NDF are no wider at the peak) — map to view directions through
      ``|dv| = 2 cos θ_d |dh|`` across the plane of incidence (``θ_d = θ_l`` at the
      mirror direction), so their width is ``2 cos θ_l`` times the half-angle width
      (``cos θ_l`` clamped at 0.1: at grazing the lobe is a thin sliver); along the
      plane it is ``2`` times the half-angle width, and :func:`~lighting.analysis.meshes.lobe_mesh`
      stretches its grid by that aspect ratio;
    * an anisotropic lobe (``lobe().widths`` along ``t`` and ``b`` unequal: Ward, Ashikhmin–Shirley,
      anisotropic Cook–Torrance) as its narrower axis;
    * the minimum over the parts of a sum, ignoring parts whose coefficient is 0;
      Lambert and ``e = 0`` have no lobe (``inf``).

    Parameters
    ----------
    brdf : lighting.models.brdf.BRDF
        The model; a sum is measured part by part (``brdf.parts``).
    theta_l : float
        Polar angle of the light, in ``[0, π/2]``.

    Returns
    -------
    float
        The width in radians; ``inf`` without a lobe, ``nan`` for a model whose ``lobe()``
        is ``None`` (:func:`~lighting.analysis.meshes.lobe_mesh` then measures the width numerically).

    Examples
    --------
    >>> from lighting import Lambert, Phong
    >>> lobe_width(Lambert(0.5) + Phong(0.5, 100))
    0.1
    """
    _check_brdf(brdf)
    return _lobe_widths(brdf, _check_angle("theta_l", theta_l, 0.0, _HALF_PI))[0]


# --------------------------------------------------------------------------- peak
def _angles_of(d):
    """Polar angle and azimuth of a unit direction (float64)."""
    return math.atan2(math.hypot(d[0], d[1]), d[2]), math.atan2(d[1], d[0])


def _polar(d) -> float:
    """Polar angle of a unit direction, at most ``π/2``."""
    return min(_angles_of(d)[0], _HALF_PI)


def _unit_light(l):  # noqa: E741
    arr = check_vectors("l", l, dtype=np.float64, nonzero=True)
    if arr.shape != (3,):
        raise ValueError(f"l must be one direction of shape (3,); got shape {arr.shape}: {quote(l)}")
    m = np.max(np.abs(arr))
    s = arr / m
    return s / math.sqrt(float(s @ s))


def _peak_candidates(theta, width):
    """Signed angles where an in-plane peak search starts, and the spacing of the grid each comes from.

    The mirror angle ``theta`` first (so that a flat lobe such as Lambert's reports ``R_l``),
    then a fine grid of ±8 widths around it at spacing ``width/10`` (if the width is finite),
    then a quarter-degree grid across the plane.
    """
    lim = _PEAK_LIMIT
    coarse = np.linspace(-lim, lim, 721)
    coarse_step = coarse[1] - coarse[0]
    fine_step = width / 10 if math.isfinite(width) else coarse_step
    t = [np.array([min(theta, lim)]), coarse]
    steps = [np.array([min(fine_step, coarse_step)]), np.full(coarse.shape, coarse_step)]
    if math.isfinite(width):
        t.insert(1, np.clip(theta + width * np.linspace(-8.0, 8.0, 161), -lim, lim))
        steps.insert(1, np.full(161, fine_step))
    return np.concatenate(t), np.concatenate(steps)


def _zoom_grid(t, step):
    """One zoom of a peak search: ``t`` itself, then 41 samples at spacing ``step/10`` across ``t ± 2 step``."""
    return np.concatenate([[t], np.clip(t + step * np.linspace(-2.0, 2.0, 41), -_PEAK_LIMIT, _PEAK_LIMIT)])


def _peak_t(brdf, theta, phi, cosine, channel, width, fixed="light", d_fixed=None, tangent=None):
    """Search the incidence plane for the largest value; returns ``(t, value)``, ``t`` the signed angle.

    The fixed direction (``l`` for ``fixed="light"``, else ``v``) is at polar angle ``theta``,
    azimuth ``phi``; the other is swept as in :func:`~lighting.analysis.slices.polar_slice`, so the
    mirror direction is at ``t = theta``.  Isotropic models are mirror-symmetric about the plane of
    incidence, and every model here peaks in it (at ``R_l``, or off-specular toward grazing for rough
    Cook–Torrance); so do anisotropic ones when the plane holds ``t`` or ``b``, and elsewhere the search
    finds the largest value *in the plane*, which is what the slices draw.  Candidates:
    :func:`_peak_candidates`; then five zooms around the best.
    """
    d_fixed = _sph(theta, phi) if d_fixed is None else d_fixed

    def value(t):
        sweep = _plane_dirs(t, phi, "incidence")
        fixed_b = np.broadcast_to(d_fixed, sweep.shape)
        l, v = (fixed_b, sweep) if fixed == "light" else (sweep, fixed_b)  # noqa: E741
        return _reduce(_quantity_rgb(brdf, l, v, cosine, np.float64, tangent), channel)

    t, steps = _peak_candidates(theta, width)
    f = value(t)
    k = int(np.argmax(f))
    # Zoom on the best candidate with the spacing of the grid it came from.
    best_t, best_f, step = float(t[k]), float(f[k]), float(steps[k])
    for _ in range(5):
        tz = _zoom_grid(best_t, step)
        fz = value(tz)
        k = int(np.argmax(fz))
        if fz[k] > best_f:
            best_t, best_f = float(tz[k]), float(fz[k])
        step /= 10
    return best_t, best_f


def _peak64(brdf, l64, cosine, channel, width, tangent=None):
    """The peak for the light ``l64``: ``(direction, value)`` in float64.

    The in-plane search (:func:`_peak_t`); for an anisotropic lobe (:func:`_half_ellipse`) also a search
    over the whole hemisphere (:func:`_peak_2d`), whose answer wins if it is larger: such a lobe is a
    ridge along its wide axis, and its largest value may lie anywhere on the ridge, off the plane.
    """
    theta, phi = _angles_of(l64)
    t, f = _peak_t(brdf, theta, phi, cosine, channel, width, d_fixed=l64, tangent=tangent)
    d = _plane_dirs(t, phi, "incidence")
    ellipse = _half_ellipse(brdf, theta, tangent)
    if ellipse is not None:
        d2, f2 = _peak_2d(brdf, l64, cosine, channel, ellipse, d, tangent)
        if f2 > f * (1 + 1e-12):
            return d2, f2
    return d, f


#: The 2D peak search: a grid of ±8 widths at a quarter width in the stretched slopes, then zooms.
_GRID_WIDTHS, _GRID_STEP, _ZOOMS, _ZOOM_SHRINK = 8.0, 0.25, 14, 0.4
#: The horizon's edge of the 2D search: the steps its length is summed over, and the most candidates on it.
_RIM_GEOMETRY, _RIM_CANDIDATES = 4096, 50_000


def _peak_2d(brdf, l64, cosine, channel, ellipse, start, tangent=None):
    """The largest value over the hemisphere of an anisotropic lobe: ``(direction, value)``.

    The half vectors are laid out in the stretched slopes ``u`` of :func:`_half_ellipse`, where the lobe
    is round with unit width: a grid over ``±8`` units at spacing ``1/4``, plus ``start`` (the in-plane
    peak), then zooms (an 11 × 11 grid across ``±2`` steps, the step shrinking by ``0.4`` each time, 14
    times: to ~1e-6 of a width).  Views closer to the horizon than the in-plane search goes count as 0;
    the edge at that limit, where a ridge often peaks, is searched on its own (candidates half a width
    apart along it, at most 50 000, then zooms) and the larger of the two answers wins.
    """
    a_inv = np.linalg.inv(ellipse)
    z_min = math.cos(_PEAK_LIMIT)

    def value(u):
        v = _reflect_slopes(u @ ellipse.T, l64)
        f = _reduce(_quantity_rgb(brdf, np.broadcast_to(l64, v.shape), v, cosine, np.float64, tangent), channel)
        return np.where(v[:, 2] >= z_min, f, -np.inf), v

    g = np.arange(-_GRID_WIDTHS, _GRID_WIDTHS + _GRID_STEP / 2, _GRID_STEP)
    u = np.stack(np.meshgrid(g, g, indexing="ij"), axis=-1).reshape(-1, 2)
    if start[2] > 0:
        u = np.concatenate([u, (a_inv @ _slopes_of(start, l64))[None, :]])
    f, v = value(u)
    k = int(np.argmax(f))
    best_u, best_f, best_v = u[k], float(f[k]), v[k]
    step = _GRID_STEP
    offsets = np.linspace(-2.0, 2.0, 11)
    zoom = np.stack(np.meshgrid(offsets, offsets, indexing="ij"), axis=-1).reshape(-1, 2)
    for _ in range(_ZOOMS):
        fz, vz = value(best_u + step * zoom)
        k = int(np.argmax(fz))
        if fz[k] > best_f:
            best_u, best_f, best_v = best_u + step * zoom[k], float(fz[k]), vz[k]
        step *= _ZOOM_SHRINK
    # The largest value of a ridge is often where it meets the horizon: search that edge on its own, in the
    # slopes whose views lie just inside the search's limit (a circle, see lighting.analysis.meshes._rim_circle).
    z = 2.0 * z_min  # inside the limit by far more than v_z rounds (its terms are ~1, it is ~1e-9)
    m = l64[2] + z
    centre = l64[:2] / m
    radius = math.sqrt(max(float(centre @ centre) + 2 * l64[2] / m - 1.0, 0.0))

    def rim_value(beta):
        sl = centre + radius * np.stack([np.cos(beta), np.sin(beta)], axis=-1)
        return value(sl @ a_inv.T)

    # Candidates half a width apart along the edge, measured in the stretched slopes (where the lobe is
    # round): the edge crosses a narrow lobe in a small part of the circle.
    fine = np.linspace(-math.pi, math.pi, _RIM_GEOMETRY + 1)
    speed = radius * np.linalg.norm(np.stack([-np.sin(fine), np.cos(fine)], axis=-1) @ a_inv.T, axis=1)
    arc = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(fine))])
    count = int(min(max(arc[-1] / (2 * _GRID_STEP), 3600), _RIM_CANDIDATES))
    beta = np.interp(np.linspace(0.0, arc[-1], count + 1), arc, fine)
    step = float(np.max(np.diff(beta)))
    f, v = rim_value(beta)
    k = int(np.argmax(f))
    rim_b, rim_f, rim_v = float(beta[k]), float(f[k]), v[k]
    for _ in range(_ZOOMS):
        bz = rim_b + step * np.linspace(-2.0, 2.0, 41)
        fz, vz = rim_value(bz)
        k = int(np.argmax(fz))
        if fz[k] > rim_f:
            rim_b, rim_f, rim_v = float(bz[k]), float(fz[k]), vz[k]
        step /= 10
    if rim_f > best_f:
        best_f, best_v = rim_f, rim_v
    return best_v, max(best_f, 0.0)


def lobe_peak(brdf, l, *, cosine=False, channel=None, tangent=None) -> LobePeak:
    r"""Direction ``v`` where ``f_r(l, v)`` (or the chosen quantity) is largest, and that value.

    The search runs in the plane of incidence — isotropic models are mirror-symmetric
    about it and peak in it — over a quarter-degree grid plus ±8 lobe widths around ``R_l``,
    then zooms five times around the best sample, down to ~1e-6 of the grid spacing.  For
    Phong and Blinn–Phong the answer is the mirror direction ``R_l = 2 n (n·l) − l``; rough
    Cook–Torrance peaks off-specular, toward grazing.  Ties (a Lambertian lobe is flat) resolve
    to ``R_l``.  An anisotropic lobe (the model's ``lobe()`` gives unequal ``widths``) is a ridge
    whose largest value may lie off the plane (Ward with ``α_x = 10⁻³``, ``α_y = 1`` rises along it
    toward the horizon): it is also searched over the whole hemisphere, in the slopes of its half
    vectors stretched by its widths (where it is round), and along the horizon's edge of the
    search, and the largest value found wins.  A light on or below the horizon gives ``(n, 0)``.

    Parameters
    ----------
    brdf : lighting.models.brdf.BRDF
        The model.
    l : array_like (3,)
        Light direction in the local frame (``n = +z``); normalized on entry.
    cosine, channel
        See :mod:`lighting.analysis.quantity`; ``channel=None`` means luminance.
    tangent : array_like (3,), optional
        The surface tangent (see :func:`~lighting.analysis.slices.polar_slice`); default ``+x``.

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
    tan = _check_tangent(tangent)
    if not l64[2] > 0:
        return LobePeak(np.array([0.0, 0.0, 1.0], dtype=dt), 0.0)
    w = _lobe_widths(brdf, _polar(l64))[0]
    if math.isnan(w):
        w = _numeric_width(brdf, l64, cos_mode, ch, tan)
    d, f = _peak64(brdf, l64, cos_mode, ch, w, tan)
    return LobePeak(d.astype(dt), f)

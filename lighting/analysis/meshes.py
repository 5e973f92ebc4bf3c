r"""The "3D surface" plot of a BRDF: a mesh whose radius in every view direction is the BRDF's value.

The grid is polar about the lobe's peak and graded on the lobe's width
(:mod:`lighting.analysis.lobes`), so a narrow highlight gets as many vertices as a broad
one; a lobe narrow along one axis and wide along the other (a ridge) is meshed about the
pole of its ridge, with rings along it.  Options (``cosine``, ``channel``) as in
:mod:`lighting.analysis.quantity`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import check_bool, check_count
from ..numerics import working_dtype
from ..vec import normalize
from . import _display
from .lobes import _MIN_COS, _half_ellipse, _lobe_widths, _numeric_width, _peak64, _polar, _unit_light
from .quantity import (
    _HALF_PI,
    _check_brdf,
    _check_channel,
    _check_cosine,
    _check_tangent,
    _quantity_rgb,
    _reduce,
    _sph,
)

__all__ = ["LobeMesh", "lobe_mesh", "VERTEX_BUDGET"]

#: Elevation (rad) of the rim of a lobe mesh: the rim shows the grazing limit of the BRDF, not its zero on the horizon.
_RIM_ELEVATION = 1e-6
#: Lobes at least this wide (rad) are meshed on a plain hemisphere grid about the normal.
_BROAD = 0.5
#: Ring spacing at the lobe centre, in lobe widths, and the number of widths meshed at that spacing.
_CORE_STEP = 1.0 / 6.0
_CORE_WIDTHS = 3.0
_MAX_RESOLUTION = 99
#: The most vertices a lobe mesh has (at ``resolution=99``): ``1 + 2·99² = 19603``, whatever the lobe.
VERTEX_BUDGET = 1 + 2 * _MAX_RESOLUTION**2


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
        Pole of the polar grid (vertex 0): the lobe peak, ``n`` for broad lobes, the pole of the
        ridge (a point just above the horizon) for an anisotropic lobe.
    peak : ndarray (3,)
        Direction of the largest value found by :func:`~lighting.analysis.lobes.lobe_peak`.
    light : ndarray (3,)
        The unit light direction.
    width : float
        Lobe width (rad) across the plane of incidence (across the ridge for an anisotropic lobe),
        used to grade the grid (``inf`` when there is no lobe).
    rings, segments : int
        Grid layout: vertex 0 is the centre, ring ``k = 1 … rings`` holds vertices
        ``1 + (k−1)·segments … k·segments``; the last ring is the rim.
    cosine, channel
        The options the mesh was made with (``cosine`` normalized to ``None``, ``"light"`` or ``"view"``).
    model : str
        The model's short name (its one-line repr).

    Printed, a mesh is one line with its counts and peak; in a notebook it shows as a 3D plot.
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
    cosine: str | None = None
    channel: object = None
    model: str = ""

    __repr__ = _display.mesh_repr
    _repr_png_ = _display.mesh_png


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


def _fit_to_rim(rho: np.ndarray, rho_max: np.ndarray, keep=None) -> np.ndarray:
    """Per azimuth, map the common radii ``rho`` (ending at ``rho[-1] >= rho_max``) onto ``[0, rho_max]``.

    The inner half, ``ρ <= b = rho_max/2``, is kept as is, so that neighbouring
    azimuths share their rings where the lobe is (no skewed triangles); beyond it
    ``b + λ log1p((ρ − b)/λ)`` compresses the rest onto the rim.  ``λ`` solves
    ``λ log1p((ρ_end − b)/λ) = rho_max − b`` (the map ends at ``rho_max``), which also
    makes it C¹ at ``b``; logarithmic compression of geometric rings spaces them
    evenly, so no rings pile up even where the rim is very close to the pole.  ``keep`` (per azimuth,
    ``< rho_max``) replaces ``b``: the radii kept as they are.
    """
    r_end = float(rho[-1])
    b = 0.5 * rho_max if keep is None else keep
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


def _graded(length: float, n: int, delta: float) -> np.ndarray:
    """``n + 1`` offsets ``0 … length``: steps ``δ q, δ q², …`` growing geometrically (uniform if ``n δ ≥ length``)."""
    if n <= 0:
        return np.array([0.0])
    target = length / delta
    if target <= n:
        return np.linspace(0.0, length, n + 1)

    def log_expm1(x):
        return x + math.log1p(-math.exp(-x)) if x > 30.0 else math.log(math.expm1(x))

    # Bisection on log q for Σ_{j=1}^{n} q^j = length/δ, in logarithms (q^n may be far beyond float range).
    lo, hi = 0.0, math.log(target) + 1.0
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        log_total = mid + log_expm1(n * mid) - log_expm1(mid)
        lo, hi = (mid, hi) if log_total < math.log(target) else (lo, mid)
    q = math.exp(0.5 * (lo + hi))
    x = np.concatenate([[0.0], np.cumsum(delta * q ** np.arange(1, n + 1))])
    x *= length / x[-1]
    x[-1] = length
    return x


def _ridge_profile(alpha0: float, rho_ref: float, K: int, delta: float):
    """Ring radii ``0 < ρ_1 < … < ρ_K = rho_ref`` graded on the ridge at radius ``alpha0``; and the core's end.

    A core of rings at spacing ``δ`` across ``alpha0 ± 12 δ`` (two widths each side; at most half the
    rings), geometric steps growing from ``δ`` inward to the centre and outward to ``rho_ref``, the
    rings outside the core shared in proportion to the logarithm of the lengths they span.
    """
    lo = max(alpha0 - 12 * delta, 0.0)
    hi = min(alpha0 + 12 * delta, rho_ref)
    n_core = max(1, min(K // 2, round((hi - lo) / delta)))
    rest = K - n_core
    span_in, span_out = lo, rho_ref - hi
    w_in = math.log1p(span_in / delta)
    w_out = math.log1p(span_out / delta)
    k_in = 0 if span_in <= 0 else max(1, min(rest - (span_out > 0), round(rest * w_in / max(w_in + w_out, 1e-300))))
    k_out = rest - k_in
    if span_out <= 0:  # the core reaches the farthest rim: its rings take the rest
        n_core, k_out = n_core + k_out, 0
    inner = lo - _graded(span_in, k_in, delta)[::-1]
    core = np.linspace(lo, hi, n_core + 1)
    outer = hi + _graded(span_out, k_out, delta)
    rho = np.concatenate([inner[:-1], core, outer[1:]])
    rho[0], rho[-1] = 0.0, rho_ref
    return rho, hi


def _ridge_grid(l64, ellipse, peak, K, S, rim_elevation, ulp_floor):
    """Directions (1 + K·S, 3) of the grid of a lobe narrow along one axis ``ê`` and wider along the other.

    Half vectors tilted along the wide axis only (perpendicular to ``ê``) reflect ``l`` into views with
    ``v·ê = −l·ê`` exactly: the ridge of the lobe is a circle about ``±ê``, at the angle
    ``α_0 = arccos |l·ê|`` from its pole.  So the grid is polar about that pole (a point of the horizon,
    raised ``max(w/20, 1e-4)`` above it): the ridge runs along the rings, which are graded on the narrow
    width ``w`` about ``α_0`` (:func:`_ridge_profile`), and the azimuths are graded on the wide width
    about the peak's azimuth, so consecutive vertices across the ridge are a sixth of its width apart
    all along it.  The peak lies on a column; the nearest vertex on it moves onto the peak.
    Returns ``(dirs, centre, width)``, ``width`` the narrow width (rad) across the ridge.
    """
    norms = np.linalg.norm(ellipse, axis=0)
    narrow = int(np.argmin(norms))
    e2 = ellipse[:, narrow] / norms[narrow]
    e = np.array([e2[0], e2[1], 0.0])
    w_n, w_w = float(norms[narrow]), float(norms[1 - narrow])
    l_e = float(l64 @ e)
    pole = -e if l_e > 0 else e  # the ridge v·ê = −l·ê lies on this side
    alpha0 = math.acos(min(abs(l_e), 1.0))
    cos_d = max(float(l64[2]), _MIN_COS)
    sin0 = max(math.sin(alpha0), _MIN_COS)
    width = 2.0 * cos_d * w_n / sin0  # across the ridge: |dv| = 2 (l·h) |dh|, as an angle from the pole
    along = 2.0 * cos_d * w_w / sin0  # along it, as an azimuth about the pole
    # The ridge is a circle about the pole itself; about the raised centre it wanders by up to the raise.
    gap = max(0.05 * width, 1e-4)
    theta_c, phi_c = _HALF_PI - gap, math.atan2(pole[1], pole[0])
    c = _sph(theta_c, phi_c)
    a, s = math.cos(theta_c), math.sin(theta_c)
    t1 = np.array([-a * math.cos(phi_c), -a * math.sin(phi_c), s])  # from c toward the normal
    t2 = np.cross(c, t1)
    # Azimuths about c: graded on the wide width about the peak's, one column through the peak.
    chi_p = math.atan2(float(peak @ t2), float(peak @ t1))
    half = S // 2
    offsets = _graded(math.pi, half, max(_CORE_STEP * along, ulp_floor))
    chi = chi_p + np.concatenate([-offsets[half - 1 : 0 : -1], offsets[: half + 1]])[: S]
    cchi, schi = np.cos(chi), np.sin(chi)
    R = np.hypot(a, s * cchi)
    psi_max = np.arctan2(s * cchi, a) + np.arccos(np.minimum(math.sin(rim_elevation) / R, 1.0))
    delta = max(_CORE_STEP * width, ulp_floor)
    rho, core_end = _ridge_profile(alpha0, float(psi_max.max()), K, delta)
    keep = np.clip(core_end, 0.5 * psi_max, psi_max * (1 - 1e-9) - 2 * delta)
    keep = np.maximum(keep, 0.5 * psi_max)
    psi = _fit_to_rim(rho, psi_max, keep)[1:]  # (K, S)
    col = half - 1  # the column of offset 0
    psi_p = math.acos(min(max(float(peak @ c), -1.0), 1.0))
    along_ray = np.concatenate([[0.0], psi[:, col]])
    k_p = max(int(np.argmin(np.abs(along_ray - psi_p))), 1)  # the centre is the pole, never the peak
    psi[k_p - 1, col] = psi_p
    radial = cchi[:, None] * t1 + schi[:, None] * t2
    dirs = np.cos(psi)[..., None] * c + np.sin(psi)[..., None] * radial[None, :, :]
    dirs = normalize(np.concatenate([c[None, :], dirs.reshape(-1, 3)]))
    dirs[1 + (k_p - 1) * S + col] = peak
    return dirs, c, width


def _polar_grid(l64, peak, K, S, width, along, narrow, snap, rim_elevation, ulp_floor):
    """Directions (1 + K·S, 3) of the elliptic polar grid about the peak (narrow lobes) or the normal.

    See :func:`lobe_mesh`; returns ``(dirs, centre)``.
    """
    theta_c, phi_c, stretch = 0.0, 0.0, 1.0
    if snap:
        phi_c = math.atan2(peak[1], peak[0])  # the peak's azimuth is the grid's χ = π ray
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
    dirs = normalize(dirs)
    if peak_vertex is not None:
        dirs[peak_vertex] = peak  # the same rounding as lobe_peak's direction, not a rebuilt one
    return dirs, c


def lobe_mesh(brdf, l, *, resolution=64, cosine=False, adaptive=True, channel=None, tangent=None,
              lock=False) -> LobeMesh:  # fmt: skip
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
    :func:`~lighting.analysis.lobes.lobe_width`: ``1/√e`` for Phong, ``2 cos θ_l/√e`` for Blinn–Phong,
    ``√2 α cos θ_l`` for Cook–Torrance):

    * ``c`` is the lobe peak (:func:`~lighting.analysis.lobes.lobe_peak`), kept at least ``max(w/2, 1e-4)``
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

    An anisotropic lobe (the model's ``lobe()`` gives unequal ``widths`` along ``t`` and ``b``;
    ``w`` is then the narrower) is a ridge: half vectors tilted along its wide axis only reflect ``l``
    into the circle ``v·ê = −l·ê`` about its narrow axis ``ê``, and its largest value may lie anywhere
    on it, off the plane of incidence (:func:`~lighting.analysis.lobes.lobe_peak` searches the
    hemisphere for it).  A polar grid about the peak would cross the ridge with its rings and draw a
    comb of spikes; so ``c`` is the pole of the ridge (the horizon point ``±ê``, raised
    ``max(w/20, 1e-4)``), the rings run along the ridge, graded on ``w`` about its radius
    ``arccos |l·ê|`` (24 rings at spacing ``w/6``, geometric steps inward and outward), and the
    azimuths are graded on the wide width about the peak's.  The peak lies on one column, and the
    vertex of that column nearest it moves onto it, as above.

    ``lock=True`` is the view lock of :func:`~lighting.analysis.slices.polar_slice`: the radius in
    direction ``d`` is ``f_r(d, d)`` (light and view together), the retro-reflection lobe; ``l`` then
    only marks the light.  Its grid is centred on the normal, where a specular lobe's retro-reflection
    peaks (graded on half the lobe's width at normal incidence).

    Vertex count ``1 + 2·resolution²`` (8193 by default, at most :data:`VERTEX_BUDGET` = 19603, for
    every lobe), faces ``2·segments·(rings − ½)``.  Faces are counter-clockwise seen from outside.

    Parameters
    ----------
    brdf : lighting.models.brdf.BRDF
        The model.
    l : array_like (3,)
        Light direction in the local frame (``n = +z``), normalized on entry.  A light
        on or below the horizon gives an all-zero lobe.
    resolution : int
        Number of rings, 4 … 99 (segments are twice that).
    cosine : bool or {"light", "view"}
        The factor ``n·l`` or ``n·v`` (see :mod:`lighting.analysis.quantity`).
    adaptive : bool
        Grade the grid on the lobe (see above); ``False``: a uniform grid about the normal.
    channel : None, 0, 1, 2, "r", "g", "b" or "luminance"
        The radius; ``None`` means luminance.  ``rgb`` always holds all three channels.
    tangent : array_like (3,), optional
        The surface tangent ``t`` (azimuth origin of anisotropic models); default ``+x``.
    lock : bool
        The view follows the light: the retro-reflection lobe ``f_r(d, d)``.

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
    K = check_count("resolution", resolution, 4, _MAX_RESOLUTION)
    cos_mode = _check_cosine(cosine)
    adaptive = check_bool("adaptive", adaptive)
    ch = _check_channel(channel, "luminance")
    tan = _check_tangent(tangent)
    lock = check_bool("lock", lock)
    S = 2 * K

    lit = l64[2] > 0 or lock
    width, along = math.inf, math.inf
    peak = np.array([0.0, 0.0, 1.0])
    ellipse = None
    if lock:
        # f(d, d): a specular lobe of width w about R_d is a cone of width w/2 about n (R_d = d at n only).
        width = along = 0.5 * _lobe_widths(brdf, 0.0)[0]
        width = along = math.inf if math.isnan(width) else width
    elif lit:
        width, along = _lobe_widths(brdf, _polar(l64))
        if math.isnan(width):
            width = along = _numeric_width(brdf, l64, cos_mode, ch, tan)
        peak, _ = _peak64(brdf, l64, cos_mode, ch, width, tan)
        if adaptive and width < _BROAD:
            ellipse = _half_ellipse(brdf, _polar(l64), tan)
    narrow = adaptive and width < _BROAD
    rim_elevation = _RIM_ELEVATION
    # The adaptive grid holds the peak as a vertex (see below), so the lobe drawn reaches the
    # value lobe_peak reports and the slices show; a peak closer to the horizon than the rim (rough
    # Cook–Torrance lit at grazing, the ridge of an anisotropic lobe) lowers the rim.
    snap = adaptive and lit and not lock
    if snap:
        rim_elevation = min(rim_elevation, math.atan2(peak[2], math.hypot(peak[0], peak[1])))
    ulp_floor = 256 * float(np.finfo(dt).eps)
    if ellipse is not None:
        dirs, c, width = _ridge_grid(l64, ellipse, peak, K, S, rim_elevation, ulp_floor)
    else:
        dirs, c = _polar_grid(l64, peak, K, S, width, along, narrow, snap, rim_elevation, ulp_floor)

    j = np.arange(S)
    jn = (j + 1) % S
    fan = np.stack([np.zeros(S, dtype=np.int64), 1 + j, 1 + jn], axis=1)
    k = np.arange(K - 1)[:, None]
    ia, ib = 1 + k * S + j, 1 + k * S + jn  # inner ring
    oa, ob = ia + S, ib + S  # outer ring
    quads = np.concatenate([np.stack([ia, oa, ob], -1), np.stack([ia, ob, ib], -1)], axis=1).reshape(-1, 3)
    faces = np.concatenate([fan, quads]).astype(np.int64)

    d_out = dirs.astype(dt)
    if lock:
        rgb = _quantity_rgb(brdf, d_out, d_out, cos_mode, dt, tan)
    elif lit:
        rgb = _quantity_rgb(brdf, np.broadcast_to(l64, dirs.shape), d_out, cos_mode, dt, tan)
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
        cosine=cos_mode,
        channel=channel,
        model=_display.model_label(brdf),
    )

"""The latitude–longitude layout of environment images: directions to pixels and back, and the lookup.

One home for the layout every environment image uses (:class:`lighting.lights.environment.LatLongEnvironment`,
the prefiltered levels of :mod:`lighting.integrate.prefilter`, the sampler of
:mod:`lighting.sampling.environment`): ``+z`` up; row ``i`` of ``H`` centred at ``θ = (i + ½)π/H`` from ``+z``;
the horizontal image coordinate ``u`` looks along ``φ = π − 2π u`` (the common orientation of panoramas:
see :mod:`lighting.lights.environment` for the notes and the correspondence with other renderers).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["LATLONG_LEFT_EDGE_PHI", "latlong_angles", "latlong_azimuth", "latlong_lookup"]


def _pixel_rows(h: int) -> np.ndarray:
    """``cos θ`` at the ``h + 1`` row boundaries, computed so that the poles are exact."""
    return np.cos(np.linspace(0.0, math.pi, h + 1))


#: The azimuth ``φ`` that the left edge of a lat-long image looks along (see the module notes).
LATLONG_LEFT_EDGE_PHI = math.pi


def latlong_angles(directions):
    """``(θ, a)`` of ``directions`` ``(..., 3)`` in the lat-long layout: the image's two coordinates as angles.

    ``θ`` is measured from ``+z`` (rows), ``a = 2π u = (π − φ) mod 2π ∈ [0, 2π)`` is the column
    angle, growing with the column index (see the module notes for the orientation).

    Parameters
    ----------
    directions : ndarray, (..., 3)

    Returns
    -------
    theta, a : ndarray, (...)

    Examples
    --------
    >>> t, a = latlong_angles(np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]))  # +x: the centre; +y: a quarter in
    >>> (a / (2 * np.pi)).round(12).tolist()
    [0.5, 0.25]
    """
    d = directions
    phi = np.arctan2(d[..., 1], d[..., 0])
    # (π − φ) mod 2π without the division: π − φ lies in [0, 2π] (φ = arctan2 in [−π, π]), where the mod
    # leaves every value but 2π itself, which it takes to 0 (NaN stays NaN).
    a = LATLONG_LEFT_EDGE_PHI - phi
    if isinstance(a, np.ndarray):
        np.copyto(a, 0.0, where=a >= 2 * math.pi)
    else:
        a = np.mod(a, 2 * math.pi)
    return np.arctan2(np.hypot(d[..., 0], d[..., 1]), d[..., 2]), a


def latlong_azimuth(a):
    """The azimuth ``φ = π − a`` that the column angle ``a = 2π u`` of :func:`latlong_angles` looks along.

    Parameters
    ----------
    a : array_like

    Returns
    -------
    ndarray
        ``φ`` in radians (from ``+x`` toward ``+y``; not wrapped).
    """
    return LATLONG_LEFT_EDGE_PHI - np.asarray(a)


def latlong_lookup(flat, height: int, width: int, directions, poles=None, *, angles=None) -> np.ndarray:
    """Bilinear lookup of a lat-long image (the layout of :class:`LatLongEnvironment`) in ``directions``.

    The one home of the lat-long lookup: :class:`LatLongEnvironment` and the prefiltered levels of
    :mod:`lighting.integrate.prefilter` read their images through it.

    Parameters
    ----------
    flat : ndarray, (height * width, C)
        The image's pixels, row-major.
    height, width : int
    directions : ndarray, (..., 3)
        Directions (need not be unit; the zero vector reads the pixel at ``θ = 0``).
    angles : (ndarray, ndarray), optional
        :func:`latlong_angles` of ``directions``, when the caller has them (several images read at the
        same directions).
    poles : (ndarray (C,), ndarray (C,)), optional
        The values at the zenith and the nadir.  Given, a direction within half a row of a pole is
        interpolated linearly in ``θ`` between the pole and the edge row (whose azimuth there means
        little: at the pole every column meets); ``None``: the edge row's value, interpolated in ``φ``.

    Returns
    -------
    ndarray, (..., C)
        In the wider of the image's and the directions' float dtypes.
    """
    theta, a = latlong_angles(directions) if angles is None else angles
    (k00, k01, k10, k11), tx, ty, raw = _bilinear_taps(theta, a, height, width)
    sx, sy = 1 - tx, 1 - ty
    # Channel by channel from contiguous planes: a gather of whole rows of C values, and products broadcast
    # over an axis of length C, run C elements per inner loop.  Each value is the reference's arithmetic.
    planes = np.ascontiguousarray(flat.T)
    out = np.empty(np.shape(tx) + (flat.shape[1],), dtype=np.result_type(flat.dtype, tx.dtype, ty.dtype))
    for c, plane in enumerate(planes):
        top = plane.take(k00) * sx + plane.take(k01) * tx
        bot = plane.take(k10) * sx + plane.take(k11) * tx
        np.add(top * sy, bot * ty, out=out[..., c])
    if poles is not None:
        _near_poles(out, raw, height, poles)
    return out


def _bilinear_taps(theta, a, h: int, w: int):
    """The four texels around each direction's angles and its fractions across them.

    Returns ``((k00, k01, k10, k11), tx, ty, raw)``: flat indices of the texels above-left, above-right,
    below-left and below-right (columns wrap across the seam, rows clamp at the poles), the fractions
    ``tx`` across and ``ty`` down, and ``raw``, the row coordinate before clamping (:func:`_near_poles`).
    """
    fx = a * (w / (2 * math.pi)) - 0.5
    j0 = np.floor(fx)
    tx = fx - j0
    j0 = j0.astype(np.int64) % w
    j1 = (j0 + 1) % w
    raw = theta * (h / math.pi) - 0.5
    fy = np.clip(raw, 0.0, h - 1)
    i0 = np.minimum(np.floor(fy).astype(np.int64), max(h - 2, 0))
    ty = np.clip(fy - i0, 0.0, 1.0)
    i1 = np.minimum(i0 + 1, h - 1)
    r0, r1 = i0 * w, i1 * w
    return (r0 + j0, r0 + j1, r1 + j0, r1 + j1), tx, ty, raw


def _near_poles(out, raw, h, poles):
    """Within half a row of a pole: from the pole's value (t = 0) to the edge row's (t = 1), linear in θ."""
    for value, t in ((poles[0], 2 * raw + 1), (poles[1], 2 * (h - 0.5 - raw))):
        near = t < 1
        if np.any(near):
            tt = np.clip(t[near], 0.0, 1.0)[..., None].astype(out.dtype)
            pole = np.asarray(value, dtype=out.dtype)
            out[near] = pole + tt * (out[near] - pole)


def _latlong_lookup_reference(flat, height: int, width: int, directions, poles=None, *, angles=None) -> np.ndarray:
    """:func:`latlong_lookup`'s blend as written, all channels at once (the taps and the poles are shared with it;
    tests hold the two equal)."""
    theta, a = latlong_angles(directions) if angles is None else angles
    (k00, k01, k10, k11), tx, ty, raw = _bilinear_taps(theta, a, height, width)
    tx, ty = tx[..., None], ty[..., None]
    top = np.take(flat, k00, axis=0) * (1 - tx) + np.take(flat, k01, axis=0) * tx
    bot = np.take(flat, k10, axis=0) * (1 - tx) + np.take(flat, k11, axis=0) * tx
    out = top * (1 - ty) + bot * ty
    if poles is not None:
        _near_poles(out, raw, height, poles)
    return out

"""Mach bands, measured.

Gouraud shading interpolates *colours* linearly inside each triangle, so the
intensity along a scan line is piecewise linear: its slope jumps at every
triangle edge, and the eye exaggerates each jump into a light or dark band
(Mach banding).  Phong interpolation lights every pixel with an interpolated
normal, so the intensity follows the smooth surface much more closely.

This module turns that into numbers:

* :func:`scanline_profile` — intensity along one image row, with its first and
  second differences (``ΔI``, ``Δ²I``);
* :func:`edge_jump_metric` — one number: the typical slope kink at the pixels
  where a scan line crosses a triangle edge, after the surface's own curvature
  is taken out, in display levels per pixel (after the sRGB encoding the eye
  sees).  It is 0 on a flat image and on one linear across the edges, small for
  smooth shading and large for Gouraud.

References
----------
F. Ratliff, *Mach Bands: Quantitative Studies on Neural Networks in the Retina*,
Holden-Day, 1965.
H. Gouraud, "Continuous Shading of Curved Surfaces", IEEE Transactions on Computers
C-20(6), 1971.
B. T. Phong, "Illumination for Computer Generated Pictures", Communications of the
ACM 18(6), 1975.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._text import quote
from .._validate import ArgumentTypeError, check_count, real_array
from . import _display
from .quantity import LUMINANCE

__all__ = ["Profile", "luminance", "scanline_profile", "edge_jump_metric", "KINK_SCALE"]

#: Rec. 709 / sRGB luminance weights of linear RGB (:data:`lighting.analysis.quantity.LUMINANCE`) as an array.
LUMA = np.array(LUMINANCE)


def _image(value, name: str = "image", *, gray_ok: bool = True) -> np.ndarray:
    allowed = "a finite linear image of shape (H, W, 3)" + (" or (H, W)" if gray_ok else "")
    img = real_array(name, value, allowed=allowed, dtype=np.float64)
    if not ((img.ndim == 3 and img.shape[-1] == 3) or (gray_ok and img.ndim == 2)):
        raise ValueError(f"{name} must be {allowed}; got shape {img.shape}: {quote(value)}")
    return img


def luminance(image) -> np.ndarray:
    """Relative luminance ``Y`` of a linear RGB image ``(..., 3)``.

    Parameters
    ----------
    image : array_like (..., 3)
        Finite linear RGB.

    Returns
    -------
    ndarray (...)
        ``Y = 0.2126 R + 0.7152 G + 0.0722 B`` (Rec. 709 weights, :data:`LUMA`), float64.
    """
    img = real_array("image", image, allowed="finite linear RGB of shape (..., 3)", dtype=np.float64)
    if img.shape[-1:] != (3,):
        raise ValueError(f"image must be finite linear RGB of shape (..., 3); got shape {img.shape}: {quote(image)}")
    return img @ LUMA


class Profile(NamedTuple):
    """Intensity along a scan line and its differences (all float64).

    Printed, one line with its length and ranges; in a notebook, a plot of ``I`` and ``Δ²I`` along the row.
    """

    x: np.ndarray  # pixel columns of the covered run
    intensity: np.ndarray  # I(x)
    d1: np.ndarray  # ΔI at x + ½ (len − 1)
    d2: np.ndarray  # Δ²I at x (len − 2, centred on x[1:-1])

    __repr__ = _display.profile_repr
    _repr_png_ = _display.profile_png


def _channel(image, channel) -> np.ndarray:
    img = _image(image)
    allowed = "'luminance', 'r', 'g', 'b' or an integer 0..2"
    if isinstance(channel, str):
        idx = {"luminance": None, "r": 0, "g": 1, "b": 2}.get(channel.lower(), -1)
    elif channel is None:
        idx = None
    elif isinstance(channel, (int, np.integer)) and not isinstance(channel, (bool, np.bool_)):
        idx = int(channel)
    else:
        raise ArgumentTypeError(f"channel must be {allowed}; got {type(channel).__name__} {quote(channel)}")
    if idx not in (None, 0, 1, 2):
        raise ValueError(f"channel must be {allowed}; got {quote(channel)}")
    if img.ndim == 2:
        return img
    return img @ LUMA if idx is None else img[..., idx]


def _mask(name: str, value, shape) -> np.ndarray:
    arr = np.asarray(value) if isinstance(value, np.ndarray) else None
    if arr is None or arr.dtype.kind != "b":
        arr = real_array(name, value, allowed=f"a boolean array of shape {shape}")
    if arr.shape != shape:
        raise ValueError(f"{name} must be a boolean array of shape {shape}; got shape {arr.shape}: {quote(value)}")
    return arr.astype(bool)


def scanline_profile(image, row: int, *, coverage=None, channel="luminance") -> Profile:
    """Intensity profile of one image row, restricted to the longest covered run.

    Parameters
    ----------
    image : array_like, (H, W, 3) or (H, W)
        Linear image.
    row : int
        Image row (0 = top).
    coverage : array_like of bool, (H, W), optional
        Pixels that show the object; default: all.
    channel : {"luminance", "r", "g", "b"}
        The intensity: luminance or one channel.

    Returns
    -------
    Profile
        The covered columns ``x``, ``intensity``, and its first and second differences.

    Examples
    --------
    >>> img = np.tile(np.array([0.0, 1.0, 2.0, 4.0]), (1, 1))
    >>> p = scanline_profile(img, 0)
    >>> p.d1.tolist(), p.d2.tolist()
    ([1.0, 1.0, 2.0], [0.0, 1.0])
    """
    y = _channel(image, channel)
    h, w = y.shape
    row = check_count("row", row, 0, h - 1)
    cov = np.ones(w, bool) if coverage is None else _mask("coverage", coverage, (h, w))[row]
    x = _longest_run(cov)
    vals = y[row, x]
    d1 = np.diff(vals)
    return Profile(x, vals, d1, np.diff(d1))


def _longest_run(mask: np.ndarray) -> np.ndarray:
    m = np.concatenate([[False], mask, [False]])
    starts = np.flatnonzero(~m[:-1] & m[1:])
    ends = np.flatnonzero(m[:-1] & ~m[1:])
    if starts.size == 0:
        return np.arange(0)
    k = np.argmax(ends - starts)
    return np.arange(starts[k], ends[k])


#: The visibility scale of :func:`edge_jump_metric`: a change of slope of one 8-bit display level per pixel.
KINK_SCALE = 1.0 / 255.0
#: Kinks within this many units of the image dtype's rounding (relative to the values they are made of) count as 0:
#: an interpolated flat image wobbles by a few ulp, which no display shows.
_ROUNDING_ULPS = 64.0
#: sRGB's linear segment ends here (:func:`lighting.render.image.linear_to_srgb`).
_SRGB_KNEE = 0.0031308
#: Offsets (from the edge's index ``k`` into the second differences) of the curvature estimate beside an edge.
_SIDE = np.array([-5, -4, -3, -2, 1, 2, 3, 4])


def _srgb_slope(x: np.ndarray) -> np.ndarray:
    """The slope of the sRGB encoding: 12.92 on its linear segment, 0 where the display clips (x ≤ 0, x ≥ 1)."""
    xs = np.clip(x, _SRGB_KNEE, 1.0)
    power = (1.055 / 2.4) * np.power(xs, 1.0 / 2.4 - 1.0)
    return np.where((x <= 0) | (x >= 1), 0.0, np.where(x <= _SRGB_KNEE, 12.92, power))


def edge_jump_metric(image, triangle_id, *, rows=None, channel="luminance", min_run: int = 16) -> float:
    r"""The Mach-band measure: the typical visible slope kink where scan lines cross triangle edges.

    Along a scan line with intensity ``I_j`` (linear, 1 = display white), first differences
    ``Δ_j = I_{j+1} − I_j`` and second differences ``Δ²_j = Δ_{j+1} − Δ_j``, a triangle edge
    between pixels ``k`` and ``k + 1`` has the kink:

        κ_k = (Δ_{k+1} − Δ_{k−1}) − 2 median(Δ²_{k−5}, …, Δ²_{k−2}, Δ²_{k+1}, …, Δ²_{k+4})
        K_k = e'((I_k + I_{k+1}) / 2) · |κ_k| / s,        s = KINK_SCALE = 1/255

    The first term is the slope jump across the edge; the second the curvature the shaded surface
    has anyway, read beside the edge (symmetric about it, so it cancels every cubic exactly; a median,
    so that a kink or step of the shading itself passing close by — the shadow terminator, a spot's
    rim — barely moves it).  ``e'`` is the slope of the sRGB encoding the eye sees: 12.92 on its
    linear segment, ``(1.055/2.4) I^{1/2.4 − 1}`` above ``I = 0.0031308``, 0 where the display clips
    (``I ≤ 0`` or ``I ≥ 1``).  So ``K_k`` is the slope change in 8-bit display levels per pixel:
    ``K = 1`` means the slope changes by one display level per pixel at the edge.  ``|κ_k|`` below
    the rounding of the image's dtype (64 ulp of the largest value in the window ``k−5 … k+6``)
    counts as 0.  The measure is:

        M = median of K_k over the shaded crossings

    A crossing counts if its window is alone (no other edge within six pixels, whose kink the
    curvature term would hold) and shaded (its values are not all equal to rounding: an unlit or
    ambient-only stretch has no slope to kink).  Hence ``M = 0`` exactly on a constant image and on
    an image linear across every edge, it grows in proportion as every kink grows, and it stays small
    where the image is nearly flat, since no slope divides it.  It is per pixel: the same shading
    rendered twice as large has kinks half as steep.

    Parameters
    ----------
    image : array_like, (H, W, 3) or (H, W)
        Linear image (display-referred: 1 is white).
    triangle_id : array_like of int, (H, W)
        Triangle seen at each pixel, -1 for background (a rasterizer's
        geometry buffer provides it).
    rows : iterable of int, optional
        Scan lines to use; default every row whose covered run is at least
        ``min_run`` pixels long.
    channel : {"luminance", "r", "g", "b"}
        The intensity: luminance or one channel.
    min_run : int
        Shortest covered run of a row that counts.

    Returns
    -------
    float
        ``M`` above, ``≥ 0``; 0 when no crossing counts.  Gouraud shading (colours interpolated
        linearly) has a kink at every edge; Phong interpolation has smaller ones — its interpolated
        normals are continuous but their derivative still jumps at edges, so it reduces Mach banding
        without removing it.

    Examples
    --------
    >>> tid = np.repeat(np.arange(2), 16)[None, :].repeat(3, axis=0)  # two triangles, 16 px each
    >>> x = np.arange(32.0)
    >>> edge_jump_metric(np.full((3, 32), 0.5), tid, min_run=1)  # flat
    0.0
    >>> edge_jump_metric(np.tile(0.2 + 0.01 * x, (3, 1)), tid, min_run=1)  # linear across the edge
    0.0
    >>> kinked = np.tile(0.2 + 0.01 * np.abs(x - 15.5), (3, 1))  # the slope jumps by 0.02 at the edge
    >>> e_slope = 1.055 / 2.4 * 0.205 ** (1 / 2.4 - 1)  # sRGB's slope at I = 0.205
    >>> bool(np.isclose(edge_jump_metric(kinked, tid, min_run=1), e_slope * 0.02 * 255))
    True
    """
    y = _channel(image, channel)
    src = np.asarray(image) if isinstance(image, np.ndarray) else None
    eps = float(np.finfo(src.dtype if src is not None and src.dtype.kind == "f" else np.float64).eps)
    tid = np.asarray(triangle_id) if isinstance(triangle_id, np.ndarray) else None
    if tid is None or tid.dtype.kind not in "iu":
        tid = real_array("triangle_id", triangle_id, allowed=f"integer triangle ids (-1 for background) of shape "
                         f"{y.shape}")  # fmt: skip
        if np.any(tid != np.floor(tid)):
            raise ValueError(f"triangle_id must be integer triangle ids (-1 for background); got {quote(triangle_id)}")
        tid = tid.astype(np.int64)
    if tid.shape != y.shape:
        raise ValueError(f"triangle_id must have the image's shape {y.shape}; got shape {tid.shape}")
    min_run = check_count("min_run", min_run, 1)
    cov = tid >= 0
    if rows is None:
        rows = range(tid.shape[0])
    else:
        if isinstance(rows, (str, bytes)) or not hasattr(rows, "__iter__"):
            raise ArgumentTypeError(f"rows must be an iterable of row indices; got {type(rows).__name__} {quote(rows)}")
        rows = [check_count("rows[]", r, 0, tid.shape[0] - 1) for r in rows]
    kinks = []
    for r in rows:
        x = _longest_run(cov[r])
        if x.size < max(min_run, 12):
            continue
        x = x[3:-3]  # the silhouette's own jump is not a Mach band
        i = y[r, x]
        d1 = np.diff(i)
        d2 = np.diff(d1)  # d2[k] = Δ_{k+1} − Δ_k, centred on x[k + 1]
        t = tid[r, x]
        k = np.flatnonzero(t[:-1] != t[1:])  # an edge between x[k] and x[k + 1]
        # Alone in its window [k − 5, k + 6]: the curvature term must not hold a neighbouring edge's kink.
        gap = np.diff(np.concatenate([[-np.inf], k, [np.inf]]))
        k = k[(gap[:-1] > 6) & (gap[1:] > 6) & (k >= 5) & (k + 4 < d2.size)]
        if not k.size:
            continue
        # The curvature beside the edge: the median of the eight second differences at k−5 … k−2 and
        # k+1 … k+4 (symmetric about the edge, so a cubic cancels exactly; a kink or step of the shading
        # itself — a terminator, a spot's rim — passing through the window moves it little).
        side = d2[k[:, None] + _SIDE]
        kappa = (d2[k - 1] + d2[k]) - 2.0 * np.median(side, axis=1)
        win = i[k[:, None] + np.arange(-5, 7)]
        floor = _ROUNDING_ULPS * eps * np.abs(win).max(axis=1)
        shaded = np.ptp(win, axis=1) > floor  # flat windows (unlit, ambient only) have no slope to kink
        kappa = np.where(np.abs(kappa) > floor, np.abs(kappa), 0.0)
        kinks.append((_srgb_slope(0.5 * (i[k] + i[k + 1])) * kappa)[shaded])
    kinks = np.concatenate(kinks) if kinks else np.zeros(0)
    return float(np.median(kinks) / KINK_SCALE) if kinks.size else 0.0

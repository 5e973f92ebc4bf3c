"""From linear float images to pictures: exposure, tone map, sRGB encoding.

Lighting happens in linear RGB.  Turning a result into an 8-bit picture is an
explicit, documented last step:

1. multiply by ``2**exposure`` (stops);
2. tone map: ``"clamp"`` (values above 1 clip — the count is reported),
   or ``"reinhard"`` (``x / (1 + x)``, nothing clips);
3. encode with the sRGB transfer function (IEC 61966-2-1) and round to 8 bits.

The PNG file itself (:func:`png_bytes`, :func:`write_png`, :func:`read_png`, :func:`file_mode`)
is written and read by :mod:`lighting.files.images`, the home of every image format; the names
are importable from here too.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import check_choice, check_range
from ..files.images import file_mode, png_bytes, read_png, write_png

#: Largest exposure, in stops, either way (2**100 is about 1e30): beyond it nothing is left to see.
MAX_EXPOSURE = 100.0
#: Pixels encoded at once by :func:`encode_srgb8`.
_ENCODE_PIXELS = 1 << 17

__all__ = [
    "EncodeReport", "linear_to_srgb", "srgb_to_linear", "encode_srgb8", "png_bytes", "write_png", "read_png",
    "file_mode",
]


def linear_to_srgb(x):
    """The sRGB transfer function on values in [0, 1].

    Parameters
    ----------
    x : array_like
        Linear values, any shape; clipped to ``[0, 1]`` first.

    Returns
    -------
    numpy.ndarray
        sRGB-encoded values in ``[0, 1]``, same shape, ``float64``.
    """
    x = np.clip(np.asarray(x, dtype=np.float64), 0, 1)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def srgb_to_linear(y):
    """Inverse of :func:`linear_to_srgb`.

    Parameters
    ----------
    y : array_like
        sRGB-encoded values, any shape; clipped to ``[0, 1]`` first.

    Returns
    -------
    numpy.ndarray
        Linear values in ``[0, 1]``, same shape, ``float64``.
    """
    y = np.clip(np.asarray(y, dtype=np.float64), 0, 1)
    return np.where(y <= 0.04045, y / 12.92, ((y + 0.055) / 1.055) ** 2.4)


@dataclass(frozen=True)
class EncodeReport:
    """What the encoding did: how many pixels clipped, out of how many."""

    clipped_pixels: int
    total_pixels: int
    max_value: float

    @property
    def clipped_fraction(self) -> float:
        return self.clipped_pixels / max(self.total_pixels, 1)

    def __str__(self) -> str:
        return (
            f"{self.clipped_pixels} of {self.total_pixels} pixels clipped "
            f"({100 * self.clipped_fraction:.2f} %), brightest value {self.max_value:.4g}"
        )


def encode_srgb8(image, *, exposure: float = 0.0, tonemap: str = "clamp"):
    """Linear RGB ``(H, W, 3)`` → sRGB ``uint8`` ``(H, W, 3)`` plus an :class:`EncodeReport`.

    Parameters
    ----------
    image : array_like, (H, W, 3)
        Linear RGB, any float dtype.  NaN is an error (the engine never makes it).
    exposure : float
        Stops, in ``[-100, 100]``: values are multiplied by ``2**exposure`` first.
    tonemap : {"clamp", "reinhard"}
        ``clamp`` clips at 1 (clipped pixels are counted in the report);
        ``reinhard`` maps ``x → x / (1 + x)``.

    Returns
    -------
    numpy.ndarray, (H, W, 3), uint8
        The sRGB-encoded picture.
    EncodeReport
        Clipped pixel count (0 for ``reinhard``), total pixel count and the brightest value after exposure.

    Examples
    --------
    >>> img, rep = encode_srgb8(np.array([[[0.0, 0.5, 2.0]]]))
    >>> img.tolist(), rep.clipped_pixels
    ([[[0, 188, 255]]], 1)
    """
    tonemap = check_choice("tonemap", tonemap, ("clamp", "reinhard"))
    exposure = check_range("exposure", exposure, -MAX_EXPOSURE, MAX_EXPOSURE)
    given, image = image, np.asarray(image)
    if image.dtype.kind not in "fiu":
        image = np.asarray(given, dtype=np.float64)
    if image.ndim != 3 or image.shape[-1] != 3:
        raise ValueError(f"image must have shape (H, W, 3); got {image.shape}")
    if np.isnan(image).any():
        raise ValueError("image contains NaN")
    y = np.empty(image.shape, dtype=np.uint8)
    peak, clipped = 0.0, 0
    # A band of rows at a time: every value is encoded alone, and the whole image's float64 temporaries would be
    # several times its size (a large render's encoding would need more memory than the render's own buffers).
    rows = max(1, _ENCODE_PIXELS // max(image.shape[1], 1))
    for r in range(0, image.shape[0], rows):
        x = np.asarray(image[r : r + rows], dtype=np.float64)
        with np.errstate(over="ignore"):  # a value near the float64 limit, brightened: saturate, never inf
            x = np.minimum(np.maximum(x, 0) * 2.0**exposure, np.finfo(np.float64).max)
        if x.size:
            peak = max(peak, float(x.max()))
        clipped += int(np.count_nonzero(np.any(x > 1, axis=-1)))
        if tonemap == "reinhard":
            x = x / (1 + x)
        y[r : r + rows] = np.round(linear_to_srgb(x) * 255).astype(np.uint8)
    if tonemap == "reinhard":
        clipped = 0
    return y, EncodeReport(clipped, image.shape[0] * image.shape[1], peak)

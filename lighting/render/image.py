"""From linear float images to pictures: exposure, tone map, sRGB encoding, PNG.

Lighting happens in linear RGB.  Turning a result into an 8-bit picture is an
explicit, documented last step:

1. multiply by ``2**exposure`` (stops);
2. tone map: ``"clamp"`` (values above 1 clip — the count is reported),
   or ``"reinhard"`` (``x / (1 + x)``, nothing clips);
3. encode with the sRGB transfer function (IEC 61966-2-1) and round to 8 bits.

:func:`write_png` writes a PNG with the standard library only (``zlib``), to a
temporary file that is renamed into place, so a failed write never leaves half a
file behind.
"""

from __future__ import annotations

import os
import stat
import struct
import tempfile
import zlib
from dataclasses import dataclass

import numpy as np

from .._numeric import check_choice, check_range

#: Largest exposure, in stops, either way (2**100 is about 1e30): beyond it nothing is left to see.
MAX_EXPOSURE = 100.0

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
    x = np.asarray(image, dtype=np.float64)
    if x.ndim != 3 or x.shape[-1] != 3:
        raise ValueError(f"image must have shape (H, W, 3); got {x.shape}")
    if np.isnan(x).any():
        raise ValueError("image contains NaN")
    with np.errstate(over="ignore"):  # a value near the float64 limit, brightened: saturate, never inf
        x = np.minimum(np.maximum(x, 0) * 2.0**exposure, np.finfo(np.float64).max)
    peak = float(x.max()) if x.size else 0.0
    clipped = int(np.count_nonzero(np.any(x > 1, axis=-1)))
    if tonemap == "reinhard":
        x = x / (1 + x)
        clipped = 0
    y = np.round(linear_to_srgb(x) * 255).astype(np.uint8)
    return y, EncodeReport(clipped, x.shape[0] * x.shape[1], peak)


def png_bytes(rgb8: np.ndarray, *, level: int = 6) -> bytes:
    """A PNG file's bytes for an 8-bit image, written with the standard library (``zlib``) only.

    Parameters
    ----------
    rgb8 : numpy.ndarray of uint8, C-contiguous, shape (H, W, 3) or (H, W, 4)
        The pixels, first row at the top (RGB, or RGBA with straight alpha).
    level : int
        ``zlib`` compression level, 0–9 (6: a file; 1: an image sent once, e.g. to a notebook widget).

    Returns
    -------
    bytes
        The PNG file (8 bits per channel, colour type 2 or 6).
    """
    h, w, c = rgb8.shape
    color_type = {3: 2, 4: 6}[c]
    raw = np.concatenate([np.zeros((h, 1), np.uint8), rgb8.reshape(h, w * c)], axis=1).tobytes()

    def chunk(tag: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    ihdr = struct.pack(">IIBBBBB", w, h, 8, color_type, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw, level)) + chunk(b"IEND", b"")


def _umask() -> int:
    try:  # Linux >= 4.7 reports it without changing it (os.umask would, for every thread, for a moment)
        with open("/proc/self/status", encoding="ascii") as f:
            for line in f:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    old = os.umask(0o022)
    os.umask(old)
    return old


def file_mode(target) -> int:
    """Permission bits for a file written to ``target``: the replaced file's, else ``0o666`` minus the umask.

    What ``open(target, "w")`` would give; ``tempfile.mkstemp`` alone gives ``0o600``.

    Parameters
    ----------
    target : str or os.PathLike
        Path of the file about to be written (it may not exist yet).

    Returns
    -------
    int
        Permission bits (``stat.S_IMODE``), e.g. ``0o644``.
    """
    try:
        st = os.stat(target)
    except OSError:
        return 0o666 & ~_umask()
    return stat.S_IMODE(st.st_mode)


def write_png(path, rgb8) -> None:
    """Write an ``(H, W, 3)`` or ``(H, W, 4)`` ``uint8`` array as PNG, atomically.

    The file keeps the user's umask (or the mode of the file it replaces).  The command line writes
    through ``explorer.output.write_image``, which adds other formats and interrupt safety.

    Parameters
    ----------
    path : str or os.PathLike
        Destination; a symbolic link is followed and its target replaced.
    rgb8 : array_like, (H, W, 3) or (H, W, 4), uint8
        RGB or RGBA pixels, first row at the top; any other dtype or shape is a ValueError.
    """
    a = np.asarray(rgb8)
    if a.dtype != np.uint8 or a.ndim != 3 or a.shape[-1] not in (3, 4):
        raise ValueError(f"write_png needs a uint8 array of shape (H, W, 3|4); got {a.dtype} {a.shape}")
    data = png_bytes(np.ascontiguousarray(a))
    path = os.fspath(path)
    target = os.path.realpath(path) if os.path.islink(path) else os.path.abspath(path)
    mode = file_mode(target)
    tmp = None
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{os.path.basename(target)}.", suffix=".part",
                                   dir=os.path.dirname(target))  # fmt: skip
        with os.fdopen(fd, "wb") as f:
            os.fchmod(f.fileno(), mode)
            f.write(data)
        os.replace(tmp, target)
    except BaseException:
        if tmp is not None and os.path.exists(tmp):
            os.unlink(tmp)
        raise


def read_png(path) -> np.ndarray:
    """Read back a PNG written by :func:`write_png` (8-bit RGB/RGBA, no interlace).

    Parameters
    ----------
    path : str or os.PathLike
        The PNG file; other bit depths, colour types, interlacing or row filters are a ValueError.

    Returns
    -------
    numpy.ndarray, (H, W, 3) or (H, W, 4), uint8
        The pixels, a writable copy.
    """
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG file")
    pos, idat = 8, b""
    w = h = c = None
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos : pos + 4])
        tag, body = data[pos + 4 : pos + 8], data[pos + 8 : pos + 8 + n]
        pos += 12 + n
        if tag == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or ctype not in (2, 6) or interlace:
                raise ValueError(f"{path}: only 8-bit RGB/RGBA non-interlaced PNG is supported")
            c = 3 if ctype == 2 else 4
        elif tag == b"IDAT":
            idat += body
    raw = np.frombuffer(zlib.decompress(idat), np.uint8).reshape(h, 1 + w * c)
    if np.any(raw[:, 0] != 0):
        raise ValueError(f"{path}: PNG filters other than 'None' are not supported by this reader")
    return raw[:, 1:].reshape(h, w, c).copy()

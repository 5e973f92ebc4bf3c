"""PNG files: the reader of 8-bit RGB/RGBA PNGs with filter 0, and the writer (``zlib`` only).

The reader checks the signature, the IHDR chunk, every chunk's CRC and the size of the pixel stream
before and while it decompresses (:mod:`lighting.files.image_checks`); the writer writes one IDAT
chunk of unfiltered rows, through :func:`lighting.files.atomic.atomic_write`.
"""

from __future__ import annotations

import struct
import zlib

import numpy as np

from .atomic import atomic_write
from .image_checks import _Bad, _error, _Limits, _path_name, _read_bytes

__all__ = ["read_png", "png_bytes", "write_png"]

_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _png_header(data: bytes):
    """``(h, w, channels, offset after IHDR)`` of a PNG file whose IHDR is the first chunk, as the format requires."""
    if not data.startswith(_PNG_SIGNATURE):
        raise _Bad("not a PNG file (no PNG signature)", "allowed: an 8-bit RGB or RGBA PNG")
    if len(data) < 33 or data[8:16] != b"\x00\x00\x00\x0dIHDR":
        raise _Bad("the first chunk is not a 13-byte IHDR", "allowed: a PNG file starting with its IHDR chunk")
    body = data[16:29]
    if struct.unpack(">I", data[29:33])[0] != zlib.crc32(b"IHDR" + body) & 0xFFFFFFFF:
        raise _Bad("the IHDR chunk's CRC does not match", "allowed: an undamaged PNG file")
    w, h, depth, ctype, compression, filtering, interlace = struct.unpack(">IIBBBBB", body)
    if depth != 8 or ctype not in (2, 6) or compression or filtering or interlace:
        raise _Bad(
            f"bit depth {depth}, colour type {ctype}, interlace {interlace}",
            "allowed: 8-bit RGB or RGBA (colour type 2 or 6), not interlaced",
        )
    return h, w, 3 if ctype == 2 else 4, 33


def _decode_png(data: bytes, limits: _Limits) -> np.ndarray:
    h, w, c, pos = _png_header(data)
    row = 1 + w * c
    limits.check(h, w, 2 * c + 1)  # the decompressed rows (c + 1 bytes a pixel at most) and the pixels' copy
    idat, n = [], len(data)
    while True:
        if pos + 12 > n:
            raise _Bad("the file ends before its IEND chunk", "allowed: a complete PNG file")
        (size,) = struct.unpack(">I", data[pos : pos + 4])
        tag = data[pos + 4 : pos + 8]
        if pos + 12 + size > n:
            raise _Bad(f"chunk {tag.decode('latin-1')!r} is truncated", "allowed: a complete PNG file")
        body = data[pos + 8 : pos + 8 + size]
        if struct.unpack(">I", data[pos + 8 + size : pos + 12 + size])[0] != zlib.crc32(tag + body) & 0xFFFFFFFF:
            raise _Bad(f"chunk {tag.decode('latin-1')!r} has a CRC that does not match", "allowed: an undamaged PNG")
        pos += 12 + size
        if tag == b"IDAT":
            idat.append(body)
        elif tag == b"IEND":
            break
    need = h * row
    z = zlib.decompressobj()
    try:
        raw = z.decompress(b"".join(idat), need + 1)  # never more than the header allows
    except zlib.error as e:
        raise _Bad(f"the pixel data cannot be decompressed ({e})", "allowed: a valid PNG file") from None
    if len(raw) != need or not z.eof:
        have = "more" if len(raw) > need else "less"
        raise _Bad(f"the pixel data holds {have} than {w}x{h} pixels", f"allowed: {need} bytes of rows")
    rows = np.frombuffer(raw, np.uint8).reshape(h, row)
    filters = np.flatnonzero(rows[:, 0])
    if filters.size:
        i = int(filters[0])
        raise _Bad(f"row {i} uses PNG filter {int(rows[i, 0])}", "allowed: filter 0 (None), as write_png writes")
    return rows[:, 1:].reshape(h, w, c).copy()


def read_png(path) -> np.ndarray:
    """Read a PNG written by :func:`write_png`: 8-bit RGB or RGBA, not interlaced, every row filter 0.

    Parameters
    ----------
    path : str or os.PathLike
        The PNG file; other bit depths, colour types, interlacing or row filters are a ValueError.

    Returns
    -------
    numpy.ndarray, (H, W, 3) or (H, W, 4), uint8
        The pixels, a writable copy.

    Raises
    ------
    ValueError
        One line ``"<path>: <what is wrong>; <what is allowed>"``: a missing or special file, a
        signature, chunk, CRC or pixel stream that does not match, a size over :data:`MAX_SIDE`, or
        a memory estimate over the budget (:class:`~lighting._budget.BudgetError`).

    Examples
    --------
    >>> import os, tempfile
    >>> p = os.path.join(tempfile.mkdtemp(), "dot.png")
    >>> write_png(p, np.full((1, 2, 3), 200, np.uint8))
    >>> read_png(p).tolist()
    [[[200, 200, 200], [200, 200, 200]]]
    """
    name = _path_name(path)
    data = _read_bytes(name, "PNG image")
    try:
        return _decode_png(data, _Limits(name, "PNG image"))
    except _Bad as e:
        raise _error(name, e.what, e.allowed) from None


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
    return _PNG_SIGNATURE + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw, level)) + chunk(b"IEND", b"")


def write_png(path, rgb8) -> None:
    """Write an ``(H, W, 3)`` or ``(H, W, 4)`` ``uint8`` array as PNG, atomically (:func:`atomic_write`).

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
    atomic_write(path, png_bytes(np.ascontiguousarray(a)))

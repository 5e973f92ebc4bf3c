"""Portable float maps (``.pfm``): the decoder :func:`lighting.files.images.read_linear` uses, and the bytes
of one.
"""

from __future__ import annotations

import math
import re

import numpy as np

from .image_checks import _Bad, _finish, _Limits

__all__ = ["pfm_bytes"]

_PFM = re.compile(rb"^(P[Ff])\s+(\d{1,9})\s+(\d{1,9})\s+(\S{1,40})\s")


def _pfm_header(data: bytes):
    """``(h, w, channels, scale, offset of the pixels)`` of a PFM file."""
    m = _PFM.match(data[:256])
    if not m:
        raise _Bad("not a PFM header", "allowed: 'PF' or 'Pf', width, height and scale, whitespace-separated")
    channels = 3 if m.group(1) == b"PF" else 1
    w, h = int(m.group(2)), int(m.group(3))
    try:
        scale = float(m.group(4).decode("ascii"))
    except (ValueError, UnicodeDecodeError):
        scale = float("nan")
    if not (math.isfinite(scale) and scale != 0):
        raise _Bad(
            f"scale {m.group(4).decode('latin-1')!r}", "allowed: a finite nonzero number (negative: little-endian)"
        )
    return h, w, channels, scale, m.end()


def _decode_pfm(data: bytes, limits: _Limits) -> np.ndarray:
    h, w, channels, scale, start = _pfm_header(data)
    limits.check(h, w, 12 + 12 + 4)
    need = h * w * channels * 4
    body = len(data) - start
    if body < need:
        raise _Bad(f"the file is truncated: {body} bytes of pixels", f"allowed: {need} bytes for {w}x{h}x{channels}")
    if body > need:
        raise _Bad(f"{body - need} extra bytes after the pixels", f"allowed: exactly {need} bytes of pixels")
    dt = "<f4" if scale < 0 else ">f4"
    px = np.frombuffer(data, dtype=dt, count=h * w * channels, offset=start).reshape(h, w, channels)
    return _finish(px[::-1], limits.name)


def pfm_bytes(linear: np.ndarray) -> bytes:
    """A portable float map's bytes: ``PF``, width and height, scale ``-1.0`` (little-endian), rows bottom to top.

    Parameters
    ----------
    linear : numpy.ndarray, (H, W, 3), float
        Linear RGB, row 0 at the top; stored as float32.

    Returns
    -------
    bytes
        The file.
    """
    h, w, _ = linear.shape
    body = np.ascontiguousarray(linear[::-1], dtype="<f4").tobytes()
    return f"PF\n{w} {h}\n-1.0\n".encode("ascii") + body

"""Radiance ``.hdr`` / ``.pic`` files (RGBE, Ward 1991): the decoder :func:`lighting.files.images.read_linear`
uses, and the writer.

The format is described in :mod:`lighting.files.images`; the decoder checks the header, the
resolution line and every run length as it reads them.
"""

from __future__ import annotations

import math
import re

import numpy as np

from .._budget import check_budget
from .._validate import ArgumentTypeError
from .atomic import atomic_write
from .image_checks import _HEADER_LIMIT, _Bad, _finish, _Limits

__all__ = ["rgbe_bytes", "write_hdr"]

_RES = re.compile(rb"^([-+])([YX]) +(\d{1,9}) +([-+])([YX]) +(\d{1,9})$")


def _rgbe_header(data: bytes):
    """``(h, w, rows_bottom_up, columns_right_to_left, exposure, offset of the pixels)`` of an RGBE file."""
    if not data.startswith(b"#?"):
        raise _Bad("not a Radiance file (no '#?' signature)", "allowed: an RGBE file starting '#?RADIANCE'")
    end = data.find(b"\n\n", 0, _HEADER_LIMIT)
    if end < 0:
        raise _Bad(
            "the header does not end (no empty line in the first 64 KiB)",
            "allowed: header lines, an empty line, then the resolution line",
        )
    exposure = 1.0
    for k, raw in enumerate(data[:end].split(b"\n")[1:], start=2):
        line = raw.strip()
        if line.startswith(b"FORMAT="):
            fmt = line[7:].strip()
            if fmt != b"32-bit_rle_rgbe":
                raise _Bad(f"line {k}: FORMAT={fmt.decode('latin-1')!r}", "allowed: FORMAT=32-bit_rle_rgbe")
        elif line.startswith(b"EXPOSURE="):
            try:
                e = float(line[9:].strip().decode("ascii"))
            except (ValueError, UnicodeDecodeError):
                e = float("nan")
            if not (math.isfinite(e) and e > 0):
                raise _Bad(f"line {k}: {line.decode('latin-1')!r}", "allowed: EXPOSURE= a finite number > 0")
            exposure *= e
    if not (math.isfinite(exposure) and exposure > 0):
        raise _Bad(f"the EXPOSURE lines multiply to {exposure!r}", "allowed: a finite product > 0")
    nl = data.find(b"\n", end + 2, end + 2 + 64)
    if nl < 0:
        raise _Bad("the resolution line is missing or too long", "allowed: '-Y H +X W' after the header")
    res = data[end + 2 : nl].strip()
    m = _RES.match(res)
    if not m or m.group(2) != b"Y" or m.group(5) != b"X":
        raise _Bad(
            f"resolution line {res[:40].decode('latin-1')!r}",
            "allowed: '-Y H +X W' (or +Y / -X: rows bottom-up / columns right-to-left)",
        )
    return int(m.group(3)), int(m.group(6)), m.group(1) == b"+", m.group(4) == b"-", exposure, nl + 1


def _decode_rgbe(data: bytes, limits: _Limits) -> np.ndarray:
    h, w, bottom_up, right_to_left, exposure, start = _rgbe_header(data)
    # Output float32 RGB, the RGBE bytes and the float64 temporaries of the conversion.
    limits.check(h, w, 12 + 4 + 48)
    rgbe = _rgbe_scanlines(data, start, h, w)
    if bottom_up:
        rgbe = rgbe[::-1]
    if right_to_left:
        rgbe = rgbe[:, ::-1]
    e = rgbe[..., 3].astype(np.int32)
    f = np.where(e > 0, np.ldexp(1.0, e - 136), 0.0)
    img = (rgbe[..., :3] + 0.5) * f[..., None]
    return _finish(img, limits.name, exposure)


def _rgbe_scanlines(data: bytes, pos: int, h: int, w: int) -> np.ndarray:
    out = np.empty((h, w, 4), dtype=np.uint8)
    n = len(data)
    rle_ok = 8 <= w <= 0x7FFF
    line = bytearray(4 * w)
    for y in range(h):
        if rle_ok and pos + 4 <= n and data[pos] == 2 and data[pos + 1] == 2 and not data[pos + 2] & 0x80:
            width = (data[pos + 2] << 8) | data[pos + 3]
            if width != w:
                raise _Bad(f"scanline {y}: run-length header for width {width}", f"allowed: width {w}")
            pos += 4
            for c in range(4):
                x = c * w
                stop = x + w
                while x < stop:
                    if pos >= n:
                        raise _Bad(f"the file ends inside scanline {y}", f"allowed: {h} complete scanlines")
                    count = data[pos]
                    if count > 128:
                        count -= 128
                        if x + count > stop or pos + 1 >= n:
                            raise _Bad(f"scanline {y}: a run overruns the scanline", f"allowed: runs within {w} pixels")
                        line[x : x + count] = data[pos + 1 : pos + 2] * count
                        pos += 2
                    else:
                        if count == 0 or x + count > stop:
                            raise _Bad(f"scanline {y}: bad run length {count}", f"allowed: runs within {w} pixels")
                        if pos + 1 + count > n:
                            raise _Bad(f"the file ends inside scanline {y}", f"allowed: {h} complete scanlines")
                        line[x : x + count] = data[pos + 1 : pos + 1 + count]
                        pos += 1 + count
                    x += count
            out[y] = np.frombuffer(line, dtype=np.uint8).reshape(4, w).T
        else:
            if pos + 4 * w > n:
                raise _Bad(f"the file ends inside scanline {y}", f"allowed: {h} complete scanlines")
            px = np.frombuffer(data, dtype=np.uint8, count=4 * w, offset=pos).reshape(w, 4)
            if np.any((px[:, 0] == 1) & (px[:, 1] == 1) & (px[:, 2] == 1)):
                raise _Bad(
                    f"scanline {y}: old-style run-length encoding (a 1 1 1 pixel)",
                    "allowed: flat or new-style run-length scanlines (re-save the file with a current tool)",
                )
            out[y] = px
            pos += 4 * w
    if pos != n:
        raise _Bad(f"{n - pos} bytes after the last scanline", f"allowed: exactly {h} scanlines")
    return out


def _rgbe_pixels(img: np.ndarray) -> np.ndarray:
    """``(H, W, 4)`` uint8 RGBE of non-negative finite RGB (Radiance's ``setcolr``: mantissas truncated)."""
    m = img.max(axis=-1)
    mant, e = np.frexp(m)  # m = mant 2^e, mant in [0.5, 1)
    ok = m >= 2.0**-127  # smaller maxima are black (exponent byte 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = np.where(ok, mant * 256.0 / np.where(ok, m, 1.0), 0.0)
    out = np.zeros(img.shape[:2] + (4,), dtype=np.uint8)
    out[..., :3] = np.clip(np.floor(img * scale[..., None]), 0, 255).astype(np.uint8)
    out[..., 3] = np.where(ok, e + 128, 0).astype(np.uint8)
    return out


def _rle_channel(a: bytes) -> bytearray:
    """New-style run-length encoding of one channel of a scanline (runs of 4 or more, dumps up to 128)."""
    out = bytearray()
    n, i = len(a), 0
    while i < n:
        # Find the next run of at least 4 equal bytes starting at or after i.
        j = i
        run_start, run_len = n, 0
        while j < n:
            k = j + 1
            while k < n and k - j < 127 and a[k] == a[j]:
                k += 1
            if k - j >= 4:
                run_start, run_len = j, k - j
                break
            j = k
        while i < run_start:  # the literal bytes before the run
            c = min(128, run_start - i)
            out.append(c)
            out += a[i : i + c]
            i += c
        if run_len:
            out.append(128 + run_len)
            out.append(a[run_start])
            i = run_start + run_len
    return out


def rgbe_bytes(image, *, rle: bool = True) -> bytes:
    """A Radiance ``.hdr`` (RGBE) file's bytes for linear RGB radiance.

    Parameters
    ----------
    image : array_like, (H, W, 3)
        Finite radiance ``>= 0`` and below ``2^127``.  Row 0 is stored first (``-Y H +X W``).
    rle : bool
        New-style run-length-encoded scanlines (default; used where the width is 8 to 32767), else
        flat 4-byte pixels.

    Returns
    -------
    bytes
        The file.

    Notes
    -----
    Each pixel keeps 8 mantissa bits against its brightest channel (truncated, as Radiance's
    ``setcolr``; the reader adds half a step back): read back, a channel is within ``2^-8`` of the
    pixel's largest value.
    """
    allowed = "an (H, W, 3) array of finite radiances >= 0 and < 2^127"
    try:
        img = np.asarray(image, dtype=np.float64)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"image must be {allowed}; got {type(image).__name__}") from None
    if img.ndim != 3 or img.shape[2] != 3 or img.shape[0] < 1 or img.shape[1] < 1:
        raise ValueError(f"image must be {allowed}; got shape {img.shape}")
    if not np.all(np.isfinite(img)) or np.any(img < 0) or np.any(img >= 2.0**127):
        raise ValueError(f"image must be {allowed}; got values in [{img.min()!r}, {img.max()!r}]")
    h, w = img.shape[:2]
    check_budget("image", img.size * 8 * 3, what=f"an RGBE encoding of {w}x{h}")
    rgbe = _rgbe_pixels(img)
    # The software line every file has carried since the writer lived in lighting.lights.envfiles:
    # kept, so that the files stay the same byte for byte.
    parts = [f"#?RADIANCE\n# lighting.lights.envfiles\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n".encode("ascii")]
    if rle and 8 <= w <= 0x7FFF:
        head = bytes([2, 2, w >> 8, w & 0xFF])
        for y in range(h):
            parts.append(head)
            for c in range(4):
                parts.append(bytes(_rle_channel(rgbe[y, :, c].tobytes())))
    else:
        # A flat (1, 1, 1, e) pixel would read as an old-style run: store the same value as (2, 2, 2, e − 1).
        ones = np.all(rgbe[..., :3] == 1, axis=-1)
        sel = ones & (rgbe[..., 3] > 1)
        rgbe[ones & ~sel] = 0  # 2^-135: black
        rgbe[sel, :3] = 2
        rgbe[sel, 3] -= 1
        parts.append(rgbe.tobytes())
    return b"".join(parts)


def write_hdr(path, image, *, rle: bool = True) -> None:
    """Write linear RGB radiance as a Radiance ``.hdr`` (RGBE) file, atomically (:func:`atomic_write`).

    Parameters
    ----------
    path : str or os.PathLike
        Destination; written to a temporary file in the same folder and renamed into place.
    image : array_like, (H, W, 3)
        Finite radiance ``>= 0`` and below ``2^127``; any shape (an environment reads back only
        ``W = 2 H``).  Row 0 is stored first (``-Y H +X W``).
    rle : bool
        New-style run-length-encoded scanlines (default; used where the width is 8 to 32767), else
        flat 4-byte pixels.

    Notes
    -----
    The encoding is :func:`rgbe_bytes`'s: read back, a channel is within ``2^-8`` of the pixel's
    largest value.

    Examples
    --------
    >>> import os, tempfile
    >>> p = os.path.join(tempfile.mkdtemp(), "grey.hdr")
    >>> write_hdr(p, np.full((4, 8, 3), 0.5))
    >>> from lighting.files.images import read_linear
    >>> float(read_linear(p).max())   # (128 + ½) 2^-8
    0.501953125
    """
    atomic_write(path, rgbe_bytes(image, rle=rle))

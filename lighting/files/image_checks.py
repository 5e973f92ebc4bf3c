"""The checks every image reader makes before it decodes a pixel, and the one-line errors they raise.

An image file is untrusted input (:mod:`lighting.files.images` says why these readers are the engine's
own): the file must be a regular file whose size fits the memory budget (:func:`_check_file`), the
declared size must fit the caller's limits and shape, and the decoder's memory is charged to the budget
(:class:`_Limits`) before any pixel is decoded; the pixels must then be finite radiance ``>= 0``
(:func:`_finish`).  A format's decoder raises :class:`_Bad`; the public reader turns it into one
``ValueError`` line naming the file, ``"<path>: <what is wrong>; <what is allowed>"``.
"""

from __future__ import annotations

import math
import os
import stat
from dataclasses import dataclass

import numpy as np

from .._budget import check_budget
from .._text import quote
from .._validate import ArgumentTypeError

__all__ = ["MAX_SIDE"]

#: The largest side :func:`~lighting.files.images.read_linear` and :func:`~lighting.files.png.read_png` accept
#: unless the caller sets a limit.
MAX_SIDE = 65536
_HEADER_LIMIT = 1 << 16  # bytes of RGBE/PFM header scanned before giving up


class _Bad(Exception):
    """A problem found while decoding; turned into the one-line ValueError naming the file."""

    def __init__(self, what: str, allowed: str):
        super().__init__(what)
        self.what, self.allowed = what, allowed


def _error(path: str, what: str, allowed: str) -> ValueError:
    return ValueError(f"{path}: {what}; {allowed}")


@dataclass(frozen=True)
class _Limits:
    """What a reader accepts: the file's name and kind (for messages), its largest size and its shape."""

    name: str
    kind: str = "image"
    max_height: int = MAX_SIDE
    max_width: int = MAX_SIDE
    aspect: int | None = None  # width = aspect x height, when given
    shape: str = ""  # the allowed shape, in words (for an aspect)

    def check(self, h: int, w: int, bytes_per_pixel: int) -> None:
        """Refuse sizes that are zero, beyond the limits or of another shape, then charge the decoder's memory."""
        shape = f"allowed: {self.shape}" if self.shape else "allowed: at least 1x1 pixels"
        if h < 1 or w < 1:
            raise _Bad(f"image size {w}x{h} is empty", shape)
        if h > self.max_height or w > self.max_width:
            raise _Bad(f"image size {w}x{h} is too large", f"allowed: at most {self.max_width}x{self.max_height}")
        if self.aspect is not None and w != self.aspect * h:
            raise _Bad(f"image size {w}x{h} is not {self.aspect}:1", shape)
        check_budget(f"{self.kind} {self.name!r}", h * w * bytes_per_pixel, what=f"a {w}x{h} image and its decoding")


def _path_name(path) -> str:
    if not isinstance(path, str | os.PathLike):
        raise ArgumentTypeError(f"path must be a str or os.PathLike; got {type(path).__name__} {quote(path)}")
    name = os.fspath(path)
    return os.fsdecode(name) if isinstance(name, bytes) else name


def _check_file(name: str, kind: str) -> None:
    """Refuse a missing file, a directory or a special file, and a file larger than the budget."""
    try:
        st = os.stat(name)  # before open: opening a FIFO for reading would wait for a writer
    except FileNotFoundError:
        raise _error(name, "no such file", f"allowed: an existing {kind}") from None
    except OSError as e:
        raise _error(name, f"cannot be opened ({e.strerror})", "allowed: a readable file") from None
    if stat.S_ISDIR(st.st_mode):
        raise _error(name, "is a directory", "allowed: a regular file")
    if not stat.S_ISREG(st.st_mode):
        raise _error(name, "is not a regular file", "allowed: a regular file")
    check_budget(f"{kind} {name!r}", st.st_size, what=f"a file of {st.st_size} bytes")


def _read_bytes(name: str, kind: str) -> bytes:
    """The whole file, after :func:`_check_file`."""
    _check_file(name, kind)
    try:
        with open(name, "rb") as f:
            return f.read()
    except OSError as e:
        raise _error(name, f"cannot be read ({e.strerror})", "allowed: a readable file") from None


def _finish(img: np.ndarray, name: str, scale: float = 1.0) -> np.ndarray:
    """float32 RGB, divided by ``scale``; refuses NaN, infinite (also by overflow) or negative pixels."""
    src = img
    if src.ndim == 2:
        src = src[..., None]
    with np.errstate(over="ignore", invalid="ignore"):
        out = np.empty(src.shape[:2] + (3,), dtype=np.float32)
        np.divide(src, scale, out=out, casting="unsafe")
    bad = ~np.isfinite(out) | (out < 0)
    if bad.any():
        i, j, c = (int(k) for k in np.argwhere(bad)[0])
        v = float(src[i, j, min(c, src.shape[2] - 1)]) / scale
        what = "negative" if v < 0 else "NaN" if math.isnan(v) else "infinite" if math.isinf(v) else "beyond float32"
        raise _Bad(
            f"radiance {v!r} ({what}) at row {i}, column {j} (from the top)",
            "allowed: finite radiance >= 0 within the float32 range",
        )
    return out

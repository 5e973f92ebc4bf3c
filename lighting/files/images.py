r"""Image files: every format the engine reads or writes, and one atomic writer for all of them.

========== ============================================== ==============================================
Format     Read                                           Written
========== ============================================== ==============================================
``.png``   :func:`read_png` (8-bit RGB/RGBA, filter 0)    :func:`png_bytes`, :func:`write_png`
``.hdr``   :func:`read_linear` (also ``.pic``)            :func:`rgbe_bytes`, :func:`write_hdr`
``.pfm``   :func:`read_linear`                            :func:`pfm_bytes`
``.npy``   :func:`read_linear` (no pickles)               :func:`npy_bytes`
``.exr``   :func:`read_linear` (with ``OpenEXR``)         :func:`exr_writer` (with ``OpenEXR``)
========== ============================================== ==============================================

Reading
-------
:func:`read_linear` reads linear radiance as RGB ``float32``, row 0 at the top:

* Radiance ``.hdr`` / ``.pic`` (RGBE, Ward 1991): the ``#?RADIANCE`` header, ``FORMAT=32-bit_rle_rgbe``,
  ``EXPOSURE=`` lines (the pixels are divided by their product, as the format defines), the resolution
  line ``-Y H +X W`` (``+Y`` stores the rows bottom to top, ``-X`` the columns right to left: both are
  turned back), flat and run-length-encoded scanlines.  A pixel ``(r, g, b, e)`` is
  ``(c + ½) 2^(e − 136)`` per channel, and 0 for ``e = 0`` (Radiance's ``colr_color``).  Old-style
  run-length encoding (a ``1 1 1`` pixel repeating its predecessor) is refused.
* ``.pfm``: ``PF`` (RGB) or ``Pf`` (grey), width and height, a scale whose sign gives the byte order
  (negative: little-endian; its magnitude is ignored), rows stored bottom to top.
* ``.npy``: an ``(H, W, 3)`` or ``(H, W)`` array of real numbers (read without pickles).
* ``.exr``: when the ``OpenEXR`` Python package is installed (its ``R``, ``G``, ``B`` channels, or
  ``Y`` for grey).

Why our own readers and PNG writer
----------------------------------
An image file is untrusted input (a scene names it; a download supplies it).  These readers check
it before they allocate: the file is a regular file whose size fits the memory budget, the header
is parsed with bounded scans, the declared size is checked against the caller's limits (and shape,
e.g. an environment's 2:1) and the decoder's memory charged to the budget
(:func:`lighting._budget.check_budget`) *before* any pixel is decoded; the RGBE run lengths, the PNG
chunks and their CRCs are checked as they are read.  They execute nothing from the file (``.npy``
without pickles) and need only NumPy and the standard library (``zlib``); OpenEXR is optional.  An
imaging library would allocate what the header claims first, accept pickled arrays or bring a
dependency the engine does not otherwise need; none of them reads RGBE with these checks.  Every
malformed file is one ``ValueError`` line, ``"<path>: <what is wrong>; <what is allowed>"``; so is a
negative, NaN or infinite radiance (naming the pixel).

Writing
-------
Every writer goes through :func:`atomic_write`: the bytes go to a temporary file in the target
folder, are flushed to disk (``fsync``) and the file is renamed over the target only when complete,
so a reader sees the old file or the whole new one; the temporary file is removed on any exception.
A new file gets ``0o666`` minus the umask, as ``open()`` gives; a replaced one keeps its mode
(:func:`file_mode`).  The command line's writer (:mod:`explorer.output`) builds on
:func:`write_temporary` and adds its flags and signal handling.

References
----------
G. Ward, "Real Pixels", Graphics Gems II (1991), 80–83; the Radiance file formats
(``radsite.lbl.gov/radiance/refer/filefmts.pdf``); the PNG specification (ISO/IEC 15948).
"""

from __future__ import annotations

import contextlib
import io
import math
import os
import re
import stat
import struct
import tempfile
import zlib
from dataclasses import dataclass

import numpy as np

from .._budget import BudgetError, check_budget
from .._text import quote
from .._validate import ArgumentTypeError

__all__ = [
    "MAX_SIDE",
    "LINEAR_EXTENSIONS",
    "read_linear",
    "declared_size",
    "read_png",
    "png_bytes",
    "write_png",
    "rgbe_bytes",
    "write_hdr",
    "pfm_bytes",
    "npy_bytes",
    "exr_writer",
    "file_mode",
    "write_temporary",
    "atomic_write",
]

#: The largest side :func:`read_linear` and :func:`read_png` accept unless the caller sets a limit.
MAX_SIDE = 65536
#: The file extensions :func:`read_linear` reads.
LINEAR_EXTENSIONS = (".hdr", ".pic", ".pfm", ".npy", ".exr")
_HEADER_LIMIT = 1 << 16  # bytes of RGBE/PFM header scanned before giving up
_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


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


# --------------------------------------------------------------------------- reading
def read_linear(path, *, kind: str = "image", max_height: int = MAX_SIDE, max_width: int = MAX_SIDE,
                aspect: int | None = None, shape: str = "") -> np.ndarray:  # fmt: skip
    """Read a linear radiance image (``.hdr``/``.pic``, ``.pfm``, ``.npy``, ``.exr``) as RGB ``float32``.

    Parameters
    ----------
    path : str or os.PathLike
        The file; the format is chosen by its extension (module notes).
    kind : str
        What the file is, in the messages (``"environment image"``: "no such file; allowed: an existing
        environment image") and the memory budget's label.
    max_height, max_width : int
        The largest size accepted, checked on the header before any pixel is decoded.
    aspect : int, optional
        When given, the width must be ``aspect`` times the height.
    shape : str
        The allowed shape in words, for the messages about an empty or wrongly shaped image.

    Returns
    -------
    ndarray, (H, W, 3), float32
        Linear RGB, row 0 at the top; finite and ``>= 0``.

    Raises
    ------
    ValueError
        One line ``"<path>: <what is wrong>; <what is allowed>"`` for a missing, unreadable or
        malformed file, a size beyond the limits or of another shape, negative, NaN or infinite
        radiance, a memory estimate over the budget (:class:`~lighting._budget.BudgetError`), or
        ``.exr`` without the ``OpenEXR`` package.

    Examples
    --------
    >>> import os, tempfile
    >>> p = os.path.join(tempfile.mkdtemp(), "strip.hdr")
    >>> write_hdr(p, np.full((1, 3, 3), 0.25))
    >>> read_linear(p)[0, :, 0].tolist()   # RGBE: 8 bits of mantissa, centred
    [0.2509765625, 0.2509765625, 0.2509765625]
    """
    name = _path_name(path)
    ext = os.path.splitext(name)[1].lower()
    if ext not in LINEAR_EXTENSIONS:
        raise _error(name, f"unknown extension {ext or '(none)'!r}", f"allowed: {', '.join(LINEAR_EXTENSIONS)}")
    limits = _Limits(name, kind, max_height, max_width, aspect, shape)
    if ext == ".exr":
        return _read_exr(limits)
    data = _read_bytes(name, kind)
    try:
        if ext in (".hdr", ".pic"):
            return _decode_rgbe(data, limits)
        if ext == ".pfm":
            return _decode_pfm(data, limits)
        return _decode_npy(data, limits)
    except _Bad as e:
        raise _error(name, e.what, e.allowed) from None


def declared_size(path) -> tuple[int, int] | None:
    """``(height, width)`` an image file's header declares, read without reading its pixels.

    The readers' own header parsers, on the file's first bytes: what a caller may charge to the
    memory budget before it reads the whole file (the reader checks it again).

    Parameters
    ----------
    path : str or os.PathLike
        A ``.hdr``/``.pic``, ``.pfm``, ``.npy``, ``.png`` or ``.exr`` file (``.exr``: when the ``OpenEXR``
        package is installed).

    Returns
    -------
    tuple of int, or None
        None when the header cannot be read or parsed: the reader then names the problem itself.

    Examples
    --------
    >>> import os, tempfile
    >>> p = os.path.join(tempfile.mkdtemp(), "big.pfm")
    >>> with open(p, "wb") as f:   # a header alone: no pixels follow
    ...     _ = f.write(b"PF\\n8192 4096\\n-1.0\\n")
    >>> declared_size(p)
    (4096, 8192)
    """
    name = os.fspath(path)
    ext = os.path.splitext(name)[1].lower()
    try:
        if ext == ".exr":
            import OpenEXR

            f = OpenEXR.InputFile(name)
            try:
                return _exr_window(f.header())
            finally:
                f.close()
        with open(name, "rb") as f:
            if ext == ".npy":
                shape = _npy_header(f)[0]
                return int(shape[0]), int(shape[1])
            head = f.read(_HEADER_LIMIT + 128)
        if ext in (".hdr", ".pic"):
            return _rgbe_header(head)[:2]
        if ext == ".pfm":
            return _pfm_header(head)[:2]
        if ext == ".png":
            return _png_header(head)[:2]
    except (_Bad, ImportError, OSError, ValueError):
        return None
    except Exception:  # noqa: BLE001 (OpenEXR raises several kinds on corrupt files: the reader names them)
        return None
    return None


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


# -- RGBE ---------------------------------------------------------------------------------
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


# -- PFM ----------------------------------------------------------------------------------
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


# -- NPY ----------------------------------------------------------------------------------
def _npy_header(f):
    """``(shape, fortran_order, dtype)`` of the ``.npy`` file object ``f``, checked; ``f`` left at the values."""
    fmt = np.lib.format
    try:
        version = fmt.read_magic(f)
        if version == (1, 0):
            shape, fortran, dtype = fmt.read_array_header_1_0(f)
        elif version == (2, 0):
            shape, fortran, dtype = fmt.read_array_header_2_0(f)
        else:
            raise _Bad(f"NPY format version {version}", "allowed: versions 1.0 and 2.0")
    except _Bad:
        raise
    except Exception as e:  # noqa: BLE001 (any failure to parse the header is the file's fault)
        msg = str(e).splitlines()[0][:120] if str(e) else type(e).__name__
        raise _Bad(f"not a NumPy .npy file ({msg})", "allowed: a file written by numpy.save") from None
    allowed = "allowed: a real array of shape (H, W, 3) or (H, W)"
    if dtype.hasobject or dtype.kind not in "fiu" or dtype.fields is not None or dtype.subdtype is not None:
        raise _Bad(f"dtype {dtype}", allowed)
    if len(shape) not in (2, 3) or (len(shape) == 3 and shape[2] != 3):
        raise _Bad(f"shape {shape}", allowed)
    return shape, fortran, dtype


def _decode_npy(data: bytes, limits: _Limits) -> np.ndarray:
    f = io.BytesIO(data)
    shape, fortran, dtype = _npy_header(f)
    h, w = shape[0], shape[1]
    limits.check(h, w, 12 + 12 * dtype.itemsize + 4)
    need = math.prod(shape) * dtype.itemsize
    body = len(data) - f.tell()
    if body < need:
        raise _Bad(f"the file is truncated: {body} bytes of values", f"allowed: {need} bytes for shape {shape}")
    if body > need:
        raise _Bad(f"{body - need} extra bytes after the values", f"allowed: exactly {need} bytes")
    flat = np.frombuffer(data, dtype=dtype, count=math.prod(shape), offset=f.tell())
    arr = flat.reshape(shape[::-1]).transpose() if fortran else flat.reshape(shape)
    return _finish(arr.astype(np.float64), limits.name)


# -- EXR ----------------------------------------------------------------------------------
def _exr_window(header):
    """``(h, w)`` of an OpenEXR header's data window."""
    dw = header["dataWindow"]
    return dw.max.y - dw.min.y + 1, dw.max.x - dw.min.x + 1


def _read_exr(limits: _Limits) -> np.ndarray:
    name = limits.name
    try:
        import Imath
        import OpenEXR
    except ImportError:
        raise _error(
            name,
            "reading .exr needs the OpenEXR Python package, which is not installed",
            "allowed here: .hdr, .pic, .pfm, .npy (or pip install OpenEXR)",
        ) from None
    _check_file(name, limits.kind)
    try:
        try:
            with open(name, "rb") as fh:
                magic = fh.read(4)
        except OSError as e:
            raise _Bad(f"cannot be read ({e.strerror})", "allowed: a readable file") from None
        if magic != b"\x76\x2f\x31\x01":
            raise _Bad("not an OpenEXR file (no magic number)", "allowed: a scanline or tiled OpenEXR image")
        f = OpenEXR.InputFile(name)
        try:
            header = f.header()
            h, w = _exr_window(header)
            chans = set(header["channels"])
            names = ("R", "G", "B") if {"R", "G", "B"} <= chans else ("Y",) if "Y" in chans else None
            if names is None:
                raise _Bad(f"channels {sorted(chans)}", "allowed: R, G, B (or Y)")
            limits.check(h, w, 12 + 12 + 4)
            pt = Imath.PixelType(Imath.PixelType.FLOAT)
            planes = [np.frombuffer(f.channel(c, pt), dtype=np.float32) for c in names]
        finally:
            f.close()
        if any(p.size != h * w for p in planes):
            raise _Bad(f"channels hold {[p.size for p in planes]} values", f"allowed: {h * w} each")
        img = np.stack([p.reshape(h, w) for p in planes], axis=-1).astype(np.float64)
        return _finish(img, name)
    except _Bad as e:
        raise _error(name, e.what, e.allowed) from None
    except BudgetError:
        raise
    except ValueError as e:
        if str(e).startswith(name):
            raise
        raise _error(name, f"cannot be decoded ({str(e)[:120]})", "allowed: a valid OpenEXR image") from None
    except Exception as e:  # noqa: BLE001 (OpenEXR raises OSError and others on corrupt files)
        raise _error(name, f"cannot be decoded ({type(e).__name__})", "allowed: a valid OpenEXR image") from None


# -- PNG ----------------------------------------------------------------------------------
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


# --------------------------------------------------------------------------- writing
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
    >>> float(read_linear(p).max())   # (128 + ½) 2^-8
    0.501953125
    """
    atomic_write(path, rgbe_bytes(image, rle=rle))


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


def npy_bytes(linear: np.ndarray) -> bytes:
    """A NumPy ``.npy`` file's bytes for an array, dtype kept, without pickles.

    Parameters
    ----------
    linear : numpy.ndarray
        The array (the command line writes its linear ``(H, W, 3)`` image).

    Returns
    -------
    bytes
        The file, as ``numpy.save`` writes it.
    """
    buf = io.BytesIO()
    np.save(buf, linear, allow_pickle=False)
    return buf.getvalue()


def exr_writer(linear: np.ndarray):
    """A function that writes ``linear`` as an OpenEXR file (float32 ``R``, ``G``, ``B``) at the path it is given.

    OpenEXR writes its files itself, so :func:`atomic_write` takes this callable in place of bytes.

    Parameters
    ----------
    linear : numpy.ndarray, (H, W, 3), float
        Linear RGB, row 0 at the top.

    Returns
    -------
    callable
        ``write(path)``; it needs the ``OpenEXR`` package when called.
    """

    def write(tmp: str) -> None:
        import Imath
        import OpenEXR

        h, w, _ = linear.shape
        header = OpenEXR.Header(w, h)
        ch = Imath.Channel(Imath.PixelType(Imath.PixelType.FLOAT))
        header["channels"] = {"R": ch, "G": ch, "B": ch}
        out = OpenEXR.OutputFile(tmp, header)
        try:
            a = np.ascontiguousarray(linear, dtype=np.float32)
            out.writePixels({c: a[..., i].tobytes() for i, c in enumerate("RGB")})
        finally:
            out.close()

    return write


# --------------------------------------------------------------------------- atomic writing
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


def write_temporary(path, data, *, guard=None) -> tuple[str, str]:
    """Write ``data`` to a new temporary file beside ``path``'s target, flushed to disk; the first half of a write.

    The file is named ``.<name>.<random>.part`` in the target's folder and gets :func:`file_mode`'s
    permissions.  On any exception (``KeyboardInterrupt`` too) it is removed before the exception
    goes on.  :func:`atomic_write` renames it into place; a caller writing several files as a unit
    renames them together.

    Parameters
    ----------
    path : str or os.PathLike
        The file to be written; a symbolic link is followed (its target is the file replaced).
    data : bytes or callable
        The contents, or ``data(temporary_path)`` writing them (for libraries that write files themselves).
    guard : callable, optional
        A context manager factory held while the temporary file is created (the command line holds
        its stop signals there, so that the file is never created without its name being known here).

    Returns
    -------
    tuple of str
        ``(temporary path, target path)``.
    """
    path = os.fspath(path)
    target = os.path.realpath(path) if os.path.islink(path) else os.path.abspath(path)
    mode = file_mode(target)
    fd, tmp = -1, None
    try:
        with guard() if guard is not None else contextlib.nullcontext():
            fd, tmp = tempfile.mkstemp(prefix=f".{os.path.basename(target)}.", suffix=".part",
                                       dir=os.path.dirname(target))  # fmt: skip
        os.fchmod(fd, mode)
        if callable(data):
            os.close(fd)
            fd = -1
            data(tmp)
            fd = os.open(tmp, os.O_RDONLY)
            os.fsync(fd)
            os.close(fd)
            fd = -1
        else:
            with os.fdopen(fd, "wb") as f:
                fd = -1
                f.write(data)
                f.flush()
                os.fsync(f.fileno())
    except BaseException:
        if fd >= 0:
            os.close(fd)
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        raise
    return tmp, target


def atomic_write(path, data) -> None:
    """Write ``data`` to ``path`` atomically: a temporary file beside it, flushed, then renamed into place.

    A reader sees the old file or the whole new one.  On any exception the temporary file is removed
    and the target is left as it was.

    Parameters
    ----------
    path : str or os.PathLike
        The file; a symbolic link is followed and its target replaced.
    data : bytes or callable
        The contents, or ``data(temporary_path)`` writing them (:func:`exr_writer`).

    Examples
    --------
    >>> import os, tempfile
    >>> d = tempfile.mkdtemp()
    >>> atomic_write(os.path.join(d, "a.pfm"), pfm_bytes(np.zeros((1, 1, 3))))
    >>> os.listdir(d), os.path.getsize(os.path.join(d, "a.pfm"))
    (['a.pfm'], 24)
    """
    tmp, target = write_temporary(path, data)
    try:
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise

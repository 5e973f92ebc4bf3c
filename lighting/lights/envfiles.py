r"""Environment images from files, rotated and scaled environments, and one loader for all sources.

Files
-----
:func:`read_environment_image` reads a latitude–longitude radiance image (the frame of
:mod:`lighting.lights.environment`: row 0 the zenith, columns growing with ``φ``; width = 2 × height)
as linear RGB ``float32``:

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

Files are untrusted input: the size is read from the header, checked (at most
:data:`MAX_HEIGHT` × :data:`MAX_WIDTH`, width = 2 × height) and its memory charged to the engine's
budget (:func:`lighting._numeric.check_budget`) *before* the pixels are read.  Every malformed file
is one ``ValueError`` line, ``"<path>: <what is wrong>; <what is allowed>"``; so is a negative, NaN
or infinite radiance (naming the pixel).

Rotation and intensity
----------------------
:class:`TransformedEnvironment` turns an environment by ``rotation`` degrees about ``+z`` (toward
``+φ``) and multiplies it by ``intensity``; :func:`load_environment` builds any environment from a
path, a sky name (:mod:`lighting.lights.skies`) or a constant radiance.

References
----------
G. Ward, "Real Pixels", Graphics Gems II (1991), 80–83; the Radiance file formats
(``radsite.lbl.gov/radiance/refer/filefmts.pdf``).
"""

from __future__ import annotations

import math
import os
import re
import stat
import tempfile

import numpy as np

from .._budget import BudgetError, check_budget
from .._numeric import ArgumentTypeError, _fmt, check_color, check_count, check_range, cos_sin_deg
from .environment import ConstantEnvironment, Environment, LatLongEnvironment

__all__ = [
    "MAX_HEIGHT",
    "MAX_WIDTH",
    "IMAGE_EXTENSIONS",
    "read_environment_image",
    "declared_image_size",
    "write_hdr",
    "TransformedEnvironment",
    "load_environment",
]

#: The largest environment image read: 8192 rows, 16384 columns (1.5 GiB as float32 RGB).
MAX_HEIGHT = 8192
MAX_WIDTH = 2 * MAX_HEIGHT
#: The file extensions :func:`read_environment_image` reads.
IMAGE_EXTENSIONS = (".hdr", ".pic", ".pfm", ".npy", ".exr")
_HEADER_LIMIT = 1 << 16  # bytes of RGBE/PFM header scanned before giving up
_ASPECT = "a latitude-longitude image, width = 2 x height (e.g. 1024x512)"


class _Bad(Exception):
    """A problem found while decoding; turned into the one-line ValueError naming the file."""

    def __init__(self, what: str, allowed: str):
        super().__init__(what)
        self.what, self.allowed = what, allowed


def _error(path: str, what: str, allowed: str) -> ValueError:
    return ValueError(f"{path}: {what}; {allowed}")


# --------------------------------------------------------------------------- reading
def read_environment_image(path) -> np.ndarray:
    """Read a latitude–longitude radiance image (``.hdr``/``.pic``, ``.pfm``, ``.npy``, ``.exr``).

    Parameters
    ----------
    path : str or os.PathLike
        The file; the format is chosen by its extension (module notes).

    Returns
    -------
    ndarray, (H, W, 3), float32
        Linear RGB radiance, row 0 at the zenith, ``W = 2 H``; finite and ``>= 0``.

    Raises
    ------
    ValueError
        One line ``"<path>: <what is wrong>; <what is allowed>"`` for a missing, unreadable or
        malformed file, a size other than ``W = 2 H`` or beyond 8192 x 16384, negative, NaN or
        infinite radiance, a memory estimate over the budget (:class:`~lighting._budget.BudgetError`),
        or ``.exr`` without the ``OpenEXR`` package.

    Examples
    --------
    >>> import os, tempfile
    >>> p = os.path.join(tempfile.mkdtemp(), "sky.hdr")
    >>> img = np.zeros((2, 4, 3), np.float32); img[0] = 1.0   # bright sky, black ground
    >>> write_hdr(p, img)
    >>> read_environment_image(p)[:, :, 0].tolist()   # RGBE: 8 bits of mantissa, centred
    [[1.00390625, 1.00390625, 1.00390625, 1.00390625], [0.0, 0.0, 0.0, 0.0]]
    """
    if not isinstance(path, str | os.PathLike):
        raise ArgumentTypeError(f"path must be a str or os.PathLike; got {type(path).__name__} {_fmt(path)}")
    name = os.fspath(path)
    if isinstance(name, bytes):
        name = os.fsdecode(name)
    ext = os.path.splitext(name)[1].lower()
    if ext not in IMAGE_EXTENSIONS:
        raise _error(name, f"unknown extension {ext or '(none)'!r}", f"allowed: {', '.join(IMAGE_EXTENSIONS)}")
    if ext == ".exr":
        return _read_exr(name)
    data = _read_bytes(name)
    try:
        if ext in (".hdr", ".pic"):
            img = _decode_rgbe(data, name)
        elif ext == ".pfm":
            img = _decode_pfm(data, name)
        else:
            img = _decode_npy(data, name)
    except _Bad as e:
        raise _error(name, e.what, e.allowed) from None
    return img


def declared_image_size(path) -> tuple[int, int] | None:
    """``(height, width)`` an environment image's header declares, read without reading its pixels.

    The readers' own header parsers, on the file's first bytes: what a scene charges to the memory
    budget before :func:`read_environment_image` reads the whole file (which checks it again).

    Parameters
    ----------
    path : str or os.PathLike
        A ``.hdr``/``.pic``, ``.pfm``, ``.npy`` or ``.exr`` file (``.exr``: when the ``OpenEXR`` package is
        installed).

    Returns
    -------
    tuple of int, or None
        None when the header cannot be read or parsed: the reader then names the problem itself.

    Examples
    --------
    >>> import os, tempfile
    >>> p = os.path.join(tempfile.mkdtemp(), "big.hdr")
    >>> with open(p, "wb") as f:   # a header alone: no pixels follow
    ...     _ = f.write(b"#?RADIANCE\\nFORMAT=32-bit_rle_rgbe\\n\\n-Y 4096 +X 8192\\n")
    >>> declared_image_size(p)
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
    except (_Bad, ImportError, OSError, ValueError):
        return None
    except Exception:  # noqa: BLE001 (OpenEXR raises several kinds on corrupt files: the reader names them)
        return None
    return None


def _check_file(name: str) -> None:
    """Refuse a missing file, a directory or a special file, and a file larger than the budget."""
    try:
        st = os.stat(name)  # before open: opening a FIFO for reading would wait for a writer
    except FileNotFoundError:
        raise _error(name, "no such file", "allowed: an existing environment image") from None
    except OSError as e:
        raise _error(name, f"cannot be opened ({e.strerror})", "allowed: a readable file") from None
    if stat.S_ISDIR(st.st_mode):
        raise _error(name, "is a directory", "allowed: a regular file")
    if not stat.S_ISREG(st.st_mode):
        raise _error(name, "is not a regular file", "allowed: a regular file")
    check_budget(f"environment image {name!r}", st.st_size, what=f"a file of {st.st_size} bytes")


def _read_bytes(name: str) -> bytes:
    """The whole file, after :func:`_check_file`."""
    _check_file(name)
    try:
        with open(name, "rb") as f:
            return f.read()
    except OSError as e:
        raise _error(name, f"cannot be read ({e.strerror})", "allowed: a readable file") from None


def _check_size(h: int, w: int, name: str, bytes_per_pixel: int) -> None:
    """Refuse sizes that are zero, beyond the caps or not 2:1, then charge the decoder's memory."""
    if h < 1 or w < 1:
        raise _Bad(f"image size {w}x{h} is empty", f"allowed: {_ASPECT}")
    if h > MAX_HEIGHT or w > MAX_WIDTH:
        raise _Bad(f"image size {w}x{h} is too large", f"allowed: at most {MAX_WIDTH}x{MAX_HEIGHT}")
    if w != 2 * h:
        raise _Bad(f"image size {w}x{h} is not 2:1", f"allowed: {_ASPECT}")
    check_budget(f"environment image {name!r}", h * w * bytes_per_pixel, what=f"a {w}x{h} image and its decoding")


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


def _decode_rgbe(data: bytes, name: str) -> np.ndarray:
    h, w, bottom_up, right_to_left, exposure, start = _rgbe_header(data)
    # Output float32 RGB, the RGBE bytes and the float64 temporaries of the conversion.
    _check_size(h, w, name, 12 + 4 + 48)
    rgbe = _rgbe_scanlines(data, start, h, w)
    if bottom_up:
        rgbe = rgbe[::-1]
    if right_to_left:
        rgbe = rgbe[:, ::-1]
    e = rgbe[..., 3].astype(np.int32)
    f = np.where(e > 0, np.ldexp(1.0, e - 136), 0.0)
    img = (rgbe[..., :3] + 0.5) * f[..., None]
    return _finish(img, name, exposure)


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


def _decode_pfm(data: bytes, name: str) -> np.ndarray:
    h, w, channels, scale, start = _pfm_header(data)
    _check_size(h, w, name, 12 + 12 + 4)
    need = h * w * channels * 4
    body = len(data) - start
    if body < need:
        raise _Bad(f"the file is truncated: {body} bytes of pixels", f"allowed: {need} bytes for {w}x{h}x{channels}")
    if body > need:
        raise _Bad(f"{body - need} extra bytes after the pixels", f"allowed: exactly {need} bytes of pixels")
    dt = "<f4" if scale < 0 else ">f4"
    px = np.frombuffer(data, dtype=dt, count=h * w * channels, offset=start).reshape(h, w, channels)
    return _finish(px[::-1], name)


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


def _decode_npy(data: bytes, name: str) -> np.ndarray:
    import io

    f = io.BytesIO(data)
    shape, fortran, dtype = _npy_header(f)
    h, w = shape[0], shape[1]
    _check_size(h, w, name, 12 + 12 * dtype.itemsize + 4)
    need = math.prod(shape) * dtype.itemsize
    body = len(data) - f.tell()
    if body < need:
        raise _Bad(f"the file is truncated: {body} bytes of values", f"allowed: {need} bytes for shape {shape}")
    if body > need:
        raise _Bad(f"{body - need} extra bytes after the values", f"allowed: exactly {need} bytes")
    flat = np.frombuffer(data, dtype=dtype, count=math.prod(shape), offset=f.tell())
    arr = flat.reshape(shape[::-1]).transpose() if fortran else flat.reshape(shape)
    return _finish(arr.astype(np.float64), name)


# -- EXR ----------------------------------------------------------------------------------
def _exr_window(header):
    """``(h, w)`` of an OpenEXR header's data window."""
    dw = header["dataWindow"]
    return dw.max.y - dw.min.y + 1, dw.max.x - dw.min.x + 1


def _read_exr(name: str) -> np.ndarray:
    try:
        import Imath
        import OpenEXR
    except ImportError:
        raise _error(
            name,
            "reading .exr needs the OpenEXR Python package, which is not installed",
            "allowed here: .hdr, .pic, .pfm, .npy (or pip install OpenEXR)",
        ) from None
    _check_file(name)
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
            _check_size(h, w, name, 12 + 12 + 4)
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


# --------------------------------------------------------------------------- writing
def _rgbe_bytes(img: np.ndarray) -> np.ndarray:
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


def write_hdr(path, image, *, rle: bool = True) -> None:
    """Write linear RGB radiance as a Radiance ``.hdr`` (RGBE) file, atomically.

    Parameters
    ----------
    path : str or os.PathLike
        Destination; written to a temporary file in the same folder and renamed into place.
    image : array_like, (H, W, 3)
        Finite radiance ``>= 0`` and below ``2^127``; any shape (:func:`read_environment_image`
        reads back only ``W = 2 H``).  Row 0 is stored first (``-Y H +X W``).
    rle : bool
        New-style run-length-encoded scanlines (default; used where the width is 8 to 32767), else
        flat 4-byte pixels.

    Notes
    -----
    Each pixel keeps 8 mantissa bits against its brightest channel (truncated, as Radiance's
    ``setcolr``; the reader adds half a step back): read back, a channel is within ``2^-8`` of the
    pixel's largest value.

    Examples
    --------
    >>> import os, tempfile
    >>> p = os.path.join(tempfile.mkdtemp(), "grey.hdr")
    >>> write_hdr(p, np.full((4, 8, 3), 0.5))
    >>> float(read_environment_image(p).max())   # (128 + ½) 2^-8
    0.501953125
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
    rgbe = _rgbe_bytes(img)
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
    _atomic_write(path, b"".join(parts))


def _atomic_write(path, data: bytes) -> None:
    """Write ``data`` to a temporary file beside ``path`` and rename it into place (mode as ``open`` gives)."""
    from ..render.image import file_mode

    path = os.fspath(path)
    target = os.path.realpath(path) if os.path.islink(path) else os.path.abspath(path)
    mode = file_mode(target)
    tmp = None
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{os.path.basename(target)}.", suffix=".part", dir=os.path.dirname(target))
        with os.fdopen(fd, "wb") as f:
            os.fchmod(f.fileno(), mode)
            f.write(data)
        os.replace(tmp, target)
        tmp = None
    finally:
        if tmp is not None and os.path.exists(tmp):
            os.unlink(tmp)


# --------------------------------------------------------------------------- transformed environments
class TransformedEnvironment(Environment):
    r"""An environment turned about ``+z`` and scaled: ``L(d) = intensity · L_base(R_z(−rotation) d)``.

    A positive ``rotation`` (degrees) turns the environment toward ``+φ``: what the base shows at
    ``φ`` appears at ``φ + rotation``.  Sampling draws from the base's density and turns the
    directions by ``+rotation``, so ``pdf(d) = pdf_base(R_z(−rotation) d)``; ``intensity`` does not
    change the density.

    Parameters
    ----------
    base : Environment
        The environment to transform.
    intensity : float or RGB triple, >= 0
        Multiplies the radiance (per channel for a triple).
    rotation : float
        Degrees about ``+z``, finite; multiples of 90° are exact.

    Attributes
    ----------
    base : Environment
    intensity : float or ndarray (3,)
        As given (a triple as a float64 array).
    rotation : float
        Degrees.

    Examples
    --------
    >>> from lighting.lights.environment import FunctionEnvironment
    >>> east = FunctionEnvironment(lambda d: np.maximum(d[..., 0], 0.0))   # bright toward +x
    >>> env = TransformedEnvironment(east, intensity=2.0, rotation=90.0)  # now toward +y, twice as bright
    >>> env.radiance(np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]))[:, 0].tolist()
    [2.0, 0.0]
    """

    def __init__(self, base: Environment, intensity=1.0, rotation: float = 0.0):
        if not isinstance(base, Environment):
            raise ArgumentTypeError(f"base must be an Environment; got {type(base).__name__} {_fmt(base)}")
        self.base = base
        scale = check_color("intensity", intensity)
        self.intensity = float(scale[0]) if np.ndim(intensity) == 0 else scale
        self._scale = scale
        self.rotation = check_range("rotation", rotation)
        c, s = cos_sin_deg(self.rotation)
        self._c, self._s = float(c), float(s)
        if base.support is not None:
            axis, half = base.support
            self.support = (self.from_base(np.asarray(axis, dtype=np.float64)), half)

    def __repr__(self):
        inten = self.intensity if isinstance(self.intensity, float) else self.intensity.tolist()
        return f"TransformedEnvironment({self.base!r}, intensity={inten!r}, rotation={self.rotation!r})"

    def to_base(self, directions) -> np.ndarray:
        """World directions in the base environment's frame: ``R_z(−rotation) d``.

        Parameters
        ----------
        directions : array_like, (..., 3)
            Any directions (not normalized; lengths are kept).

        Returns
        -------
        ndarray, (..., 3)
            In the float dtype of ``directions`` (float64 for integers or Python numbers).
        """
        return self._turn(directions, -self._s)

    def from_base(self, directions) -> np.ndarray:
        """Base-frame directions in the world frame: ``R_z(+rotation) d`` (inverse of :meth:`to_base`).

        Parameters
        ----------
        directions : array_like, (..., 3)

        Returns
        -------
        ndarray, (..., 3)
            In the float dtype of ``directions`` (float64 for integers or Python numbers).
        """
        return self._turn(directions, self._s)

    def _turn(self, directions, s):
        d = np.asarray(directions)
        if d.dtype.kind != "f":
            d = d.astype(np.float64)
        if self._c == 1.0 and s == 0.0:
            return d.copy()
        c = d.dtype.type(self._c)
        s = d.dtype.type(s)
        x, y = d[..., 0], d[..., 1]
        return np.stack([c * x - s * y, s * x + c * y, d[..., 2]], axis=-1)

    def _radiance(self, d):
        return self.base._radiance(self.to_base(d)) * self._scale

    def _sample(self, u):
        d, pdf = self.base._sample(u)
        return self.from_base(d), pdf

    def _pdf(self, d):
        return self.base._pdf(self.to_base(d))


# --------------------------------------------------------------------------- one loader
def _downsample(img: np.ndarray, height: int, name: str) -> np.ndarray:
    h = img.shape[0]
    if height == h:
        return img
    if height > h or h % height:
        raise _error(name, f"height {height} does not divide the image's {h} rows", f"allowed: a divisor of {h}")
    k = h // height
    out = img.reshape(height, k, 2 * height, k, 3).astype(np.float64).mean(axis=(1, 3))
    return out


def load_environment(source, *, intensity=1.0, rotation: float = 0.0, height: int | None = None) -> Environment:
    """An environment from a file, a sky name or a constant radiance, optionally scaled and turned.

    Parameters
    ----------
    source : str, os.PathLike, float, RGB triple or Environment
        A path to a ``.hdr``/``.pic``/``.pfm``/``.npy``/``.exr`` latitude–longitude image
        (:class:`~lighting.lights.environment.LatLongEnvironment`), the name of a sky of
        :data:`lighting.lights.skies.SKIES`, a radiance (:class:`~lighting.lights.environment.ConstantEnvironment`)
        or an environment (used as is).
    intensity : float or RGB triple, >= 0
        Radiance multiplier.
    rotation : float
        Degrees about ``+z`` (toward ``+φ``).
    height : int, optional
        For a sky: tabulate it as an image of ``height`` rows (fast lookups); for an image file:
        average it down to ``height`` rows (a divisor of its height).  Ignored for constants.

    Returns
    -------
    Environment
        Wrapped in :class:`TransformedEnvironment` only when ``intensity != 1`` or ``rotation != 0``.

    Examples
    --------
    >>> env = load_environment("uniform", intensity=0.5)
    >>> env.radiance((0.0, 0.0, 1.0)).tolist()
    [0.5, 0.5, 0.5]
    >>> load_environment((1.0, 0.5, 0.25))
    ConstantEnvironment([1.0, 0.5, 0.25])
    """
    from .skies import SKIES, _lookup, sky

    scale = check_color("intensity", intensity)
    rotation = check_range("rotation", rotation)
    if height is not None:
        height = check_count("height", height, 1, MAX_HEIGHT)
    if isinstance(source, Environment):
        env = source
    elif isinstance(source, os.PathLike) or (
        isinstance(source, str)
        and (
            os.path.splitext(source)[1].lower() in IMAGE_EXTENSIONS
            or (source.strip().lower().replace("_", "-") not in SKIES and os.path.exists(source))
        )
    ):
        name = os.fspath(source)
        img = read_environment_image(name)
        if height is not None:
            img = _downsample(img, height, name)
        env = LatLongEnvironment(img)
    elif isinstance(source, str):
        try:
            s = _lookup(source)
        except ValueError as e:
            raise ValueError(f"{e} (or a path to a {', '.join(IMAGE_EXTENSIONS)} image)") from None
        env = sky(s.name)
        if height is not None:
            env = LatLongEnvironment.from_function(s.function, height)
    else:
        try:
            env = ConstantEnvironment(source)
        except ValueError:
            raise ValueError(
                f"environment source must be a path, a sky name ({', '.join(SKIES)}) or a radiance >= 0; "
                f"got {type(source).__name__} {_fmt(source)}"
            ) from None
    if np.all(scale == 1.0) and rotation == 0.0:
        return env
    return TransformedEnvironment(env, intensity=intensity, rotation=rotation)

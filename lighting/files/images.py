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

Modules
-------
This module reads by extension (:func:`read_linear`, :func:`declared_size`) and gathers every public
name; each format lives in its own module: :mod:`lighting.files.png`, :mod:`lighting.files.rgbe`,
:mod:`lighting.files.pfm`, :mod:`lighting.files.npy`, :mod:`lighting.files.exr`.  The checks before
allocation are :mod:`lighting.files.image_checks`'s, the atomic writer :mod:`lighting.files.atomic`'s.

References
----------
G. Ward, "Real Pixels", Graphics Gems II (1991), 80–83; the Radiance file formats
(``radsite.lbl.gov/radiance/refer/filefmts.pdf``); the PNG specification (ISO/IEC 15948).
"""

from __future__ import annotations

import os

import numpy as np

from .atomic import atomic_write, file_mode, write_temporary
from .exr import _exr_window, _read_exr, exr_writer
from .image_checks import _HEADER_LIMIT, MAX_SIDE, _Bad, _error, _Limits, _path_name, _read_bytes
from .npy import _decode_npy, _npy_header, npy_bytes
from .pfm import _decode_pfm, _pfm_header, pfm_bytes
from .png import _png_header, png_bytes, read_png, write_png
from .rgbe import _decode_rgbe, _rgbe_header, rgbe_bytes, write_hdr

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
#: The file extensions :func:`read_linear` reads.
LINEAR_EXTENSIONS = (".hdr", ".pic", ".pfm", ".npy", ".exr")


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

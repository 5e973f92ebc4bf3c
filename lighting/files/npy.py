"""NumPy ``.npy`` images: the decoder :func:`lighting.files.images.read_linear` uses (without pickles), and
the bytes of one.
"""

from __future__ import annotations

import io
import math

import numpy as np

from .image_checks import _Bad, _finish, _Limits

__all__ = ["npy_bytes"]


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

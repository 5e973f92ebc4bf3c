"""OpenEXR images, when the optional ``OpenEXR`` package is installed: the reader
:func:`lighting.files.images.read_linear` uses, and the writer :func:`lighting.files.atomic.atomic_write` calls.
"""

from __future__ import annotations

import numpy as np

from .._budget import BudgetError
from .image_checks import _Bad, _check_file, _error, _finish, _Limits

__all__ = ["exr_writer"]


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

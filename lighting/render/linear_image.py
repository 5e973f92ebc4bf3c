r"""A rendered image that knows it is linear RGB: :class:`LinearImage`.

The engine lights in linear RGB, and a picture on a screen is sRGB-encoded.  Shown as
it is (``plt.imshow(img)``), a linear image looks too dark and its gradients wrong.  The
renderers therefore return a :class:`LinearImage`: a NumPy array (an ``ndarray``
subclass, so every computation on it works as before) that also carries its display
settings (``exposure`` in stops, ``tonemap``) and shows itself correctly encoded:

* in Jupyter, as an image: :meth:`LinearImage._repr_png_` encodes with the engine's own
  sRGB transfer function (:func:`lighting.render.image.encode_srgb8`) and writes the PNG
  with the standard library (no PIL, no Matplotlib);
* :meth:`LinearImage.srgb8` gives the 8-bit sRGB pixels (for ``plt.imshow`` or any image
  library), :meth:`LinearImage.png` the PNG bytes, :meth:`LinearImage.save` a PNG file;
* ``np.asarray(img)`` is the plain linear array, values unchanged (no copy).

Arithmetic keeps the type (``2 * img`` is still a linear image); results that are no
longer an RGB image (a reduction such as ``img.max()``, a comparison, one channel) are
plain arrays and scalars.

Examples
--------
>>> img = LinearImage(np.full((2, 3, 3), 0.5))
>>> img
LinearImage(3x2 linear RGB, float64, max 0.5)
>>> img.srgb8()[0, 0].tolist()          # linear 0.5 is sRGB code 188, not 128
[188, 188, 188]
>>> img.with_exposure(1).srgb8()[0, 0].tolist()   # one stop brighter: 1.0
[255, 255, 255]
>>> type(np.asarray(img)).__name__, type(img * 2).__name__, type(img.max()).__name__
('ndarray', 'LinearImage', 'float64')
"""

from __future__ import annotations

import numpy as np

from .._validate import check_choice, check_range
from .image import MAX_EXPOSURE, encode_srgb8, png_bytes, write_png

__all__ = ["LinearImage", "as_linear_image"]

TONEMAPS = ("clamp", "reinhard")


def _is_image(a: np.ndarray) -> bool:
    """Whether ``a`` is a picture: ``(H, W, 3)`` floats with at least one pixel."""
    return a.ndim == 3 and a.shape[-1] == 3 and a.shape[0] > 0 and a.shape[1] > 0 and a.dtype.kind == "f"


class LinearImage(np.ndarray):
    """A linear RGB image ``(H, W, 3)`` that shows itself sRGB-encoded (an ``ndarray`` subclass).

    Parameters
    ----------
    data : array_like, shape (H, W, 3)
        Linear RGB values (floats; integers are converted to float64).  Not copied when it
        already is a float array.
    exposure : float
        Display exposure in stops, in ``[-100, 100]``: values are multiplied by
        ``2**exposure`` when encoded.  The values of the array do not change.
    tonemap : {"clamp", "reinhard"}
        ``clamp`` clips at 1; ``reinhard`` maps ``x → x / (1 + x)`` (see
        :func:`lighting.render.image.encode_srgb8`).

    Attributes
    ----------
    exposure : float
        Stops applied when the image is encoded for display.
    tonemap : str
        Tone map applied when the image is encoded for display.

    Notes
    -----
    ``np.asarray(img)`` (or ``img.view(np.ndarray)``) is the plain array, the same memory;
    ``np.array(img)`` a plain copy.  Slices that are still ``(h, w, 3)`` images stay linear
    images; anything else comes out as a plain array.

    Examples
    --------
    >>> img = LinearImage([[[0.0, 0.5, 2.0]]], exposure=0)
    >>> img.srgb8().tolist()
    [[[0, 188, 255]]]
    >>> img.png()[:8] == b"\\x89PNG\\r\\n\\x1a\\n"
    True
    """

    exposure: float
    tonemap: str

    def __new__(cls, data, *, exposure: float = 0.0, tonemap: str = "clamp"):
        arr = np.asarray(data)
        if arr.dtype.kind not in "f":
            if arr.dtype.kind not in "iub":
                raise ValueError(f"image must hold real numbers; got dtype {arr.dtype}")
            arr = arr.astype(np.float64)
        if arr.ndim != 3 or arr.shape[-1] != 3:
            raise ValueError(f"image must have shape (H, W, 3); got {arr.shape}")
        obj = arr.view(cls)
        obj.exposure = float(check_range("exposure", exposure, -MAX_EXPOSURE, MAX_EXPOSURE))
        obj.tonemap = check_choice("tonemap", tonemap, TONEMAPS)
        return obj

    def __array_finalize__(self, obj):
        self.exposure = getattr(obj, "exposure", 0.0)
        self.tonemap = getattr(obj, "tonemap", "clamp")

    def __array_wrap__(self, arr, context=None, return_scalar=False):
        # A ufunc's result: still a picture (2 * img, img + other) keeps the type; anything else
        # (a comparison's booleans, a reduction, a scalar) is a plain array or a plain scalar.
        if return_scalar:
            return arr[()]
        if isinstance(arr, np.ndarray) and _is_image(arr):
            out = arr.view(type(self))
            out.exposure, out.tonemap = self.exposure, self.tonemap
            return out
        return np.asarray(arr)

    def __getitem__(self, key):
        out = super().__getitem__(key)
        if isinstance(out, LinearImage) and not _is_image(out):
            return out.view(np.ndarray)
        return out

    def __reduce__(self):
        rebuild, args, state = super().__reduce__()
        return rebuild, args, (state, self.exposure, self.tonemap)

    def __setstate__(self, state):
        base, self.exposure, self.tonemap = state
        super().__setstate__(base)

    def __repr__(self) -> str:
        if not _is_image(self):  # pragma: no cover - slicing and ufuncs hand such arrays back as plain arrays
            return repr(self.view(np.ndarray))
        h, w, _ = self.shape
        plain = self.view(np.ndarray)
        peak = float(plain.max())
        text = f"LinearImage({w}x{h} linear RGB, {self.dtype}, max {peak:.4g}"
        if self.exposure != 0:
            text += f", exposure {self.exposure:g}"
        if self.tonemap != "clamp":
            text += f", tonemap {self.tonemap}"
        return text + ")"

    # ------------------------------------------------------------------ display
    def with_exposure(self, exposure: float, tonemap: str | None = None) -> LinearImage:
        """The same pixels (no copy) shown with another exposure (and tone map).

        Parameters
        ----------
        exposure : float
            Stops, in ``[-100, 100]``.
        tonemap : {"clamp", "reinhard"}, optional
            Default: this image's.

        Returns
        -------
        LinearImage
            A view of the same memory.
        """
        return LinearImage(self.view(np.ndarray), exposure=exposure,
                           tonemap=self.tonemap if tonemap is None else tonemap)  # fmt: skip

    def srgb8(self, *, exposure: float | None = None, tonemap: str | None = None) -> np.ndarray:
        """The 8-bit sRGB pixels ``(H, W, 3)`` (what the screen should show).

        Parameters
        ----------
        exposure : float, optional
            Stops; default :attr:`exposure`.
        tonemap : {"clamp", "reinhard"}, optional
            Default :attr:`tonemap`.

        Returns
        -------
        numpy.ndarray, (H, W, 3), uint8
            :func:`lighting.render.image.encode_srgb8` of the linear values.
        """
        e = self.exposure if exposure is None else exposure
        t = self.tonemap if tonemap is None else tonemap
        return encode_srgb8(self.view(np.ndarray), exposure=e, tonemap=t)[0]

    def png(self, *, exposure: float | None = None, tonemap: str | None = None) -> bytes:
        """The image as PNG bytes, sRGB-encoded (:meth:`srgb8`).

        Parameters
        ----------
        exposure, tonemap : optional
            As :meth:`srgb8`.

        Returns
        -------
        bytes
            A complete PNG file (8-bit RGB).
        """
        return png_bytes(np.ascontiguousarray(self.srgb8(exposure=exposure, tonemap=tonemap)))

    def save(self, path) -> None:
        """Write the image as a PNG file, sRGB-encoded with this image's exposure and tone map.

        Parameters
        ----------
        path : str or os.PathLike
            Destination (written atomically, :func:`lighting.render.image.write_png`).
        """
        write_png(path, self.srgb8())

    def _repr_png_(self):
        """Jupyter's rich display: the PNG of :meth:`png`, or None (plain text) when no picture can be made."""
        if not _is_image(self) or not np.isfinite(self.view(np.ndarray)).all():
            return None
        return self.png()


def as_linear_image(image, *, exposure: float = 0.0, tonemap: str = "clamp") -> LinearImage:
    """``image`` as a :class:`LinearImage` (a view, no copy), keeping its display settings if it is one.

    Parameters
    ----------
    image : array_like, shape (H, W, 3)
        Linear RGB.
    exposure : float
        Stops, used when ``image`` is not already a :class:`LinearImage`.
    tonemap : {"clamp", "reinhard"}
        Likewise.

    Returns
    -------
    LinearImage
    """
    if isinstance(image, LinearImage):
        return image
    return LinearImage(image, exposure=exposure, tonemap=tonemap)

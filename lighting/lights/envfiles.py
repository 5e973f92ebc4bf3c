r"""Environments from image files, rotated and scaled environments, and one loader for all sources.

Files
-----
:func:`read_environment_image` reads a latitude–longitude radiance image (the frame of
:mod:`lighting.lights.environment`: row 0 the zenith, columns growing with ``φ``; width = 2 × height)
as linear RGB ``float32`` from a Radiance ``.hdr``/``.pic`` (RGBE), ``.pfm``, ``.npy`` or (with the
``OpenEXR`` package) ``.exr`` file.  The formats, their checks and the writers live in
:mod:`lighting.files.images`; this module adds what makes an environment of an image: the size
(at most :data:`MAX_HEIGHT` × :data:`MAX_WIDTH`, width = 2 × height), checked on the header and
charged to the engine's budget (:func:`lighting._budget.check_budget`) *before* the pixels are read,
and messages that speak of an environment image.  Every malformed file is one ``ValueError`` line,
``"<path>: <what is wrong>; <what is allowed>"``.

Rotation and intensity
----------------------
:class:`TransformedEnvironment` turns an environment by ``rotation`` degrees about ``+z`` (toward
``+φ``) and multiplies it by ``intensity``; :func:`load_environment` builds any environment from a
path, a sky name (:mod:`lighting.lights.skies`) or a constant radiance.
"""

from __future__ import annotations

import os

import numpy as np

from .._text import quote
from .._validate import ArgumentTypeError, check_color, check_count, check_range
from ..files import images
from ..files.images import write_hdr
from ..numerics import cos_sin_deg
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
IMAGE_EXTENSIONS = images.LINEAR_EXTENSIONS
_ASPECT = "a latitude-longitude image, width = 2 x height (e.g. 1024x512)"


def _error(path: str, what: str, allowed: str) -> ValueError:
    return ValueError(f"{path}: {what}; {allowed}")


# --------------------------------------------------------------------------- reading
def read_environment_image(path) -> np.ndarray:
    """Read a latitude–longitude radiance image (``.hdr``/``.pic``, ``.pfm``, ``.npy``, ``.exr``).

    Parameters
    ----------
    path : str or os.PathLike
        The file; the format is chosen by its extension (:mod:`lighting.files.images`).

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
    return images.read_linear(path, kind="environment image", max_height=MAX_HEIGHT, max_width=MAX_WIDTH,
                              aspect=2, shape=_ASPECT)  # fmt: skip


def declared_image_size(path) -> tuple[int, int] | None:
    """``(height, width)`` an environment image's header declares, read without reading its pixels.

    The readers' own header parsers (:func:`lighting.files.images.declared_size`), on the file's first
    bytes: what a scene charges to the memory budget before :func:`read_environment_image` reads the
    whole file (which checks it again).

    Parameters
    ----------
    path : str or os.PathLike
        A ``.hdr``/``.pic``, ``.pfm``, ``.npy`` or ``.exr`` file (``.exr``: when the ``OpenEXR`` package is
        installed).

    Returns
    -------
    tuple of int, or None
        None when the header cannot be read or parsed, or the file is not one of :data:`IMAGE_EXTENSIONS`:
        the reader then names the problem itself.

    Examples
    --------
    >>> import os, tempfile
    >>> p = os.path.join(tempfile.mkdtemp(), "big.hdr")
    >>> with open(p, "wb") as f:   # a header alone: no pixels follow
    ...     _ = f.write(b"#?RADIANCE\\nFORMAT=32-bit_rle_rgbe\\n\\n-Y 4096 +X 8192\\n")
    >>> declared_image_size(p)
    (4096, 8192)
    """
    if os.path.splitext(os.fspath(path))[1].lower() not in IMAGE_EXTENSIONS:
        return None
    return images.declared_size(path)


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
            raise ArgumentTypeError(f"base must be an Environment; got {type(base).__name__} {quote(base)}")
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

    def _radiance_and_pdf(self, d):
        radiance, pdf = self.base._radiance_and_pdf(self.to_base(d))
        return radiance * self._scale, pdf


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
                f"got {type(source).__name__} {quote(source)}"
            ) from None
    if np.all(scale == 1.0) and rotation == 0.0:
        return env
    return TransformedEnvironment(env, intensity=intensity, rotation=rotation)

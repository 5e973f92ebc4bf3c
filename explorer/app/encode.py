"""8-bit sRGB codes of the explorer's linear images, by table look-up.

:func:`encode8` is a fast path of :func:`lighting.render.image.encode_srgb8` (clamp tone map): it
must give the same codes bit for bit, and ``tests/explorer/test_app.py`` holds it to that.  Its
thresholds come from the engine's :func:`lighting.render.image.srgb_to_linear`, so the sRGB
formula keeps one home.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from lighting.render import srgb_to_linear

__all__ = ["encode8"]


@lru_cache(maxsize=64)
def _srgb_thresholds(exposure: float, dtype_name: str) -> np.ndarray:
    """Linear values at which the 8-bit sRGB code steps up, divided by ``2**exposure``, in ``dtype``.

    Code ``k`` starts where ``255 · srgb(x) = k − ½`` (``encode_srgb8`` rounds), i.e. at
    ``srgb_to_linear((k − ½)/255)``; the 256th entry is 1, where clipping starts.  Each
    threshold is rounded *up* to the dtype, so ``x >= t`` in that dtype is the same test as
    in float64.
    """
    dt = np.dtype(dtype_name)
    t = np.append(srgb_to_linear((np.arange(1, 256) - 0.5) / 255.0), 1.0) / 2.0**exposure
    t_dt = t.astype(dt)
    below = t_dt.astype(np.float64) < t
    t_dt[below] = np.nextafter(t_dt[below], dt.type(np.inf))
    return t_dt


@lru_cache(maxsize=64)
def _srgb_bucket_table(exposure: float):
    """Look-up tables that give float32 sRGB codes in two steps, or None if they cannot be exact.

    A float32 ``x >= 0`` falls in one of 65536 *buckets* by its top 16 bits (sign, exponent and
    7 mantissa bits): a bucket spans a relative width of at most 2⁻⁷ = 0.78 %.  The 8-bit
    code steps up at linear values at least 0.9 % apart (the closest pair, codes 254 and 255:
    ``((254.5/255 + 0.055)/(253.5/255 + 0.055))^2.4 = 1.009``), and more below, so a bucket
    holds at most one step: the code of ``x`` is the code of its bucket's smallest value,
    plus one if ``x`` reaches the next step.  Returns ``(first, step)``: the code of each
    bucket's smallest value (uint8, 65536 entries; 0 for negatives, 255 for inf and NaN) and
    the step thresholds by code (float32, 256 entries, the last NaN so that no code passes
    255).  The one-step property is checked on every bucket; None if it fails.
    """
    thr = _srgb_thresholds(exposure, "float32")[:255]
    keys = np.arange(1 << 16, dtype=np.uint32)
    first = np.searchsorted(thr, (keys << 16).view(np.float32), side="right")
    finite = keys[:0x7F80]  # positive finite buckets; 0x7F80 starts inf
    last = np.searchsorted(thr, ((finite << 16) | 0xFFFF).view(np.float32), side="right")
    if np.any(last - first[:0x7F80] > 1):  # pragma: no cover - the sRGB curve never does this
        return None
    step = np.append(thr, np.float32(np.nan)).astype(np.float32)
    return first.astype(np.uint8), step


def encode8(image, coverage=None, exposure: float = 0.0):
    """8-bit sRGB codes of a linear image: :func:`lighting.render.image.encode_srgb8` (clamp) by table look-up.

    The same codes as ``encode_srgb8(image, exposure=exposure)``, without evaluating the sRGB
    curve at every pixel.  Code ``k`` starts at the linear value ``t_k = srgb_to_linear((k −
    ½)/255) / 2^exposure``, so the code of ``x`` is the number of ``t_k <= x``.  For float32 images
    two table look-ups find it (:func:`_srgb_bucket_table`: the top 16 bits of ``x`` give the
    code of its bucket, one comparison adds the step inside the bucket) instead of a binary search
    among the 255 ``t_k``, which float64 images still use.  Pixels outside
    ``coverage`` are black.  Returns ``(rgb8, clipped)``: codes ``(..., 3)`` and the number of
    covered pixels with a channel above 1 after the exposure (counted as the engine counts them).

    Parameters
    ----------
    image : array_like, shape (..., 3)
        Linear RGB; float32 takes the two-step look-up, other dtypes a binary search in float64.
    coverage : array_like of bool, shape (...), optional
        Pixels to encode; the others become black and are not counted as clipped.
    exposure : float
        Stops: the codes of ``image · 2^exposure``.

    Returns
    -------
    rgb8 : ndarray of uint8, shape (..., 3)
        The codes, equal to ``encode_srgb8(image, exposure=exposure)[0]``.
    clipped : int
        Covered pixels with a channel above 1 after the exposure.

    Examples
    --------
    >>> from lighting.render.image import encode_srgb8
    >>> img = np.array([[[0.0, 0.5, 2.0], [0.001, 0.2, 1.0]]])
    >>> bool(np.array_equal(encode8(img)[0], encode_srgb8(img)[0]))
    True
    >>> bool(np.array_equal(encode8(img.astype(np.float32))[0], encode_srgb8(img)[0]))
    True
    """
    # A fast path of lighting.render.image.encode_srgb8 (clamp): it must give that function's codes bit
    # for bit; test_encode8_* in tests/explorer/test_app.py hold it to that at every code step.
    img = np.asarray(image)
    if img.dtype not in (np.float32, np.float64):
        img = img.astype(np.float64)
    x = np.ascontiguousarray(img)
    exposure = float(exposure)
    thr = _srgb_thresholds(exposure, x.dtype.name)
    table = _srgb_bucket_table(exposure) if x.dtype == np.float32 else None
    if table is None:
        codes = np.searchsorted(thr[:255], x, side="right").astype(np.uint8)
    else:
        first, step = table
        codes = first.take(x.view(np.uint32) >> 16)
        codes += x >= step.take(codes)
    cov = None if coverage is None else np.asarray(coverage, dtype=bool).reshape(-1)
    if cov is not None:
        codes *= cov.reshape(x.shape[:-1] + (1,))
    # Clipped: the engine's test ``x · 2^exposure > 1`` in float64, made only on the values that
    # can pass it (at least one step of the dtype below the clip level; usually none).
    near = np.flatnonzero(x.reshape(-1) >= np.nextafter(thr[255], x.dtype.type(0)))
    clipped = 0
    if near.size:
        over = near[x.reshape(-1)[near].astype(np.float64) * 2.0**exposure > 1.0] // 3
        if cov is not None:
            over = over[cov[over]]
        clipped = int(np.count_nonzero(np.diff(over) != 0) + 1) if over.size else 0
    return codes, clipped

"""Row-pair convolution of latitude–longitude images, the heart of prefiltering (:mod:`lighting.integrate.prefilter`).

Every pixel of a level is ``Σ K(ψ) L Ω`` over the source's pixels, with ``K`` a function of ``1 − cos ψ``
between the two pixel centres.  Along a row pair the kernel depends only on ``Δφ``, so each pair is one
FFT product.  :func:`_convolve_rows` is the readable reference (one row offset at a time);
:func:`_convolve_rows_fast` computes the same sums with each distinct kernel row evaluated and transformed
once and the sum over source rows as matrix products, and is held to the reference by tests.
"""

from __future__ import annotations

import math

import numpy as np


def _row_bounds(height: int) -> np.ndarray:
    """``θ`` at the row boundaries of a lat-long image (``height + 1`` values from 0 to π)."""
    return np.arange(height + 1) * (math.pi / height)


def _row_solid_angles(height: int, width: int) -> np.ndarray:
    """The exact solid angle of one pixel in each row, ``(cos θ_top − cos θ_bottom) 2π / W``."""
    t = _row_bounds(height)
    # cos a − cos b = 2 sin((a+b)/2) sin((b−a)/2): no cancellation near the poles.
    return 2.0 * np.sin((t[:-1] + t[1:]) / 2) * math.sin(math.pi / height / 2) * (2 * math.pi / width)


def _convolve_rows(image: np.ndarray, kernel_of, support: float, rows=None) -> np.ndarray:
    r"""``Σ_{θ', φ'} K(ψ) L Ω`` for every pixel of ``image`` ``(H, W, C)``, the kernel a function of ``1 − cos ψ``.

    ``kernel_of(one_minus_cos)`` gives ``K``; only source rows within ``support`` radians in ``θ``
    are summed.  Also returns ``Σ K Ω`` per row (the normalization; the same for every column).
    ``rows`` (increasing row indices), when given, are the only output rows computed, each the same as
    without it, bit for bit (the kernel, its transform and the sum over offsets are row by row); the
    others are NaN.
    """
    h, w, c = image.shape
    theta = (np.arange(h) + 0.5) * (math.pi / h)
    dphi = np.arange(w) * (2 * math.pi / w)
    s2phi = np.sin(dphi / 2) ** 2
    omega = _row_solid_angles(h, w)
    reach = min(h - 1, int(math.ceil(support / (math.pi / h))))
    offsets = np.arange(-reach, reach + 1)
    src = np.fft.rfft(image * omega[:, None, None], axis=1)  # (H, W/2+1, C)
    out = np.zeros((h, w // 2 + 1, c), dtype=np.complex128)
    norm = np.zeros(h)
    sin_t = np.sin(theta)
    wanted = np.arange(h) if rows is None else np.asarray(rows, dtype=np.intp)
    # One offset at a time keeps the kernel block at H × W values however wide the support; the rows it
    # pairs are two contiguous slices (no gather, no scatter) when every row is wanted.
    for o in offsets:
        if rows is None:
            i = slice(max(0, -o), min(h, h - o))
            j = slice(i.start + o, i.stop + o)
        else:
            i = wanted[(wanted + o >= 0) & (wanted + o < h)]
            j = i + o
        dlat = np.sin((theta[i] - theta[j]) / 2)
        one_minus_cos = (2 * dlat * dlat)[:, None] + (2 * sin_t[i] * sin_t[j])[:, None] * s2phi[None, :]
        k = kernel_of(one_minus_cos)  # (rows, W), symmetric in Δφ: its spectrum is real
        out[i] += np.fft.rfft(k, axis=1).real[:, :, None] * src[j]
        norm[i] += k.sum(axis=1) * omega[j]
    if rows is None:
        return np.fft.irfft(out, n=w, axis=1), norm
    conv = np.full((h, w, c), np.nan)
    conv[wanted] = np.fft.irfft(out[wanted], n=w, axis=1)
    left = np.ones(h, dtype=bool)
    left[wanted] = False
    norm[left] = np.nan
    return conv, norm


#: Spectral terms of a kernel row smaller than this fraction of the largest row sum are left out of the fast
#: path's products (:func:`_convolve_rows_fast`): below the rounding of the row FFTs themselves.
_SPECTRUM_TOL = 1e-14
#: Row pairs whose kernels are evaluated and transformed at once (blocks of a few hundred kB).
_PAIR_CHUNK = 512
#: Kernel weights gathered and multiplied at once (memory).
_BAND_CHUNK = 1 << 19
#: Output rows per block of the banded products.
_ROW_BLOCK = 32


class _RowSpectra:
    """The row FFTs of ``L Ω`` of one image, frequency-major and padded by ``H/2`` zero rows on both sides.

    Row ``H/2 + j`` of :attr:`padded` holds row ``j``'s spectra (real and imaginary parts of each channel),
    then row ``H − 1 − j``'s: the image and its mirror ``θ → π − θ`` side by side.  Computed once per mip
    height and shared by every width and family that convolves that image.
    """

    def __init__(self, image: np.ndarray):
        h, w, c = image.shape
        omega = _row_solid_angles(h, w)
        spectrum = np.fft.rfft(image * omega[:, None, None], axis=1)  # (H, W/2+1, C)
        rows = np.ascontiguousarray(spectrum.transpose(1, 0, 2)).view(np.float64)  # (W/2+1, H, 2C)
        # A banded product reads at most R < H/2 rows beyond the image (wider bands are dense products).
        self.pad = pad = h // 2
        self.padded = np.zeros((w // 2 + 1, h + 2 * pad, 4 * c))
        self.padded[:, pad:pad + h, :2 * c] = rows
        self.padded[:, pad:pad + h, 2 * c:] = rows[:, ::-1]
        self.omega_padded = np.zeros((h + 2 * pad, 2))
        self.omega_padded[pad:pad + h] = np.stack([omega, omega[::-1]], axis=1)


def _convolve_rows_fast(image: np.ndarray, kernel_of, support: float, spectra: _RowSpectra | None = None):
    r""":func:`_convolve_rows` (the readable reference) with each distinct kernel row evaluated and transformed once.

    The kernel of output row ``i`` and source row ``j`` is symmetric in the two rows and under the mirror
    ``θ → π − θ``, and even in ``Δφ``: one row pair in four is evaluated, on ``W/2 + 1`` columns, in blocks
    of pairs.  The sum over source rows is then, for each frequency ``m``, a band of row weights times the
    source's spectra: one batched matrix product instead of a loop over offsets.  Frequencies at which every
    kernel row's spectrum is below :data:`_SPECTRUM_TOL` of the largest row sum are left out (a narrow band
    of frequencies for a lobe wide in ``φ``).  Same result as the reference to float64 rounding.

    ``spectra`` (:class:`_RowSpectra` of ``image``) lets several kernels share the source's row FFTs.
    """
    h, w, c = image.shape
    if spectra is None:
        spectra = _RowSpectra(image)
    n = w // 2 + 1
    theta = (np.arange(h) + 0.5) * (math.pi / h)
    s2phi = np.sin(np.arange(n) * (math.pi / w)) ** 2
    sin_t = np.sin(theta)
    reach = min(h - 1, int(math.ceil(support / (math.pi / h))))
    # The distinct pairs: offset d = j − i from 0 to the reach, and the upper row i of each pair that is not the
    # mirror image of another (i <= H − 1 − d − i).
    d = np.arange(reach + 1)
    counts = (h - 1 - d) // 2 + 1
    start = np.concatenate([[0], np.cumsum(counts)])
    pairs = int(start[-1])
    pair_d = np.repeat(d, counts)
    upper = np.arange(pairs) - start[pair_d]
    lower = upper + pair_d
    dlat = np.sin((theta[upper] - theta[lower]) / 2)
    a = 2 * dlat * dlat
    b = 2 * sin_t[upper] * sin_t[lower]
    # Real spectra of the kernel rows, frequency-major; the last column is a zero row for pairs off the map.
    spec = np.empty((n, pairs + 1))
    spec[:, pairs] = 0.0
    row = np.empty((min(_PAIR_CHUNK, pairs), w))
    for p0 in range(0, pairs, _PAIR_CHUNK):
        p1 = min(pairs, p0 + _PAIR_CHUNK)
        k = kernel_of(a[p0:p1, None] + b[p0:p1, None] * s2phi[None, :])
        full = row[: p1 - p0]
        full[:, :n] = k
        full[:, n:] = k[:, n - 2:0:-1]  # the even extension: the row over the whole circle of Δφ
        part = np.fft.rfft(full, axis=1).real
        spec[:, p0:p1] = part.T
    peak = np.maximum(spec.max(axis=1), -spec.min(axis=1))
    kept = np.flatnonzero(peak > _SPECTRUM_TOL * peak[0])
    m_eff = int(kept[-1]) + 1 if kept.size else 1
    # The weights of frequency m are an H × H matrix, banded within the reach, and the same read from the
    # opposite corner (the mirror θ → π − θ): its upper half rows times the source and times the mirrored
    # source give the upper and the lower half of the sums.  The rows are cut into blocks of B, each reading
    # B + 2R source rows (all H when that is as many): a batch of dense products.
    rows = h // 2
    dense = _ROW_BLOCK + 2 * reach >= h
    block = rows if dense else _ROW_BLOCK
    span = h if dense else block + 2 * reach
    blocks = -(-rows // block)
    first = spectra.pad - (0 if dense else reach)  # the padded row of block 0's first source row
    i = np.arange(blocks * block)[:, None]
    j = (i // block) * block + np.arange(span)[None, :] + (first - spectra.pad)
    # Which distinct pair (row i, row j) is: the upper row and the distance, mirrored into the stored half.
    top, dist = np.minimum(i, j), np.abs(j - i)
    top = np.where(2 * top > h - 1 - dist, h - 1 - dist - top, top)
    inside = (j >= 0) & (j < h) & (i < rows) & (dist <= reach)
    index = np.where(inside, start[np.minimum(dist, reach)] + top, pairs).reshape(blocks, block, span)
    src = spectra.padded[:, first:]
    st = src.strides
    out = np.zeros((h, n, 2 * c))
    step = min(m_eff, max(1, _BAND_CHUNK // (blocks * block * span)))
    # One buffer for every chunk's weights and products (fresh large arrays would each be paged in anew).
    weight_buf = np.empty((step, blocks, block, span))
    product_buf = np.empty((step, blocks, block, 4 * c))
    for m0 in range(0, m_eff, step):
        m1 = min(m_eff, m0 + step)
        weights = np.take(spec[m0:m1], index, axis=1, out=weight_buf[: m1 - m0], mode="clip")  # (m, blocks, B, span)
        window = np.lib.stride_tricks.as_strided(src[m0:], shape=(m1 - m0, blocks, span, 4 * c),
                                                 strides=(st[0], block * st[1], st[1], st[2]))  # fmt: skip
        both = np.matmul(weights, window, out=product_buf[: m1 - m0])
        both = both.reshape(m1 - m0, blocks * block, 4 * c)[:, :rows].transpose(1, 0, 2)
        out[:rows, m0:m1] = both[..., :2 * c]
        out[rows:, m0:m1] = both[::-1, :, 2 * c:]
    so = spectra.omega_padded[first:]
    omega = np.lib.stride_tricks.as_strided(so, shape=(blocks, span, 2), strides=(block * so.strides[0],) + so.strides)
    both = np.matmul(np.take(spec[0], index), omega).reshape(-1, 2)[:rows]
    norm = np.concatenate([both[:, 0], both[::-1, 1]])
    return np.fft.irfft(out.view(np.complex128), n=w, axis=1), norm

r"""Filtered importance sampling of a prefiltered environment: the glossy residual of the dominant-light method.

A glossy lobe's mean of the residual, ``Σ_k w_k L̄(l_k, σ_k)`` (:mod:`lighting.integrate.dominant`), is a sum
over ``N`` fixed sample directions per pixel, each read from the prefiltered level whose width matches its
share of the lobe.  Everything that does not depend on the pixel is tabulated once per part: the sample
directions in a local frame, their weights ``f_r (n·l) / p`` (normalized) and their levels, over the view
angle.  Per pixel the samples are turned into the pixel's frame by three multiply-adds per coordinate, and
read by one gather per bilinear tap from a flat array of texels that hold two levels' RGBA (every level after
the other), pixels a block at a time so that the block's arrays stay in the processor's cache.

Each sample reads the two levels around its width and blends them (linear in ``log σ``): reading only the
nearest level moves the value by a whole level's blur where the width crosses a midpoint, and the error of a
narrow lobe over a studio's sharp-edged boxes grows by a quarter.  The two levels sit side by side in each
texel (:class:`LevelStack`), so that one gather per bilinear tap reads both.
"""

from __future__ import annotations

import math
import threading

import numpy as np

from .._recent import Recent
from ..shading.batch import in_blocks

#: ``c_σ``: a sample's blur width relative to the width ``√(Ω_s / 2π)`` of its share ``Ω_s = 1/(N p)`` of the lobe.
FILTER_SCALE = 0.8
#: ``c_σ`` of the half-vector samples of a narrow microfacet lobe (:func:`half_vector_mean`).
HALF_FILTER_SCALE = 1.2
#: View angles of the per-part sample tables: 0° to 89.5° in 0.5° steps (a pixel reads the nearest).
TABLE_STEP = math.radians(0.5)
TABLE_ANGLES = np.arange(0.0, math.radians(89.75), TABLE_STEP)
#: View azimuths of the half-vector weight tables (a pixel reads the nearest).
AZIMUTHS = 64
#: Pixel-samples (pixels times samples) per block: enough that each of a block's NumPy passes outlasts the Python
#: between them, so that the shading threads run side by side (blocks a quarter of this size spend most of a
#: re-shade waiting on each other for the interpreter), few enough that its arrays stay in the processor's caches.
#: ``lighting-explorer bench --ibl`` measures it: the rows pixel by pixel and of the narrow lobe.
_BLOCK = 1 << 15
#: Bytes of a block's arrays at their peak (its directions, levels and weights, and each of the four taps' index,
#: weight and texels of two levels): about 275 per pixel-sample, traced over a whole call on one block of a
#: narrow lobe; this with a margin.
BLOCK_BYTES = 440 * _BLOCK
#: The sample tables of the parts met last.
_tables = Recent(64)
#: View angles of a half-vector table evaluated at once (:func:`half_table`).
_TABLE_ROWS = 12
#: Texels of a level read from the next at once while a :class:`LevelStack` is made (the lookup's temporaries).
_LOOKUP_PIXELS = 1 << 16


def stratified_square(count: int) -> np.ndarray:
    """``count`` points of the unit square, a rank-1 lattice (Fibonacci when it can): stratified in both axes."""
    k = np.arange(count)
    golden = (math.sqrt(5.0) - 1.0) / 2.0
    return np.stack([(k + 0.5) / count, np.mod(0.5 + k * golden, 1.0)], axis=-1)


def _padded_pair(levels, k):
    """Level ``k`` with level ``k + 1`` (read at level ``k``'s texel centres) beside it: ``(h + 2, w + 2, 8)`` float32,
    each texel the RGB and a zero of both, with a border of one texel (:class:`LevelStack`)."""
    from ..lights.environment import LatLongEnvironment
    from ..lights.latlong import latlong_lookup

    im = levels[k]
    nxt = levels[min(k + 1, len(levels) - 1)]
    if nxt.shape != im.shape:  # coarser: read at this level's texel centres, a band of rows at a time
        d = LatLongEnvironment.pixel_directions(*im.shape[:2])
        coarse, nxt = nxt, np.empty(im.shape, dtype=np.float32)
        step = max(1, _LOOKUP_PIXELS // im.shape[1])
        for r in range(0, im.shape[0], step):
            nxt[r : r + step] = latlong_lookup(coarse.reshape(-1, 3), *coarse.shape[:2], d[r : r + step])
    pair = np.zeros(im.shape[:2] + (8,), dtype=np.float32)
    pair[..., :3], pair[..., 4:7] = im, nxt
    return np.pad(np.pad(pair, ((0, 0), (1, 1), (0, 0)), mode="wrap"), ((1, 1), (0, 0), (0, 0)), mode="edge")


def _texel_coordinates(x, y, z, scale):
    """The bilinear taps of unit directions ``(x, y, z)`` (float32) in a padded level of ``scale`` texels per radian:
    ``(jx, iy, tx, ty)``, the upper-left texel's column and row and the fractions toward the next, in float32.

    Rows and columns as :func:`lighting.lights.latlong.latlong_lookup` (:class:`LevelStack`), shifted by the border
    of one texel (+ 1) and to the texel centres (+ ½): positive, so the truncation to an integer is the floor.
    Float32 fractions are taken from float32 integer parts, which NumPy would otherwise promote to float64.
    """
    theta = np.arccos(np.clip(z, np.float32(-1), np.float32(1)))
    a = np.float32(math.pi) - np.arctan2(y, x)  # (π − φ) ∈ [0, 2π]
    fx = a * scale + np.float32(0.5)
    fy = theta * scale + np.float32(0.5)
    jx, iy = fx.astype(np.int32), fy.astype(np.int32)
    return jx, iy, fx - jx.astype(np.float32), fy - iy.astype(np.float32)


class LevelStack:
    """Every level of a prefiltered environment's von Mises–Fisher family, for one gather per bilinear tap.

    A sample between levels ``k`` and ``k + 1`` is bilinear in each and linear between them.  Level ``k`` is stored
    with level ``k + 1`` beside it, read at level ``k``'s texel centres (bilinearly where it is coarser: its blur
    spans several of its own texels), each texel the RGB and a zero of both in float32 (32 bytes): one gather per
    bilinear tap moves both levels' values (a gather of rows of three values costs several times as much).  The
    levels follow each other in one flat array, each with a border of one texel: the first and last columns repeated
    across the seam (the map wraps in azimuth) and the first and last rows repeated (the edge rows are clamped), so
    that a lookup needs no wrapping or clamping.  Rows and columns as
    :func:`lighting.lights.latlong.latlong_lookup`: row ``i`` of ``h`` centred at ``θ = (i + ½)π/h``, column angle
    ``a = (π − φ) mod 2π`` over ``2h`` columns.

    Parameters
    ----------
    pre : PrefilteredEnvironment
    """

    def __init__(self, pre):
        levels = [np.asarray(im, dtype=np.float32) for im in pre.families["mirror"]]
        self.count = len(levels)
        padded = [_padded_pair(levels, k) for k in range(self.count)]
        sizes = [im.shape[0] * im.shape[1] for im in padded]
        #: Per level: texels per radian (``h/π`` both ways), the padded row length, the first texel.
        self.scale = np.array([im.shape[0] / math.pi for im in levels], dtype=np.float32)
        self.row = np.array([im.shape[1] for im in padded], dtype=np.int32)
        self.offsets = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int32)
        flat = np.concatenate([im.reshape(-1, 8) for im in padded])
        self.texels = flat.view(np.dtype((np.void, 32))).reshape(-1)
        sig = np.asarray(pre.sigmas, dtype=np.float64)
        self.sigma1 = np.float32(sig[1])
        self.log_sigmas = np.log(sig[1:])
        self.indices = np.arange(1, len(sig), dtype=np.float64)

    def level_of(self, log_sigma):
        """The fractional level of each width (given as ``log σ``, float32): linear in ``log σ`` between the levels
        ``1 …``, linear in ``σ`` between the map (level 0, ``σ = 0``) and level 1."""
        frac = np.interp(log_sigma, self.log_sigmas, self.indices).astype(np.float32)
        below = np.exp(np.minimum(log_sigma, np.float32(0))) / self.sigma1
        return np.where(below < 1, below, frac)

    def mean(self, x, y, z, level, w):
        """``Σ_k w_k L(d_k, level_k)`` over the last axis: ``x, y, z`` the unit directions, all ``(P, N)``; ``(P, 3)``.

        Bilinear in each of the two levels around a fractional ``level``, linear between them, in float32: the
        directions, the texel coordinates (:func:`_texel_coordinates`), the weights and their sum (the weights of a
        pixel sum to 1; a float32 sum of a few hundred products errs by a few units of 1e-7 of the result, where the
        sample count's own error is percents): half the bytes of float64 gathered and multiplied per tap.
        """
        k = level.astype(np.int32)  # level >= 0: the truncation is the floor
        t = level - k.astype(np.float32)
        jx, iy, tx, ty = _texel_coordinates(x, y, z, np.take(self.scale, k))
        row = np.take(self.row, k)
        base = np.take(self.offsets, k) + iy * row + jx
        one = np.float32(1)
        wy0, wy1 = w * (one - ty), w * ty
        wx0 = one - tx
        # Every tap of every sample side by side: one gather, then one weighted sum per pixel (a matrix product)
        # over the taps' two levels, weighted 1 − t and t.  The taps' indices and weights are written in place, in
        # the order (tap, sample, level) of the gathered texels' values.
        p, n = base.shape
        index = np.empty((p, 4, n), dtype=base.dtype)
        index[:, 0] = base
        np.add(base, 1, out=index[:, 1])
        np.add(base, row, out=index[:, 2])
        np.add(index[:, 2], 1, out=index[:, 3])
        weight = np.empty((p, 4, n, 2), dtype=wy0.dtype)
        tap = np.empty((p, n), dtype=wy0.dtype)
        for q, (wy, wx) in enumerate(((wy0, wx0), (wy0, tx), (wy1, wx0), (wy1, tx))):
            np.multiply(wy, wx, out=tap)
            np.multiply(tap, t, out=weight[:, q, :, 1])
            np.subtract(tap, weight[:, q, :, 1], out=weight[:, q, :, 0])
        texel = np.take(self.texels, index.reshape(p, -1)).view(np.float32).reshape(p, -1, 4)
        return np.matmul(weight.reshape(p, 1, -1), texel)[:, 0, :3]


class OneLevel:
    """A prefiltered family at one lobe width: its two levels around it blended once, a bilinear read per direction.

    Parameters
    ----------
    pre : PrefilteredEnvironment
    kernel : str
        The family (a key of ``pre.families``).
    sigma : float
        The lobe width (radians): levels as :meth:`PrefilteredEnvironment.level_of`.
    """

    def __init__(self, pre, kernel, sigma):
        levels = [np.asarray(im, dtype=np.float32) for im in pre.families[kernel]]
        level = float(pre.level_of(sigma))
        k = min(int(level), len(levels) - 1)
        t = np.float32(level - k)
        pair = _padded_pair(levels, k)
        blend = pair[..., :4] * (np.float32(1) - t) + pair[..., 4:] * t
        self.texels = np.ascontiguousarray(blend).reshape(-1, 4).view(np.dtype((np.void, 16))).reshape(-1)
        self.scale, self.row = np.float32(levels[k].shape[0] / math.pi), pair.shape[1]

    def read(self, d):
        """``L̄(d)`` of unit directions ``d`` (P, 3) float32: (P, 3) float32, bilinear as :meth:`LevelStack.mean`."""
        jx, iy, tx, ty = _texel_coordinates(d[:, 0], d[:, 1], d[:, 2], self.scale)
        # Each fraction repeated over the texel's four values: the products run over contiguous runs instead of
        # broadcasting one fraction over four values at a time (the same products).
        tx, ty = np.repeat(tx, 4).reshape(-1, 4), np.repeat(ty, 4).reshape(-1, 4)
        base = iy * self.row + jx
        below = base + self.row

        def tap(index):  # (P, 4): RGB and a zero, contiguous (a slice of three would be strided in every pass)
            return np.take(self.texels, index).view(np.float32).reshape(-1, 4)

        top = tap(base)
        top += (tap(base + 1) - top) * tx
        bottom = tap(below)
        bottom += (tap(below + 1) - bottom) * tx
        top += (bottom - top) * ty
        return top[:, :3]


def _sampler(part):
    """The part's sampler; for a rough isotropic GGX or Beckmann part the visible normals' (its weights vary least).

    Below ``α = 0.1`` the lobe is narrow and ``D(h)(n·h)`` sampling, stratified in ``θ_h``, reads it better.
    """
    mf = part.microfacet()
    if mf is not None and mf.ndf in ("ggx", "beckmann") and mf.isotropic and mf.alpha_x >= 0.1:
        from ..sampling.microfacet import VisibleNormalSampler

        return VisibleNormalSampler(mf.ndf, float(mf.alpha_x))
    return part.sampler()


def view_table(part, samples: int, stack: LevelStack, sigmas: tuple):
    """The filtered-importance samples of one part at :data:`TABLE_ANGLES`, in the frame where ``v`` is in ``xz``.

    Returns ``(directions (M, N, 3) float32, weights (M, N) float32 summing to 1 per row (or 0 where every
    sample is below the horizon), level (M, N) float32, fractional)``; cached per part, sample count and levels.
    """
    key = ("view", type(part).__qualname__, repr(part), samples, sigmas)
    found = _tables.get(key)
    if found is not None:
        return found
    th = TABLE_ANGLES
    vl = np.stack([np.sin(th), np.zeros_like(th), np.cos(th)], axis=-1)[:, None, :]
    u = stratified_square(samples)[None, :, :]
    s = _sampler(part).sample(u, vl)
    ld = np.asarray(s.directions, dtype=np.float64)
    p = np.asarray(s.pdf, dtype=np.float64)
    f = np.asarray(part.eval(np.array([0.0, 0.0, 1.0]), ld, vl), dtype=np.float64)
    cos_l = ld[..., 2]
    ok = (p > 0) & (cos_l > 0)
    safe_p = np.where(ok, p, 1.0)
    w = np.where(ok, f.mean(axis=-1) * np.maximum(cos_l, 0.0) / safe_p, 0.0)
    total = w.sum(axis=-1, keepdims=True)
    w = np.where(total > 0, w / np.where(total > 0, total, 1.0), 0.0)
    # σ_k = c_σ √(Ω_k / 2π), Ω_k = 1 / (N p_k): the sample's share of the lobe.
    sigma = FILTER_SCALE * np.sqrt(1.0 / (samples * safe_p) / (2 * math.pi))
    level = np.where(ok, stack.level_of(np.log(sigma).astype(np.float32)), 0).astype(np.float32)
    return _tables.put(key, (ld.astype(np.float32), w.astype(np.float32), level))


def view_table_mean(part, stack, n, v, cos_v, samples, sigmas):
    """The residual's mean over the part's lobe by filtered importance sampling, per pixel: ``((P, 3), ok (P,))``.

    The samples of the nearest tabulated view angle, turned into each pixel's frame (``x`` along the view's
    projection on the surface, ``z`` the normal); their weights sum to 1 (``ok`` false where every sample
    of the pixel's view angle is below the horizon).  ``n``, ``v``, ``cos_v`` float32.
    """
    ld, w, level = view_table(part, samples, stack, sigmas)
    m = np.minimum(np.rint(np.arccos(np.clip(cos_v, 0, 1)) * np.float32(1 / TABLE_STEP)).astype(np.int32),
                   len(TABLE_ANGLES) - 1)  # fmt: skip
    t = v - n * cos_v[:, None]
    tl = np.sqrt(np.einsum("ij,ij->i", t, t))
    facing = tl < 1e-6  # v along n: any tangent (the lobe is symmetric about the normal there)
    if np.any(facing):
        from ..vec import orthonormal_basis

        t[facing] = orthonormal_basis(n[facing])[0]
        tl[facing] = 1
    t = t / tl[:, None]
    b = np.cross(n, t)
    out = np.empty(n.shape, dtype=np.float32)

    def block(s):
        mm = m[s]
        lx, ly, lz = ld[mm, :, 0], ld[mm, :, 1], ld[mm, :, 2]
        x = _turn(lx, ly, lz, t[s, 0], b[s, 0], n[s, 0])
        y = _turn(lx, ly, lz, t[s, 1], b[s, 1], n[s, 1])
        z = _turn(lx, ly, lz, t[s, 2], b[s, 2], n[s, 2])
        out[s] = stack.mean(x, y, z, level[mm], w[mm])

    in_blocks(n.shape[0], max(1, _BLOCK // samples), block, balanced=True)  # each pixel on its own
    return out, w[m].sum(axis=-1) > 0


def _turn(lx, ly, lz, tc, bc, nc):
    """One world coordinate of local directions ``(lx, ly, lz)`` ``(P, N)`` in the frames ``t, b, n``: ``(P, N)``."""
    return lx * tc[:, None] + ly * bc[:, None] + lz * nc[:, None]


def smooth_frame(n):
    """Tangents ``(t, b)`` of unit normals ``n`` varying smoothly with ``n`` but at ``n = −z`` (Frisvad 2012)."""
    x, y, z = n[:, 0], n[:, 1], n[:, 2]
    south = z < -0.9999
    a = 1 / np.where(south, 1, 1 + z)
    c = -x * y * a
    t = np.stack([1 - x * x * a, c, -x], axis=-1)
    b = np.stack([c, 1 - y * y * a, -y], axis=-1)
    t[south], b[south] = (0.0, -1.0, 0.0), (-1.0, 0.0, 0.0)
    return t, b


def _half_samples(part, samples: int):
    """The half vectors ``h (N, 3)`` of ``D(h)(n·h)`` sampling at the fixed stratified points and ``D(h)(n·h)`` at each
    (``d (N,)``), float64."""
    from ..sampling.microfacet import MicrofacetSampler

    mf = part.microfacet()
    sampler = MicrofacetSampler(mf.ndf, float(mf.alpha_x))
    up = np.array([0.0, 0.0, 1.0])
    s = sampler.sample(stratified_square(samples), up)  # at normal incidence l = 2 h_z h − z
    ld = np.asarray(s.directions, dtype=np.float64)
    h = ld + up
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    d = 4 * h[:, 2] * np.asarray(s.pdf, dtype=np.float64)  # p(l) = D (n·h) / (4 v·h)
    return h, d


def _half_weights(part, h, d, theta, phi):
    """``f_r (n·l)/p`` of the half vectors ``h`` for views at polar angles ``theta`` and azimuths ``phi`` (arrays that
    broadcast together, shape ``S``), in the frame of the half vectors: ``S + (N,)`` float32, 0 where the reflected
    direction or the view is below the horizon.  Each view's weights are the same whatever views are computed with
    it (every step is elementwise in the view)."""
    up = np.array([0.0, 0.0, 1.0])
    v = np.stack(np.broadcast_arrays(np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)),
                 -1)[..., None, :]  # fmt: skip
    vh = np.sum(v * h, axis=-1)
    lw = 2 * vh[..., None] * h - v
    ok = (vh > 0) & (lw[..., 2] > 0) & (d > 0)
    f = np.asarray(part.eval(up, lw, np.broadcast_to(v, lw.shape)), dtype=np.float64).mean(axis=-1)
    return np.where(ok, f * np.maximum(lw[..., 2], 0) * 4 * np.where(ok, vh, 1) / np.where(ok, d, 1),
                    0.0).astype(np.float32)  # fmt: skip


#: The azimuths of the half-vector weight tables (radians).
_AZIMUTH_ANGLES = np.arange(AZIMUTHS) * (2 * math.pi / AZIMUTHS)


def half_table(part, samples: int):
    """A narrow microfacet lobe's fixed half vectors and their weights over view angles (see :func:`half_vector_mean`).

    Returns ``(h (N, 3), d (N,), weights (M, A, N))``: the half vectors of ``D(h)(n·h)`` sampling at the fixed
    stratified points, ``D(h)(n·h)`` at each, and ``f_r (n·l)/p`` for views at :data:`TABLE_ANGLES` (rows)
    and ``A`` azimuths (columns) in the frame of the half vectors.  The readable reference, every view at once:
    :func:`half_vector_mean` reads a :class:`HalfTable`, which evaluates the views its pixels look from.
    """
    h, d = _half_samples(part, samples)
    w = np.empty((len(TABLE_ANGLES), AZIMUTHS, samples), dtype=np.float32)
    # A few view angles at a time: the model's evaluation over every view, azimuth and sample at once would hold
    # hundreds of MiB of temporaries; each value is the same computed either way.
    for start in range(0, len(TABLE_ANGLES), _TABLE_ROWS):
        th = TABLE_ANGLES[start : start + _TABLE_ROWS, None]
        w[start : start + len(th)] = _half_weights(part, h, d, th, _AZIMUTH_ANGLES[None, :])
    return h.astype(np.float32), d.astype(np.float32), w


class HalfTable:
    """:func:`half_table` of one part, its weights evaluated view by view as pixels first look from them.

    A small image reads a few of the table's :data:`TABLE_ANGLES` × :data:`AZIMUTHS` views; each view's weights are
    those :func:`half_table` gives, bit for bit (:func:`_half_weights` is elementwise in the view).  Cached per part
    and sample count (:func:`half_table_of`), so that the next image evaluates only the views it adds.

    Parameters
    ----------
    part : BRDF
        A microfacet part with an isotropic GGX or Beckmann distribution.
    samples : int
        Half vectors per view.

    Attributes
    ----------
    h : ndarray, (N, 3) float32
        The half vectors, in the frame of the surface.
    d : ndarray, (N,) float32
        ``D(h)(n·h)`` at each.
    weights : ndarray, (M, A, N) float32
        ``f_r (n·l)/p`` per view angle, azimuth and half vector, where :attr:`filled`.
    filled : ndarray, (M, A) bool
        The views evaluated so far.
    """

    def __init__(self, part, samples: int):
        self.part = part
        h, d = _half_samples(part, samples)
        self._h64, self._d64 = h, d
        self.h, self.d = h.astype(np.float32), d.astype(np.float32)
        self.weights = np.zeros((len(TABLE_ANGLES), AZIMUTHS, samples), dtype=np.float32)
        self.filled = np.zeros((len(TABLE_ANGLES), AZIMUTHS), dtype=bool)
        self._lock = threading.Lock()

    def fill(self, rows, cols) -> None:
        """Evaluate the views ``(rows, cols)`` (integer arrays of table indices) not evaluated yet.

        Parameters
        ----------
        rows, cols : ndarray of int
            View-angle and azimuth indices, of one shape.

        Returns
        -------
        None
        """
        flat = np.unique(np.asarray(rows, dtype=np.intp) * AZIMUTHS + np.asarray(cols, dtype=np.intp))
        with self._lock:
            missing = flat[~self.filled.reshape(-1)[flat]]
            # As many views at once as :func:`half_table` evaluates (its temporaries' bound).
            step = _TABLE_ROWS * AZIMUTHS
            for start in range(0, missing.size, step):
                views = missing[start : start + step]
                r, c = np.divmod(views, AZIMUTHS)
                self.weights.reshape(-1, self.weights.shape[-1])[views] = _half_weights(
                    self.part, self._h64, self._d64, TABLE_ANGLES[r], _AZIMUTH_ANGLES[c])
                self.filled.reshape(-1)[views] = True


def half_table_of(part, samples: int) -> HalfTable:
    """The :class:`HalfTable` of a part and sample count, made once per part (by its ``repr``) and kept among the
    tables of the parts met last.

    Parameters
    ----------
    part : BRDF
        A microfacet part with an isotropic GGX or Beckmann distribution.
    samples : int
        Half vectors per view.

    Returns
    -------
    HalfTable
    """
    key = ("half", type(part).__qualname__, repr(part), samples)
    found = _tables.get(key)
    if found is not None:
        return found
    return _tables.put(key, HalfTable(part, samples))


def half_vector_mean(part, stack, n, v, cos_v, samples, sigmas):
    """Filtered importance sampling of a narrow microfacet lobe with half vectors fixed to the surface.

    ``D(h)(n·h)`` sampling does not depend on the view, so the half vectors stay put in a frame that turns
    smoothly with the normal (:func:`smooth_frame`); each pixel reflects its own ``v`` about them.  Turning
    the pattern with the plane of incidence instead would make it spin about the point that faces the viewer,
    where a narrow lobe's sparse tail samples then draw a pinwheel.  The weights come from a table over the
    view's angles in that frame, times each pixel's own horizon; the levels from each sample's exact density.
    Returns ``((P, 3), ok (P,))`` as :func:`view_table_mean`.
    """
    table = half_table_of(part, samples)
    h_loc, d, wtab = table.h, table.d, table.weights
    # log σ_k = ½ log(c_σ² 4 (v·h) / (2π N D(h)(n·h))): the sample's share 1 / (N p), p = D (n·h) / (4 v·h).
    log_c = (0.5 * np.log(HALF_FILTER_SCALE**2 * 4 / (2 * math.pi * samples * np.maximum(d, 1e-30)))).astype(np.float32)
    t, b = smooth_frame(n)
    vt, vb = np.einsum("ij,ij->i", v, t), np.einsum("ij,ij->i", v, b)
    mt = np.minimum(np.rint(np.arccos(np.clip(cos_v, 0, 1)) * np.float32(1 / TABLE_STEP)).astype(np.int32),
                    len(TABLE_ANGLES) - 1)  # fmt: skip
    ma = np.rint(np.arctan2(vb, vt) * np.float32(AZIMUTHS / (2 * math.pi))).astype(np.int32) % AZIMUTHS
    table.fill(mt, ma)
    hz = h_loc[:, 2]
    out = np.empty(n.shape, dtype=np.float32)
    any_ok = np.empty(n.shape[0], dtype=bool)
    tiny = np.float32(1e-6)

    def block(s):
        nn, vv = n[s], v[s]
        p = nn.shape[0]
        # The half vectors in the world, h_c = Σ_k h_k frame_k,c (the frame t, b, n), and v·h = Σ_k h_k (v·frame_k):
        # each one product of the frames by the fixed local half vectors.
        frames = np.stack([t[s], b[s], nn], axis=-1).reshape(3 * p, 3)
        h = (frames @ h_loc.T).reshape(p, 3, -1)
        vh = np.stack([vt[s], vb[s], cos_v[s]], axis=-1) @ h_loc.T
        two = vh + vh
        x, y, z = (two * h[:, c] - vv[:, c, None] for c in range(3))
        # n·l = 2 (v·h)(n·h) − n·v, and n·h is the local half vector's z.
        nl = two * hz - cos_v[s, None]
        w = np.where((vh > 0) & (nl > 0), wtab[mt[s], ma[s]], np.float32(0))
        total = w.sum(axis=-1)
        any_ok[s] = total > 0
        w /= np.where(total > 0, total, 1)[:, None]
        level = stack.level_of(np.float32(0.5) * np.log(np.maximum(vh, tiny)) + log_c)
        out[s] = stack.mean(x, y, z, level, w)

    in_blocks(n.shape[0], max(1, _BLOCK // samples), block, balanced=True)  # each pixel on its own
    return out, any_ok

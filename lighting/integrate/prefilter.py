r"""Prefiltered environments: the environment averaged over a lobe, once, for every roughness.

Real-time image-based lighting (Karis 2013, "split sum") splits the rendering equation of a glossy
lobe into the lobe's albedo times the environment averaged over the lobe:

$$
L_o(v) = ∫ f_r L_i (n·l)\, dω ≈ \underbrace{∫ f_r (n·l)\, dω}_{ρ(v)}
         \cdot \underbrace{\frac{∫ K(r·l) L_i(l)\, dω}{∫ K(r·l)\, dω}}_{\bar L(r, σ)},
$$

with ``r`` the lobe's axis (the mirror direction) and ``K`` a kernel as wide as the lobe.  The
second factor depends on the environment alone, so it is computed once per environment for a
ladder of widths ``σ`` (:class:`PrefilteredEnvironment`) and looked up per pixel; the first is a
table of the model (:mod:`lighting.integrate.ibl`).

The kernel is the von Mises–Fisher lobe ``K(ψ) = exp(−κ (1 − cos ψ))``, ``κ = 1/σ²``, which is
``exp(−ψ²/(2σ²))`` near its axis: a Gaussian of angular standard deviation ``σ``, the width a
model's :class:`~lighting.models.protocol.Lobe` states.  For Phong's ``(r·l)^e`` it is the lobe
itself (``κ = e``).

How a level is computed (a midpoint rule over the map's pixels, with no sampling noise): an image
of ``H × 2H`` pixels whose centres share their ``φ`` grid with the output, so between one output
row ``θ`` and one source row ``θ'`` the kernel depends on ``Δφ`` alone,

$$
1 − \cos ψ = 2 \sin^2\frac{θ − θ'}{2} + 2 \sin θ \sin θ' \sin^2\frac{Δφ}{2}
$$

(the cancellation-free form), and the sum over a source row is a circular convolution in ``φ``,
done by FFT.  Only rows with ``|θ − θ'| <= 6σ`` contribute more than ``e^{−18}`` (the great-circle
distance is at least the latitude difference, also across a pole).  Each level is computed at the
coarsest power-of-two height with at least eight pixels per ``σ`` (``H >= 8π/σ``: the bilinear
lookup between its pixel centres then bends a linear sky by under 0.2 %), from a source
averaged down to that height by solid-angle-weighted 2 × 2 blocks; level 0 is the source itself
(``σ = 0``, the mirror).

Two implementations of that sum sit side by side.  ``_convolve_rows`` is the readable reference: one
offset ``θ' − θ`` at a time, the kernel evaluated and transformed for every row pair.  ``_convolve_rows_fast``
gives the same sums to float64 rounding with less work: the kernel of rows ``(i, j)`` is that of ``(j, i)`` and
of their mirror images ``θ → π − θ``, and even in ``Δφ``, so one row pair in four is evaluated, on half the
columns; the sum over source rows becomes, for each frequency, a banded matrix of those spectra times the
source's row spectra (shared by every kernel of a height), done as batched matrix products; frequencies at
which every kernel row's spectrum is below ``1e-14`` of the largest row sum are skipped.
:func:`prefilter_environment` uses the fast one and computes the levels on the engine's shading threads, each
level independent of the others, so the result is the same bits on one thread or several.

The same machinery with the clamped cosine ``max(cos ψ, 0)`` as kernel gives the irradiance of the pixelized map to
the midpoint rule's ``O(pixel²)`` (:func:`irradiance_map`, by the fast sums up to 256 source rows, the reference's
above): the reference that SH9 irradiance is measured against.

References
----------
B. Karis, "Real Shading in Unreal Engine 4", SIGGRAPH 2013 course notes (the split sum).
"""

from __future__ import annotations

import copy
import hashlib
import math
import threading

import numpy as np

from .._budget import check_budget
from .._recent import Recent
from .._text import quote
from .._validate import ArgumentTypeError, check_bool, check_count, check_vectors
from ..lights.environment import (
    ConstantEnvironment,
    Environment,
    LatLongEnvironment,
    _pixel_directions,
    as_environment,
    latlong_angles,
    latlong_azimuth,
    latlong_lookup,
)
from ..numerics import working_dtype
from .rowconv import _convolve_rows, _convolve_rows_fast, _row_bounds, _row_solid_angles, _RowSpectra
from .sh import SH_CONSTANTS

__all__ = [
    "KERNELS",
    "kernel_of_lobe",
    "PREFILTER_SIGMAS",
    "PrefilteredEnvironment",
    "prefilter_environment",
    "prefilter_height",
    "irradiance_map",
    "latlong_sh",
]

#: The lobe widths ``σ`` (radians) of the prefiltered levels: the mirror, then doubling from 0.025.
#: ``σ = 1.6`` is broader than any glossy lobe (a GGX ``α = 1`` reflects into about ``σ = 1.4``).
PREFILTER_SIGMAS = (0.0, 0.025, 0.05, 0.1, 0.2, 0.4, 0.8, 1.6)
#: The kernels of the prefiltered families (:attr:`PrefilteredEnvironment.families`).
KERNELS = ("mirror", "beckmann", "ggx")
#: Kernel support in standard deviations: beyond ``6σ`` the kernel is below ``e^{-18}``.
_SUPPORT = 6.0
#: The smallest level height (a 16 × 32 image resolves ``σ = 1.6`` with eight pixels per σ).
_MIN_HEIGHT = 16
#: The largest height of a blurred level (σ > 0): at 256 rows the narrowest lobe, σ = 0.025, still spans two
#: pixels per σ, and the cost of prefiltering stops growing with the source (level 0 keeps the source's detail).
_MAX_LEVEL_HEIGHT = 256
#: At most this many threads compute levels at once (each holds its level's kernel spectra, up to tens of MB).
_LEVEL_THREADS = 4


def _halve(image: np.ndarray) -> np.ndarray:
    """Average 2 × 2 blocks, each pixel weighted by its solid angle (the radiance the block receives)."""
    h, w = image.shape[:2]
    omega = _row_solid_angles(h, w)[:, None, None]
    weighted = (image * omega).reshape(h // 2, 2, w // 2, 2, -1).sum(axis=(1, 3))
    total = omega.reshape(h // 2, 2, 1, 1).sum(axis=1) * 2
    return weighted / total


def _level_height(sigma: float, source_height: int) -> int:
    """The coarsest power-of-two height with eight pixels per ``σ``, at most the source's and 256 rows."""
    need, cap = 8 * math.pi / sigma, min(source_height, _MAX_LEVEL_HEIGHT)
    h = _MIN_HEIGHT
    while h < need and h < cap:
        h *= 2
    return min(h, source_height)


def _ggx_kernel(alpha: float):
    r"""GGX's lobe as a kernel of ``x = 1 − cos ψ`` about the reflected direction (Karis's ``n = v = r``).

    With ``n = v = r``, a half vector ``θ_h`` from ``r`` reflects ``l`` at ``ψ = 2 θ_h``; the prefilter
    weights ``L(l)`` by ``D(θ_h) (n·l)``, and ``cos²θ_h = 1 − x/2`` gives
    ``D ∝ 1 / (α² + (x/2)(1 − α²))²``, times ``max(cos ψ, 0) = max(1 − x, 0)``.
    """
    a2 = alpha * alpha

    def kernel(x):
        return np.maximum(1.0 - x, 0.0) / (a2 + 0.5 * x * (1.0 - a2)) ** 2

    return kernel


def _beckmann_kernel(alpha: float):
    r"""Beckmann's lobe as a kernel of ``x = 1 − cos ψ`` about ``r`` (Karis's ``n = v = r``, as :func:`_ggx_kernel`).

    ``D ∝ exp(−tan²θ_h / α²) / cos⁴θ_h`` with ``θ_h = ψ/2``: ``cos²θ_h = 1 − x/2``, ``tan²θ_h = (x/2)/(1 − x/2)``,
    times ``max(1 − x, 0)``.  Near its axis it is the Gaussian ``exp(−ψ²/(2σ²))`` of ``σ = √2 α``; away from it
    the ``n·l`` factor and the NDF's own shape matter (a rough Beckmann lobe under a smooth sky: 9 % median
    error with the plain Gaussian kernel, 1.7 % with this one).
    """
    a2 = alpha * alpha

    def kernel(x):
        c2 = np.maximum(1.0 - 0.5 * x, 1e-6)  # 0 only at ψ = π, where n·l = 0 anyway
        return np.exp(-(0.5 * x) / (c2 * a2)) / (c2 * c2) * np.maximum(1.0 - x, 0.0)

    return kernel


#: Where a GGX level's kernel is split (in σ): the core within it at the level's resolution, the long
#: tail beyond it on a map eight pixels per core radius.
_TAIL_START = 6.0


def _ggx_level(convolve, sigma: float, h0: int, *, fast: bool = False) -> np.ndarray:
    """One level of the GGX-tailed family: ``Σ K L Ω / Σ K Ω`` for the kernel of :func:`_ggx_kernel`.

    GGX's tails reach the horizon, so the kernel is split at ``ψ₁ = 6σ``: ``K − K(max(x, x₁))``, zero
    beyond ``ψ₁``, at the level's own resolution, and ``K(max(x, x₁))``, flat inside ``ψ₁`` and smooth on
    the scale of ``ψ₁``, on a coarser map (its sums resampled bilinearly); the two add up to ``K``.
    ``convolve(height, kernel_of, support)`` is a row convolution of the mip of that height.  With ``fast``,
    the core's kernel is evaluated once per point, a tail map as fine as the level is not made apart (the two
    parts are one convolution with ``K``) and a coarser one is resampled row by row, then column by column
    (:func:`_upsample`): the same values, to rounding.
    """
    alpha = sigma / math.sqrt(2.0)
    kernel = _ggx_kernel(alpha)
    h = _level_height(sigma, h0)
    psi1 = _TAIL_START * sigma
    if psi1 >= math.pi / 2 or (fast and _tail_height(sigma, h0) == h):
        conv, norm = convolve(h, kernel, math.pi / 2 + math.pi / h)
        return conv / norm[:, None, None]
    x1 = 1.0 - math.cos(psi1)
    if fast:
        # K falls with x: K − K(max(x, x₁)) is K − K(x₁) inside ψ₁ and 0 beyond, one evaluation of K.
        k1 = kernel(np.array([x1]))[0]
        conv, norm = convolve(h, lambda x: np.maximum(kernel(x) - k1, 0.0), psi1 + math.pi / h)
    else:
        conv, norm = convolve(h, lambda x: kernel(x) - kernel(np.maximum(x, x1)), psi1 + math.pi / h)
    ht = _tail_height(sigma, h0)
    tconv, tnorm = convolve(ht, lambda x: kernel(np.maximum(x, x1)), math.pi / 2 + math.pi / ht)
    tail = np.concatenate([tconv, np.broadcast_to(tnorm[:, None, None], (ht, 2 * ht, 1))], axis=2)
    if ht < h and fast:
        tail = _upsample(tail, h)
    elif ht < h:
        flat = tail.reshape(-1, 4)
        tail = latlong_lookup(flat, ht, 2 * ht, _pixel_directions(h, 2 * h))
    return (conv + tail[..., :3]) / (norm[:, None, None] + tail[..., 3:])


def _upsample(image: np.ndarray, h: int) -> np.ndarray:
    """:func:`latlong_lookup` of a lat-long ``image`` at the pixel centres of an ``h × 2h`` one, ``h`` a multiple.

    The bilinear lookup at a regular grid is separable: rows first (clamped at the edge rows, as the lookup
    without poles), then columns (wrapping around).
    """
    hi = image.shape[0]

    def weights(count, scale, size, wrap):
        f = (np.arange(count) + 0.5) / scale - 0.5
        if not wrap:
            f = np.clip(f, 0.0, size - 1)
        i0 = np.floor(f).astype(np.int64)
        if not wrap:
            i0 = np.minimum(i0, size - 2)
        t = f - i0
        return i0 % size, (i0 + 1) % size if wrap else np.minimum(i0 + 1, size - 1), t

    r0, r1, ty = weights(h, h // hi, hi, wrap=False)
    rows = image[r0] * (1 - ty)[:, None, None] + image[r1] * ty[:, None, None]
    c0, c1, tx = weights(2 * h, h // hi, 2 * hi, wrap=True)
    return rows[:, c0] * (1 - tx)[None, :, None] + rows[:, c1] * tx[None, :, None]


def _tail_height(sigma: float, h0: int) -> int:
    """The height of a GGX level's tail map: eight pixels per core radius ``ψ₁``, at most the level's."""
    h, psi1 = _level_height(sigma, h0), _TAIL_START * sigma
    ht = _MIN_HEIGHT
    while ht < 8 * math.pi / psi1 and ht < h:
        ht *= 2
    return ht


def _level_tasks(convolve, sigmas, h0: int, *, fast: bool = False) -> list:
    """``(family, index, fn, work)`` for every blurred level: ``fn()`` returns the level, float32.

    ``convolve(height, kernel_of, support)`` convolves the mip of that height.  Each call is independent of
    the others (they may run on several threads in any order and give the same levels).  ``fast``: as
    :func:`_ggx_level`.  ``work`` counts the kernel values the level's convolutions evaluate (to order them).
    """

    def normalized(h, kernel_of, support):
        conv, norm = convolve(h, kernel_of, support)
        return (conv / norm[:, None, None]).astype(np.float32)

    def work(h, support):
        d = np.arange(min(h - 1, int(math.ceil(support / (math.pi / h)))) + 1)
        return int(((h - 1 - d) // 2 + 1).sum()) * h

    tasks = []
    for k, s in enumerate(sigmas):
        if k == 0:
            continue
        h = _level_height(s, h0)
        kappa = 1.0 / (s * s)
        beckmann_support = min(_SUPPORT * s, math.pi / 2) + math.pi / h
        tasks.append(("mirror", k, lambda h=h, kappa=kappa, s=s: normalized(
            h, lambda x: np.exp(-kappa * x), _SUPPORT * s), work(h, _SUPPORT * s)))
        tasks.append(("beckmann", k, lambda h=h, s=s, support=beckmann_support: normalized(
            h, _beckmann_kernel(s / math.sqrt(2.0)), support), work(h, beckmann_support)))
        psi1, ht = _TAIL_START * s, _tail_height(s, h0)
        whole = psi1 >= math.pi / 2 or (fast and ht == h)
        ggx_work = work(h, math.pi / 2 + math.pi / h) if whole else (
            work(h, psi1 + math.pi / h) + work(ht, math.pi / 2 + math.pi / ht))  # fmt: skip
        tasks.append(("ggx", k, lambda s=s: _ggx_level(convolve, s, h0, fast=fast).astype(np.float32), ggx_work))
    return tasks


def _run_all(fns: list) -> list:
    """``[fn() for fn in fns]``, the calls shared between this thread and the engine's shading threads.

    Each result is the same whichever thread makes it.  This thread takes calls too and waits only for calls
    already started, so a full pool (or a caller that is itself one of its threads) cannot stall it.
    """
    from ..shading.batch import _pool, _threads

    helpers = min(_threads(), len(fns), _LEVEL_THREADS) - 1
    if helpers <= 0:
        return [fn() for fn in fns]
    results = [None] * len(fns)
    lock = threading.Lock()
    queue = iter(range(len(fns)))

    def work():
        while True:
            with lock:
                k = next(queue, None)
            if k is None:
                return
            results[k] = fns[k]()

    futures = [_pool().submit(work) for _ in range(helpers)]
    try:
        work()
    finally:
        for f in futures:
            if not f.cancel():
                f.result()
    return results


def _base_image(env: Environment, height: int) -> np.ndarray:
    """The environment as a lat-long image of power-of-two ``height`` (float64)."""
    if isinstance(env, LatLongEnvironment) and env.width == 2 * env.height:
        img = env.image
        while img.shape[0] > height and img.shape[0] % 2 == 0:
            img = _halve(img)
        if img.shape[0] == height:
            return img
    d = _pixel_directions(height, 2 * height)  # the callers checked and budgeted this size
    return np.broadcast_to(np.asarray(env._radiance(d), dtype=np.float64), (height, 2 * height, 3)).copy()


def _source_height(env: Environment, height) -> int:
    if height is not None:
        h = check_count("height", height, _MIN_HEIGHT, 8192)
        if h & (h - 1):
            raise ValueError(f"height must be a power of two (16, 32, …, 8192); got {quote(height)}")
        return h
    if isinstance(env, LatLongEnvironment):
        h = _MIN_HEIGHT
        while h * 2 <= env.height:
            h *= 2
        return min(h, 1024)
    return 256


def latlong_sh(image) -> np.ndarray:
    r"""The nine SH coefficients of a lat-long image taken as constant over each pixel, integrated exactly.

    Each basis function of :func:`lighting.integrate.sh_basis` is a product ``g(θ) h(φ)``, so its
    integral over a pixel is ``∫ g sin θ dθ · ∫ h dφ``, both in closed form: ``L_lm = Σ_pixels L
    ∫_pixel Y_lm dω``.  (Summing ``Y`` at pixel centres instead is off by the square of a pixel:
    0.8 % in the irradiance of a constant sky at 8 rows.)

    Parameters
    ----------
    image : ndarray, (H, 2H or any W, 3)

    Returns
    -------
    ndarray, (9, 3)
        Float64 coefficients in :func:`~lighting.integrate.sh_basis` order.

    Examples
    --------
    >>> c = latlong_sh(np.ones((4, 8, 3)))
    >>> round(float(c[0, 0]) / (2 * math.sqrt(math.pi)), 12), float(np.abs(c[1:]).max()) < 1e-15
    (1.0, True)
    """
    img = np.asarray(image, dtype=np.float64)
    h, w = img.shape[:2]
    t = _row_bounds(h)
    t0, t1 = t[:-1], t[1:]
    z0, z1 = np.cos(t0), np.cos(t1)
    # Column j spans the azimuths from φ(a = 2π(j+1)/W) up to φ(a = 2πj/W): φ falls as the columns grow.
    p = latlong_azimuth(np.arange(w + 1) * (2 * math.pi / w))
    p0, p1 = p[1:], p[:-1]
    # ∫ g(θ) sin θ dθ over each row (z = cos θ decreasing from z0 to z1).
    rows = {
        "1": z0 - z1,
        "s": (t1 - t0) / 2 - (np.sin(2 * t1) - np.sin(2 * t0)) / 4,  # ∫ sin²θ dθ
        "c": (z0 * z0 - z1 * z1) / 2,  # ∫ cos θ sin θ dθ
        "ss": (z0 - z0**3 / 3) - (z1 - z1**3 / 3),  # ∫ sin³θ dθ
        "sc": (np.sin(t1) ** 3 - np.sin(t0) ** 3) / 3,  # ∫ sin²θ cos θ dθ
        "p2": (z0**3 - z0) - (z1**3 - z1),  # ∫ (3cos²θ − 1) sin θ dθ
    }
    cols = {
        "1": p1 - p0,
        "cos": np.sin(p1) - np.sin(p0),
        "sin": np.cos(p0) - np.cos(p1),
        "sincos": (np.sin(p1) ** 2 - np.sin(p0) ** 2) / 2,
        "cos2": (np.sin(2 * p1) - np.sin(2 * p0)) / 2,
    }
    k1, k2, k20, k22 = (math.sqrt(3 / (4 * math.pi)), 0.5 * math.sqrt(15 / math.pi), 0.25 * math.sqrt(5 / math.pi),
                        0.25 * math.sqrt(15 / math.pi))  # fmt: skip
    # (constant, row factor, column factor) of Y00, Y1-1 (y), Y10 (z), Y11 (x), Y2-2 (xy), Y2-1 (yz),
    # Y20 (3z² − 1), Y21 (xz), Y22 (x² − y²).
    terms = [
        (0.5 / math.sqrt(math.pi), "1", "1"),
        (k1, "s", "sin"),
        (k1, "c", "1"),
        (k1, "s", "cos"),
        (k2, "ss", "sincos"),
        (k2, "sc", "sin"),
        (k20, "p2", "1"),
        (k2, "sc", "cos"),
        (k22, "ss", "cos2"),
    ]
    return np.stack([k * np.einsum("i,ijc,j->c", rows[r], img, cols[c]) for k, r, c in terms])


def kernel_of_lobe(lobe) -> str:
    """The prefiltered family a lobe is looked up in: ``"mirror"`` for a lobe about the mirror direction
    (Phong), ``"ggx"`` for a half-vector lobe with GGX's tails, ``"beckmann"`` for any other half-vector lobe.

    Parameters
    ----------
    lobe : Lobe

    Returns
    -------
    str
        A key of :data:`KERNELS`.
    """
    if lobe.axis != "half":
        return "mirror"
    return "ggx" if lobe.tails == "ggx" else "beckmann"


def prefilter_height(environment, height=None) -> int:
    """The source height :func:`prefilter_environment` uses for ``environment`` (width: twice it).

    A lat-long image: its largest power-of-two height up to 1024; a constant: 16 rows (it is the same at
    every width); any other environment: 256 rows; an intensity and rotation are looked through.

    Parameters
    ----------
    environment : Environment, scalar/RGB radiance or callable
    height : int, optional
        Asked for explicitly (a power of two, 16 to 8192; a constant still uses 16).

    Returns
    -------
    int

    Examples
    --------
    >>> prefilter_height(1.0), prefilter_height(lambda d: d[..., 2:3] + 1.0)
    (16, 256)
    """
    env = _unwrap(as_environment(environment))[0]
    h = _source_height(env, height)
    return _MIN_HEIGHT if isinstance(env, ConstantEnvironment) else h


class PrefilteredEnvironment:
    """An environment averaged over lobes of widths :attr:`sigmas`, its SH9 projection, and lookups.

    Build one with :func:`prefilter_environment`.  Levels are ``float32`` lat-long images.

    Attributes
    ----------
    environment : Environment
        What was prefiltered (after unwrapping an intensity and rotation, see ``to_base``).
    sigmas : tuple of float
        The lobe width ``σ`` of each level, radians; ``sigmas[0] = 0`` is the environment itself.
    levels : list of ndarray
        ``(H_k, 2 H_k, 3)`` float32 images, averaged over Gaussian (von Mises–Fisher) lobes.
    families : dict of str to list of ndarray
        The levels of each kernel (:data:`KERNELS`): ``"mirror"`` (:attr:`levels`: the von Mises–Fisher
        lobe about ``r``, Phong's), ``"beckmann"`` and ``"ggx"`` (the NDF's own lobe with ``n = v = r``,
        times ``n·l``: Karis's kernel; GGX with its long tails).
    sh : ndarray, (9, 3)
        The SH9 projection of level 0, each pixel's basis integral exact (:func:`latlong_sh`).
    """

    def __init__(self, environment, sigmas, families, sh, scale=1.0, to_base=None):
        self.environment = environment
        #: What the levels were made from (see :func:`prefilter_environment`), or None.
        self.content_key = None
        self.sigmas = tuple(float(s) for s in sigmas)
        self.families = families
        self.levels = families["mirror"]
        self.sh = sh
        self._scale = np.broadcast_to(np.asarray(scale, dtype=np.float64), (3,))
        self._to_base = to_base
        self._flat = {k: [np.ascontiguousarray(im.reshape(-1, 3)) for im in v] for k, v in families.items()}
        # Each level's value at the zenith and the nadir: the mean of its edge row (every column meets there).
        self._poles = {k: [(im[0].mean(axis=0), im[-1].mean(axis=0)) for im in v] for k, v in families.items()}
        c1, c2, c3, c4, c5 = SH_CONSTANTS
        L = np.asarray(sh, dtype=np.float64)  # noqa: N806 - the paper's L_lm
        self._sh_matrices = [
            np.array([
                [c1 * L[8, k], c1 * L[4, k], c1 * L[7, k], c2 * L[3, k]],
                [c1 * L[4, k], -c1 * L[8, k], c1 * L[5, k], c2 * L[1, k]],
                [c1 * L[7, k], c1 * L[5, k], c3 * L[6, k], c2 * L[2, k]],
                [c2 * L[3, k], c2 * L[1, k], c2 * L[2, k], c4 * L[0, k] - c5 * L[6, k]],
            ])
            for k in range(3)
        ]  # fmt: skip

    def __repr__(self):
        h, w = self.levels[0].shape[:2]
        return f"PrefilteredEnvironment({len(self.levels)} levels from {h}x{w}, σ up to {self.sigmas[-1]:g})"

    @property
    def nbytes(self) -> int:
        """Bytes held by the levels of every family (level 0 counted once: the families share it)."""
        return sum(im.nbytes for fam in self.families.values() for im in fam[1:]) + self.levels[0].nbytes

    def _base(self, d):
        return d if self._to_base is None else self._to_base(d)

    def for_environment(self, environment) -> PrefilteredEnvironment:
        """These levels for ``environment``: the same base turned or scaled (no prefiltering again).

        Parameters
        ----------
        environment : Environment
            :attr:`environment` itself, or a ``TransformedEnvironment`` of it (an intensity and a rotation).

        Returns
        -------
        PrefilteredEnvironment
            Sharing the levels; the intensity and rotation applied at lookup.

        Raises
        ------
        ValueError
            If ``environment`` is not :attr:`environment`, turned or scaled.
        """
        base, scale, to_base = _unwrap(as_environment(environment))
        if base is not self.environment:
            raise ValueError("prefiltered must be prefilter_environment() of this light's environment (or of the "
                             f"environment it turns or scales); got one of {self.environment!r}")  # fmt: skip
        out = copy.copy(self)
        out._scale = np.broadcast_to(np.asarray(scale, dtype=np.float64), (3,))
        out._to_base = to_base
        return out

    def level_of(self, sigma) -> np.ndarray:
        """The fractional level index of lobe width ``sigma``: linear in ``σ`` below ``sigmas[1]``,
        linear in ``log σ`` above, clamped to the last level."""
        s = np.asarray(sigma, dtype=np.float64)
        sig = self.sigmas
        if len(sig) == 1:
            return np.zeros(s.shape)
        with np.errstate(divide="ignore"):
            logs = np.log(np.maximum(s, sig[1]))
        above = np.interp(logs, np.log(sig[1:]), np.arange(1, len(sig)))
        return np.where(s < sig[1], np.clip(s / sig[1], 0.0, 1.0), above)

    def lookup(self, directions, sigma, kernel: str = "mirror") -> np.ndarray:
        r"""``\bar L(r, σ)``: the environment averaged over a lobe of width ``sigma`` about ``directions``.

        Bilinear in each level (within half a row of a pole, linear in ``θ`` to the pole's value, the
        mean of the edge row), linear between the two levels around ``σ``.

        Parameters
        ----------
        directions : array_like, (..., 3)
            Lobe axes (world frame; need not be unit).
        sigma : array_like, broadcasting to (...)
            Lobe widths in radians, ``>= 0``.
        kernel : {"mirror", "beckmann", "ggx"}
            The family of levels (:func:`kernel_of_lobe` chooses one for a model's lobe).

        Returns
        -------
        ndarray, (..., 3)
            Radiance, in the dtype of ``directions`` (float32 stays float32).
        """
        d = check_vectors("directions", directions)
        if kernel not in self.families:
            raise ValueError(f"kernel must be one of {', '.join(map(repr, self.families))}; got {quote(kernel)}")
        return self._lookup(d, sigma, kernel)

    def _lookup(self, d: np.ndarray, sigma, kernel: str) -> np.ndarray:
        """:meth:`lookup` for finite float directions and a kernel of :attr:`families`: the integrators' path."""
        levels, flat, poles = self.families[kernel], self._flat[kernel], self._poles[kernel]
        dt = working_dtype(d)
        shape = d.shape[:-1]
        d = self._base(d.reshape(-1, 3))
        lf = np.broadcast_to(self.level_of(sigma), shape).reshape(-1)
        k0 = np.minimum(np.floor(lf).astype(np.int64), len(levels) - 1)
        angles = latlong_angles(d)
        out = np.zeros((d.shape[0], 3), dtype=dt)
        # One width for every direction (a part's σ) is the common case: one group, no gather.
        groups = [(int(k0[0]), slice(None))] if k0.size and np.all(k0 == k0[0]) else [
            (int(k), np.flatnonzero(k0 == k)) for k in np.unique(k0)]  # fmt: skip
        for k, idx in groups:
            ang = (angles[0][idx], angles[1][idx])
            h = levels[k].shape[0]
            val = latlong_lookup(flat[k], h, 2 * h, None, poles[k], angles=ang).astype(dt, copy=False)
            if k + 1 < len(levels):
                t = (lf[idx] - k).astype(dt)[:, None]
                h1 = levels[k + 1].shape[0]
                upper = latlong_lookup(flat[k + 1], h1, 2 * h1, None, poles[k + 1], angles=ang).astype(dt, copy=False)
                val = val + t * (upper - val)
            out[idx] = val
        return (out * self._scale.astype(dt)).reshape(shape + (3,))

    def irradiance_sh(self, normals) -> np.ndarray:
        """SH9 irradiance ``E(n)`` (Ramamoorthi & Hanrahan), clamped at 0, in the dtype of ``normals``.

        Parameters
        ----------
        normals : array_like, (..., 3)
            Unit normals, world frame.

        Returns
        -------
        ndarray, (..., 3)
        """
        return self._irradiance_sh(check_vectors("normals", normals))

    def _irradiance_sh(self, n: np.ndarray) -> np.ndarray:
        """:meth:`irradiance_sh` for finite float normals: the integrators' path."""
        dt = working_dtype(n)
        shape = n.shape
        n = self._base(n.reshape(-1, 3)).astype(dt, copy=False)
        # E = (n, 1)ᵀ M (n, 1) per channel: the matrix form of Ramamoorthi & Hanrahan's eq. 13 (their
        # eq. 12), three small matrix products instead of nine broadcast terms (sh_irradiance, the reference).
        n4 = np.concatenate([n, np.ones((n.shape[0], 1), dtype=dt)], axis=1)
        e = np.empty((n.shape[0], 3), dtype=dt)
        for c in range(3):
            e[:, c] = np.einsum("ij,ij->i", n4 @ self._sh_matrices[c].astype(dt), n4)
        return (np.maximum(e, 0) * self._scale.astype(dt)).reshape(shape).astype(dt, copy=False)


def _unwrap(env):
    """``(base environment, scale, to_base)`` of an environment with an intensity and a rotation."""
    scale, to_base = 1.0, None
    base = getattr(env, "base", None)
    if base is not None and callable(getattr(env, "to_base", None)):
        scale, to_base = getattr(env, "intensity", 1.0), env.to_base
        env = base
    return env, scale, to_base


def _prefilter_levels(base: np.ndarray, sigmas, h0: int, *, fast: bool = True) -> dict:
    """The levels of every family (:data:`KERNELS`) of ``base``, an ``(h0, 2 h0, 3)`` float64 image.

    ``fast=False`` computes them with the readable reference, :func:`_convolve_rows`, one call after the
    other; the default with :func:`_convolve_rows_fast`, the source's row FFTs shared by every kernel of a
    height and the levels shared between threads.
    """
    mips = {h0: base}
    h = h0
    while h > _MIN_HEIGHT:
        mips[h // 2] = _halve(mips[h])
        h //= 2
    if fast:
        spectra = {h: _RowSpectra(img) for h, img in mips.items() if h <= _MAX_LEVEL_HEIGHT}

        def convolve(h, kernel_of, support):
            return _convolve_rows_fast(mips[h], kernel_of, support, spectra[h])
    else:

        def convolve(h, kernel_of, support):
            return _convolve_rows(mips[h], kernel_of, support)

    tasks = _level_tasks(convolve, sigmas, h0, fast=fast)
    # The most work first: the threads then finish together.
    order = sorted(range(len(tasks)), key=lambda t: -tasks[t][3])
    done = _run_all([tasks[t][2] for t in order]) if fast else [tasks[t][2]() for t in order]
    level0 = base.astype(np.float32)
    families = {k: [level0] + [None] * (len(sigmas) - 1) for k in KERNELS}
    for t, level in zip(order, done, strict=True):
        family, k = tasks[t][:2]
        families[family][k] = level
    return families


def prefilter_environment(environment, *, sigmas=PREFILTER_SIGMAS, height=None,
                          reuse: bool = True) -> PrefilteredEnvironment:  # fmt: skip
    r"""Prefilter an environment for the split sum: one lat-long level per lobe width ``σ``.

    Parameters
    ----------
    environment : Environment, scalar/RGB radiance or callable
        A lat-long image is used at the largest power-of-two height it holds (up to 1024, halving by
        2 × 2 solid-angle-weighted blocks; other sizes are resampled bilinearly); other environments
        are sampled at ``height`` rows (default 256).  An intensity and rotation
        (``TransformedEnvironment``) are applied at lookup, not baked in.
    sigmas : sequence of float
        Increasing lobe widths in radians, the first 0 (default :data:`PREFILTER_SIGMAS`).
    height : int, optional
        The source height, a power of two from 16 to 8192.
    reuse : bool, optional
        Share the levels of an image among the last few prefiltered that is equal to this one, bit for bit, at
        the same widths (a sky loaded again); ``False`` prefilters in any case (what a benchmark times).

    Returns
    -------
    PrefilteredEnvironment

    Examples
    --------
    >>> from lighting.lights.environment import ConstantEnvironment
    >>> pre = prefilter_environment(ConstantEnvironment(2.0), height=16)
    >>> pre.lookup([0.0, 0.0, 1.0], 0.3).round(6).tolist()  # a constant stays constant at every width
    [2.0, 2.0, 2.0]
    """
    env, scale, to_base = _unwrap(as_environment(environment))
    try:
        sig = [float(s) for s in sigmas]
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"sigmas must be a sequence of lobe widths in radians; got {quote(sigmas)}") from None
    increasing = all(b > a for a, b in zip(sig[:-1], sig[1:], strict=True))
    if not sig or sig[0] != 0.0 or not increasing or not math.isfinite(sig[-1]):
        raise ValueError(f"sigmas must start at 0 and increase, finite (radians); got {quote(sigmas)}")
    h0 = prefilter_height(env, height)
    check_budget("height", h0 * 2 * h0 * 3 * 8 * 12, what=f"prefiltering a {2 * h0}x{h0} environment")
    base = _base_image(env, h0)
    first = base.reshape(-1, base.shape[-1])[0]
    if np.all(base == first):
        # A constant environment (the uniform sky, a constant radiance): a normalized kernel leaves it as it
        # is, so every level of every family is the constant itself, exactly, and nothing is convolved.
        level = base.astype(np.float32)
        families = {k: [level] * len(sig) for k in ("mirror", "beckmann", "ggx")}
        return PrefilteredEnvironment(env, sig, families, latlong_sh(base), scale=scale, to_base=to_base)
    reuse = check_bool("reuse", reuse)
    key = _content_key(base, sig)
    found = _recent.get(key) if reuse else None
    if found is None:
        families = _prefilter_levels(base, sig, h0)
        for levels in families.values():
            for level in levels:
                level.setflags(write=False)  # shared by every environment of the same image
        found = _recent.put(key, (families, latlong_sh(base)))
    pre = PrefilteredEnvironment(env, sig, found[0], found[1], scale=scale, to_base=to_base)
    pre.content_key = key
    return pre


#: The levels of the last few images prefiltered, by content: a sky loaded again (a scene rendered once more, the
#: explorer switching back) is not prefiltered again.  Each entry holds what one PrefilteredEnvironment holds.
_recent = Recent(4)


def _content_key(base: np.ndarray, sigmas) -> tuple:
    """What the levels depend on: the base image's bytes (as a digest), its shape and dtype, and the widths."""
    data = np.ascontiguousarray(base)
    return hashlib.sha256(data.tobytes()).hexdigest(), data.shape, data.dtype.str, tuple(sigmas)


def irradiance_map(environment, height: int = 32, *, source_height=None) -> LatLongEnvironment:
    r"""The irradiance ``E(n) = ∫ L(l) max(n·l, 0) dω`` of the pixelized environment, as a lat-long map.

    Computed with the clamped cosine as the kernel of the row convolution (module notes), a midpoint
    rule over the source's pixels: relative error ``O((π/H)²)``, 6e-5 for a constant sky at 64 source
    rows, 5e-6 at 256.  The reference SH9 irradiance is measured against.  Look it up with ``.radiance(n)``.

    Parameters
    ----------
    environment : Environment, scalar/RGB radiance or callable
        As :func:`prefilter_environment` (an intensity and a rotation are not supported here: pass
        the base environment and rotate the normals).
    height : int
        Rows of the irradiance map (a power of two, 8 to 1024; ``E`` is smooth, 32 is plenty).
    source_height : int, optional
        Rows the environment is sampled at (default: as :func:`prefilter_environment`).

    Returns
    -------
    LatLongEnvironment
        ``E`` at its pixel centres (bilinear between them).

    Examples
    --------
    >>> from lighting.lights.environment import ConstantEnvironment
    >>> E = irradiance_map(ConstantEnvironment(1.0), height=8, source_height=64)
    >>> round(float(E.radiance([0.0, 0.0, 1.0])[0]), 3)  # π L
    3.142
    """
    env = as_environment(environment)
    h_src = _source_height(env, source_height)
    h = check_count("height", height, 8, 1024)
    if h & (h - 1) or h > h_src:
        raise ValueError(f"height must be a power of two from 8 to the source height {h_src}; got {quote(height)}")
    check_budget("source_height", h_src * 2 * h_src * 3 * 8 * 12, what=f"irradiance of a {2 * h_src}x{h_src} map")
    src = _base_image(env, h_src)
    support = math.pi / 2 + math.pi / h_src  # the hemisphere, and half a source row
    if h_src <= _MAX_LEVEL_HEIGHT:
        # The fast convolution of every source row: a few times faster than the reference on the rows it reads
        # (the same sums to float64 rounding); its tables grow as the source's height squared, hence the bound.
        conv = np.maximum(_convolve_rows_fast(src, _clamped_cosine, support)[0], 0.0)
        return LatLongEnvironment(conv if h == h_src else _bilinear(conv, _pixel_directions(h, 2 * h)))
    return LatLongEnvironment(_irradiance_reference(src, h, support))


def _clamped_cosine(one_minus_cos):
    """``max(cos ψ, 0)``, the irradiance's kernel, as a function of ``1 − cos ψ``."""
    return np.maximum(1.0 - one_minus_cos, 0.0)


def _irradiance_reference(src: np.ndarray, h: int, support: float) -> np.ndarray:
    """:func:`irradiance_map`'s image of ``h`` rows from the source ``src`` by the reference convolution (the clamped
    cosine within ``support`` radians) on the source grid, read bilinearly at the output centres.  An output row's
    centre lies between source rows ``f r + f/2 − 1`` and ``f r + f/2`` (``f`` the ratio of the heights): those alone
    are convolved; the others are NaN, which any read would carry into the map (the whole grid is convolved then)."""
    factor = src.shape[0] // h
    kernel = _clamped_cosine
    if factor == 1:
        conv, _ = _convolve_rows(src, kernel, support)
        return np.maximum(conv, 0.0)
    read = np.arange(h)[:, None] * factor + np.array([factor // 2 - 1, factor // 2])
    conv, _ = _convolve_rows(src, kernel, support, rows=read.reshape(-1))
    out = _bilinear(np.maximum(conv, 0.0), _pixel_directions(h, 2 * h))
    if np.isnan(out).any():
        conv, _ = _convolve_rows(src, kernel, support)
        out = _bilinear(np.maximum(conv, 0.0), _pixel_directions(h, 2 * h))
    return out


def _bilinear(image: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """``LatLongEnvironment(image).radiance(directions)`` of a float64 image that may hold NaN (rows not computed)."""
    return latlong_lookup(np.ascontiguousarray(image.reshape(-1, 3)), image.shape[0], image.shape[1], directions)

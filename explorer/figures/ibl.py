"""Image-based lighting: the split sum beside its Monte-Carlo reference, and where they differ.

Registered on import (see :mod:`explorer.figures.base`); drawn by :mod:`explorer.figures`.  The
sphere, environment and error measure are those of :mod:`lighting.validation.accuracy` (the ``ibl``
study of ``report accuracy``), whose error against run time for every model is the figure
``accuracy_ibl`` (:mod:`explorer.figures.accuracy`).
"""

from __future__ import annotations

import time

import numpy as np

from lighting import CookTorrance
from lighting.integrate.dominant import dominant_radiance
from lighting.integrate.ibl import ProgressiveRadiance, split_sum_radiance
from lighting.integrate.prefilter import prefilter_environment
from lighting.render.image import encode_srgb8
from lighting.validation import accuracy

from .base import new_figure, register, show_image

#: The colour of the pixels the error map leaves out: the reference is too dark there to divide by.
UNLIT_COLOUR = "#8C8C8C"


def _image(values, coverage, background=0.0):
    """Per-pixel values ``(N, ...)`` of the sphere's covered pixels as a ``(size, size, ...)`` image."""
    out = np.full(coverage.shape + values.shape[1:], background, dtype=np.float64)
    out[coverage] = values
    return out


def _faded(img):
    """A sphere image with its silhouette pixels faded by their coverage of the disc (display only).

    The spheres are computed at fewer pixels than they are shown with: without the fade their outline
    would show staircase steps.  The disc is :func:`lighting.render.sphere.sphere_camera`'s (radius
    ``size / 2.16``), as in :mod:`explorer.figures.rendering`.
    """
    size = img.shape[0]
    c = np.arange(size) + 0.5 - size / 2
    d = np.hypot(c[:, None], c[None, :])
    return img * np.clip(size / 2 / 1.08 - d + 0.5, 0.0, 1.0)[..., None]


@register(
    "ibl_error",
    title="Image-based lighting: the split sum against Monte Carlo",
    caption=(
        "A GGX sphere (α = {alpha:g}, F = 1) under the '{sky}' environment ({env_height}×{env_width} "
        "latitude–longitude map). Left, top: the fast path — the split sum (the lobe's albedo times the "
        "environment prefiltered over a lobe of the same width; a diffuse lobe would take SH9 irradiance), "
        "{fast_ms:.1f} ms for {pixels} pixels in float32. Left, bottom: the Monte-Carlo reference with multiple "
        "importance sampling at {spp} samples per pixel ({mc_s:.2g} s). Right: their per-pixel relative "
        "difference |split sum − MC| / MC over the lit pixels (median {median_error:.1%}, 95th percentile "
        "{p95_error:.1%}; the reference's own median error is {reference_error:.1%}, part of what the map shows). "
        "Grey: the {unlit_percent:.0f} % of the sphere's pixels where the reference is darker than "
        "{lit_percent:g} % of its 99th-percentile pixel, left out of the error (a relative error there divides "
        "by almost nothing; the study does the same); its ragged edge is the reference's noise at that "
        "threshold. The split sum is worst where the environment changes across the lobe and at grazing views, "
        "where the real lobe stretches and shifts off the mirror direction. The engine's default method, the "
        "dominant lights with filtered importance sampling, on the same pixels: median {dominant_median_error:.1%}, "
        "95th percentile {dominant_p95_error:.1%}, {dominant_ms:.0f} ms. Error against run time for every model "
        "and environment: accuracy_ibl."
    ),
    slides="Beyond the slides: image-based lighting (Ramamoorthi & Hanrahan 2001; Karis 2013)",
    nondeterministic="states measured wall-clock times (the split sum's, the dominant method's and Monte Carlo's) "
                     "in its titles and caption",
    size="4:3",
    sky="studio",
    alpha=0.2,
)
def ibl_error(q, *, sky, alpha):
    """The split sum, the Monte-Carlo reference and their per-pixel difference, on one sphere.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    sky : str
        A procedural sky (:mod:`lighting.lights.skies`).
    alpha : float
        GGX roughness.

    Returns
    -------
    tuple
        ``(figure, measured)``: ``median_error``, ``p95_error`` and ``reference_error`` (relative, lit
        pixels), ``dominant_median_error``, ``dominant_p95_error`` and ``dominant_ms`` (the dominant-light
        method on the same pixels), ``fast_ms``, ``mc_s``, ``spp``, ``pixels``, ``lit_pixels``, ``unlit_percent``.
    """
    import matplotlib.colors
    from matplotlib.patches import Patch

    size = 48 if q.quick else 160
    spp = 32 if q.quick else 256
    env = accuracy.ibl_environment(sky, 64 if q.quick else 128)
    coverage, n, v = accuracy.ibl_sphere(size)
    model = CookTorrance(1.0, alpha, 1.0, ndf="ggx", fresnel="none")
    pre = prefilter_environment(env)
    n32, v32 = n.astype(np.float32), v.astype(np.float32)
    split_sum_radiance(model, pre, n32, v32)  # the albedo table once, out of the timing
    t0 = time.perf_counter()
    fast = split_sum_radiance(model, pre, n32, v32)
    fast_ms = 1e3 * (time.perf_counter() - t0)
    mc = ProgressiveRadiance(model, env, n, v, seed=7)
    for _ in range(8):
        mc.add(spp // 8)
    errs, lit, own = accuracy.ibl_pixel_errors(fast, mc.value, mc.error)
    dominant_radiance(model, pre, n32, v32)  # its lights, residual and sample tables once, out of the timing
    t0 = time.perf_counter()
    dom = dominant_radiance(model, pre, n32, v32)
    dominant_ms = 1e3 * (time.perf_counter() - t0)
    dom_errs, _, _ = accuracy.ibl_pixel_errors(dom, mc.value, mc.error)

    fig = new_figure()
    grid = fig.add_gridspec(2, 2, width_ratios=[1.0, 1.9])
    exposure = 1.0 / max(float(np.percentile(np.max(mc.value[lit], axis=-1), 99)), 1e-6)
    for row, values, title in ((0, fast, f"split sum, {fast_ms:.1f} ms"),
                               (1, mc.value, f"Monte Carlo (MIS), {mc.samples} spp, {mc.seconds:.2g} s")):  # fmt: skip
        ax = fig.add_subplot(grid[row, 0])
        rgb = _faded(_image(np.asarray(values, dtype=np.float64) * exposure, coverage))
        show_image(ax, encode_srgb8(rgb)[0], title, fontsize=12.5)
    ax = fig.add_subplot(grid[:, 1])
    # Two layers on a white ground: the error of the lit pixels (a colour map), then the unlit pixels of
    # the sphere in one flat grey; outside the silhouette stays white.
    err_px = np.full(n.shape[0], np.nan)
    err_px[lit] = errs
    cmap = matplotlib.colormaps["magma"].with_extremes(bad=(0, 0, 0, 0))
    im = ax.imshow(np.ma.masked_invalid(_image(err_px, coverage, np.nan)), cmap=cmap,
                   norm=matplotlib.colors.LogNorm(1e-3, 1.0), interpolation="nearest")  # fmt: skip
    unlit = np.zeros(coverage.shape + (4,))
    unlit[coverage] = np.where(lit[:, None], 0.0, (*matplotlib.colors.to_rgb(UNLIT_COLOUR), 1.0))
    ax.imshow(unlit, interpolation="nearest")
    ax.set_xticks([])
    ax.set_yticks([])
    for spine in ax.spines.values():
        spine.set_visible(False)
    ax.set_title("relative difference per pixel, |split sum − MC| / MC")
    fig.colorbar(im, ax=ax, shrink=0.8, pad=0.02, label="relative difference (log scale)")
    ax.legend(handles=[Patch(color=UNLIT_COLOUR, label=f"not lit: reference < {100 * accuracy.IBL_LIT_FRACTION:g} % "
                                                       "of its bright pixels, not scored")],
              loc="lower center", bbox_to_anchor=(0.5, -0.06), fontsize=11, handlelength=1.4)  # fmt: skip

    return fig, {
        "alpha": alpha,
        "sky": sky,
        "env_height": env.height,
        "env_width": env.width,
        "median_error": float(np.median(errs)),
        "p95_error": float(np.percentile(errs, 95)),
        "dominant_median_error": float(np.median(dom_errs)),
        "dominant_p95_error": float(np.percentile(dom_errs, 95)),
        "dominant_ms": dominant_ms,
        "reference_error": float(np.median(own)),
        "fast_ms": fast_ms,
        "mc_s": mc.seconds,
        "spp": mc.samples,
        "pixels": int(n.shape[0]),
        "lit_pixels": int(lit.sum()),
        "unlit_percent": float(100.0 * (1.0 - lit.mean())),
        "lit_percent": 100 * accuracy.IBL_LIT_FRACTION,
    }

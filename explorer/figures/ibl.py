"""Image-based lighting: the split sum beside its Monte-Carlo reference, and what each costs in error.

Registered on import (see :mod:`explorer.figures.base`); drawn by :mod:`explorer.figures`.  The
numbers come from :mod:`lighting.validation.accuracy` (the ``ibl`` study of ``report accuracy``),
run here on one environment.
"""

from __future__ import annotations

import numpy as np

from lighting import CookTorrance
from lighting.integrate.ibl import ProgressiveRadiance, split_sum_radiance
from lighting.integrate.prefilter import prefilter_environment
from lighting.render.image import encode_srgb8
from lighting.validation import accuracy

from .base import PALETTE, new_figure, register, series_colours, show_image


def _image(values, coverage, background=0.0):
    """Per-pixel values ``(N, ...)`` of the sphere's covered pixels as a ``(size, size, ...)`` image."""
    out = np.full(coverage.shape + values.shape[1:], background, dtype=np.float64)
    out[coverage] = values
    return out


@register(
    "ibl_error",
    title="Image-based lighting: the split sum against Monte Carlo",
    caption=(
        "A GGX sphere (α = {alpha:g}, F = 1) under the '{sky}' environment. Top: the fast path — the split sum "
        "(the lobe's albedo times the environment prefiltered over a lobe of the same width; a diffuse lobe would "
        "take SH9 irradiance), {fast_ms:.1f} ms for {pixels} pixels in float32 — beside the "
        "Monte-Carlo reference with multiple importance sampling at {spp} samples per pixel ({mc_s:.2g} s), and "
        "their per-pixel relative difference (median {median_error:.1%}, 95th percentile {p95_error:.1%}; the "
        "reference's own median error {reference_error:.1%}). The split sum is worst where the environment "
        "changes across the lobe and at grazing views, where the real lobe stretches and shifts off the mirror "
        "direction. Bottom: median error over the lit pixels against run time, per roughness, for the split sum "
        "(stars) and Monte Carlo at increasing samples per pixel (lines), against a {ref_spp}-spp reference; "
        "SH9 irradiance (square) against the exact irradiance of the same pixelized map: {sh9_error:.2%}. "
        "Split sum by roughness: {split_errors}. Hollow markers: the reference's error exceeds the measured one."
    ),
    slides="Beyond the slides: image-based lighting (Ramamoorthi & Hanrahan 2001; Karis 2013)",
    nondeterministic="the bottom panel plots measured wall-clock times",
    sky="studio",
    alpha=0.2,
    alphas=(0.05, 0.2, 0.5),
)
def ibl_error(q, *, sky, alpha, alphas):
    """The split sum, the Monte-Carlo reference and their difference; error against time per roughness.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    sky : str
        A procedural sky (:mod:`lighting.lights.skies`).
    alpha : float
        GGX roughness of the top row.
    alphas : sequence of float
        GGX roughnesses of the bottom panel.

    Returns
    -------
    tuple
        ``(figure, measured)``: ``median_error``, ``p95_error`` and ``reference_error`` of the top row
        (relative, lit pixels), ``fast_ms``, ``mc_s``, ``spp``, ``pixels``, ``sh9_error``, and per
        roughness the split sum's median error (``split_by_alpha``).
    """
    size = 48 if q.quick else 320
    spp = 32 if q.quick else 256
    env = accuracy.ibl_environment(sky, 64 if q.quick else 256)
    coverage, n, v = accuracy.ibl_sphere(size)
    model = CookTorrance(1.0, alpha, 1.0, ndf="ggx", fresnel="none")
    pre = prefilter_environment(env)
    n32, v32 = n.astype(np.float32), v.astype(np.float32)
    split_sum_radiance(model, pre, n32, v32)  # the albedo table once, out of the timing
    import time

    t0 = time.perf_counter()
    fast = split_sum_radiance(model, pre, n32, v32)
    fast_ms = 1e3 * (time.perf_counter() - t0)
    mc = ProgressiveRadiance(model, env, n, v, seed=7)
    for _ in range(8):
        mc.add(spp // 8)
    errs, lit, own = accuracy.ibl_pixel_errors(fast, mc.value, mc.error)
    err_px = np.full(n.shape[0], np.nan)
    err_px[lit] = errs

    cfg = {
        "ibl_size": 24 if q.quick else 128,
        "ibl_pixels": 256 if q.quick else 1024,
        "repeat": 1 if q.quick else 3,
        "ibl_env_height": 64 if q.quick else 256,
        "ibl_irradiance_height": 16 if q.quick else 64,
        "ibl_reference_spp": 256 if q.quick else 8192,
        "ibl_spp": [8, 32] if q.quick else [8, 32, 128, 512],
        "ibl_models": [(f"α = {a:g}", CookTorrance(1.0, a, 1.0, ndf="ggx", fresnel="none")) for a in alphas],
        "ibl_environments": {sky: sky},
    }
    points = accuracy._ibl_points(cfg, lambda: None)

    fig = new_figure(15.0, 10.0)
    top, bottom = fig.subfigures(2, 1, height_ratios=[1.0, 0.95])
    axes = top.subplots(1, 3)
    exposure = 1.0 / max(float(np.percentile(np.max(mc.value[lit], axis=-1), 99)), 1e-6)
    for ax, values, title in ((axes[0], fast, f"split sum, {fast_ms:.1f} ms"),
                              (axes[1], mc.value, f"Monte Carlo (MIS), {spp} spp, {mc.seconds:.2g} s")):  # fmt: skip
        rgb = _image(np.asarray(values, dtype=np.float64) * exposure, coverage)
        show_image(ax, encode_srgb8(rgb)[0], title)
    import matplotlib.colors

    err_img = np.ma.masked_invalid(_image(err_px, coverage, np.nan))
    axes[2].set_facecolor("black")
    im = axes[2].imshow(err_img, cmap="magma", norm=matplotlib.colors.LogNorm(1e-3, 1.0), interpolation="nearest")
    axes[2].set_xticks([])
    axes[2].set_yticks([])
    axes[2].set_title("relative difference per pixel")
    top.colorbar(im, ax=axes[2], shrink=0.85, label="|split sum − MC| / MC")

    ax = bottom.subplots(1, 1)
    colours = series_colours(len(alphas), "viridis", 0.85)
    split_by_alpha = {}
    for (label, _), colour in zip(cfg["ibl_models"], colours, strict=True):
        pts = [p for p in points if p.case.startswith(label + " ·")]
        mc_pts = sorted((p for p in pts if p.method != "split sum"), key=lambda p: p.cost)
        ax.plot([p.seconds * 1e3 for p in mc_pts], [p.error for p in mc_pts], "o-", color=colour,
                label=f"Monte Carlo, {label}")  # fmt: skip
        for p in mc_pts:
            ax.annotate(f"{p.cost}", (p.seconds * 1e3, p.error), textcoords="offset points", xytext=(4, 4),
                        fontsize=9, color=colour)  # fmt: skip
        ss = next(p for p in pts if p.method == "split sum")
        split_by_alpha[label] = ss.error
        noisy = ss.reference_error > ss.error  # the reference cannot resolve this error: hollow
        ax.plot(ss.seconds * 1e3, ss.error, "*", ms=16, color=colour, mec=colour if noisy else "k",
                mfc="none" if noisy else colour, label=f"split sum, {label}")  # fmt: skip
    sh = next(p for p in points if p.method == "SH9 irradiance")
    ax.plot(sh.seconds * 1e3, sh.error, "s", ms=10, color=PALETTE[1], mec="k", label="SH9 irradiance (vs exact)")
    ax.axhline(1e-2, color="0.5", ls="--", lw=1.0)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(f"run time (ms) for {sh.reference.split('(times: ')[-1].rstrip(')')}")
    ax.set_ylabel("median relative error, lit pixels")
    ax.set_title(f"Error against run time under '{sky}' (numbers: samples per pixel; dashed: 1 %)")
    ax.grid(True, which="major")
    ax.legend(fontsize=10, ncol=2, loc="lower left")

    measured = {
        "alpha": alpha,
        "sky": sky,
        "median_error": float(np.median(errs)),
        "p95_error": float(np.percentile(errs, 95)),
        "reference_error": float(np.median(own)),
        "fast_ms": fast_ms,
        "mc_s": mc.seconds,
        "spp": mc.samples,
        "pixels": int(n.shape[0]),
        "ref_spp": cfg["ibl_reference_spp"],
        "sh9_error": sh.error,
        "split_by_alpha": split_by_alpha,
        "split_errors": ", ".join(f"{k} {e:.1%}" for k, e in split_by_alpha.items()),
    }
    return fig, measured

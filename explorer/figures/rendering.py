"""Figures for the rendering equation and the accuracy report.

Registered on import (see :mod:`explorer.figures.base`); drawn by :mod:`explorer.figures`.
"""

from __future__ import annotations

import csv
import math

import numpy as np

from lighting import CookTorrance, DirectionalLight, Lambert, Material
from lighting.integrate import outgoing_radiance
from lighting.lights.environment import LatLongEnvironment, SmallPatchEnvironment
from lighting.lights.skies import SKIES
from lighting.render.image import encode_srgb8
from lighting.render.renderer import AnalyticSphere, Renderer
from lighting.render.sphere import render_sphere, sphere_camera

from .base import PALETTE, new_figure, register, show_image

# Camera frame (x right, y up, z toward the viewer) → environment frame (z up): (x, y, z) ↦ (x, −z, y).
_CAM_TO_ENV = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])


def _sky(sun_env):
    """The engine's daylight sky (:data:`lighting.lights.skies.SKIES`) around ``sun_env``: radiance function."""
    return SKIES["daylight"].make(sun=sun_env)


def _sphere_frames(size):
    r = Renderer(AnalyticSphere(), sphere_camera(size))
    n_cam = np.asarray(r.sample_normals("phong"))
    return r, n_cam @ _CAM_TO_ENV.T, np.array([0.0, 0.0, 1.0]) @ _CAM_TO_ENV.T


def _image(r, values, fade=True):
    """Per-pixel values as an image, its silhouette pixels faded by their coverage of the disc.

    These spheres are computed at fewer pixels than they are shown with: without the fade their outline
    would show staircase steps.  (Display anti-aliasing only; the values inside are untouched.)
    """
    img = r.spread("phong", np.ascontiguousarray(values))
    if not fade:
        return img
    size = img.shape[0]
    c = np.arange(size) + 0.5 - size / 2
    d = np.hypot(c[:, None], c[None, :])
    cover = np.clip(size / 2 / 1.08 - d + 0.5, 0.0, 1.0)
    return img * cover[..., None]


@register(
    "rendering_equation",
    title="The rendering equation: full environment vs light at one point",
    caption=(
        "L_o(v) = ∫ f_r(v, l) L_i(l) (n·l) dω(l), integrated per pixel by the engine "
        "(lighting.integrate.outgoing_radiance, quadrature with {samples} nodes on the BRDF lobe, "
        "{patch_samples} on the patch). Top: a sphere lit by a full environment — a daylight sky with a bright "
        "sun glow, shown as a latitude–longitude map (θ "
        "from the zenith, φ around it) — light arrives from every direction. Bottom: the same sun as a small "
        "patch (Ω = {solid_angle:g} sr), black elsewhere: the integral becomes one term of the sum "
        "Σ_i f_r(v, l_i) L_i (n·l_i), and the picture matches a directional light of irradiance L Ω to "
        "{point_difference:.2%} of the brightest pixel. Left sphere: Lambert "
        "(k_d = {kd:g}); right: glossy metal (Cook–Torrance α = {alpha:g}, f0 = {f0_text})."
    ),
    slides="CMSC 435: Rendering equation; Rendering equation for point lights; Results",
    sun_cam=(-0.45, 0.55, 0.7),
    solid_angle=2e-3,
    patch_irradiance=2.5,
    kd=0.8,
    alpha=0.15,
    f0=(0.95, 0.8, 0.55),
)
def rendering_equation(q, *, sun_cam, solid_angle, patch_irradiance, kd, alpha, f0):
    """The rendering equation: a sphere under a full environment against light from one point.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    sun_cam : tuple
        Direction of the sun, in camera space.
    solid_angle : float
        Solid angle of the small patch light, in steradians.
    patch_irradiance : float
        Irradiance the patch delivers at normal incidence.
    kd : colour
        Diffuse albedo.
    alpha : float
        Cook–Torrance roughness.
    f0 : colour
        Reflectance at normal incidence.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    sun_cam = np.asarray(sun_cam, dtype=np.float64) / np.linalg.norm(sun_cam)
    sun_env = _CAM_TO_ENV @ sun_cam
    h = 48 if q.quick else 192
    env = LatLongEnvironment.from_function(_sky(sun_env), h)
    patch = SmallPatchEnvironment(sun_env, solid_angle, patch_irradiance / solid_angle)
    r, n_env, v_env = _sphere_frames(q.env_px)
    models = [("Lambert", Lambert(kd)), ("glossy metal", CookTorrance(1.0, alpha, f0))]
    rows = []
    # The patch is nearly uniform across its tiny cap: a few nodes on it are exact to display precision.
    for env_i, samples in ((env, q.env_samples), (patch, max(16, q.env_samples // 4))):
        imgs = []
        for _, m in models:
            lo = outgoing_radiance(m, env_i, n_env, v_env, method="quadrature", samples=samples)
            imgs.append((_image(r, lo), _image(r, lo, fade=False)))
        rows.append(imgs)
    # The point-light sum for the same sun: the engine's physical form, per pixel.
    sun = [DirectionalLight(sun_cam, intensity=patch_irradiance)]
    diffs = []
    for (_, m), (_, img) in zip(models, rows[1], strict=True):
        ref = render_sphere(Material(m, ambient=0.0), sun, size=q.env_px, form="physical")
        diffs.append(float(np.max(np.abs(img - ref)) / np.max(ref)))

    fig = new_figure(14.0, 8.6)
    gs = fig.add_gridspec(2, 3, width_ratios=[1.7, 1.0, 1.0])
    env_rgb = encode_srgb8(env.image)[0]
    dark = np.zeros_like(env_rgb)
    labels = ("Integrating the full environment", "Light at one point, black elsewhere")
    for i, (row, env_img) in enumerate(zip(rows, (env_rgb, dark), strict=True)):
        ax = fig.add_subplot(gs[i, 0])
        ax.imshow(env_img, extent=(0, 360, 180, 0), aspect="auto", interpolation="antialiased")
        ax.set_xticks(np.arange(0, 361, 90))
        ax.set_yticks(np.arange(0, 181, 45))
        ax.set_xlabel("φ (degrees)")
        ax.set_ylabel("θ from the zenith (degrees)")
        ax.set_title(labels[i], loc="left", fontsize=14.5)
        if i == 1:
            th = math.degrees(math.acos(sun_env[2]))
            ph = math.degrees(math.atan2(sun_env[1], sun_env[0])) % 360
            ax.plot(ph, th, "o", ms=4, color="white")
            ax.plot(ph, th, "o", ms=22, mfc="none", mec="#F0B400", mew=1.6)
            ax.annotate(f"Ω = {solid_angle:g} sr", (ph, th), xytext=(18, -14), textcoords="offset points",
                        color="#F0B400", fontsize=12.5)  # fmt: skip
        for j, ((img, _), (name, _)) in enumerate(zip(row, models, strict=True)):
            b = fig.add_subplot(gs[i, 1 + j])
            show_image(b, encode_srgb8(img)[0], name if i == 0 else None)
    return fig, {
        "samples": q.env_samples,
        "patch_samples": max(16, q.env_samples // 4),
        "solid_angle": solid_angle,
        "point_difference": max(diffs),
        "kd": kd,
        "alpha": alpha,
        "f0_text": ", ".join(f"{x:g}" for x in f0),
    }


# --------------------------------------------------------------------------- accuracy
def _read_points(path):
    """Points of an ``accuracy.csv`` written by ``lighting-explorer report accuracy``."""
    from lighting.validation.accuracy import Point

    pts = []
    with open(path, newline="", encoding="utf-8") as f:
        for row in csv.DictReader(f):
            pts.append(
                Point(
                    row["study"],
                    row["case"],
                    row["method"],
                    int(row["cost"]),
                    row["cost_unit"],
                    float(row["error"]),
                    float(row["error_spread"] or 0.0),
                    float(row["seconds"]),
                    row["reference"],
                )  # fmt: skip
            )
    return pts


_FLOOR = 1e-16  # exact zeros on a log axis


@register(
    "accuracy",
    title="Error against run time",
    caption=(
        "Error against run time wherever the engine trades accuracy for speed ({source}): hemisphere "
        "integration methods on four cases, area-light sample counts, flat / Gouraud / Phong interpolation "
        "by tessellation, float32 against float64. Each line is one method at increasing cost; shaded bands "
        "are ± one standard deviation over seeds for Monte Carlo methods; dashed and dotted lines mark 1 % and "
        "0.1 % error; exact zeros are drawn at 10⁻¹⁶. Times are medians on the machine that drew the figure."
    ),
    slides="Accuracy report (lighting-explorer report accuracy)",
    nondeterministic="plots measured wall-clock times, which differ from run to run (reproducible with --accuracy-csv)",
    csv=None,
)
def accuracy(q, *, csv):
    """Error against run time of the engine's approximations (measured now, or read from an accuracy.csv).

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    csv : str or None
        An ``accuracy.csv`` of ``lighting-explorer report accuracy``; ``None`` measures now.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    import matplotlib.ticker as mt

    if csv:
        points = _read_points(csv)
        source = "read from an accuracy.csv of lighting-explorer report accuracy"
    else:
        from lighting.validation.accuracy import run_studies

        points = [p for st in run_studies(quick=q.quick) for p in st.points]
        source = "measured while drawing, with the settings of lighting-explorer report accuracy" + (
            " --quick" if q.quick else ""
        )
    import textwrap

    panels = list(dict.fromkeys((p.study, p.case) for p in points))
    methods = list(dict.fromkeys(p.method for p in points))
    style = {m: (PALETTE[i % len(PALETTE)], "osD^vP*X<>"[i % 10]) for i, m in enumerate(methods)}
    cols = 4
    rows = (len(panels) + cols - 1) // cols
    fig = new_figure(16.0, 4.6 * rows)
    axes = fig.subplots(rows, cols, squeeze=False)
    for ax, (study, case) in zip(axes.flat, panels, strict=False):
        pts = [p for p in points if p.case == case and p.study == study]
        for m in dict.fromkeys(p.method for p in pts):
            mp = sorted((p for p in pts if p.method == m), key=lambda p: p.cost)
            t = np.array([p.seconds * 1e3 for p in mp])
            e = np.array([max(p.error, _FLOOR) for p in mp])
            c, mk = style[m]
            ax.plot(t, e, "-", marker=mk, ms=5, lw=1.6, color=c, label=m)
            spread = np.array([p.error_spread for p in mp])
            if np.any(spread > 0):
                lo = np.maximum(np.maximum(e - spread, e / 10), _FLOOR)
                ax.fill_between(t, lo, e + spread, color=c, alpha=0.15, lw=0)
        ax.axhline(1e-2, color="0.45", ls="--", lw=1.0)
        ax.axhline(1e-3, color="0.45", ls=":", lw=1.0)
        ax.set_xscale("log")
        ax.set_yscale("log")
        # At least a factor 4 of time on every axis, so a 1-2-5 tick always falls inside it.
        times = [p.seconds * 1e3 for p in pts]
        lo, hi = min(times) / 1.3, max(times) * 1.3
        if hi / lo < 4:
            mid = math.sqrt(lo * hi)
            lo, hi = mid / 2, mid * 2
        ax.set_xlim(lo, hi)
        ax.xaxis.set_major_locator(mt.LogLocator(base=10, subs=(1.0,) if hi / lo > 100 else (1.0, 2.0, 5.0)))
        ax.xaxis.set_major_formatter(mt.FuncFormatter(lambda x, _: f"{x:g}"))
        ax.xaxis.set_minor_formatter(mt.NullFormatter())
        ax.set_title("\n".join(textwrap.wrap(case, 32)), fontsize=12)
        ax.set_xlabel("time per evaluation (ms)", fontsize=12)
        ax.set_ylabel("relative error", fontsize=12)
        ax.grid(True, which="major")
        ax.legend(fontsize=9.5, loc="best", ncol=1 if len(set(p.method for p in pts)) < 5 else 2, frameon=True,
                  framealpha=0.85, edgecolor="none")  # fmt: skip
    for ax in list(axes.flat)[len(panels) :]:
        ax.axis("off")
    return fig, {"source": source, "points": len(points)}

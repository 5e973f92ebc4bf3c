"""The rendering equation: a sphere under a full environment against light from one point.

Registered on import (see :mod:`explorer.figures.base`); drawn by :mod:`explorer.figures`.
"""

from __future__ import annotations

import math

import numpy as np

from lighting import CookTorrance, DirectionalLight, Lambert, Material
from lighting.integrate import outgoing_radiance
from lighting.lights.environment import LatLongEnvironment, SmallPatchEnvironment, latlong_angles
from lighting.lights.skies import SKIES
from lighting.render.image import encode_srgb8
from lighting.render.renderer import AnalyticSphere, Renderer
from lighting.render.sphere import render_sphere, sphere_camera

from .base import new_figure, register, show_image

# Camera frame (x right, y up, z toward the viewer) → environment frame (z up): (x, y, z) ↦ (x, −z, y).
_CAM_TO_ENV = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])


def _sky(sun_env):
    """The engine's daylight sky (:data:`lighting.lights.skies.SKIES`) around ``sun_env``: radiance function."""
    return SKIES["daylight"].make(sun=sun_env)


#: Side of the integrated spheres at full resolution, in pixels.  A sphere fills about 440 pixels of the
#: 150-dpi figure and 280 of a 1280-pixel-wide slide; these smooth images, faded at the silhouette, show
#: no more at 256 pixels, which costs 1.8 times the integration.
SPHERE_PX = 192


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
    size="16:9",
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
    px = q.env_px if q.quick else SPHERE_PX
    r, n_env, v_env = _sphere_frames(px)
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
        ref = render_sphere(Material(m, ambient=0.0), sun, size=px, form="physical")
        diffs.append(float(np.max(np.abs(img - ref)) / np.max(ref)))

    fig = new_figure()
    gs = fig.add_gridspec(2, 3, width_ratios=[1.7, 1.0, 1.0])
    env_rgb = encode_srgb8(env.image)[0]
    dark = np.zeros_like(env_rgb)
    labels = ("Integrating the full environment", "Light at one point, black elsewhere")
    for i, (row, env_img) in enumerate(zip(rows, (env_rgb, dark), strict=True)):
        ax = fig.add_subplot(gs[i, 0])
        ax.imshow(env_img, extent=(0, 360, 180, 0), aspect="auto", interpolation="antialiased")
        # The image's columns run along a = (180° − φ) mod 360° (lighting.lights.environment.latlong_angles):
        # the ticks name the azimuth φ each column looks along.
        ax.set_xticks(np.arange(0, 361, 90), [f"{180 - a:g}" for a in range(0, 361, 90)])
        ax.set_yticks(np.arange(0, 181, 45))
        ax.set_xlabel("azimuth φ (degrees)")
        ax.set_ylabel("θ from the zenith (degrees)")
        ax.set_title(labels[i], loc="left", fontsize=14.5)
        if i == 1:
            th, col = (math.degrees(float(x)) for x in latlong_angles(sun_env))
            ax.plot(col, th, "o", ms=4, color="white")
            ax.plot(col, th, "o", ms=22, mfc="none", mec="#F0B400", mew=1.6)
            # The label on the side of the map's centre, so that it stays inside the map.
            side = 1 if col < 180 else -1
            ax.annotate(f"Ω = {solid_angle:g} sr", (col, th), xytext=(18 * side, -14), textcoords="offset points",
                        color="#F0B400", fontsize=12.5, ha="left" if side > 0 else "right")  # fmt: skip
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

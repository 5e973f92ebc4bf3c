"""The slides' concepts before any model: local vs global illumination, one point lit from several directions,
diffuse / glossy / specular, the micro-roughness of chalk, glossy reflectance around the mirror direction, the
BRDF as L_i → L_o, retro-reflection as the third part of a decomposed BRDF.

Every curve is the engine's (polar slices, the illumination equation, the models' ``eval``); the diagrams
only place arrows.  Registered on import (see :mod:`explorer.figures.base`); drawn by :mod:`explorer.figures`.
"""

from __future__ import annotations

import math

import numpy as np

from lighting import BlinnPhong, CookTorrance, DirectionalLight, Lambert, Material, Phong, PointLight, shade
from lighting.analysis import polar_slice
from lighting.models import BRDFFlags, model_class, model_names
from lighting.models.oren_nayar import OrenNayar
from lighting.render.image import encode_srgb8

from .base import PALETTE, VEC, new_figure, register, series_colours, show_image, sphere_rgb8, vector
from .brdf import _profile
from .models import _diagram_axes, _surface
from .zoo import half_disc

N = np.array([0.0, 0.0, 1.0])


def _light_ray(ax, theta_deg, length, *, color=VEC["l"], label=None, lw=2.4):
    """An incoming ray arriving at the origin from ``theta_deg`` (negative: from the left)."""
    t = math.radians(theta_deg)
    start = (length * math.sin(t), length * math.cos(t))
    vector(ax, start, (0.0, 0.0), color, lw=lw)
    if label:
        ax.text(start[0] * 1.08, start[1] * 1.08, label, color=color, fontsize=15, ha="center", va="center")


def _arrow(ax, start, end, color, *, lw=1.5, head=10):
    """A thin arrow with a head scaled for dense diagrams (``vector`` draws the slides' bold ones)."""
    from matplotlib.patches import FancyArrowPatch

    ax.add_patch(FancyArrowPatch(tuple(start), tuple(end), arrowstyle="-|>", mutation_scale=head, color=color, lw=lw,
                                 shrinkA=0, shrinkB=0, zorder=4))  # fmt: skip


def _delta_model():
    """The first registered delta model (the ideal mirror) at its defaults, or ``None`` if there is none."""
    for name in model_names():
        cls = model_class(name)
        if BRDFFlags.DELTA in cls.flags:
            return name, cls()
    return None


# --------------------------------------------------------------------------- local vs global
def _wall_grid(height, depth, cells):
    """Cell centres and areas of the wall ``x = 0``, ``0 <= y <= height``, ``|z| <= depth/2``.

    Both axes are graded toward the floor points' foot, ``y = height u²`` and ``z = ±(depth/2) w²``
    (midpoints in ``u`` and ``w``, ``dy = 2 height u du``): the floor next to the wall sees the wall's
    foot at close range, where a uniform grid would be too coarse.
    """
    u = (np.arange(cells) + 0.5) / cells
    ys, dy = height * u * u, 2.0 * height * u / cells
    half = cells // 2
    w = (np.arange(half) + 0.5) / half
    zs = np.concatenate([-(depth / 2) * w[::-1] ** 2, (depth / 2) * w**2])
    dz = np.concatenate([depth * w[::-1] / half, depth * w / half])
    y, z = np.meshgrid(ys, zs, indexing="ij")
    area = (dy[:, None] * dz[None, :]).reshape(-1)
    return np.stack([np.zeros_like(y), y, z], axis=-1).reshape(-1, 3), area


def _one_bounce(floor_pts, floor_mat, wall_pts, wall_L, cell_area, view):
    """Floor radiance from the wall's reflected light: Σ f_r(n_f, l, v) (n_f·l) L_w (n_w·(−l)) ΔA / r².

    The rendering equation with the wall as the only source, its solid angle summed cell by cell
    (dω = (n_w·(−l)) ΔA / r²); the floor's BRDF is the engine's.
    """
    d = wall_pts[None, :, :] - floor_pts[:, None, :]
    r2 = np.sum(d * d, axis=-1)
    l = d / np.sqrt(r2)[..., None]  # noqa: E741
    cos_w = np.maximum(-l[..., 0], 0.0)  # the wall's normal is +x
    f_cos = floor_mat.brdf.eval_cos(np.array([0.0, 1.0, 0.0]), l, view)
    return np.sum(f_cos * wall_L[None, :, :] * (cos_w / r2 * cell_area[None, :])[..., None], axis=1)


@register(
    "local_vs_global",
    size="16:9",
    title="Local vs global illumination",
    caption=(
        "Left: the paths of light. Local illumination follows light → surface → eye only (solid); global "
        "illumination adds the light that bounces between objects, here light → red wall → floor → eye (dashed). "
        "Right: the floor's radiance along the dotted line, computed by the engine: local (direct light only, "
        "the point light's inverse-square falloff), local + the slides' ambient hack I_a k_a (a constant, "
        "grey, here set to the bounce's mean), and global with one bounce off the wall, summed over the wall (a "
        "{cells}×{cells} grid; {grid_difference:.1g} relative change from a grid half as fine). The bounce is red "
        "(its colour ratios are the wall's albedo, {bounce_colour_ratio:.3f} = {wall_ratio:.3f}) and strongest "
        "at the wall's foot: {bounce_ratio_near:.0%} of the direct light there, {bounce_ratio_far:.1%} at the far "
        "end — the slides' 'ambient ~1 % of direct' is an average, and it has no direction and no colour bleeding."
    ),
    slides="CMSC 435: Local vs. global; Ambient illumination. UBC: Local vs. global illumination models",
    light=(1.2, 2.0, 0.0),
    intensity=6.0,
    floor_kd=0.7,
    wall_kd=(0.75, 0.12, 0.1),
    wall_height=2.2,
    wall_depth=4.0,
    x_max=3.0,
    cells=64,
)
def local_vs_global(q, *, light, intensity, floor_kd, wall_kd, wall_height, wall_depth, x_max, cells):
    """Local vs global illumination: a floor beside a red wall, direct light only against one bounce.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    light : tuple
        Position of the point light (x, y, z); the wall is the plane x = 0, the floor y = 0.
    intensity : float
        The light's intensity.
    floor_kd, wall_kd : colour
        Lambertian albedos of the floor and the wall.
    wall_height, wall_depth : float
        The wall's size.
    x_max : float
        The floor's extent from the wall.
    cells : int
        Wall cells per side.

    Returns
    -------
    tuple
        ``(figure, measured)``: bounce/direct ratios near and far from the wall, the bounce's colour
        ratio against the wall's albedo ratio, and the relative change from a grid half as fine.

    Notes
    -----
    The bounce is the rendering equation at a floor point with the wall as the only emitter,
    ``L_o = ∫ f_r L_w (n·l) dω`` and ``dω = cos θ_w dA / r²``; the wall's radiance is the engine's
    physical illumination equation ``f_r E (n·l)``.  Light reflected twice (floor → wall → floor) is left out.
    """
    pl = PointLight(light, intensity=intensity)
    floor_mat = Material(Lambert(floor_kd), ambient=0.0)
    wall_mat = Material(Lambert(wall_kd), ambient=0.0)
    xs = np.linspace(0.05, x_max, q.curve_n // 4 + 1)
    floor_pts = np.stack([xs, np.zeros_like(xs), np.zeros_like(xs)], axis=-1)
    view = np.array([1.0, 1.0, 0.0]) / math.sqrt(2.0)
    direct = shade(floor_pts, (0.0, 1.0, 0.0), floor_mat, [pl], view_dir=view, form="physical")

    def bounce(k):
        wall_pts, area = _wall_grid(wall_height, wall_depth, k)
        wall_L = shade(wall_pts, (1.0, 0.0, 0.0), wall_mat, [pl], view_dir=(1.0, 0.0, 0.0), form="physical")
        return _one_bounce(floor_pts, floor_mat, wall_pts, wall_L, area, view)

    b = bounce(cells)
    b_half = bounce(cells // 2)
    grid_diff = float(np.max(np.abs(b - b_half)) / np.max(np.abs(b)))
    # The slides' ambient term I_a k_a: one grey constant (here the bounce's mean), no direction, no colour.
    ambient = np.full(3, float(np.mean(b)))
    total = direct + b

    fig = new_figure()
    gs = fig.add_gridspec(2, 2, width_ratios=[1.15, 1.0], height_ratios=[1.0, 1.35])
    ax = fig.add_subplot(gs[:, 0])
    _diagram_axes(ax, (-0.5, 3.4), (-0.5, 3.0))
    from matplotlib.patches import Rectangle

    ax.add_patch(Rectangle((0.0, -0.1), 3.3, 0.1, color="0.55", lw=0))
    ax.add_patch(Rectangle((-0.12, 0.0), 0.12, wall_height, color=encode_srgb8(np.array([[wall_kd]]))[0][0, 0] / 255,
                           lw=0))  # fmt: skip
    ax.plot(light[0], light[1], marker="*", ms=26, color="#F0B400", mec="0.2", zorder=6)
    eye = np.array([3.1, 2.4])
    ax.text(eye[0], eye[1] + 0.16, "eye", ha="center", fontsize=13)
    ax.plot(*eye, marker="o", ms=9, color=VEC["v"])
    p_direct, p_floor, p_wall = np.array([2.1, 0.0]), np.array([0.8, 0.0]), np.array([0.0, 1.0])
    lp = np.array(light[:2])
    vector(ax, lp, p_direct, VEC["l"], lw=2.2)
    vector(ax, p_direct, eye, VEC["v"], lw=2.2)
    vector(ax, lp, p_wall, VEC["surface"], lw=2.0, ls="--")
    vector(ax, p_wall, p_floor, VEC["surface"], lw=2.0, ls="--")
    vector(ax, p_floor, eye, VEC["surface"], lw=2.0, ls="--")
    ax.plot([0.02, x_max], [0.03, 0.03], ls=":", color="0.2", lw=1.6)
    ax.text(1.65, 2.75, "local: light → surface → eye", color=VEC["l"], fontsize=13, ha="center")
    ax.text(1.65, 2.5, "global: light → wall → floor → eye", color=VEC["surface"], fontsize=13, ha="center")
    ax.text(1.5, -0.35, "floor (grey, Lambert)", ha="center", fontsize=12, color="0.3")
    ax.set_title("Paths of light")

    # The strips: the floor as the eye sees it, sRGB-encoded, one exposure for all three.
    sa = fig.add_subplot(gs[0, 1])
    rows = [direct, direct + ambient[None, :], total]
    strip = np.concatenate([np.repeat(r[None, :, :], 12, axis=0) for r in rows], axis=0)
    peak = float(np.max(total))
    img, _ = encode_srgb8(strip / peak)
    sa.imshow(img, aspect="auto", extent=(xs[0], xs[-1], 3, 0), interpolation="nearest")
    sa.set_yticks([0.5, 1.5, 2.5])
    sa.set_yticklabels(["local", "local + ambient", "global (1 bounce)"], fontsize=11.5)
    sa.set_xticks([])
    for s in sa.spines.values():
        s.set_visible(False)
    sa.set_title("The floor as the eye sees it (wall on the left)")

    pa = fig.add_subplot(gs[1, 1])
    pa.plot(xs, direct[:, 0], color="0.25", lw=2.2, label="local: every channel")
    pa.plot(xs, direct[:, 0] + ambient[0], color="0.5", ls="--", label="local + ambient (constant)")
    pa.plot(xs, total[:, 0], color="#C0392B", lw=2.2, label="global: red channel")
    pa.plot(xs, total[:, 2], color=PALETTE[0], lw=2.2, label="global: blue channel")
    pa.set_xlim(0, x_max)
    pa.set_ylim(0, 1.08 * float(np.max(total)))
    pa.set_xlabel("distance from the wall along the floor")
    pa.set_ylabel("floor radiance")
    pa.grid(True)
    pa.legend(loc="lower center", fontsize=11, ncol=2)
    ratio = b[:, 0] / direct[:, 0]
    kd = np.broadcast_to(np.asarray(wall_kd, dtype=np.float64), (3,))
    return fig, {
        "cells": cells,
        "grid_difference": grid_diff,
        "bounce_ratio_near": float(ratio[0]),
        "bounce_ratio_far": float(ratio[-1]),
        "bounce_colour_ratio": float(b[0, 2] / b[0, 0]),
        "wall_ratio": float(kd[2] / kd[0]),
        "bounce_colour_ratio_spread": float(np.max(np.abs(b[:, 2] / b[:, 0] - kd[2] / kd[0]))),
        "mean_bounce_over_direct": float(np.mean(b[:, 0]) / np.mean(direct[:, 0])),
    }


# --------------------------------------------------------------------------- one point, several directions
@register(
    "one_point_many_directions",
    size="16:9",
    title="One surface point lit from several directions",
    caption=(
        "Illuminate a surface point with a ray of light from different directions: how much light is reflected in "
        "each direction? Left: for each incoming direction (θ_l = {angles}°, arrows), the radiance reflected toward "
        "every view direction in the plane, f_r(l, v) E (n·l) for a unit irradiance E across the beam, from the "
        "engine (Lambert k_d = {kd:g} + Phong k_s = {ks:g}, e = {e:g}; one radial scale for all). Each lobe peaks "
        "at its mirror direction (measured {peaks}°) on a diffuse floor, and a grazing beam reflects less "
        "(it spreads over more surface: n·l). Right: the same surface on a sphere lit from each direction."
    ),
    slides="UBC: Materials (illuminate a surface point from different directions); Reflectance distribution model",
    angles_deg=(-15.0, -40.0, -65.0),
    kd=0.25,
    ks=0.5,
    e=40.0,
)
def one_point_many_directions(q, *, angles_deg, kd, ks, e):
    """One surface point lit from several directions, and the light it reflects into each direction.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    angles_deg : sequence of float
        The incoming directions, degrees from the normal (negative: from the left).
    kd, ks, e : float
        The surface: Lambert(kd) + Phong(ks, e).

    Returns
    -------
    tuple
        ``(figure, measured)``: each lobe's peak direction and value.
    """
    brdf = Lambert(kd) + Phong(ks, e)
    cols = series_colours(len(angles_deg), "plasma", 0.8)
    slices = [polar_slice(brdf, math.radians(abs(a)), n=q.polar_n, cosine=True, channel=0) for a in angles_deg]
    rmax = 1.1 * max(float(s.values.max()) for s in slices)
    fig = new_figure()
    gs = fig.add_gridspec(len(angles_deg), 2, width_ratios=[3.2, 1.0])
    ax = fig.add_subplot(gs[:, 0])
    half_disc(ax, rmax, ticks=3)
    peaks, values = [], []
    for a, s, c in zip(angles_deg, slices, cols, strict=True):
        x, y = s.xy.T
        ax.plot(x, y, color=c, lw=2.2)
        t = math.radians(a)
        vector(ax, (rmax * math.sin(t), rmax * math.cos(t)), (0, 0), c, lw=2.2)
        ax.text(1.05 * rmax * math.sin(t), 1.05 * rmax * math.cos(t), f"{abs(a):g}°", color=c, fontsize=13,
                ha="center", va="center")  # fmt: skip
        i = int(np.argmax(s.values))
        peaks.append(math.degrees(float(s.angles[i])))
        values.append(float(s.values[i]))
    _surface(ax, -rmax, rmax, thickness=0.03 * rmax)
    lo = r"$f_r(\mathbf{l}, \mathbf{v})\, E\, (\mathbf{n}\cdot\mathbf{l})$"
    ax.set_title(f"reflected radiance {lo}, one lobe per incoming direction", pad=16)
    for i, (a, c) in enumerate(zip(angles_deg, cols, strict=True)):
        sa = fig.add_subplot(gs[i, 1])
        t = math.radians(a)
        img = sphere_rgb8(Material(brdf, ambient=0.0), [DirectionalLight((math.sin(t), 0.0, math.cos(t)))],
                          q.sphere_px)  # fmt: skip
        show_image(sa, img)
        sa.set_ylabel(f"{abs(a):g}°", color=c, fontsize=14, rotation=0, labelpad=18, va="center")
    return fig, {
        "angles": ", ".join(f"{abs(a):g}" for a in angles_deg),
        "peaks": ", ".join(f"{p:.0f}" for p in peaks),
        "peak_angles_deg": peaks,
        "peak_values": values,
        "kd": kd,
        "ks": ks,
        "e": e,
    }


# --------------------------------------------------------------------------- diffuse / glossy / specular
@register(
    "diffuse_glossy_specular",
    size="16:9",
    title="Diffuse, glossy, specular",
    caption=(
        "The three basic reflectance behaviours for light at θ_l = {theta_deg:g}° (dotted), as polar plots of f_r "
        "(1/sr) from the engine: diffuse (top left; Lambert, k_d = {kd:g}: the constant {lambert_value:.3f} = k_d/π "
        "in every direction), glossy (top right; Cook–Torrance GGX, α = {alpha:g}: a lobe about the mirror direction, "
        "peak at {glossy_peak_deg:.0f}°) and specular (below; {mirror}: all reflected light leaves along R, a Dirac "
        "delta of weight R = {mirror_weight:.3g}, drawn as a spike δ)."
    ),
    slides="UBC: Materials — practical considerations: diffuse, glossy, specular; Physics of specular reflection",
    theta_deg=40.0,
    kd=0.8,
    alpha=0.2,
)
def diffuse_glossy_specular(q, *, theta_deg, kd, alpha):
    """Diffuse, glossy and specular reflection side by side.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    theta_deg : float
        The light's angle from the normal, in degrees.
    kd : float
        Lambert's albedo.
    alpha : float
        The glossy model's roughness (GGX, Smith, F = 1).

    Returns
    -------
    tuple
        ``(figure, measured)``: Lambert's constant value, the glossy lobe's peak angle, the mirror's weight.
    """
    th = math.radians(theta_deg)
    fig = new_figure()
    # Two lobes above, the delta below between them: each half disc as wide as half the slide.
    gs = fig.add_gridspec(2, 4)
    axes = [fig.add_subplot(gs[0, :2]), fig.add_subplot(gs[0, 2:]), fig.add_subplot(gs[1, 1:3])]
    lam = polar_slice(Lambert(kd), th, n=q.polar_n, channel=0)
    glossy = polar_slice(CookTorrance(1.0, alpha, 1.0, ndf="ggx", geometry="smith"), th, n=q.polar_n, channel=0)
    found = _delta_model()
    mirror_name, mirror = found if found else ("ideal mirror", None)
    weight = float(np.asarray(mirror.reflectance(math.cos(th)))[0]) if mirror is not None else 1.0
    measured = {"theta_deg": theta_deg, "kd": kd, "alpha": alpha, "mirror": mirror_name, "mirror_weight": weight}
    for ax, s, title, what in (
        (axes[0], lam, "diffuse", "equally in every direction"),
        (axes[1], glossy, "glossy", "spread about the mirror direction"),
        (axes[2], None, "specular", "all of it along R"),
    ):
        rmax = 1.15 * float(s.values.max()) if s is not None else 1.0
        half_disc(ax, rmax, label=s is not None)
        _light_line = (-rmax * math.sin(th), rmax * math.cos(th))
        ax.plot([0, _light_line[0]], [0, _light_line[1]], color=VEC["l"], ls=":", lw=1.8)
        ax.text(1.08 * _light_line[0], 1.08 * _light_line[1], "l", color=VEC["l"], fontsize=16, ha="center")
        if s is not None:
            x, y = s.xy.T
            ax.fill(x, y, color=PALETTE[0], alpha=0.2, lw=0)
            ax.plot(x, y, color=PALETTE[0], lw=2.2)
        else:
            tip = (0.95 * math.sin(th), 0.95 * math.cos(th))
            spike = {"arrowstyle": "-|>", "color": PALETTE[1], "lw": 3.0, "mutation_scale": 20}
            ax.annotate("", xy=tip, xytext=(0, 0), arrowprops=spike)
            ax.text(tip[0] + 0.08, tip[1] - 0.08, "δ", color=PALETTE[1], fontsize=22)
        ax.set_title(f"{title}: {what}", fontsize=14)
    measured["lambert_value"] = float(lam.values[len(lam.values) // 2])
    measured["glossy_peak_deg"] = math.degrees(float(glossy.angles[int(np.argmax(glossy.values))]))
    return fig, measured


# --------------------------------------------------------------------------- chalk
def _oren_nayar_pair(kd, sigma, th, n):
    on = polar_slice(OrenNayar(kd, sigma), th, n=n, channel=0)
    lam = polar_slice(Lambert(kd), th, n=n, channel=0)
    return on, lam


@register(
    "chalk_microroughness",
    size="16:9",
    title="Micro-roughness of a diffuse surface (chalk)",
    caption=(
        "Top: a very rough surface at the microscopic level (a random profile, seed {seed}): the local normals "
        "(black) point every way, so parallel incoming light (orange) is scattered by each facet about its own "
        "normal (blue fans), over the whole hemisphere — the ideal diffuse surface. Bottom: the difference this "
        "roughness makes (left: the two lobes; right: their ratio as the view sweeps), Oren–Nayar (Lambertian "
        "facets with slopes of σ = {sigma:g} rad) against Lambert with "
        "the same k_d, light at θ_l = {theta_deg:g}°: dimmer seen from above (ratio {ratio_normal:.3f} at θ_v = 0), "
        "brighter looking back toward the light ({ratio_back:.3f} at v = l): rough surfaces back-scatter, "
        "which is why the full moon looks flat."
    ),
    slides="UBC: Physics of diffuse reflection (chalk); Lambert's law",
    seed=5,
    sigma=0.5,
    kd=0.8,
    theta_deg=60.0,
    facets=16,
)
def chalk_microroughness(q, *, seed, sigma, kd, theta_deg, facets):
    """The micro-roughness of chalk and the Oren–Nayar vs Lambert difference it causes.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    seed : int
        Seed of the random profile.
    sigma : float
        The facets' slope spread (Oren–Nayar's σ, radians) and the profile's RMS slope.
    kd : float
        Albedo of the facets.
    theta_deg : float
        The light's angle from the normal, in degrees.
    facets : int
        Facets in the profile.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Oren–Nayar / Lambert ratio at normal view and at v = l.
    """
    rng = np.random.default_rng(seed)
    x, y = _profile(rng, facets, 0.5, math.tan(sigma))
    fig = new_figure()
    gs = fig.add_gridspec(2, 2, height_ratios=[1.0, 1.15], width_ratios=[1.2, 1.0])
    ax = fig.add_subplot(gs[0, :])
    ax2, ax3 = fig.add_subplot(gs[1, 0]), fig.add_subplot(gs[1, 1])
    ax.set_aspect("equal")
    ax.axis("off")
    ax.fill_between(x, y, y.min() - 0.5, color="0.86", lw=0)
    ax.plot(x, y, color="0.2", lw=2.0)
    t = math.radians(theta_deg)
    d_in = np.array([math.sin(t), -math.cos(t)])  # travelling down and to the right
    fan = np.radians(np.linspace(-75.0, 75.0, 7))
    for k in range(facets):
        mid = np.array([(x[k] + x[k + 1]) / 2, (y[k] + y[k + 1]) / 2])
        tangent = np.array([x[k + 1] - x[k], y[k + 1] - y[k]])
        nrm = np.array([-tangent[1], tangent[0]]) / np.hypot(*tangent)
        _arrow(ax, mid, mid + 0.42 * nrm, VEC["n"], lw=1.5)
        if k % 3 == 1 and nrm @ -d_in > 0.3:
            _arrow(ax, mid - 1.3 * d_in, mid, VEC["l"], lw=2.0, head=14)
            for a in fan:  # lengths ∝ cos: a Lambertian facet's radiant intensity about its own normal
                c, s_ = math.cos(a), math.sin(a)
                d = np.array([c * nrm[0] - s_ * nrm[1], s_ * nrm[0] + c * nrm[1]])
                _arrow(ax, mid, mid + 0.75 * c * d, VEC["v"], lw=1.2, head=7)
    ax.set_xlim(x[0] - 0.2, x[-1] + 0.2)
    ax.set_ylim(y.min() - 0.5, y.max() + 1.4)
    ax.text(x[0], y.max() + 1.25, "incoming light", color=VEC["l"], fontsize=13, va="top")
    ax.text(x[0] + 2.6, y.max() + 1.25, "local normals", color=VEC["n"], fontsize=13, va="top")
    ax.text(x[0] + 5.0, y.max() + 1.25, "light scattered by one facet (∝ cos about its normal)", color=VEC["v"],
            fontsize=13, va="top")  # fmt: skip
    ax.set_title("Chalk under a microscope: every facet scatters about its own normal")

    th = math.radians(theta_deg)
    on, lam = _oren_nayar_pair(kd, sigma, th, q.polar_n)
    rmax = 1.1 * max(float(on.values.max()), float(lam.values.max()))
    half_disc(ax2, rmax, ticks=2)
    ax2.plot(*lam.xy.T, color="0.35", lw=2.0, ls="--", label="Lambert")
    ax2.plot(*on.xy.T, color=PALETTE[1], lw=2.2, label=f"Oren–Nayar, σ = {sigma:g}")
    ax2.plot([0, -rmax * math.sin(th)], [0, rmax * math.cos(th)], color=VEC["l"], ls=":", lw=1.8)
    ax2.legend(loc="upper right", fontsize=11, bbox_to_anchor=(1.05, 1.12))
    ax2.set_title(f"$f_r$ (1/sr), light at {theta_deg:g}°", pad=18)

    # Each slice samples its own peak (Oren–Nayar's may be at the horizon's edge): Lambert read at its angles.
    lam_at = np.interp(on.angles, lam.angles, lam.values)
    ratio = on.values / np.where(lam_at > 0, lam_at, 1.0)
    deg = np.degrees(on.angles)
    keep = np.abs(deg) < 89.5
    ax3.plot(deg[keep], ratio[keep], color=PALETTE[1], lw=2.2)
    ax3.axhline(1.0, color="0.35", ls="--", lw=1.4)
    ax3.axvline(-theta_deg, color=VEC["l"], ls=":", lw=1.6)
    ax3.text(-theta_deg + 3, 0.62, "v = l", color=VEC["l"], fontsize=12)
    ax3.set_xlim(-90, 90)
    ax3.set_xticks([-90, -45, 0, 45, 90])
    ax3.set_xlabel(r"view angle $\theta_v$ (light on the left)")
    ax3.set_ylabel("Oren–Nayar / Lambert")
    ax3.set_ylim(0.55, 1.1 * float(ratio[keep].max()))
    ax3.grid(True)
    ax3.set_title("Oren–Nayar / Lambert, view swept")
    n_dir = np.array([[0.0, 0.0, 1.0]])
    l_dir = np.array([[-math.sin(th), 0.0, math.cos(th)]])
    on_m, lam_m = OrenNayar(kd, sigma), Lambert(kd)
    r_normal = float(on_m.eval(N, l_dir, n_dir)[0, 0] / lam_m.eval(N, l_dir, n_dir)[0, 0])
    r_back = float(on_m.eval(N, l_dir, l_dir)[0, 0] / lam_m.eval(N, l_dir, l_dir)[0, 0])
    return fig, {"seed": seed, "sigma": sigma, "theta_deg": theta_deg, "ratio_normal": r_normal, "ratio_back": r_back,
                 "ratio_max_deg": float(deg[keep][np.argmax(ratio[keep])])}  # fmt: skip


# --------------------------------------------------------------------------- glossy around the mirror
@register(
    "glossy_around_mirror",
    size="4:3",
    title="Glossy reflectance around the mirror direction",
    caption=(
        "Most light leaves near the mirror direction R (light at θ_l = {theta_deg:g}°), less as the angle from R "
        "grows; the falloff sharpens as the exponent grows (Phong, above) or the roughness shrinks (Cook–Torrance "
        "GGX with Smith G and F = 1, below). Each lobe is f_r (n·l) from the engine divided by its own peak. "
        "Phong's half-width at half maximum is arccos(2^(−1/e)) about R: measured {phong_hwhm} degrees. "
        "The rough microfacet lobes peak beyond R, toward grazing (the off-specular peak: {ct_peaks} degrees)."
    ),
    slides="UBC: Glossy reflectance; Empirical approximation (angular falloff). CMSC 435: Specular microfacets",
    theta_deg=45.0,
    exponents=(5.0, 20.0, 80.0, 320.0),
    alphas=(0.5, 0.3, 0.15, 0.05),
)
def glossy_around_mirror(q, *, theta_deg, exponents, alphas):
    """Glossy lobes around the mirror direction for growing exponents and shrinking roughness.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    theta_deg : float
        The light's angle from the normal, in degrees.
    exponents : sequence of float
        Phong exponents.
    alphas : sequence of float
        GGX roughness values.

    Returns
    -------
    tuple
        ``(figure, measured)``: Phong's measured half-widths and the Cook–Torrance peak angles.
    """
    th = math.radians(theta_deg)
    fig = new_figure()
    # One family per row, its legend to the right of its half disc (stacked, the two lobes fill a 4:3 slide).
    axes = fig.subplots(2, 1)
    out = {}
    for ax, family, params in ((axes[0], "phong", exponents), (axes[1], "ct", alphas)):
        half_disc(ax, 1.1, label=False)
        cols = series_colours(len(params))
        ax.plot([0, -1.1 * math.sin(th)], [0, 1.1 * math.cos(th)], color=VEC["l"], ls=":", lw=1.8)
        ax.text(-1.16 * math.sin(th), 1.16 * math.cos(th), "l", color=VEC["l"], fontsize=16, ha="center")
        vector(ax, (0, 0), (1.1 * math.sin(th), 1.1 * math.cos(th)), VEC["R_l"], None, lw=1.6, ls="--")
        ax.text(1.17 * math.sin(th), 1.17 * math.cos(th), "R", color=VEC["R_l"], fontsize=16, ha="center")
        hw, pk = [], []
        for p, c in zip(params, cols, strict=True):
            if family == "phong":
                brdf, lab = Phong(1.0, p), f"e = {p:g}"
            else:
                brdf, lab = CookTorrance(1.0, p, 1.0, ndf="ggx", geometry="smith"), f"α = {p:g}"
            s = polar_slice(brdf, th, n=q.polar_n, cosine=True, channel=0)
            v = s.values / float(s.values.max())
            ax.plot(v * np.sin(s.angles), v * np.cos(s.angles), color=c, lw=2.0, label=lab)
            i = int(np.argmax(v))
            pk.append(math.degrees(float(s.angles[i])))
            # Half width at half maximum on the far side of the peak, interpolated between samples.
            j = i + int(np.argmax(v[i:] < 0.5))
            a0, a1, v0, v1 = s.angles[j - 1], s.angles[j], v[j - 1], v[j]
            hw.append(math.degrees(float(a0 + (0.5 - v0) * (a1 - a0) / (v1 - v0) - s.angles[i])))
        ax.legend(loc="center left", fontsize=13, bbox_to_anchor=(1.0, 0.45), handlelength=1.6)
        ax.set_title("Phong: growing exponent e" if family == "phong" else "Cook–Torrance GGX: shrinking roughness α")
        if family == "phong":  # a lobe that peaks at the horizon has no far side: only Phong's are kept
            out["phong_half_widths_deg"] = hw
        out[f"{family}_peak_deg"] = pk
    out["phong_hwhm"] = ", ".join(f"{w:.1f}" for w in out["phong_half_widths_deg"])
    out["ct_peaks"] = ", ".join(f"{p:.0f}" for p in out["ct_peak_deg"])
    return fig, {"theta_deg": theta_deg, "exponents": list(exponents), "alphas": list(alphas), **out}


# --------------------------------------------------------------------------- the BRDF as L_i → L_o
def _cone_ratio(brdf, l, v, half_angle, nodes=12):  # noqa: E741
    """``L_o(v) / E_i`` for radiance 1 arriving inside a cone of ``half_angle`` about ``l``.

    Gauss–Legendre in the angle ψ from the cone's axis, uniform in its azimuth: ``E_i = ∫ (n·l') dω``
    and ``L_o = ∫ f_r(l', v) (n·l') dω`` (the engine's ``eval_cos``), ``dω = sin ψ dψ dφ``.
    """
    x, w = np.polynomial.legendre.leggauss(nodes)
    psi, wpsi = 0.5 * half_angle * (x + 1), 0.5 * half_angle * w
    phi = (np.arange(2 * nodes) + 0.5) * (2 * math.pi / (2 * nodes))
    a = np.cross(l, [0.0, 1.0, 0.0])
    a /= np.linalg.norm(a)
    b = np.cross(l, a)
    P, F = np.meshgrid(psi, phi, indexing="ij")
    dirs = np.cos(P)[..., None] * l + np.sin(P)[..., None] * (np.cos(F)[..., None] * a + np.sin(F)[..., None] * b)
    dw = (np.sin(P) * wpsi[:, None]) * (2 * math.pi / (2 * nodes))
    cos_l = dirs[..., 2]
    e_i = float(np.sum(cos_l * dw))
    l_o = float(np.sum(brdf.eval_cos(N, dirs, v)[..., 0] * dw))
    return l_o / e_i


@register(
    "brdf_li_to_lo",
    size="16:9",
    title="The BRDF: how much light reflects from L_i to L_o",
    caption=(
        "The BRDF is a ratio: light arrives from l in a narrow cone dω_i with radiance L_i, giving the surface "
        "the irradiance dE_i = L_i cos θ_i dω_i; the surface sends radiance dL_o(v) toward every view direction "
        "v. f_r(l, v) = dL_o(v) / dE_i (1/sr), drawn as the lobe (engine: Lambert k_d = {kd:g} + Cook–Torrance "
        "GGX α = {alpha:g}, light at {theta_l_deg:g}°). Right: the same ratio measured with finite cones of "
        "radiance 1 (the rendering equation integrated over the cone) approaches f_r(l, v) = {f_value:.4f} as the "
        "cone shrinks, the difference falling as the square of its half-angle (measured order {order:.2f})."
    ),
    slides="CMSC 435: BRDF (how much light reflects from L_i to L_o); Rendering equation for point lights",
    theta_l_deg=40.0,
    theta_v_deg=28.0,
    kd=0.2,
    alpha=0.3,
    half_angles_deg=(16.0, 8.0, 4.0, 2.0, 1.0),
)
def brdf_li_to_lo(q, *, theta_l_deg, theta_v_deg, kd, alpha, half_angles_deg):
    """The BRDF as the ratio of outgoing radiance to incoming irradiance, and its limit.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    theta_l_deg : float
        The light's angle from the normal (on the left), in degrees.
    theta_v_deg : float
        The marked view direction's angle from the normal (on the right), in degrees.
    kd, alpha : float
        The surface: Lambert(kd) + Cook–Torrance GGX (Smith, f0 = 0.9) of roughness alpha.
    half_angles_deg : sequence of float
        Half-angles of the incoming cones, in degrees.

    Returns
    -------
    tuple
        ``(figure, measured)``: ``f_r(l, v)``, the cone ratios' relative differences from it and the
        observed order of convergence.
    """
    brdf = Lambert(kd) + CookTorrance(1.0, alpha, 0.9, ndf="ggx", geometry="smith")
    th = math.radians(theta_l_deg)
    l3 = np.array([-math.sin(th), 0.0, math.cos(th)])
    tv = math.radians(theta_v_deg)
    v3 = np.array([math.sin(tv), 0.0, math.cos(tv)])
    f = float(brdf.eval(N, l3, v3)[0])
    diffs = [abs(_cone_ratio(brdf, l3, v3, math.radians(h)) / f - 1) for h in half_angles_deg]
    order = math.log(diffs[-2] / diffs[-1]) / math.log(half_angles_deg[-2] / half_angles_deg[-1])

    fig = new_figure()
    ax, ax2 = fig.subplots(1, 2, width_ratios=[2.2, 1.0])
    ax2.set_box_aspect(1.15)  # about as tall as the half disc beside it, not a tall strip
    s = polar_slice(brdf, th, n=q.polar_n, channel=0)
    rmax = 1.15 * float(s.values.max())
    half_disc(ax, rmax, label=True, ticks=3)
    x, y = s.xy.T
    ax.fill(x, y, color=PALETTE[0], alpha=0.18, lw=0)
    ax.plot(x, y, color=PALETTE[0], lw=2.2)
    from matplotlib.patches import Wedge

    cone = 8.0  # drawn wider than any measured cone, to be seen
    mid = 90.0 + theta_l_deg
    ax.add_patch(Wedge((0, 0), rmax, mid - cone, mid + cone, color="#F5C66B", alpha=0.6, lw=0, zorder=1))
    _arrow(ax, (0.98 * rmax * l3[0], 0.98 * rmax * l3[2]), (0, 0), VEC["l"], lw=2.4, head=18)
    ax.text(1.0 * rmax * l3[0] - 0.02 * rmax, 1.07 * rmax * l3[2], r"$L_i$ in $d\omega_i$", color=VEC["l"],
            fontsize=15, ha="right")  # fmt: skip
    _arrow(ax, (0, 0), (f * v3[0], f * v3[2]), VEC["v"], lw=2.4, head=18)
    ax.text(f * v3[0] + 0.03 * rmax, f * v3[2] + 0.05 * rmax, r"$dL_o(\mathbf{v})$", color=VEC["v"], fontsize=15)
    ax.text(-0.98 * rmax, 0.18 * rmax, r"$f_r(\mathbf{l},\mathbf{v}) = \dfrac{dL_o(\mathbf{v})}{dE_i(\mathbf{l})}$"
            "\n" r"$dE_i = L_i\,\cos\theta_i\,d\omega_i$", fontsize=16, ha="left", va="bottom")  # fmt: skip
    ax.set_title(r"How much light reflects from $L_i$ to $L_o$: the lobe is $f_r(\mathbf{l}, \cdot)$ (1/sr)")

    ax2.loglog(half_angles_deg, diffs, "o-", color=PALETTE[1], ms=7, label="finite cone: |ratio / f_r − 1|")
    ref = diffs[-1] * (np.asarray(half_angles_deg) / half_angles_deg[-1]) ** 2
    ax2.loglog(half_angles_deg, ref, color="0.5", ls="--", label="∝ (half-angle)²")
    ax2.set_xlabel("cone half-angle (degrees)")
    ax2.set_ylabel(r"relative difference from $f_r(\mathbf{l}, \mathbf{v})$")
    ax2.grid(True, which="both")
    ax2.legend(loc="upper left", fontsize=11)
    ax2.set_title(r"$L_o / E_i \to f_r$ as the cone shrinks")
    return fig, {"theta_l_deg": theta_l_deg, "kd": kd, "alpha": alpha, "f_value": f, "relative_differences": diffs,
                 "half_angles_deg": list(half_angles_deg), "order": order}  # fmt: skip


# --------------------------------------------------------------------------- retro-reflection
@register(
    "retro_reflection",
    size="16:9",
    title="Decomposing a BRDF: diffuse + specular + retro-reflection",
    caption=(
        "The third, less common part of a decomposed BRDF: retro-reflection, light sent back toward where it came "
        "from. Polar plots of f_r (1/sr, one scale for all) for light at θ_l = {theta_deg:g}° (dotted): the "
        "diffuse part (Oren–Nayar's constant term k_d A/π), the specular part (normalized Blinn–Phong, "
        "k_s = {ks:g}, e = {shininess:g}, about the mirror direction), and the retro-reflective part (Oren–Nayar's "
        "back-scatter term for rough facets, σ = {sigma:g}: zero on the mirror side, "
        "{retro_over_diffuse_at_l:.2f}× the diffuse part at v = l, growing toward the light's horizon); "
        "their sum is the model Oren–Nayar + Blinn–Phong "
        "(sum and parts agree to {sum_difference:.0e})."
    ),
    slides="CMSC 435: Decomposing BRDFs (diffuse, specular, others: retro-reflection)",
    theta_deg=60.0,
    kd=0.8,
    sigma=0.8,
    ks=0.06,
    shininess=40.0,
)
def retro_reflection(q, *, theta_deg, kd, sigma, ks, shininess):
    """Diffuse + specular + retro-reflective parts of one BRDF, and their sum.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    theta_deg : float
        The light's angle from the normal, in degrees.
    kd, sigma : float
        Oren–Nayar's albedo and facet slope spread (radians).
    ks, shininess : float
        The specular part: normalized Blinn–Phong.

    Returns
    -------
    tuple
        ``(figure, measured)``: the retro part's largest value on the mirror side (0), its ratio to the
        diffuse part at ``v = l``, its peak angle and the largest difference between the sum and the parts.

    Notes
    -----
    Oren–Nayar's qualitative model is ``k_d/π (A + B max(0, cos Δφ) sin α tan β)``.  Its value at
    ``v = n`` (``β = 0``) is the constant ``k_d A/π`` whatever ``l``: the diffuse part is read from the
    engine there, and the retro part is the model minus it.
    """
    th = math.radians(theta_deg)
    on = OrenNayar(kd, sigma)
    spec = BlinnPhong(ks, shininess, normalized=True)
    l3 = np.array([-math.sin(th), 0.0, math.cos(th)])
    diffuse = Lambert(math.pi * float(on.eval(N, l3, N)[0]))
    s_on = polar_slice(on, th, n=q.polar_n, channel=0, refine=False)
    s_d = polar_slice(diffuse, th, n=q.polar_n, channel=0, refine=False)
    s_s = polar_slice(spec, th, n=q.polar_n, channel=0, refine=False)
    s_sum = polar_slice(on + spec, th, n=q.polar_n, channel=0, refine=False)
    # One grid for all four (no refinement), so that the parts add sample by sample.
    retro = s_on.values - s_d.values
    parts = [("diffuse", s_d.values, PALETTE[0]), ("specular", s_s.values, PALETTE[1]),
             ("retro-reflection", retro, PALETTE[2]), ("sum", s_sum.values, "0.2")]  # fmt: skip
    rmax = 1.1 * float(s_sum.values.max())
    fig = new_figure()
    # The sum in two rows, read left to right and down: diffuse + specular / + retro-reflection = sum.
    gs = fig.add_gridspec(2, 4, width_ratios=[0.14, 1.0, 0.14, 1.0])
    axes = []
    for row, ops in ((0, ("", "+")), (1, ("+", "="))):
        for k, op in enumerate(ops):
            s_ax = fig.add_subplot(gs[row, 2 * k])
            s_ax.axis("off")
            s_ax.text(0.5, 0.4, op, fontsize=32, ha="center", va="center", transform=s_ax.transAxes)
            axes.append(fig.add_subplot(gs[row, 2 * k + 1]))
    ang = s_on.angles
    for ax, (title, vals, c) in zip(axes, parts, strict=True):
        half_disc(ax, rmax, ticks=2, label=title == "diffuse")
        x, y = vals * np.sin(ang), vals * np.cos(ang)
        ax.fill(x, y, color=c, alpha=0.2, lw=0)
        ax.plot(x, y, color=c, lw=2.2)
        ax.plot([0, rmax * l3[0]], [0, rmax * l3[2]], color=VEC["l"], ls=":", lw=1.8)
        ax.set_title(title, fontsize=14)
    i_l = int(np.argmin(np.abs(ang + th)))
    mirror_side = ang > 0
    v_l = l3[None, :]
    retro_at_l = float(on.eval(N, v_l, v_l)[0, 0] - diffuse.eval(N, v_l, v_l)[0, 0])
    return fig, {
        "theta_deg": theta_deg,
        "sigma": sigma,
        "ks": ks,
        "shininess": shininess,
        "kd": kd,
        "diffuse_value": float(s_d.values[len(ang) // 2]),
        "retro_mirror_side_max": float(np.max(retro[mirror_side])),
        "retro_over_diffuse_at_l": retro_at_l / float(diffuse.eval(N, v_l, v_l)[0, 0]),
        "retro_slice_at_l": float(retro[i_l]),
        "retro_peak_deg": math.degrees(float(ang[int(np.argmax(retro))])),
        "sum_difference": float(np.max(np.abs(s_d.values + s_s.values + retro - s_sum.values))),
    }

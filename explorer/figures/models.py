"""Figures for the reflectance models: Lambert's law, mirror geometry, Phong, Blinn–Phong.

Registered on import (see :mod:`explorer.figures.base`); drawn by :mod:`explorer.figures`.
"""

from __future__ import annotations

import math

import numpy as np

from lighting import AmbientLight, BlinnPhong, DirectionalLight, Lambert, Material, Phong, PointLight
from lighting.render.camera import Camera
from lighting.render.image import encode_srgb8
from lighting.render.mesh import TriangleMesh
from lighting.render.renderer import Renderer
from lighting.vec import halfway, reflect

from .base import PALETTE, VEC, angle_arc, new_figure, register, series_colours, show_image, sphere_rgb8, vector

N = np.array([0.0, 0.0, 1.0])


def _in_plane(theta_deg):
    """Unit directions in the x–z plane at signed angles from the normal ``+z`` (positive toward ``+x``)."""
    t = np.radians(np.asarray(theta_deg, dtype=np.float64))
    return np.stack([np.sin(t), np.zeros_like(t), np.cos(t)], axis=-1)


def _diagram_axes(ax, xlim, ylim):
    ax.set_aspect("equal")
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    ax.axis("off")


def _surface(ax, x0, x1, *, thickness=0.12):
    from matplotlib.patches import Rectangle

    ax.add_patch(Rectangle((x0, -thickness), x1 - x0, thickness, color=VEC["surface"], zorder=2, lw=0))


# --------------------------------------------------------------------------- Lambert
@register(
    "lambert_cosine_law",
    size="16:9",
    title="Lambert's cosine law",
    caption=(
        "Lambert's cosine law, E_θ = E cos θ. Left: a beam of cross-section A spreads over A / cos θ "
        "of the surface when it arrives at θ from the normal (here θ = {theta_deg:g}°, twice the area), so each "
        "unit of area receives cos θ as much light. Right: the engine's diffuse term k_d (n·l) for a unit "
        "light and k_d = 1 (dots) against cos θ (line); behind the surface (θ > 90°) it is 0, not negative."
    ),
    slides="UBC: Lambert's cosine law; Computing diffuse reflection",
    theta_deg=60.0,
)
def lambert_cosine_law(q, *, theta_deg):
    """Lambert's cosine law: the light a surface patch receives falls as cos θ.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    theta_deg : float
        The tilt of the light shown in the diagram, in degrees.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    from matplotlib.patches import Polygon

    fig = new_figure()
    ax, ax2 = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.5, 1.0]})
    ax2.set_box_aspect(1.05)
    _diagram_axes(ax, (-0.4, 8.0), (-1.1, 4.9))
    _surface(ax, -0.3, 7.9)
    beam = "#F5C66B"
    th = math.radians(theta_deg)
    for cx, t in ((1.0, 0.0), (6.2, th)):
        half = 0.5 / math.cos(t)  # footprint half-width of a beam of width 1
        d = np.array([-math.sin(t), math.cos(t)])  # toward the light (up and to the left)
        across = np.array([d[1], -d[0]])
        length = 4.6 if t == 0 else 3.6  # the tilted beam stays clear of the upright one
        foot = [np.array([cx - half, 0.0]), np.array([cx + half, 0.0])]
        top = [f + length * d for f in foot]
        ax.add_patch(Polygon([foot[0], foot[1], top[1], top[0]], closed=True, color=beam, alpha=0.55, lw=0, zorder=1))
        for s in (-0.3, 0.0, 0.3):
            start = np.array([cx, 0.0]) + s * across + (length - 0.2) * d
            vector(ax, start, start - 1.35 * d, VEC["l"], lw=1.8)
        bracket = {"arrowstyle": "|-|", "color": "0.2", "lw": 1.4, "shrinkA": 0, "shrinkB": 0}
        ax.annotate("", xy=(cx - half, -0.32), xytext=(cx + half, -0.32), arrowprops=bracket)
        vector(ax, (cx, 0.0), (cx, 1.6), VEC["n"], r"$\mathbf{n}$", label_offset=(0.22, 0.05), lw=2.2)
        if t > 0:
            angle_arc(ax, (cx, 0.0), 1.0, 90, 90 + theta_deg, VEC["l"], r"$\theta$", fontsize=17)
            ax.text(cx, -0.75, "area A / cos θ:  E cos θ", ha="center", va="center", fontsize=15)
        else:
            ax.text(cx, -0.75, "area A:  E", ha="center", va="center", fontsize=15)
    ax.set_title("The same beam, spread over more area")

    # Right: the engine's Lambert term against cos θ.
    deg = np.linspace(0.0, 120.0, q.curve_n)
    dots = np.arange(0.0, 120.0 + 1e-9, 7.5)
    lam = Lambert(1.0)
    eng = lam.classic(N, _in_plane(dots), N)[:, 0]
    ax2.plot(deg, np.maximum(np.cos(np.radians(deg)), 0), color=PALETTE[0], label="cos θ, clamped at 0")
    ax2.plot(dots, eng, "o", color=PALETTE[1], ms=7, label=r"engine: Lambert $k_d\,(\mathbf{n}\cdot\mathbf{l})$")
    ax2.axvline(90, color="0.6", ls=":", lw=1.2)
    ax2.text(92, 0.55, "light behind\nthe surface", fontsize=12, color="0.35", va="center")
    ax2.set_xlim(0, 120)
    ax2.set_ylim(-0.03, 1.08)
    ax2.set_xticks(np.arange(0, 121, 30))
    ax2.set_xlabel("angle of incidence θ between n and l (degrees)")
    ax2.set_ylabel(r"$I_{diffuse}\,/\,(k_d\,I_{light})$")
    ax2.grid(True)
    ax2.legend(loc="upper right")
    ax2.set_title(r"$I_{diffuse} = k_d\, I_{light}\, \max(\mathbf{n}\cdot\mathbf{l},\, 0)$")
    err = float(np.max(np.abs(eng - np.maximum(np.cos(np.radians(dots)), 0))))
    return fig, {"theta_deg": theta_deg, "max_abs_difference_from_cos": err}


@register(
    "lambert_sphere_angles",
    size="16:9",
    title="Lambertian sphere from several lighting angles",
    caption=(
        "A Lambertian sphere (k_d = {kd:g}, no ambient light) under a directional light at angle θ from the "
        "viewer, turning toward the top of the picture. Only the angle between n and l matters, so every "
        "picture is the same cosine falloff, moved: the brightest point is where n = l, and the terminator "
        "(n·l = 0) is a great circle 90° away. Angles from 0° to 90° cover every case up to symmetry. Last panel: "
        "the light directions seen from the side, the viewer on the right."
    ),
    slides="UBC: Diffuse lighting examples (Lambertian sphere from several lighting angles)",
    angles_deg=(0.0, 22.5, 45.0, 67.5, 90.0),
    kd=0.85,
)
def lambert_sphere_angles(q, *, angles_deg, kd):
    """A Lambertian sphere lit from several angles.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    angles_deg : sequence of float
        Light elevations, in degrees, one sphere each.
    kd : colour
        Diffuse albedo.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    fig = new_figure()
    cols = 3
    rows = -(-(len(angles_deg) + 1) // cols)  # the spheres, then the side view
    axes = fig.subplots(rows, cols).ravel()
    mat = Material(Lambert(kd))
    for ax, a in zip(axes, angles_deg, strict=False):
        t = math.radians(a)
        light = DirectionalLight((0.0, math.sin(t), math.cos(t)))
        show_image(ax, sphere_rgb8(mat, [light], q.sphere_px), f"θ = {a:g}°", fontsize=16)
    axes[0].set_title("θ = 0° (from the viewer)", fontsize=16)
    axes[len(angles_deg) - 1].set_title(f"θ = {angles_deg[-1]:g}° (from above)", fontsize=16)
    for ax in axes[len(angles_deg) + 1 :]:
        ax.axis("off")

    # The side view: the viewer looks along −z (from the right), the light turns from the viewer to the top.
    ax = axes[len(angles_deg)]
    _diagram_axes(ax, (-0.9, 2.4), (-1.15, 2.25))
    from matplotlib.patches import Circle

    ax.add_patch(Circle((0, 0), 0.55, color="0.8", ec="0.35", lw=1.2))
    for a in angles_deg:
        t = math.radians(a)
        d = np.array([math.cos(t), math.sin(t)])
        vector(ax, 1.75 * d, 0.62 * d, VEC["l"], lw=2.0)
        ax.text(*(1.98 * d), f"{a:g}°", color=VEC["l"], fontsize=13, ha="center", va="center")
    ax.text(0.75, -0.85, "the viewer is far to the right", fontsize=13, ha="center", va="center", color=VEC["v"])
    ax.set_title("light directions θ, side view", fontsize=16)
    return fig, {"kd": kd}


# --------------------------------------------------------------------------- mirror geometry
@register(
    "reflection_geometry",
    size="16:9",
    title="Mirror reflection and the important directions",
    caption=(
        "Left: perfect mirror reflection. The reflected ray r makes the same angle α with the normal as "
        "the light direction l; the dashed construction is r = 2 n (n·l) − l. Right: the vectors every "
        "model uses, computed by the engine (lighting.vec): n, l (toward the light), v (toward the viewer), "
        "h = (l + v)/|l + v|, R_l = 2 n (n·l) − l and R_v = 2 n (n·v) − v. Phong uses the angle φ "
        "between R_l and v, Blinn–Phong the angle θ_h between n and h; in the plane of incidence "
        "φ = 2 θ_h (here {phi_deg:.0f}° and {theta_h_deg:.0f}°)."
    ),
    slides="UBC: Physics of specular reflection; Blinn–Phong. CMSC 435: Important directions",
    alpha_deg=40.0,
    light_deg=-60.0,
    view_deg=30.0,
)
def reflection_geometry(q, *, alpha_deg, light_deg, view_deg):
    """Mirror reflection and the slides' vectors n, l, v, r and h.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    alpha_deg : float
        Angle of incidence α of the mirror diagram (l to n, and n to r), in degrees.
    light_deg : float
        Direction of l in the second diagram, in degrees from the normal (negative: to the left).
    view_deg : float
        Direction of v in the second diagram, in degrees from the normal.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    fig = new_figure()
    # Each diagram's width follows its data range, so that both are drawn at one scale, as tall as they fit.
    ax, ax2 = fig.subplots(1, 2, width_ratios=[4.8, 6.0])
    L = 2.6
    # Left: l, n, r in the plane (x right, y up).
    _diagram_axes(ax, (-2.4, 2.4), (-0.6, 3.3))
    _surface(ax, -2.3, 2.3)
    ln = _in_plane(-alpha_deg)
    r3 = reflect(ln, N)
    lp, rp = L * ln[[0, 2]], L * r3[[0, 2]]
    foot = np.array([0.0, L * float(ln @ N)])
    ax.plot([lp[0], foot[0], rp[0]], [lp[1], foot[1], rp[1]], ls="--", color="0.45", lw=1.5, zorder=2)
    vector(ax, (0, 0), lp, VEC["l"], r"$\mathbf{l}$", label_offset=(-0.2, 0.15))
    vector(ax, (0, 0), (0, 3.0), VEC["n"], r"$\mathbf{n}$", label_offset=(0.22, 0.0))
    vector(ax, (0, 0), rp, VEC["r"], r"$\mathbf{r}$", label_offset=(0.2, 0.15))
    ax.plot(*foot, "o", color="0.3", ms=5, zorder=5)
    ax.text(foot[0] + 0.12, foot[1] + 0.16, r"$(\mathbf{n}\cdot\mathbf{l})\,\mathbf{n}$", fontsize=14, color="0.3")
    angle_arc(ax, (0, 0), 0.85, 90, 90 + alpha_deg, VEC["l"], r"$\alpha$")
    angle_arc(ax, (0, 0), 0.85, 90 - alpha_deg, 90, VEC["r"], r"$\alpha$")
    ax.text(0, -0.45, r"$\mathbf{r} = 2\,\mathbf{n}\,(\mathbf{n}\cdot\mathbf{l}) - \mathbf{l}$", ha="center",
            va="center", fontsize=18)  # fmt: skip
    ax.set_title("Perfect mirror: angle in = angle out", fontsize=16)

    # Right: all the slide vectors for one light and one viewer.
    _diagram_axes(ax2, (-3.0, 3.0), (-0.6, 3.3))
    _surface(ax2, -2.9, 2.9)
    l3, v3 = _in_plane(light_deg), _in_plane(view_deg)
    h3 = halfway(l3, v3)
    rl3, rv3 = reflect(l3, N), reflect(v3, N)
    items = [
        (N, VEC["n"], r"$\mathbf{n}$", (0.2, 0.12)),
        (l3, VEC["l"], r"$\mathbf{l}$", (-0.15, 0.2)),
        (v3, VEC["v"], r"$\mathbf{v}$", (0.18, 0.18)),
        (h3, VEC["h"], r"$\mathbf{h}$", (-0.1, 0.25)),
        (rl3, VEC["R_l"], r"$\mathbf{R}_l$", (0.3, 0.1)),
        (rv3, VEC["R_v"], r"$\mathbf{R}_v$", (-0.3, 0.1)),
    ]
    for d, c, lab, off in items:
        p = L * d[[0, 2]]
        vector(ax2, (0, 0), p, c, lab, label_offset=off)

    def ang(d):
        return math.degrees(math.atan2(d[2], d[0]))

    angle_arc(ax2, (0, 0), 1.7, ang(v3), ang(rl3), VEC["R_l"], r"$\phi$", fontsize=16)
    angle_arc(ax2, (0, 0), 1.25, ang(h3), 90.0, VEC["h"], r"$\theta_h$", fontsize=15, label_radius=1.62)
    phi = math.degrees(math.acos(float(np.clip(rl3 @ v3, -1, 1))))
    th = math.degrees(math.acos(float(np.clip(h3 @ N, -1, 1))))
    ax2.text(0, -0.45, r"Phong: $(\mathbf{R}_l\cdot\mathbf{v})^e = \cos^e\phi$     Blinn–Phong: "
             r"$(\mathbf{n}\cdot\mathbf{h})^e = \cos^e\theta_h$", ha="center", va="center", fontsize=15)  # fmt: skip
    ax2.set_title("The important directions", fontsize=16)
    return fig, {"phi_deg": phi, "theta_h_deg": th}


# --------------------------------------------------------------------------- Phong
@register(
    "phong_falloff",
    size="16:9",
    title="Phong's angular falloff",
    caption=(
        "Phong lighting, I_specular = k_s I_light (cos φ)^n_s with φ the angle between the mirror "
        "direction r and the view direction v. Top: the engine's Phong term (light along the normal, "
        "viewer swept across the plane of incidence) for several exponents n_s; the highlight's half-width "
        "shrinks roughly as 1/√n_s. Bottom: a sphere with the same exponents (k_d = {kd}, k_s = {ks:g}, one "
        "directional light from the upper left, ambient {ambient:g})."
    ),
    slides="UBC: Empirical approximation (angular falloff); Phong lighting; Calculating Phong lighting",
    exponents=(1.0, 5.0, 20.0, 80.0, 320.0),
    kd=(0.55, 0.1, 0.08),
    ks=0.6,
    ambient=0.06,
    light=(-1.0, 1.0, 1.4),
)
def phong_falloff(q, *, exponents, kd, ks, ambient, light):
    """Phong's angular falloff cosᵉ α for several exponents, with rendered spheres.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    exponents : sequence of float
        The exponents e compared.
    kd : colour
        Diffuse albedo of the spheres.
    ks : float
        Specular coefficient.
    ambient : float
        Ambient intensity.
    light : tuple
        Direction of the directional light.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    fig = new_figure()
    gs = fig.add_gridspec(2, len(exponents), height_ratios=[1.25, 1.0])
    ax = fig.add_subplot(gs[0, :])
    cols = series_colours(len(exponents))
    phi = np.linspace(-90.0, 90.0, q.curve_n)
    widths = {}
    for e, c in zip(exponents, cols, strict=True):
        y = Phong(1.0, e).classic(N, N, _in_plane(phi))[:, 0]
        ax.plot(phi, y, color=c, label=f"$n_s$ = {e:g}")
        widths[f"half_width_deg_e{e:g}"] = math.degrees(math.acos(0.5 ** (1.0 / e)))
    ax.set_xlim(-90, 90)
    ax.set_ylim(0, 1.05)
    ax.set_xticks(np.arange(-90, 91, 30))
    ax.set_xlabel("angle φ between r and v (degrees)")
    ax.set_ylabel(r"$(\cos\phi)^{n_s}$")
    ax.grid(True)
    ax.legend(loc="upper right", ncol=1)
    ax.set_title(r"$I_{specular} = k_s\, I_{light}\, (\mathbf{v}\cdot\mathbf{r})^{n_s}$")
    lights = [AmbientLight(intensity=ambient), DirectionalLight(light)]
    for i, (e, c) in enumerate(zip(exponents, cols, strict=True)):
        a = fig.add_subplot(gs[1, i])
        mat = Material(Lambert(kd) + Phong(ks, e))
        show_image(a, sphere_rgb8(mat, lights, q.sphere_px), f"$n_s$ = {e:g}", color=c)
    return fig, {"kd": ", ".join(f"{x:g}" for x in kd), "ks": ks, "ambient": ambient, **widths}


def _floor_renderer(px_w, px_h):
    """A flat floor (y = 0) seen at a grazing angle: where Phong and Blinn–Phong highlights differ most."""
    v = np.array([[-40.0, 0, -80.0], [40.0, 0, -80.0], [40.0, 0, 5.0], [-40.0, 0, 5.0]])
    mesh = TriangleMesh(v, np.array([[0, 2, 1], [0, 3, 2]]), normals=np.tile([0.0, 1.0, 0.0], (4, 1)))
    cam = Camera((0.0, 1.0, 3.0), (0.0, 0.0, -6.0), fov_y_deg=30.0, width=px_w, height=px_h)
    return Renderer(mesh, cam, cull_backfaces=False)


@register(
    "phong_vs_blinn_phong",
    size="16:9",
    title="Phong vs Blinn–Phong highlights",
    caption=(
        "Phong, k_s (R_l·v)^e, against Blinn–Phong, k_s (n·h)^e, on a sphere lit from {sphere_light_deg:g}° "
        "off the view direction (top row) and on a floor seen at a grazing angle under a point light (bottom row), "
        "one column per model. "
        "Blinn–Phong with 4× the exponent ({e4:g}) gives about the same highlight where l, v and n are close "
        "(φ ≈ 2 θ_h); with the same exponent ({e:g}) its highlight is much larger. At grazing angles the "
        "Blinn–Phong highlight stretches along the direction toward the viewer, Phong's stays round."
    ),
    slides="UBC: Alternative model (Blinn–Phong). CMSC 435: Blinn–Phong",
    e=50.0,
    kd=(0.1, 0.22, 0.55),
    ks=0.7,
    sphere_light_deg=60.0,
    floor_kd=0.02,
    floor_light=(0.0, 2.0, -14.0),
    floor_light_intensity=60.0,
)
def phong_vs_blinn_phong(q, *, e, kd, ks, sphere_light_deg, floor_kd, floor_light, floor_light_intensity):
    """Phong against Blinn–Phong highlights, on a sphere and at grazing angles on a floor.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    e : float
        Phong exponent (Blinn–Phong uses 4e).
    kd : colour
        Diffuse albedo of the spheres.
    ks : float
        Specular coefficient.
    sphere_light_deg : float
        Light elevation over the spheres, in degrees.
    floor_kd : colour
        Diffuse albedo of the floor.
    floor_light : tuple
        Position of the floor's light.
    floor_light_intensity : float
        Intensity of the floor's light.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    rows = [
        (f"Phong, e = {e:g}", Phong(ks, e)),
        (f"Blinn–Phong, e = {4 * e:g}", BlinnPhong(ks, 4 * e)),
        (f"Blinn–Phong, e = {e:g}", BlinnPhong(ks, e)),
    ]
    fig = new_figure()
    # One column per model: the sphere above, the floor below (the floor image is 1.7 times as wide as tall).
    gs = fig.add_gridspec(2, len(rows), height_ratios=[1.0, 1.0 / 1.7])
    t = math.radians(sphere_light_deg)
    s_lights = [
        AmbientLight(intensity=0.05),
        DirectionalLight((-math.sin(t) * 0.7071, math.sin(t) * 0.7071, math.cos(t))),
    ]
    fw, fh = (int(round(q.sphere_px * 1.7)), q.sphere_px)
    floor = _floor_renderer(fw, fh)
    f_lights = [AmbientLight(intensity=0.02), PointLight(floor_light, intensity=floor_light_intensity)]
    for i, (label, spec) in enumerate(rows):
        mat = Material(Lambert(kd) + spec)
        a = fig.add_subplot(gs[0, i])
        show_image(a, sphere_rgb8(mat, s_lights, q.sphere_px))
        a.set_title(label, fontsize=16)
        b = fig.add_subplot(gs[1, i])
        img, _ = encode_srgb8(floor.render(Material(Lambert(floor_kd) + spec), f_lights))
        show_image(b, img)
        if i == 0:
            a.set_ylabel(f"sphere, light {sphere_light_deg:g}°\noff the view", fontsize=14)
            b.set_ylabel("floor at a grazing\nangle, point light", fontsize=14)
    return fig, {"sphere_light_deg": sphere_light_deg, "e": e, "e4": 4 * e}

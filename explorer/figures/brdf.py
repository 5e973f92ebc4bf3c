"""Figures for BRDFs: decomposition, polar slices, 3D lobes, reciprocity, microfacets, Cook–Torrance, plausibility.

Registered on import (see :mod:`explorer.figures.base`); drawn by :mod:`explorer.figures`.
"""

from __future__ import annotations

import math

import numpy as np

from lighting import AmbientLight, BlinnPhong, CookTorrance, Lambert, Material, Phong, PointLight
from lighting.analysis import lobe_mesh, polar_slice, reciprocity_pair
from lighting.models.brdf import Geometry
from lighting.models.fresnel import dielectric, schlick
from lighting.models.microfacet import beckmann_ndf, ggx_ndf, smith_g1_beckmann
from lighting.render.image import encode_srgb8
from lighting.render.renderer import AnalyticSphere, Renderer
from lighting.render.sphere import sphere_camera

from .base import PALETTE, VEC, equation_row, new_figure, register, series_colours, show_image
from .zoo import half_disc

_THETAS_DEG = (15.0, 35.0, 55.0)


def _models():
    """The deck's models at representative parameters (scalar coefficients: every channel alike)."""
    return [
        ("Lambert", Lambert(1.0), r"$k_d$ = 1"),
        ("Phong (the slides' BRDF)", Phong(1.0, 20.0), r"$k_s$ = 1, e = 20"),
        ("Blinn–Phong", BlinnPhong(1.0, 80.0), r"$k_s$ = 1, e = 80"),
        ("Blinn–Phong, normalized", BlinnPhong(1.0, 80.0, normalized=True), r"$k_s$ = 1, e = 80"),
        ("Cook–Torrance (Beckmann, V-cavity)", CookTorrance(1.0, 0.25, 1.0), "α = 0.25, F = 1 (f0 = 1)"),
        (
            "Cook–Torrance (GGX, Smith)",
            CookTorrance(1.0, 0.25, 1.0, ndf="ggx", geometry="smith"),
            "α = 0.25, F = 1 (f0 = 1)",
        ),  # fmt: skip
    ]


def _incidence_lines(ax, theta_deg, rmax, color, label=None):
    t = -math.radians(theta_deg)  # the fixed direction sits at −θ_in, on the left
    ax.plot([0, rmax * math.sin(t)], [0, rmax * math.cos(t)], color=color, ls=":", lw=1.6)
    if label:  # inside the disc, beside the line's outer end, on the side away from the normal
        d, side = np.array([math.sin(t), math.cos(t)]), np.array([-math.cos(t), math.sin(t)])
        ax.text(*(rmax * (0.8 * d + 0.1 * side)), label, color=color, fontsize=16, ha="center", va="center")


def _slice_axes(ax, rmax):
    """``ax`` as the upper half disc of radius ``rmax`` (normal up, mirror side right), with its angles and
    scale; returns the disc, to clip curves to: a Cartesian half disc fills its cell, a polar axes keeps a
    square box and leaves half of it empty."""
    from matplotlib.patches import Circle

    half_disc(ax, rmax, ticks=3, angles=True, scale_label=r"$f_r$ (1/sr)", fontsize=10.5)
    return Circle((0.0, 0.0), rmax, transform=ax.transData)


def _slice_plot(ax, s, disc, *, fill=None, **style):
    """A polar slice ``s`` on a half disc, clipped to the disc (a curve beyond the scale leaves the plot)."""
    x, y = s.xy.T
    if fill is not None:
        ax.fill(x, y, color=fill, alpha=0.2, lw=0, clip_path=disc)
    (line,) = ax.plot(x, y, **style)
    line.set_clip_path(disc)
    return line


# --------------------------------------------------------------------------- decomposition
@register(
    "brdf_decomposition",
    size="16:9",
    title="Decomposing a BRDF: diffuse + specular",
    caption=(
        "The usual breakdown of a BRDF, f_r = f_d + f_s, as polar plots of f_r (1/sr) for a light at "
        "{theta_deg:g}° (dotted; the normal points up): the diffuse part is view independent — a half-disc "
        "of radius k_d/π —, the specular part is a lobe around the mirror direction, and the sum is what a "
        "surface such as Lambert(k_d = {kd:g}) + Phong(k_s = {ks:g}, e = {e:g}) reflects. Below: the engine's "
        "spheres of the two parts and of the sum under one directional light {theta_deg:g}° from the viewer "
        "(upper left), one exposure for the three, the slides' classic terms k_d (n·l) and k_s (R_l·v)^e: the "
        "sum's image is the parts' images added (largest difference {sphere_sum_difference:.1e})."
    ),
    slides="CMSC 435: Decomposing BRDFs",
    theta_deg=40.0,
    kd=0.6,
    ks=0.5,
    e=30.0,
)
def brdf_decomposition(q, *, theta_deg, kd, ks, e):
    """Decomposing a BRDF: diffuse + specular, as polar slices (above) and the engine's spheres (below).

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    theta_deg : float
        Incidence angle of the light, in degrees.
    kd : float
        Diffuse coefficient.
    ks : float
        Specular coefficient.
    e : float
        Phong exponent.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    from lighting import DirectionalLight
    from lighting.render.sphere import render_sphere

    parts = [("diffuse  $f_d$", Lambert(kd)), ("specular  $f_s$", Phong(ks, e)), ("sum  $f_d + f_s$",
             Lambert(kd) + Phong(ks, e))]  # fmt: skip
    slices = [polar_slice(b, math.radians(theta_deg), n=q.polar_n, channel=0) for _, b in parts]
    rmax = 1.08 * max(float(s.values.max()) for s in slices)
    t = math.radians(theta_deg)
    light = DirectionalLight((-math.sin(t) * math.sqrt(0.5), math.sin(t) * math.sqrt(0.5), math.cos(t)))
    # A dim grey behind the spheres shows the outline of their unlit halves.
    images = [render_sphere(Material(b), [light], size=q.sphere_px, background=0.03) for _, b in parts]
    exposure = -math.log2(float(np.max(images[2])))  # the sum's brightest pixel at white; the parts alike
    fig = new_figure()
    gs = fig.add_gridspec(2, 1, height_ratios=[0.8, 1.0])
    axes = equation_row(fig, "+=", gap=0.12, subplotspec=gs[0])
    sphere_axes = equation_row(fig, "+=", gap=0.12, subplotspec=gs[1])
    terms = (r"$k_d\,(\mathbf{n}\cdot\mathbf{l})$", r"$k_s\,(\mathbf{R}_l\cdot\mathbf{v})^e$",
             r"$k_d\,(\mathbf{n}\cdot\mathbf{l}) + k_s\,(\mathbf{R}_l\cdot\mathbf{v})^e$")  # fmt: skip
    for ax, img, term in zip(sphere_axes, images, terms, strict=True):
        show_image(ax, encode_srgb8(img, exposure=exposure)[0], term, fontsize=14)
    for i, (ax, (title, _), s) in enumerate(zip(axes, parts, slices, strict=True)):
        disc = _slice_axes(ax, rmax)
        _slice_plot(ax, s, disc, fill=PALETTE[i], color=PALETTE[i])
        _incidence_lines(ax, theta_deg, rmax, VEC["l"], r"$\mathbf{l}$")
        ax.set_title(title, pad=2)
    plain = [render_sphere(Material(b), [light], size=q.sphere_px, background=0.0) for _, b in parts]
    difference = float(np.max(np.abs(plain[2] - plain[0] - plain[1])))
    return fig, {"theta_deg": theta_deg, "kd": kd, "ks": ks, "e": e, "sphere_sum_difference": difference,
                 "exposure_stops": exposure}  # fmt: skip


# --------------------------------------------------------------------------- polar plots
@register(
    "brdf_polar",
    size="16:9",
    title="BRDF polar plots (2D slices) of every model",
    caption=(
        "2D slices of each model: f_r (1/sr) for a fixed light direction (dotted, at θ_l = 15°, 35°, 55° from "
        "the normal, which points up) as the view direction sweeps the plane of incidence. Lambert is a half-"
        "disc; Phong and Blinn–Phong are lobes about the mirror direction (Phong's grows with 1/(n·l) as the "
        "light tilts — the slides' BRDF divides by n·l); normalized Blinn–Phong keeps its energy as it "
        "narrows; Cook–Torrance lobes (α = 0.25, F = 1) lean toward grazing, where 1/(4 (n·v)(n·l)) grows "
        "faster than shadowing removes. Each panel has its own radial scale."
    ),
    slides="UBC: BRDF measurements/plots (2D slice). CMSC 435: Plotting BRDFs",
    theta_deg=_THETAS_DEG,
)
def brdf_polar(q, *, theta_deg):
    """Polar slices of the lecture's models in the plane of incidence.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    theta_deg : float
        Incidence angle of the light, in degrees.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    models = _models()
    fig = new_figure()
    axes = fig.subplots(2, 3)
    cols = [PALETTE[0], PALETTE[2], PALETTE[1]]
    peaks = {}
    for ax, (name, brdf, params) in zip(axes.flat, models, strict=True):
        slices = [polar_slice(brdf, math.radians(t), n=q.polar_n, channel=0) for t in theta_deg]
        rmax = 1.1 * max(float(s.values.max()) for s in slices)
        disc = _slice_axes(ax, rmax)
        for t, s, c in zip(theta_deg, slices, cols, strict=True):
            _slice_plot(ax, s, disc, color=c, label=rf"light at $\theta_l$ = {t:g}°")
            _incidence_lines(ax, t, rmax, c)
        ax.set_title(f"{name}\n{params}", fontsize=13, pad=0)
        peaks[name] = float(rmax / 1.1)
    handles, labels = axes.flat[1].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=3)
    return fig, {"peak_values": peaks}


# --------------------------------------------------------------------------- 3D lobes
def _lobe_axes(ax, mesh, title):
    import matplotlib
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    v = mesh.vertices
    peak = float(mesh.values.max()) or 1.0
    face_val = mesh.values[mesh.faces].mean(axis=1) / peak
    colours = matplotlib.colormaps["viridis"](face_val)
    edges = colours.copy()
    edges[:, :3] *= 0.72  # a darker grid on the surface shows its shape without any lighting
    poly = Poly3DCollection(v[mesh.faces], facecolors=colours, edgecolors=edges, linewidths=0.3)
    ax.add_collection3d(poly)
    r = float(np.max(np.linalg.norm(v, axis=1))) or 1.0
    t = np.linspace(0, 2 * np.pi, 73)
    ax.plot(r * np.cos(t), r * np.sin(t), 0 * t, color="0.55", lw=1.0)
    ax.plot([-r, r], [0, 0], [0, 0], color="0.75", lw=0.8)
    ax.plot([0, 0], [0, 0], [0, 1.05 * r], color=VEC["n"], lw=1.6)
    ax.text(0, 0, 1.12 * r, r"$\mathbf{n}$", color=VEC["n"], fontsize=15, ha="center")
    ld = mesh.light
    ax.plot([0, ld[0] * r], [0, ld[1] * r], [0, ld[2] * r], color=VEC["l"], lw=2.2)
    ax.text(ld[0] * r * 1.12, ld[1] * r * 1.12, ld[2] * r * 1.12, r"$\mathbf{l}$", color=VEC["l"], fontsize=16,
            ha="center")  # fmt: skip
    ax.set_xlim(-r, r)
    ax.set_ylim(-r, r)
    ax.set_zlim(0, r)
    ax.set_box_aspect((2, 2, 1), zoom=1.3)
    ax.view_init(elev=16, azim=-68)
    ax.set_axis_off()
    ax.set_title(title, fontsize=12.5, pad=-6)
    return peak


@register(
    "brdf_lobes_3d",
    size="16:9",
    title="BRDF 3D lobe surfaces of every model",
    caption=(
        "The 3D surface plot of each BRDF for one light direction l (θ_l = {theta_deg:g}°): the distance "
        "from the centre in a view direction v is f_r(l, v), and the colour (viridis) is the same value "
        "relative to the lobe's peak. The grey circle is the surface, n its normal. Meshes from "
        "lighting.analysis.lobe_mesh, whose grid follows narrow lobes; each panel has its own scale."
    ),
    slides="UBC: BRDF measurements/plots (3D surface). CMSC 435: Diffuse; Phong; Cook–Torrance; Blinn–Phong",
    theta_deg=45.0,
)
def brdf_lobes_3d(q, *, theta_deg):
    """3D lobe surfaces of the lecture's models.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    theta_deg : float
        Incidence angle of the light, in degrees.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    import matplotlib
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    t = math.radians(theta_deg)
    light = (-math.sin(t), 0.0, math.cos(t))
    fig = new_figure()
    axes = fig.subplots(2, 3, subplot_kw={"projection": "3d"})
    peaks = {}
    for ax, (name, brdf, params) in zip(axes.flat, _models(), strict=True):
        mesh = lobe_mesh(brdf, light, resolution=q.lobe_resolution)
        peak = _lobe_axes(ax, mesh, "")
        ax.set_title(f"{name}\n{params}; peak {peak:.3g}/sr", fontsize=12.5)
        peaks[name] = peak
    sm = ScalarMappable(norm=Normalize(0, 1), cmap=matplotlib.colormaps["viridis"])
    fig.colorbar(sm, ax=axes, shrink=0.55, label=r"$f_r$ / peak", pad=0.01, aspect=30)
    return fig, {"theta_deg": theta_deg, "peak_values": peaks}


# --------------------------------------------------------------------------- reciprocity
@register(
    "reciprocity",
    size="16:9",
    title="Reciprocity: swapping view and light",
    caption=(
        "The two polar plots of a BRDF: for one light direction showing view directions (solid), and for one "
        "view direction showing light directions (dashed), both fixed at {theta_deg:g}° (dotted). A reciprocal "
        "BRDF, f_r(l, v) = f_r(v, l), gives the same curve both ways: normalized Blinn–Phong (top right, "
        "largest relative difference {bp_difference:.1e}). The slides' Phong BRDF k_s (R_l·v)^e / (π (n·l)) "
        "does not (top left): dividing by n·l breaks reciprocity, and the two slices differ by exactly the factor "
        "(n·v)/(n·l) (bottom: measured ratio against that formula), and its dashed curve climbs again toward "
        "the horizon, where 1/(n·l) grows without bound."
    ),
    slides="CMSC 435: Physically plausible BRDF (reciprocity); Plotting BRDFs; Phong (non-physical)",
    theta_deg=50.0,
    phong_e=20.0,
    blinn_e=80.0,
)
def reciprocity(q, *, theta_deg, phong_e, blinn_e):
    """Reciprocity: swapping view and light, for the Phong and the Blinn–Phong BRDFs.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    theta_deg : float
        Incidence angle, in degrees.
    phong_e : float
        Phong exponent.
    blinn_e : float
        Blinn–Phong exponent.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    th = math.radians(theta_deg)
    cases = [
        (f"Phong BRDF, e = {phong_e:g}", Phong(1.0, phong_e)),
        (f"Blinn–Phong normalized, e = {blinn_e:g}", BlinnPhong(1.0, blinn_e, normalized=True)),
    ]
    fig = new_figure()
    # The two slices side by side, as large as the slide's height allows; their ratio across the bottom.
    gs = fig.add_gridspec(2, 2, height_ratios=[1.25, 1.0])
    measured = {}
    ratios = []
    for i, (title, brdf) in enumerate(cases):
        a, b = reciprocity_pair(brdf, th, n=q.polar_n, channel=0)
        ax = fig.add_subplot(gs[0, i])
        # The scale comes from the slices away from the last degree above the horizon: there the Phong
        # BRDF's 1/(n·l) grows without bound, and the slice (which samples its peak) reaches it; the
        # dashed curve leaves the plot there instead of shrinking every lobe to a dot.
        inner = np.abs(a.angles) <= math.radians(89.0)
        scale = max(float(a.values[inner].max()), float(b.values[inner].max()))
        rmax = 1.1 * scale
        disc = _slice_axes(ax, rmax)
        _slice_plot(ax, a, disc, color=PALETTE[0], label="light fixed, view swept")
        _slice_plot(ax, b, disc, color=PALETTE[1], ls="--", label="view fixed, light swept")
        _incidence_lines(ax, theta_deg, rmax, "0.4")
        ax.set_title(title, pad=2)
        big = np.maximum(a.values, b.values)
        ok = big > 1e-6 * scale
        rel = float(np.max(np.abs(a.values - b.values)[ok] / big[ok]))
        measured["phong_difference" if i == 0 else "bp_difference"] = rel
        measured["phong_plot_scale" if i == 0 else "bp_plot_scale"] = scale
        ratios.append((a, b, ok))
        if i == 0:
            fig.legend(loc="outside upper center", ncol=2)
    ax = fig.add_subplot(gs[1, :])
    t_deg = np.degrees(ratios[0][0].angles)
    formula = np.cos(ratios[0][0].angles) / math.cos(th)
    ax.plot(t_deg, formula, color="0.3", lw=1.4, label=r"$(\mathbf{n}\cdot\mathbf{v})/(\mathbf{n}\cdot\mathbf{l})$")
    for (a, b, ok), c, lab in zip(ratios, (PALETTE[3], PALETTE[2]), ("Phong", "Blinn–Phong normalized"),
                                  strict=True):  # fmt: skip
        keep = ok & (b.values > 0)
        step = max(1, int(keep.sum() // 40))
        x = np.degrees(a.angles[keep])[::step]
        y = (a.values[keep] / b.values[keep])[::step]
        ax.plot(x, y, "o", color=c, ms=5, label=lab)
        measured["phong_ratio_points" if lab == "Phong" else "bp_ratio_points"] = int(len(x))
    ph = ratios[0]
    keep = ph[2] & (ph[1].values > 0)
    dev = np.abs(ph[0].values[keep] / ph[1].values[keep] / formula[keep] - 1)
    measured["phong_ratio_error"] = float(dev.max())
    ax.set_xlim(-90, 90)
    ax.set_xticks(np.arange(-90, 91, 30))
    ax.set_ylim(0, 1.7)
    ax.set_xlabel("swept direction (degrees from n)")
    ax.set_ylabel("light-fixed / view-fixed")
    ax.grid(True)
    ax.legend(loc="lower center", fontsize=11)
    ax.set_title("Ratio of the two slices")
    return fig, {"theta_deg": theta_deg, **measured}


# --------------------------------------------------------------------------- microfacets
def _profile(rng, count, width, sigma):
    slopes = rng.normal(0.0, sigma, count)
    x = np.arange(count + 1) * width
    y = np.concatenate([[0.0], np.cumsum(slopes * width)])
    y -= np.polyval(np.polyfit(x, y, 1), x)  # no overall tilt: the macro normal is +y
    return x, y


def _blocked(x, y, i, p, d):
    """Whether the ray from point ``p`` (on segment ``i``) in direction ``d`` hits another segment; and where."""
    best, hit = math.inf, None
    for j in range(len(x) - 1):
        if j == i:
            continue
        a = np.array([x[j], y[j]])
        e = np.array([x[j + 1] - x[j], y[j + 1] - y[j]])
        m = np.array([[d[0], -e[0]], [d[1], -e[1]]])
        det = np.linalg.det(m)
        if abs(det) < 1e-12:
            continue
        t, s = np.linalg.solve(m, a - p)
        if t > 1e-9 and 0 <= s <= 1 and t < best:
            best, hit = t, p + t * d
    return hit


@register(
    "microfacets",
    size="16:9",
    title="Specular microfacets: normal distribution, shadowing, masking",
    caption=(
        "A rough surface as random mirrored microfacets (a 2D profile with Gaussian slopes, σ = {sigma:g}, "
        "seed {seed}), light from {light_deg:g}° on the left, viewer at {view_deg:g}° on the right. Only "
        "facets whose normal is the half vector h reflect l into v (green): how many there are is the normal "
        "distribution D(h). Some of them receive no light — another facet is in the way (shadowing) — or "
        "cannot be seen from v (masking); the geometry term G is the fraction left. Below, right: the facets' slope "
        "distribution against the Gaussian it was drawn from (Beckmann's model: Gaussian slopes)."
    ),
    slides="CMSC 435: Specular microfacets (NDF, shadowing, masking); Cook–Torrance (Beckmann)",
    seed=14,
    sigma=0.55,
    light_deg=-72.0,
    view_deg=55.0,
    facets=34,
    tolerance_deg=6.0,
)
def microfacets(q, *, seed, sigma, light_deg, view_deg, facets, tolerance_deg):
    """Specular microfacets: a random rough profile, the facets that reflect l into v, shadowing and masking.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    seed : int
        Seed of the random profile.
    sigma : float
        RMS slope of the profile.
    light_deg : float
        Direction of l, in degrees from the normal.
    view_deg : float
        Direction of v, in degrees from the normal.
    facets : int
        Number of facets.
    tolerance_deg : float
        How close to h a facet normal must be to count, in degrees.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    from matplotlib.collections import LineCollection

    rng = np.random.default_rng(seed)
    x, y = _profile(rng, facets, 0.5, sigma)
    y = y - y.min() + 0.4
    lt = math.radians(light_deg)
    vt = math.radians(view_deg)
    ld = np.array([math.sin(lt), math.cos(lt)])
    vd = np.array([math.sin(vt), math.cos(vt)])
    h = (ld + vd) / np.linalg.norm(ld + vd)
    segs, kinds = [], []
    examples = {"reflect": [], "shadow": [], "mask": []}
    for i in range(facets):
        p0, p1 = np.array([x[i], y[i]]), np.array([x[i + 1], y[i + 1]])
        e = p1 - p0
        m = np.array([-e[1], e[0]]) / np.linalg.norm(e)
        mid = 0.5 * (p0 + p1)
        lit = m @ ld > 0 and _blocked(x, y, i, mid, ld) is None
        seen = m @ vd > 0 and _blocked(x, y, i, mid, vd) is None
        aligned = math.degrees(math.acos(float(np.clip(m @ h, -1, 1)))) < tolerance_deg
        segs.append([p0, p1])
        if aligned and lit and seen:
            kinds.append("reflect")
        elif aligned and not lit:
            kinds.append("shadow")
        elif aligned and not seen:
            kinds.append("mask")
        else:
            kinds.append("other")
        if kinds[-1] in examples:
            examples[kinds[-1]].append((i, mid))

    fig = new_figure()
    # The profile across the slide; below it, the key to its colours and the slope histogram.
    gs = fig.add_gridspec(2, 2, height_ratios=[1.55, 1.0], width_ratios=[1.0, 1.25])
    ax = fig.add_subplot(gs[0, :])
    ax.fill_between(x, 0, y, color="0.88", lw=0)
    colour = {"reflect": PALETTE[2], "shadow": "0.35", "mask": PALETTE[3], "other": "0.1"}
    width = {"reflect": 4.5, "shadow": 4.5, "mask": 4.5, "other": 1.6}
    ax.add_collection(LineCollection(segs, colors=[colour[k] for k in kinds], linewidths=[width[k] for k in kinds],
                                     capstyle="round"))  # fmt: skip
    L = 3.2
    for _, mid in examples["reflect"]:
        ax.annotate("", xy=mid, xytext=mid + L * ld, arrowprops={"arrowstyle": "-|>", "color": VEC["l"], "lw": 1.6})
        ax.annotate("", xy=mid + L * vd, xytext=mid, arrowprops={"arrowstyle": "-|>", "color": VEC["v"], "lw": 1.6})
    for i, mid in examples["shadow"][:2]:
        hit = _blocked(x, y, i, mid, ld)
        ax.annotate("", xy=hit, xytext=hit + min(L, (hit[0] + 0.1) / -ld[0] if ld[0] < 0 else L) * ld,
                    arrowprops={"arrowstyle": "-|>", "color": VEC["l"], "lw": 1.6, "ls": "--"})  # fmt: skip
        ax.plot([hit[0], mid[0]], [hit[1], mid[1]], color="0.45", ls=":", lw=1.4)
        ax.text(hit[0] + 0.3, hit[1] + 0.85, "shadowing", fontsize=12.5, ha="center", color="0.25",
                bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.8, "pad": 1})  # fmt: skip
    for i, mid in examples["mask"][:2]:
        hit = _blocked(x, y, i, mid, vd)
        ax.plot([mid[0], hit[0]], [mid[1], hit[1]], color=VEC["v"], ls="--", lw=1.6)
        ax.plot(*hit, marker="x", color=VEC["v"], ms=9, mew=2)
        ax.text(mid[0], mid[1] - 0.3, "masking", fontsize=12.5, ha="center", va="top", color=PALETTE[3])
    # The macro frame and the directions, drawn once at the left.
    o = np.array([1.6, y.max() + 2.0])
    for d, c, lab in ((np.array([0.0, 1.0]), VEC["n"], "n"), (ld, VEC["l"], "l"), (vd, VEC["v"], "v"),
                      (h, VEC["h"], "h")):  # fmt: skip
        ax.annotate("", xy=o + 1.1 * d, xytext=o, arrowprops={"arrowstyle": "-|>", "color": c, "lw": 2.2})
        ax.text(*(o + 1.32 * d), lab, color=c, fontsize=15, ha="right" if lab == "h" else "center", va="center",
                fontweight="bold")  # fmt: skip
    handles = [
        __import__("matplotlib.lines", fromlist=["Line2D"]).Line2D([], [], color=colour[k], lw=4.5, label=lab)
        for k, lab in (
            ("reflect", "normal = h: reflects l into v"),
            ("shadow", "normal = h, but in shadow"),
            ("mask", "normal = h, but masked"),
        )  # fmt: skip
    ]
    key = fig.add_subplot(gs[1, 0])
    key.axis("off")
    key.legend(handles=handles, loc="center", fontsize=13, title="the thick facets", title_fontsize=13)
    ax.set_xlim(-0.2, x[-1] + 0.2)
    ax.set_ylim(0, y.max() + 3.4)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title("Random mirrored microfacets")

    # Right: the slope distribution of a long profile from the same generator.
    big = _profile(np.random.default_rng(seed + 1), 4000 if q.quick else 40000, 0.5, sigma)
    slopes = np.diff(big[1]) / 0.5
    b = fig.add_subplot(gs[1, 1])
    b.hist(slopes, bins=41, range=(-2, 2), density=True, color=PALETTE[5], alpha=0.75, label="facets")
    s = np.linspace(-2, 2, 201)
    b.plot(s, np.exp(-0.5 * (s / sigma) ** 2) / (sigma * math.sqrt(2 * math.pi)), color=PALETTE[0],
           label=f"Gaussian, σ = {sigma:g}")  # fmt: skip
    b.set_xlabel("facet slope (tan of its tilt)")
    b.set_ylabel("probability density")
    b.set_title("Distribution of facet normals")
    b.legend(loc="upper left", fontsize=11)
    b.set_ylim(0, 1.05 / (sigma * math.sqrt(2 * math.pi)) * 1.25)
    b.grid(True)
    counts = {k: kinds.count(k) for k in ("reflect", "shadow", "mask")}
    return fig, {"sigma": sigma, "seed": seed, "light_deg": abs(light_deg), "view_deg": view_deg, "counts": counts}


# --------------------------------------------------------------------------- Cook–Torrance
_ALPHAS = (0.1, 0.2, 0.35, 0.6)


@register(
    "cook_torrance_terms",
    size="16:9",
    title="Cook–Torrance: D, G and F over roughness",
    caption=(
        "The three factors of Cook–Torrance, f_r = D G F / (4 (n·v)(n·l)), over roughness α. D: the normal "
        "distribution against the half-vector angle — Beckmann (solid, Gaussian slopes, the slides') and GGX "
        "(dashed, longer tails); narrower and taller as α falls (log scale). G: masking of one direction "
        "against its angle from the normal — Smith's for Beckmann (solid) and the slides' V-cavity for a light "
        "along n (black dashed: 1 until 60°, then 2 cos θ). F: Schlick's approximation against the angle "
        "between v and h for several f0, and the exact dielectric formula for glass (η = 1.5, dashed). "
        "Together: f_r in the plane of incidence for a light at {theta_deg:g}° (Beckmann, V-cavity, Schlick "
        "f0 = {f0:g}), on a log scale: the highlight widens and dims as α grows."
    ),
    slides="CMSC 435: Specular microfacets; Cook–Torrance (Beckmann distribution, V-shaped microfacets, Fresnel)",
    alphas=_ALPHAS,
    theta_deg=45.0,
    f0=0.04,
)
def cook_torrance_terms(q, *, alphas, theta_deg, f0):
    """Cook–Torrance's D, G and F over roughness.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    alphas : sequence of float
        Roughness values α.
    theta_deg : float
        Incidence angle, in degrees.
    f0 : float
        Reflectance at normal incidence.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    cols = series_colours(len(alphas))
    fig = new_figure()
    axes = fig.subplots(2, 2)
    (ad, ag), (af, ar) = axes
    deg = np.linspace(0.0, 89.5, q.curve_n)
    c = np.cos(np.radians(deg))
    for a, col in zip(alphas, cols, strict=True):
        ad.plot(deg, beckmann_ndf(c, a), color=col, label=f"α = {a:g}")
        ad.plot(deg, ggx_ndf(c, a), color=col, ls="--", lw=1.5)
        ag.plot(deg, smith_g1_beckmann(c, a), color=col, label=f"α = {a:g}")
    ag.plot(deg, np.minimum(1.0, 2.0 * c), color="k", ls="--", lw=1.6, label="V-cavity (l = n)")
    ad.set_yscale("log")
    ad.set_ylim(1e-3, 60)
    ad.set_xlabel(r"half-vector angle $\theta_h$ (degrees)")
    ad.set_ylabel("D (1/sr)")
    ad.set_title("D: normal distribution (solid Beckmann, dashed GGX)")
    ad.legend(loc="upper right")
    ag.set_ylim(0, 1.05)
    ag.set_xlabel("angle of v (or l) from n (degrees)")
    ag.set_ylabel(r"$G_1$")
    ag.set_title("G: shadowing and masking")
    ag.legend(loc="lower left")
    for f, col in zip((0.04, 0.2, 0.5, 0.9), series_colours(4, "cividis"), strict=True):
        af.plot(deg, schlick(c, f), color=col, label=f"Schlick, f0 = {f:g}")
    af.plot(deg, dielectric(c, 1.5), color=PALETTE[1], ls="--", label="exact, glass η = 1.5")
    af.set_ylim(0, 1.02)
    af.set_xlabel(r"angle between v and h (degrees)")
    af.set_ylabel("F")
    af.set_title("F: Fresnel reflectance")
    af.legend(loc="upper left")
    for ax in (ad, ag, af):
        ax.set_xlim(0, 90)
        ax.set_xticks(np.arange(0, 91, 15))
        ax.grid(True)
    th = math.radians(theta_deg)
    for a, col in zip(alphas, cols, strict=True):
        s = polar_slice(CookTorrance(1.0, a, f0), th, n=q.polar_n, channel=0)
        keep = s.values > 0
        ar.plot(np.degrees(s.angles[keep]), s.values[keep], color=col, label=f"α = {a:g}")
    ar.axvline(theta_deg, color=VEC["r"], ls=":", lw=1.4)
    ar.text(theta_deg + 1.5, 2e-4, "mirror\ndirection", color=VEC["r"], fontsize=11)
    ar.set_yscale("log")
    ar.set_ylim(1e-4, 10)
    ar.set_xlim(-90, 90)
    ar.set_xticks(np.arange(-90, 91, 30))
    ar.set_xlabel("view direction in the plane of incidence (degrees from n)")
    ar.set_ylabel(r"$f_r$ (1/sr)")
    ar.set_title(r"Together: $f_r = DGF\,/\,(4\,(\mathbf{n}\cdot\mathbf{v})(\mathbf{n}\cdot\mathbf{l}))$")
    ar.grid(True)
    ar.legend(loc="upper left")
    return fig, {"theta_deg": theta_deg, "f0": f0}


@register(
    "cook_torrance_spheres",
    size="4:3",
    title="Cook–Torrance on a sphere: D, G and the result over roughness",
    caption=(
        "Cook–Torrance's factors on a sphere, per pixel, for a point light at the upper left. Rows: roughness "
        "α = {alpha_list}. D (Beckmann, log colour scale) makes the highlight: small and intense when smooth, "
        "broad and faint when rough. G (V-cavity) darkens where n turns away from l or v, the same for every α. "
        "F (Schlick, f0 = {f0:g}) depends only on v·h, which hardly changes here: it stays between {f_lo:.4f} "
        "and {f_hi:.4f} over the sphere (it grows only at grazing v·h). Together, k_s D G F / (4 (n·v)(n·l)) "
        "× π (n·l): the specular term of the illumination equation (log scale). Right: the rendered sphere, "
        "Lambert (k_d = {kd_text}) + Cook–Torrance, one exposure for every row. Black: below the horizon of "
        "l or v, where f_r = 0."
    ),
    slides="CMSC 435: Cook–Torrance; Specular microfacets",
    alphas=(0.1, 0.25, 0.5),
    f0=0.04,
    kd=(0.25, 0.06, 0.05),
    light=((-2.2, 1.8, 1.6), 12.0),
)
def cook_torrance_spheres(q, *, alphas, f0, kd, light):
    """Cook–Torrance on a sphere: D, G and the result over roughness.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    alphas : sequence of float
        Roughness values α, one row each.
    f0 : float
        Reflectance at normal incidence.
    kd : colour
        Diffuse albedo added under the specular lobe.
    light : tuple
        Direction of the directional light.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    import matplotlib
    from matplotlib.colors import LogNorm, Normalize
    from matplotlib.patches import Circle

    size = q.sphere_px
    r = Renderer(AnalyticSphere(), sphere_camera(size))
    pts = r.sample_points("phong")
    n = r.sample_normals("phong")
    v = np.broadcast_to(r.sample_view("phong")[0], n.shape)
    lp = np.asarray(light[0], dtype=np.float64)
    ldir = lp - pts
    ldir = ldir / np.linalg.norm(ldir, axis=-1, keepdims=True)
    g = Geometry(n, ldir, v, unit=True)
    above = np.asarray(g.above)
    cov = r.gbuffer.coverage

    def image(values):
        vals = np.where(above, np.asarray(values, dtype=np.float64), np.nan)
        out = r.spread("phong", np.repeat(vals[:, None], 3, axis=1))[..., 0]
        return np.where(cov, out, np.nan)

    lights = [AmbientLight(intensity=0.05), PointLight(light[0], intensity=light[1])]
    # π f_r (n·l) E for the light's irradiance E at each point: the specular term of the slides' equation.
    e = light[1] / np.sum((lp - pts) ** 2, axis=-1)
    rows = []
    f_all = []
    for a in alphas:
        ct = CookTorrance(1.0, a, f0)
        f_all.append(np.asarray(ct.F(g))[above, 0])
        spec = np.asarray(ct.classic_geometry(g))[:, 0] * e
        rendered = r.render(Material(Lambert(kd) + ct), lights)
        rows.append((a, image(ct.D(g)), image(ct.G(g)), image(spec), rendered))
    f_all = np.concatenate(f_all)
    peak = max(float(np.nanmax(x[4])) for x in rows)
    exposure = -math.log2(peak) if peak > 0 else 0.0
    dmax = max(float(np.nanmax(x[1])) for x in rows)
    smax = max(float(np.nanmax(x[3])) for x in rows)
    norms = [LogNorm(vmin=dmax * 1e-4, vmax=dmax), Normalize(0.0, 1.0), LogNorm(vmin=smax * 1e-4, vmax=smax)]
    cmaps = ["magma", "viridis", "magma"]
    fig = new_figure()
    gs = fig.add_gridspec(len(alphas) + 1, 4, height_ratios=[1.0] * len(alphas) + [0.06])
    titles = ("D (Beckmann), 1/sr", "G (V-cavity)", r"specular term $\pi f_r (\mathbf{n}\cdot\mathbf{l}) E$",
              "rendered")  # fmt: skip
    for i, (a, d, gg, sp, rendered) in enumerate(rows):
        for j, (img, norm, cm) in enumerate(zip((d, gg, sp), norms, cmaps, strict=True)):
            ax = fig.add_subplot(gs[i, j])
            cmap = matplotlib.colormaps[cm].with_extremes(bad="black", under=matplotlib.colormaps[cm](0.0))
            im = ax.imshow(img, cmap=cmap, norm=norm, interpolation="antialiased")
            # The sphere's outline: its unlit half is black like the background.
            ax.add_patch(Circle(((size - 1) / 2, (size - 1) / 2), size / 2 / 1.08, fill=False, ec="0.45", lw=0.8))
            ax.set_xticks([])
            ax.set_yticks([])
            for sp_ in ax.spines.values():
                sp_.set_visible(False)
            if i == 0:
                ax.set_title(titles[j], fontsize=13.5)
            if j == 0:
                ax.set_ylabel(f"α = {a:g}", fontsize=15)
            if i == len(alphas) - 1:
                fig.colorbar(im, cax=fig.add_subplot(gs[-1, j]), orientation="horizontal")
        ax = fig.add_subplot(gs[i, 3])
        show_image(ax, encode_srgb8(rendered, exposure=exposure)[0], titles[3] if i == 0 else None, fontsize=13.5)
    return fig, {
        "alpha_list": ", ".join(f"{a:g}" for a in alphas),
        "f0": f0,
        "kd_text": ", ".join(f"{x:g}" for x in kd),
        "exposure_stops": exposure,
        "f_lo": float(f_all.min()),
        "f_hi": float(f_all.max()),
    }

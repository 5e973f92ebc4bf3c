"""Figures for lights, the illumination equation, and shading interpolation.

Registered on import (see :mod:`explorer.figures.base`); drawn by :mod:`explorer.figures`.
"""

from __future__ import annotations

import math

import numpy as np

from lighting import (
    AmbientLight,
    DirectionalLight,
    Lambert,
    Material,
    Phong,
    PointLight,
    RectLight,
    SpotLight,
    shade,
)
from lighting.analysis.machband import edge_jump_metric, luminance, scanline_profile
from lighting.render.camera import Camera
from lighting.render.image import encode_srgb8
from lighting.render.mesh import TriangleMesh, uv_sphere
from lighting.render.renderer import AnalyticSphere, Renderer
from lighting.render.sphere import sphere_camera
from lighting.scene import SceneRenderer, example_path, load_scene

from .base import PALETTE, VEC, equation_row, new_figure, register, show_image, sphere_rgb8, vector


def _floor_points(x):
    """Points on the floor ``y = 0`` along ``x`` (the plane ``z = 0``), normals ``+y``."""
    p = np.stack([x, np.zeros_like(x), np.zeros_like(x)], axis=-1)
    return p, np.array([0.0, 1.0, 0.0])


def _diffuse_on_floor(light, x):
    """``k_d (n·l) E`` with ``k_d = 1`` along the floor: the classic diffuse term (no ambient)."""
    p, n = _floor_points(x)
    return shade(p, n, Material(Lambert(1.0), ambient=0.0), [light], view_dir=(0.0, 1.0, 0.0), terms=("diffuse",))[:, 0]


# --------------------------------------------------------------------------- light is linear
@register(
    "light_is_linear",
    size="16:9",
    title="Light is linear",
    caption=(
        "Light is linear: the picture under two lights is the sum of the pictures under each. A sphere "
        "(Lambert + Phong) under a warm light from the left, under a cool light from the right, and under "
        "both; the engine's image under both equals the sum of the two images to {max_difference:.1e}. Below: the "
        "luminance along the middle row of each image (dashed line), and the sum of the first two (dots) on the "
        "third."
    ),
    slides="UBC: Materials (last bit): light is linear",
    warm=((-1.0, 0.6, 0.8), (1.0, 0.75, 0.45)),
    cool=((1.0, 0.2, 0.7), (0.35, 0.55, 1.0)),
)
def light_is_linear(q, *, warm, cool):
    """Light is linear: the image under two lights is the sum of the images under each.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    warm : tuple
        ``(direction, colour)`` of the warm directional light.
    cool : tuple
        ``(direction, colour)`` of the cool directional light.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    mat = Material(Lambert(0.75) + Phong(0.35, 30.0))
    a = [DirectionalLight(warm[0], color=warm[1])]
    b = [DirectionalLight(cool[0], color=cool[1])]
    from lighting.render.sphere import render_sphere

    ia, ib, iab = (render_sphere(mat, lts, size=q.sphere_px) for lts in (a, b, a + b))
    diff = float(np.max(np.abs(ia + ib - iab)))
    fig = new_figure()
    gs = fig.add_gridspec(2, 1, height_ratios=[1.6, 1.0])
    axes = equation_row(fig, "+=", subplotspec=gs[0])
    row = q.sphere_px // 2
    names = ("warm light from the left", "cool light from the right", "both lights")
    colours = (PALETTE[4], PALETTE[0], "0.15")
    for ax, img, title in zip(axes, (ia, ib, iab), names, strict=True):
        show_image(ax, encode_srgb8(img)[0], title, fontsize=15)
        ax.axhline(row, color="white", lw=1.0, ls="--", alpha=0.6)
    # The middle row of each image: the third curve is the sum of the first two, pixel by pixel.
    pa = fig.add_subplot(gs[1])
    cols = np.arange(q.sphere_px)
    for img, title, c in zip((ia, ib, iab), names, colours, strict=True):
        pa.plot(cols, luminance(img[row]), color=c, lw=2.2, label=title)
    step = max(1, q.sphere_px // 40)
    pa.plot(cols[::step], luminance(ia[row] + ib[row])[::step], "o", color=PALETTE[1], ms=5,
            label="warm + cool, added")  # fmt: skip
    pa.set_xlim(0, q.sphere_px - 1)
    pa.set_ylim(0, None)
    pa.set_xlabel("pixel column along the middle row")
    pa.set_ylabel("luminance (linear)")
    pa.grid(True)
    pa.legend(loc="center left", bbox_to_anchor=(1.0, 0.5))
    return fig, {"max_difference": diff}


# --------------------------------------------------------------------------- light sources
def _source_panel(ax, kind, light, xs):
    """Rays from ``light`` to the floor, on the x scale of the plot below (heights drawn a little compressed)."""
    from matplotlib.patches import Polygon, Rectangle

    ax.set_xlim(-4.0, 4.0)
    ax.set_ylim(-0.35, 3.2)
    ax.axis("off")
    ax.add_patch(Rectangle((-4.0, -0.12), 8.0, 0.12, color=VEC["surface"], lw=0))
    ray = {"color": VEC["l"], "lw": 1.5}
    if kind == "point":
        src = light.position[[0, 1]]
        for x in xs:
            vector(ax, src, (x, 0.02), VEC["l"], lw=1.5)
        ax.plot(*src, marker="*", ms=24, color="#F0B400", mec="0.2", zorder=6)
    elif kind == "directional":
        d = light.direction[[0, 1]]
        shift = 3.0 * d[0] / d[1]  # keep every ray's start inside the panel
        for x in np.linspace(xs[0] - 0.4, xs[-1] - shift + 0.4, len(xs)):
            start = np.array([x, 0.0]) + d * (3.0 / d[1])
            vector(ax, start, (x, 0.02), VEC["l"], lw=1.5)
    elif kind == "area":
        c = light.center[[0, 1]]
        half = 0.5 * light.edge_u[0]
        ax.plot([c[0] - half, c[0] + half], [c[1], c[1]], color="#F0B400", lw=7, solid_capstyle="butt", zorder=6)
        for sx in (c[0] - half * 0.8, c[0], c[0] + half * 0.8):
            for x in xs[::2]:
                ax.plot([sx, x], [c[1], 0.02], alpha=0.35, **ray)
    else:  # spot
        src = light.position[[0, 1]]
        axis = light.direction[[0, 1]]
        half = math.radians(light.cutoff_deg)
        edges = []
        for s in (-1, 1):
            c, sn = math.cos(s * half), math.sin(s * half)
            d = np.array([c * axis[0] - sn * axis[1], sn * axis[0] + c * axis[1]])
            t = -src[1] / d[1]
            edges.append(src + t * d)
        ax.add_patch(Polygon([src, edges[0], edges[1]], closed=True, color="#F5C66B", alpha=0.45, lw=0, zorder=1))
        lo, hi = sorted((edges[0][0], edges[1][0]))
        for x in np.linspace(lo, hi, 6)[1:-1]:
            vector(ax, src, (x, 0.02), VEC["l"], lw=1.5)
        ax.plot(*src, marker="*", ms=24, color="#F0B400", mec="0.2", zorder=6)


@register(
    "light_sources",
    size="16:9",
    title="Point, directional, area and spot lights",
    caption=(
        "The kinds of light, one panel each. Above: rays from each source to a planar surface — a point source's "
        "rays hit at different angles; a directional (parallel) source's all at the same angle; an area source lies "
        "in between; a spotlight is a point source limited to a cone (cutoff {cutoff:g}°). Below, on the same "
        "horizontal scale: the engine's diffuse term k_d (n·l) E along the surface (k_d = 1): a bump under the "
        "point light, a constant for "
        "the directional light, a broader bump for the area light, cut off at the cone's edge for the spot."
    ),
    slides="UBC: Light sources (point, parallel, area, spotlights)",
    height=2.0,
    cutoff=25.0,
)
def light_sources(q, *, height, cutoff):
    """Point, directional, area and spot lights as diagrams.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    height : float
        Height of the lights over the surface.
    cutoff : float
        Spot cut-off angle, in degrees.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    h = height
    lights = {
        "point": PointLight((0.0, h, 0.0), intensity=h * h),
        "directional": DirectionalLight((0.45, 1.0, 0.0)),
        "area": RectLight(
            (0.0, h, 0.0),
            edge_u=(3.0, 0.0, 0.0),
            edge_v=(0.0, 0.0, 1.0),
            intensity=1.0,
            samples=256 if not q.quick else 64,
        ),  # fmt: skip
        "spot": SpotLight((-0.5, h, 0.0), intensity=h * h, direction=(0.35, -1.0, 0.0), cutoff_deg=cutoff),
    }
    titles = {"point": "point", "directional": "directional (parallel)", "area": "area", "spot": "spotlight"}
    x = np.linspace(-4.0, 4.0, q.curve_n)
    curves = {k: _diffuse_on_floor(lt, x) for k, lt in lights.items()}
    # The area light's radiance is chosen so its peak matches the point light's (1 under the light).
    curves["area"] = curves["area"] / curves["area"].max()
    fig = new_figure()
    # A 2 × 2 grid of sources, each its ray diagram above its diffuse term along the surface.
    outer = fig.add_gridspec(2, 2)
    xs = np.linspace(-3.5, 3.5, 9)
    for i, (k, lt) in enumerate(lights.items()):
        cell = outer[i // 2, i % 2].subgridspec(2, 1, height_ratios=[1.6, 1.0])
        ax = fig.add_subplot(cell[0])
        _source_panel(ax, k, lt, xs)
        ax.set_title(titles[k], fontsize=15)
        b = fig.add_subplot(cell[1])
        b.plot(x, curves[k], color=PALETTE[i])
        b.set_ylim(0, 1.1)
        b.set_xlim(-4, 4)
        b.set_yticks([0, 0.5, 1.0])
        b.grid(True)
        if i // 2 == 1:
            b.set_xlabel("position on the surface")
        if i % 2 == 0:
            b.set_ylabel(r"$k_d\,(\mathbf{n}\cdot\mathbf{l})\,E$")
    return fig, {"cutoff": cutoff}


# --------------------------------------------------------------------------- one scene, four lights
_LIGHT_SETUPS = {
    "ambient only": (
        [AmbientLight(intensity=0.6)],
        "light position: not important\nviewer position: not important\nsurface angle: not important",
    ),
    "directional + ambient": (
        [AmbientLight(intensity=0.15), DirectionalLight((-1.0, 2.0, 1.5))],
        "surface angle: important\nlight position: not important\nviewer position: not important",
    ),
    "point + ambient": (
        [AmbientLight(intensity=0.08), PointLight((0.3, 1.6, 1.4), intensity=3.0)],
        "light position: important\nviewer position: important\nsurface angle: important",
    ),
    "spotlight + ambient": (
        [
            AmbientLight(intensity=0.08),
            SpotLight((-0.6, 3.0, 1.6), intensity=9.0, direction=(-0.35, -1.0, -0.55), cutoff_deg=24.0, exponent=2.0),
        ],
        "as the point light,\ninside a cone only\n(cutoff 24°, exponent 2)",
    ),
}


@register(
    "light_types",
    size="4:3",
    title="One scene under ambient, directional, point and spot light",
    caption=(
        "The same scene (the example scene 'ambient_only': a floor, two spheres and a cube) under four kinds "
        "of light. Ambient only: every object is a flat silhouette of its colour I_a k_a. Directional + "
        "ambient: shading follows the surface angle, the same everywhere on the floor. Point + ambient: the "
        "floor darkens away from the light (inverse-square falloff) and highlights move with the viewer. "
        "Spotlight + ambient: only what lies inside the cone is lit. No shadows: local illumination."
    ),
    slides="UBC: Ambient / Directional / Point light sources; Light sources (spotlights)",
    scene="ambient_only",
)
def light_types(q, *, scene):
    """One example scene rendered under each kind of light.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    scene : str
        The example scene's name.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    base = load_scene(example_path(scene))
    w = int(round(base.image.width * q.scene_scale))
    h = int(round(base.image.height * q.scene_scale))
    base = base.with_size(w, h)
    fig = new_figure()
    axes = fig.subplots(2, 2)
    clipped = {}
    for ax, (title, (lights, note)) in zip(axes.flat, _LIGHT_SETUPS.items(), strict=True):
        img, _ = SceneRenderer(base.with_lights(lights)).render()
        rgb8, rep = encode_srgb8(img)
        clipped[title] = rep.clipped_fraction
        show_image(ax, rgb8, title)
        ax.set_xlabel(note, fontsize=12.5, color="0.25", linespacing=1.25)
    return fig, {"clipped_fraction": clipped}


# --------------------------------------------------------------------------- falloff
_FALLOFFS = (
    ((1.0, 0.0, 0.0), r"$1/r^2$ (physical: quadratic)"),
    ((0.0, 1.0, 0.0), r"$1/r$"),
    ((0.0, 0.0, 1.0), "none (constant)"),
    ((0.3, 0.4, 0.3), r"$1/(0.3r^2 + 0.4r + 0.3)$"),
)


def _falloff_floor(px_w, px_h):
    v = np.array([[-7.0, 0, -7.0], [7.0, 0, -7.0], [7.0, 0, 7.0], [-7.0, 0, 7.0]])
    mesh = TriangleMesh(v, np.array([[0, 2, 1], [0, 3, 2]]), normals=np.tile([0.0, 1.0, 0.0], (4, 1)))
    cam = Camera((0.0, 5.5, 6.5), (0.0, 0.0, -0.4), fov_y_deg=40.0, width=px_w, height=px_h)
    return Renderer(mesh, cam, cull_backfaces=False)


@register(
    "falloff",
    size="16:9",
    title="Light source falloff",
    caption=(
        "Falloff of a point light, I_in = I_0 / (a r² + b r + c). Top: the factor against distance for the "
        "physical inverse-square law and the 'non-quadratic' choices OpenGL allows (each (a, b, c) sums to 1, "
        "so all agree at r = 1). Bottom: a floor lit by the same point light {light_height:g} above its "
        "centre (k_d = {kd:g}, no ambient) with each falloff: the slower the falloff, the more evenly lit — "
        "the old trick for faking area lights."
    ),
    slides="UBC: Light source falloff (quadratic and non-quadratic)",
    light_height=1.0,
    kd=0.7,
)
def falloff(q, *, light_height, kd):
    """Light source falloff with distance over a surface.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    light_height : float
        Height of the point light.
    kd : colour
        Diffuse albedo.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    fig = new_figure()
    gs = fig.add_gridspec(2, len(_FALLOFFS), height_ratios=[1.15, 1.0])
    ax = fig.add_subplot(gs[0, :])
    r = np.linspace(0.2, 6.0, q.curve_n)
    pts = np.stack([np.zeros_like(r), r, np.zeros_like(r)], axis=-1)
    w = q.sphere_px
    floor = _falloff_floor(w, int(round(w * 0.75)))
    for i, (att, label) in enumerate(_FALLOFFS):
        light = PointLight((0.0, 0.0, 0.0), intensity=1.0, attenuation=att)
        e = next(light.incident(pts)).irradiance[:, 0]
        ax.plot(r, e, color=PALETTE[i], label=f"(a, b, c) = ({att[0]:g}, {att[1]:g}, {att[2]:g}):  {label}")
        b = fig.add_subplot(gs[1, i])
        lamp = [PointLight((0.0, light_height, 0.0), intensity=1.0, attenuation=att)]
        img, _ = encode_srgb8(floor.render(Material(Lambert(kd)), lamp))
        show_image(b, img, f"(a, b, c) = ({att[0]:g}, {att[1]:g}, {att[2]:g})", color=PALETTE[i], fontsize=12.5)
    ax.set_xlim(0, 6)
    ax.set_ylim(0, 2.6)
    ax.axvline(1.0, color="0.6", ls=":", lw=1.2)
    ax.set_xlabel("distance r from the light (scene units)")
    ax.set_ylabel(r"$I_{in} / I_0$")
    ax.grid(True)
    ax.legend(loc="upper right")
    ax.set_title(r"$I_{in}(\mathbf{x}) = \dfrac{I_0}{a r^2 + b r + c}$")
    return fig, {"light_height": light_height, "kd": kd}


# --------------------------------------------------------------------------- light colour
_COLOUR_CASES = (
    ("white light\non a white surface", (1.0, 1.0, 1.0), (0.9, 0.9, 0.9)),
    ("blue light\non a white surface", (0.0, 0.0, 1.0), (0.9, 0.9, 0.9)),
    ("white light\non a red surface", (1.0, 1.0, 1.0), (0.9, 0.0, 0.0)),
    ("blue light\non a red surface", (0.0, 0.0, 1.0), (0.9, 0.0, 0.0)),
    ("red light\non a green surface", (1.0, 0.0, 0.0), (0.0, 0.9, 0.0)),
)


def _triple(c):
    return "(" + ", ".join(f"{x:g}" for x in c) + ")"


@register(
    "light_colour",
    size="16:9",
    title="Light colour × surface colour",
    caption=(
        "Light has colour, and it interacts with the surface colour channel by channel: I = (I_r k_r, "
        "I_g k_g, I_b k_b). A Lambertian sphere (one directional light plus ambient light of the same colour, "
        "on a grey background). Blue light on a white surface is blue; blue light on a red surface is black, "
        "and so is red light on a green surface: the surface reflects none of the light's colour. Under each "
        "sphere: light colour × surface colour, channel by channel."
    ),
    slides="UBC: Light (light has colour; blue light on white / red surface); Lighting in OpenGL (red × green)",
    ambient=0.12,
    background=0.22,
)
def light_colour(q, *, ambient, background):
    """Light colour times surface colour.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    ambient : float
        Ambient intensity.
    background : float
        Linear value behind the spheres.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    fig = new_figure()
    cols = 3
    rows = -(-(len(_COLOUR_CASES) + 1) // cols)  # the cases, then the rule they follow
    axes = fig.subplots(rows, cols).ravel()
    for ax, (title, light_c, surf) in zip(axes, _COLOUR_CASES, strict=False):
        lights = [AmbientLight(light_c, intensity=ambient), DirectionalLight((-0.6, 0.7, 1.0), color=light_c)]
        show_image(ax, sphere_rgb8(Material(Lambert(surf)), lights, q.sphere_px, background=background), title,
                   fontsize=13)  # fmt: skip
        prod = tuple(a * b for a, b in zip(light_c, surf, strict=True))
        ax.set_xlabel(f"{_triple(light_c)} × {_triple(surf)}\n= {_triple(prod)}", fontsize=13)
    for ax in axes[len(_COLOUR_CASES) :]:
        ax.axis("off")
    rule = axes[len(_COLOUR_CASES)]
    rule.text(0.5, 0.5, "light colour × surface colour,\nchannel by channel:\n\n"
              r"$I = (I_r\,k_r,\ I_g\,k_g,\ I_b\,k_b)$", ha="center", va="center", fontsize=17,
              transform=rule.transAxes, linespacing=1.4)  # fmt: skip
    return fig


# --------------------------------------------------------------------------- illumination equation
@register(
    "illumination_terms",
    size="16:9",
    title="The illumination equation, term by term",
    caption=(
        "The illumination equation I = I_a k_a + Σ_p I_p/A(d_p) (k_d (n·l_p) + k_s (r_p·v)^n), one term at a "
        "time: ambient (a flat disc of colour I_a k_a), diffuse (Lambert), specular (Phong, n = {shininess:g}) "
        "and their sum, for one point light (inverse-square falloff) and ambient light {ambient:g}. The engine "
        "computes each term separately (Renderer.render_terms); their sum equals the full render to "
        "{max_difference:.1e}. Below: the terms' luminance stacked along the row through the highlight (dashed "
        "line), with the full render's on top."
    ),
    slides="UBC: Illumination equation; Ambient light. CMSC 435: Decomposing BRDFs",
    kd=(0.7, 0.2, 0.12),
    ks=0.5,
    shininess=40.0,
    ambient=0.15,
    light=((-2.0, 2.5, 4.0), 24.0),
)
def illumination_terms(q, *, kd, ks, shininess, ambient, light):
    """The illumination equation term by term: ambient + diffuse + specular = the image.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    kd : colour
        Diffuse albedo.
    ks : float
        Specular coefficient.
    shininess : float
        Blinn–Phong exponent.
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
    mat = Material(Lambert(kd) + Phong(ks, shininess))
    lights = [AmbientLight(intensity=ambient), PointLight(light[0], intensity=light[1])]
    r = Renderer(AnalyticSphere(), sphere_camera(q.sphere_px))
    terms = r.render_terms(mat, lights, terms=("ambient", "diffuse", "specular"))
    total = r.render(mat, lights)
    diff = float(np.max(np.abs(terms["ambient"] + terms["diffuse"] + terms["specular"] - total)))
    fig = new_figure()
    gs = fig.add_gridspec(2, 1, height_ratios=[1.25, 1.0])
    axes = equation_row(fig, "++=", subplotspec=gs[0])
    row = int(np.unravel_index(np.argmax(luminance(terms["specular"])), total.shape[:2])[0])
    titles = (
        ("ambient", r"$I_a k_a$"),
        ("diffuse", r"$\sum_p \dfrac{I_p}{A(d_p)}\, k_d\,(\mathbf{n}\cdot\mathbf{l}_p)$"),
        ("specular", r"$\sum_p \dfrac{I_p}{A(d_p)}\, k_s\,(\mathbf{r}_p\cdot\mathbf{v})^n$"),
        ("sum", r"$I$"),
    )
    for ax, (key, label) in zip(axes, titles, strict=True):
        img = total if key == "sum" else terms[key]
        show_image(ax, encode_srgb8(img)[0], key, fontsize=15)
        ax.set_xlabel(label, fontsize=15)
        ax.axhline(row, color="white", lw=1.0, ls="--", alpha=0.6)
    # The terms stacked along the row through the highlight: their top is the full render.
    pa = fig.add_subplot(gs[1])
    cols = np.arange(total.shape[1])
    parts = [luminance(terms[k][row]) for k in ("ambient", "diffuse", "specular")]
    pa.stackplot(cols, *parts, colors=["0.7", PALETTE[0], PALETTE[1]], alpha=0.55,
                 labels=["ambient", "+ diffuse", "+ specular"])  # fmt: skip
    pa.plot(cols, luminance(total[row]), color="0.1", lw=2.0, label="full render")
    pa.set_xlim(0, cols[-1])
    pa.set_ylim(0, None)
    pa.set_xlabel("pixel column along the dashed row")
    pa.set_ylabel("luminance (linear)")
    pa.grid(True)
    pa.legend(loc="center left", bbox_to_anchor=(1.0, 0.5))
    return fig, {"shininess": shininess, "ambient": ambient, "max_difference": diff, "scan_row_px": row}


# --------------------------------------------------------------------------- Gouraud vs Phong interpolation
@register(
    "gouraud_vs_phong",
    size="16:9",
    title="Gouraud vs Phong interpolation, and Mach bands",
    caption=(
        "When to compute lighting. The same {triangles}-triangle sphere lit per vertex with the colours "
        "interpolated (Gouraud shading) and per pixel with the normals interpolated (Phong interpolation); "
        "thin lines are the triangle edges, the red line the scan line plotted on the right (latitude "
        "{scan_latitude_deg:g}°, midway between two rings of vertices, through the matte part). Gouraud loses "
        "the sharp highlight (it falls between vertices), and its intensity is piecewise linear: the slope "
        "jumps at every edge (dotted lines), which the eye exaggerates into Mach bands. The second difference "
        "shows the kinks; the Mach band measure (median slope kink at an edge, in display levels per pixel) is "
        "{metric_gouraud:.2g} for Gouraud, {metric_phong:.2g} for Phong interpolation. (The late spike of both is "
        "the shadow terminator, where max(n·l, 0) itself has a kink.)"
    ),
    slides="UBC: Lighting in the rendering pipeline (per-vertex lighting). CMSC 435: When to compute; Gouraud; Phong",
    n_lat=5,
    n_lon=10,
    kd=(0.7, 0.22, 0.15),
    ks=0.6,
    shininess=60.0,
    light=(-0.6, 0.55, 1.0),
    scan_latitude_deg=0.0,
)
def gouraud_vs_phong(q, *, n_lat, n_lon, kd, ks, shininess, light, scan_latitude_deg):
    """Gouraud against Phong interpolation on a coarse sphere, with a scanline showing Mach bands.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    n_lat : int
        Latitude bands of the sphere mesh.
    n_lon : int
        Longitude segments of the sphere mesh.
    kd : colour
        Diffuse albedo.
    ks : float
        Specular coefficient.
    shininess : float
        Blinn–Phong exponent.
    light : tuple
        Direction of the directional light.
    scan_latitude_deg : float
        Latitude of the plotted scanline, in degrees.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    from matplotlib.collections import LineCollection

    size = max(q.sphere_px, 128)  # the Mach band metric needs scan lines of some length, even in quick mode
    cam = sphere_camera(size)
    mesh = uv_sphere(n_lat, n_lon)
    mat = Material(Lambert(kd) + Phong(ks, shininess))
    lights = [AmbientLight(intensity=0.06), DirectionalLight(light)]
    rm = Renderer(mesh, cam)
    images = {m: rm.render(mat, lights, mode=m) for m in ("gouraud", "phong")}
    exact = Renderer(AnalyticSphere(), cam).render(mat, lights)
    gb = rm.gbuffer
    # The scan line runs along a latitude midway between two rings of vertices (through the matte part).
    lat = math.radians(scan_latitude_deg)
    row = int(cam.project(np.array([0.0, math.sin(lat), math.cos(lat)]))[0][1])
    metrics = {m: edge_jump_metric(images[m], gb.triangle_id) for m in images}

    # Visible triangle edges, projected (pixel centres sit at integer imshow coordinates).
    faces = mesh.faces
    fn = mesh.face_normals
    front = fn @ np.array([0.0, 0.0, 1.0]) > 0
    xy, _ = cam.project(mesh.vertices)
    xy = xy - 0.5
    segs = []
    for f in faces[front]:
        for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0])):
            segs.append([xy[a], xy[b]])

    fig = new_figure()
    # The two images in the left column, the scan line's profile and its kinks beside them.
    gs = fig.add_gridspec(2, 2, width_ratios=[1.0, 1.9])
    titles = {"gouraud": "Gouraud: light the vertices, interpolate colours",
              "phong": "Phong: interpolate normals, light every pixel"}  # fmt: skip
    colours = {"gouraud": PALETTE[4], "phong": PALETTE[0]}
    for i, m in enumerate(("gouraud", "phong")):
        ax = fig.add_subplot(gs[i, 0])
        show_image(ax, encode_srgb8(images[m])[0], titles[m], fontsize=13)
        ax.add_collection(LineCollection(segs, colors="white", linewidths=0.6, alpha=0.35))
        ax.axhline(row, color="#ff3b30", lw=1.4)
        ax.set_xlim(-0.5, size - 0.5)
        ax.set_ylim(size - 0.5, -0.5)
    prof = {m: scanline_profile(img, row, coverage=gb.coverage) for m, img in images.items()}
    pex = scanline_profile(exact, row, coverage=gb.coverage)
    tid = gb.triangle_id[row]
    xs = prof["gouraud"].x
    edges = xs[:-1][tid[xs[:-1]] != tid[xs[1:]]] + 0.5
    ax1 = fig.add_subplot(gs[0, 1])
    ax2 = fig.add_subplot(gs[1, 1], sharex=ax1)
    for e in edges:
        ax1.axvline(e, color="0.75", ls=":", lw=1.0)
        ax2.axvline(e, color="0.75", ls=":", lw=1.0)
    ax1.plot(pex.x, pex.intensity, color="0.35", lw=1.4, ls="--", label="exact sphere")
    scale = 1.0 / max(float(np.mean(np.abs(prof["phong"].d1))), 1e-12)
    for m in ("gouraud", "phong"):
        p = prof[m]
        ax1.plot(p.x, p.intensity, color=colours[m], label=m.capitalize())
        ax2.plot(p.x[1:-1], p.d2 * scale, color=colours[m], lw=1.6,
                 label=f"{m.capitalize()}  (measure {metrics[m]:.2g})")  # fmt: skip
    ax1.tick_params(labelbottom=False)
    ax1.set_ylim(0.0, None)
    ax1.set_ylabel("luminance (linear)")
    ax1.set_title("Intensity along the scan line")
    ax1.legend(loc="upper right")
    ax2.set_xlabel("pixel column along the scan line")
    ax2.set_ylabel("second difference / mean slope")
    ax2.set_title("Kinks at the triangle edges")
    ax2.legend(loc="upper left")
    # Limits from every plotted value, the terminator's spikes included, with a margin.
    d2 = np.concatenate([prof[m].d2 * scale for m in prof])
    lo, hi = float(min(d2.min(), 0.0)), float(max(d2.max(), 0.0))
    pad = 0.08 * (hi - lo) or 1.0
    ax2.set_ylim(lo - pad, hi + pad)
    ax2.axhline(0.0, color="0.6", lw=0.8)
    for a in (ax1, ax2):
        a.set_xlim(xs[0], xs[-1])
    return fig, {
        "triangles": mesh.n_triangles,
        "metric_gouraud": metrics["gouraud"],
        "metric_phong": metrics["phong"],
        "scan_row_px": row,
        "scan_latitude_deg": scan_latitude_deg,
    }

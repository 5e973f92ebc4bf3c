"""OpenGL's light positions (w = 0: a direction, w = 1: a point) and the spot light's parameters.

Every value is the OpenGL mode's (:mod:`lighting.gl`, the fixed-function equation as Mesa computes it)
or the engine's spot light (:class:`lighting.SpotLight`); the diagrams only place arrows.
Registered on import (see :mod:`explorer.figures.base`); drawn by :mod:`explorer.figures`.
"""

from __future__ import annotations

import math

import numpy as np

from lighting import SpotLight, gl
from lighting.render.image import encode_srgb8

from .base import PALETTE, VEC, angle_arc, new_figure, register, series_colours, show_image, vector

#: A white diffuse-only material and no ambient anywhere: the vertex colour is the light's n·VP term alone.
_WHITE = gl.Material(ambient=(0.0, 0.0, 0.0), diffuse=(1.0, 1.0, 1.0), specular=(0.0, 0.0, 0.0))
_NO_AMBIENT = (0.0, 0.0, 0.0, 1.0)


def _floor(ax, x0, x1):
    from matplotlib.patches import Rectangle

    ax.add_patch(Rectangle((x0, -0.12), x1 - x0, 0.12, color=VEC["surface"], lw=0, zorder=2))


def _diffuse_along_floor(light, xs):
    """The fixed-function colour of white floor vertices ``(x, 0, −4)`` (normal +y) under ``light`` alone."""
    pts = np.stack([xs, np.zeros_like(xs), np.full_like(xs, -4.0)], axis=-1)
    return gl.shade_vertices(pts, (0.0, 1.0, 0.0), _WHITE, [light], scene_ambient=_NO_AMBIENT)[:, 0]


@register(
    "gl_light_position",
    size="16:9",
    title="OpenGL light positions: w = 0 is a direction, w = 1 a point",
    caption=(
        "glLightfv(GL_LIGHT0, GL_POSITION, (x, y, z, w)). Left: w = 0 makes (x, y, z) a direction toward the "
        "light: its rays are parallel, every floor point sees the same angle, and the diffuse term n·VP is the "
        "same everywhere (spread {w0_spread:.0e}, value {w0_value:.3f} = cos {w0_angle_deg:g}°). Right: w = 1 puts "
        "a point light at (x, y, z): the rays spread from it, and n·VP = h/√(h² + d²) falls off with the distance d "
        "from the foot of the light (largest difference from that formula {w1_formula_difference:.0e}; no "
        "attenuation here, constant_attenuation = 1). Values from the OpenGL mode, lighting.gl.shade_vertices."
    ),
    slides="UBC: Light sources — OpenGL (GL_POSITION: directional [x y z 0], point source [x y z 1])",
    direction=(-0.5, 1.0, 0.0),
    point=(0.0, 2.0, -4.0),
    x_range=(-4.0, 4.0),
)
def gl_light_position(q, *, direction, point, x_range):
    """OpenGL's homogeneous light position: a directional light (w = 0) and a point light (w = 1).

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    direction : tuple
        ``(x, y, z)`` of the ``w = 0`` light (toward the light).
    point : tuple
        ``(x, y, z)`` of the ``w = 1`` light, in eye coordinates.
    x_range : tuple
        The floor's extent.

    Returns
    -------
    tuple
        ``(figure, measured)``: the directional light's spread along the floor and its value, the point
        light's largest difference from ``h/√(h² + d²)``.
    """
    xs = np.linspace(*x_range, q.curve_n)
    lights = {0: gl.Light(position=(*direction, 0.0)), 1: gl.Light(position=(*point, 1.0))}
    values = {w: _diffuse_along_floor(lt, xs) for w, lt in lights.items()}
    h = point[1]
    formula = h / np.hypot(h, xs - point[0])
    d = np.asarray(direction, dtype=np.float64)
    fig = new_figure()
    gs = fig.add_gridspec(2, 2, height_ratios=[1.0, 1.15])
    for col, w in enumerate((0, 1)):
        ax = fig.add_subplot(gs[0, col])
        ax.set_aspect("equal")
        ax.set_xlim(x_range[0] - 0.2, x_range[1] + 0.2)
        ax.set_ylim(-0.4, 3.2)
        ax.axis("off")
        _floor(ax, x_range[0] - 0.1, x_range[1] + 0.1)
        feet = np.linspace(x_range[0] + 0.6, x_range[1] - 0.6, 7)
        if w == 0:
            u = d[:2] / np.linalg.norm(d[:2])
            shift = 2.9 * u[0] / u[1]  # where a ray starts, relative to its foot: keep every start in the panel
            feet = np.linspace(x_range[0] + 0.6 - min(shift, 0.0), x_range[1] - 0.6 - max(shift, 0.0), 7)
            for x in feet:
                vector(ax, np.array([x, 0.0]) + 2.9 / u[1] * u, (x, 0.03), VEC["l"], lw=1.6)
            ax.set_title(f"GL_POSITION = ({d[0]:g}, {d[1]:g}, {d[2]:g}, 0): a direction, parallel rays")
        else:
            src = np.array(point[:2])
            for x in feet:
                vector(ax, src, (x, 0.03), VEC["l"], lw=1.6)
            ax.plot(*src, marker="*", ms=24, color="#F0B400", mec="0.2", zorder=6)
            ax.set_title(f"GL_POSITION = ({point[0]:g}, {point[1]:g}, {point[2]:g}, 1): a point, rays from it")
        pa = fig.add_subplot(gs[1, col])
        pa.plot(xs, values[w], color=PALETTE[0], lw=2.4, label="OpenGL mode: n·VP")
        if w == 1:
            pa.plot(xs[::24], formula[::24], "o", color=PALETTE[1], ms=6, label="h / √(h² + d²)")
        pa.set_xlim(*x_range)
        pa.set_ylim(0, 1.05)
        pa.set_xlabel("position along the floor")
        pa.set_ylabel("diffuse term (white light, k_d = 1)")
        pa.grid(True)
        pa.legend(loc="lower center")
    w0_angle = math.degrees(math.acos(d[1] / np.linalg.norm(d)))
    return fig, {
        "w0_spread": float(values[0].max() - values[0].min()),
        "w0_value": float(values[0][0]),
        "w0_angle_deg": round(w0_angle, 2),
        "w1_formula_difference": float(np.max(np.abs(values[1] - formula))),
        "w1_peak_x": float(xs[int(np.argmax(values[1]))]),
    }


@register(
    "gl_spot_parameters",
    size="4:3",
    title="OpenGL spot light: GL_SPOT_DIRECTION, GL_SPOT_CUTOFF, GL_SPOT_EXPONENT",
    caption=(
        "Top left: a spot light is a point light limited to a cone about GL_SPOT_DIRECTION (ŝ), of half-angle "
        "GL_SPOT_CUTOFF ({cutoff:g}°); inside it the light falls off as (−VP·ŝ)^GL_SPOT_EXPONENT = cos^e ψ, ψ the "
        "angle from the axis (rays shaded by that factor, e = {exponent_drawn:g}). Below: the spot factor for "
        "several exponents: lines from the engine's SpotLight.spot_factor, dots from the OpenGL mode "
        "(lighting.gl.shade_vertices; largest difference {max_difference:.0e}). It is cos^e(cutoff) at the edge "
        "(e = {exponent_drawn:g}: {edge_value:.3f}) and drops to 0 outside: the exponent softens the pool of "
        "light, the cutoff ends it. Top right: the floor under this spot, per vertex in the OpenGL mode."
    ),
    slides="UBC: Light sources — OpenGL (spotlight: GL_SPOT_DIRECTION, GL_SPOT_EXPONENT, GL_SPOT_CUTOFF); Spotlights",
    cutoff=30.0,
    exponents=(0.0, 2.0, 10.0, 50.0),
    exponent_drawn=10.0,
    height=3.0,
)
def gl_spot_parameters(q, *, cutoff, exponents, exponent_drawn, height):
    """OpenGL's spot parameters drawn on the cone, the spot factor curves, and the pool of light.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    cutoff : float
        GL_SPOT_CUTOFF, degrees.
    exponents : sequence of float
        GL_SPOT_EXPONENT values compared.
    exponent_drawn : float
        The exponent of the diagram and the floor image.
    height : float
        The spot's height above the floor.

    Returns
    -------
    tuple
        ``(figure, measured)``: the largest difference between the engine's spot factor and the OpenGL
        mode's, the factor at the cutoff and just outside it.
    """
    fig = new_figure()
    # The cone beside the pool of light it makes on the floor; the spot factor's curves across the bottom.
    gs = fig.add_gridspec(2, 2, height_ratios=[1.15, 1.0], width_ratios=[1.25, 1.0])
    ax, ia, pa = fig.add_subplot(gs[0, 0]), fig.add_subplot(gs[0, 1]), fig.add_subplot(gs[1, :])
    ax.set_aspect("equal")
    ax.set_xlim(-2.6, 2.6)
    ax.set_ylim(-1.05, height + 0.6)
    ax.axis("off")
    _floor(ax, -2.5, 2.5)
    src = np.array([0.0, height])
    spot = SpotLight((0.0, height, 0.0), direction=(0.0, -1.0, 0.0), cutoff_deg=cutoff, exponent=exponent_drawn)
    for psi in np.linspace(-cutoff, cutoff, 13):
        t = math.radians(psi)
        f = float(spot.spot_factor(math.cos(t))[()])
        end = src + (height / math.cos(t)) * np.array([math.sin(t), -math.cos(t)])
        ax.plot([src[0], end[0]], [src[1], end[1]], color=VEC["l"], lw=2.2, alpha=0.15 + 0.85 * f)
    for s in (-1, 1):
        t = math.radians(cutoff * s)
        edge = src + (height / math.cos(t)) * np.array([math.sin(t), -math.cos(t)])
        ax.plot([src[0], edge[0]], [src[1], edge[1]], color="0.3", ls="--", lw=1.4)
    vector(ax, src, src + np.array([0.0, -1.6]), VEC["v"], lw=2.6)
    ax.text(0.12, height - 1.75, "GL_SPOT_DIRECTION ŝ", color=VEC["v"], fontsize=12.5, va="top")
    angle_arc(ax, tuple(src), 1.0, -90.0, -90.0 + cutoff, "0.2", "", fontsize=13)
    ax.text(0.9, height - 0.55, "GL_SPOT_CUTOFF", fontsize=12.5, color="0.2")
    ax.plot(*src, marker="*", ms=24, color="#F0B400", mec="0.2", zorder=6)
    ax.text(0, -0.33, f"brightness along each ray: cos^e ψ,\nGL_SPOT_EXPONENT e = {exponent_drawn:g}",
            ha="center", va="top", fontsize=12.5)  # fmt: skip
    ax.set_title("The spot's parameters on its cone")

    psi = np.linspace(0.0, 60.0, q.curve_n)
    dots = np.arange(0.0, 60.0 + 1e-9, 2.5)
    cols = series_colours(len(exponents))
    diff = 0.0
    for e, c in zip(exponents, cols, strict=True):
        lt = SpotLight((0.0, 0.0, 0.0), direction=(0.0, 0.0, -1.0), cutoff_deg=cutoff, exponent=e)
        pa.plot(psi, lt.spot_factor(np.cos(np.radians(psi))), color=c, lw=2.2, label=f"e = {e:g}")
        # Vertices one unit from the light at angle ψ from the axis, facing it: n·VP = 1, no attenuation.
        t = np.radians(dots)
        pts = np.stack([np.sin(t), np.zeros_like(t), -np.cos(t)], axis=-1)
        glt = gl.Light(position=(0.0, 0.0, 0.0, 1.0), spot_direction=(0.0, 0.0, -1.0), spot_cutoff=cutoff,
                       spot_exponent=e)  # fmt: skip
        col = gl.shade_vertices(pts, -pts, _WHITE, [glt], scene_ambient=_NO_AMBIENT)[:, 0]
        pa.plot(dots, col, "o", color=c, ms=4.5)
        diff = max(diff, float(np.max(np.abs(col - lt.spot_factor(np.cos(t))))))
    pa.axvline(cutoff, color="0.3", ls="--", lw=1.4)
    pa.text(cutoff + 1, 0.9, "cutoff", fontsize=12, color="0.3")
    pa.set_xlim(0, 60)
    pa.set_ylim(-0.02, 1.05)
    pa.set_xlabel("angle ψ from the spot direction (degrees)")
    pa.set_ylabel("spot factor")
    pa.grid(True)
    pa.legend(loc="upper right", title="GL_SPOT_EXPONENT", fontsize=11)
    pa.set_title("spot factor: lines engine, dots OpenGL mode")

    # The pool of light on the floor, computed per vertex by the OpenGL mode.
    n = q.sphere_px
    g = np.linspace(-2.5, 2.5, n)
    X, Z = np.meshgrid(g, g)
    pts = np.stack([X, np.full_like(X, -height), Z], axis=-1)  # floor below the light at the origin
    glt = gl.Light(position=(0.0, 0.0, 0.0, 1.0), spot_direction=(0.0, -1.0, 0.0), spot_cutoff=cutoff,
                   spot_exponent=exponent_drawn)  # fmt: skip
    img = gl.shade_vertices(pts, (0.0, 1.0, 0.0), _WHITE, [glt], scene_ambient=_NO_AMBIENT)[..., :3]
    show_image(ia, encode_srgb8(img)[0], "the pool of light (OpenGL mode)")
    edge = SpotLight(cutoff_deg=cutoff, exponent=exponent_drawn)
    c_cut = math.cos(math.radians(cutoff))
    return fig, {
        "cutoff": cutoff,
        "exponent_drawn": exponent_drawn,
        "max_difference": diff,
        "edge_value": float(edge.spot_factor(c_cut)[()]),
        "outside_value": float(edge.spot_factor(math.cos(math.radians(cutoff + 0.01)))[()]),
        "pool_radius_px": float(np.sqrt(np.count_nonzero(img[..., 0] > 0) / math.pi)),
        "pool_radius_expected_px": height * math.tan(math.radians(cutoff)) / (5.0 / (n - 1)),
    }

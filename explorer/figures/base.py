"""Shared pieces of the lecture-note figures: the registry, the look, and small drawing helpers.

Every figure is a function registered with :func:`register` under a name, with a
caption and the parameters that made it.  It receives a :class:`Quality` (image
sizes and sample counts: full or ``--quick``) plus its parameters, and returns a
Matplotlib :class:`~matplotlib.figure.Figure` — or ``(figure, measured)`` where
``measured`` is a dict of numbers computed while drawing (they fill ``{...}``
fields of the caption and go into the figure's JSON sidecar).

The look is one style for the whole set (:data:`STYLE`): type sizes meant for a
lecture slide, the Okabe–Ito colour-blind-safe palette for curves, one colour per
slide vector wherever it appears (``n``, ``l``, ``v``, ``r``/``R_l``, ``R_v``,
``h``: :data:`VEC`), and perceptually uniform colour maps (viridis for values,
magma for quantities spanning decades).  Rendered spheres and scenes are the
engine's linear images, sRGB-encoded by :func:`lighting.render.image.encode_srgb8` and
shown with ``imshow``: no Matplotlib or VTK lighting anywhere.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from lighting.render.image import encode_srgb8
from lighting.render.sphere import render_sphere

__all__ = [
    "Quality",
    "FigureSpec",
    "SLIDE_SIZES",
    "REGISTRY",
    "register",
    "STYLE",
    "PALETTE",
    "VEC",
    "series_colours",
    "new_figure",
    "sphere_rgb8",
    "show_image",
    "polar_half",
    "vector",
    "angle_arc",
    "equation_row",
]

# --------------------------------------------------------------------------- look
#: Okabe & Ito's colour-blind-safe palette (blue, vermillion, green, purple, orange, sky blue, yellow, black).
PALETTE = ("#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#F0E442", "#000000")

#: One colour per slide vector, used by every diagram and plot.
VEC = {
    "n": "#222222",
    "l": "#E69F00",
    "v": "#0072B2",
    "r": "#D55E00",
    "R_l": "#D55E00",
    "R_v": "#CC79A7",
    "h": "#009E73",
    "surface": "#B22222",
}

#: Matplotlib settings shared by every figure: legible on a projected slide.
STYLE = {
    "font.family": "DejaVu Sans",
    "font.size": 13,
    "axes.titlesize": 14,
    "axes.labelsize": 13,
    "xtick.labelsize": 11.5,
    "ytick.labelsize": 11.5,
    "legend.fontsize": 11.5,
    "figure.titlesize": 16,
    "axes.prop_cycle": __import__("cycler").cycler(color=list(PALETTE)),
    "axes.grid": False,
    "grid.color": "0.88",
    "grid.linewidth": 0.7,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "lines.linewidth": 2.0,
    "legend.frameon": False,
    "image.cmap": "viridis",
    "mathtext.fontset": "dejavusans",
    "figure.facecolor": "white",
    "savefig.facecolor": "white",
    "svg.hashsalt": "lighting-explorer-figures",
    "svg.fonttype": "path",
    "pdf.fonttype": 42,
    "path.simplify": False,
}


def series_colours(count: int, cmap: str = "viridis", stop: float = 0.85) -> list:
    """``count`` colours along a perceptually uniform map (light end trimmed for a white background).

    Parameters
    ----------
    count : int
        How many colours.
    cmap : str, optional
        A Matplotlib colour map name.
    stop : float, optional
        Where along the map the last colour sits (0 to 1).

    Returns
    -------
    list
        ``count`` RGBA tuples.
    """
    import matplotlib

    m = matplotlib.colormaps[cmap]
    if count == 1:
        return [m(0.0)]
    return [m(stop * i / (count - 1)) for i in range(count)]


# --------------------------------------------------------------------------- quality
@dataclass(frozen=True)
class Quality:
    """Resolution and sample counts: the full set (default) or ``quick`` (tests, seconds)."""

    quick: bool = False
    dpi: int = 150

    @property
    def sphere_px(self) -> int:
        """Side of a rendered sphere image, in pixels."""
        return 48 if self.quick else 320

    @property
    def scene_scale(self) -> float:
        """Scene images are rendered at this fraction of their file's size."""
        return 0.25 if self.quick else 1.0

    @property
    def polar_n(self) -> int:
        """Samples of a polar slice."""
        return 91 if self.quick else 721

    @property
    def curve_n(self) -> int:
        """Samples of a 1D curve."""
        return 61 if self.quick else 721

    @property
    def lobe_resolution(self) -> int:
        """``resolution`` of :func:`lighting.analysis.lobe_mesh`."""
        return 8 if self.quick else 40

    @property
    def env_px(self) -> int:
        """Side of a sphere lit by an environment (per-pixel integration)."""
        return 32 if self.quick else 256

    @property
    def env_samples(self) -> int:
        """Integration nodes per pixel for the rendering equation."""
        return 64 if self.quick else 256

    @property
    def audit_samples(self) -> int:
        """Quadrature nodes per view angle in the plausibility audit."""
        return 512 if self.quick else 4096


# --------------------------------------------------------------------------- registry
@dataclass(frozen=True)
class FigureSpec:
    """One figure of the set: how to draw it and what to say about it."""

    name: str
    func: Callable
    title: str
    caption: str
    slides: str
    parameters: dict = field(default_factory=dict)
    #: Why two runs may differ (measured wall-clock times), or ``None`` when the pixels are reproducible.
    nondeterministic: str | None = None
    #: The figure's size in inches, ``(width, height)``: a slide's shape (see :data:`SLIDE_SIZES`).
    size_in: tuple[float, float] | None = None


#: The two slide shapes every figure is drawn at, in inches: 1280 pixels across is 96 per inch at 16:9,
#: so text of 8 points or more stays at least 10 pixels tall when a figure fills a 1280-pixel-wide slide.
SLIDE_SIZES = {"16:9": (40 / 3, 7.5), "4:3": (10.0, 7.5)}

# The declared size of the figure being drawn (set by :func:`explorer.figures.make_figure`): what
# :func:`new_figure` uses when it is given no size.
_drawing_size: list = [None]


#: name → :class:`FigureSpec`, in lecture order (registration order).
REGISTRY: dict[str, FigureSpec] = {}


def register(
    name: str,
    *,
    title: str,
    caption: str,
    slides: str,
    nondeterministic: str | None = None,
    size: str | tuple[float, float] | None = None,
    **parameters,
):
    """Decorator: add a figure function to :data:`REGISTRY` under ``name``.

    Parameters
    ----------
    name : str
        The figure's name (its files are ``NAME.png`` ...); registering a name twice raises ``ValueError``.
    title, caption, slides : str
        What the sidecar and the gallery say about it (``{...}`` fields of the caption are filled from
        what the figure measured).
    nondeterministic : str, optional
        Why two runs may differ, or ``None`` when the pixels are reproducible.
    size : str or tuple of float, optional
        The figure's shape, ``"16:9"`` or ``"4:3"`` (:data:`SLIDE_SIZES`), or its size in inches; the
        command line checks ``--dpi`` against it before anything is drawn, and :func:`new_figure`
        called without a size draws at it.
    **parameters
        The parameters the function is called with.

    Returns
    -------
    callable
        The decorator, which returns the function unchanged.
    """

    def deco(func):
        if name in REGISTRY:
            raise ValueError(f"figure {name!r} is registered twice")
        size_in = SLIDE_SIZES[size] if isinstance(size, str) else (tuple(float(x) for x in size) if size else None)
        REGISTRY[name] = FigureSpec(name, func, title, caption, slides, dict(parameters), nondeterministic, size_in)
        return func

    return deco


# --------------------------------------------------------------------------- drawing helpers
def new_figure(width: float | None = None, height: float | None = None, **kwargs):
    """A Matplotlib figure (no pyplot: nothing global, safe in worker processes) with constrained layout.

    Parameters
    ----------
    width, height : float, optional
        Size in inches; by default the size the figure being drawn was registered with.
    **kwargs
        Passed to :class:`matplotlib.figure.Figure` (``layout`` defaults to ``"constrained"``).

    Returns
    -------
    matplotlib.figure.Figure
        The new figure.
    """
    from matplotlib.figure import Figure

    if width is None or height is None:
        if _drawing_size[0] is None:
            raise ValueError("new_figure() without a size needs a figure registered with a size")
        width, height = _drawing_size[0]
    kwargs.setdefault("layout", "constrained")
    return Figure(figsize=(width, height), **kwargs)


def sphere_rgb8(material, lights, size: int, *, exposure: float = 0.0, background=0.0) -> np.ndarray:
    """The engine's exact (ray-cast) unit sphere under ``lights``, sRGB-encoded.

    Parameters
    ----------
    material : lighting.Material
        The sphere's material.
    lights : list
        The engine's lights.
    size : int
        Image width and height in pixels.
    exposure : float, optional
        Exposure in stops.
    background : float or colour, optional
        The linear value behind the sphere.

    Returns
    -------
    numpy.ndarray
        ``(size, size, 3)`` uint8.
    """
    img = render_sphere(material, lights, size=size, background=background)
    rgb8, _ = encode_srgb8(img, exposure=exposure)
    return rgb8


def show_image(ax, rgb8, title: str | None = None, *, color=None, fontsize=None, dark=True) -> None:
    """An engine image in ``ax``: no ticks, no frame, optional title.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to show it.
    rgb8 : numpy.ndarray
        ``(h, w, 3)`` uint8.
    title : str, optional
        The axes title.
    color, fontsize : optional
        The title's colour and size.
    dark : bool, optional
        Black axes background.

    Returns
    -------
    None
    """
    ax.imshow(rgb8, interpolation="antialiased")
    ax.set_xticks([])
    ax.set_yticks([])
    for s in ax.spines.values():
        s.set_visible(False)
    if dark:
        ax.set_facecolor("black")
    if title is not None:
        kw = {}
        if color is not None:
            kw["color"] = color
        if fontsize is not None:
            kw["fontsize"] = fontsize
        ax.set_title(title, **kw)


def polar_half(ax, rmax: float, *, label: str | None = r"$f_r$ (1/sr)", ticks: int = 3) -> None:
    """A polar axes showing the upper hemisphere: the normal points up, angles in degrees from it.

    Positive angles are to the right (the mirror side in :func:`lighting.analysis.polar_slice`); the
    radial scale reads along the right half of the baseline, its label sits under the origin.

    Parameters
    ----------
    ax : matplotlib.projections.polar.PolarAxes
        The axes to set up.
    rmax : float
        The radial limit.
    label : str, optional
        The radial scale's label (none if empty).
    ticks : int, optional
        About how many radial ticks.

    Returns
    -------
    None
    """
    ax.set_theta_zero_location("N")
    ax.set_theta_direction(-1)
    ax.set_thetamin(-90)
    ax.set_thetamax(90)
    ax.set_ylim(0, rmax)
    ax.set_xticks(np.radians([-90, -60, -30, 0, 30, 60, 90]))
    ax.set_xticklabels(["−90°", "−60°", "−30°", "0°", "30°", "60°", "90°"])
    r = _nice_ticks(rmax, ticks)
    ax.set_yticks(r)
    ax.set_yticklabels([_fmt_tick(x) for x in r], fontsize=10.5, color="0.3")
    # A wedge draws its radial labels along a side edge: the right half of the baseline reads 0 → rmax.
    ax.tick_params(axis="y", pad=1, labelleft=False, labelright=True, left=False, right=True)
    ax.grid(True, color="0.85", lw=0.7)
    if label:
        ax.annotate(label, xy=(np.radians(90), 0.55 * rmax), xytext=(0, -20), textcoords="offset points",
                    ha="center", va="top", fontsize=11.5, color="0.3")  # fmt: skip


def _nice_ticks(rmax: float, count: int) -> list:
    step = rmax / count
    mag = 10 ** math.floor(math.log10(step))
    for m in (1, 2, 2.5, 5, 10):
        if m * mag >= step:
            step = m * mag
            break
    return [step * k for k in range(1, count + 1) if step * k <= rmax * 1.0001]


def _fmt_tick(x: float) -> str:
    return f"{x:.3g}"


def vector(ax, start, end, color, label=None, *, lw=2.6, label_offset=(0.0, 0.0), fontsize=18, zorder=4, ls="-"):
    """An arrow from ``start`` to ``end`` with a bold label near its tip (for the vector diagrams).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The diagram.
    start, end : tuple of float
        Tail and tip, in data coordinates.
    color : str
        Arrow and label colour (see :data:`VEC`).
    label : str, optional
        Drawn at the tip, shifted by ``label_offset``.
    lw, fontsize, zorder, ls : optional
        Line width, label size, drawing order and line style.
    label_offset : tuple of float, optional
        Offset of the label from the tip.

    Returns
    -------
    None
    """
    from matplotlib.patches import FancyArrowPatch

    arrow = FancyArrowPatch(start, end, arrowstyle="-|>", mutation_scale=22, color=color, lw=lw, zorder=zorder,
                            shrinkA=0, shrinkB=0, linestyle=ls)  # fmt: skip
    ax.add_patch(arrow)
    if label:
        ax.text(end[0] + label_offset[0], end[1] + label_offset[1], label, color=color, fontsize=fontsize,
                ha="center", va="center", zorder=zorder + 1)  # fmt: skip


def angle_arc(ax, center, radius, a0_deg, a1_deg, color, label=None, *, label_radius=None, fontsize=15):
    """An arc from angle ``a0`` to ``a1`` (degrees, counter-clockwise from +x) with a label at its middle.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The diagram.
    center : tuple of float
        The arc's centre.
    radius : float
        The arc's radius.
    a0_deg, a1_deg : float
        Its ends, in degrees.
    color : str
        Arc and label colour.
    label : str, optional
        Drawn at the arc's middle, ``label_radius`` (default 1.35 ``radius``) from the centre.
    label_radius, fontsize : float, optional
        Where and how large the label is.

    Returns
    -------
    None
    """
    from matplotlib.patches import Arc

    lo, hi = min(a0_deg, a1_deg), max(a0_deg, a1_deg)
    ax.add_patch(Arc(center, 2 * radius, 2 * radius, theta1=lo, theta2=hi, color=color, lw=1.6, zorder=3))
    if label:
        mid = math.radians(0.5 * (lo + hi))
        rr = label_radius if label_radius is not None else radius * 1.35
        ax.text(center[0] + rr * math.cos(mid), center[1] + rr * math.sin(mid), label, color=color,
                fontsize=fontsize, ha="center", va="center")  # fmt: skip


def equation_row(fig, symbols, *, gap: float = 0.16, subplotspec=None):
    """Axes for ``len(symbols) + 1`` images in a row with an operator between each pair ("+", "=").

    The operators sit in narrow axes of their own, so they never overlap an image.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    symbols : sequence of str
        The operators, one between each pair of images.
    gap : float, optional
        Width of an operator's axes relative to an image's.
    subplotspec : matplotlib.gridspec.SubplotSpec, optional
        Lay the row out inside this cell instead of the whole figure.

    Returns
    -------
    list of matplotlib.axes.Axes
        The image axes, left to right.
    """
    n = len(symbols) + 1
    ratios = []
    for i in range(n):
        ratios.append(1.0)
        if i < n - 1:
            ratios.append(gap)
    gs = (subplotspec.subgridspec if subplotspec is not None else fig.add_gridspec)(1, len(ratios), width_ratios=ratios)
    axes = []
    for i in range(n):
        axes.append(fig.add_subplot(gs[0, 2 * i]))
        if i < n - 1:
            s = fig.add_subplot(gs[0, 2 * i + 1])
            s.axis("off")
            s.text(0.5, 0.5, symbols[i], fontsize=32, ha="center", va="center", transform=s.transAxes)
    return axes

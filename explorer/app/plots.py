"""The explorer's Matplotlib panels: scan-line profile, polar slice, angle curves and half/difference image.

Each panel is a :class:`BlitFigure`: a small Matplotlib figure whose data
artists are *animated* — a full draw (axes, ticks, labels: the slow part) happens
only when the layout changes (axis limits, the figure's size); otherwise an
update restores the saved background and redraws the data artists alone
(``docs/explorer.md`` gives the costs).  Axis limits follow the data with hysteresis (they grow at once,
shrink only when the data fall below a quarter of the range), so updates rarely
need a full draw.  The window updates the panels when a slider is released,
not during the drag.

The panels only draw what :class:`explorer.app.views.ExplorerModel` computed;
nothing here touches the engine.  Imports Matplotlib (Agg canvas only, no
pyplot), not PyVista.
"""

from __future__ import annotations

import math

import matplotlib
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.ticker import FuncFormatter, MaxNLocator

__all__ = ["BlitFigure", "ProfilePlot", "PolarPlot", "AnglePlots", "AnglePlotsGrid", "AlbedoPlot", "nice_ceiling",
           "hysteresis_limit", "COLOURS", "OVERLAY_SLOTS"]

COLOURS = {
    "gouraud": "#ffa94d",
    "phong": "#4dd4ff",
    "light": "#ffe066",
    "mirror": "#ff6b6b",
    "luminance": "#f1f3f5",
    "r": "#ff6b6b",
    "g": "#51cf66",
    "b": "#5c9dff",
    "text": "#e9ecef",
    "muted": "#868e96",
    "edge": "#adb5bd",
}

STYLE = {
    "font.size": 8,
    "axes.titlesize": 8,
    "axes.labelsize": 8,
    "xtick.labelsize": 7,
    "ytick.labelsize": 7,
    "legend.fontsize": 7,
    "text.color": COLOURS["text"],
    "axes.labelcolor": COLOURS["text"],
    "axes.edgecolor": COLOURS["muted"],
    "xtick.color": COLOURS["text"],
    "ytick.color": COLOURS["text"],
    "grid.color": "#495057",
    "grid.linewidth": 0.5,
    "axes.facecolor": "none",
    "figure.facecolor": "none",
    "legend.frameon": False,
    "lines.linewidth": 1.4,
}


#: Curves of comparison entries each BRDF plot can draw (explorer.app.state.MAX_ENTRIES).
OVERLAY_SLOTS = 6
#: Half-range of the profile's relative second-difference axis.
D2_LIMIT = 2.0
#: Angles (degrees) beyond which the θ_h / θ_d plots do not set their scale (see AnglePlots.set_data).
GRAZING_DEG = 80.0


def nice_ceiling(x: float) -> float:
    """The smallest of 1, 2, 5 × 10^k that is ≥ ``x`` (1 for ``x <= 0`` or non-finite).

    Coarse steps on purpose: an axis that changes its limit needs a full redraw.

    Parameters
    ----------
    x : float
        The value to cover.

    Returns
    -------
    float
        The limit.

    Examples
    --------
    >>> [nice_ceiling(v) for v in (0.0, 0.23, 1.0, 7.1, 1234.0)]
    [1.0, 0.5, 1.0, 10.0, 2000.0]
    """
    if not (math.isfinite(x) and x > 0):
        return 1.0
    e = math.floor(math.log10(x))
    for k in (e, e + 1):
        for s in (1.0, 2.0, 5.0, 10.0):
            v = float(f"{s * 10.0**k:.6g}")  # 0.15, not 0.15000000000000002
            if v >= x * (1 - 1e-12):
                return v
    return 10.0 ** (e + 1)  # pragma: no cover


def hysteresis_limit(peak: float, current: float | None, margin: float = 1.05) -> float:
    """An axis limit for data reaching ``peak``: keep ``current`` while ``current/4 <= peak <= current``.

    Parameters
    ----------
    peak : float
        The data's largest value.
    current : float or None
        The axis limit now (None: none yet).
    margin : float
        Head room above the peak before rounding up.

    Returns
    -------
    float
        The new limit.

    Examples
    --------
    >>> hysteresis_limit(0.9, 1.0), hysteresis_limit(1.2, 1.0), hysteresis_limit(0.1, 1.0)
    (1.0, 2.0, 0.2)
    """
    if not (math.isfinite(peak) and peak > 0):
        return current if current else 1.0
    if current and current / 4.0 <= peak <= current:
        return current
    return nice_ceiling(peak * margin)


def _finite(a) -> np.ndarray:
    a = np.asarray(a, dtype=np.float64)
    return np.where(np.isfinite(a), a, 0.0)


def _set_overlays(lines, overlays, degrees=False):
    """Put the comparison entries' curves into the line slots (in their colours); returns their peak."""
    peak = 0.0
    for k, line in enumerate(lines):
        if k < len(overlays):
            o = overlays[k]
            v = _finite(o.values)
            line.set_data(np.degrees(o.angles) if degrees else o.angles, v)
            line.set_color(o.colour)
            line.set_visible(True)
            peak = max(peak, float(v.max(initial=0.0)))
        else:
            line.set_data([], [])
            line.set_visible(False)
    return peak


class BlitFigure:
    """A Matplotlib figure redrawn by blitting its animated artists over a saved background.

    Parameters
    ----------
    size_px : (int, int)
        Width and height in pixels (at ``dpi``).  A host (``pyvista.ChartMPL``) may
        resize the figure; the next update then draws in full.
    dpi : float
        Pixels per inch: font sizes are in points, so a larger ``dpi`` scales the
        whole layout (the window passes ``100 × height / 768``).
    captions : bool
        Draw the texts that change with the data (titles with numbers).  Text is the
        slow part of a blit; a host that can draw text faster shows
        :attr:`captions` itself and passes False.

    Attributes
    ----------
    captions : dict
        The current caption texts by key (``"title"``, ...).
    on_image : callable or None
        Called with the RGBA buffer ``(H, W, 4)`` after every update (the window
        pushes it into its chart).
    full_draws, blits : int
        How many updates drew everything, and how many only the data.
    """

    def __init__(self, size_px, dpi: float = 100, *, captions: bool = True):
        self.captions: dict[str, str] = {}
        self._caption_artists: dict = {}
        self.show_captions = bool(captions)
        with matplotlib.rc_context(STYLE):
            self.fig = Figure(figsize=(size_px[0] / dpi, size_px[1] / dpi), dpi=dpi)
            FigureCanvasAgg(self.fig)
            self._build()
        self.fig.patch.set_alpha(0.0)
        self._animated: list = []
        self._animated_axes: list = []
        self._bg_axes = None  # (the axes' key, the background with the axes drawn on it)
        self._bg = None
        self._bg_size = None
        self._dirty = True
        self.on_image = None
        self.full_draws = 0
        self.blits = 0
        self.fig.canvas.mpl_connect("draw_event", self._on_draw)
        for artist in self._data_artists():
            self._animate(artist)
        for axis in self._data_axes():
            self._animate_axis(axis)
        for artist in self._caption_artists.values():
            self._animate(artist)
            artist.set_visible(self.show_captions)

    # subclasses: build axes/artists in _build, list data artists in _data_artists, fill them in set_data
    def _build(self):  # pragma: no cover - abstract
        raise NotImplementedError

    def _data_artists(self) -> list:  # pragma: no cover - abstract
        raise NotImplementedError

    def _data_axes(self) -> list:
        """The axes (``Axis``) whose limits follow the data: blitted with it (:meth:`_animate_axis`)."""
        return []

    def _caption(self, key, artist):
        """Register a text that changes with the data (drawn by the figure only if ``show_captions``)."""
        self._caption_artists[key] = artist
        return artist

    def _set_caption(self, key, text):
        self.captions[key] = text
        self._caption_artists[key].set_text(text)

    def _animate(self, artist):
        artist.set_animated(True)
        self._animated.append(artist)
        return artist

    #: Margins kept in pixels whatever the figure's size: ``(left, right, top, bottom, column gap, row gap)``
    #: around the grid of axes made in ``_build`` (``_grid`` rows × columns); None keeps ``_build``'s fractions.
    MARGINS_PX: tuple | None = None
    _grid = (1, 1)

    def relayout(self) -> None:
        """Place the axes with :attr:`MARGINS_PX` at the figure's current size (a resized panel).

        Tick labels and titles take the same pixels at any size, so fixed fractions let them collide in
        a small panel and waste room in a large one.
        """
        if self.MARGINS_PX is None:
            return
        w, h = (float(x) for x in self.fig.get_size_inches() * self.fig.dpi)
        left, right, top, bottom, gap_w, gap_h = self.MARGINS_PX
        rows, cols = self._grid
        inner_w = max(w - left - right - (cols - 1) * gap_w, 1.0)
        inner_h = max(h - top - bottom - (rows - 1) * gap_h, 1.0)
        if inner_w < 0.2 * w or inner_h < 0.2 * h:
            return  # too small for the margins: keep the last layout rather than axes of no size
        self.fig.subplots_adjust(left=left / w, right=1.0 - right / w, top=1.0 - top / h, bottom=bottom / h,
                                 wspace=gap_w / (inner_w / cols), hspace=gap_h / (inner_h / rows))  # fmt: skip

    def _animate_axis(self, axis):
        """Make a data-following axis (its ticks, labels and grid) part of the blit, drawn under the data.

        A new limit then redraws that axis over the saved background instead of the whole figure: the
        slow full draw (every axis, tick and text) is left to resizes and new layouts.
        """
        axis.set_animated(True)
        axis._explorer_blitted = True
        self._animated_axes.append(axis)
        return axis

    def _axes_key(self) -> tuple:
        """What the blitted axes look like: their axes' data limits (ticks and labels follow from them)."""
        return tuple(tuple(a.axes.viewLim.bounds) for a in self._animated_axes)

    def invalidate(self):
        """Draw everything at the next update (axis limits or labels changed)."""
        self._dirty = True

    def _on_draw(self, event=None):
        # After any full draw (ours, or the host's after a resize): keep the background, add the data.
        canvas = self.fig.canvas
        self._bg = canvas.copy_from_bbox(self.fig.bbox)
        self._bg_size = canvas.get_width_height()
        self._bg_axes = None
        self._draw_animated()

    def _draw_animated(self):
        # Two levels: the background, then the data-following axes (text: the costly part, drawn again only
        # when a limit moved, else restored with them as a second background), then the data.
        key = self._axes_key()
        if self._animated_axes:
            if self._bg_axes is not None and self._bg_axes[0] == key:
                self.fig.canvas.restore_region(self._bg_axes[1])
            else:
                for a in self._animated_axes:
                    if a.get_visible():
                        self.fig.draw_artist(a)
                self._bg_axes = (key, self.fig.canvas.copy_from_bbox(self.fig.bbox))
        for a in self._animated:
            if a.get_visible():
                self.fig.draw_artist(a)

    def render(self) -> np.ndarray:
        """Redraw (blit if possible) and return the RGBA buffer ``(H, W, 4)`` (a view: copy to keep it).

        Returns
        -------
        ndarray of uint8, shape (H, W, 4)
            The figure's pixels (also passed to :attr:`on_image` when set).
        """
        canvas = self.fig.canvas
        if self._dirty or self._bg is None or self._bg_size != canvas.get_width_height():
            self.relayout()
            with matplotlib.rc_context(STYLE):
                canvas.draw()  # fires draw_event → _on_draw
            self._dirty = False
            self.full_draws += 1
        else:
            canvas.restore_region(self._bg)
            self._draw_animated()
            self.blits += 1
        rgba = np.asarray(canvas.buffer_rgba())
        if self.on_image is not None:
            self.on_image(rgba)
        return rgba

    def _ylim(self, ax, peak: float):
        """Set ``ax``'s y range to ``[0, limit]`` following ``peak`` with hysteresis; returns the limit."""
        lo, hi = ax.get_ylim()
        current = hi if getattr(ax, "_explorer_auto", False) else None
        new = hysteresis_limit(peak, current)
        if new != current:
            ax.set_ylim(0.0, new)
            ax._explorer_auto = True
            if not getattr(ax.yaxis, "_explorer_blitted", False):
                self._dirty = True
        return new


# =============================================================================== panels
class ProfilePlot(BlitFigure):
    """Intensity along the scan line (Gouraud against Phong interpolation) and its second difference."""

    MARGINS_PX = (50, 10, 10, 36, 0, 8)
    _grid = (2, 1)

    def _build(self):
        fig = self.fig
        self.ax, self.ax2 = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [2.2, 1]})
        fig.subplots_adjust(left=0.16, right=0.965, top=0.88, bottom=0.145, hspace=0.12)
        ax, ax2 = self.ax, self.ax2
        (self.g_line,) = ax.plot([], [], color=COLOURS["gouraud"], label="Gouraud")
        (self.p_line,) = ax.plot([], [], color=COLOURS["phong"], label="Phong")
        (self.g_d2,) = ax2.plot([], [], color=COLOURS["gouraud"], lw=1.0)
        (self.p_d2,) = ax2.plot([], [], color=COLOURS["phong"], lw=1.0)
        self.edges = LineCollection([], colors=COLOURS["edge"], linewidths=0.6, linestyles=":", alpha=0.7)
        ax.add_collection(self.edges)
        ax.set_xlim(-1.02, 1.02)
        ax.set_ylabel("intensity I(x)")
        ax2.set_ylabel("Δ²I ÷ |ΔI|")
        ax2.set_ylim(-D2_LIMIT, D2_LIMIT)  # fixed: kinks are ~0.1-1 of the mean slope; larger ones clip
        ax2.set_xlabel("x (sphere radii), ⋮ triangle edges", labelpad=1)
        ax.legend(loc="upper left", ncol=2, borderaxespad=0.1, handlelength=1.5, columnspacing=0.8)
        ax.grid(True)
        ax2.grid(True)
        ax.tick_params(labelbottom=False)
        self._caption("title", fig.text(0.5, 0.95, "", ha="center", va="center", fontsize=8.5))

    def _data_artists(self):
        return [self.g_line, self.p_line, self.g_d2, self.p_d2, self.edges]

    def _data_axes(self):
        return [self.ax.yaxis]

    def set_data(self, profile, channel_label: str = "luminance Y"):
        """Show a :class:`~explorer.app.views.ProfileView`.

        Parameters
        ----------
        profile : ProfileView
            The scan line's data.
        channel_label : str
            The plotted channel, for the axis label.
        """
        x = profile.x
        g, p = _finite(profile.gouraud), _finite(profile.phong)
        self.g_line.set_data(x, g)
        self.p_line.set_data(x, p)
        xm = x[1:-1] if x.size > 2 else x[:0]
        # Second differences relative to the row's mean slope (as the metric measures them), so one
        # fixed axis suits every light and tessellation.
        scale = profile.slope if profile.slope > 0 else 1.0
        gd2, pd2 = _finite(profile.gouraud_d2) / scale, _finite(profile.phong_d2) / scale
        self.g_d2.set_data(xm, gd2)
        self.p_d2.set_data(xm, pd2)
        peak = float(max(g.max(initial=0.0), p.max(initial=0.0)))
        top = self._ylim(self.ax, peak)
        self.edges.set_segments([[(e, 0.0), (e, top)] for e in profile.edges])
        self._set_caption(
            "title",
            f"Scan line {profile.row} ({channel_label}) — Mach-band metric: "
            f"Gouraud {profile.metric_gouraud:.2f}, Phong {profile.metric_phong:.2f}",
        )


def radial_scale(top: float) -> tuple[float, str]:
    """The factor the radial labels of a polar axis up to ``top`` are divided by, and its caption.

    Polar axes draw no offset text, so a radial axis up to 7.9e15 would read "1.0, 0.75, …" with
    nothing to say "× 1e16".  Labels are given in units of a power of ten, named by the caption.

    Parameters
    ----------
    top : float
        The largest value to show.

    Returns
    -------
    factor : float
        What the radial labels are divided by (a power of ten).
    caption : str
        The scale's caption (empty when the factor is 1).

    Examples
    --------
    >>> radial_scale(0.8), radial_scale(7.9e15), radial_scale(2e-5)
    ((1.0, ''), (1000000000000000.0, 'radius × 1e15'), (1e-05, 'radius × 1e-5'))
    """
    if not (math.isfinite(top) and top > 0) or 1e-2 <= top < 1e4:
        return 1.0, ""
    exponent = math.floor(math.log10(top))
    return 10.0**exponent, f"radius × 1e{exponent}"


class PolarPlot(BlitFigure):
    """The polar slice in the plane of incidence, with the incident and mirror directions."""

    MARGINS_PX = (34, 34, 14, 50, 0, 0)

    def _build(self):
        fig = self.fig
        ax = fig.add_subplot(projection="polar")
        fig.subplots_adjust(left=0.09, right=0.91, top=0.99, bottom=0.16)
        ax.set_theta_zero_location("N")
        ax.set_theta_direction(-1)
        ax.set_thetamin(-90)
        ax.set_thetamax(90)
        ax.set_xticks(np.radians([-90, -60, -30, 0, 30, 60, 90]))
        ax.set_xticklabels(["−90°", "−60°", "−30°", "n", "30°", "60°", "90°"])
        ax.grid(True)
        ax.tick_params(axis="y", labelsize=6.5, colors=COLOURS["muted"])
        ax.yaxis.set_major_locator(MaxNLocator(4))
        # Polar axes draw no offset text ("1e16"): the labels are in units of radial_scale, named below the axis.
        self._r_scale = 1.0
        ax.yaxis.set_major_formatter(FuncFormatter(lambda x, pos: f"{x / self._r_scale:.3g}"))
        self._caption("scale", ax.text(1.0, 0.2, "", transform=ax.transAxes, ha="right", va="bottom", fontsize=6.5,
                                       color=COLOURS["muted"]))  # fmt: skip
        self.ax = ax
        (self.light_ray,) = ax.plot([], [], color=COLOURS["light"], lw=1.6, label="light l")
        (self.mirror_ray,) = ax.plot([], [], color=COLOURS["mirror"], lw=1.2, ls="--", label="mirror R")
        (self.fixed_light,) = ax.plot([], [], color=COLOURS["luminance"], lw=1.6, label="f(l fixed, v swept)")
        (self.fixed_view,) = ax.plot(
            [], [], color=COLOURS["muted"], lw=1.0, ls=(0, (4, 2)), label="f(v fixed, l swept)"
        )
        # The comparison entries' light-fixed slices, each in its entry's colour, under the current model's.
        self.overlay_lines = [ax.plot([], [], lw=1.3, zorder=1.5)[0] for _ in range(OVERLAY_SLOTS)]
        fig.legend(loc="lower center", bbox_to_anchor=(0.5, 0.0), ncol=2, handlelength=1.6, columnspacing=0.8)
        # An ideal mirror's Dirac delta: a spike at the mirror direction, as tall as the reflected fraction R.
        (self.spike,) = ax.plot([], [], color=COLOURS["mirror"], lw=2.6, solid_capstyle="butt")
        (self.spike_head,) = ax.plot([], [], color=COLOURS["mirror"], marker="^", ms=6, ls="none")
        self.spike_label = ax.text(0.0, 0.0, "", color=COLOURS["mirror"], fontsize=8, ha="left", va="bottom")
        self._caption("title", fig.text(0.5, 0.955, "", ha="center", va="center", fontsize=8.5))
        self._caption("note", fig.text(0.5, 0.5, "", ha="center", va="center", fontsize=9, color=COLOURS["mirror"]))

    def _data_artists(self):
        return [self.light_ray, self.mirror_ray, *self.overlay_lines, self.fixed_light, self.fixed_view, self.spike,
                self.spike_head, self.spike_label]  # fmt: skip

    def _data_axes(self):
        return [self.ax.yaxis]

    def set_data(self, polar, *, channel="luminance", label="f_r"):
        """Show a :class:`~explorer.app.views.PolarView`.

        Parameters
        ----------
        polar : PolarView
            The two slices.
        channel : str
            The plotted channel (its colour).
        label : str
            What the values are (:meth:`~explorer.app.state.AppState.quantity_label`).

        The shown comparison entries' slices (polar.overlays) are drawn in their colours; the
        radial scale follows them and the current model's solid curve.
        """
        a = _finite(polar.light_fixed)
        overlay_peak = _set_overlays(self.overlay_lines, getattr(polar, "overlays", ()))
        b = _finite(polar.view_fixed)
        self.fixed_light.set_data(polar.angles, a)
        self.fixed_view.set_data(polar.view_angles, b)
        self.fixed_light.set_color(COLOURS.get(channel, COLOURS["luminance"]))
        # The scale follows the main slice; the swapped one (dashed) may leave the plot where a
        # non-reciprocal model (Phong's 1/(n·l)) grows toward grazing light.
        spike = float(getattr(polar, "spike", 0.0))
        peak = max(float(a.max(initial=0.0)), spike, overlay_peak)
        lo, hi = self.ax.get_ylim()
        current = hi if getattr(self.ax, "_explorer_auto", False) else None
        top = hysteresis_limit(peak, current)
        if top != current:
            self.ax.set_ylim(0.0, top)
            self.ax._explorer_auto = True
            self._r_scale, caption = radial_scale(top)
            self._set_caption("scale", caption)
            if not getattr(self.ax.yaxis, "_explorer_blitted", False):
                self._dirty = True
        t = polar.theta_in
        self.light_ray.set_data([-t, -t], [0.0, top])
        self.mirror_ray.set_data([t, t], [0.0, top])
        if spike > 0:
            s_at = float(getattr(polar, "spike_angle", t))
            self.spike.set_data([s_at, s_at], [0.0, spike])
            self.spike_head.set_data([s_at], [spike])
            self.spike_label.set_position((s_at, spike))
            self.spike_label.set_text(f"  δ: R = {spike:.3g}")
        else:
            self.spike.set_data([], [])
            self.spike_head.set_data([], [])
            self.spike_label.set_text("")
        self._set_caption("title", f"Polar slice, plane of incidence: {label}   θ_l = {math.degrees(t):.0f}°")
        self._set_caption("note", "light below the horizon: no reflection" if polar.below_horizon else "")


class AnglePlots(BlitFigure):
    """Value against θ_v, θ_h and θ_d, and the image over (θ_h, θ_d) — the usual BRDF-tool views."""

    #: The panels' arrangement: one row of four (a wide strip), or two rows of two (a squarer panel).
    GRID = (1, 4)

    def _build(self):
        fig = self.fig
        if self.GRID == (2, 2):
            axs = fig.subplots(2, 2, gridspec_kw={"width_ratios": [1.15, 1]}).ravel()
            fig.subplots_adjust(left=0.11, right=0.93, top=0.93, bottom=0.1, wspace=0.42, hspace=0.55)
        else:
            axs = fig.subplots(1, 4, gridspec_kw={"width_ratios": [1.25, 1, 1, 1.05]})
            fig.subplots_adjust(left=0.065, right=0.95, top=0.8, bottom=0.2, wspace=0.45)
        self.axes = axs
        grid = self.GRID == (2, 2)
        titles = ["vs θ_v (view)", "vs θ_h (half)", "vs θ_d (difference)", "θ_h →, θ_d ↑"]
        if grid:  # a squarer panel: each plot about half as wide, so shorter titles and fewer ticks
            titles = ["θ_v (view)", "θ_h (half)", "θ_d (difference)", "f(θ_h, θ_d)"]
        self.curves, self.markers = [], []
        for ax, title in zip(axs, titles, strict=True):
            ax.set_title(title, pad=3)
            ax.grid(True)
        self.overlay_lines = []
        for ax in axs[:3]:
            self.overlay_lines.append([ax.plot([], [], lw=1.2)[0] for _ in range(OVERLAY_SLOTS)])
            (line,) = ax.plot([], [], color=COLOURS["luminance"])
            self.curves.append(line)
        axs[0].set_xlim(-90, 90)
        axs[0].set_xticks([-90, 0, 90] if grid else [-90, -45, 0, 45, 90])
        for ax in axs[1:]:
            ax.set_xlim(0, 90)
            ax.set_xticks([0, 45, 90] if grid else [0, 30, 60, 90])
        for ax in axs[:3]:
            ax.set_xlabel("degrees", labelpad=1)
        self.markers.append(axs[0].axvline(0, color=COLOURS["light"], lw=1.0))
        self.markers.append(axs[0].axvline(0, color=COLOURS["mirror"], lw=1.0, ls="--"))
        self.markers.append(axs[1].axvline(0, color=COLOURS["mirror"], lw=1.0, ls="--"))
        self.markers.append(axs[2].axvline(0, color=COLOURS["light"], lw=1.0))
        im_ax = axs[3]
        self.image = im_ax.imshow(
            np.zeros((2, 2)), origin="lower", extent=(0, 90, 0, 90), vmin=0.0, vmax=1.0, cmap="viridis",
            aspect="auto", interpolation="nearest",
        )  # fmt: skip
        im_ax.set_yticks([0, 45, 90] if grid else [0, 30, 60, 90])
        im_ax.set_xlabel("θ_h (degrees)" if grid else "degrees", labelpad=1)
        im_ax.set_ylabel("θ_d", labelpad=1)
        im_ax.grid(False)
        (self.im_marker,) = im_ax.plot([], [], marker="o", ms=5, mfc="none", mec=COLOURS["mirror"], ls="none")
        # The colour bar in the image's own axes coordinates, so that it follows the image when the axes move.
        cbar = fig.colorbar(self.image, cax=im_ax.inset_axes([1.06, 0.0, 0.07, 1.0]))
        cbar.set_ticks([0, 0.5, 1])
        cbar.ax.tick_params(labelsize=6, pad=1)
        self._caption("title", fig.text(0.5, 0.94, "", ha="center", va="center", fontsize=8.5))
        self._caption(
            "peak",
            im_ax.text(0.97, 0.03, "", transform=im_ax.transAxes, ha="right", va="bottom", fontsize=6.5, color="white"),
        )

    def _data_artists(self):
        return [line for lines in self.overlay_lines for line in lines] + self.curves + self.markers + [
            self.image, self.im_marker]  # fmt: skip

    def _data_axes(self):
        return [ax.yaxis for ax in self.axes[:3]]

    def set_data(self, theta_v, theta_h, theta_d, halfdiff, *, channel="luminance", label="f_r"):
        """Show three :class:`~explorer.app.views.CurveView` and a :class:`~explorer.app.views.HalfDiffView`.

        Parameters
        ----------
        theta_v, theta_h, theta_d : CurveView
            The three angle curves (their ``overlays``, the comparison entries', drawn in their colours;
            the axes follow them too).
        halfdiff : HalfDiffView
            The half/difference image.
        channel : str
            The plotted channel (its colour).
        label : str
            What the values are.
        """
        colour = COLOURS.get(channel, COLOURS["luminance"])
        tl = math.degrees(theta_v.markers[1])
        # Models with 1/(n·l) (Phong, unnormalized Blinn-Phong) grow without bound toward grazing: the
        # θ_h and θ_d axes are scaled to the values up to 80° (or the current incidence, if larger),
        # and the curve leaves the plot beyond.
        reach = max(GRAZING_DEG, tl + 2.0)
        for k, (ax, line, c) in enumerate(zip(self.axes[:3], self.curves, (theta_v, theta_h, theta_d), strict=True)):
            v = _finite(c.values)
            deg = np.degrees(c.angles)
            line.set_data(deg, v)
            line.set_color(colour)
            scaled = v if k == 0 else v[deg <= (GRAZING_DEG if k == 1 else reach)]
            top = float(scaled.max(initial=0.0))
            overlays = getattr(c, "overlays", ())
            _set_overlays(self.overlay_lines[k], overlays, degrees=True)
            for o in overlays:
                od, ov = np.degrees(o.angles), _finite(o.values)
                top = max(top, float((ov if k == 0 else ov[od <= (GRAZING_DEG if k == 1 else reach)]).max(initial=0.0)))
            self._ylim(ax, top)
        self.markers[0].set_xdata([-tl, -tl])
        self.markers[1].set_xdata([tl, tl])
        self.markers[2].set_xdata([0.0, 0.0])
        td = math.degrees(theta_d.markers[0])
        self.markers[3].set_xdata([td, td])
        vals = _finite(halfdiff.values)
        peak = float(vals.max(initial=0.0))
        # The colour scale ends at the largest value away from grazing (θ_h <= 80°, θ_d <= 80° or the
        # current incidence): a 1/(n·l) spike at grazing would otherwise leave the rest black.
        th, td = np.degrees(halfdiff.theta_h), np.degrees(halfdiff.theta_d)
        inner = vals[np.ix_(td <= reach, th <= GRAZING_DEG)]
        top = float(inner.max(initial=0.0))
        top = top if top > 0 else (peak if peak > 0 else 1.0)
        self.image.set_data(np.minimum(vals / top, 1.0))
        self.im_marker.set_data([math.degrees(halfdiff.marker[0])], [math.degrees(halfdiff.marker[1])])
        self._set_caption(
            "peak", f"colour 1 = {top:.3g}" + (f" (peak {peak:.3g} at grazing)" if peak > 1.001 * top else "")
        )
        self._set_caption(
            "title",
            f"{label} against the Rusinkiewicz angles (θ_h at θ_d = θ_l, θ_d at θ_h = 0, image at φ_d = 90°)",
        )


class AnglePlotsGrid(AnglePlots):
    """The angle plots in two rows of two, for a panel about as tall as it is wide."""

    GRID = (2, 2)
    MARGINS_PX = (40, 44, 18, 32, 56, 46)
    _grid = (2, 2)


class AlbedoPlot(BlitFigure):
    """The directional albedo ``ρ(θ_v)`` of the current model and of each shown comparison entry.

    The axes fill the figure but for the tick labels' room (:attr:`MARGINS_PX`); the legend is inside them.

    Each curve is drawn in its colour (the current model white) with its error as a band (``± error``;
    at the quadrature's usual 1e-5 thinner than the line), and every value whose relative error is
    above 2 % (:attr:`lighting.integrate.AlbedoCurve.unconverged`) is circled in red.  The legend names
    the curves.
    """

    MARGINS_PX = (54, 12, 14, 34, 0, 0)

    def _build(self):
        fig = self.fig
        ax = fig.add_subplot()
        fig.subplots_adjust(left=0.12, right=0.97, top=0.92, bottom=0.16)
        ax.set_xlim(0, 90)
        ax.set_xticks([0, 15, 30, 45, 60, 75, 90])
        ax.set_xlabel("view angle θ_v (degrees)", labelpad=1)
        ax.set_ylabel("albedo ρ(θ_v)", labelpad=2)
        ax.grid(True)
        self.ax = ax
        n = 1 + OVERLAY_SLOTS
        self.bands = [ax.fill_between([0.0], [0.0], [0.0], alpha=0.35, lw=0) for _ in range(n)]
        self.lines = [ax.plot([], [], lw=1.5, marker=".", ms=3)[0] for _ in range(n)]
        (self.flags,) = ax.plot([], [], ls="none", marker="o", ms=7, mfc="none", mec=COLOURS["mirror"], mew=1.4)
        self._labels: tuple = ()
        self._legend = None
        self._caption("title", fig.text(0.5, 0.94, "", ha="center", va="center", fontsize=8.5))
        self._caption("flags", fig.text(0.62, 0.05, "", ha="left", va="bottom", fontsize=7, color=COLOURS["mirror"]))

    def _data_artists(self):
        return [*self.bands, *self.lines, self.flags]

    def _data_axes(self):
        return [self.ax.yaxis]

    def set_data(self, curves, *, channel="luminance"):
        """Show the :class:`~explorer.app.comparing.AlbedoCurveView` of each BRDF (the current model first).

        Parameters
        ----------
        curves : sequence of AlbedoCurveView
            The curves (``colour`` None: the current model, drawn in the channel's colour).
        channel : str
            The plotted channel.
        """
        peak, flagged, worst = 0.0, 0, 0.0
        fx, fy = [], []
        handles = []
        for k, (line, band) in enumerate(zip(self.lines, self.bands, strict=True)):
            if k >= len(curves):
                line.set_visible(False)
                band.set_visible(False)
                continue
            c = curves[k]
            colour = c.colour or COLOURS.get(channel, COLOURS["luminance"])
            deg = np.degrees(c.theta)
            v, e = _finite(c.value), _finite(c.error)
            line.set_data(deg, v)
            line.set_color(colour)
            line.set_visible(True)
            outline = np.column_stack([np.concatenate([deg, deg[::-1]]), np.concatenate([v - e, (v + e)[::-1]])])
            band.set_verts([outline])
            band.set_facecolor(colour)
            band.set_visible(True)
            peak = max(peak, float((v + e).max(initial=0.0)))
            flags = np.asarray(c.unconverged, dtype=bool)
            fx += list(deg[flags])
            fy += list(v[flags])
            flagged += int(flags.sum())
            with np.errstate(divide="ignore", invalid="ignore"):
                rel = np.where(np.abs(v) > 0, e / np.abs(v), 0.0)
            worst = max(worst, float(rel.max(initial=0.0)))
            handles.append(line)
        self.flags.set_data(fx, fy)
        self._ylim(self.ax, max(peak, 0.1))
        labels = tuple((c.label, c.colour) for c in curves) + (channel,)
        if labels != self._labels:
            if self._legend is not None:
                self._legend.remove()
            with matplotlib.rc_context(STYLE):
                # Inside the axes, where the curves leave room (albedo falls toward grazing views): the
                # panel's width goes to the plot, and a long label is never cut at the figure's edge.
                self._legend = self.ax.legend(handles, [c.label for c in curves], loc="best", framealpha=0.7,
                                              facecolor="#1e2024", edgecolor="#495057", handlelength=1.4,
                                              fontsize=6.5)  # fmt: skip
            for text, h in zip(self._legend.get_texts(), handles, strict=True):
                text.set_color(h.get_color())
            self._labels = labels
            self._dirty = True
        samples = curves[0].samples if curves else 0
        self._set_caption("title", f"Albedo ρ(θ_v) = ∫ f_r (n·l) dω_l by quadrature ({samples} nodes), band ± error")
        self._set_caption(
            "flags",
            f"○ {flagged} value{'s' if flagged != 1 else ''} unconverged (error > 2 %)" if flagged
            else f"all converged (largest error {100 * worst:.2g} %)",
        )

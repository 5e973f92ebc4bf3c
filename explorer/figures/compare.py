"""Several BRDFs side by side: one plotting verb for a :class:`~explorer.compare.BRDFList`, and its lecture figure.

:func:`plot_brdfs` draws every *shown* entry of a list (solo honoured, hidden entries left out) in the
entry's colour, in up to four views: the polar slice in the plane of incidence for a fixed light, the
BRDF against Rusinkiewicz's ``θ_h`` and ``θ_d``, and the directional albedo ``ρ(θ_v)`` with its error
estimate and a mark on every value the integrator flags as unconverged.  Every number drawn comes from
:mod:`lighting.analysis` and :func:`lighting.integrate.albedo_curve`; nothing here evaluates a BRDF.

The figure ``compare_brdfs`` puts a measured stand-in, a Cook–Torrance GGX fitted to it, a model read
from a ``.brdf`` file and a built-in model in one list; its second row shows one entry solo.
"""

from __future__ import annotations

import math
import os
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from lighting import load_brdf
from lighting.analysis import polar_slice, theta_d_curve, theta_h_curve
from lighting.analysis.fit import fit_brdf
from lighting.analysis.quantity import LUMINANCE
from lighting.integrate import UNCONVERGED_RELATIVE_ERROR, AlbedoCurve, albedo_curve
from lighting.models import BlinnPhong, CookTorrance
from lighting.models.base import BRDF

from ..compare import COMPARE_COLOURS, BRDFList
from .base import SLIDE_SIZES, VEC, new_figure, register
from .zoo import half_disc

__all__ = ["VIEWS", "ComparisonPlot", "plot_brdfs", "albedo_channel", "compare_brdfs"]

#: The views :func:`plot_brdfs` draws, in its default order.
VIEWS = ("polar", "theta_h", "theta_d", "albedo")

_CHANNELS = {"r": 0, "red": 0, "g": 1, "green": 1, "b": 2, "blue": 2, "luminance": "luminance", "y": "luminance"}
_CHANNEL_ALLOWED = "0, 1, 2, 'r', 'g', 'b' or 'luminance'"


def _check_channel(channel):
    if isinstance(channel, int | np.integer) and not isinstance(channel, bool | np.bool_) and 0 <= channel <= 2:
        return int(channel)
    if isinstance(channel, str) and channel.strip().lower() in _CHANNELS:
        return _CHANNELS[channel.strip().lower()]
    raise ValueError(f"channel must be {_CHANNEL_ALLOWED}; got {channel!r}")


def albedo_channel(curve: AlbedoCurve, channel="luminance"):
    """One channel of an albedo curve: the value, its error estimate and its convergence flag.

    Parameters
    ----------
    curve : lighting.integrate.AlbedoCurve
        The RGB albedo, error and flags of :func:`lighting.integrate.albedo_curve`.
    channel : int or str, optional
        ``0``/``1``/``2``, ``"r"``/``"g"``/``"b"``, or ``"luminance"`` (Rec. 709 weights
        :data:`lighting.analysis.quantity.LUMINANCE`, which sum to 1: a grey albedo keeps its value).

    Returns
    -------
    albedo, error : numpy.ndarray, shape (T,)
        The channel's albedo and error estimate.  The luminance's error is ``Σ w_c error_c``: the
        errors of one integration share its nodes (or samples), so they add, at most, linearly.
    unconverged : numpy.ndarray of bool, shape (T,)
        :attr:`~lighting.integrate.AlbedoCurve.unconverged` of that channel; for the luminance, true
        where any channel is unconverged.

    Raises
    ------
    ValueError
        ``channel`` is none of the above.

    Examples
    --------
    >>> from lighting import Lambert
    >>> rho, err, flag = albedo_channel(albedo_curve(Lambert((0.2, 0.5, 0.8)), [0.0, 1.0]))
    >>> rho.round(6).tolist(), flag.tolist()  # 0.2126·0.2 + 0.7152·0.5 + 0.0722·0.8
    ([0.45788, 0.45788], [False, False])
    """
    c = _check_channel(channel)
    if c == "luminance":
        w = np.asarray(LUMINANCE, dtype=curve.albedo.dtype)
        return curve.albedo @ w, curve.error @ w, curve.unconverged.any(axis=-1)
    return curve.albedo[:, c], curve.error[:, c], curve.unconverged[:, c]


@dataclass
class ComparisonPlot:
    """What :func:`plot_brdfs` drew.

    Attributes
    ----------
    figure : matplotlib.figure.Figure
        The figure holding the axes.
    axes : dict
        View name → its :class:`~matplotlib.axes.Axes`.
    shown : list of (int, Entry)
        The entries drawn, with their index in the list (the ``gid`` of their artists is
        ``"VIEW:INDEX"``, e.g. ``"albedo:2"``; the albedo band is ``"albedo-band:INDEX"`` and the
        unconverged marks ``"albedo-flags:INDEX"``).
    albedo : dict
        Index → the :class:`~lighting.integrate.AlbedoCurve` of that entry (when the albedo view is drawn).
    legend : matplotlib.legend.Legend or None
        The legend naming the entries (and the albedo band and flag).
    """

    figure: object
    axes: dict
    shown: list
    albedo: dict = field(default_factory=dict)
    legend: object = None


def _as_list(brdfs) -> BRDFList:
    if isinstance(brdfs, BRDFList):
        return brdfs
    if isinstance(brdfs, BRDF):
        return BRDFList([brdfs], max_entries=1)
    if not isinstance(brdfs, Sequence) or isinstance(brdfs, str | bytes):
        raise TypeError(f"brdfs must be a BRDFList, a BRDF or a list of BRDFs or (BRDF, label) pairs; "
                        f"got {type(brdfs).__name__}")  # fmt: skip
    items = [tuple(b) if isinstance(b, list) else b for b in brdfs]
    return BRDFList(items, max_entries=max(1, len(items)))


def _per_entry(name, value, count, check):
    """``value`` for every entry: one value for all, or a sequence with one per list entry."""
    if isinstance(value, Sequence) and not isinstance(value, str):
        if len(value) != count:
            raise ValueError(f"{name} must be one value or one per entry of the list ({count}); got {len(value)}")
        return [check(v) for v in value]
    return [check(value)] * count


def _check_views(views):
    if isinstance(views, str):
        views = (views,)
    views = tuple(views)
    bad = [v for v in views if v not in VIEWS]
    if not views or bad or len(set(views)) != len(views):
        raise ValueError(f"views must be distinct names among {', '.join(VIEWS)}; got {views!r}")
    return views


def _axes_for(views, fig, axes):
    if axes is not None:
        axes = list(axes)
        if len(axes) != len(views):
            raise ValueError(f"axes must hold one Axes per view ({len(views)}); got {len(axes)}")
        return axes[0].figure, dict(zip(views, axes, strict=True))
    if fig is None:
        fig = new_figure(*SLIDE_SIZES["16:9"])
    # Up to three views in a row; four in two rows of two, so that a new figure is one 16:9 slide.
    cols = len(views) if len(views) <= 3 else 2
    rows = math.ceil(len(views) / cols)
    ratios = [max(1.5 if v == "polar" else 1.0 for v in views[c::cols]) for c in range(cols)]
    grid = fig.add_gridspec(rows, cols, width_ratios=ratios)
    return fig, {v: fig.add_subplot(grid[i // cols, i % cols]) for i, v in enumerate(views)}


def plot_brdfs(
    brdfs,
    *,
    theta_l: float = math.radians(45.0),
    phi_l: float = 0.0,
    views=VIEWS,
    channel="luminance",
    log: bool = False,
    theta_d: float = 0.0,
    theta_h: float = 0.0,
    n: int = 361,
    curve_n: int = 181,
    albedo_thetas=None,
    albedo_samples=4096,
    albedo_method="quadrature",
    seed: int = 0,
    fig=None,
    axes=None,
    legend=True,
    titles: bool = True,
) -> ComparisonPlot:
    """Draw the shown entries of a list of BRDFs side by side, each in its colour.

    Parameters
    ----------
    brdfs : BRDFList, BRDF, or list of BRDF or (BRDF, label)
        What to compare.  A :class:`~explorer.compare.BRDFList` is drawn as it stands: its shown
        entries (:meth:`~explorer.compare.BRDFList.shown`: the solo one alone, else the visible ones)
        in their colours; a plain list becomes a list with every entry shown.
    theta_l, phi_l : float, optional
        The light's polar angle and azimuth (radians) of the polar view.
    views : sequence of str, optional
        Among :data:`VIEWS`: ``"polar"`` (:func:`~lighting.analysis.polar_slice`, light fixed at
        ``theta_l``, the view swept across the plane of incidence; a half disc, mirror side right),
        ``"theta_h"`` (:func:`~lighting.analysis.theta_h_curve` at ``theta_d``), ``"theta_d"``
        (:func:`~lighting.analysis.theta_d_curve` at ``theta_h``) and ``"albedo"`` (``ρ(θ_v)`` of
        :func:`~lighting.integrate.albedo_curve`, a ±2σ band of its error estimate, and a hollow mark on
        every value :attr:`~lighting.integrate.AlbedoCurve.unconverged` flags: relative error above
        :data:`~lighting.integrate.UNCONVERGED_RELATIVE_ERROR`).
    channel : int or str, optional
        What is plotted of the RGB values: ``"luminance"`` (default), or one channel (see
        :func:`albedo_channel`).
    log : bool or sequence of str, optional
        Plot ``log10(1 + f_r)`` (the engine's ``log`` option) in the three BRDF views (``True``) or in
        those named (e.g. ``("theta_h", "theta_d")``: a microfacet model's ``θ_d`` curve grows without
        bound toward grazing); the albedo stays linear.
    theta_d, theta_h : float, optional
        The fixed angle of the ``θ_h`` view (default ``θ_d = 0``: ``l = v``, the back-scatter curve) and
        of the ``θ_d`` view (default ``θ_h = 0``: ``h = n``, the specular peak toward grazing).
    n, curve_n : int, optional
        Samples of the polar slice and of the ``θ_h``/``θ_d`` curves.
    albedo_thetas : array_like, optional
        View angles of the albedo (radians); default 0°, 2°, …, 88° and 89° (at exactly 90° ``n·v = 0``
        and every albedo is 0 by the engine's horizon convention).
    albedo_samples, albedo_method : int or str, or a sequence with one per list entry, optional
        Cost and method of each entry's :func:`~lighting.integrate.albedo_curve` (e.g. importance
        sampling for a measured table, whose quadrature has no lobe to centre on).
    seed : int, optional
        Random source of the Monte Carlo methods (each entry's curve is drawn with this seed).
    fig : matplotlib.figure.Figure, optional
        Lay the views out in this figure (default: a new 16:9 one); up to three views in a row, four in
        two rows of two.
    axes : sequence of Axes, optional
        Draw into these, one per view, instead (``fig`` is then ignored).
    legend : bool or Axes, optional
        ``True``: a legend naming each entry (and what the albedo's band and marks mean) to the right of
        the albedo view, or of the last view; an Axes: there (its frame is switched off; in an Axes much
        wider than tall the entries stand side by side, in one row up to three, else two); ``False``: none.
    titles : bool, optional
        Title each view.

    Returns
    -------
    ComparisonPlot
        The figure, the axes by view, the entries drawn and their albedo curves.

    Raises
    ------
    ValueError
        An unknown view or channel; ``axes``, ``albedo_samples`` or ``albedo_method`` of the wrong
        length; and whatever the engine refuses (an angle out of range, a bad sample count …), by name.
    TypeError
        ``brdfs`` is none of the accepted forms.

    Examples
    --------
    >>> from lighting import Lambert, Phong
    >>> from explorer.compare import BRDFList
    >>> group = BRDFList([(Lambert(0.5), "matte"), (Phong(0.5, 20.0), "glossy")])
    >>> group.set_visible(0, False)
    >>> p = plot_brdfs(group, views=("polar", "albedo"), albedo_samples=256)
    >>> [i for i, _ in p.shown], sorted(a.get_gid() for a in p.axes["polar"].lines if a.get_gid())
    ([1], ['polar:1'])
    >>> round(float(p.albedo[1].albedo[0, 0]), 6)  # the slides' Phong: 2 k_s / (e + 1) at normal view
    0.047619
    """
    group = _as_list(brdfs)
    views = _check_views(views)
    ch = _check_channel(channel)
    samples = _per_entry("albedo_samples", albedo_samples, len(group), lambda s: s)
    methods = _per_entry("albedo_method", albedo_method, len(group), lambda m: m)
    if albedo_thetas is None:
        albedo_thetas = np.radians(np.append(np.arange(0.0, 89.0, 2.0), 89.0))
    logs = _check_log(log, views)
    fig, ax_of = _axes_for(views, fig, axes)
    drawn = {id(e) for e in group.shown()}
    shown = [(i, e) for i, e in enumerate(group.entries) if id(e) in drawn]
    plot = ComparisonPlot(fig, ax_of, shown)
    # Later entries are drawn over earlier ones, a little thinner, so that curves that coincide all show.
    width = {i: max(1.4, 3.2 - 0.45 * k) for k, (i, _) in enumerate(shown)}

    if "polar" in views:
        ax = ax_of["polar"]
        lg = "polar" in logs
        slices = [(i, e, polar_slice(e.brdf, theta_l, phi_in=phi_l, n=n, channel=ch, log=lg)) for i, e in shown]
        peak = max([float(s.values.max()) for _, _, s in slices] + [0.0])
        rmax = 1.12 * peak if peak > 0 else 1.0
        half_disc(ax, rmax)
        for i, e, s in slices:
            ax.plot(*s.xy.T, color=e.colour, lw=width[i], label=e.label, gid=f"polar:{i}")
        ax.plot([0, -rmax * math.sin(theta_l)], [0, rmax * math.cos(theta_l)], color=VEC["l"], ls=":", lw=1.8)
        ax.text(-1.02 * rmax * math.sin(theta_l), 1.02 * rmax * math.cos(theta_l), "$l$", color=VEC["l"],
                fontsize=15, ha="right", va="bottom", fontweight="bold")  # fmt: skip
        if titles:
            ax.set_title(f"{_fr(lg)}, light at $\\theta_l$ = {math.degrees(theta_l):.0f}°")

    for view, curve_of, fixed in (("theta_h", theta_h_curve, theta_d), ("theta_d", theta_d_curve, theta_h)):
        if view not in views:
            continue
        ax = ax_of[view]
        for i, e in shown:
            c = curve_of(e.brdf, fixed, n=curve_n, channel=ch, log=view in logs)
            # Where l or v lies on the horizon the value is 0 by convention, not the model's limit: left out.
            ax.plot(np.degrees(c.angles[c.valid]), c.values[c.valid], color=e.colour, lw=width[i],
                    label=e.label, gid=f"{view}:{i}")  # fmt: skip
        other = "d" if view == "theta_h" else "h"
        meaning = {"theta_h": " ($l = v$)", "theta_d": " ($h = n$)"}[view] if fixed == 0 else ""
        _cartesian(ax, f"$\\theta_{view[-1]}$ (degrees)", _fr(view in logs))
        if titles:
            ax.set_title(f"$\\theta_{other}$ = {math.degrees(fixed):.0f}°{meaning}")

    if "albedo" in views:
        ax = ax_of["albedo"]
        top = 0.0
        for i, e in shown:
            curve = albedo_curve(e.brdf, albedo_thetas, samples[i], methods[i], seed=seed)
            plot.albedo[i] = curve
            rho, err, flag = albedo_channel(curve, ch)
            deg = np.degrees(curve.theta)
            ax.fill_between(deg, rho - 2 * err, rho + 2 * err, color=e.colour, alpha=0.25, lw=0,
                            gid=f"albedo-band:{i}")  # fmt: skip
            ax.plot(deg, rho, color=e.colour, lw=width[i], label=e.label, gid=f"albedo:{i}")
            ax.plot(deg[flag], rho[flag], ls="none", marker="o", ms=7.5, mfc="white", mec=e.colour, mew=2.0,
                    gid=f"albedo-flags:{i}")  # fmt: skip
            # A band reaching far above the curve is clipped: its marks already say the value is not to be trusted.
            top = max(top, min(float(np.max(rho + 2 * err, initial=0.0)), 1.5 * float(np.max(rho, initial=0.0))))
        ax.axhline(1.0, color="0.55", ls=":", lw=1.1)
        _cartesian(ax, r"$\theta_v$ (degrees)", r"albedo $\rho(\theta_v)$")
        ax.set_ylim(0, max(1.1, 1.05 * top))
        if titles:
            ax.set_title(r"$\rho(\theta_v) = \int f_r\,(n\cdot l)\,d\omega_l$")

    if legend is not False and shown:
        plot.legend = _legend(ax_of, views, shown, legend, "albedo" in views, width)
    return plot


def _check_log(log, views):
    if log is True or log is False:
        return {v for v in views if v != "albedo"} if log else set()
    names = (log,) if isinstance(log, str) else tuple(log)
    if any(v not in VIEWS[:3] for v in names):
        raise ValueError(f"log must be True, False or names among polar, theta_h, theta_d; got {log!r}")
    return set(names)


def _fr(log):
    return r"$\log_{10}(1 + f_r)$" if log else r"$f_r$ (1/sr)"


def _cartesian(ax, xlabel, ylabel):
    ax.set_xlim(0, 90)
    ax.set_xticks([0, 30, 60, 90])
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(True)
    ax.set_ylim(bottom=0)


def _legend(ax_of, views, shown, where, albedo, width):
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles = [Line2D([], [], color=e.colour, lw=width[i], label=e.label) for i, e in shown]
    if albedo:
        handles.append(Patch(facecolor="0.6", alpha=0.45, lw=0, label=r"$\rho \pm 2\sigma$ (error estimate)"))
        handles.append(
            Line2D([], [], ls="none", marker="o", ms=7.5, mfc="white", mec="0.25", mew=2.0,
                   label=f"unconverged: error > {100 * UNCONVERGED_RELATIVE_ERROR:g} % of $\\rho$"),
        )  # fmt: skip
    if where is True:
        ax = ax_of["albedo"] if albedo else ax_of[views[-1]]
        # Outside, to the right: inside, it would cover curves in one view or another.
        return ax.legend(handles=handles, loc="center left", bbox_to_anchor=(1.03, 0.5), frameon=False)
    where.axis("off")
    if where.bbox.width < 2.5 * where.bbox.height:
        return where.legend(handles=handles, loc="center left", frameon=False)
    # A strip: the entries side by side, in one row up to three (their labels fit a slide's width), else two.
    ncol = len(handles) if len(handles) <= 3 else math.ceil(len(handles) / 2)
    return where.legend(handles=handles, loc="center", ncol=ncol, frameon=False, columnspacing=1.6)


# --------------------------------------------------------------------------- the lecture figure
#: A small BRDF Explorer file, written at build time and read with lighting.load_brdf (docs/brdf-files.md).
BLINN_PHONG_BRDF = """# Blinn-Phong, raw or normalized (BRDF Explorer's format)
analytic

::begin parameters
color ks 0.5 0.5 0.5
float n 1 1000 30
bool normalized 0
::end parameters

::begin shader
const float PI = 3.14159265358979;

vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)
{
    vec3 H = normalize(L + V);
    float lobe = pow(max(dot(N, H), 0.0), n);
    if (normalized)
        return ks * (n + 2.0) / (2.0 * PI) * lobe;
    return ks * lobe / (PI * dot(N, L));
}
::end shader
"""

#: Albedo cost: the measured table's importance sampler (its 80° value converges to 0.2 %) and the analytic
#: models' quadrature nodes.
_MEASURED_SAMPLES = 16384
_QUADRATURE_NODES = 16384
_GGX = {"ndf": "ggx", "geometry": "smith-correlated", "fresnel": "schlick"}


@register(
    "compare_brdfs",
    size="16:9",
    title="Several BRDFs side by side",
    caption=(
        "Four BRDFs in one comparison list (explorer.compare.BRDFList), each in its colour: a measured stand-in "
        "(Disney's metallic lobe, roughness {roughness:g}, in MERL's table layout with {noise_percent:g} % "
        "noise), a Cook–Torrance GGX fitted to it (α = {fit_alpha:.3f}), a normalized Blinn–Phong read from a "
        ".brdf file (k_s = {bp_ks:g}, n = {bp_n:g}) and a built-in GGX with α = {sharp_alpha:g}. Top: the list "
        "with the sharp GGX hidden; bottom: the same list with the sharp GGX solo. Left to right: the polar slice "
        "in the plane of incidence, the BRDF against θ_h (θ_d = 0) and θ_d (θ_h = 0) on a log₁₀(1 + f_r) scale, "
        "and the directional albedo with a ±2σ band of the integrator's error estimate. Luminance; albedo "
        "ρ(0°) / ρ(80°) ± σ: measured {rho0_measured:.3f} ± {err0_measured:.3f} / {rho80_measured:.3f} ± "
        "{err80_measured:.3f} (the table's importance sampler, {measured_samples} samples), fitted GGX "
        "{rho0_fit:.3f} ± {err0_fit:.0e} / {rho80_fit:.3f} ± {err80_fit:.0e} ({quadrature_nodes} quadrature "
        "nodes), Blinn–Phong file {rho0_bp:.4f} ± {err0_bp:.0e} (closed form {rho0_bp_exact:.4f}) / "
        "{rho80_bp:.3f} ± {err80_bp:.3f} (built-in Blinn–Phong: {rho80_bp_builtin:.4f}). Blinn–Phong's albedo "
        "falls toward grazing (no Fresnel, no 1/(n·v)), the measured one rises. Hollow circles mark values "
        "whose error exceeds {threshold_percent:g} % of ρ: {bp_flagged} small grazing values of the file model "
        "(from {bp_first_flag_deg:g}°: a file names no lobe for the quadrature to centre on; the built-in model "
        "with the same nodes has {bp_builtin_flagged} flagged), and {sharp_flagged} of the sharp GGX's "
        "{sharp_angles} values, integrated with only {sharp_samples} importance samples (at 80°: "
        "{rho80_sharp:.3f} ± {err80_sharp:.3f}, against {rho80_sharp_ref:.4f} from {quadrature_nodes} "
        "quadrature nodes)."
    ),
    slides="UBC: comparing BRDFs (BRDF Explorer); CMSC 435: BRDF models compared, energy and albedo",
    roughness=0.3,
    noise=0.03,
    missing=0.05,
    bp_ks=0.25,
    bp_n=300.0,
    sharp_alpha=0.02,
    sharp_samples=96,
    theta_l_deg=45.0,
)
def compare_brdfs(q, *, roughness, noise, missing, bp_ks, bp_n, sharp_alpha, sharp_samples, theta_l_deg):
    """Measured, fitted, file and built-in BRDFs in one list; one hidden, then solo.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Sample counts (full or quick).
    roughness, noise, missing : float
        The measured stand-in (as in ``fit_to_measured``): Disney roughness, relative noise, missing bins.
    bp_ks, bp_n : float
        The ``.brdf`` file's normalized Blinn–Phong.
    sharp_alpha : float
        The built-in GGX's roughness α.
    sharp_samples : int
        Its albedo's importance samples per angle (few on purpose: some values are unconverged).
    theta_l_deg : float
        The light's angle in the polar views.

    Returns
    -------
    fig : matplotlib.figure.Figure
    measured : dict
        The caption's numbers: albedo at 0° and 80° with errors, counts of flagged values.
    """
    from .fitting import _measured

    data = _measured(roughness, noise, missing, seed=3)
    fit = fit_brdf("cook-torrance", data, fixed=_GGX, n_theta=8 if q.quick else 12, n_phi=12 if q.quick else 16)
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "blinnphong.brdf")
        with open(path, "w", encoding="utf-8") as f:
            f.write(BLINN_PHONG_BRDF)
        blinn = load_brdf(path, ks=(bp_ks,) * 3, n=bp_n, normalized=True)
    sharp = CookTorrance(1.0, sharp_alpha, 0.9, **_GGX)

    group = BRDFList()
    group.add(data, "measured (stand-in)", COMPARE_COLOURS[4])
    group.add(fit.model, "Cook–Torrance GGX, fitted", COMPARE_COLOURS[0])
    group.add(blinn, "Blinn–Phong (.brdf file)", COMPARE_COLOURS[6])
    group.add(sharp, f"built-in GGX, α = {sharp_alpha:g}", COMPARE_COLOURS[2])
    group.set_visible(3, False)

    step = 5.0 if q.quick else 2.0
    thetas = np.radians(np.append(np.arange(0.0, 89.0, step), 89.0))
    options = {
        "theta_l": math.radians(theta_l_deg), "n": q.polar_n, "curve_n": q.curve_n, "albedo_thetas": thetas,
        "log": ("theta_h", "theta_d"), "seed": 1,
        "albedo_samples": [_MEASURED_SAMPLES, _QUADRATURE_NODES, _QUADRATURE_NODES, sharp_samples],
        "albedo_method": ["importance", "quadrature", "quadrature", "importance"],
    }  # fmt: skip

    fig = new_figure()
    rows = []
    for sub, title in zip(fig.subfigures(2, 1, hspace=0.04), (
        "The list: four BRDFs, the sharp GGX hidden (it keeps its place and colour)",
        "The same list with the sharp GGX solo: the others are not drawn, whatever their check boxes say",
    ), strict=True):  # fmt: skip
        # Each row: the four views, and under them a strip with the legend (beside them it would take a
        # fifth of the slide's width).
        grid = sub.add_gridspec(2, 4, width_ratios=(1.6, 1.0, 1.0, 1.1), height_ratios=(1.0, 0.13))
        axes = [sub.add_subplot(grid[0, k]) for k in range(4)]
        if rows:
            group.set_solo(3)
        rows.append(plot_brdfs(group, axes=axes, legend=sub.add_subplot(grid[1, :]), **options))
        sub.suptitle(title, x=0.01, ha="left", fontsize=13, fontweight="bold")
    top, bottom = rows

    def at(curve, deg):
        rho, err, _ = albedo_channel(curve)
        k = int(np.argmin(np.abs(np.degrees(curve.theta) - deg)))
        return float(rho[k]), float(err[k])

    measured = {
        "roughness": roughness,
        "noise_percent": 100 * noise,
        "fit_alpha": fit.parameters["roughness"],
        "bp_ks": bp_ks,
        "bp_n": bp_n,
        "sharp_alpha": sharp_alpha,
        "sharp_samples": sharp_samples,
        "measured_samples": _MEASURED_SAMPLES,
        "quadrature_nodes": _QUADRATURE_NODES,
        "threshold_percent": 100 * UNCONVERGED_RELATIVE_ERROR,
        "rho0_bp_exact": _blinn_phong_normal_albedo(bp_ks, bp_n),
    }
    for key, i in (("measured", 0), ("fit", 1), ("bp", 2)):
        for deg in (0, 80):
            measured[f"rho{deg}_{key}"], measured[f"err{deg}_{key}"] = at(top.albedo[i], deg)
    measured["rho80_sharp"], measured["err80_sharp"] = at(bottom.albedo[3], 80)
    flags = albedo_channel(bottom.albedo[3])[2]
    measured["sharp_flagged"], measured["sharp_angles"] = int(flags.sum()), int(flags.size)
    measured["sharp_flagged_deg"] = [float(d) for d in np.degrees(bottom.albedo[3].theta[flags])]
    reference = albedo_curve(sharp, [math.radians(80.0)], _QUADRATURE_NODES)
    measured["rho80_sharp_ref"] = float(albedo_channel(reference)[0][0])
    flags = albedo_channel(top.albedo[2])[2]
    measured["bp_flagged"] = int(flags.sum())
    measured["bp_first_flag_deg"] = float(np.degrees(top.albedo[2].theta[flags]).min(initial=90.0))
    builtin = albedo_curve(BlinnPhong(bp_ks, bp_n, normalized=True), thetas, _QUADRATURE_NODES)
    measured["bp_builtin_flagged"] = int(albedo_channel(builtin)[2].sum())
    measured["rho80_bp_builtin"] = at(builtin, 80)[0]
    return fig, measured


def _blinn_phong_normal_albedo(ks: float, e: float) -> float:
    """ρ(0) of the normalized Blinn–Phong lobe ``k_s (e+2)/(2π) (n·h)^e``: with ``v = n``, ``θ_h = θ_l / 2`` and
    ``∫ f (n·l) dω = 4 k_s (e+2) [2 (1 − c^(e+4))/(e+4) − (1 − c^(e+2))/(e+2)]``, ``c = cos 45°``."""
    c = math.sqrt(0.5)
    return 4 * ks * (e + 2) * (2 * (1 - c ** (e + 4)) / (e + 4) - (1 - c ** (e + 2)) / (e + 2))

"""The model gallery: every registered model on the same lit sphere, in the same polar slice, with its albedo curve.

The cards are generated from the model registry (:func:`lighting.models.model_variants`: each model and
each named variant, at its default parameters), never listed by hand, so a model registered later
appears here by itself; each figure is one 16:9 slide whose grid of cards (:func:`card_grid`) follows
the number of models.  The gallery is split in two figures by family — the lobe axis each model
declares (:meth:`~lighting.models.brdf.BRDF.lobe`): models reflecting about the normal or the mirror
direction (diffuse, Phong, delta mirrors) and half-vector models (Blinn–Phong and the microfacet family).

Registered on import (see :mod:`explorer.figures.base`); drawn by :mod:`explorer.figures`.
"""

from __future__ import annotations

import math

import numpy as np

from lighting import CookTorrance, DirectionalLight, Lambert, Material
from lighting.analysis import polar_slice
from lighting.integrate import albedo_curve, directional_albedo
from lighting.models import BRDFFlags, create_model, model_variants
from lighting.models.oren_nayar import OrenNayar

from .base import PALETTE, VEC, new_figure, register, show_image, sphere_rgb8

#: The figures of the gallery: name → (family test on a model's lobe axis, title of the family).
FAMILIES = {
    "model_gallery_normal_mirror": ("normal", "models reflecting about the normal or the mirror direction"),
    "model_gallery_half_vector": ("half", "half-vector models: Blinn–Phong and the microfacet family"),
}

#: The most cards a gallery column holds before the figure takes one more column (16:9 slide).
MAX_ROWS = 4


def card_grid(count: int) -> tuple[int, int]:
    """Rows and columns of a gallery figure's cards: every card fits one 16:9 slide.

    One column of wide cards for one or two models, two columns up to ``2 * MAX_ROWS`` models, then as
    many columns as keep at most :data:`MAX_ROWS` rows; the cards shrink, their text does not.

    Parameters
    ----------
    count : int
        How many cards (models).

    Returns
    -------
    tuple of int
        ``(rows, columns)``, with ``rows * columns >= count``.

    Examples
    --------
    >>> card_grid(1), card_grid(4), card_grid(6), card_grid(9), card_grid(13)
    ((1, 1), (2, 2), (3, 2), (3, 3), (4, 4))
    """
    count = max(1, int(count))
    if count <= 2:
        return count, 1
    cols = max(2, math.ceil(count / MAX_ROWS))
    if cols > 2:  # as square a grid as the rows allow
        cols = math.ceil(count / min(MAX_ROWS, math.ceil(math.sqrt(count))))
    return math.ceil(count / cols), cols


def family_of(brdf) -> str:
    """``"half"`` for a model whose lobe is a distribution of half vectors, else ``"normal"``.

    Parameters
    ----------
    brdf : lighting.models.brdf.BRDF
        A model.

    Returns
    -------
    str
        ``"half"`` or ``"normal"`` (diffuse, mirror-direction, delta or unknown lobes).

    Examples
    --------
    >>> from lighting.models import create_model
    >>> family_of(create_model("lambert")), family_of(create_model("cook-torrance"))
    ('normal', 'half')
    """
    lobe = brdf.lobe()
    return "half" if lobe is not None and lobe.axis == "half" else "normal"


def gallery_entries(family: str) -> list[tuple[str, object]]:
    """The registered models and variants of one family, at their default parameters, in registry order.

    Parameters
    ----------
    family : {"normal", "half"}
        See :func:`family_of`.

    Returns
    -------
    list of (str, BRDF)
        The registered name and the model.

    Examples
    --------
    >>> [name for name, _ in gallery_entries("half")][:2]
    ['blinn-phong', 'blinn-phong-normalized']
    """
    out = []
    for name in model_variants():
        brdf = create_model(name)
        if family_of(brdf) == family:
            out.append((name, brdf))
    return out


def _param_text(brdf, width: int = 44, lead: str = "") -> str:
    """``lead`` and the model's parameters as ``name value`` pairs, wrapped to at most two lines."""
    import textwrap

    items = []
    for p in brdf.parameters:
        value = getattr(brdf, p.name, None)
        if value is None:  # an optional parameter left at "same as another" (Ward's alpha_y)
            continue
        if p.kind == "choice" and value == "none" == p.default and p.name != "fresnel":
            continue  # an option left off (the mirror's metal); "fresnel none" stays: it says F = 1
        if p.kind == "color":
            arr = np.asarray(value, dtype=np.float64).reshape(-1)
            text = f"{arr[0]:g}" if np.all(arr == arr[0]) else "(" + ", ".join(f"{x:g}" for x in arr) + ")"
        elif p.kind == "float":
            text = f"{float(value):g}"
        else:
            text = str(value)
        items.append(f"{p.name} {text}")
    lines = textwrap.wrap(lead + ", ".join(items), width)
    if len(lines) > 2:
        lines = lines[:2]
        lines[1] = lines[1].rstrip(",") + " …"
    return "\n".join(lines)


def half_disc(
    ax,
    rmax: float,
    *,
    ticks: int = 2,
    label: bool = True,
    angles: bool = False,
    scale_label: str | None = None,
    fontsize: float = 10.0,
) -> None:
    """Cartesian axes showing the upper hemisphere as a half disc (normal up, mirror side right).

    A Matplotlib polar axes restricted to [−90°, 90°] keeps a square box and leaves its lower half
    empty; drawn in Cartesian coordinates with equal aspect the half disc fills a 2:1 cell.  Plot a
    slice with ``ax.plot(*slice.xy.T)`` (``x = f sin t``, ``y = f cos t``).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes to set up.
    rmax : float
        The radius of the outer circle (the radial scale's limit).
    ticks : int, optional
        About how many radial grid circles.
    label : bool, optional
        Print the radial scale's values along the right half of the baseline.
    angles : bool, optional
        Print the angles from the normal, −90° to 90° every 30°, around the rim.
    scale_label : str, optional
        What the radial scale measures (e.g. ``"$f_r$ (1/sr)"``), under the baseline's right half.
    fontsize : float, optional
        The size of the scale's values; the angles and ``scale_label`` are 1.5 pt larger.

    Returns
    -------
    None

    Examples
    --------
    >>> from lighting import Phong
    >>> from lighting.analysis import polar_slice
    >>> from explorer.figures.base import new_figure
    >>> ax = new_figure(4, 2).add_subplot()
    >>> half_disc(ax, 1.0)
    >>> lines = ax.plot(*polar_slice(Phong(1.0, 20), 0.7, n=91, channel=0).xy.T)
    """
    from .base import _fmt_tick, _nice_ticks

    t = np.linspace(-math.pi / 2, math.pi / 2, 181)
    for r in _nice_ticks(rmax, ticks):
        ax.plot(r * np.sin(t), r * np.cos(t), color="0.85", lw=0.7, zorder=0)
        if label and r < 0.97 * rmax:
            ax.text(r, -0.03 * rmax, _fmt_tick(r), ha="center", va="top", fontsize=fontsize, color="0.35")
    for deg in (-60, -30, 0, 30, 60):
        a = math.radians(deg)
        ax.plot([0, rmax * math.sin(a)], [0, rmax * math.cos(a)], color="0.85", lw=0.7, zorder=0)
    ax.plot(rmax * np.sin(t), rmax * np.cos(t), color="0.2", lw=1.0, zorder=1)
    ax.plot([-rmax, rmax], [0, 0], color="0.2", lw=1.0, zorder=1)
    ax.text(0.03 * rmax, 0.99 * rmax, "n", ha="left", va="top", fontsize=11, color=VEC["n"], fontweight="bold")
    if angles:
        for deg in range(-90, 91, 30):
            a = math.radians(deg)
            ha = "center" if deg == 0 else ("left" if deg > 0 else "right")
            va = "center" if abs(deg) == 90 else "bottom"
            text = f"{deg}°".replace("-", "−")
            ax.text(1.04 * rmax * math.sin(a), 1.04 * rmax * math.cos(a), text, ha=ha, va=va, fontsize=fontsize + 1.5)
    if scale_label:
        ax.text(0.55 * rmax, -0.13 * rmax, scale_label, ha="center", va="top", fontsize=fontsize + 1.5, color="0.3")
    ax.set_aspect("equal")
    wide = 1.22 if angles else 1.04  # room for the angles at the ends of the baseline
    ax.set_xlim(-wide * rmax, wide * rmax)
    ax.set_ylim((-0.3 if scale_label else -0.16) * rmax, (1.22 if angles else 1.02) * rmax)
    ax.axis("off")


def _delta_albedo(brdf, thetas: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A delta model's albedo ρ(θ_v) = reflectance(cos θ_v) (its own closed form: no quadrature error)."""
    c = np.where(thetas >= math.pi / 2, 0.0, np.cos(thetas))
    rho = np.asarray(brdf.reflectance(c), dtype=np.float64)[:, 0]
    return rho, np.zeros_like(rho)


def delta_weight_symbol(brdf, angle: str = r"\theta_l") -> str:
    r"""The name of a delta model's weight (its ``reflectance``) in the model's own parameters, as mathtext.

    The ideal mirror's weight is its parameter ``ks`` (``k_s``), times the Fresnel factor when it has one;
    any other delta model is named by its method, ``reflectance``.  (Not ``R``: that is the reflection
    vector ``R_l``.)

    Parameters
    ----------
    brdf : lighting.models.brdf.BRDF
        A delta model (``BRDFFlags.DELTA`` in its flags).
    angle : str, optional
        The mathtext angle the Fresnel factor depends on.

    Returns
    -------
    str
        Mathtext, e.g. ``"$k_s$"`` or ``"$k_s\,F(\cos\theta_l)$"``.

    Examples
    --------
    >>> from lighting.models import create_model
    >>> delta_weight_symbol(create_model("mirror")), delta_weight_symbol(create_model("mirror", fresnel="schlick"))
    ('$k_s$', '$k_s\\,F(\\cos\\theta_l)$')
    """
    try:
        table = brdf.to_dict()  # the parameters, as a scene file writes them
    except ValueError:
        table = {}
    fresnel = table.get("fresnel")
    if "ks" not in table or fresnel is None:
        return rf"$\mathrm{{reflectance}}(\cos{angle})$"
    return "$k_s$" if fresnel == "none" else rf"$k_s\,F(\cos{angle})$"


def _sphere_panel(ax, brdf, light, q, background, fs):
    """The engine's sphere; for a delta model, the one point where R_l = v is marked."""
    show_image(ax, sphere_rgb8(Material(brdf), [light], q.sphere_px, background=background))
    if BRDFFlags.DELTA in brdf.flags:
        # The only place a viewer on +z sees a directional light in a mirror: n = h = (l + v)/|l + v|.
        h = light.direction + np.array([0.0, 0.0, 1.0])
        h = h / np.linalg.norm(h)
        px = q.sphere_px
        x, y = (h[0] / 1.08 + 1) / 2 * px - 0.5, (1 - h[1] / 1.08) / 2 * px - 0.5
        ax.plot(x, y, "o", ms=9, mfc="none", mec="#F0E442", mew=1.8)
        # A plain line and a separate label: an annotation's arrow is clipped to its text's box, whose
        # measured extent can differ by a pixel between draws (the figures must be bitwise reproducible).
        tx, ty = x + 0.18 * px, y + 0.32 * px
        ax.plot([x + 0.02 * px, tx], [y + 0.04 * px, ty - 0.02 * px], color="#F0E442", lw=1.0)
        ax.text(tx, ty, "$\\mathbf{R}_l = \\mathbf{v}$\nonly here", color="#F0E442", fontsize=fs, ha="center",
                va="top")  # fmt: skip


def _polar_panel(ax, brdf, theta_l_deg, q, fs):
    """The slice f_r(l, v) for the light at θ_l, linear radial scale up to the model's own peak."""
    th = math.radians(theta_l_deg)
    lx, ly = -math.sin(th), math.cos(th)  # the light's side is on the left
    if BRDFFlags.DELTA in brdf.flags:
        r = float(np.asarray(brdf.reflectance(math.cos(th)))[0])
        half_disc(ax, 1.0, label=False)
        d = np.array([math.sin(th), math.cos(th)])
        ax.annotate("", xy=tuple(0.92 * d), xytext=(0, 0),
                    arrowprops={"arrowstyle": "-|>", "color": PALETTE[1], "lw": 2.6, "mutation_scale": 16})  # fmt: skip
        # The δ names the spike beside its middle, on the side away from the light, clear of the frame.
        side = np.array([d[1], -d[0]])
        ax.text(*(0.5 * d + 0.14 * side), "δ", color=PALETTE[1], fontsize=fs + 7, ha="center", va="center")
        ax.plot([0, lx], [0, ly], color=VEC["l"], ls=":", lw=1.6)
        ax.set_title(rf"δ along $\mathbf{{R}}_l$, weight {delta_weight_symbol(brdf)} = {r:.3g}", fontsize=fs, pad=1)
        return {"peak_angle_deg": theta_l_deg, "peak_value": None, "delta_weight": r}
    s = polar_slice(brdf, th, n=q.polar_n, channel=0)
    peak = float(s.values.max())
    rmax = 1.1 * peak if peak > 0 else 1.0
    half_disc(ax, rmax)
    x, y = s.xy.T
    ax.fill(x, y, color=PALETTE[0], alpha=0.18, lw=0)
    ax.plot(x, y, color=PALETTE[0], lw=1.8)
    ax.plot([0, rmax * lx], [0, rmax * ly], color=VEC["l"], ls=":", lw=1.6)
    i = int(np.argmax(s.values))
    inner = s.values[np.abs(s.angles) < math.radians(89.0)]
    if float(inner.max() - inner.min()) <= 1e-9 * peak:
        ax.set_title(f"constant {peak:.3g}/sr", fontsize=fs, pad=1)
    else:
        ax.set_title(f"peak {peak:.3g}/sr at {math.degrees(float(s.angles[i])):+.0f}°", fontsize=fs, pad=1)
    return {"peak_angle_deg": math.degrees(float(s.angles[i])), "peak_value": peak}


def _albedo_panel(ax, brdf, q, fs):
    """ρ(θ_v) with its ±2σ band (the integrator's honest error estimate)."""
    from matplotlib.ticker import MaxNLocator

    # Up to 89°: at exactly 90° every albedo is 0 (n·v = 0, the engine's horizon convention), a drop
    # that would draw a vertical line at the panel's edge and say nothing about the model.
    step = 5.0 if q.quick else 1.0
    thetas = np.radians(np.append(np.arange(0.0, 89.0, step), 89.0))
    if BRDFFlags.DELTA in brdf.flags:
        rho, err = _delta_albedo(brdf, thetas)
        how = "exact: " + delta_weight_symbol(brdf, r"\theta_v")
    else:
        c = albedo_curve(brdf, thetas, 512 if q.quick else 4096)
        rho, err = c.albedo[:, 0], c.error[:, 0]
        how = f"max error {float(err.max()):.1g}"
    deg = np.degrees(thetas)
    ax.fill_between(deg, rho - 2 * err, rho + 2 * err, color=PALETTE[2], alpha=0.3, lw=0)
    ax.plot(deg, rho, color=PALETTE[2], lw=2.0)
    ax.axhline(1.0, color="0.55", ls=":", lw=1.1)
    top = max(1.1, 1.08 * float(np.max(rho + 2 * err)))
    ax.set_ylim(0, top)
    ax.set_xlim(0, 90)
    ax.set_xticks([0, 30, 60, 89])
    ax.set_xticklabels(["0°", "30°", "60°", "89°"])  # the view angle θ_v: the title names the curve
    ax.yaxis.set_major_locator(MaxNLocator(nbins=3, steps=[1, 2, 2.5, 5, 10]))
    # As tall as the half disc beside it, whatever the card's height: the panels read as one row.
    ax.set_box_aspect(0.62)
    ax.tick_params(labelsize=10, pad=2)
    ax.grid(True)
    ax.set_title(f"$\\rho(\\theta_v)$:  $\\rho(0)$ = {rho[0]:.3f}\n{how}", fontsize=fs, pad=2, linespacing=1.15)
    return {"rho0": float(rho[0]), "rho0_error": float(err[0]), "rho_max": float(rho.max()),
            "max_error": float(err.max())}  # fmt: skip


def _gallery(q, family: str, title: str, theta_l_deg: float, light_deg: float, background: float):
    entries = gallery_entries(family)
    rows, cols = card_grid(len(entries))
    fig = new_figure()
    fig.suptitle(f"The model gallery: {title}", fontsize=16)
    subs = np.atleast_1d(fig.subfigures(rows, cols, wspace=0.03, hspace=0.02)).reshape(rows, cols)
    # A card's text: 11 pt on cards of a grid up to 3 x 2, 10.5 pt on smaller ones (never below 10).
    fs = 11.0 if rows <= 3 and cols <= 2 else 10.5
    card_width_in = fig.get_figwidth() / cols
    wrap = max(24, int(0.92 * card_width_in * 72 / (0.6 * (fs + 0.5))))  # characters of bold DejaVu Sans a line
    t = math.radians(light_deg)
    light = DirectionalLight((-math.sin(t) * math.sqrt(0.5), math.sin(t) * math.sqrt(0.5), math.cos(t)))
    measured = {}
    for k, sub in enumerate(subs.flat):
        if k >= len(entries):
            sub.set_facecolor("white")
            continue
        name, brdf = entries[k]
        sub.suptitle(_param_text(brdf, wrap, f"{name}:  "), fontsize=fs + 0.5, x=0.01, ha="left", linespacing=1.1,
                     fontweight="bold")  # fmt: skip
        gs = sub.add_gridspec(1, 3, width_ratios=[0.9, 1.8, 1.35])
        a, b, c = sub.add_subplot(gs[0, 0]), sub.add_subplot(gs[0, 1]), sub.add_subplot(gs[0, 2])
        _sphere_panel(a, brdf, light, q, background, fs - 0.5)
        m = _polar_panel(b, brdf, theta_l_deg, q, fs)
        m.update(_albedo_panel(c, brdf, q, fs))
        m["delta"] = BRDFFlags.DELTA in brdf.flags
        measured[name] = m
    return fig, measured


_CAPTION = (
    "Every registered model of this family ({model_list}) at its default parameters, one card each (a grid of "
    "cards whose columns follow the number of models). In each card, left: the "
    "engine's sphere under one white directional light {light_deg:g}° from the viewer (upper left), same "
    "exposure for all, the slides' classic form π f_r (n·l) without ambient light. Middle: the polar slice "
    "f_r (1/sr) in the plane of incidence for a light at θ_l = {theta_l_deg:g}° (dotted; the normal points "
    "up, the mirror direction is at +{theta_l_deg:g}°), each on its own linear radial scale up to its peak, so "
    "that every lobe fills its panel; the peak is printed above. Right: the directional albedo ρ(θ_v) = "
    "∫ f_r (n·l) dω_l with a ±2σ band of the integrator's error estimate (lighting.integrate.albedo_curve); "
    "above the dotted line at 1 a model reflects more than it receives."
)


@register(
    "model_gallery_normal_mirror",
    size="16:9",
    title="The model gallery (1): models about the normal or the mirror direction",
    caption=_CAPTION
    + (
        " A delta model (the ideal mirror: f_r is a Dirac delta, eval gives 0) is drawn as a spike δ along the "
        "mirror direction with its weight, the reflectance k_s (times the Fresnel factor F(cos θ) when it has "
        "one), and its albedo is that reflectance exactly, ρ(θ_v) = k_s F(cos θ_v); under a point or directional "
        "light it shows nothing but the one point where R_l = v (circled). Oren–Nayar at σ = 0 "
        "equals Lambert (albedo difference {on_sigma0_difference:.1g}); Oren–Nayar's ρ(0) = k_d A "
        "({on_rho0:.6f})."
    ),
    slides="UBC: BRDF measurements/plots; Materials: diffuse, glossy, specular. CMSC 435: Plotting BRDFs; Models",
    theta_l_deg=45.0,
    light_deg=45.0,
    background=0.03,
)
def model_gallery_normal_mirror(q, *, theta_l_deg, light_deg, background):
    """The gallery's first figure: diffuse, mirror-direction and delta models.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    theta_l_deg : float
        Light angle from the normal in the polar slices, in degrees.
    light_deg : float
        Angle of the spheres' directional light from the view direction, in degrees.
    background : float
        Linear grey behind the spheres (a black sphere stays visible).

    Returns
    -------
    tuple
        ``(figure, measured)``: per model ``rho0`` (ρ at normal view), its error, the slice's peak angle
        and value, and the closed-form checks of the albedo integrator (Lambert, Oren–Nayar at σ = 0).

    Notes
    -----
    Oren–Nayar's qualitative model at normal view (β = 0, so tan β = 0) keeps only its constant term:
    ρ(0) = k_d A, A = 1 − σ²/(2 (σ² + 0.33)) (Oren & Nayar 1994).

    References
    ----------
    M. Oren and S. K. Nayar, "Generalization of Lambert's reflectance model", SIGGRAPH 1994.
    """
    fig, measured = _gallery(q, "normal", FAMILIES["model_gallery_normal_mirror"][1], theta_l_deg, light_deg,
                             background)  # fmt: skip
    thetas = np.radians(np.arange(0.0, 90.0 + 1e-9, 10.0))
    on0 = directional_albedo(OrenNayar(0.8, 0.0), thetas, 512)[:, 0]
    lam = directional_albedo(Lambert(0.8), thetas, 512)[:, 0]
    on = create_model("oren-nayar").to_dict()
    extra = {
        "on_sigma0_difference": float(np.max(np.abs(on0 - lam))),
        "on_rho0": measured.get("oren-nayar", {}).get("rho0", float("nan")),
        "on_default_kd": float(on["kd"][0]),
        "on_default_sigma": float(on["sigma"]),
        "lambert_default_kd": float(create_model("lambert").to_dict()["kd"][0]),
    }
    caption = {"model_list": ", ".join(measured), "theta_l_deg": theta_l_deg, "light_deg": light_deg}
    return fig, {"models": measured, **extra, **caption}


@register(
    "model_gallery_half_vector",
    size="16:9",
    title="The model gallery (2): half-vector models — Blinn–Phong and the microfacet family",
    caption=_CAPTION
    + (
        " The integrator's check: Cook–Torrance with GGX, height-correlated Smith G, α = 1 and F = 1 has "
        "ρ(0) = 1 − ln 2 = 0.306853 exactly; measured {ggx_rho0:.6f} ± {ggx_rho0_error:.1g}."
    ),
    slides="CMSC 435: Specular microfacets; Cook–Torrance; Blinn–Phong (normalized); Plotting BRDFs",
    theta_l_deg=45.0,
    light_deg=45.0,
    background=0.03,
)
def model_gallery_half_vector(q, *, theta_l_deg, light_deg, background):
    """The gallery's second figure: Blinn–Phong and the microfacet models.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    theta_l_deg : float
        Light angle from the normal in the polar slices, in degrees.
    light_deg : float
        Angle of the spheres' directional light from the view direction, in degrees.
    background : float
        Linear grey behind the spheres.

    Returns
    -------
    tuple
        ``(figure, measured)``: per model ``rho0``, its error, the slice's peak angle and value, and the
        albedo integrator's closed-form check.

    Notes
    -----
    With the height-correlated Smith term, ``α = 1`` GGX and ``F = 1``, the albedo at normal view is
    ``1 − ln 2`` (Λ(v) = 0 there, and the remaining integral has a closed form; Heitz 2014).

    References
    ----------
    E. Heitz, "Understanding the masking-shadowing function in microfacet-based BRDFs", JCGT 3(2), 2014.
    """
    fig, measured = _gallery(q, "half", FAMILIES["model_gallery_half_vector"][1], theta_l_deg, light_deg,
                             background)  # fmt: skip
    est = directional_albedo(
        CookTorrance(1.0, 1.0, 1.0, ndf="ggx", geometry="smith-correlated"), 0.0, 4096, return_error=True
    )  # one angle: cheap even in quick mode
    caption = {"model_list": ", ".join(measured), "theta_l_deg": theta_l_deg, "light_deg": light_deg}
    return fig, {"models": measured, "ggx_rho0": float(est.value[0]), "ggx_rho0_error": float(est.error[0]),
                 **caption}  # fmt: skip

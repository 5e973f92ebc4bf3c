"""Energy compensation (Kulla–Conty 2017): the white furnace before and after, for rough microfacet models.

Registered on import (see :mod:`explorer.figures.base`); drawn by :mod:`explorer.figures`.
"""

from __future__ import annotations

import numpy as np

from lighting import CookTorrance
from lighting.integrate import directional_albedo
from lighting.models.energy import albedo_table

from .base import new_figure, register, series_colours


@register(
    "energy_compensation",
    size="16:9",
    title="Energy compensation: the white furnace before and after",
    caption=(
        "A white furnace test: a surface with F = 1 (a perfect white metal) under a uniform white sky should "
        "return all the light, ρ(θ_v) = 1. Left: the directional albedo of Cook–Torrance with GGX and the "
        "height-correlated Smith G (dashed) falls with the roughness α, down to {min_uncompensated:.3f} at α = 1 "
        "(1 − ln 2 at normal incidence), because light that hits a second microfacet is dropped. "
        "Kulla and Conty's multiple-scattering lobe f_ms = (1 − E(μ_o))(1 − E(μ_i)) / (π (1 − E_avg)) gives it "
        "back (solid). Top right: the compensated albedo, magnified, stays within ±1 % (shaded) up to θ_v = 85° "
        "(largest deviation {max_deviation:.1e}). Bottom right: the table E(μ, α) the lobe is built from (computed by "
        "the engine on first use, 32 × 32 nodes in μ and √α)."
    ),
    slides="Beyond the slides: energy conservation of microfacet models (Kulla & Conty, SIGGRAPH 2017)",
    alphas=(0.1, 0.3, 0.5, 0.75, 1.0),
    ndf="ggx",
    geometry="smith-correlated",
)
def energy_compensation(q, *, alphas, ndf, geometry):
    """The white furnace of a microfacet model without and with Kulla–Conty energy compensation.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    alphas : sequence of float
        The roughnesses drawn, one curve each.
    ndf, geometry : str
        The model's normal distribution and Smith geometry.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar): ``max_deviation`` (max ``|1 − ρ|`` with
        compensation for ``θ_v <= 85°`` over every α), ``min_uncompensated`` (the lowest ρ without it),
        ``E_normal_alpha1`` (the table's ``E(1, 1)``).
    """
    step = 5.0 if q.quick else 1.0
    deg = np.arange(0.0, 89.0 + 1e-9, step)
    theta = np.radians(deg)
    inside = deg <= 85.0
    samples = 1024 if q.quick else 4096
    colours = series_colours(len(alphas), "viridis", 0.85)

    fig = new_figure()
    gs = fig.add_gridspec(2, 2, width_ratios=[1.3, 1.0])
    ax = fig.add_subplot(gs[:, 0])
    zoom, tab = fig.add_subplot(gs[0, 1]), fig.add_subplot(gs[1, 1])
    deviation = 0.0
    lowest = 1.0
    for alpha, colour in zip(alphas, colours, strict=True):
        kw = {"ndf": ndf, "geometry": geometry, "fresnel": "none"}
        before = directional_albedo(CookTorrance(1.0, alpha, 1.0, **kw), theta, samples)[:, 0]
        after = directional_albedo(CookTorrance(1.0, alpha, 1.0, energy_compensation=True, **kw), theta, samples)
        after = after[:, 0]
        ax.plot(deg, before, ls="--", color=colour, lw=1.8)
        ax.plot(deg, after, color=colour, label=f"α = {alpha:g}")
        zoom.plot(deg, after, color=colour, label=f"α = {alpha:g}")
        deviation = max(deviation, float(np.max(np.abs(1.0 - after[inside]))))
        lowest = min(lowest, float(np.min(before[inside])))
    ax.plot([], [], color="0.3", ls="--", lw=1.8, label="without (dashed)")
    ax.set_xlim(0, 90)
    ax.set_ylim(0, 1.08)
    ax.set_xticks(np.arange(0, 91, 15))
    ax.set_xlabel(r"view angle $\theta_v$ (degrees)")
    ax.set_ylabel(r"directional albedo $\rho(\theta_v)$, F = 1")
    ax.grid(True)
    ax.legend(loc="lower left", ncol=2, fontsize=12)
    ax.set_title("White furnace: without (dashed) and with (solid)")

    zoom.axhspan(0.99, 1.01, color="#56B4E9", alpha=0.18, lw=0, label="±1 %")
    zoom.axhline(1.0, color="0.4", lw=0.9)
    zoom.axvline(85.0, color="0.6", ls=":", lw=1.2)
    zoom.set_xlim(0, 90)
    zoom.set_ylim(0.974, 1.015)  # room under the band for the legend
    zoom.set_xticks(np.arange(0, 91, 15))
    zoom.set_xlabel(r"view angle $\theta_v$ (degrees)")
    zoom.set_ylabel(r"$\rho(\theta_v)$ with compensation")
    zoom.grid(True)
    zoom.legend(loc="lower left", ncol=3, fontsize=11)
    zoom.set_title("With compensation, magnified")

    table = albedo_table(ndf, geometry)
    mu = np.linspace(0.0, 1.0, 201)
    r = np.linspace(0.0, 1.0, 201)
    e = table.E(mu[None, :], (r * r)[:, None])
    im = tab.imshow(e, origin="lower", extent=(0, 1, 0, 1), aspect="auto", vmin=0.0, vmax=1.0, cmap="viridis")
    cs = tab.contour(mu, r, e, levels=(0.4, 0.6, 0.8, 0.9, 0.95), colors="white", linewidths=0.9)
    tab.clabel(cs, fmt="%.2f", fontsize=10.5)
    tab.set_xlabel(r"$\mu = \cos\theta$")
    tab.set_ylabel(r"$\sqrt{\alpha}$")
    tab.set_title(r"Albedo table $E(\mu, \alpha)$ (GGX, Smith corr.)")
    fig.colorbar(im, ax=tab, label="E (F = 1)", shrink=0.9)
    measured = {
        "max_deviation": deviation,
        "min_uncompensated": lowest,
        "E_normal_alpha1": float(table.E(1.0, 1.0)),
        "alphas": list(alphas),
        "max_view_deg": 85.0,
    }
    return fig, measured

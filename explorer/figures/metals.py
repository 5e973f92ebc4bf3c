"""Figures for metals: the conductor Fresnel term of the named metals, and spheres of them under a sky.

Registered on import (see :mod:`explorer.figures.base`); drawn by :mod:`explorer.figures`.
"""

from __future__ import annotations

import numpy as np

from lighting import Material
from lighting.lights.envlight import EnvironmentLight
from lighting.models.cook_torrance import CookTorrance
from lighting.models.fresnel import METAL_WAVELENGTHS_NM, METALS, conductor, conductor_f0
from lighting.render.camera import Camera
from lighting.render.image import encode_srgb8, linear_to_srgb
from lighting.render.renderer import AnalyticSphere, Renderer

from .base import new_figure, register, show_image

#: The channels' curve colours (R, G, B), dark enough to read on white.
CHANNEL_COLOURS = ("#C0392B", "#1E8449", "#1F4E9E")


def _srgb8(f0) -> tuple[int, ...]:
    """A linear RGB reflectance as 8-bit sRGB (what a colour picker shows)."""
    return tuple(int(round(255 * float(x))) for x in linear_to_srgb(np.asarray(f0, dtype=np.float64)))


@register(
    "metal_fresnel",
    size="16:9",
    title="Fresnel reflectance of metals against the angle of incidence",
    caption=(
        "Top: spheres of five metals (Cook–Torrance, GGX with the height-correlated Smith term, α = {alpha:g}, "
        "k_s = 1, the exact conductor Fresnel term) under the engine's daylight sky, image-based lighting by its "
        "default method (the sky's dominant lights shaded exactly, the rest filtered). Bottom: each metal's "
        "unpolarized Fresnel reflectance F(θ) of its complex index η + ik per channel, the index read at "
        "{wavelengths} nm for R, G and B (Johnson and Christy 1972 for gold, "
        "silver and copper; Rakić et al. 1998 for aluminium and chromium). F rises to 1 at grazing incidence "
        "for every channel, some after a shallow dip between 70° and 85° (near the parallel polarization's "
        "pseudo-Brewster angle): a metal's tint is strongest at normal incidence, its F0, and fades at grazing "
        "angles, where it mirrors what it sees uncoloured. F0 in linear RGB: gold {gold}, "
        "silver {silver}, copper {copper}, aluminium {aluminium}, chromium {chromium}."
    ),
    slides="Beyond the slides: Fresnel reflection of conductors; Cook–Torrance's F for metals",
    alpha=0.1,
)
def metal_fresnel(q, *, alpha):
    """Each named metal's Fresnel reflectance per channel against the angle of incidence, and a sphere of it.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    alpha : float
        The spheres' GGX roughness.

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it (each
        metal's F0 in linear RGB and as 8-bit sRGB, the smallest F over angles and channels).
    """
    names = list(METALS)
    fig = new_figure()
    grid = fig.add_gridspec(2, len(names), height_ratios=[1.0, 1.05])
    deg = np.linspace(0.0, 90.0, q.curve_n)
    cos = np.cos(np.radians(deg))
    cos[-1] = 0.0  # exactly grazing at 90°
    sky = EnvironmentLight("daylight", background=False)
    size = q.sphere_px
    # Seen from the side and a little above (the sky's +z is up): the upper half mirrors the sky and the sun,
    # the lower half the ground, the rim the horizon.
    camera = Camera((0.0, -10.0, 2.0), (0.0, 0.0, 0.0), up=(0.0, 0.0, 1.0), projection="orthographic",
                    ortho_height=2.16, width=size, height=size)  # fmt: skip
    renderer = Renderer(AnalyticSphere(), camera)
    measured = {"alpha": alpha, "wavelengths": "/".join(f"{w:g}" for w in METAL_WAVELENGTHS_NM)}
    lowest = 1.0
    axes = []
    for i, name in enumerate(names):
        eta, k = METALS[name]
        f0 = conductor_f0(eta, k)
        model = CookTorrance(1.0, alpha, ndf="ggx", geometry="smith-correlated", fresnel="conductor", metal=name)
        img = renderer.render(Material(model, ambient=0.0), [sky], form="physical", background=0.9)
        rgb8, _ = encode_srgb8(img, exposure=-0.5)
        ax_img = fig.add_subplot(grid[0, i])
        show_image(ax_img, rgb8, name, fontsize=16, dark=False)
        ax = fig.add_subplot(grid[1, i], sharey=axes[0] if axes else None)
        axes.append(ax)
        f = conductor(cos, eta, k)
        lowest = min(lowest, float(f.min()))
        for c, (label, colour) in enumerate(zip(("R", "G", "B"), CHANNEL_COLOURS, strict=True)):
            ax.plot(deg, f[:, c], color=colour, lw=2.2, label=f"{label} {METAL_WAVELENGTHS_NM[c]:g} nm")
        ax.set_xlim(0, 90)
        ax.set_xticks([0, 30, 60, 90])
        ax.grid(True, alpha=0.5)
        ax.set_xlabel("angle of incidence θ (°)", fontsize=13)
        ax.tick_params(labelsize=12)
        ax.set_title("F0 = " + ", ".join(f"{x:.2f}" for x in f0), fontsize=13)
        if i == 0:
            ax.set_ylabel("Fresnel reflectance F(θ)", fontsize=13)
        else:
            ax.tick_params(labelleft=False)
        measured[name] = "(" + ", ".join(f"{x:.3f}" for x in f0) + ")"
        measured[f"{name}_f0_linear"] = [float(x) for x in f0]
        measured[f"{name}_f0_srgb8"] = list(_srgb8(f0))
        # As text for the docs' table (docs/models.md quotes them).
        measured[f"{name}_f0_srgb8_text"] = "(" + ", ".join(str(x) for x in _srgb8(f0)) + ")"
        measured[f"{name}_f0_srgb_hex"] = "#" + "".join(f"{x:02X}" for x in _srgb8(f0))
        measured[f"{name}_eta_text"] = "(" + ", ".join(f"{x:.3f}" for x in eta) + ")"
        measured[f"{name}_k_text"] = "(" + ", ".join(f"{x:.3f}" for x in k) + ")"
    axes[0].set_ylim(min(0.4, np.floor(lowest * 10) / 10), 1.01)
    axes[-1].legend(loc="lower left", fontsize=12)
    measured["lowest_f"] = lowest
    return fig, measured

"""Measured data against fitted models: a MERL table, three analytic fits, their slices and spheres side by side."""

from __future__ import annotations

import functools
import math

import numpy as np

from lighting import DirectionalLight, Material
from lighting.analysis import polar_slice
from lighting.analysis.fit import fit_brdf
from lighting.files.merl import MerlBRDF, tabulate_merl
from lighting.models import create_model

from ..compare import FIT_MODELS
from .base import PALETTE, VEC, new_figure, register, show_image, sphere_rgb8
from .zoo import half_disc

#: The analytic models fitted to the data (three of the explorer's fit models), each with what is held fixed,
#: and its colour.
FITS = tuple((*FIT_MODELS[key][:2], colour) for key, colour in (("ggx", PALETTE[1]), ("ward", PALETTE[2]),
                                                                 ("blinn-phong", PALETTE[4])))  # fmt: skip
_LABEL = {"cook-torrance": "Cook–Torrance GGX", "ward": "Ward", "blinn-phong-normalized": "Blinn–Phong norm."}


@functools.lru_cache(maxsize=1)
def _measured(roughness: float, noise: float, missing: float, seed: int) -> MerlBRDF:
    """A stand-in for measured data: Disney's metallic lobe tabulated in MERL's layout, with relative noise
    and missing bins (no measured data ships with the package).  Kept for the next call: ``compare_brdfs``
    draws the same table, and building it (tabulating, filling the missing bins) is most of either figure's
    work; nothing modifies it once built."""
    table = tabulate_merl(create_model("disney", base_color=(0.9, 0.6, 0.3), metallic=1.0, roughness=roughness))
    rng = np.random.default_rng(seed)
    table = table * (1.0 + noise * rng.standard_normal(table.shape[1:]))  # the same noise in every channel
    table[:, rng.random(table.shape[1:]) < missing] = -1.0
    return MerlBRDF(table, interpolation="linear")  # 3 % noise never reaches −100 %: negatives are the marks


@register(
    "fit_to_measured",
    size="16:9",
    title="Fitting analytic models to measured data",
    caption=(
        "A measured BRDF (here a stand-in: Disney's metallic lobe, roughness {roughness:g}, tabulated in MERL's "
        "layout with {noise_percent:g} % noise and {missing_percent:g} % missing bins) against three analytic "
        "models fitted to it by cosine-weighted least squares (lighting.analysis.fit): polar slices at two "
        "light angles (dots: the data; lines: the fits) and the spheres each gives under one directional light. "
        "Relative rms residual: Cook–Torrance GGX {rel_cook_torrance:.3f}, Ward {rel_ward:.3f}, normalized "
        "Blinn–Phong {rel_blinn_phong_normalized:.3f}; the fitted GGX roughness is {ct_roughness:.3f} "
        "(Disney's α = roughness² = {disney_alpha:.3f})."
    ),
    slides="UBC: BRDF measurements (gonioreflectometer, MERL); CMSC 435: BRDF models compared",
    roughness=0.3,
    noise=0.03,
    missing=0.05,
    angles_deg=(30.0, 60.0),
)
def fit_to_measured(q, *, roughness, noise, missing, angles_deg):
    """Measured data against fitted models.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).
    roughness : float
        Disney roughness of the stand-in data.
    noise : float
        Relative noise of the stand-in data.
    missing : float
        Fraction of missing bins.
    angles_deg : tuple of float
        Light angles of the polar slices.

    Returns
    -------
    fig : matplotlib.figure.Figure
    measured : dict
        Each fit's parameters and relative rms residual.
    """
    data = _measured(roughness, noise, missing, seed=3)
    fits = []
    for name, fixed, colour in FITS:
        result = fit_brdf(name, data, fixed=fixed, n_theta=8 if q.quick else 12, n_phi=12 if q.quick else 16)
        fits.append((name, result, colour))

    fig = new_figure()
    grid = fig.add_gridspec(2, 4, height_ratios=(1.15, 1.0))
    light_deg = 45.0
    light = DirectionalLight((-math.sin(math.radians(light_deg)), 0.0, math.cos(math.radians(light_deg))))
    for j, a in enumerate(angles_deg):
        ax = fig.add_subplot(grid[0, 2 * j : 2 * j + 2])
        th = math.radians(a)
        measured_slice = polar_slice(data, th, n=q.polar_n // 4, channel=0)
        peak = max(float(measured_slice.values.max()), 1e-12)
        half_disc(ax, 1.12 * peak)
        x, y = measured_slice.xy.T
        ax.plot(x, y, "o", ms=3.0, color="0.15", label="measured (R channel)")
        for name, result, colour in fits:
            s = polar_slice(result.model, th, n=q.polar_n, channel=0)
            ax.plot(*s.xy.T, color=colour, lw=2.0, label=f"{_LABEL[name]}  (rel. rms {result.relative_rms:.3f})")
        ax.plot([0, -1.12 * peak * math.sin(th)], [0, 1.12 * peak * math.cos(th)], color=VEC["l"], ls=":", lw=1.6)
        ax.set_title(rf"$f_r$ (1/sr), light at $\theta_l$ = {a:g}°", fontsize=13)
        if j == 0:
            # Above both slices: inside a half disc the legend would cover its frame and the light's line.
            fig.legend(loc="outside upper center", ncol=4, fontsize=11, frameon=False, columnspacing=1.5)
    spheres = [("measured", data, "0.15")] + [(_LABEL[name], r.model, c) for name, r, c in fits]
    for k, (label, brdf, colour) in enumerate(spheres):
        ax = fig.add_subplot(grid[1, k])
        show_image(ax, sphere_rgb8(Material(brdf), [light], q.sphere_px, background=0.03), label, color=colour,
                   fontsize=12, dark=False)  # fmt: skip
    measured = {
        "roughness": roughness,
        "noise_percent": 100 * noise,
        "missing_percent": 100 * missing,
        "disney_alpha": roughness**2,
        "ct_roughness": fits[0][1].parameters["roughness"],
    }
    for name, result, _ in fits:
        key = name.replace("-", "_")
        measured[f"rel_{key}"] = result.relative_rms
        measured[f"params_{key}"] = {k: v for k, v in result.parameters.items() if isinstance(v, float | tuple)}
    return fig, measured

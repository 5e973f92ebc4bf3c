"""The figure ``compare_brdfs``: its measured numbers against independent computations (slow set: drawing the
figure fits a model to measured data and integrates five albedo curves; what plot_brdfs draws:
test_figures_compare.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_figures_compare import GGX, Y, _gids

from explorer.figures import figure_names, make_figure
from explorer.figures.compare import VIEWS
from lighting.integrate import albedo_curve
from lighting.models import CookTorrance, create_model

pytestmark = pytest.mark.slow  # the figure's fit and albedo curves: seconds of work


# --------------------------------------------------------------------------- the lecture figure
@pytest.fixture(scope="module")
def figure():
    fig, spec, params, q, measured = make_figure("compare_brdfs", quick=True)
    return fig, spec, params, q, measured


def _blinn_phong_rho0(ks, e):
    """ρ(0) of k_s (e+2)/(2π) (n·h)^e, integrated here in θ_l by composite Simpson (v = n, θ_h = θ_l/2)."""
    t = np.linspace(0.0, math.pi / 2, 200001)
    f = ks * (e + 2) / (2 * math.pi) * np.cos(t / 2) ** e * np.cos(t) * np.sin(t) * 2 * math.pi
    h = t[1] - t[0]
    return float(h / 3 * (f[0] + f[-1] + 4 * f[1:-1:2].sum() + 2 * f[2:-1:2].sum()))


def test_the_figure_is_registered_after_fitting_and_its_caption_is_measured(figure):
    fig, spec, params, q, m = figure
    names = figure_names()
    assert names.index("fit_to_measured") < names.index("compare_brdfs") < names.index("accuracy_integration")
    text = spec.caption.format(**m)
    assert "{" not in text and f"{m['rho0_bp']:.4f}" in text


def test_the_file_model_s_albedo_is_the_closed_form_and_the_built_in_s(figure):
    _, _, params, _, m = figure
    exact = _blinn_phong_rho0(params["bp_ks"], params["bp_n"])
    assert m["rho0_bp"] == pytest.approx(exact, rel=1e-9)
    assert m["rho0_bp_exact"] == pytest.approx(exact, rel=1e-9)
    # At 80° the file model's quadrature is flagged; its honest error still covers the built-in model's value.
    assert abs(m["rho80_bp"] - m["rho80_bp_builtin"]) <= 2 * m["err80_bp"]
    assert m["bp_flagged"] > 0 and m["bp_builtin_flagged"] == 0
    assert m["rho80_bp_builtin"] < 0.1 * m["rho0_bp"]  # normalized Blinn–Phong loses its energy toward grazing


def test_the_measured_stand_in_the_fit_and_the_analytic_lobe_agree(figure):
    _, _, params, _, m = figure
    disney = create_model("disney", base_color=(0.9, 0.6, 0.3), metallic=1.0, roughness=params["roughness"])
    ref = albedo_curve(disney, np.radians([0.0, 80.0]), 4096)
    rho = ref.albedo @ Y
    # The table carries 3 % noise per bin and MERL's binning: averaged over the hemisphere, under 2 %.
    assert m["rho0_measured"] == pytest.approx(rho[0], rel=0.02)
    assert m["rho80_measured"] == pytest.approx(rho[1], rel=0.02)
    assert m["rho0_fit"] == pytest.approx(rho[0], rel=0.04)
    assert m["rho80_fit"] == pytest.approx(rho[1], rel=0.04)
    assert m["rho80_measured"] > m["rho0_measured"]  # Fresnel and masking: the metal's albedo rises toward grazing


def test_the_sharp_lobe_s_flags_and_honest_error(figure):
    _, _, params, q, m = figure
    sharp = CookTorrance(1.0, params["sharp_alpha"], 0.9, **GGX)
    thetas = np.radians(np.append(np.arange(0.0, 89.0, 5.0), 89.0))  # the quick figure's angles
    c = albedo_curve(sharp, thetas, params["sharp_samples"], "importance", seed=1)
    flags = c.unconverged.any(axis=1)
    assert (m["sharp_flagged"], m["sharp_angles"]) == (int(flags.sum()), thetas.size)
    assert m["sharp_flagged"] >= 1
    assert m["rho80_sharp"] == pytest.approx(float(Y @ c.albedo[16]), rel=1e-12)
    assert abs(m["rho80_sharp"] - m["rho80_sharp_ref"]) <= 2 * m["err80_sharp"]
    assert m["rho80_sharp_ref"] == pytest.approx(float(Y @ albedo_curve(sharp, [math.radians(80)], 16384).albedo[0]))


def test_the_figure_draws_three_entries_then_one_solo(figure):
    fig = figure[0]
    top, bottom = fig.subfigs
    gids = [{}, {}]
    for row, sub in zip(gids, (top, bottom), strict=True):
        for ax in sub.axes:
            for g in _gids(ax):
                view, i = g.split(":")
                row.setdefault(view, set()).add(int(i))
    assert all(gids[0][v] == {0, 1, 2} for v in VIEWS)  # the sharp GGX (3) is hidden
    assert all(gids[1][v] == {3} for v in VIEWS)  # and then solo
    assert gids[1]["albedo-flags"] == {3}
    labels = [t.get_text() for t in top.axes[-1].get_legend().get_texts()]
    assert labels[:3] == ["measured (stand-in)", "Cook–Torrance GGX, fitted", "Blinn–Phong (.brdf file)"]

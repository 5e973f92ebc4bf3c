"""The energy-compensation figure: drawn in quick mode, its measured values checked against the laws it shows."""

from __future__ import annotations

import math

import pytest

from explorer.figures import make_figure


def test_energy_compensation_figure_measures_the_furnace():
    # Drawn as the figure set draws it: at its registered slide size.
    fig, spec, _, _, measured = make_figure("energy_compensation", quick=True)
    # With compensation the furnace returns all the light to 1 % up to 85° (measured 2.1e-3, as the model tests).
    assert measured["max_deviation"] <= 0.01
    assert measured["max_deviation"] <= 3e-3
    # Without it, the lowest albedo is GGX's 1 − ln 2 at normal incidence and α = 1 (exact for the quadrature).
    assert measured["min_uncompensated"] == pytest.approx(1 - math.log(2), abs=1e-9)
    assert measured["E_normal_alpha1"] == pytest.approx(1 - math.log(2), abs=1e-12)
    titles = [ax.get_title() for ax in fig.axes]
    assert any("White furnace" in t for t in titles) and any("magnified" in t for t in titles)
    zoom = next(ax for ax in fig.axes if "magnified" in ax.get_title())
    lo, hi = zoom.get_ylim()
    assert lo < 0.99 and hi > 1.01  # the ±1 % band is in view
    spec.caption.format(**measured)  # every field of the caption is measured

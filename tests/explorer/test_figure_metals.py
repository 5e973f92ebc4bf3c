"""The metals figure: what it measured while drawing, against the closed forms and the sRGB encoding."""

from __future__ import annotations

import numpy as np
import pytest

pytestmark = pytest.mark.slow  # draws the metals figure (seconds): the full run has it

pytest.importorskip("matplotlib")

from explorer.figures import figure_names, make_figure  # noqa: E402
from lighting.models.fresnel import METALS, conductor  # noqa: E402
from lighting.render.image import linear_to_srgb  # noqa: E402


@pytest.fixture(scope="module")
def drawn():
    fig, spec, params, _, measured = make_figure("metal_fresnel", quick=True)
    return fig, spec, measured


def test_the_figure_follows_the_models_in_lecture_order():
    names = figure_names()
    first_metal = names.index("metal_fresnel")
    models = [i for i, n in enumerate(names) if n.startswith(("lambert_", "phong_", "blinn_"))]
    assert models and first_metal > max(models)


def test_each_metals_f0_is_its_closed_form_and_its_srgb_the_encoding(drawn):
    _, spec, m = drawn
    assert spec.size_in == pytest.approx((40 / 3, 7.5))
    for name, (eta, k) in METALS.items():
        eta, k = np.array(eta), np.array(k)
        f0 = ((eta - 1) ** 2 + k**2) / ((eta + 1) ** 2 + k**2)
        np.testing.assert_allclose(m[f"{name}_f0_linear"], f0, rtol=1e-15)
        srgb = [int(round(255 * float(x))) for x in linear_to_srgb(f0)]
        assert m[f"{name}_f0_srgb8"] == srgb
        assert m[f"{name}_f0_srgb_hex"] == "#" + "".join(f"{x:02X}" for x in srgb)
    # Gold and copper are red-heavy, silver and aluminium nearly grey.
    assert m["gold_f0_linear"][0] > m["gold_f0_linear"][1] > m["gold_f0_linear"][2]
    assert m["copper_f0_linear"][0] > m["copper_f0_linear"][1] > m["copper_f0_linear"][2]
    assert np.ptp(m["silver_f0_linear"]) < 0.02 and np.ptp(m["aluminium_f0_linear"]) < 0.02


def test_the_lowest_reflectance_and_the_dip_before_grazing(drawn):
    _, _, m = drawn
    deg = np.linspace(0.0, 90.0, 61)  # the quick curve's sampling
    c = np.cos(np.radians(deg))
    c[-1] = 0.0
    lowest = min(float(conductor(c, *METALS[name]).min()) for name in METALS)
    assert m["lowest_f"] == pytest.approx(lowest, rel=1e-12)
    # Aluminium and chromium dip below their F0 in every channel before rising to 1 at grazing incidence.
    for name in ("aluminium", "chromium"):
        f = conductor(c, *METALS[name])
        assert np.all(f.min(axis=0) < np.array(m[f"{name}_f0_linear"]) - 0.02) and np.all(f[-1] == 1.0)

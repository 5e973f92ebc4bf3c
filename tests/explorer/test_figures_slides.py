"""The slides' concept figures, the OpenGL figures and the model gallery: what each measured while drawing.

Each figure is drawn in quick mode (no file written) and the numbers it put in its sidecar are checked
against closed forms and laws: the albedo integrator against Lambert, Oren–Nayar's A and 1 − ln 2; the
OpenGL mode against h/√(h² + d²) and the engine's spot factor; Oren–Nayar's ratios to Lambert; the
finite-cone limit that defines the BRDF; the colour of one bounce off a red wall.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from explorer.figures import figure_names, make_figure  # noqa: E402
from explorer.figures.zoo import FAMILIES, family_of, gallery_entries  # noqa: E402
from lighting.models import create_model, model_variants  # noqa: E402

SLIDE_FIGURES = (
    "local_vs_global",
    "one_point_many_directions",
    "diffuse_glossy_specular",
    "chalk_microroughness",
    "glossy_around_mirror",
    "brdf_li_to_lo",
    "retro_reflection",
    "gl_light_position",
    "gl_spot_parameters",
    *FAMILIES,
)


def _oren_nayar_ab(sigma):
    """Oren & Nayar (1994), qualitative model: A = 1 − σ²/(2(σ² + 0.33)), B = 0.45 σ²/(σ² + 0.09)."""
    s2 = sigma * sigma
    return 1.0 - 0.5 * s2 / (s2 + 0.33), 0.45 * s2 / (s2 + 0.09)


@pytest.fixture(scope="module")
def measured():
    out = {}
    for name in SLIDE_FIGURES:
        fig, spec, params, _, m = make_figure(name, quick=True)
        assert spec.caption.format(**m)  # every caption field is measured
        out[name] = (params, m)
        fig.clf()
    return out


def test_the_figures_are_registered_in_lecture_order():
    names = figure_names()
    assert set(SLIDE_FIGURES) <= set(names)
    # The concepts open the set, the OpenGL figures follow the lights, the gallery follows the BRDF figures.
    assert names.index("local_vs_global") == 0
    assert names.index("gl_light_position") > names.index("light_sources")
    assert names.index("model_gallery_normal_mirror") > names.index("brdf_polar")


def test_gallery_shows_every_registered_model_and_variant_once(measured):
    shown = [name for fam in FAMILIES for name in measured[fam][1]["models"]]
    assert sorted(shown) == sorted(model_variants())
    for fig_name, (axis, _) in FAMILIES.items():
        for name in measured[fig_name][1]["models"]:
            assert family_of(create_model(name)) == axis
    assert [n for n, _ in gallery_entries("normal")] == list(measured["model_gallery_normal_mirror"][1]["models"])


def test_gallery_albedo_matches_closed_forms(measured):
    m1 = measured["model_gallery_normal_mirror"][1]
    models = m1["models"]
    # Lambert: ρ = k_d at every view.
    assert models["lambert"]["rho0"] == pytest.approx(m1["lambert_default_kd"], rel=1e-12)
    assert models["lambert"]["max_error"] < 1e-12
    # Oren–Nayar at σ = 0 is Lambert; at normal view its albedo is k_d A (β = 0: the B term vanishes).
    assert m1["on_sigma0_difference"] < 1e-12
    a, _ = _oren_nayar_ab(m1["on_default_sigma"])
    assert models["oren-nayar"]["rho0"] == pytest.approx(m1["on_default_kd"] * a, rel=1e-9)
    # Phong's BRDF k_s (R·v)^e/(π n·l) has albedo 2 k_s/(e + 1) at normal incidence.
    ph = create_model("phong")
    assert models["phong"]["rho0"] == pytest.approx(2 * float(ph.ks[0]) / (ph.shininess + 1), rel=1e-6)
    # Height-correlated Smith GGX, α = 1, F = 1: ρ(0) = 1 − ln 2, within the integrator's own error bar.
    m2 = measured["model_gallery_half_vector"][1]
    assert abs(m2["ggx_rho0"] - (1 - math.log(2))) <= max(2 * m2["ggx_rho0_error"], 1e-9)
    assert m2["ggx_rho0_error"] < 1e-6
    # Every albedo is drawn with its error estimate, and the half-vector lobes peak on the mirror side.
    for name, m in {**models, **m2["models"]}.items():
        assert m["max_error"] >= 0 and math.isfinite(m["rho0"]), name
    for name, m in m2["models"].items():
        assert m["peak_angle_deg"] > 0, name


def test_gallery_draws_a_delta_model_as_its_reflectance():
    deltas = [n for n in model_variants() if create_model(n).is_delta]
    if not deltas:
        pytest.skip("no delta model registered")
    _, _, _, _, m = make_figure("model_gallery_normal_mirror", quick=True)
    for name in deltas:
        entry = m["models"][name]
        brdf = create_model(name)
        assert entry["delta"] is True and entry["peak_value"] is None
        assert entry["rho0"] == pytest.approx(float(brdf.reflectance(1.0)[0]), rel=1e-12)
        assert entry["delta_weight"] == pytest.approx(float(brdf.reflectance(math.cos(math.radians(45)))[0]))


def test_local_vs_global_bounce_has_the_wall_colour_and_converges(measured):
    params, m = measured["local_vs_global"]
    kd = np.asarray(params["wall_kd"], dtype=float)
    # A white light off a white floor: the bounce's channels are in the wall's albedo ratios, exactly.
    assert m["bounce_colour_ratio"] == pytest.approx(kd[2] / kd[0], rel=1e-12)
    assert m["bounce_colour_ratio_spread"] < 1e-12
    # The bounce is strongest at the wall's foot and a fraction of the direct light (albedo < 1).
    assert 0 < m["bounce_ratio_far"] < m["bounce_ratio_near"] < 1
    assert m["grid_difference"] < 0.01


def test_one_point_lobes_peak_at_the_mirror_directions(measured):
    params, m = measured["one_point_many_directions"]
    assert m["peak_angles_deg"] == pytest.approx([abs(a) for a in params["angles_deg"]], abs=1e-9)
    # The diffuse floor under the lobe: at the peak, f_r E (n·l) = (k_d/π + k_s/(π n·l)) (n·l).
    for a, v in zip(params["angles_deg"], m["peak_values"], strict=True):
        c = math.cos(math.radians(a))
        assert v == pytest.approx((params["kd"] * c + params["ks"]) / math.pi, rel=1e-12)


def test_diffuse_glossy_specular_values(measured):
    params, m = measured["diffuse_glossy_specular"]
    assert m["lambert_value"] == pytest.approx(params["kd"] / math.pi, rel=1e-14)
    # GGX with F = 1 peaks at the mirror direction or a little beyond it (toward grazing).
    assert params["theta_deg"] <= m["glossy_peak_deg"] < params["theta_deg"] + 5


def test_chalk_oren_nayar_over_lambert(measured):
    params, m = measured["chalk_microroughness"]
    a, b = _oren_nayar_ab(params["sigma"])
    t = math.radians(params["theta_deg"])
    assert m["ratio_normal"] == pytest.approx(a, rel=1e-12)
    # Looking back along the light (α = β = θ, cos Δφ = 1): A + B sin θ tan θ.
    assert m["ratio_back"] == pytest.approx(a + b * math.sin(t) * math.tan(t), rel=1e-12)
    assert m["ratio_max_deg"] < -80  # back-scatter grows toward the light's horizon


def test_glossy_lobes_half_widths_and_off_specular_peaks(measured):
    params, m = measured["glossy_around_mirror"]
    for e, hw, pk in zip(params["exponents"], m["phong_half_widths_deg"], m["phong_peak_deg"], strict=True):
        assert pk == pytest.approx(params["theta_deg"], abs=1e-9)
        # (cos ψ)^e = 1/2 at ψ = arccos(2^(−1/e)); linear interpolation between 91 quick samples.
        assert hw == pytest.approx(math.degrees(math.acos(0.5 ** (1 / e))), abs=0.05 * hw + 0.1)
    peaks = m["ct_peak_deg"]
    assert all(p >= params["theta_deg"] - 1e-9 for p in peaks)
    assert peaks == sorted(peaks, reverse=True)  # the rougher the surface, the farther beyond R


def test_brdf_is_the_limit_of_the_cone_ratio(measured):
    params, m = measured["brdf_li_to_lo"]
    d = m["relative_differences"]
    assert d == sorted(d, reverse=True) and d[-1] < 1e-3
    assert m["order"] == pytest.approx(2.0, abs=0.05)  # a smooth f_r: the error is O(δ²)


def test_retro_reflection_decomposition(measured):
    params, m = measured["retro_reflection"]
    a, b = _oren_nayar_ab(params["sigma"])
    t = math.radians(params["theta_deg"])
    assert m["diffuse_value"] == pytest.approx(params["kd"] * a / math.pi, rel=1e-12)
    assert m["retro_mirror_side_max"] == 0.0
    assert m["retro_over_diffuse_at_l"] == pytest.approx(b / a * math.sin(t) * math.tan(t), rel=1e-12)
    assert m["retro_peak_deg"] < -params["theta_deg"]  # on the light's side, beyond it toward the horizon
    assert m["sum_difference"] < 1e-15


def test_gl_light_position(measured):
    params, m = measured["gl_light_position"]
    d = np.asarray(params["direction"], dtype=float)
    assert m["w0_spread"] == 0.0
    assert m["w0_value"] == pytest.approx(d[1] / np.linalg.norm(d), rel=1e-15)
    assert m["w1_formula_difference"] < 1e-14
    assert m["w1_peak_x"] == pytest.approx(params["point"][0], abs=1e-12)


def test_gl_spot_parameters(measured):
    params, m = measured["gl_spot_parameters"]
    assert m["max_difference"] < 1e-12  # the OpenGL mode's own transcription agrees with the engine's
    c = math.cos(math.radians(params["cutoff"]))
    assert m["edge_value"] == pytest.approx(c ** params["exponent_drawn"], rel=1e-12)
    assert m["outside_value"] == 0.0
    assert m["pool_radius_px"] == pytest.approx(m["pool_radius_expected_px"], rel=0.05)


def test_gouraud_vs_phong_plots_everything_inside_its_axes():
    fig, _, _, _, m = make_figure("gouraud_vs_phong", quick=True)
    plots = [ax for ax in fig.axes if ax.get_lines() and not ax.images]
    assert {ax.get_title() for ax in plots} == {"Intensity along the scan line", "Kinks at the triangle edges"}
    for ax in plots:
        (x0, x1), (y0, y1) = sorted(ax.get_xlim()), sorted(ax.get_ylim())
        for line in ax.get_lines():
            if line.get_transform() != ax.transData:  # guides across the axes: the edges, the zero line
                continue
            x, y = (np.asarray(a, dtype=float) for a in line.get_data())
            assert np.all((x >= x0) & (x <= x1) & (y >= y0) & (y <= y1)), (ax.get_title(), line.get_label())
    # The Mach band kinks stay visible: Gouraud's largest kink spans a good part of the kink panel's height.
    kinks = next(ax for ax in plots if ax.get_title() == "Kinks at the triangle edges")
    gouraud = next(line for line in kinks.get_lines() if line.get_label().startswith("Gouraud"))
    span = abs(np.subtract(*kinks.get_ylim()))
    assert np.max(np.abs(gouraud.get_ydata())) > 0.25 * span
    assert m["metric_gouraud"] > 5 * m["metric_phong"]
    fig.clf()

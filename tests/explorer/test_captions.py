"""The explorer's captions (explorer.app.captions): what each says, from the controls and the views."""

import math
import os

import numpy as np
import pytest

from explorer.app import captions
from explorer.app.environment import ENVIRONMENT_HELP, ENVIRONMENT_LABELS, environment_label
from explorer.app.params import kd_label, model_label
from explorer.app.state import ENVIRONMENTS, AppState
from explorer.app.views import AlbedoView, ExplorerModel
from lighting.lights import SKIES
from lighting.models.protocol import unregister_model

PI = "const float PI = 3.14159265358979323846;\n"
SIG = "vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)"
#: A BRDF Explorer file: a Lambert of its own colour (the file is the whole material).
LAMBERT_FILE = (f"::begin parameters\ncolor albedo 0.8 0.5 0.2\n::end parameters\n::begin shader\n{PI}{SIG} "
                "{ return albedo / PI; }\n::end shader\n")  # fmt: skip


def _model(state, size=32):
    model = ExplorerModel(state, sphere_size=size, mesh_size=32, lobe_resolution=8)
    model.update()
    return model


# ------------------------------------------------------------------ the window
def test_keys_are_the_window_s_keys_once_each():
    keys = [k.key for k in captions.KEYS]
    assert len(keys) == len(set(keys)) == 27
    old = {"m", "M", "t", "i", "c", "f", "1", "2", "3", "l", "n", "Up", "Down", "Left", "Right", "r", "h", "e", "s",
           "p", "F", "a", "v", "x", "o", "k", "q"}  # fmt: skip
    as_typed = {k[-1] if k.startswith("Shift+") else (k.lower() if len(k) == 1 else k) for k in keys}
    assert as_typed == old
    assert all(k.description and k.description == k.description.strip() for k in captions.KEYS)
    help_lines = captions.keys_help().splitlines()
    assert len(help_lines) == len(keys) + 2 and help_lines[4] == "Shift+M   previous reflectance model"


def test_keys_are_qt_key_sequences():
    qtgui = pytest.importorskip("PySide6.QtGui")
    for k in captions.KEYS:
        seq = qtgui.QKeySequence(k.key)
        assert seq.count() == 1 and seq.toString() == k.key


def test_window_title_names_the_model_and_environment():
    assert captions.window_title(AppState(model="cook-torrance")) == "lighting-explorer — Cook-Torrance"
    sunset = AppState(environment="sunset")
    assert captions.window_title(sunset) == "lighting-explorer — Blinn-Phong, environment sunset"


# ------------------------------------------------------------------ the light's angle, below the horizon
@pytest.mark.parametrize("elevation, theta", [(45.0, 45), (0.0, 90), (-36.0, 126), (-90.0, 180)])
def test_captions_give_the_true_incident_angle(elevation, theta):
    state = AppState(elevation=elevation)
    model = _model(state)
    m = model.views
    assert math.degrees(state.theta_l) == pytest.approx(theta, abs=1e-9)
    word = " (below the horizon)" if theta > 90 else (" (on the horizon)" if theta == 90 else "")
    assert captions.incidence(state) == f"θ_l = {theta}°{word}"
    assert captions.polar_title(state, m["polar"]) == f"Polar slice, θ_l = {theta}°{word}, φ_l = 180°"
    assert captions.lobe_caption(state, m["lobe"]).startswith(f"light l at θ_l = {theta}°{word}, φ_l = 180°")
    # The views plot at most 90°: the caption is the light's, not the clamped plotting angle.
    assert math.degrees(m["polar"].theta_in) == pytest.approx(min(theta, 90))


def test_polar_note_follows_what_is_drawn_below_the_horizon():
    state = AppState(elevation=-36.0)
    model = _model(state)
    pv = model.views["polar"]
    assert pv.below_horizon and not np.any(pv.light_fixed) and not np.any(pv.view_fixed)
    assert captions.polar_note(state, pv) == "light below the horizon:\nnothing reflected"
    assert captions.lobe_caption(state, model.views["lobe"]).splitlines()[1].endswith(" · nothing reflected")
    state.lock = True  # the retro-reflection f(d, d): drawn whatever the light's place
    model.update()
    pv, lv = model.views["polar"], model.views["lobe"]
    assert pv.below_horizon and pv.light_fixed.max() > 0.2 and lv.peak > 0.2
    note = captions.polar_note(state, pv)
    assert "nothing reflected" not in note and "f(d, d)" in note
    assert "nothing reflected" not in captions.lobe_caption(state, lv)
    assert captions.polar_title(state, pv) == "Retro-reflection f(d, d) (view lock), φ = 180°"
    assert captions.lobe_title(state, lv).startswith("retro-reflection lobe f(d, d), view lock: f_r")
    state.elevation = 45.0
    model.update()
    assert captions.polar_note(state, model.views["polar"]) == ""


# ------------------------------------------------------------------ the albedo readout
def _albedo(value, error):
    return AlbedoView(math.pi / 4, value, error, error / value, False, np.full(3, value), np.full(3, error),
                      "quadrature", 4096)  # fmt: skip


@pytest.mark.parametrize("controls", [{"model": "ward", "ks": 1.0}, {"model": "blinn-phong", "shininess": 1.0},
                                      {"model": "cook-torrance", "roughness": 1.0, "f0": 1.0}])  # fmt: skip
def test_albedo_above_one_says_not_energy_conserving(controls):
    av = _model(AppState(**controls)).views["albedo"]
    text = captions.albedo_caption(av)
    assert text == f"albedo ρ(θ_v = 45°) = {av.value:.4g} ± {av.error:.2g}  above 1: not energy conserving"


def test_albedo_caption_flags_only_beyond_twice_the_error():
    assert captions.albedo_caption(_albedo(0.98, 0.001)) == "albedo ρ(θ_v = 45°) = 0.98 ± 0.001"
    assert captions.albedo_caption(_albedo(1.01, 0.006)) == "albedo ρ(θ_v = 45°) = 1.01 ± 0.006"  # 1 within 2σ
    assert captions.albedo_caption(_albedo(1.02, 0.006)).endswith("  above 1: not energy conserving")
    red = AlbedoView(0.0, 0.9, 0.001, 0.001, False, np.array([1.2, 0.8, 0.8]), np.full(3, 0.001), "quadrature", 4096)
    assert captions.albedo_caption(red) == "albedo ρ(θ_v = 0°) = 0.9 ± 0.001  red above 1: not energy conserving"


def test_the_window_and_the_notebook_show_the_same_albedo_caption():
    import explorer.app

    assert explorer.app.albedo_caption is captions.albedo_caption
    folder = os.path.join(os.path.dirname(captions.__file__), "..")
    with open(os.path.join(folder, "qt", "window.py"), encoding="utf-8") as f:
        assert "captions.albedo_caption(av)" in f.read()
    with open(os.path.join(folder, "notebook.py"), encoding="utf-8") as f:
        assert "from .app.captions import albedo_caption" in f.read()


# ------------------------------------------------------------------ the lit sphere
def test_sphere_caption_of_the_default_state():
    state = AppState()
    model = _model(state)
    sv = model.views["sphere"]
    assert captions.sphere_title(state, sv) == "Lit sphere (engine): Blinn-Phong"
    assert captions.sphere_legend(state, sv) == "per pixel, exact sphere · arrow: the key light"
    share = 100 * sv.clipped / sv.coverage.sum()  # the highlight of k_s + k_d above 1 at exposure 0
    assert 0.5 <= share < 10
    assert captions.sphere_caption(state, sv) == (f"{share:.0f}% of the sphere above 1: clipped (lower the exposure)\n"
                                                  "directional, elevation 45°, azimuth 135°\n"
                                                  "classic I · ambient + diffuse + specular")  # fmt: skip
    state.exposure = -1.0
    model.update()
    assert captions.sphere_caption(state, model.views["sphere"]) == ("directional, elevation 45°, azimuth 135°\n"
                                                                     "classic I · ambient + diffuse + specular\n"
                                                                     "exposure −1.0 stops")  # fmt: skip


def test_sphere_caption_says_how_much_clips_and_the_exposure():
    state = AppState(intensity=4.0, exposure=1.0)
    model = _model(state)
    sv = model.views["sphere"]
    share = 100 * sv.clipped / sv.coverage.sum()
    assert share >= 0.5
    lines = captions.sphere_caption(state, sv).splitlines()
    assert lines[0] == f"{share:.0f}% of the sphere above 1: clipped (lower the exposure)"
    assert lines[-1] == "exposure +1.0 stops"


def test_split_legend_names_the_halves_along_the_light():
    assert captions.split_sides(90.0) == ("left", "right")
    assert captions.split_sides(135.0) == ("lower left", "upper right")
    assert captions.split_sides(0.0) == ("top", "bottom")
    assert captions.split_sides(-90.0) == ("right", "left")
    state = AppState()
    model = _model(state)
    entry = model.pin("pinned")
    state.split = True
    model.update()
    sv = model.views["sphere"]
    assert sv.split == entry.label and sv.split_angle == 135.0
    assert captions.sphere_legend(state, sv).splitlines()[0] == (
        "split along the light: lower left current · upper right ▸ pinned")
    # The named half is the current model's: its pixels lie lower left of the centre.
    rows, cols = np.nonzero(sv.split_mask & sv.coverage)
    h, w = sv.coverage.shape
    assert cols.mean() < w / 2 and rows.mean() > h / 2


def test_mirror_note():
    assert captions.delta_note(AppState()) == ""
    assert captions.delta_note(AppState(model="mirror")) == (
        "ideal mirror (δ): a point or directional light shows only\n"
        "where R = v exactly (one point): black but for ambient and k_d\n")


# ------------------------------------------------------------------ the polar and angle plots
def test_polar_and_angle_captions_name_the_compare_list_when_drawn():
    state = AppState()
    model = _model(state)
    polar = captions.polar_caption(state, model.views["polar"], {"scale": "linear"})
    assert polar == "f_r (1/sr)  [luminance Y] · linear"
    assert captions.angles_title(state, model.views["theta_v"]) == (
        "Blinn-Phong: f_r (1/sr)  [luminance Y] against θ_v, θ_h, θ_d (Rusinkiewicz)")
    model.pin()
    state.shininess = 80.0
    model.update()
    assert captions.polar_caption(state, model.views["polar"]).endswith(" · colours: Compare list")
    assert captions.angles_title(state, model.views["theta_v"]).startswith("Blinn-Phong (white; colours: Compare list)")
    assert captions.albedo_panel_title(state, {"title": "Directional albedo"}) == "Directional albedo  [luminance Y]"


# ------------------------------------------------------------------ a BRDF file's name and its k_d control
def test_a_file_model_keeps_its_file_name_and_its_kd_control_says_ambient(tmp_path):
    path = tmp_path / "ggx-copper.brdf"
    path.write_text(LAMBERT_FILE)
    model = _model(AppState())
    name = model.open_brdf(path)
    try:
        state = model.state
        assert model_label(name) == "ggx-copper (file)"
        assert captions.window_title(state) == "lighting-explorer — ggx-copper (file)"
        assert captions.sphere_title(state) == "Lit sphere (engine): ggx-copper (file)"
        assert kd_label(name) == captions.kd_control_label(state) == "k_a (ambient)"
        # What the label says: k_d moves the ambient coefficient only, the BRDF stays the file's.
        before = state.material()
        state.kd = 0.25
        after = state.material()
        assert [type(p).__name__ for p in after.brdf.parts] == [type(p).__name__ for p in before.brdf.parts]
        n, l, v = np.array([0.0, 0, 1]), np.array([0.6, 0, 0.8]), np.array([0.0, 0, 1])
        np.testing.assert_allclose(after.brdf.eval(n, l, v), before.brdf.eval(n, l, v))
        np.testing.assert_allclose(after.ambient, 0.25 * np.asarray(state.color))
        assert not np.allclose(before.ambient, after.ambient)
        # A model the explorer adds Lambert(k_d) to, and one whose diffuse colour k_d fills: k_d is the albedo.
        assert kd_label("blinn-phong") == kd_label("lambert") == kd_label("oren-nayar") == "k_d (diffuse albedo)"
    finally:
        unregister_model(name)


# ------------------------------------------------------------------ one name per environment
def test_one_label_per_environment_everywhere():
    assert tuple(ENVIRONMENT_LABELS) == tuple(ENVIRONMENTS) and set(ENVIRONMENT_HELP) == set(ENVIRONMENTS)
    for name in SKIES:
        # The command line's name, the button's label and every caption's word are one.
        assert environment_label(name) == name and AppState(environment=name).environment == name
        assert ENVIRONMENT_HELP[name] == SKIES[name].description
    assert environment_label("band-limited") == "band-limited"
    assert not any("SH" in label for label in ENVIRONMENT_LABELS.values())
    with pytest.raises(ValueError, match="environment must be one of none, .*; got 'sh9'"):
        environment_label("sh9")


def test_captions_load_no_toolkit():
    import subprocess
    import sys

    code = ("import sys, explorer.app.captions; "
            "print(sorted(m for m in ('PySide6', 'vtk', 'pyvista', 'matplotlib') if m in sys.modules))")  # fmt: skip
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"

"""Image-based lighting in the explorer: the environment choice, the lit object and the progressive reference.

Values, not smoke: a uniform sky on a Lambert surface is the white furnace (every pixel is k_d, π k_d in
the classic form), encoded as the window encodes; the key light keeps its place on screen under an
environment; the reference's error shrinks like 1/√spp, both as it estimates it and against the truth.
"""

import math
import os

import numpy as np
import pytest

from explorer import app as app_mod
from explorer.app import environment as environment_mod
from explorer.app.environment import PASS_SAMPLES, VIEW_TO_WORLD, world_light
from explorer.app.state import CONTROLS, DEFAULTS, AppState
from explorer.app.views import LIVE_VIEWS, VIEWS, ExplorerModel
from lighting import DirectionalLight, PointLight
from lighting.lights import SKIES
from lighting.render import AnalyticSphere, Renderer, sphere_camera
from lighting.render.image import encode_srgb8

pv = pytest.importorskip("pyvista")

SMALL = {"sphere_size": 40, "mesh_size": 32, "lobe_resolution": 8, "object_size": (48, 32)}


@pytest.fixture(autouse=True, scope="module")
def _small_skies():
    """Named skies sampled into 32-row maps, not the window's 256: the same laws, a fraction of the prefiltering."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(environment_mod, "SKY_ROWS", 32)
        yield


def furnace_state(**kw):
    # No key light: the sky alone (the environment replaces the ambient light).
    return AppState(model="lambert", light="ambient", environment="uniform", **kw)


# ------------------------------------------------------------------ controls
def test_controls_table_has_the_environment_and_defaults_keep_todays_window():
    assert CONTROLS["environment"].choices == ("none", *SKIES, "file")
    assert DEFAULTS["environment"] == "none" and DEFAULTS["view3d"] == "lobe" and DEFAULTS["reference"] is False
    state = AppState()
    model = ExplorerModel(state, **SMALL)
    assert model.update() == set(VIEWS)  # no object view while the 3D panel shows the lobe
    r = Renderer(AnalyticSphere(), sphere_camera(SMALL["sphere_size"]), dtype=np.float32)
    want = r.render(state.material(), state.lights(), mode="phong", form="classic")
    np.testing.assert_array_equal(model.views["sphere"].image, want)
    with pytest.raises(ValueError, match=r"env_rotation must be a number in \[-180, 180\]; got 190"):
        AppState(env_rotation=190.0)
    # "file" without a file read: no environment (the window offers the choice only with --environment FILE).
    model = ExplorerModel(AppState(environment="file"), **SMALL)
    model.update()
    assert not model.environment_active and model.environment_light() is None
    with pytest.raises(ValueError, match="environment must be one of none, uniform"):
        AppState(environment="moon")


def test_world_light_turns_the_view_frame_into_the_environments():
    assert np.allclose(VIEW_TO_WORLD @ [0.0, 1.0, 0.0], [0.0, 0.0, 1.0])  # image up is the sky's up
    assert np.isclose(np.linalg.det(VIEW_TO_WORLD), 1.0)
    p = world_light(PointLight((1.0, 2.0, 3.0), intensity=2.0))
    assert np.allclose(p.position, [1.0, -3.0, 2.0]) and p.intensity == 2.0
    d = world_light(DirectionalLight((0.0, 0.6, 0.8)))
    assert np.allclose(d.direction, [0.0, -0.8, 0.6])


# ------------------------------------------------------------------ values
@pytest.mark.parametrize("form, factor", [("physical", 1.0), ("classic", math.pi)])
def test_uniform_sky_on_lambert_is_the_white_furnace(form, factor):
    state = furnace_state(kd=0.25, color=(1.0, 0.6, 0.2), form=form, exposure=-1.0)
    model = ExplorerModel(state, **SMALL)
    model.update()
    sv = model.views["sphere"]
    albedo = state.diffuse_albedo
    lit = sv.image[sv.coverage].astype(np.float64)
    assert sv.coverage.sum() > 900
    np.testing.assert_allclose(lit, np.broadcast_to(factor * albedo, lit.shape), rtol=2e-6)
    # Encoded as the window encodes: the engine's sRGB encoder at the exposure.
    want8 = encode_srgb8(np.asarray(factor * albedo * 2.0**-1.0).reshape(1, 1, 3))[0].reshape(3)
    assert np.all(sv.rgb8[sv.coverage] == want8)
    assert not sv.rgb8[~sv.coverage].any()  # the sphere's panel shows no sky behind it (transparent)
    # The object: the same furnace on every pixel of the mesh, the sky (radiance 1) behind it.
    state.view3d = "object"
    assert "object" in model.update()
    ov = model.views["object"]
    np.testing.assert_allclose(ov.image[ov.coverage], np.broadcast_to(factor * albedo, (ov.coverage.sum(), 3)),
                               rtol=2e-6)  # fmt: skip
    np.testing.assert_allclose(ov.image[~ov.coverage], factor, rtol=1e-6)
    assert 0.15 < ov.coverage.mean() < 0.85 and ov.method == "dominant lights"


def test_key_light_keeps_its_place_on_screen_under_an_environment():
    # An environment of intensity 0 adds nothing: the image is the key light's, rendered in the sky's frame.
    kw = {"model": "blinn-phong", "elevation": 30.0, "azimuth": 150.0, "ambient": 0.0}
    plain = ExplorerModel(AppState(**kw), **SMALL)
    dark = ExplorerModel(AppState(environment="daylight", env_intensity=0.0, **kw), **SMALL)
    plain.update(), dark.update()
    a, b = plain.views["sphere"], dark.views["sphere"]
    assert np.array_equal(a.coverage, b.coverage)
    np.testing.assert_allclose(b.image, a.image, atol=2e-5)
    assert a.brightest == b.brightest


def test_rotation_and_intensity_reuse_one_prefiltered_environment():
    state = AppState(environment="glow", model="cook-torrance", roughness=0.3, light="ambient", form="physical")
    model = ExplorerModel(state, **SMALL)
    model.update()
    first = model.views["sphere"].image.astype(np.float64)
    pre = model._prefiltered["glow"]
    state.env_intensity = 2.0
    model.update()
    np.testing.assert_allclose(model.views["sphere"].image, 2.0 * first, rtol=1e-5, atol=1e-7)
    state.update(env_intensity=1.0, env_rotation=90.0)
    model.update()
    turned = model.views["sphere"].image.astype(np.float64)
    assert model._prefiltered["glow"] is pre
    assert np.abs(turned - first).max() > 0.05  # the glow's sun went round: the image changed


def test_a_drag_shows_the_split_sum_and_the_release_the_dominant_lights():
    # A glossy sphere under a sky with a sun, where the two methods differ: the image a drag shows is the split
    # sum's, the same light rendered by the engine; the release re-shades it once by the engine's default.
    from lighting.lights import EnvironmentLight

    state = AppState(environment="sunset", model="cook-torrance", roughness=0.2, light="ambient", form="physical")
    model = ExplorerModel(state, **SMALL)
    model.update()
    r, _ = model._sphere_renderer_world(state.mode, state.tessellation)
    pre = model._prefiltered["sunset"]

    def render(method, rotation):
        light = EnvironmentLight(model._base("sunset"), rotation=rotation, background=False, prefiltered=pre,
                                 method=method)  # fmt: skip
        return np.asarray(r.render(state.material(), [light], mode=state.mode, form=state.form))

    np.testing.assert_array_equal(model.views["sphere"].image, render("dominant", 0.0))
    state.env_rotation = 30.0
    assert model.update(only={"sphere", "coarse"}) == {"sphere"} and model.provisional == {"sphere"}
    assert not model.pending & LIVE_VIEWS  # what the drag shows is current, by the cheaper method
    live = render("split-sum", 30.0)
    np.testing.assert_array_equal(model.views["sphere"].image, live)
    assert model.update() == {"sphere"} and model.pending == set() and model.provisional == set()
    rest = render("dominant", 30.0)
    np.testing.assert_array_equal(model.views["sphere"].image, rest)
    assert np.abs(rest - live).max() > 0.01 * rest.max()  # the two methods differ here: the release is seen
    assert model.update() == set()  # nothing left: one re-shade


# ------------------------------------------------------------------ the reference
def _run_to(ref, spp):
    while ref.samples < spp:
        ref.step(0.0)  # one pass a call
    assert all(t.samples == spp for t in ref.tiles)


def test_reference_refines_and_its_error_shrinks_like_one_over_root_spp():
    state = furnace_state(kd=0.5, reference=True, view3d="object", form="physical")
    model = ExplorerModel(state, **SMALL)
    model.update()
    ref = model.refinement
    assert ref.samples == 0 and model.refine_caption() == "reference: starting (dominant lights shown)"
    counts = []
    for _ in range(3):
        assert model.refine(0.0) == {"sphere", "object"}
        counts.append(ref.passes)
    assert counts == [1, 2, 3]
    albedo = state.diffuse_albedo
    est, true = [], []
    for spp in (64, 256):
        _run_to(ref, spp)
        value, error = ref.value, ref.error
        est.append(ref.relative_error())
        true.append(float(np.sqrt(np.mean((value - albedo) ** 2))))
        # Honest: the truth lies within 2σ for at least 90 % of the pixel channels.
        assert np.mean(np.abs(value - albedo) <= 2 * error) >= 0.9
    assert 2 / 1.3 <= est[0] / est[1] <= 2 * 1.3
    assert 2 / 1.3 <= true[0] / true[1] <= 2 * 1.3
    # The images are the reference's: the furnace again, now within its error.
    model.refine(0.0)
    ov = model.views["object"]
    assert ov.method == "reference"
    assert abs(ov.image[ov.coverage].mean(axis=0) / albedo - 1).max() < 0.01
    assert model.refine_caption().startswith(f"reference: {ref.samples} spp, ±")


def test_a_control_change_restarts_the_reference_and_others_do_not():
    state = AppState(environment="sunset", model="cook-torrance", roughness=0.2, reference=True)
    model = ExplorerModel(state, **SMALL)
    model.update()
    for _ in range(4):
        model.refine(0.0)
    old = model.refinement
    assert old.samples == PASS_SAMPLES * (4 // len(old.tiles))
    state.phi = 30.0  # the BRDF views' frame: not the images
    model.update()
    assert model.refinement is old
    state.env_rotation = 40.0
    model.update()
    assert model.refinement is not old and model.refinement.samples == 0
    # A drag (the lit sphere live by the split sum, provisional until the dominant lights; the object left pending)
    # stops it; the release starts it again.
    state.view3d = "object"
    model.update()
    state.env_rotation = 50.0
    assert model.update(only={"sphere", "coarse"}) == {"sphere"}
    assert model.pending == {"object"} and model.provisional == {"sphere"}
    assert model.refinement is None and model.refine(0.0) == set()
    assert model.update() == {"object", "sphere"} and model.refinement.samples == 0
    assert model.refine(0.0) == {"sphere", "object"}
    state.reference = False
    model.update()
    assert model.refinement is None and model.refine(0.0) == set()


# ------------------------------------------------------------------ the window and the command


def test_command_bad_mesh_or_environment_file_is_one_error_line(tmp_path, monkeypatch, capsys):
    bad = tmp_path / "broken.obj"
    bad.write_text("v 0 0 0\nf 1 2 3\n")
    monkeypatch.chdir(tmp_path)  # names as given, whole: a long temporary folder would be abbreviated
    assert app_mod.main(["--mesh", bad.name, "--off-screen"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "broken.obj" in err
    assert app_mod.main(["--environment", "none.hdr", "--off-screen"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "none.hdr" in err
    assert app_mod.main(["--environment", "file", "--off-screen"]) == 2
    assert "--environment PATH" in capsys.readouterr().err


def test_help_lists_the_environment_options_with_defaults(capsys):
    with pytest.raises(SystemExit):
        app_mod.main(["--help"])
    out = capsys.readouterr().out
    for option in ("--environment NAME|FILE", "--env-rotation", "--env-intensity", "--view3d", "--reference",
                   "--mesh FILE"):  # fmt: skip
        assert option in out
    assert "(default: none)" in out and "(default: lobe)" in out


def test_a_scene_s_environment_light_becomes_the_environment_controls():
    from explorer.app.scenes import scene_environment_file
    from explorer.app.state import AppState
    from lighting.scene import example_path

    studio = AppState.from_args({"scene": example_path("studio")})
    assert (studio.environment, studio.env_rotation, studio.env_intensity) == ("studio", 0.0, 1.0)
    assert scene_environment_file(example_path("studio")) is None  # a sky: nothing to read
    sky_file = AppState.from_args({"scene": example_path("environment")})
    assert sky_file.environment == "file"
    path, env = scene_environment_file(example_path("environment"))
    assert path.endswith("daylight_sky.hdr") and os.path.isfile(path)
    from lighting.lights import read_environment_image

    np.testing.assert_array_equal(env.image, read_environment_image(path))  # the sky the file holds
    assert AppState.from_args({"scene": example_path("cube")}).environment == "none"

"""The explorer's extra lights (explorer/app/lights.py, AppState.scene_lights, state_from_scene).

Every light a scene holds reaches the explorer: a scene lit only by a rect, a disk or an OpenGL light
shows the same lit sphere in the explorer as ``lighting-explorer render`` draws (the scene renderer,
:class:`lighting.scene.SceneRenderer`), pixel for pixel where the framings agree.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from explorer.app import captions
from explorer.app.command import build_parser
from explorer.app.lights import (
    EXTRA_LIGHT_TYPES,
    LIGHT_FIELDS,
    check_lights,
    field_value,
    has_direct_light,
    light_label,
    lights_line,
    new_light,
    with_field,
)
from explorer.app.scenes import state_from_scene
from explorer.app.state import CONTROLS, AppState
from explorer.app.views import ExplorerModel
from lighting.scene import SceneRenderer, load_scene

SIZE = 64
#: Explorer (float32 shading) against the scene renderer (float64), relative to the image's peak.
TOLERANCE = 2e-5
#: The same for a disk light sampled at 4096 points in a turned frame (its sample pattern turns differently).
DISK_TOLERANCE = 1e-3

SPHERE_MATERIAL = ('material = {parts = [{model = "lambert", kd = 0.6}, '
                   '{model = "blinn-phong", ks = 0.3, shininess = 20}]}')  # fmt: skip
GL_MATERIAL = ('material = {model = "opengl", ambient = [0.5, 0.3, 0.2, 1.0], diffuse = [0.5, 0.3, 0.2, 1.0], '
               'specular = [0.3, 0.3, 0.3, 1.0], shininess = 20}')  # fmt: skip


def _scene(tmp_path, lights: str, *, centre=(0.0, 0.0, 0.0), radius=1.0, toward=(0.0, 0.0, 1.0), up=(0.0, 1.0, 0.0),
           material=SPHERE_MATERIAL, extra="") -> str:  # fmt: skip
    """A scene file: one sphere, an orthographic camera framing it as the explorer's lit sphere is framed."""
    c, t = np.asarray(centre, float), np.asarray(toward, float) / np.linalg.norm(toward)
    eye = c + 20.0 * radius * t
    text = f"""
[camera]
eye = {eye.tolist()}
target = {c.tolist()}
up = {list(up)}
projection = "orthographic"
ortho_height = {2 * 1.08 * radius!r}

[image]
width = {SIZE}
height = {SIZE}
{extra}
[[objects]]
type = "sphere"
center = {c.tolist()}
radius = {radius!r}
{material}

{lights}
"""
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return str(path)


def _explorer_image(state):
    model = ExplorerModel(state, sphere_size=SIZE, mesh_size=32, lobe_resolution=8)
    model.update()
    sv = model.views["sphere"]
    return np.asarray(sv.image, dtype=np.float64), sv.coverage


def _compare(path):
    """The explorer's lit sphere and the scene renderer's image of a scene file: (state, explorer, render, coverage)."""
    state = state_from_scene(path)
    img, cov = _explorer_image(state)
    ref, _ = SceneRenderer(load_scene(path)).render()
    return state, img, np.asarray(ref, dtype=np.float64), cov


def _assert_same_image(img, ref, cov, tolerance=TOLERANCE):
    peak = float(ref.max())
    assert peak > 0.1  # lit, not black
    assert np.count_nonzero(np.any(img[cov] > 0.01 * peak, axis=-1)) > 0.3 * cov.sum()  # a good part of it lit
    diff = float(np.max(np.abs(img - ref)))
    assert diff <= tolerance * peak, (diff, peak)
    return diff / peak


RECT = """
[[lights]]
type = "rect"
center = [1.5, 1.0, 2.5]
edge_u = [1.0, 0.0, 0.0]
edge_v = [0.0, -1.0, 0.0]
intensity = 3.0
samples = 16
"""
DISK = """
[[lights]]
type = "disk"
center = [-1.2, 1.6, 2.2]
normal_dir = [0.4, -0.5, -0.8]
radius = 0.6
intensity = 2.5
two_sided = true
"""


@pytest.mark.parametrize("light", [RECT, DISK], ids=["rect", "disk"])
def test_a_scene_lit_by_an_area_light_alone_is_lit_in_the_explorer_as_render_draws_it(tmp_path, light):
    state, img, ref, cov = _compare(_scene(tmp_path, light))
    assert state.light == "ambient" and state.ambient == 0.0  # no key light, no ambient light: only the area light
    assert [t["type"] for t in state.scene_lights] == [light.split('"')[1]]
    _assert_same_image(img, ref, cov)
    kind = state.scene_lights[0]["type"]
    assert has_direct_light(state) and lights_line(state) == f"no key light + 1 scene light ({kind})"
    assert "ambient light only" not in captions.light_summary(state)  # the lit sphere's caption
    # Without the extra light the sphere is black: the light seen is the area light's.
    state.scene_lights = ()
    assert not np.any(_explorer_image(state)[0]) and lights_line(state) == "ambient light only"
    assert captions.light_summary(state).startswith("ambient light only\n")


@pytest.mark.slow  # seconds of work: the full run has it, the fast loop leaves it out
def test_scene_lights_are_moved_scaled_and_turned_into_the_view_frame(tmp_path):
    """A sphere of radius 2 away from the origin, seen from an oblique camera: every kind of light agrees."""
    lights = """
[[lights]]
type = "directional"
direction = [0.2, -0.3, 1.0]
intensity = 0.4

[[lights]]
type = "point"
position = [4.0, 3.0, 3.0]
intensity = 20.0
attenuation = [1.0, 0.5, 0.2]

[[lights]]
type = "spot"
position = [1.0, 7.0, 2.0]
direction = [0.0, -1.0, 0.1]
cutoff_deg = 40.0
exponent = 4.0
intensity = 30.0

[[lights]]
type = "rect"
center = [3.0, -1.0, 4.0]
edge_u = [1.2, 0.0, 0.0]
edge_v = [0.0, 0.0, -0.8]
intensity = 2.0
two_sided = true

[[lights]]
type = "disk"
center = [-2.0, 4.0, 3.0]
normal_dir = [0.5, -0.4, -0.6]
radius = 1.0
intensity = 1.5
samples = 4096

[[lights]]
type = "directional"
direction = [-1.0, 0.5, 0.5]
color = [0.2, 0.4, 0.9]
intensity = 0.5
"""
    path = _scene(tmp_path, lights, centre=(1.0, 2.0, -1.0), radius=2.0, toward=(1.0, 1.0, 2.0), up=(0.0, 0.0, 1.0))
    state, img, ref, cov = _compare(path)
    # The first directional light is the key light; the other five are extra lights, in the scene's order.
    assert state.light == "directional"
    assert [t["type"] for t in state.scene_lights] == ["point", "spot", "rect", "disk", "directional"]
    # The point light's falloff in object radii: 1 / (a r² d'² + b r d' + c) with r = 2.
    assert state.scene_lights[0]["attenuation"] == [4.0, 1.0, 0.2]
    assert state.scene_lights[3]["radius"] == 0.5
    # A disk's sample points are laid out in a frame made from its normal, which does not turn with the scene: in
    # the view frame they are other points of the same disk, and the two estimates agree to the sampling error.
    _assert_same_image(img, ref, cov, DISK_TOLERANCE)
    assert lights_line(state).endswith("+ 5 scene lights (point, spot, rect, disk, directional)")


def test_a_scene_lit_by_opengl_lights_is_lit_in_the_explorer_as_render_draws_it(tmp_path):
    """The first OpenGL light is the key light, the second an extra light; both in an oblique, scaled frame."""
    lights = """
[[lights]]
type = "opengl"
position = [-1.0, 1.0, 1.0, 0.0]
diffuse = [0.5, 0.5, 0.5, 1.0]
specular = [0.5, 0.5, 0.5, 1.0]
ambient = [0.1, 0.1, 0.1, 1.0]

[[lights]]
type = "opengl"
position = [4.0, 2.0, 3.0, 1.0]
diffuse = [0.3, 0.4, 0.9, 1.0]
specular = [0.3, 0.4, 0.9, 1.0]
spot_direction = [-0.6, -0.1, -0.5]
spot_cutoff = 40.0
spot_exponent = 6.0
constant_attenuation = 0.5
linear_attenuation = 0.1
quadratic_attenuation = 0.05
"""
    path = _scene(tmp_path, lights, centre=(0.5, 0.0, -0.5), radius=1.5, toward=(0.3, 0.4, 1.0), material=GL_MATERIAL,
                  extra='[opengl]\nscene_ambient = [0.1, 0.1, 0.1, 1.0]\n')  # fmt: skip
    state, img, ref, cov = _compare(path)
    assert state.light == "directional" and [t["type"] for t in state.scene_lights] == ["opengl"]
    assert float(ref.max()) < 1.0  # OpenGL clamps each colour to [0, 1]: the comparison stays below that
    _assert_same_image(img, ref, cov)
    assert "+ 1 scene light (opengl)" in lights_line(state)


def test_a_scene_lit_by_one_opengl_light_is_lit_in_the_explorer_as_render_draws_it(tmp_path):
    """One positional OpenGL light (no falloff, no cone): the key light, as before; the explorer matches render."""
    lights = """
[[lights]]
type = "opengl"
position = [1.0, 2.0, 3.0, 1.0]
diffuse = [0.9, 0.8, 0.6, 1.0]
specular = [0.9, 0.8, 0.6, 1.0]
"""
    path = _scene(tmp_path, lights, material=GL_MATERIAL, extra="[opengl]\nscene_ambient = [0.0, 0.0, 0.0, 1.0]\n")
    state, img, ref, cov = _compare(path)
    assert state.light == "point" and state.scene_lights == ()
    _assert_same_image(img, ref, cov)


# ----------------------------------------------------------------------------- the lights module
@pytest.mark.parametrize("kind", EXTRA_LIGHT_TYPES)
def test_a_new_light_of_every_kind_lights_the_visible_side(kind):
    state = AppState(light="ambient", ambient=0.0)
    state.scene_lights = [new_light(kind, state)]
    img, cov = _explorer_image(state)
    y = img @ np.array([0.2126, 0.7152, 0.0722])
    assert float(img[cov].mean()) > 0.05
    assert np.count_nonzero(y[cov] > 0.01) > 0.3 * cov.sum()
    # From the upper right (azimuth 45°, 35° above the image plane): the brightest pixel is up and right.
    row, col = np.unravel_index(int(np.argmax(y)), y.shape)
    assert row < SIZE / 2 < col
    # Every field of the kind reads back, and the label names the kind.
    table = state.scene_lights[0]
    assert all(field_value(table, f.name) is not None for f in LIGHT_FIELDS[kind])
    assert light_label(table).startswith(kind)


def test_a_new_light_comes_from_across_the_key_light():
    state = AppState(light="directional", elevation=30.0, azimuth=0.0)  # key light from the right
    d = np.asarray(new_light("directional", state)["direction"])
    assert d[0] < 0 and abs(d[1]) < 1e-4 and math.isclose(math.degrees(math.asin(d[2])), 35.0, abs_tol=0.01)


def test_with_field_refusals_name_the_light_and_the_field():
    state = AppState()
    lights = tuple(new_light(k, state) for k in EXTRA_LIGHT_TYPES)  # directional, point, spot, rect, disk, opengl
    for index, name, value, detail in [
        (0, "intensity", -1.0, "intensity must be a finite number >= 0; got -1.0"),
        (1, "attenuation", [0.0, 0.0, 0.0], "attenuation must be three finite numbers"),
        (2, "cutoff_deg", 120.0, "cutoff_deg must be in [0, 90] degrees or exactly 180"),
        (3, "edge_v", [2 * x for x in lights[3]["edge_u"]], "edge_u and edge_v must span a rectangle"),
        (3, "samples", 2.5, "must be an integer >= 1; got a float 2.5"),
        (4, "radius", 0.0, "radius must be"),
        (4, "center", "up", "must be a 3-vector (an array of 3 numbers); got a string"),
        (5, "spot_cutoff", 100.0, "spot_cutoff must be a number of degrees in [0, 90], or exactly 180"),
        (5, "diffuse", [-1.0, 0.0, 0.0], "diffuse must be a finite scalar or RGB triple with every entry >= 0"),
        (0, "position", [1.0, 0.0, 0.0], "unknown field of a 'directional' light; fields: direction, color, intensity"),
    ]:
        key = {"edge_v": "edge_u"}.get(name, name)  # the rectangle's check names its first edge
        with pytest.raises(ValueError) as info:
            with_field(lights, index, name, value)
        msg = str(info.value)
        assert msg.startswith(f"scene_lights[{index}].{key}: ") and detail in msg and "\n" not in msg, msg
    # The refusal through the state: the same message, and nothing changes.
    state.scene_lights = lights
    before = state.to_dict()
    bad = list(lights)
    bad[2] = {**bad[2], "exponent": float("nan")}
    with pytest.raises(ValueError, match=r"^scene_lights\[2\]\.exponent: must be a finite number; got nan"):
        state.update(scene_lights=bad, kd=0.2)
    assert state.to_dict() == before
    for value in ("rect", {"type": "rect"}, 3, None):
        with pytest.raises(ValueError, match="^scene_lights must be a list of light tables"):
            state.scene_lights = value
    with pytest.raises(ValueError, match=r"^scene_lights\[0\]\.type: must be one of 'directional', .*'opengl'"):
        state.scene_lights = [{"type": "environment"}]
    with pytest.raises(ValueError, match=r"^scene_lights\[0\]\.space: unknown key for an 'opengl' light"):
        state.scene_lights = [{"type": "opengl", "space": "eye"}]
    assert state.to_dict() == before


def test_with_field_changes_one_field_and_the_image_follows():
    state = AppState(light="ambient", ambient=0.0)
    state.scene_lights = [new_light("rect", state), new_light("opengl", state)]
    model = ExplorerModel(state, sphere_size=SIZE, mesh_size=32, lobe_resolution=8)
    model.update()
    one = np.asarray(model.views["sphere"].image, dtype=np.float64)
    lights = state.scene_lights
    changed = with_field(lights, 0, "intensity", 3 * lights[0]["intensity"])
    assert lights == state.scene_lights and changed[1] == lights[1]  # a new tuple; the old one as it was
    state.scene_lights = changed
    # The extra lights are lights: only the images follow (the BRDF plots show the key light's angle).
    assert model.update() == {"sphere", "coarse", "profile"}
    three = np.asarray(model.views["sphere"].image, dtype=np.float64)
    state.scene_lights = lights[1:]
    model.update()
    gl_only = np.asarray(model.views["sphere"].image, dtype=np.float64)
    # Light adds up: tripling the rect's radiance adds twice its image.
    np.testing.assert_allclose(three - gl_only, 3 * (one - gl_only), atol=1e-5 * float(three.max()))
    # An OpenGL colour keeps its alpha; its position keeps w, and "directional" sets it.
    gl = with_field(lights, 1, "diffuse", (0.5, 0.25, 0.0))[1]
    assert gl["diffuse"] == [0.5, 0.25, 0.0, 1.0] and field_value(gl, "diffuse") == (0.5, 0.25, 0.0)
    gl = with_field(lights, 1, "directional", False)[1]
    assert gl["position"][3] == 1.0 and field_value(gl, "directional") is False
    gl = with_field((gl,), 0, "position", [0.0, 2.0, 2.0])[0]
    assert gl["position"] == [0.0, 2.0, 2.0, 1.0] and field_value(gl, "position") == (0.0, 2.0, 2.0)
    assert with_field(lights, 0, "samples", 32.0)[0]["samples"] == 32  # an editor's whole float


def test_scene_lights_round_trip_through_to_dict():
    state = AppState(model="phong")
    state.update(scene_lights=[new_light(k, state) for k in EXTRA_LIGHT_TYPES])
    d = state.to_dict()
    again = AppState(**d)
    assert again == state and again.scene_lights == state.scene_lights
    assert again.to_dict() == d and state.copy() == state
    # What the state hands out is a copy: changing it changes nothing.
    state.scene_lights[0]["intensity"] = 5.0
    d["scene_lights"][1]["position"][0] = 9.0
    assert state.scene_lights == again.scene_lights
    # The tables are the scene loader's (defaults filled in): checking them again leaves them as they are.
    assert check_lights(state.scene_lights) == state.scene_lights
    assert len(state.lights()) == 1 + 1 + len(EXTRA_LIGHT_TYPES)  # ambient, key, one engine light each
    assert "scene_lights" in state.reset() and state.scene_lights == () and len(state.lights()) == 2


def test_extra_lights_reach_the_object_view_and_the_environment():
    state = AppState(light="ambient", ambient=0.0, view3d="object")
    model = ExplorerModel(state, sphere_size=32, mesh_size=32, lobe_resolution=8, object_size=(48, 32))
    model.update()
    dark = np.asarray(model.views["object"].image, dtype=np.float64)
    state.scene_lights = [new_light("disk", state)]
    assert {"sphere", "object"} <= model.update()
    lit = np.asarray(model.views["object"].image, dtype=np.float64)
    assert not np.any(dark) and float(lit.mean()) > 0.01
    assert len(model.world_lights()) == 1  # no key light; the disk, turned into the environment's frame


def test_the_command_line_offers_no_scene_lights_option():
    assert CONTROLS["scene_lights"].kind == "lights"
    text = build_parser().format_help()
    assert "scene-lights" not in text and "scene_lights" not in text

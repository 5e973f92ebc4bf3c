"""Value tests for ``lighting.shading.opengl``: hand-computed colours of the OpenGL 2.1
fixed-function lighting equation (§2.14.1), dtype policy, degenerate inputs
and parameter validation."""

from __future__ import annotations

import dataclasses
import doctest
import math
import warnings

import numpy as np
import pytest

import lighting.shading.opengl as gl
from lighting.shading.opengl import Light, Material, shade_vertices

BLACK = (0.0, 0.0, 0.0)
UP = (0.0, 0.0, 1.0)


def shade(positions, normals, material, lights, **kw):
    kw.setdefault("scene_ambient", BLACK)
    return shade_vertices(positions, normals, material, lights, **kw)


def diffuse_only(rgb=(1.0, 1.0, 1.0), alpha=1.0):
    return Material(ambient=BLACK, diffuse=(*rgb, alpha), specular=BLACK)


# --------------------------------------------------------------------------- basic terms
def test_defaults_straight_on():
    # GL defaults: c = a_cm a_cs + d_cm d_cl (n·VP) = 0.2·0.2 + 0.8·1·1.
    c = shade_vertices((0.0, 0.0, -1.0), UP, Material(), [Light()])
    np.testing.assert_allclose(c, [0.84, 0.84, 0.84, 1.0], rtol=0, atol=1e-15)


def test_red_light_on_green_surface_is_black():
    red = Light(diffuse=(1, 0, 0), specular=BLACK)
    green = Material(ambient=BLACK, diffuse=(0, 1, 0))
    c = shade((0, 0, -1), UP, green, red)
    np.testing.assert_array_equal(c, [0.0, 0.0, 0.0, 1.0])


def test_lambert_cosine():
    theta = math.radians(60)
    light = Light(position=(math.sin(theta), 0.0, math.cos(theta), 0.0), specular=BLACK)
    c = shade((0, 0, -1), UP, diffuse_only((0.5, 0.25, 1.0)), light)
    np.testing.assert_allclose(c[:3], np.array([0.5, 0.25, 1.0]) * 0.5, rtol=0, atol=1e-15)


def test_emission_and_scene_ambient_without_lights():
    m = Material(ambient=(0.5, 0.4, 0.3), emission=(0.1, 0.2, 0.3))
    c = shade_vertices((0, 0, -1), UP, m, [], scene_ambient=(0.2, 0.5, 1.0))
    np.testing.assert_allclose(c, [0.1 + 0.1, 0.2 + 0.2, 0.3 + 0.3, 1.0], rtol=0, atol=1e-15)


def test_lights_add_up():
    light = Light(diffuse=(0.25, 0.25, 0.25), specular=BLACK)
    one = shade((0, 0, -1), UP, diffuse_only(), [light])
    two = shade((0, 0, -1), UP, diffuse_only(), [light, light])
    np.testing.assert_allclose(two[:3], 2 * one[:3], rtol=0, atol=1e-15)


def test_light_ambient_term():
    # a_cm a_cl is added regardless of the normal (for a plain light).
    light = Light(ambient=(0.5, 0.5, 0.5), diffuse=BLACK, specular=BLACK)
    m = Material(ambient=(0.2, 0.4, 0.6), diffuse=BLACK)
    c = shade((0, 0, -1), (0, 0, -1), m, light)
    np.testing.assert_allclose(c[:3], [0.1, 0.2, 0.3], rtol=0, atol=1e-15)


def test_gl_default_other_lights_are_black():
    assert Light.gl_default(0) == Light()
    l1 = Light.gl_default(3)
    assert l1.diffuse == (0.0, 0.0, 0.0, 1.0) and l1.specular == (0.0, 0.0, 0.0, 1.0)
    assert l1.ambient == (0.0, 0.0, 0.0, 1.0) and l1.position == (0.0, 0.0, 1.0, 0.0)
    assert Light.gl_default(2, diffuse=(1, 0, 0)).diffuse == (1.0, 0.0, 0.0, 1.0)
    c = shade((0, 0, -1), UP, Material(specular=(1, 1, 1)), [Light.gl_default(1)])
    np.testing.assert_array_equal(c, [0.0, 0.0, 0.0, 1.0])


# --------------------------------------------------------------------------- specular
def specular_only(shininess, rgb=(1.0, 1.0, 1.0)):
    return Material(ambient=BLACK, diffuse=BLACK, specular=rgb, shininess=shininess)


def test_highlight_infinite_viewer():
    # Light along +z, normal +z: h = normalize(VP + (0,0,1)) = n, so (n·h)^s = 1.
    c = shade((0.3, -0.2, -1), UP, specular_only(37.0, (0.5, 0.25, 0.125)), Light(diffuse=BLACK))
    np.testing.assert_allclose(c[:3], [0.5, 0.25, 0.125], rtol=0, atol=1e-15)


def test_highlight_off_peak():
    # VP at 60° from the normal: h at 30°, (n·h)^s = cos(30°)^s.
    theta = math.radians(60)
    light = Light(position=(math.sin(theta), 0, math.cos(theta), 0), diffuse=BLACK)
    c = shade((0, 0, -1), UP, specular_only(8.0), light)
    np.testing.assert_allclose(c[:3], math.cos(math.radians(30)) ** 8, rtol=1e-14)


def test_local_viewer_changes_only_the_half_vector():
    # Vertex at (1, 0, -1): VP_e = (-1, 0, 1)/√2 is 45° from VP = (0, 0, 1), so
    # the local viewer's h is 22.5° from n; the infinite viewer's h is n.
    light = Light(diffuse=BLACK)
    m = specular_only(10.0)
    far = shade((1.0, 0.0, -1.0), UP, m, light, local_viewer=False)
    near = shade((1.0, 0.0, -1.0), UP, m, light, local_viewer=True)
    np.testing.assert_allclose(far[:3], 1.0, rtol=0, atol=1e-15)
    np.testing.assert_allclose(near[:3], math.cos(math.pi / 8) ** 10, rtol=1e-14)
    # On the z axis VP_e = (0, 0, 1): both agree.
    a = shade((0, 0, -3), UP, m, light, local_viewer=False)
    b = shade((0, 0, -3), UP, m, light, local_viewer=True)
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-15)


def test_no_specular_from_behind_even_with_zero_shininess():
    # f_i = 0 when n·VP <= 0: 0^0 = 1 must not light the back.
    behind = Light(position=(0, 0, -1, 0), ambient=BLACK)
    m = Material(ambient=BLACK, diffuse=(0.5, 0.5, 0.5), specular=(0.5, 0.5, 0.5), shininess=0.0)
    np.testing.assert_array_equal(shade((0, 0, -1), UP, m, behind), [0, 0, 0, 1])
    # Grazing (n·VP = 0 exactly) although n·h = cos 45° > 0.
    grazing = Light(position=(1, 0, 0, 0))
    np.testing.assert_array_equal(shade((0, 0, -1), UP, m, grazing), [0, 0, 0, 1])
    # In front, shininess 0 gives the full s_cm s_cl (0^0 = 1 case included).
    front = Light(position=(0.6, 0, 0.8, 0))
    np.testing.assert_allclose(shade((0, 0, -1), UP, m, front)[:3], 0.8 * 0.5 + 0.5, rtol=0, atol=1e-15)


def test_degenerate_half_vector_zero_shininess():
    # VP = (0, 0, -1) and the infinite viewer's (0, 0, 1) cancel: h = 0, and
    # (n·h)^s = 0^s is 1 for s = 0 and 0 otherwise.
    light = Light(position=(0, 0, -1, 0), diffuse=BLACK)
    n = (0.0, 0.0, -1.0)  # facing the light, so f_i = 1
    with np.errstate(all="raise"):
        c0 = shade((0, 0, -1), n, specular_only(0.0), light)
        c5 = shade((0, 0, -1), n, specular_only(5.0), light)
    np.testing.assert_array_equal(c0, [1, 1, 1, 1])
    np.testing.assert_array_equal(c5, [0, 0, 0, 1])


# --------------------------------------------------------------------------- attenuation and spots
def test_distance_attenuation():
    # d = 2: 1 / (1 + 0.5·2 + 0.25·4) = 1/3.
    light = Light(
        position=(0, 0, 0, 1),
        constant_attenuation=1.0,
        linear_attenuation=0.5,
        quadratic_attenuation=0.25,
        specular=BLACK,
    )
    c = shade((0, 0, -2), UP, diffuse_only((0.6, 0.6, 0.6)), light)
    np.testing.assert_allclose(c[:3], 0.2, rtol=1e-15)


def test_homogeneous_light_position():
    a = Light(position=(0, 0, 1, 1), linear_attenuation=1.0)
    b = Light(position=(0, 0, 2, 2), linear_attenuation=1.0)
    p = np.array([[0.3, 0.1, -1.0], [0.0, 0.0, -5.0]])
    m = Material(specular=(1, 1, 1), shininess=20)
    np.testing.assert_allclose(shade(p, UP, m, a), shade(p, UP, m, b), rtol=0, atol=1e-15)


def test_directional_lights_are_not_attenuated():
    light = Light(position=(0, 0, 1, 0), constant_attenuation=4.0, quadratic_attenuation=9.0, specular=BLACK)
    c = shade((0, 0, -100), UP, diffuse_only((0.5, 0.5, 0.5)), light)
    np.testing.assert_allclose(c[:3], 0.5, rtol=0, atol=1e-15)


def spot(cutoff, exponent=0.0, **kw):
    return Light(position=(0, 0, 0, 1), spot_direction=(0, 0, -1), spot_cutoff=cutoff, spot_exponent=exponent, **kw)


def test_spot_cone_masks_everything_including_ambient():
    light = spot(30.0, ambient=(1, 1, 1), diffuse=(1, 1, 1), specular=BLACK)
    m = Material(ambient=(0.2, 0.2, 0.2), diffuse=(0.5, 0.5, 0.5), emission=(0.1, 0, 0))
    # Normals point back at the light at the origin: n·VP = 1.
    inside = shade((0, 0, -1), UP, m, light)
    d = np.array([1.0, 0.0, -1.0]) / math.sqrt(2)  # 45° off axis: outside
    outside = shade(d, -d, m, light)
    np.testing.assert_allclose(inside[:3], [0.1 + 0.2 + 0.5, 0.7, 0.7], rtol=0, atol=1e-15)
    np.testing.assert_allclose(outside[:3], [0.1, 0.0, 0.0], rtol=0, atol=1e-15)


def test_spot_exponent():
    a = math.radians(20)
    d = np.array([math.sin(a), 0.0, -math.cos(a)])
    c = shade(d, -d, diffuse_only(), spot(25.0, 3.0, specular=BLACK))
    np.testing.assert_allclose(c[:3], math.cos(a) ** 3, rtol=1e-14)


def test_spot_cutoff_90_lights_a_hemisphere():
    # The spot cone: the raw cosine -VP·ŝ decides, as Mesa does (conventions.md).  A 90° cone
    # is the half-space in front of the spot's plane: behind it nothing, whatever the exponent
    # (the specification's clamped cosine lit the whole sphere, with 0^0 = 1 behind the plane).
    m = Material(ambient=(0.5, 0.5, 0.5), diffuse=BLACK)
    behind = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 1e-9], [0.0, -3.0, 1e-300]])
    front = np.array([[0.0, 0.0, -1.0], [1.0, 0.0, -1e-9], [0.0, 2.0, -1e-300]])
    for exponent in (0.0, 1.0, 128.0):
        light = spot(90.0, exponent, ambient=(1, 1, 1))
        np.testing.assert_array_equal(shade(behind, UP, m, light)[:, :3], 0.0)
        c = shade(front, UP, m, light)[:, :3]
        cos_s = -front[:, 2] / np.linalg.norm(front, axis=-1)  # -VP·ŝ with ŝ = (0, 0, -1)
        np.testing.assert_allclose(c, np.broadcast_to(0.5 * (cos_s**exponent)[:, None], c.shape), rtol=1e-14, atol=0)
    # On the plane itself the cosine is exactly 0 >= cos 90° = 0: inside, 0^0 = 1, 0^e = 0.
    on_plane = (1.0, 0.0, 0.0)
    np.testing.assert_allclose(shade(on_plane, UP, m, spot(90.0, 0.0, ambient=(1, 1, 1)))[:3], 0.5, atol=0)
    np.testing.assert_array_equal(shade(on_plane, UP, m, spot(90.0, 2.0, ambient=(1, 1, 1)))[:3], 0.0)


@pytest.mark.parametrize("cutoff", [89.0, 89.999999, 90.0])
def test_spot_cone_edge_near_90_uses_the_exact_cosine(cutoff):
    # cos 90° is exactly 0 (cos_sin_deg), not 6.1e-17: a vertex 1e-20 rad in front of the plane is
    # inside a 90° cone; for cutoffs below 90° the edge sits at the angle itself on either side.
    m = Material(ambient=(0.5, 0.5, 0.5), diffuse=BLACK)
    light = spot(cutoff, 0.0, ambient=(1, 1, 1))
    edge = math.radians(cutoff)
    for delta, lit in ((-1e-9, True), (1e-9, False)) if cutoff < 90 else ((-1e-20, True), (1e-20, False)):
        # At 90° the offset is put into the z component directly (π/2 + 1e-20 rounds to π/2).
        p = (math.sin(edge + delta), 0.0, -math.cos(edge + delta)) if cutoff < 90 else (1.0, 0.0, delta)
        got = shade(p, UP, m, light)[:3]
        np.testing.assert_array_equal(got, 0.5 if lit else 0.0)


def test_spot_applies_to_directional_lights():
    # The light-to-vertex direction of a directional light is -VP everywhere.
    m = diffuse_only()
    lit = Light(position=(0, 0, 1, 0), spot_direction=(0, 0, -1), spot_cutoff=10.0, specular=BLACK)
    dark = Light(position=(0, 0, 1, 0), spot_direction=(1, 0, -1), spot_cutoff=10.0, specular=BLACK)
    np.testing.assert_allclose(shade((0, 0, -1), UP, m, lit)[:3], 1.0, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(shade((0, 0, -1), UP, m, dark)[:3], 0.0)


def test_spot_direction_is_normalized():
    a = spot(40.0, 2.0, specular=BLACK)
    b = Light(position=(0, 0, 0, 1), spot_direction=(0, 0, -7), spot_cutoff=40.0, spot_exponent=2.0, specular=BLACK)
    p = np.array([[0.1, 0.2, -1.0], [0.5, 0.0, -1.0]])
    np.testing.assert_allclose(shade(p, -p, diffuse_only(), a), shade(p, -p, diffuse_only(), b), rtol=0, atol=1e-15)


# --------------------------------------------------------------------------- clamp, alpha, normals
def test_clamped_to_unit_interval():
    bright = Light(diffuse=(5, 0.5, 5), specular=BLACK)
    c = shade((0, 0, -1), UP, diffuse_only((1.0, 1.0, 0.0)), bright)
    np.testing.assert_allclose(c, [1.0, 0.5, 0.0, 1.0], rtol=0, atol=1e-15)
    negative = Light(diffuse=(-1, -1, -1), specular=BLACK)  # a "negative light" darkens
    c = shade_vertices((0, 0, -1), UP, Material(), [negative])
    np.testing.assert_array_equal(c, [0.0, 0.0, 0.0, 1.0])


def test_alpha_is_the_diffuse_alpha():
    m = Material(ambient=(1, 1, 1, 0.1), diffuse=(0.5, 0.5, 0.5, 0.3), specular=(1, 1, 1, 0.9), emission=(0, 0, 0, 0.7))
    light = Light(ambient=(1, 1, 1, 0.2), diffuse=(1, 1, 1, 0.0), specular=(1, 1, 1, 0.5))
    p = np.random.default_rng(0).uniform(-1, 1, (5, 3))
    c = shade_vertices(p, UP, m, [light, light], scene_ambient=(0.2, 0.2, 0.2, 0.6))
    np.testing.assert_array_equal(c[:, 3], 0.3)
    np.testing.assert_array_equal(shade_vertices(p, UP, Material(diffuse=(1, 1, 1, 2.0)), [])[:, 3], 1.0)


def test_normalize_flag():
    light = Light(specular=BLACK, diffuse=(0.25, 0.25, 0.25))
    m = diffuse_only()
    unit = shade((0, 0, -1), (0, 0, 1), m, light)
    np.testing.assert_allclose(shade((0, 0, -1), (0, 0, 3), m, light), unit, rtol=0, atol=1e-15)
    # Without GL_NORMALIZE the length scales n·VP (here by 3).
    raw = shade((0, 0, -1), (0, 0, 3), m, light, normalize=False)
    np.testing.assert_allclose(raw[:3], 0.75, rtol=0, atol=1e-15)


def test_zero_normal_is_finite():
    m = Material(specular=(1, 1, 1), shininess=0.0)
    light = Light(ambient=(0.1, 0.1, 0.1))
    for normalize in (True, False):
        with np.errstate(all="raise"):
            c = shade_vertices((0, 0, -1), (0, 0, 0), m, light, normalize=normalize)
        # Only ambient: 0.2·0.2 + 0.2·0.1; f_i = 0 so no specular either.
        np.testing.assert_allclose(c, [0.06, 0.06, 0.06, 1.0], rtol=0, atol=1e-15)


# --------------------------------------------------------------------------- shapes and dtypes
def test_shapes_broadcast():
    p = np.zeros((4, 5, 3))
    p[..., 2] = -1.0
    assert shade_vertices(p, UP, Material(), [Light()]).shape == (4, 5, 4)
    assert shade_vertices((0, 0, -1), np.tile(UP, (7, 1)), Material(), [Light()]).shape == (7, 4)
    assert shade_vertices((0, 0, -1), UP, Material(), Light()).shape == (4,)
    assert shade_vertices(np.empty((0, 3)), UP, Material(), [Light()]).shape == (0, 4)


@pytest.mark.parametrize(
    "p_dtype, n_dtype, expected",
    [
        (np.float32, np.float32, np.float32),
        (np.float64, np.float64, np.float64),
        (np.float32, None, np.float32),
        (np.float32, np.float64, np.float64),
        (np.int64, None, np.float64),
        (None, None, np.float64),
    ],
)
def test_dtype_policy(p_dtype, n_dtype, expected):
    p = (0.1, 0.2, -1.0) if p_dtype is None else np.array([0.1, 0.2, -1.0]).astype(p_dtype)
    n = (0.0, 0.6, 0.8) if n_dtype is None else np.array([0.0, 0.6, 0.8], dtype=n_dtype)
    m = Material(specular=(1, 1, 1), shininess=30)
    c = shade_vertices(p, n, m, [Light(position=(1, 2, 3, 1), linear_attenuation=0.1)])
    assert c.dtype == expected


def test_float32_matches_float64():
    rng = np.random.default_rng(1)
    p = rng.uniform(-1, 1, (50, 3))
    n = rng.normal(size=(50, 3))
    m = Material(specular=(0.5, 0.5, 0.5), shininess=40)
    lights = [Light(position=(1, 1, 1, 1), quadratic_attenuation=0.3), Light(position=(0, 1, 1, 0))]
    c64 = shade_vertices(p, n, m, lights, local_viewer=True)
    c32 = shade_vertices(p.astype(np.float32), n.astype(np.float32), m, lights, local_viewer=True)
    assert c32.dtype == np.float32
    np.testing.assert_allclose(c32, c64, rtol=0, atol=2e-5)


# --------------------------------------------------------------------------- degenerate and extreme inputs
def _strict(fn):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with np.errstate(all="raise"):
            return fn()


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_vertex_at_a_positional_light(dtype):
    # VP is the zero vector: no diffuse or specular; the ambient term remains.
    light = Light(position=(0.5, 0.5, -1, 1), ambient=(0.25, 0.25, 0.25), linear_attenuation=1.0)
    m = Material(ambient=(1, 1, 1), specular=(1, 1, 1), shininess=0.0)
    p = np.array([0.5, 0.5, -1.0], dtype=dtype)
    c = _strict(lambda: shade_vertices(p, np.array(UP, dtype=dtype), m, [light], local_viewer=True))
    assert c.dtype == dtype
    np.testing.assert_allclose(c, [0.45, 0.45, 0.45, 1.0], rtol=0, atol=1e-6)


def test_infinite_attenuation_saturates():
    # Only quadratic attenuation at d = 0: 1/0.  Saturate, then clamp.
    light = Light(position=(0, 0, -1, 1), constant_attenuation=0.0, quadratic_attenuation=1.0, ambient=(0.5, 0.0, 0.5))
    m = Material(ambient=(1, 1, 0.0), diffuse=(1, 1, 1), emission=BLACK)
    c = _strict(lambda: shade((0, 0, -1), UP, m, light))
    np.testing.assert_array_equal(c, [1.0, 0.0, 0.0, 1.0])


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_extreme_inputs_stay_finite(dtype):
    big = np.finfo(dtype).max
    tiny = np.finfo(dtype).smallest_subnormal
    p = np.array(
        [
            [0, 0, 0],
            [big, big, -big],
            [tiny, 0, -tiny],
            [1e-20, 1e20, -1],
            [-big, 0, 0],
        ],
        dtype=dtype,
    )
    n = np.array([[0, 0, 0], [big, -big, big], [tiny, tiny, 0], [0, 0, 1], [1, 0, 0]], dtype=dtype)
    lights = [
        Light(position=(1e300, -1e300, 1e300, 1e-300), quadratic_attenuation=1e300, ambient=(1, 1, 1)),
        Light(
            position=(0, 0, 0, 1),
            constant_attenuation=0.0,
            linear_attenuation=1e-300,
            spot_cutoff=0.0,
            spot_exponent=128.0,
        ),
        Light(position=(1e-300, 0, 0, 0), spot_cutoff=90.0, spot_direction=(1e-300, 0, 0)),
        Light(position=(0, 0, -1, 0), diffuse=(1e300, 1e300, 1e300), specular=(-1e300, 0, 1e300)),
        Light(position=(1, 1, 1, 0), diffuse=(1e300, -1e300, 0), specular=(-1e300, 1e300, 0)),
        Light.gl_default(1, position=(-1, 0, 1e-300, 0)),
    ]
    m = Material(ambient=(1e300, 0.0, 1), specular=(1e300, 1e300, 1e300), shininess=128.0)
    for lv in (False, True):
        for normalize in (False, True):
            c = _strict(
                lambda lv=lv, normalize=normalize: shade_vertices(
                    p, n, m, lights, scene_ambient=(1e300, 1e300, 1e300), local_viewer=lv, normalize=normalize
                )
            )
            assert c.dtype == dtype
            assert np.all(np.isfinite(c)) and np.all((c >= 0) & (c <= 1))


def test_tiny_highlight_underflows_quietly():
    theta = math.radians(89.9)
    light = Light(position=(math.sin(theta), 0, math.cos(theta), 0), diffuse=BLACK)
    c = _strict(lambda: shade((0, 0, -1), (0.0, 0.0, 1.0), specular_only(128.0), light))
    assert np.all(np.isfinite(c))


# --------------------------------------------------------------------------- parameters
def test_colours_accept_rgb_and_rgba():
    assert Material(diffuse=(0.8, 0.8, 0.8)) == Material()
    assert Material(ambient=np.array([0.1, 0.2, 0.3, 0.4])).ambient == (0.1, 0.2, 0.3, 0.4)
    assert Light(position=(1, 2, 3)).position == (1.0, 2.0, 3.0, 1.0)
    assert Light(position=(0, 0, 5, 1)).is_directional is False
    assert Light().is_directional and not Light().is_spot and spot(45.0).is_spot


def test_parameters_are_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError):
        Material().shininess = 3.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        Light().position = (0, 0, 0, 1)


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: Material(shininess=128.5), r"shininess must be .*\[0, 128\].*128\.5"),
        (lambda: Material(shininess=-1), r"shininess must be .*\[0, 128\].*-1"),
        (lambda: Material(shininess=float("nan")), r"shininess .*nan"),
        (lambda: Material(shininess="shiny"), r"shininess .*'shiny'"),
        (lambda: Material(diffuse=(1, 2)), r"diffuse must be an RGB triple or RGBA 4-tuple"),
        (lambda: Material(ambient=(float("nan"), 0, 0)), r"ambient must be .*finite.*nan"),
        (lambda: Material(emission=(0, 0, float("inf"))), r"emission must be .*inf"),
        (lambda: Light(specular="white"), r"specular must be"),
        (lambda: Light(spot_cutoff=95.0), r"spot_cutoff must be .*\[0, 90\].*180.*95\.0"),
        (lambda: Light(spot_cutoff=-1.0), r"spot_cutoff must be .*-1\.0"),
        (lambda: Light(spot_cutoff=179.9), r"spot_cutoff must be .*exactly 180.*179\.9"),
        (lambda: Light(spot_exponent=129.0), r"spot_exponent must be .*\[0, 128\].*129\.0"),
        (lambda: Light(spot_exponent=-0.5), r"spot_exponent must be .*-0\.5"),
        (lambda: Light(linear_attenuation=-1.0), r"linear_attenuation must be .*>= 0.*-1\.0"),
        (lambda: Light(quadratic_attenuation=float("inf")), r"quadratic_attenuation must be .*inf"),
        (lambda: Light(constant_attenuation=0.0), r"must not all be zero"),
        (lambda: Light(spot_direction=(0, 0, 0)), r"spot_direction must be a nonzero"),
        (lambda: Light(spot_direction=(0, 1)), r"spot_direction must be"),
        (lambda: Light(position=(0, 0, 0, 0)), r"position must give a nonzero direction .*w = 0"),
        (lambda: Light(position=(1, 2)), r"position must be \(x, y, z, w\)"),
        (lambda: Light(position=(0, 0, float("nan"), 1)), r"position must be .*nan"),
        (lambda: Light.gl_default(-1), r"index must be an integer >= 0; got -1"),
        (lambda: Light.gl_default(1.5), r"index must be an integer"),
    ],
)
def test_bad_parameters(make, match):
    with pytest.raises(ValueError, match=match):
        make()


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(positions=np.zeros((3, 2))), r"positions must be finite real vectors of shape \(\.\.\., 3\)"),
        (dict(normals=(0, 0, float("nan"))), r"normals must be finite"),
        (dict(positions=np.zeros((2, 3)), normals=np.ones((3, 3))), r"positions and normals must broadcast"),
        (dict(material="plastic"), r"material must be a Material; got str 'plastic'"),
        (dict(lights=[Light(), "sun"]), r"lights\[1\] must be a Light; got str 'sun'"),
        (dict(lights=3), r"lights must be a Light or a sequence of Light"),
        (dict(scene_ambient=(0.2, 0.2)), r"scene_ambient must be an RGB triple or RGBA 4-tuple"),
        (dict(local_viewer="yes"), r"local_viewer must be True or False; got str 'yes'"),
        (dict(normalize=None), r"normalize must be True or False; got NoneType None"),
    ],
)
def test_bad_shade_arguments(kwargs, match):
    args = dict(positions=(0, 0, -1), normals=UP, material=Material(), lights=[Light()])
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        shade_vertices(**args)


def test_docstring_examples():
    assert doctest.testmod(gl, raise_on_error=False).failed == 0


@pytest.mark.parametrize("name", ["ambient", "diffuse", "specular"])
def test_negative_material_reflectance_is_rejected(name):
    with pytest.raises(ValueError, match=rf"{name} \(a reflectance\) must have every component >= 0; got"):
        Material(**{name: (0.5, -0.1, 0.5, 1.0)})

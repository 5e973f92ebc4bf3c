"""EnvironmentLight: the environment as a light the renderer reflects and shows behind the geometry."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lighting import CookTorrance, Lambert, Material, Phong
from lighting.lights import DirectionalLight, EnvironmentLight, LatLongEnvironment, split_environment_lights
from lighting.render import AnalyticSphere, Renderer, sphere_camera
from lighting.render.camera import Camera


def _camera(size=48):
    return Camera.look_at((0.0, -4.0, 0.0), up=(0.0, 0.0, 1.0), width=size, height=size, fov_y_deg=40)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_the_furnace_image_is_the_albedo_on_the_sphere_and_the_sky_behind(dtype):
    r = Renderer(AnalyticSphere(), _camera(), dtype=dtype)
    covered = r.gbuffer.coverage
    img = r.render(Material(Lambert(0.5)), [EnvironmentLight(1.0)], form="physical")
    assert img.dtype == dtype
    np.testing.assert_allclose(img[covered], 0.5, rtol=2e-6)
    np.testing.assert_array_equal(img[~covered], 1.0)
    classic = r.render(Material(Lambert(0.5)), [EnvironmentLight(1.0)], form="classic")
    np.testing.assert_allclose(classic[covered], 0.5 * math.pi, rtol=2e-6)  # π times the physical, conventions.md
    np.testing.assert_allclose(classic[~covered], math.pi, rtol=1e-6)


def test_no_background_keeps_the_background_colour_and_terms_split():
    r = Renderer(AnalyticSphere(), _camera())
    covered = r.gbuffer.coverage
    light = EnvironmentLight(2.0, background=False)
    mat = Material(Lambert(0.25) + Phong(0.5, 20), ambient=0.0)
    img = r.render(mat, [light], form="physical", background=(0.1, 0.2, 0.3))
    np.testing.assert_array_equal(img[~covered], np.broadcast_to([0.1, 0.2, 0.3], img[~covered].shape))
    terms = r.render_terms(mat, [light], form="physical")
    np.testing.assert_allclose(terms["diffuse"][covered], 0.5, rtol=2e-6)  # k_d L
    total = terms["diffuse"] + terms["specular"] + terms["ambient"] + terms["emission"]
    np.testing.assert_allclose(total, img * covered[..., None], rtol=1e-6, atol=1e-12)
    diffuse_only = r.render(mat, [light], form="physical", terms=("diffuse",))
    np.testing.assert_allclose(diffuse_only[covered], 0.5, rtol=2e-6)


def test_environment_and_punctual_lights_add():
    r = Renderer(AnalyticSphere(), _camera())
    mat = Material(Lambert(0.5), ambient=0.0)
    sun = DirectionalLight.from_angles(30.0, 200.0)
    both = r.render(mat, [sun, EnvironmentLight(1.0, background=False)], form="physical")
    alone = r.render(mat, [sun], form="physical")
    env = r.render(mat, [EnvironmentLight(1.0, background=False)], form="physical")
    np.testing.assert_allclose(both, alone + env, rtol=1e-12, atol=1e-15)


def test_a_rotation_by_whole_columns_is_the_rolled_image():
    rng = np.random.default_rng(0)
    img = rng.random((32, 64, 3)) ** 4
    # A perspective view from the side: an orthographic sphere_camera looks straight down -z, exactly at the
    # nadir, where a lat-long lookup's azimuth is undefined (and a turned map reads other columns).
    r = Renderer(AnalyticSphere(), _camera(40))
    mat = Material(Lambert(0.3) + CookTorrance(1.0, 0.2, 0.04, ndf="ggx", geometry="smith"))
    turned = r.render(mat, [EnvironmentLight(LatLongEnvironment(img), rotation=360 / 64 * 5)], form="physical")
    # Turning toward +φ moves the picture left: the columns run against φ.
    rolled = r.render(mat, [EnvironmentLight(LatLongEnvironment(np.roll(img, -5, axis=1)))], form="physical")
    np.testing.assert_allclose(turned, rolled, rtol=1e-4, atol=1e-6)


def test_monte_carlo_method_agrees_with_the_split_sum_where_both_are_exact():
    r = Renderer(AnalyticSphere(), sphere_camera(24))
    covered = r.gbuffer.coverage
    mc = r.render(Material(Lambert(0.5), ambient=0.0), [EnvironmentLight(1.0, method="monte-carlo", samples=64)],
                  form="physical")  # fmt: skip
    # MIS on a constant sky is not noise-free, but its mean is k_d L: the pixels' mean within 1 %.
    assert abs(float(mc[covered].mean()) - 0.5) < 5e-3
    again = r.render(Material(Lambert(0.5), ambient=0.0), [EnvironmentLight(1.0, method="monte-carlo", samples=64)],
                     form="physical")  # fmt: skip
    np.testing.assert_array_equal(mc, again)  # seeded: the same image


def test_repr_to_dict_and_split():
    light = EnvironmentLight("studio", intensity=2.0, rotation=45.0, method="monte-carlo", samples=32)
    assert repr(light) == "EnvironmentLight('studio', intensity=2.0, rotation=45.0, method='monte-carlo')"
    assert light.to_dict() == {"type": "environment", "source": "studio", "intensity": 2.0, "rotation": 45.0,
                               "method": "monte-carlo", "samples": 32, "seed": 0}  # fmt: skip
    assert EnvironmentLight([1.0, 0.5, 0.25]).to_dict() == {"type": "environment", "radiance": [1.0, 0.5, 0.25]}
    sun = DirectionalLight((0.0, 0.0, 1.0))
    others, envs = split_environment_lights([sun, light])
    assert others == [sun] and envs == [light]
    with pytest.raises(ValueError, match="method must be one of"):
        EnvironmentLight(1.0, method="fast")
    with pytest.raises(ValueError, match="cannot be saved"):
        EnvironmentLight(LatLongEnvironment(np.ones((2, 4, 3)))).to_dict()


def test_a_light_reuses_the_prefiltered_levels_of_the_environment_it_turns():
    from lighting.integrate.prefilter import prefilter_environment

    base = LatLongEnvironment(np.random.default_rng(1).random((16, 32, 3)))
    pre = prefilter_environment(base)
    r = Renderer(AnalyticSphere(), _camera(32))
    mat = Material(Lambert(0.3) + CookTorrance(1.0, 0.2, 0.04, ndf="ggx", geometry="smith"))
    fresh = r.render(mat, [EnvironmentLight(base, intensity=2.0, rotation=30.0)], form="physical")
    reused_light = EnvironmentLight(base, intensity=2.0, rotation=30.0, prefiltered=pre)
    assert reused_light.prefiltered.levels is pre.levels  # the same arrays: nothing prefiltered again
    np.testing.assert_array_equal(r.render(mat, [reused_light], form="physical"), fresh)
    with pytest.raises(ValueError, match="prefiltered must be prefilter_environment"):
        EnvironmentLight(LatLongEnvironment(np.ones((16, 32, 3))), prefiltered=pre)

"""Environment lights in scene files rendered with named skies, and the memory estimate against what the default
method allocates to shade its first frame (slow set; fast: test_scene_environment.py)."""

import shutil

import numpy as np
import pytest
from test_scene_environment import FURNACE, SKY_FILE, render

from explorer.commands.render import load_with_defines
from lighting.lights.environment import LatLongEnvironment
from lighting.lights.skies import sky
from lighting.scene import SceneRenderer, example_path, load_scene, parse_scene, scene_to_toml

pytestmark = pytest.mark.slow  # each test prefilters a 256-row sky twice, or a 64-row one under tracemalloc


def test_background_is_the_sky_along_each_camera_ray_rotated():
    # With rotation = 90, what the sky shows at φ appears at φ + 90°: the background along d is L(R_z(−90°) d).
    # (The band-limited sky: its x and y terms make every azimuth different.)
    text = FURNACE.format(form="physical", mode="phong", extra="").replace("radiance = 1", 'source = "band-limited"')
    scene = parse_scene(text + "rotation = 90\n")
    image, owner = render(scene)
    _, dirs = scene.camera.rays()
    turned = np.stack([dirs[..., 1], -dirs[..., 0], dirs[..., 2]], axis=-1)
    expected = sky("band-limited").radiance(turned)
    np.testing.assert_allclose(image[owner < 0], expected[owner < 0], rtol=1e-12)
    unturned = render(parse_scene(text))[0]
    assert np.abs(unturned[owner < 0] - image[owner < 0]).max() > 0.1  # the rotation shows


def test_studio_example_values_against_the_engine():
    # Each pixel of an object is what the light's own reflected() gives for its normal and view (physical form).
    scene = load_scene(example_path("studio")).with_size(96, 54)
    sr = SceneRenderer(scene)
    image, _ = sr.render()
    owner = sr.visibility()
    light = scene.lights[0]
    for i in (0, 7):
        r = sr.renderer(i)
        gb = r.gbuffer
        mine = owner.reshape(-1)[gb.pixels] == i
        n = gb.normal[gb.coverage][mine]
        p = gb.position[gb.coverage][mine]
        v = scene.camera.eye - p
        v /= np.linalg.norm(v, axis=1, keepdims=True)
        expected = light.reflected(scene.objects[i].material.brdf, n, v)
        np.testing.assert_allclose(np.asarray(image)[owner == i], expected, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize(
    "extra",
    ['source = "sky.hdr"\nrotation = 30.0\nintensity = [1.0, 0.9, 0.8]',
     'source = "sunset"\nbackground = false', "radiance = [0.5, 0.6, 0.7]",
     'source = "sky.hdr"\nmethod = "monte-carlo"\nsamples = 8\nseed = 5'],
)  # fmt: skip
def test_saving_and_loading_gives_the_same_image(tmp_path, extra):
    shutil.copy(SKY_FILE, tmp_path / "sky.hdr")
    text = FURNACE.format(form="physical", mode="phong", extra="").replace("radiance = 1\n", extra + "\n")
    (tmp_path / "a.toml").write_text(text)
    scene = load_scene(tmp_path / "a.toml")
    saved = scene_to_toml(scene)
    assert "[[lights]]\ntype = \"environment\"\n" in saved
    (tmp_path / "b.toml").write_text(saved)
    again = load_scene(tmp_path / "b.toml")
    assert again.to_dict() == scene.to_dict()
    np.testing.assert_array_equal(render(again)[0], render(scene)[0])


def test_define_rotation_overrides_the_file(tmp_path):
    text = FURNACE.format(form="physical", mode="phong", extra="").replace("radiance = 1", 'source = "daylight"')
    (tmp_path / "a.toml").write_text(text)
    (tmp_path / "b.toml").write_text(text + "rotation = 90\n")
    turned = load_with_defines(str(tmp_path / "a.toml"), ["lights[0].rotation=90"])
    assert turned.lights[0].rotation == 90.0
    np.testing.assert_array_equal(render(turned)[0], render(load_scene(tmp_path / "b.toml"))[0])
    with pytest.raises(ValueError, match=r"lights\[0\]\.rotation: must be a finite number.*\(with -D lights"):
        load_with_defines(str(tmp_path / "a.toml"), ['lights[0].rotation="x"'])


def test_the_estimate_covers_what_the_default_method_allocates_to_shade_its_first_frame():
    # Everything traced from the sky's prefilter to a glossy sphere's first frame under the dominant lights (the
    # tables of a part not met before, the residual's levels) stays within the estimate; the parts' albedo tables,
    # which every method but Monte Carlo reads, are made before.
    import tracemalloc

    from lighting._budget import environment_setup_bytes
    from lighting.integrate.dominant import dominant_radiance, forget_environments
    from lighting.integrate.ibl import lobe_albedo
    from lighting.integrate.prefilter import prefilter_environment
    from lighting.lights.envlight import EnvironmentLight
    from lighting.models.brdf import CookTorrance, Lambert

    forget_environments()
    env = LatLongEnvironment(sky("daylight").radiance(LatLongEnvironment.pixel_directions(64, 128)))
    model = Lambert(0.3) + CookTorrance(1.0, 0.0731, ndf="ggx")  # a roughness no other test shades
    n = LatLongEnvironment.pixel_directions(96, 96).reshape(-1, 3)
    n = n[n[:, 1] < 0]
    v = np.broadcast_to([0.0, -1.0, 0.0], n.shape)
    for part in model.parts:
        lobe_albedo(part)
    tracemalloc.start()
    try:
        dominant_radiance(model, prefilter_environment(env, reuse=False), n, v)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < environment_setup_bytes(EnvironmentLight(env)), peak

"""Every example scene loads, renders and round-trips (slow set; test_plan.py renders each one in the fast loop)."""

import numpy as np
import pytest
from test_scene import EXAMPLES, raw, small

from lighting.scene import parse_scene, render_scene, scene_to_toml
from lighting.scene.examples import EXAMPLES_DIR

pytestmark = pytest.mark.slow  # renders every example three times, the studio sky prefiltered each time


@pytest.mark.parametrize("name", EXAMPLES)
def test_every_example_loads_renders_and_round_trips(name):
    scene = small(name, 64)
    image, info = render_scene(scene)
    assert image.shape == (scene.camera.height, scene.camera.width, 3)
    assert np.all(np.isfinite(image)) and np.all(image >= 0)
    assert info["objects"] == len(raw(name)["objects"]) and all(v > 0 for v in info["visible_pixels"])
    # Round trip: dict and TOML text read back to the same scene and the same picture.
    d = scene.to_dict()
    again = parse_scene(d, base_dir=EXAMPLES_DIR)
    assert again.to_dict() == d
    text = scene_to_toml(scene)
    saved = parse_scene(text, base_dir=EXAMPLES_DIR)
    assert saved.to_dict() == d
    np.testing.assert_array_equal(render_scene(again)[0], image)
    np.testing.assert_array_equal(render_scene(saved)[0], image)  # load, save, load: the same picture, bit for bit

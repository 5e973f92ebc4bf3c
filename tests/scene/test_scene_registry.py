"""Scene files take their models from the registry: a model defined and registered in this file is read,
rendered and written back with no edit to lighting.scene."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lighting.models import BRDF, Lobe, Parameter, register_model
from lighting.models.protocol import unregister_model
from lighting.scene import SceneError, parse_scene, render_scene, scene_to_toml
from lighting.scene.schema import model_keys


class WrapDiffuse(BRDF):
    """Wrap lighting, ``k_d/π · (((n·l) + w)/(1 + w))^p`` above the horizon (halved with ``half``).

    A diffuse model with one parameter of every kind a table may hold (colour, number, flag, choice);
    the choice ``falloff`` is spelled in digits, so a scene file may write it as an integer.

    References
    ----------
    Green, S. "Real-Time Approximations to Subsurface Scattering", GPU Gems, 2004 (wrap lighting).
    """

    name = "test-wrap-diffuse"
    term = "diffuse"
    parameters = (
        Parameter("kd", "color", 0.5, slider=(0.0, 1.0), description="albedo"),
        Parameter("wrap", "float", 0.25, low=0.0, high=1.0, description="how far light wraps past the terminator"),
        Parameter("half", "bool", False, description="halve the result"),
        Parameter("falloff", "choice", "1", choices=("1", "2"), description="the exponent p"),
    )

    def __init__(self, kd=0.5, wrap=0.25, half=False, falloff="1"):
        self.kd = np.broadcast_to(np.asarray(kd, dtype=np.float64), (3,)).copy()
        if not 0.0 <= float(wrap) <= 1.0:
            raise ValueError(f"wrap must be in [0, 1]; got {wrap!r}")
        if falloff not in ("1", "2"):
            raise ValueError(f"falloff must be '1' or '2'; got {falloff!r}")
        self.wrap, self.half, self.falloff = float(wrap), bool(half), falloff

    def _params(self):
        return {"kd": self.kd, "wrap": self.wrap, "half": self.half, "falloff": self.falloff}

    def lobe(self):
        return Lobe("normal")

    def _f_cos(self, g):
        nl = np.asarray(g.n_dot_l, dtype=np.float64)
        s = np.clip((nl + self.wrap) / (1.0 + self.wrap), 0.0, 1.0) ** int(self.falloff) / math.pi
        s = np.where(g.above, s * (0.5 if self.half else 1.0), 0.0)
        return (s[..., None] * self.kd).astype(g.dtype)


SCENE = """
[camera]
eye = [0, 0, 5]
[image]
width = 24
height = 24
[materials.wrapped]
parts = [{model = "test-wrap-diffuse", kd = [0.6, 0.3, 0.1], wrap = 0.5, half = true, falloff = 2}]
[[objects]]
type = "icosphere"
level = 2
material = "wrapped"
[[lights]]
type = "directional"
direction = [0, 0, 1]
"""


@pytest.fixture
def wrap_model():
    register_model(WrapDiffuse)
    yield WrapDiffuse
    unregister_model(WrapDiffuse.name)


def test_a_model_registered_after_import_is_read_rendered_and_written_back(wrap_model):
    scene = parse_scene(SCENE)
    (part,) = scene.materials["wrapped"].brdf.parts
    assert type(part) is wrap_model
    assert part.kd.tolist() == [0.6, 0.3, 0.1] and part.wrap == 0.5 and part.half is True
    assert part.falloff == "2"  # the integer 2 is the choice "2"

    image, info = render_scene(scene)
    assert info["visible_pixels"][0] > 0 and np.all(np.isfinite(image))
    centre = image[12, 12]
    expected = 0.5 * np.array([0.6, 0.3, 0.1]) / math.pi * math.pi  # classic form: π f_r (n·l) at n·l = 1
    assert np.allclose(centre, expected, rtol=1e-2), centre

    text = scene_to_toml(scene)
    assert 'model = "test-wrap-diffuse"' in text and 'falloff = "2"' in text and "half = true" in text
    again = parse_scene(text)
    assert again.to_dict() == scene.to_dict()
    assert np.array_equal(render_scene(again)[0], image)


def test_defaults_and_checks_come_from_the_parameter_table(wrap_model):
    keys = model_keys()[wrap_model.name]
    assert list(keys) == ["model", "kd", "wrap", "half", "falloff"]
    scene = parse_scene(SCENE.replace(', kd = [0.6, 0.3, 0.1], wrap = 0.5, half = true, falloff = 2', ''))
    (part,) = scene.materials["wrapped"].brdf.parts
    assert part.kd.tolist() == [0.5] * 3 and part.wrap == 0.25 and part.half is False and part.falloff == "1"
    where = "<string>: materials.wrapped.parts[0]."
    for old, new, message in [
        ("wrap = 0.5", 'wrap = "a lot"', 'wrap: must be a finite number; got a string "a lot"'),
        ("half = true", "half = 1", "half: must be true or false; got an integer 1"),
        ("falloff = 2", "falloff = 3", "falloff: must be one of '1', '2'; got an integer 3"),
        ("falloff = 2", "falof = 2", "falof: unknown key for a 'test-wrap-diffuse' model; did you mean 'falloff'? "
                                     "allowed keys: model, kd, wrap, half, falloff"),
        ("wrap = 0.5", "wrap = 2.0", "wrap: wrap must be in [0, 1]; got 2.0"),
    ]:
        with pytest.raises(SceneError) as err:
            parse_scene(SCENE.replace(old, new))
        assert str(err.value) == where + message, str(err.value)


def test_an_unregistered_model_is_refused_again(wrap_model):
    unregister_model(wrap_model.name)
    assert wrap_model.name not in model_keys()
    with pytest.raises(SceneError, match=r"parts\[0\]\.model: must be one of 'lambert', 'phong', 'blinn-phong'"):
        parse_scene(SCENE)


def _two_spheres(objects: str) -> str:
    return f"""
[camera]
eye = [0.0, 0.0, 7.0]
fov_y_deg = 24.0
[image]
width = 96
height = 48
[materials.brushed]
parts = [{{model = "ward", ks = 1.0, alpha_x = 0.4, alpha_y = 0.08}}]
{objects}
[[lights]]
type = "directional"
direction = [-0.6, 0.8, 1.5]
"""


_LEFT = """
[[objects]]
type = "sphere"
center = [-1.15, 0.0, 0.0]
material = "brushed"
"""
_RIGHT = _LEFT.replace("-1.15", "1.15")


def test_objects_sharing_a_plan_keep_their_own_tangents():
    """Two anisotropic spheres shaded in one batch give the pixels each gives alone (tangents along φ)."""
    both, _ = render_scene(parse_scene(_two_spheres(_LEFT + _RIGHT)))
    left, _ = render_scene(parse_scene(_two_spheres(_LEFT)))
    right, _ = render_scene(parse_scene(_two_spheres(_RIGHT)))
    alone = np.where(left > 0, left, right)
    assert np.count_nonzero(left) > 100 and np.count_nonzero(right) > 100
    np.testing.assert_allclose(both, alone, rtol=1e-12, atol=0)

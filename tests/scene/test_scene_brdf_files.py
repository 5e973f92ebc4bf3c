"""Scene files naming BRDF files: ``parts = [{file = "paint.brdf", name = value}]``.

The file's model is the same model ``load_brdf`` gives; the path starts at the scene's folder; the
file's parameter table is the part's keys; every problem is one ``SceneError`` naming the key.
"""

from __future__ import annotations

import math
import os
import tomllib

import numpy as np
import pytest

from lighting import Lambert, Phong
from lighting._budget import set_memory_budget
from lighting.files import file_model, load_brdf
from lighting.files.merl import write_merl
from lighting.scene import SceneBudgetError, SceneError, load_scene, parse_scene
from lighting.scene.budget import BRDF_FILE_BYTES
from lighting.scene.renderer import render_scene
from lighting.scene.save import scene_to_toml

#: Lambert transcribed into BRDF Explorer's format: f_r = k_d / π.
LAMBERT = """analytic
::begin parameters
float kd 0 1 0.5
::end parameters
::begin shader
vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return vec3(kd / 3.14159265358979323846); }
::end shader
"""

SCENE = """
[camera]
eye = [0, 0, 5]
[image]
width = 24
height = 24
[materials.paint]
parts = [PART]
ambient = 0.0
[[lights]]
type = "directional"
direction = [0.3, 0.5, 1]
[[objects]]
type = "sphere"
material = "paint"
"""


def scene_text(part: str) -> str:
    return SCENE.replace("PART", part)


def error_of(text, folder, name="bad.toml"):
    path = folder / name
    path.write_text(text)
    with pytest.raises(SceneError) as exc:
        load_scene(path)
    msg = str(exc.value)
    assert msg.startswith(str(path) + ": ") and "\n" not in msg
    return msg


@pytest.fixture
def folder(tmp_path):
    (tmp_path / "lambert.brdf").write_text(LAMBERT)
    return tmp_path


def test_a_brdf_file_part_renders_as_the_built_in_model_it_transcribes(folder):
    (folder / "s.toml").write_text(scene_text('{file = "lambert.brdf", kd = 0.8}'))
    (folder / "r.toml").write_text(scene_text('{model = "lambert", kd = 0.8}'))
    got, _ = render_scene(load_scene(folder / "s.toml"))
    want, _ = render_scene(load_scene(folder / "r.toml"))
    assert want.max() > 0.2  # a lit sphere, not a black image
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=0)
    brdf = load_scene(folder / "s.toml").objects[0].material.brdf
    assert brdf.kd == 0.8 and brdf.file_path == str(folder / "lambert.brdf")
    l, v = np.array([0.0, 0.6, 0.8]), np.array([0.48, 0.0, 0.8775])
    v /= np.linalg.norm(v)
    np.testing.assert_allclose(brdf.eval((0, 0, 1.0), l, v), load_brdf(folder / "lambert.brdf", kd=0.8).eval(
        (0, 0, 1.0), l, v), rtol=0, atol=0)  # fmt: skip


def test_the_path_starts_at_the_scene_folder_not_the_current_one(folder, tmp_path, monkeypatch):
    sub = folder / "scenes"
    sub.mkdir()
    (sub / "s.toml").write_text(scene_text('{file = "../lambert.brdf"}'))
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    brdf = load_scene(sub / "s.toml").objects[0].material.brdf
    assert brdf.kd == 0.5  # the file's default
    assert float(brdf.eval((0, 0, 1.0), (0, 0, 1.0), (0, 0, 1.0))[0]) == pytest.approx(0.5 / math.pi, rel=1e-15)


def test_a_file_part_sums_with_a_model_part(folder):
    scene = load_scene_text(folder, '{file = "lambert.brdf", kd = 0.25}, {model = "phong", ks = 0.5, shininess = 20}')
    brdf = scene.objects[0].material.brdf
    n, l, v = np.array([0, 0, 1.0]), np.array([0, 0.6, 0.8]), np.array([0, -0.6, 0.8])
    want = Lambert(0.25).eval(n, l, v) + Phong(0.5, 20.0).eval(n, l, v)
    np.testing.assert_allclose(brdf.eval(n, l, v), want, rtol=1e-15)


def load_scene_text(folder, parts):
    path = folder / "s.toml"
    path.write_text(scene_text(parts))
    return load_scene(path)


def test_materials_naming_one_file_share_one_class_and_one_read(folder):
    text = scene_text('{file = "lambert.brdf", kd = 0.2}') + (
        '[materials.other]\nparts = [{file = "./lambert.brdf", kd = 0.9}]\n'
        '[[objects]]\ntype = "sphere"\ncenter = [2, 0, 0]\nmaterial = "other"\n'
    )
    (folder / "s.toml").write_text(text)
    a, b = (ob.material.brdf for ob in load_scene(folder / "s.toml").objects)
    assert type(a) is type(b) and (a.kd, b.kd) == (0.2, 0.9)


def test_the_scene_writes_the_file_part_back_and_reads_it_again(folder):
    scene = load_scene_text(folder, '{file = "lambert.brdf", kd = 0.7}')
    text = scene_to_toml(scene)
    assert f'\nfile = "{folder / "lambert.brdf"}"\nkd = 0.7\n' in text
    assert tomllib.loads(text)["materials"]["paint"]["parts"] == [{"file": str(folder / "lambert.brdf"), "kd": 0.7}]
    again = parse_scene(text, source="again")
    np.testing.assert_array_equal(render_scene(again)[0], render_scene(scene)[0])


def test_a_merl_table_in_a_scene_is_the_constant_it_holds(tmp_path):
    write_merl(tmp_path / "grey.binary", np.full((3, 90, 90, 180), 0.3 / math.pi))
    scene = load_scene_text(tmp_path, '{file = "grey.binary", interpolation = "linear"}')
    brdf = scene.objects[0].material.brdf
    assert brdf.interpolation == "linear"
    (tmp_path / "r.toml").write_text(scene_text('{model = "lambert", kd = 0.3}'))
    want, _ = render_scene(load_scene(tmp_path / "r.toml"))
    np.testing.assert_allclose(render_scene(scene)[0], want, rtol=1e-12, atol=0)
    msg = error_of(scene_text('{file = "grey.binary", interpolation = "cubic"}'), tmp_path)
    assert "materials.paint.parts[0].interpolation" in msg and "'nearest', 'linear'" in msg


@pytest.mark.parametrize(
    ("part", "key", "words"),
    [
        ('{file = "none.brdf"}', "parts[0].file", "does not exist"),
        ('{file = "."}', "parts[0].file", "is not a BRDF file; allowed extensions: .binary, .brdf"),
        ('{file = "sub.brdf"}', "parts[0].file", "is not a regular file"),
        ('{file = "lambert.obj"}', "parts[0].file", "allowed extensions: .binary, .brdf"),
        ('{file = 3}', "parts[0].file", "must be the path of a BRDF file (.binary, .brdf)"),
        ('{file = ""}', "parts[0].file", "must be the path of a BRDF file"),
        ('{file = "lambert.brdf", model = "lambert"}', "parts[0]", "not both"),
        ('{file = "lambert.brdf", kd = 2.0}', "parts[0].kd", "[0, 1]"),
        ('{file = "lambert.brdf", kds = 0.5}', "parts[0].kds", "did you mean 'kd'?"),
        ('{file = "broken.brdf"}', "parts[0].file", "broken.brdf:6:70: expected an expression"),
        ('{kd = 0.5}', "parts[0].model", "or file = 'NAME.brdf' / 'NAME.binary'"),
    ],
)
def test_each_bad_file_part_is_one_error_naming_its_key(folder, part, key, words):
    (folder / "sub.brdf").mkdir()
    (folder / "broken.brdf").write_text(LAMBERT.replace("vec3(kd", "vec3(kd +"))
    msg = error_of(scene_text(part), folder)
    assert f"materials.paint.{key}: " in msg and words in msg, msg


def test_a_brdf_file_is_charged_against_the_budget_before_it_is_read(folder):
    size = os.path.getsize(folder / "lambert.brdf")
    per_byte, fixed = BRDF_FILE_BYTES[".brdf"]
    need = fixed + per_byte * size + 64 * len(scene_text('{file = "lambert.brdf"}'))
    previous = set_memory_budget(fixed + per_byte * size - 1)
    try:
        (folder / "s.toml").write_text(scene_text('{file = "lambert.brdf"}'))
        with pytest.raises(SceneBudgetError, match=r"materials\.paint\.parts\[0\]\.file: .*reading a BRDF file of "
                                                   rf"{size} bytes"):  # fmt: skip
            load_scene(folder / "s.toml")
        set_memory_budget(need)
        assert load_scene(folder / "s.toml").objects[0].material.brdf.kd == 0.5
    finally:
        set_memory_budget(previous)


def test_the_merl_charge_covers_what_reading_holds():
    # read_merl keeps the stored values and the filled RGB table (2 × 35 MB) and peaks at 3.1 × with a
    # temporary; 4 bytes per byte of file leaves room for both.
    per_byte, fixed = BRDF_FILE_BYTES[".binary"]
    assert per_byte * 34_992_012 + fixed >= 3.2 * 34_992_012


def test_file_model_names_are_unique_and_a_file_keeps_its_name(folder):
    a = file_model(folder / "lambert.brdf", register=True)
    try:
        assert a.name == "lambert-2"  # "lambert" is the built-in model's
        b = file_model(folder / "lambert.brdf", register=True)  # the same file again: same name, replaced
        assert b.name == "lambert-2"
        from lighting.models import model_class

        assert model_class("lambert-2") is b and model_class("lambert") is Lambert
        scene = parse_scene(scene_text('{model = "lambert-2", kd = 0.4}'), source="named")
        assert scene.objects[0].material.brdf.kd == 0.4
    finally:
        from lighting.models.protocol import unregister_model

        unregister_model("lambert-2")

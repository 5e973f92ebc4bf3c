"""The JSON Schema of the scene format (docs/scene.schema.json): in step with the loader's tables.

Cross-checks between two independent judges of a scene file: the schema (through the ``jsonschema``
package, when installed) and the loader (:func:`lighting.load_scene`).  Both accept every shipped example;
both refuse a misspelt key and a value outside its choices.
"""

from __future__ import annotations

import copy
import json
import tomllib
from pathlib import Path

import pytest

from lighting.scene import load_scene, schema
from lighting.scene.json_schema import main, scene_json_schema
from lighting.scene.load import parse_scene

ROOT = Path(__file__).resolve().parents[2]
SCHEMA_FILE = ROOT / "docs" / "scene.schema.json"
EXAMPLES = sorted((ROOT / "lighting" / "scene" / "examples").glob("*.toml"))


def _validator():
    jsonschema = pytest.importorskip("jsonschema")
    s = json.loads(SCHEMA_FILE.read_text(encoding="utf-8"))
    jsonschema.Draft202012Validator.check_schema(s)
    return jsonschema.Draft202012Validator(s)


def test_committed_schema_is_the_generated_one(tmp_path):
    assert json.loads(SCHEMA_FILE.read_text(encoding="utf-8")) == scene_json_schema()
    out = tmp_path / "s.json"
    assert main([str(out)]) == 0
    assert out.read_text(encoding="utf-8") == SCHEMA_FILE.read_text(encoding="utf-8")


def test_schema_lists_every_key_of_the_loader_tables():
    s = scene_json_schema()
    for name, table in (("camera", schema.CAMERA_KEYS), ("image", schema.IMAGE_KEYS), ("render", schema.RENDER_KEYS)):
        assert list(s["$defs"][name]["properties"]) == list(table), name
        assert s["$defs"][name]["additionalProperties"] is False
    lights = {v["properties"]["type"]["const"]: v for v in s["$defs"]["light"]["anyOf"]}
    assert {k: list(v["properties"]) for k, v in lights.items()} == {k: list(t) for k, t in schema.LIGHT_KEYS.items()}
    assert lights["spot"]["required"] == ["type", "position", "direction"]
    assert lights["spot"]["properties"]["cutoff_deg"] == {"type": "number", "default": 30.0}
    assert s["$defs"]["image"]["properties"]["width"] == {
        "type": "integer",
        "minimum": 1,
        "maximum": 16384,
        "default": 512,
    }
    parts = {p["properties"]["model"]["const"]: p for p in s["$defs"]["part"]["anyOf"] if "model" in p["properties"]}
    assert list(parts["phong"]["properties"]) == ["model", "ks", "shininess"]
    assert parts["cook-torrance"]["properties"]["denominator"]["enum"] == ["4", "pi", 4]


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_examples_valid_for_schema_and_loader(path):
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    assert list(_validator().iter_errors(data)) == []
    load_scene(path)  # the loader agrees


@pytest.mark.parametrize(
    "edit, key",
    [
        (lambda d: d.__setitem__("camra", {"eye": [0, 0, 5]}), "camra"),
        (lambda d: d["camera"].__setitem__("fov", 40.0), "fov"),
        (lambda d: d["lights"][0].__setitem__("cutoff", 20.0), "cutoff"),
        (lambda d: d["materials"]["white"]["parts"][1].__setitem__("shinyness", 30.0), "shinyness"),
        (lambda d: d["objects"][1].__setitem__("radius_m", 1.0), "radius_m"),
    ],
)
def test_unknown_key_rejected_by_both(edit, key):
    src = ROOT / "lighting" / "scene" / "examples" / "spotlight.toml"
    data = tomllib.loads(src.read_text(encoding="utf-8"))
    bad = copy.deepcopy(data)
    edit(bad)
    assert list(_validator().iter_errors(bad)) != []
    with pytest.raises(ValueError, match=key):
        parse_scene(bad, source="bad.toml", base_dir=src.parent)


def test_bad_choice_and_missing_required_rejected():
    v = _validator()
    data = tomllib.loads((ROOT / "lighting" / "scene" / "examples" / "spotlight.toml").read_text(encoding="utf-8"))
    bad = copy.deepcopy(data)
    bad["render"]["mode"] = "smooth"
    assert not v.is_valid(bad)
    bad = copy.deepcopy(data)
    del bad["camera"]["eye"]
    assert not v.is_valid(bad)
    bad = copy.deepcopy(data)
    bad["image"]["width"] = 0
    assert not v.is_valid(bad)

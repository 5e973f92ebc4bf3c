"""The JSON Schema of the scene format (docs/scene.schema.json): in step with the loader's tables.

Cross-checks between two independent judges of a scene file: the schema (through the ``jsonschema``
package, when installed) and the loader (:func:`lighting.load_scene`).  Both accept every shipped example;
both refuse a misspelt key and a value outside its choices.
"""

from __future__ import annotations

import copy
import functools
import json
import math
import tomllib
from pathlib import Path

import pytest

from lighting.scene import SceneError, load_scene, schema
from lighting.scene.checks import ABSENT, REQUIRED, _Ctx
from lighting.scene.json_schema import main, scene_json_schema
from lighting.scene.load import parse_scene

ROOT = Path(__file__).resolve().parents[2]
SCHEMA_FILE = ROOT / "docs" / "scene.schema.json"
EXAMPLES = sorted((ROOT / "lighting" / "scene" / "examples").glob("*.toml"))


@functools.cache
def _validator():
    """The validator of the committed schema file, built and checked against the metaschema once.

    Every test judges against the same file, and validating (``iter_errors``, ``is_valid``) leaves the validator
    as it was, so all of them share this one.
    """
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
    assert lights["spot"]["properties"]["cutoff_deg"] == {
        "type": "number",
        "default": 30.0,
        "description": "cone half-angle in degrees: [0, 90], or 180 for no cone",
    }
    assert s["$defs"]["image"]["properties"]["width"] == {
        "type": "integer",
        "minimum": 1,
        "maximum": 16384,
        "default": 512,
        "description": "image width in pixels",
    }
    parts = {p["properties"]["model"]["const"]: p for p in s["$defs"]["part"]["anyOf"] if "model" in p["properties"]}
    assert list(parts["phong"]["properties"]) == ["model", "ks", "shininess"]
    assert parts["cook-torrance"]["properties"]["denominator"]["enum"] == ["4", "pi", 4]


def _tables() -> list:
    """Every table of the format: its name, its fields, and the properties the schema gives it."""
    s = scene_json_schema()
    d = s["$defs"]
    out = [("top", schema.TOP_KEYS, s["properties"])]
    out += [(n, getattr(schema, f"{n.upper()}_KEYS"), d[n]["properties"]) for n in ("camera", "image", "render")]
    out += [("opengl", schema.OPENGL_KEYS, d["opengl"]["properties"])]
    out += [("material", schema.MATERIAL_KEYS, d["material"]["oneOf"][0]["properties"])]
    out += [("gl material", schema.GL_MATERIAL_KEYS, d["material"]["oneOf"][1]["properties"])]
    for name, tables, variants, tag in (
        ("light", schema.LIGHT_KEYS, d["light"]["anyOf"], "type"),
        ("object", schema.OBJECT_KEYS, d["object"]["anyOf"], "type"),
        ("part", schema.model_keys(), [p for p in d["part"]["anyOf"] if "model" in p["properties"]], "model"),
    ):
        by_kind = {v["properties"][tag]["const"]: v["properties"] for v in variants}
        assert list(by_kind) == list(tables), name
        out += [(f"{kind} {name}", fields, by_kind[kind]) for kind, fields in tables.items()]
    return out


def _bounds(prop) -> set:
    """Every ``minimum`` and ``maximum`` anywhere in a property's schema (a colour states them twice)."""
    if isinstance(prop, dict):
        found = {(k, v) for k, v in prop.items() if k in ("minimum", "maximum")}
        return found.union(*(_bounds(v) for v in prop.values()))
    return set().union(*(_bounds(v) for v in prop)) if isinstance(prop, list) else set()


def test_each_field_is_published_with_its_default_bounds_and_description():
    tables = _tables()
    assert len(tables) == 7 + len(schema.LIGHT_KEYS) + len(schema.OBJECT_KEYS) + len(schema.model_keys())
    for name, fields, props in tables:
        assert list(props) == list(fields), name
        for key, field in fields.items():
            prop = props[key]
            if field.default is REQUIRED or field.default is ABSENT:
                assert "default" not in prop, (name, key)
            else:
                assert prop["default"] == json.loads(json.dumps(field.default)), (name, key)
            stated = {(k, v) for k, v in (("minimum", field.minimum), ("maximum", field.maximum)) if v is not None}
            assert _bounds(prop) == stated, (name, key)
            assert prop.get("description", "") == field.description, (name, key)
            assert field.description, (name, key)


def test_the_loader_enforces_the_bounds_the_schema_publishes():
    fields = [(n, k, f) for n, table, _ in _tables() for k, f in table.items()]
    bounded = [(n, k, f) for n, k, f in fields if f.minimum is not None or f.maximum is not None]
    lights = [(f"{kind} light", key) for kind in ("ambient", "directional", "disk", "point", "rect", "spot")
              for key in ("color", "intensity")]  # fmt: skip
    assert sorted((n, k) for n, k, _ in bounded) == sorted([
        *lights,
        ("disk light", "samples"),
        ("environment light", "intensity"),
        ("environment light", "radiance"),
        ("environment light", "samples"),
        ("environment light", "seed"),
        ("image", "exposure"),
        ("image", "height"),
        ("image", "width"),
        ("rect light", "samples"),
    ])  # fmt: skip
    assert schema.LIGHT_KEYS["environment"]["radiance"].maximum == schema.MAX_ENVIRONMENT_VALUE == 1e30
    assert schema.MAX_LIGHT_VALUE == 1e30
    assert all(schema.LIGHT_KEYS[kind.split()[0]][key].maximum == schema.MAX_LIGHT_VALUE for kind, key in lights)
    ctx = _Ctx("s.toml", str(ROOT))
    for _, key, field in bounded:
        for bound, side in ((field.minimum, -1), (field.maximum, 1)):
            if bound is None:
                continue
            past = bound + side if field.kind == "integer" else math.nextafter(bound, side * math.inf)
            assert field.check(ctx, key, bound) == bound
            with pytest.raises(SceneError) as e:
                field.check(ctx, key, past)
            assert str(e.value).startswith(f"s.toml: {key}: must be ") and f"got {past!r}" in str(e.value)
            assert (f"{bound:g}" if field.kind != "integer" else str(bound)) in str(e.value)


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

"""A JSON Schema of the scene format, built from the tables of :mod:`lighting.scene.schema`, for editors.

Editors that understand JSON Schema (VS Code with *Even Better TOML* or *Taplo*, JetBrains IDEs)
complete keys, show their defaults and flag unknown keys in a scene file.  The schema is
derived from the same tables the loader checks against, so it cannot list a key the loader
refuses; it is written to ``docs/scene.schema.json`` by::

    python -m lighting.scene.json_schema docs/scene.schema.json

The schema is a guide, and the loader stays the judge: names of models and choices are
listed in their canonical spelling (the loader also accepts other cases and ``_`` for ``-``),
checks that span keys (eye and target apart, a mesh file that exists) are not expressed, and a
part read from a BRDF file (``file = ...``) may carry any parameter name of that file.
"""

from __future__ import annotations

import json
import sys

from ..models import model_class, model_names
from ..shading.equation import TERMS
from . import checks as _c
from . import schema as _s

__all__ = ["scene_json_schema", "SCHEMA_ID"]

#: The ``$id`` of the schema (its name in the documentation site).
SCHEMA_ID = "scene.schema.json"


def _closure(fn) -> dict:
    return dict(zip(fn.__code__.co_freevars, (c.cell_contents for c in fn.__closure__ or ()), strict=True))


def _numbers_schema(lengths) -> dict:
    return {"type": "array", "items": {"type": "number"}, "minItems": min(lengths), "maxItems": max(lengths)}


def _check_schema(check) -> dict:
    """The JSON Schema of one value check of :mod:`lighting.scene.checks`."""
    if check is _c._number:
        return {"type": "number"}
    if check is _c._boolean:
        return {"type": "boolean"}
    if check is _c._string:
        return {"type": "string"}
    if check is _c._rgba:
        return {"anyOf": [{"type": "number"}, _numbers_schema((3, 4))]}
    if check is _c._terms_check:
        return {"type": "array", "items": {"enum": list(TERMS)}, "minItems": 1, "uniqueItems": True}
    owner = check.__qualname__.split(".", 1)[0]
    free = _closure(check)
    if owner == "_choice":
        choices = list(free["choices"])
        # An integer whose text is a choice is that choice (denominator = 4).
        return {"enum": choices + [int(c) for c in choices if c.isdigit()]}
    if owner == "_integer_check":
        out = {"type": "integer"}
        if free.get("minimum") is not None:
            out["minimum"] = free["minimum"]
        if free.get("maximum") is not None:
            out["maximum"] = free["maximum"]
        return out
    if owner == "_number_in":
        return {"type": "number", "minimum": free["lo"], "maximum": free["hi"]}
    if owner == "_numbers":
        return _numbers_schema(free["lengths"])
    if owner == "_number_or":
        return {"anyOf": [{"type": "number"}, _check_schema(free["vec"])]}
    raise TypeError(f"no JSON Schema for the check {check.__qualname__}")


def _object(spec: dict, *, description: str = "", overrides: dict | None = None, const: dict | None = None) -> dict:
    """A closed object (no unknown key) from a ``key -> (check, default)`` table."""
    props, required = {}, []
    for key, (check, default) in spec.items():
        if overrides and key in overrides:
            prop = dict(overrides[key])
        elif const and key in const:
            prop = {"const": const[key]}
        else:
            prop = _check_schema(check)
        if default is _c.REQUIRED:
            required.append(key)
        elif default is not _c._ABSENT and "default" not in prop:
            prop["default"] = default
        props[key] = prop
    out = {"type": "object", "properties": props, "additionalProperties": False}
    if required:
        out["required"] = required
    if description:
        out = {"description": description, **out}
    return out


def _model_parts() -> list:
    parts = []
    for name in model_names():
        cls = model_class(name)
        props = {"model": {"const": name}}
        required = ["model"]
        for p in cls.parameters:
            prop = _check_schema(_s._parameter_check(p))
            prop["default"] = list(p.default) if isinstance(p.default, tuple) else p.default
            if getattr(p, "description", ""):
                prop["description"] = p.description
            props[p.name] = prop
        parts.append({"type": "object", "properties": props, "required": required, "additionalProperties": False})
    parts.append(
        {
            "description": "A model read from a BRDF file (.brdf or MERL .binary), its parameters by name",
            "type": "object",
            "properties": {"file": {"type": "string", "minLength": 1}},
            "required": ["file"],
            "not": {"required": ["model"]},
        }
    )
    return parts


def scene_json_schema() -> dict:
    """The JSON Schema (draft 2020-12) of a scene file, from the loader's tables and the model registry.

    Returns
    -------
    dict
        The schema; ``json.dumps`` of it is what ``docs/scene.schema.json`` holds.  Every table is
        closed (``additionalProperties: false``), so an editor flags a misspelt key.

    Examples
    --------
    >>> s = scene_json_schema()
    >>> sorted(s["properties"]) == sorted(["version", "description", "camera", "image", "render", "opengl",
    ...                                    "materials", "objects", "lights"])
    True
    >>> s["$defs"]["camera"]["required"]
    ['eye']
    """
    light_variants = [
        _object(spec, description=f"a {kind} light", const={"type": kind}) for kind, spec in _s.LIGHT_KEYS.items()
    ]
    material = {
        "oneOf": [
            _object(
                _s.MATERIAL_KEYS,
                description="engine reflectance models, summed",
                overrides={"parts": {"type": "array", "minItems": 1, "items": {"$ref": "#/$defs/part"}}},
            ),
            _object(_s.GL_MATERIAL_KEYS, description="an OpenGL fixed-function material", const={"model": "opengl"}),
        ]
    }
    object_overrides = {
        "material": {"anyOf": [{"type": "string"}, {"$ref": "#/$defs/material"}]},
        "lights": {"type": "array", "items": {"$ref": "#/$defs/light"}},
    }
    object_variants = [
        _object(spec, description=f"a {kind}", overrides=object_overrides, const={"type": kind})
        for kind, spec in _s.OBJECT_KEYS.items()
    ]
    top = _object(
        _s.TOP_KEYS,
        overrides={
            "version": {"const": _s.FORMAT_VERSION, "default": _s.FORMAT_VERSION},
            "camera": {"$ref": "#/$defs/camera"},
            "image": {"$ref": "#/$defs/image"},
            "render": {"$ref": "#/$defs/render"},
            "opengl": {"$ref": "#/$defs/opengl"},
            "materials": {"type": "object", "additionalProperties": {"$ref": "#/$defs/material"}},
            "objects": {"type": "array", "minItems": 1, "items": {"$ref": "#/$defs/object"}},
            "lights": {"type": "array", "items": {"$ref": "#/$defs/light"}},
        },
    )
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "$id": SCHEMA_ID,
        "title": "lighting-explorer scene file",
        "description": "A scene of the lighting engine (TOML). Generated from lighting.scene.schema; "
        "the loader (lighting.load_scene) is the judge.",
        **top,
        "$defs": {
            "camera": _object(_s.CAMERA_KEYS),
            "image": _object(_s.IMAGE_KEYS),
            "render": _object(_s.RENDER_KEYS),
            "opengl": _object(_s.OPENGL_KEYS),
            "material": material,
            "part": {"anyOf": _model_parts()},
            "light": {"anyOf": light_variants},
            "object": {"anyOf": object_variants},
        },
    }


def main(argv=None) -> int:
    """Write the schema as JSON to a file (or to standard output without an argument).

    Parameters
    ----------
    argv : list of str, optional
        ``[PATH]``; default ``sys.argv[1:]``.

    Returns
    -------
    int
        0.
    """
    argv = sys.argv[1:] if argv is None else argv
    text = json.dumps(scene_json_schema(), indent=2, ensure_ascii=False) + "\n"
    if argv:
        with open(argv[0], "w", encoding="utf-8", newline="\n") as f:
            f.write(text)
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())

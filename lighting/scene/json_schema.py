"""A JSON Schema of the scene format, generated from the fields of :mod:`lighting.scene.schema`, for editors.

Editors that understand JSON Schema (VS Code with *Even Better TOML* or *Taplo*, JetBrains IDEs)
complete keys, show their defaults and descriptions and flag unknown keys in a scene file.  Each key's
schema is its :class:`~lighting.scene.checks.Field` (type, bounds, choices, lengths, default, description)
stated as JSON Schema: the loader checks the same fields, so the schema cannot list a key the loader
refuses nor a bound it does not enforce; it is written to ``docs/scene.schema.json`` by:

    python -m lighting.scene.json_schema docs/scene.schema.json

The schema is a guide, and the loader stays the judge: names of models and choices are
listed in their canonical spelling (the loader also accepts other cases and ``_`` for ``-``),
checks that span keys (eye and target apart, a mesh file that exists) are not expressed, and a
part read from a BRDF file (``file = ...``) may carry any parameter name of that file.
"""

from __future__ import annotations

import json
import sys

from . import schema as _s
from .checks import ABSENT, REQUIRED

__all__ = ["scene_json_schema", "SCHEMA_ID"]

#: The ``$id`` of the schema (its name in the documentation site).
SCHEMA_ID = "scene.schema.json"


def _plain(v):
    """A default as JSON holds it (a tuple is an array)."""
    return [_plain(x) for x in v] if isinstance(v, (list, tuple)) else v


def _bounded(out: dict, field) -> dict:
    for key, bound in (("minimum", field.minimum), ("maximum", field.maximum)):
        if bound is not None:
            out[key] = bound
    return out


def _field_schema(field) -> dict:
    """The JSON Schema of one :class:`~lighting.scene.checks.Field`: what its check enforces, stated as data."""
    kind, ref = field.kind, {"$ref": f"#/$defs/{field.ref}"}
    if kind in ("number", "integer"):
        out = _bounded({"type": kind}, field)
        if field.choices:
            out = {"const": field.choices[0]} if len(field.choices) == 1 else {**out, "enum": list(field.choices)}
    elif kind in ("bool", "string"):
        out = {"type": "boolean" if kind == "bool" else "string"}
    elif kind == "choice":
        # An integer whose text is a choice is that choice (denominator = 4).
        out = {"enum": list(field.choices) + [int(c) for c in field.choices if c.isdigit()]}
    elif kind == "terms":
        out = {"type": "array", "items": {"enum": list(field.choices)}, "minItems": 1, "uniqueItems": True}
    elif kind == "table":
        out = ref
    elif kind == "named":
        out = {"type": "object", "additionalProperties": ref}
    elif kind == "name_or_table":
        out = {"anyOf": [{"type": "string"}, ref]}
    elif kind == "tables":
        out = {"type": "array", **({"minItems": 1} if field.empty is not None else {}), "items": ref}
    else:  # an array of numbers
        entry = _bounded({"type": "number"}, field)
        lengths = field.lengths
        out = {"type": "array", "items": entry, "minItems": min(lengths), "maxItems": max(lengths)}
        out = {"anyOf": [entry, out]} if field.scalar else out
    if field.default is not REQUIRED and field.default is not ABSENT:
        out["default"] = _plain(field.default)
    if field.description:
        out["description"] = field.description
    return out


def _object(spec: dict, *, description: str = "", const: dict | None = None) -> dict:
    """A closed object (no unknown key) from a ``key -> Field`` table; ``const`` keys hold one value."""
    props = {k: _field_schema(f) for k, f in spec.items()}
    for k, value in (const or {}).items():  # the variant's tag: one value, and what the key is
        props[k] = {"const": value, **({"description": spec[k].description} if spec[k].description else {})}
    required = [k for k, f in spec.items() if f.default is REQUIRED]
    out = {"type": "object", "properties": props, "additionalProperties": False}
    if required:
        out["required"] = required
    return {"description": description, **out} if description else out


def _model_parts() -> list:
    parts = [_object(spec, const={"model": name}) for name, spec in _s.model_keys().items()]
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
    """The JSON Schema (draft 2020-12) of a scene file, from the loader's fields and the model registry.

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
            _object(_s.MATERIAL_KEYS, description="engine reflectance models, summed"),
            _object(_s.GL_MATERIAL_KEYS, description="an OpenGL fixed-function material", const={"model": "opengl"}),
        ]
    }
    object_variants = [
        _object(spec, description=f"a {kind}", const={"type": kind}) for kind, spec in _s.OBJECT_KEYS.items()
    ]
    top = _object(_s.TOP_KEYS)
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

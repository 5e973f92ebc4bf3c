"""Value checks of scene files, with the key path in every message.

Each key of each table is a :class:`Field`: data saying its type, shape, bounds, choices and default
(:mod:`lighting.scene.schema` lists them).  :meth:`Field.check` is the loader's check and the JSON Schema is
generated from the same fields (:mod:`lighting.scene.json_schema`).  Ranges that the engine's constructors
check stay theirs: the constructors run on every value (see :meth:`_Ctx.build`).  Before any of that, the
text (or dict) is checked for nesting deeper than :data:`MAX_NESTING`.
"""

from __future__ import annotations

import copy
import math
import numbers
import os
import re
from dataclasses import dataclass

import numpy as np

from .._budget import BudgetError, check_budget
from .._text import abbreviate
from ..render.mesh import TriangleMesh
from .budget import _clamp
from .errors import SceneBudgetError, SceneError, _describe, _fmt_value, _int_text, _join, _norm_name, _suggest
from .examples import EXAMPLES_DIR

__all__ = ["MAX_NESTING", "Field", "REQUIRED", "ABSENT"]


class _Ctx:
    """Where a parse is: the file label (for messages) and the folder relative paths start from."""

    def __init__(self, source: str, base_dir: str):
        self.source, self.base_dir = source, base_dir
        # A shipped example's files are named as the scene names them (cube.obj), not by the package's folder.
        shipped = os.path.normcase(os.path.abspath(base_dir)) == os.path.normcase(EXAMPLES_DIR)
        self._folder_shown = EXAMPLES_DIR + os.sep if shipped else None
        self.meshes: dict[str, TriangleMesh] = {}
        self.brdf_files: dict[str, type] = {}  # absolute path → model class (a table read once per scene)
        self.held_bytes = 0  # estimated memory of the geometry built so far (see _charge)

    def charge(self, path: str, nbytes, what: str, *, held: bool = True):
        """Refuse, naming ``path``, a value whose estimated memory (with what the scene holds) is over the budget.

        Called *before* the value is built; ``held`` adds it to what the scene holds from then on.
        """
        total = _clamp(self.held_bytes + nbytes)
        try:
            check_budget("this value", total, what=what + ("; with the rest of the scene" if self.held_bytes else ""))
        except BudgetError as e:
            raise SceneBudgetError(self.source, path, self.shown(str(e))) from None
        if held:
            self.held_bytes = total

    def shown(self, detail: str) -> str:
        """``detail`` as a message shows it: a shipped example's folder left out of the paths in it."""
        return detail.replace(self._folder_shown, "") if self._folder_shown else detail

    def resolved(self, given: str, path: str) -> str:
        """`` (path)``: where a file the scene names was looked for, when that says more than the name given."""
        return "" if self.shown(path) == given else f" ({abbreviate(path, keep_end=True)})"

    def fail(self, path: str, detail: str):
        raise SceneError(self.source, path, self.shown(detail))

    def build(self, path: str, factory, kwargs: dict, keymap: dict | None = None):
        """Call an engine constructor; its ValueError comes back with the file and key in front.

        The engine names the offending parameter first in its messages
        (conventions.md); that name, mapped to the file's key, completes the path.
        """
        try:
            return factory(**kwargs)
        except ValueError as e:
            msg = str(e)
            keymap = keymap or {}
            names = sorted(set(kwargs) | set(keymap), key=len, reverse=True)
            hit = next((k for k in names if re.match(rf"{re.escape(k)}\b", msg)), None)
            key = keymap.get(hit, hit) if hit else None
            raise SceneError(self.source, _join(path, key) if key else path, self.shown(msg)) from None


REQUIRED = object()  # a key the table must have
ABSENT = object()  # an optional key with no default: left out

#: What each kind of array of numbers is: its lengths, whether one number stands for it too, and its words.
_ARRAYS = {
    "vec3": ((3,), False, "a 3-vector (an array of 3 numbers)"),
    "color": ((3,), True, "a colour: a number or [r, g, b]"),
    "rgba": ((3, 4), True, "an OpenGL colour: a number, [r, g, b] or [r, g, b, a]"),
}


@dataclass(frozen=True)
class Field:
    """One key of a scene table, described once as data: the loader checks it, the JSON Schema publishes it.

    :meth:`check` is the loader's check; :func:`lighting.scene.json_schema.scene_json_schema` reads the same
    attributes, so a bound stated here is the bound both enforce.  A field checks the value's type, shape and
    the bounds it states; the engine's constructors check the rest (their messages get the key in front,
    :meth:`_Ctx.build`).

    Parameters
    ----------
    kind : str
        ``"number"`` (finite), ``"integer"``, ``"bool"``, ``"string"``, ``"choice"`` (one of ``choices``,
        any case, ``_`` for ``-``), ``"terms"`` (a non-empty array of ``choices``), an array of numbers:
        ``"vec3"``, ``"color"`` (a number or ``[r, g, b]``), ``"rgba"`` (made ``[r, g, b, a]``), ``"numbers"``
        (``lengths`` and ``scalar`` as given); a table checked later by the loader's own code: ``"table"``,
        ``"named"`` (a table of named ``ref`` tables), ``"name_or_table"``; or ``"tables"`` (an array of tables).
    default
        What a missing key means; :data:`REQUIRED`, or :data:`ABSENT` (left out).
    description : str
        One line for editors.
    minimum, maximum : float, optional
        Inclusive bounds of a number, an integer, or each entry of an array of numbers.
    unit : str
        Said after a number's range in messages.
    choices : tuple
        The allowed values of a choice, of the terms, or of an integer.
    lengths : tuple of int
        The lengths an array of numbers may have (set by the kinds ``vec3``, ``color`` and ``rgba``).
    scalar : bool
        An array of numbers may be given as one number.
    what : str
        What is allowed, in the messages' words: of an array (set by its kind), of an array of tables (the
        entries), or of an integer with choices.
    ref : str
        The JSON Schema definition a table (or each entry of an array of tables) follows.
    empty : str, optional
        An array of tables: the message when it is empty (``None``: empty is allowed).
    """

    kind: str
    default: object = REQUIRED
    description: str = ""
    minimum: float | None = None
    maximum: float | None = None
    unit: str = ""
    choices: tuple = ()
    lengths: tuple = ()
    scalar: bool = False
    what: str = ""
    ref: str = ""
    empty: str | None = None

    def __post_init__(self):
        if self.kind in _ARRAYS:
            for name, value in zip(("lengths", "scalar", "what"), _ARRAYS[self.kind], strict=True):
                object.__setattr__(self, name, value)

    def check(self, ctx, path: str, v):
        """The value ``v`` of the key at ``path``, checked and normalized; :meth:`_Ctx.fail` otherwise."""
        kind = self.kind
        if kind == "number":
            return self._number(ctx, path, v, self._number_words())
        if kind == "integer":
            return self._integer(ctx, path, v)
        if kind == "bool":
            if not isinstance(v, (bool, np.bool_)):
                ctx.fail(path, f"must be true or false; got {_describe(v)}")
            return bool(v)
        if kind == "string":
            if not isinstance(v, str):
                ctx.fail(path, f"must be a string; got {_describe(v)}")
            return v
        if kind == "choice":
            return _choice(self.choices)(ctx, path, v)
        if kind == "terms":
            if not isinstance(v, (list, tuple)) or not v:
                ctx.fail(path, f"must be a non-empty array of terms from {', '.join(map(repr, self.choices))}; "
                               f"got {_describe(v)}")  # fmt: skip
            pick = _choice(self.choices)
            given = [pick(ctx, _join(path, i), t) for i, t in enumerate(v)]
            return [t for t in self.choices if t in given]  # canonical order, no duplicates
        if kind == "tables":
            if not isinstance(v, (list, tuple)) or not all(isinstance(x, dict) for x in v):
                ctx.fail(path, f"must be an array of tables ([[{path}]] entries, {self.what}); got {_describe(v)}")
            if not v and self.empty is not None:
                ctx.fail(path, self.empty)
            return list(v)
        if kind in ("table", "named", "name_or_table"):
            return v  # the loader's own code checks it, with messages that say what such a table holds
        return self._numbers(ctx, path, v)

    def _range(self, fmt=format) -> str:
        """The bounds in words: ``" in [lo, hi]"``, ``" <= hi"``, ``" >= lo"`` or ``""``."""
        lo, hi = self.minimum, self.maximum
        if lo is not None and hi is not None:
            return f" in [{fmt(lo)}, {fmt(hi)}]"
        if hi is not None:
            return f" <= {fmt(hi)}"
        return "" if lo is None else f" >= {fmt(lo)}"

    def _number_words(self) -> str:
        bounds = self._range(lambda x: f"{x:g}")
        words = ("a number" if bounds.startswith(" in") else "a finite number") + bounds
        return words + (f" ({self.unit})" if self.unit else "")

    def _number(self, ctx, path, v, allowed):
        if not _is_number(v):
            ctx.fail(path, f"must be {allowed}; got {_describe(v)}")
        f = float(v)
        if not math.isfinite(f):
            ctx.fail(path, f"must be {allowed}; got {_fmt_value(f)} (nan and inf are not allowed)")
        if (self.minimum is not None and f < self.minimum) or (self.maximum is not None and f > self.maximum):
            ctx.fail(path, f"must be {allowed}; got {_fmt_value(v)}")
        return f

    def _integer(self, ctx, path, v):
        allowed = self.what or "an integer" + self._range(str)
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Integral):
            ctx.fail(path, f"must be {allowed}; got {_describe(v)}")
        lo, hi = self.minimum, self.maximum
        if (lo is not None and v < lo) or (hi is not None and v > hi) or (self.choices and v not in self.choices):
            ctx.fail(path, f"must be {allowed}; got {_fmt_value(v)}")
        return int(v)

    def _numbers(self, ctx, path, v):
        """An array of ``lengths`` numbers (each within the bounds), or one number where ``scalar``."""
        if self.scalar and _is_number(v):
            bounds = self._range(lambda x: f"{x:g}")
            f = self._number(ctx, path, v, f"{self.what}, finite" + (f" and{bounds}" if bounds else ""))
            return [f, f, f, 1.0] if self.kind == "rgba" else f  # OpenGL's colour of 4: a number is grey
        if not isinstance(v, (list, tuple)):
            ctx.fail(path, f"must be {self.what}; got {_describe(v)}")
        if len(v) not in self.lengths:
            ctx.fail(path, f"must be {self.what}; got {len(v)} entries {_fmt_value(v)}")
        entry = self._number_words()
        out = [self._number(ctx, _join(path, i), x, entry) for i, x in enumerate(v)]
        return out + [1.0] if self.kind == "rgba" and len(out) == 3 else out  # OpenGL's [r, g, b] has alpha 1


def _is_number(v) -> bool:
    return isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_))


def _choice(choices):
    """One of ``choices`` (case-insensitive, ``_`` and ``-`` alike); a check function.

    An integer whose text is a choice is taken as that choice: Cook–Torrance's ``denominator = 4``
    means ``"4"`` (TOML has no other way to write it unquoted).
    """

    def check(ctx, path, v):
        allowed = "one of " + ", ".join(repr(c) for c in choices)
        if isinstance(v, numbers.Integral) and not isinstance(v, bool):
            text = _int_text(int(v))  # never str() of a huge integer (Python refuses ints above 4300 digits)
            if text in choices:
                return text
        if not isinstance(v, str):
            ctx.fail(path, f"must be {allowed}; got {_describe(v)}")
        for c in choices:
            if _norm_name(v) == _norm_name(c):
                return c
        hint = _suggest(v, choices).strip()
        ctx.fail(path, f"must be {allowed}; got {_fmt_value(v)}" + (f" ({hint})" if hint else ""))

    return check


def _table(ctx, path, value, spec: dict, what: str) -> dict:
    """Check a table against ``spec`` (key → :class:`Field`); unknown keys get a suggestion."""
    if not isinstance(value, dict):
        ctx.fail(path, f"must be a table ({what}); got {_describe(value)}")
    for k in value:
        if k not in spec:
            hint = _suggest(k, spec)
            ctx.fail(_join(path, k), f"unknown key for {what}; {hint}allowed keys: {', '.join(spec)}")
    out = {}
    for k, field in spec.items():
        if k in value:
            out[k] = field.check(ctx, _join(path, k), value[k])
        elif field.default is REQUIRED:
            ctx.fail(_join(path, k), f"is required in {what}")
        elif field.default is not ABSENT:
            out[k] = copy.copy(field.default)  # a list or table of its own: the field's stays as declared
    return out


#: Deepest nesting of arrays and tables a scene may use (a scene needs about 7: objects[0].material.parts[0].kd).
#: tomllib reads nested values recursively, and 500 levels exhaust Python's stack: the text is scanned first.
MAX_NESTING = 32

# TOML's lexical pieces that matter for nesting: strings (brackets inside them do not count), comments,
# brackets and braces, line ends; everything else in runs.
_NEST_TOKENS = re.compile(
    r'"""(?:\\.|[^\\])*?"""|\'\'\'.*?\'\'\'|"(?:\\.|[^"\\\n])*"|\'[^\'\n]*\'|#[^\n]*|[\[\]{}\n]|[^"\'#\[\]{}\n]+',
    re.S,
)
_HEADER = re.compile(r"(?m)^[ \t]*(\[\[?)[ \t]*([^\[\]\n]+?)[ \t]*\]")


def _check_text_nesting(ctx, text: str) -> None:
    """Refuse TOML text whose arrays or inline tables nest deeper than :data:`MAX_NESTING`, naming the key."""
    depth, opened = 0, 0
    for m in _NEST_TOKENS.finditer(text):
        tok = m.group()
        if tok in ("[", "{"):
            if depth == 0:
                opened = m.start()
            depth += 1
            if depth > MAX_NESTING:
                ctx.fail(_key_at(text, opened), f"arrays or tables nested more than {MAX_NESTING} deep "
                         f"(line {text.count(chr(10), 0, m.start()) + 1}); a scene needs fewer than 10 levels")
        elif tok in ("]", "}"):
            depth = max(depth - 1, 0)


def _key_at(text: str, pos: int) -> str:
    """The key path of the value starting at ``pos``: the last table header before it and the key on its line."""
    path = ""
    headers = list(_HEADER.finditer(text, 0, pos))
    if headers:
        last = headers[-1]
        name = ".".join(part.strip().strip("\"'") for part in last.group(2).split("."))
        if last.group(1) == "[[":
            index = sum(1 for h in headers if h.group(1) == "[[" and h.group(2) == last.group(2)) - 1
            name = f"{name}[{index}]"
        path = name
    line = text[text.rfind("\n", 0, pos) + 1 : pos]
    if "=" in line:
        key = line.split("=", 1)[0].strip().strip("\"'")
        path = _join(path, key) if key else path
    return path


def _check_dict_nesting(ctx, data: dict) -> None:
    """The same limit for a scene given as a dict (walked without recursion)."""
    stack = [("", data, 1)]
    while stack:
        path, value, depth = stack.pop()
        if depth > MAX_NESTING:
            ctx.fail(path, f"arrays or tables nested more than {MAX_NESTING} deep; a scene needs fewer than 10 levels")
        items = value.items() if isinstance(value, dict) else enumerate(value)
        for k, v in items:
            if isinstance(v, (dict, list, tuple)):
                stack.append((_join(path, k if isinstance(k, (int, str)) else str(k)), v, depth + 1))

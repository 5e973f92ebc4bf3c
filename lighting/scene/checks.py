"""Value checks of scene files: types and finiteness, with the key path in every message.

A check is ``f(ctx, path, value) -> normalized value``; it only checks the *type* and finiteness.
Ranges are the engine's business: its constructors run on every value (see :meth:`_Ctx.build`).
Before any of that, the text (or dict) is checked for nesting deeper than :data:`MAX_NESTING`.
"""

from __future__ import annotations

import math
import numbers
import os
import re

import numpy as np

from .._numeric import BudgetError, abbreviate, check_budget
from ..render.mesh import TriangleMesh
from ..shading.equation import TERMS
from .budget import _clamp
from .errors import SceneBudgetError, SceneError, _describe, _fmt_value, _int_text, _join, _norm_name, _suggest
from .examples import EXAMPLES_DIR

__all__ = ["MAX_NESTING"]


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
        return "" if self.shown(path) == given else f" ({abbreviate(path)})"

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


REQUIRED = object()
_ABSENT = object()  # optional key with no default: left out


def _is_number(v) -> bool:
    return isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_))


def _finite_number(ctx, path, v, allowed="a finite number"):
    if not _is_number(v):
        ctx.fail(path, f"must be {allowed}; got {_describe(v)}")
    f = float(v)
    if not math.isfinite(f):
        ctx.fail(path, f"must be {allowed}; got {_fmt_value(f)} (nan and inf are not allowed)")
    return f


def _number(ctx, path, v):
    return _finite_number(ctx, path, v)


def _number_in(lo: float, hi: float, unit: str = ""):
    """A finite number in ``[lo, hi]``; a check function (``unit`` is said after the range)."""
    allowed = f"a number in [{lo:g}, {hi:g}]" + (f" ({unit})" if unit else "")

    def check(ctx, path, v):
        f = _finite_number(ctx, path, v, allowed)
        if not lo <= f <= hi:
            ctx.fail(path, f"must be {allowed}; got {_fmt_value(v)}")
        return f

    return check


def _integer_check(minimum=None, maximum=None):
    lo = "" if minimum is None else f" >= {minimum}"
    allowed = f"an integer{lo}" if maximum is None else f"an integer in [{minimum}, {maximum}]"

    def check(ctx, path, v):
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Integral):
            ctx.fail(path, f"must be {allowed}; got {_describe(v)}")
        if (minimum is not None and v < minimum) or (maximum is not None and v > maximum):
            ctx.fail(path, f"must be {allowed}; got {_fmt_value(v)}")
        return int(v)

    return check


def _boolean(ctx, path, v):
    if not isinstance(v, (bool, np.bool_)):
        ctx.fail(path, f"must be true or false; got {_describe(v)}")
    return bool(v)


def _string(ctx, path, v):
    if not isinstance(v, str):
        ctx.fail(path, f"must be a string; got {_describe(v)}")
    return v


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


def _numbers(lengths, what):
    """An array of finite numbers of one of ``lengths``; a check function.  ``what`` says what is allowed."""

    def check(ctx, path, v):
        if not isinstance(v, (list, tuple)):
            ctx.fail(path, f"must be {what}; got {_describe(v)}")
        if len(v) not in lengths:
            ctx.fail(path, f"must be {what}; got {len(v)} entries {_fmt_value(v)}")
        return [_finite_number(ctx, _join(path, i), x) for i, x in enumerate(v)]

    return check


_vec3 = _numbers((3,), "a 3-vector (an array of 3 numbers)")


def _number_or(lengths, what):
    """A finite number, or an array as for :func:`_numbers`."""
    vec = _numbers(lengths, what)

    def check(ctx, path, v):
        if _is_number(v):
            return _finite_number(ctx, path, v, f"{what}, finite")
        return vec(ctx, path, v)

    return check


_color = _number_or((3,), "a colour: a number or [r, g, b]")
_rgba_or_number = _number_or((3, 4), "an OpenGL colour: a number, [r, g, b] or [r, g, b, a]")


def _rgba(ctx, path, v):
    """An OpenGL colour as a list of 4: a number is grey, [r, g, b] has alpha 1."""
    c = _rgba_or_number(ctx, path, v)
    c = [c, c, c] if isinstance(c, float) else c
    return c + [1.0] if len(c) == 3 else c


def _terms_check(ctx, path, v):
    if not isinstance(v, (list, tuple)) or not v:
        ctx.fail(path, f"must be a non-empty array of terms from {', '.join(map(repr, TERMS))}; got {_describe(v)}")
    pick = _choice(TERMS)
    out = [pick(ctx, _join(path, i), t) for i, t in enumerate(v)]
    return [t for t in TERMS if t in out]  # canonical order, no duplicates


def _table(ctx, path, value, spec: dict, what: str) -> dict:
    """Check a table against ``spec`` (key → (check, default)); unknown keys get a suggestion."""
    if not isinstance(value, dict):
        ctx.fail(path, f"must be a table ({what}); got {_describe(value)}")
    for k in value:
        if k not in spec:
            hint = _suggest(k, spec)
            ctx.fail(_join(path, k), f"unknown key for {what}; {hint}allowed keys: {', '.join(spec)}")
    out = {}
    for k, (check, default) in spec.items():
        if k in value:
            out[k] = check(ctx, _join(path, k), value[k])
        elif default is REQUIRED:
            ctx.fail(_join(path, k), f"is required in {what}")
        elif default is not _ABSENT:
            out[k] = default
    return out


def _array_of_tables(ctx, path, value, what) -> list:
    if not isinstance(value, (list, tuple)) or not all(isinstance(x, dict) for x in value):
        ctx.fail(path, f"must be an array of tables ([[{path}]] entries, {what}); got {_describe(value)}")
    return list(value)


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

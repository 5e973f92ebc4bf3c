"""Scene-file errors and the text they show: the key path, the user's value abbreviated, did-you-mean hints.

Every problem with a scene file is a :class:`SceneError` (a ``ValueError``) whose message is one line
``"<file>: <key path>: <what is wrong and what is allowed>"``, of bounded length whatever the file holds.
"""

from __future__ import annotations

import difflib
import json
import math
import numbers
import re

from .._budget import BudgetError
from .._text import abbreviate

__all__ = ["SceneError", "SceneBudgetError"]


class SceneError(ValueError):
    """A malformed scene: ``"<file>: <key path>: <what is wrong and what is allowed>"``.

    Attributes
    ----------
    source : str
        The file (as given) or ``"<string>"``.
    key : str
        The key path, e.g. ``"lights[2].cutoff_deg"`` (empty for the file as a whole).
    detail : str
        The message without file and key.
    """

    def __init__(self, source: str, key: str, detail: str):
        # One line, of bounded length, whatever the file holds: a 100k-character key or value is cut
        # (lighting._text.abbreviate) and line breaks inside passed-on messages become spaces.
        source, key, detail = (" ".join(str(x).splitlines()) for x in (source, key, detail))
        source, key, detail = abbreviate(source, 200), abbreviate(key, 160), abbreviate(detail, 800)
        self.source, self.key, self.detail = source, key, detail
        super().__init__(f"{source}: {key}: {detail}" if key else f"{source}: {detail}")


def _toml_key(k: str) -> str:
    """A key as TOML writes it: bare when it is letters, digits, ``_`` and ``-``, else quoted."""
    return k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else json.dumps(k)


def _join(path: str, key) -> str:
    """The key path ``path.key`` (or ``path[i]`` for an index), the key written as in TOML and abbreviated."""
    if isinstance(key, int):
        return f"{path}[{key}]"
    k = abbreviate(_toml_key(key), 60)  # a key is the user's text too: a 100k-character one is cut
    return f"{path}.{k}" if path else k


def _fmt_value(v, depth: int = 0) -> str:
    """A value as TOML-like text for a message: at most a few entries of two levels, abbreviated."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return "nan" if math.isnan(v) else ("inf" if v == math.inf else ("-inf" if v == -math.inf else repr(v)))
    if isinstance(v, numbers.Integral):
        return abbreviate(_int_text(int(v)))
    if isinstance(v, str):
        return abbreviate(json.dumps(v))
    if isinstance(v, (list, tuple)):
        if depth >= 2:
            return "[...]" if v else "[]"
        inner = ", ".join(_fmt_value(x, depth + 1) for x in list(v)[:6])
        return abbreviate("[" + inner + (", ..." if len(v) > 6 else "") + "]")
    if isinstance(v, dict):
        if depth >= 2:
            return "{...}" if v else "{}"
        items = list(v.items())[:4]
        return abbreviate("{" + ", ".join(f"{_join('', k)} = {_fmt_value(x, depth + 1)}" for k, x in items) + "}")
    return abbreviate(repr(v))


def _int_text(n: int) -> str:
    """``str(n)``, or its size for an integer too long to print (Python refuses ints above 4300 digits)."""
    if abs(n) < 10**60:
        return str(n)
    return f"{'-' if n < 0 else ''}<an integer of about {int(abs(n).bit_length() * 0.30103) + 1} digits>"


def _describe(v) -> str:
    """A TOML-flavoured description of a value: its type and the value."""
    if isinstance(v, bool):
        kind = "a boolean"
    elif isinstance(v, numbers.Integral):
        kind = "an integer"
    elif isinstance(v, numbers.Real):
        kind = "a float"
    elif isinstance(v, str):
        kind = "a string"
    elif isinstance(v, (list, tuple)):
        kind = "an array"
    elif isinstance(v, dict):
        return "a table"
    else:
        kind = f"a {type(v).__name__}"
    return f"{kind} {_fmt_value(v)}"


def _norm_name(s: str) -> str:
    return s.strip().lower().replace("_", "-")


def _suggest(word: str, candidates) -> str:
    close = difflib.get_close_matches(_norm_name(word), [_norm_name(c) for c in candidates], n=1, cutoff=0.6)
    if not close:
        return ""
    original = next(c for c in candidates if _norm_name(c) == close[0])
    return f"did you mean {abbreviate(repr(original))}? "


class SceneBudgetError(SceneError, BudgetError):
    """A scene (or one of its values) whose estimated memory or work is over the budget
    (:func:`lighting._budget.memory_budget`)."""

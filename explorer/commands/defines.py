"""``-D KEY=VALUE``: override values of a scene file from the command line (as Mitsuba's ``-D``).

``KEY`` is a dotted path into the scene's TOML, with ``[N]`` for an entry of an array of tables:
``image.width``, ``lights[0].intensity``, ``materials.red.parts[0].kd``.  ``VALUE`` is a TOML value
(``320``, ``2.5``, ``true``, ``"text"``, ``[0.9, 0.1, 0.1]``, ``{ type = "point" }``); a bare word
that is not one (``gouraud``) is taken as a string.  A key that does not exist yet is added (tables on
the way are created), so a scene may be given a value it leaves to its default.  The edited scene goes
through the same checks as the file; see :func:`explorer.commands.render.run`.

Not a sub-command: a helper of ``render``.
"""

from __future__ import annotations

import re
import tomllib

from lighting._text import quote

__all__ = ["Define", "parse_define", "apply_defines", "key_label"]

_SEGMENT = re.compile(r'(?:([A-Za-z0-9_-]+)|"([^"\\]*)")((?:\[\d{1,6}\])*)')
_BARE_WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_.+-]*")


class Define:
    """One parsed ``-D KEY=VALUE``: the key path, the value and the text the user gave.

    Parameters
    ----------
    text : str
        The ``KEY=VALUE`` as given (named in errors).
    path : list of str or int
        Table keys (``str``) and array indices (``int``), outermost first.
    value : object
        The TOML value.
    """

    def __init__(self, text: str, path: list, value):
        self.text, self.path, self.value = text, path, value

    def __repr__(self) -> str:
        return f"Define({self.text!r})"


def parse_define(text: str) -> Define:
    """Parse ``KEY=VALUE`` (one ``-D``).

    Parameters
    ----------
    text : str
        E.g. ``"lights[0].intensity=2"``.

    Returns
    -------
    Define
        The key path and the value.

    Raises
    ------
    ValueError
        One line starting ``-D <text>:`` saying what is wrong and what is allowed.

    Examples
    --------
    >>> d = parse_define("materials.red.parts[0].kd=[0.9, 0.1, 0.1]")
    >>> d.path, d.value
    (['materials', 'red', 'parts', 0, 'kd'], [0.9, 0.1, 0.1])
    >>> parse_define("render.mode=gouraud").value
    'gouraud'
    """
    text = str(text)
    shown = quote(text)
    key, sep, raw = text.partition("=")
    if not sep:
        raise ValueError(f"-D {shown}: expected KEY=VALUE, e.g. -D image.width=320 or -D lights[0].intensity=2")
    path: list = []
    for part in key.strip().split(".") if key.strip() else [""]:
        m = _SEGMENT.fullmatch(part.strip())
        if not m:
            raise ValueError(
                f"-D {shown}: the key must be names joined by '.', each with optional [N] indices "
                f"(e.g. lights[0].intensity); got {quote(key)}"
            )
        path.append(m.group(1) if m.group(1) is not None else m.group(2))
        path.extend(int(i) for i in re.findall(r"\[(\d+)\]", m.group(3)))
    raw = raw.strip()
    try:
        value = tomllib.loads(f"v = {raw}")["v"]
    except (tomllib.TOMLDecodeError, RecursionError, ValueError):
        if not _BARE_WORD.fullmatch(raw):
            raise ValueError(
                f'-D {shown}: the value must be a TOML value (a number, true or false, "text", [a, list] or '
                f"{{ a = table }}) or a bare word; got {quote(raw)}"
            ) from None
        value = raw
    return Define(text, path, value)


def _describe(value) -> str:
    kinds = {dict: "a table", list: "an array", str: "a string", bool: "a boolean", int: "a number", float: "a number"}
    return kinds.get(type(value), type(value).__name__)


def key_label(path) -> str:
    """A define's key path as the scene loader names keys in its messages.

    Parameters
    ----------
    path : list of str or int
        :attr:`Define.path`.

    Returns
    -------
    str
        E.g. ``"lights[0].intensity"``.

    Examples
    --------
    >>> key_label(parse_define("materials.red.parts[0].kd=1").path)
    'materials.red.parts[0].kd'
    """
    from lighting.scene.errors import _join

    out = ""
    for p in path:
        out = _join(out, p)
    return out


def apply_defines(data: dict, defines) -> dict:
    """Set each define's value in ``data`` (the dict ``tomllib`` read from the scene file), in order.

    Parameters
    ----------
    data : dict
        The scene's TOML as a dict; changed in place.
    defines : iterable of Define or str
        The overrides (a ``str`` is parsed with :func:`parse_define`); a later one wins.

    Returns
    -------
    dict
        ``data``.

    Raises
    ------
    ValueError
        A path through something that is not a table or an array, or an index past the end of an array:
        one line starting ``-D <text>:``.

    Examples
    --------
    >>> apply_defines({"lights": [{"intensity": 1.0}]}, ["lights[0].intensity=2", "image.width=320"])
    {'lights': [{'intensity': 2}], 'image': {'width': 320}}
    """
    for d in defines:
        d = d if isinstance(d, Define) else parse_define(d)
        node = data
        for i, step in enumerate(d.path):
            last = i == len(d.path) - 1
            where = key_label(d.path[:i]) or "the scene"
            if isinstance(step, int):
                if not isinstance(node, list):
                    raise ValueError(
                        f"-D {quote(d.text)}: {where} is {_describe(node)}, not an array; [{step}] needs one"
                    )
                if step >= len(node):
                    n = len(node)
                    has = {0: "no entries", 1: "1 entry (index 0)"}.get(n, f"{n} entries (indices 0 to {n - 1})")
                    raise ValueError(f"-D {quote(d.text)}: {where} has {has}; got [{step}]")
            elif not isinstance(node, dict):
                raise ValueError(f"-D {quote(d.text)}: {where} is {_describe(node)}, not a table; .{step} needs one")
            if last:
                node[step] = d.value
            else:
                if isinstance(node, dict) and step not in node:
                    node[step] = [] if isinstance(d.path[i + 1], int) else {}
                node = node[step]
    return data

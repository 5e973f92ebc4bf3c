r"""Griffe extension: the reST that the engine's NumPy-style docstrings use, as the Markdown mkdocstrings renders.

``mkdocs.yml`` names this file among the Python handler's Griffe ``extensions``.  Griffe and mkdocstrings read
the NumPy docstring *sections*, but the text in them is rendered as Markdown, and their maintainers keep reST
markup out of scope (no released Griffe or mkdocstrings extension reads Sphinx roles; the one for "Sphinx"
reads ``#:`` attribute comments).  So, once a package is loaded, every docstring is rewritten in place:

* a role ``:func:`name``` (also ``:class:``, ``:meth:``, ``:mod:``, ``:attr:``, ``:data:``, ``:obj:``, ``:exc:``,
  with or without ``py:``) becomes an optional cross-reference that mkdocs-autorefs links when the object is
  on a page, and shows as code otherwise; ``~a.b.c`` shows ``c``; the name is looked up as Python would from
  the docstring's object, then as a full path, then as the last part of one object's path in the package;
* a role inside a code span, or on a NumPy section's item line (``name : type``; mkdocstrings shows types as
  code, not Markdown), becomes the plain name, and that line's reST literals (double backticks) their text, so
  Griffe can read the type and link it;
* a ``.. math::`` directive and its indented block become a displayed formula (``$$ ... $$``, typeset by
  ``pymdownx.arithmatex``), and the ``::`` that ends a paragraph before a literal block becomes ``:``.

The last two are syntax, not links: :func:`markdown_syntax` applied to a file's docstring source writes them as
Markdown for good (the result renders the same); once no docstring holds them, only the roles need this file.

Examples
--------
>>> print(rest_to_markdown(":func:`~lighting.vec.dot` and ``:class:`X` here``", lambda name: "lighting.vec.dot"))
<autoref identifier="lighting.vec.dot" optional>`dot`</autoref> and ``X here``
>>> print(rest_to_markdown(":meth:`the dot <lighting.vec.dot>`", lambda name: name))
<autoref identifier="lighting.vec.dot" optional>`the dot`</autoref>
"""

from __future__ import annotations

import re
from collections.abc import Callable

import griffe

# :role:`target`, :role:`~a.b.target`, :role:`target()` or :role:`title <target>`.
_ROLE = r":(?:py:)?(?:func|class|meth|mod|attr|data|obj|exc):`(?:([^`<]*?)\s*<)?(~?)([\w.]+?)(\(\))?>?`"
_ROLE_RE = re.compile(_ROLE)
# A role, or a code span (double or single backticks): scanned together, so a role's own backticks are not a span.
_ROLE_OR_CODE_RE = re.compile(_ROLE + r"|(?<!`)``(?!`).+?(?<!`)``(?!`)|(?<!`)`(?!`)[^`]+?`(?!`)", re.S)
_MATH_RE = re.compile(r"^([ \t]*)\.\. math::[ \t]*\n((?:[ \t]*\n)*)((?:\1[ \t]+\S.*\n?|[ \t]*\n)+)", re.M)
_LITERAL_BLOCK_RE = re.compile(r"(\S)::[ \t]*\n([ \t]*\n)")
# NumPy sections whose items are "name : type" (or a type alone) at the section's indentation.
_ITEM_SECTIONS = {"Parameters", "Other Parameters", "Returns", "Yields", "Receives", "Raises", "Warns", "Attributes"}


def _shown(m: re.Match) -> str:
    title, short, target, call = m.group(1), m.group(2), m.group(3), m.group(4) or ""
    return title or (target.rsplit(".", 1)[-1] if short else target) + call


def _plain(text: str) -> str:
    return _ROLE_RE.sub(_shown, text)


def markdown_syntax(text: str) -> str:
    """The reST constructs of a docstring other than cross-references, as Markdown (see the module docstring).

    Parameters
    ----------
    text : str
        A docstring, or its source with the indentation it has in the file (the rewriting keeps it).

    Returns
    -------
    str
        The text with each ``.. math::`` block as ``$$ ... $$``, ``word::`` before a literal block as ``word:``,
        and the item lines of NumPy sections with plain names for roles and text for double-backtick literals.

    Examples
    --------
    >>> print(markdown_syntax(".. math::\\n\\n    E = mc^2\\n\\nso::\\n\\n    x\\n"))
    $$
    E = mc^2
    $$
    <BLANKLINE>
    so:
    <BLANKLINE>
        x
    <BLANKLINE>
    """

    def math(m: re.Match) -> str:
        indent, lines = m.group(1), m.group(3).rstrip().split("\n")
        cut = min(len(line) - len(line.lstrip()) for line in lines if line.strip())
        body = "".join(f"{indent}{line[cut:]}".rstrip() + "\n" for line in lines)
        return f"{indent}$$\n{body}{indent}$$\n" + ("\n" if m.string[m.end() :].strip() else "")

    lines = text.split("\n")
    section, indent = None, ""
    for i, line in enumerate(lines):
        below = lines[i + 1] if i + 1 < len(lines) else ""
        if line.strip() and set(below.strip()) == {"-"} and len(below.strip()) >= 3:
            section, indent = line.strip(), line[: len(line) - len(line.lstrip())]
        elif section in _ITEM_SECTIONS and line.strip("- ") and len(line) - len(line.lstrip()) == len(indent):
            lines[i] = re.sub(r"``(.+?)``", r"\1", _plain(line))
    text = _MATH_RE.sub(math, "\n".join(lines))
    return _LITERAL_BLOCK_RE.sub(r"\1:\n\2", text)


def rest_to_markdown(text: str, resolve: Callable[[str], str | None]) -> str:
    """Rewrite the reST of one docstring as Markdown (see the module docstring).

    Parameters
    ----------
    text : str
        The docstring.
    resolve : callable
        Maps a role's target (``a.b`` as written, without ``~`` or ``()``) to the object's full path, or ``None``
        when no object has that name (the role then shows as code, unlinked).

    Returns
    -------
    str
        The docstring as Markdown: :func:`markdown_syntax`, then roles as cross-references (plain names in code).
    """

    def role(m: re.Match) -> str:
        path = resolve(m.group(3))
        code = f"`{_shown(m)}`"
        return f'<autoref identifier="{path}" optional>{code}</autoref>' if path else code

    text = markdown_syntax(text)
    return _ROLE_OR_CODE_RE.sub(lambda m: role(m) if m.group(3) else _plain(m.group(0)), text)


class RestRoles(griffe.Extension):
    """Rewrite every docstring of a loaded package from reST to Markdown (see the module docstring)."""

    def on_package(self, *, pkg: griffe.Module, loader: griffe.GriffeLoader, **kwargs) -> None:
        """Griffe event: the package ``pkg`` is loaded; rewrite its docstrings.

        Parameters
        ----------
        pkg : griffe.Module
            The package.
        loader : griffe.GriffeLoader
            The loader, whose collection holds every package loaded so far.
        **kwargs
            Other event arguments.
        """
        objects: list[griffe.Object] = []

        def walk(obj: griffe.Object) -> None:
            objects.append(obj)
            for member in obj.members.values():
                if not member.is_alias:
                    walk(member)

        walk(pkg)
        by_last: dict[str, list[str]] = {}
        for obj in objects:
            by_last.setdefault(obj.name, []).append(obj.path)
        collection = loader.modules_collection

        def canonical(path: str) -> str | None:
            for _ in range(10):  # follow re-exports to the object's own path
                try:
                    obj = collection.get_member(path)
                except (KeyError, ValueError, AttributeError, griffe.AliasResolutionError):
                    return None
                if not obj.is_alias:
                    return obj.path
                path = obj.target_path
            return None

        for obj in objects:
            if obj.docstring is None or ":" not in obj.docstring.value:
                continue

            def resolve(name: str, obj=obj) -> str | None:
                head, _, rest = name.partition(".")
                try:
                    scoped = obj.resolve(head) + ("." + rest if rest else "")
                except (griffe.NameResolutionError, KeyError, ValueError):
                    scoped = None
                for path in (scoped, name):
                    if path and (found := canonical(path)):
                        return found
                ends = [p for p in by_last.get(name.rsplit(".", 1)[-1], []) if p.endswith("." + name)]
                return ends[0] if len(ends) == 1 else None

            obj.docstring.value = rest_to_markdown(obj.docstring.value, resolve)

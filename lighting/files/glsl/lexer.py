"""Tokens of the GLSL subset, each with its line and column in the file.

Examples
--------
>>> [(t.kind, t.text) for t in tokenize("x += 1.5e1; // c", "f.brdf")][:3]
[('id', 'x'), ('op', '+='), ('num', '1.5e1')]
"""

from __future__ import annotations

import re
from dataclasses import dataclass

__all__ = ["GLSLError", "Token", "tokenize", "error"]

#: The longest source the lexer takes (the file is bounded before reading; this bounds work too).
MAX_TOKENS = 200_000


class GLSLError(ValueError):
    """A ``.brdf`` file the reader refuses: the message is ``"FILE:LINE:COL: what is wrong"``."""


def error(filename: str, line: int, col: int, message: str) -> GLSLError:
    """The one error type of the GLSL front end, with the place in the file.

    Parameters
    ----------
    filename : str
        The file's name, as the user gave it.
    line, col : int
        1-based line and column.
    message : str
        What was expected and what was found.

    Returns
    -------
    GLSLError
        A ``ValueError`` to raise.

    Examples
    --------
    >>> str(error("a.brdf", 3, 7, "expected ';', got '}'"))
    "a.brdf:3:7: expected ';', got '}'"
    """
    return GLSLError(f"{filename}:{line}:{col}: {message}")


@dataclass(frozen=True)
class Token:
    """One token: ``kind`` is ``"id"``, ``"num"``, ``"op"`` or ``"eof"``; ``text`` is its source text."""

    kind: str
    text: str
    line: int
    col: int

    def describe(self) -> str:
        """How an error message names the token."""
        return "end of shader" if self.kind == "eof" else repr(self.text)


_OPS = sorted(
    "+= -= *= /= ++ -- == != <= >= && || ^^ + - * / % < > = ! ? : ; , . ( ) { } [ ]".split(), key=len, reverse=True
)
_TOKEN = re.compile(
    r"(?P<ws>[ \t\r\f\v]+)|(?P<nl>\n)|(?P<line>//[^\n]*)|(?P<block>/\*)"
    r"|(?P<num>(?:\d+\.\d*|\.\d+|\d+)(?:[eE][+-]?\d+)?[fF]?)"
    r"|(?P<id>[A-Za-z_][A-Za-z_0-9]*)"
    r"|(?P<op>" + "|".join(re.escape(o) for o in _OPS) + ")"
)


def tokenize(source: str, filename: str, first_line: int = 1) -> list[Token]:
    """Split GLSL source into tokens, skipping ``//`` and ``/* */`` comments.

    Parameters
    ----------
    source : str
        The shader text.
    filename : str
        For error messages.
    first_line : int
        The file line the source starts on (the shader block sits inside a larger file).

    Returns
    -------
    list of Token
        Ending with one ``"eof"`` token.

    Raises
    ------
    GLSLError
        An unterminated block comment, a character outside the subset (``#`` directives included),
        or more than :data:`MAX_TOKENS` tokens.

    Examples
    --------
    >>> tokenize("a.x", "f")[1]
    Token(kind='op', text='.', line=1, col=2)
    """
    tokens: list[Token] = []
    pos, line, line_start = 0, first_line, 0
    n = len(source)
    while pos < n:
        m = _TOKEN.match(source, pos)
        col = pos - line_start + 1
        if m is None:
            raise error(filename, line, col, f"expected a GLSL token, got {source[pos]!r}")
        kind = m.lastgroup
        if kind == "nl":
            line, line_start = line + 1, m.end()
        elif kind == "block":
            end = source.find("*/", m.end())
            if end < 0:
                raise error(filename, line, col, "expected '*/' closing this comment, got end of shader")
            body = source[pos:end]
            newlines = body.count("\n")
            if newlines:
                line, line_start = line + newlines, pos + body.rfind("\n") + 1
            pos = end + 2
            continue
        elif kind in ("num", "id", "op"):
            if kind == "num" and m.end() < n and (source[m.end()].isalnum() or source[m.end()] == "_"):
                raise error(filename, line, col, f"expected a number, got {source[pos : m.end() + 1]!r}")
            tokens.append(Token(kind, m.group(), line, col))
            if len(tokens) > MAX_TOKENS:
                raise error(filename, line, col, f"expected at most {MAX_TOKENS} tokens in the shader")
        pos = m.end()
    tokens.append(Token("eof", "", line, pos - line_start + 1))
    return tokens

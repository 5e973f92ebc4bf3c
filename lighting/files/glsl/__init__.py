"""A small GLSL subset for BRDF Explorer's ``.brdf`` files: lexer, parser and a vectorised NumPy interpreter.

Nothing read from a file runs as Python: the source becomes tokens (:mod:`.lexer`), then a tree of
small dataclasses (:mod:`.parser`), which :mod:`.interpret` walks with NumPy arrays holding every
direction pair at once.  Every error is one ``ValueError`` ``"FILE:LINE:COL: expected X, got Y"``.
"""

from .interpret import Interpreter, Value
from .lexer import GLSLError, tokenize
from .parser import parse

__all__ = ["GLSLError", "Interpreter", "Value", "parse", "tokenize"]

"""Recursive-descent parser (precedence climbing for expressions) of the GLSL subset into small dataclasses.

The subset: ``float int bool vec2 vec3 vec4`` declarations and ``const`` globals; constructors;
swizzles (``.xyzw``, ``.rgba``, ``.stpq``) read and written; arithmetic, comparisons, ``&& || ^^ !``,
the ternary; ``= += -= *= /=``, ``++``/``--``; ``if``/``else``; ``for``; ``return``; functions with
``in``/``out``/``inout`` parameters, overloaded by argument types.

Examples
--------
>>> from lighting.files.glsl.lexer import tokenize
>>> prog = parse(tokenize("float f(float x) { return x * 2.0; }", "f"), "f")
>>> prog.functions[0].name, type(prog.functions[0].body[0]).__name__
('f', 'Return')
"""

from __future__ import annotations

from dataclasses import dataclass, field

from .lexer import Token, error

__all__ = ["TYPES", "parse", "Program"]

#: The value types of the subset and their component counts.
TYPES = {"float": 1, "int": 1, "bool": 1, "vec2": 2, "vec3": 3, "vec4": 4}
_KEYWORDS = {"if", "else", "for", "while", "do", "return", "break", "continue", "discard", "const", "uniform",
             "in", "out", "inout", "void", "true", "false", "struct"} | set(TYPES)  # fmt: skip
#: Binary operators by precedence (higher binds tighter), as GLSL 4.10 section 5.1 orders them.
_BINARY = {"||": 1, "^^": 2, "&&": 3, "==": 4, "!=": 4, "<": 5, ">": 5, "<=": 5, ">=": 5, "+": 6, "-": 6,
           "*": 7, "/": 7, "%": 7}  # fmt: skip
_ASSIGN = {"=", "+=", "-=", "*=", "/="}
#: Nesting bound: a recursive-descent parser recurses per level, so a hostile file could exhaust the stack.
MAX_DEPTH = 200


@dataclass
class Node:
    """A place in the file (every node has one, for errors found while interpreting)."""

    line: int
    col: int


@dataclass
class Num(Node):
    value: float
    type: str  # "float", "int" or "bool"


@dataclass
class Var(Node):
    name: str


@dataclass
class Call(Node):
    name: str
    args: list


@dataclass
class Swizzle(Node):
    base: Node
    fields: str


@dataclass
class Unary(Node):
    op: str
    operand: Node


@dataclass
class Binary(Node):
    op: str
    left: Node
    right: Node


@dataclass
class Ternary(Node):
    cond: Node
    then: Node
    other: Node


@dataclass
class Assign(Node):
    op: str
    target: Node
    value: Node


@dataclass
class IncDec(Node):
    op: str  # "++" or "--"
    target: Node
    prefix: bool


@dataclass
class Decl(Node):
    type: str
    name: str
    init: Node | None
    const: bool = False


@dataclass
class ExprStmt(Node):
    expr: Node


@dataclass
class If(Node):
    cond: Node
    then: list
    other: list


@dataclass
class For(Node):
    init: list
    cond: Node | None
    step: Node | None
    body: list


@dataclass
class Return(Node):
    value: Node | None


@dataclass
class Param:
    qualifier: str  # "in", "out" or "inout"
    type: str
    name: str


@dataclass
class Function(Node):
    type: str
    name: str
    params: list
    body: list


@dataclass
class Program:
    """A parsed shader: global declarations (in order) and functions (in order)."""

    globals: list = field(default_factory=list)
    functions: list = field(default_factory=list)


class _Parser:
    def __init__(self, tokens: list[Token], filename: str):
        self.t, self.i, self.file, self.depth = tokens, 0, filename, 0

    # -- tokens
    @property
    def tok(self) -> Token:
        return self.t[self.i]

    def fail(self, expected: str, tok: Token | None = None):
        tok = self.tok if tok is None else tok
        raise error(self.file, tok.line, tok.col, f"expected {expected}, got {tok.describe()}")

    def peek(self, text: str, ahead: int = 0) -> bool:
        t = self.t[min(self.i + ahead, len(self.t) - 1)]
        return t.kind in ("op", "id") and t.text == text

    def accept(self, text: str) -> Token | None:
        if self.peek(text):
            self.i += 1
            return self.t[self.i - 1]
        return None

    def expect(self, text: str, what: str | None = None) -> Token:
        tok = self.accept(text)
        if tok is None:
            self.fail(what or repr(text))
        return tok

    def name(self, what: str = "a name") -> Token:
        tok = self.tok
        if tok.kind != "id" or tok.text in _KEYWORDS:
            self.fail(what)
        self.i += 1
        return tok

    def type_name(self, allow_void: bool = False) -> Token:
        tok = self.tok
        if tok.kind == "id" and (tok.text in TYPES or (allow_void and tok.text == "void")):
            self.i += 1
            return tok
        self.fail("a type (" + ", ".join(TYPES) + (", void" if allow_void else "") + ")")

    def nest(self, tok: Token):
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise error(self.file, tok.line, tok.col, f"expected at most {MAX_DEPTH} levels of nesting")

    # -- top level
    def program(self) -> Program:
        prog = Program()
        while self.tok.kind != "eof":
            start = self.tok
            const = bool(self.accept("const"))
            if not const and self.accept("uniform"):
                self.fail("a function or a const global (the parameter block declares the uniforms)", start)
            ty = self.type_name(allow_void=not const)
            name = self.name()
            if not const and self.peek("("):
                prog.functions.append(self.function(ty, name))
            else:
                if ty.text == "void":
                    self.fail("'(' after a void function's name")
                prog.globals.extend(self.declarators(ty, name, const=True, top=True))
                self.expect(";")
        return prog

    def function(self, ty: Token, name: Token) -> Function:
        self.expect("(")
        params = []
        if self.peek("void") and self.peek(")", 1):
            self.i += 1
        elif not self.peek(")"):
            while True:
                self.accept("const")
                q = next((x for x in ("inout", "out", "in") if self.accept(x)), "in")
                pty = self.type_name()
                params.append(Param(q, pty.text, self.name("a parameter name").text))
                if not self.accept(","):
                    break
        self.expect(")", "')' or ','")
        if not self.peek("{"):
            self.fail("'{' (a function body; prototypes are not needed)")
        return Function(ty.line, ty.col, ty.text, name.text, params, self.block())

    def declarators(self, ty: Token, name: Token, const: bool, top: bool = False) -> list[Decl]:
        out = []
        while True:
            init = None
            if self.accept("="):
                init = self.assignment()
            elif const:
                self.fail("'=' (a const needs a value)" if top else "'='")
            out.append(Decl(name.line, name.col, ty.text, name.text, init, const))
            if not self.accept(","):
                return out
            name = self.name()

    # -- statements
    def block(self) -> list:
        open_ = self.expect("{")
        self.nest(open_)
        body = []
        while not self.accept("}"):
            if self.tok.kind == "eof":
                self.fail("'}'")
            body.extend(self.statement())
        self.depth -= 1
        return body

    def statement(self) -> list:
        tok = self.tok
        if self.peek("{"):
            return self.block()
        if self.accept(";"):
            return []
        if self.accept("if"):
            self.expect("(")
            cond = self.expression()
            self.expect(")")
            self.nest(tok)
            then = self.statement()
            other = self.statement() if self.accept("else") else []
            self.depth -= 1
            return [If(tok.line, tok.col, cond, then, other)]
        if self.accept("for"):
            self.expect("(")
            init = [] if self.accept(";") else self.simple_statement()
            cond = None if self.peek(";") else self.expression()
            self.expect(";")
            step = None if self.peek(")") else self.expression()
            self.expect(")")
            self.nest(tok)
            body = self.statement()
            self.depth -= 1
            return [For(tok.line, tok.col, init, cond, step, body)]
        if self.accept("return"):
            value = None if self.peek(";") else self.expression()
            self.expect(";")
            return [Return(tok.line, tok.col, value)]
        if tok.kind == "id" and tok.text in ("while", "do", "break", "continue", "discard", "struct", "uniform"):
            self.fail("a statement of the subset (if, for, return, a declaration or an expression)")
        return self.simple_statement()

    def simple_statement(self) -> list:
        """A declaration or an expression, with its ``;``."""
        const = bool(self.accept("const"))
        if const or (self.tok.kind == "id" and self.tok.text in TYPES and not self.peek("(", 1)):
            ty = self.type_name()
            decls = self.declarators(ty, self.name(), const)
            self.expect(";", "';' or ','")
            return decls
        tok = self.tok
        expr = self.expression()
        self.expect(";")
        return [ExprStmt(tok.line, tok.col, expr)]

    # -- expressions
    def expression(self) -> Node:
        return self.assignment()

    def assignment(self) -> Node:
        tok = self.tok
        self.nest(tok)
        left = self.ternary()
        op = self.tok
        if op.kind == "op" and op.text in _ASSIGN:
            self.i += 1
            if not _is_lvalue(left):
                self.fail("a variable or a swizzle of one on the left of " + repr(op.text), tok)
            left = Assign(op.line, op.col, op.text, left, self.assignment())
        self.depth -= 1
        return left

    def ternary(self) -> Node:
        cond = self.binary(1)
        q = self.accept("?")
        if q is None:
            return cond
        then = self.assignment()
        self.expect(":")
        return Ternary(q.line, q.col, cond, then, self.assignment())

    def binary(self, min_prec: int) -> Node:
        left = self.unary()
        depth = self.depth
        while self.tok.kind == "op" and _BINARY.get(self.tok.text, 0) >= min_prec:
            op = self.tok
            self.i += 1
            self.nest(op)  # a chain a + b + c + ... is a left-deep tree the interpreter walks recursively
            right = self.binary(_BINARY[op.text] + 1)  # left-associative
            left = Binary(op.line, op.col, op.text, left, right)
        self.depth = depth
        return left

    def unary(self) -> Node:
        tok = self.tok
        if tok.kind == "op" and tok.text in ("-", "+", "!", "++", "--"):
            self.i += 1
            self.nest(tok)
            operand = self.unary()
            self.depth -= 1
            if tok.text in ("++", "--"):
                if not _is_lvalue(operand):
                    self.fail("a variable after " + repr(tok.text), tok)
                return IncDec(tok.line, tok.col, tok.text, operand, True)
            return Unary(tok.line, tok.col, tok.text, operand)
        return self.postfix(self.primary())

    def postfix(self, expr: Node) -> Node:
        while True:
            tok = self.tok
            if self.accept("."):
                f = self.tok
                if f.kind != "id":
                    self.fail("swizzle letters (xyzw, rgba or stpq)")
                self.i += 1
                expr = Swizzle(f.line, f.col, expr, f.text)
            elif tok.kind == "op" and tok.text in ("++", "--"):
                self.i += 1
                if not _is_lvalue(expr):
                    self.fail("a variable before " + repr(tok.text), tok)
                expr = IncDec(tok.line, tok.col, tok.text, expr, False)
            elif self.accept("["):
                # A vector's component by a constant index, as BRDF Explorer's files write colour[0]: the
                # swizzle of that letter (arrays and matrices are not in the subset; the type check says so).
                k = self.tok
                text = k.text.rstrip("uU")
                if k.kind != "num" or not text.isdigit() or int(text) > 3:
                    self.fail("a constant index 0, 1, 2 or 3 (only vector components can be indexed)")
                self.i += 1
                self.expect("]")
                expr = Swizzle(k.line, k.col, expr, "xyzw"[int(text)])
            else:
                return expr

    def primary(self) -> Node:
        tok = self.tok
        if tok.kind == "num":
            self.i += 1
            text = tok.text.rstrip("fF")
            is_int = not any(c in text for c in ".eE") and not tok.text.endswith(("f", "F"))
            try:
                value = float(int(text)) if is_int else float(text)
            except (ValueError, OverflowError):
                self.fail("a number")
            return Num(tok.line, tok.col, value, "int" if is_int else "float")
        if tok.kind == "id" and tok.text in ("true", "false"):
            self.i += 1
            return Num(tok.line, tok.col, float(tok.text == "true"), "bool")
        if self.accept("("):
            self.nest(tok)
            e = self.expression()
            self.depth -= 1
            self.expect(")")
            return e
        if tok.kind == "id" and (tok.text in TYPES or tok.text not in _KEYWORDS):
            self.i += 1
            if self.accept("("):
                args = []
                if not self.peek(")"):
                    while True:
                        args.append(self.assignment())
                        if not self.accept(","):
                            break
                self.expect(")", "')' or ','")
                return Call(tok.line, tok.col, tok.text, args)
            if tok.text in TYPES:
                self.fail("'(' after a constructor's type")
            return Var(tok.line, tok.col, tok.text)
        self.fail("an expression")


def _is_lvalue(e: Node) -> bool:
    return isinstance(e, Var) or (isinstance(e, Swizzle) and _is_lvalue(e.base))


def parse(tokens: list[Token], filename: str) -> Program:
    """The tree of a shader's tokens.

    Parameters
    ----------
    tokens : list of Token
        From :func:`~lighting.files.glsl.lexer.tokenize`.
    filename : str
        For error messages.

    Returns
    -------
    Program
        Globals and functions.

    Raises
    ------
    GLSLError
        ``"FILE:LINE:COL: expected X, got Y"`` at the first token that does not fit.

    Examples
    --------
    >>> from lighting.files.glsl.lexer import tokenize
    >>> parse(tokenize("const float k = 2.0;", "f"), "f").globals[0].name
    'k'
    """
    return _Parser(tokens, filename).program()

"""Vectorised evaluation of a parsed shader: every direction pair at once, branches as masks.

A value is a NumPy array with the lanes (direction pairs) first and, for vectors, a trailing
component axis.  ``if``/``else`` and ``?:`` evaluate both sides and keep each lane's own (``np.where``
on the condition); a ``return`` inside a branch marks its lanes "returned", and later statements no
longer change them.  Loops run while any active lane's condition holds, at most
:data:`MAX_LOOP` times; calls nest at most :data:`MAX_CALLS` deep; and the whole evaluation executes at
most :data:`MAX_STEPS` statements, so no file can make the reader hang.

Where GLSL leaves a result undefined (``sqrt`` or ``log`` of a negative number, ``pow(x, y)`` with
``x < 0`` or ``x = 0, y <= 0``, ``asin``/``acos`` outside ``[-1, 1]``, ``inversesqrt(x <= 0)``,
division by zero, ``normalize`` of the zero vector, ``atan(0, 0)``), the result here is 0 rather than
NaN or infinity; defined results (``exp(1000.0) = inf``) are kept, and the loader saturates them.
"""

from __future__ import annotations

import numpy as np

from .lexer import error
from .parser import (
    TYPES,
    Assign,
    Binary,
    Call,
    Decl,
    ExprStmt,
    For,
    If,
    IncDec,
    Num,
    Return,
    Swizzle,
    Ternary,
    Unary,
    Var,
)

__all__ = ["Value", "Interpreter", "MAX_LOOP", "MAX_CALLS", "MAX_STEPS"]

MAX_LOOP = 1024
MAX_CALLS = 64
MAX_STEPS = 200_000
_VEC = {1: "float", 2: "vec2", 3: "vec3", 4: "vec4"}
_SWIZZLE_SETS = ("xyzw", "rgba", "stpq")


class Value:
    """A typed value: ``type`` in :data:`~lighting.files.glsl.parser.TYPES`, ``a`` an array (lanes first)."""

    __slots__ = ("type", "a")

    def __init__(self, type_: str, a):
        self.type, self.a = type_, a

    @property
    def size(self) -> int:
        return TYPES[self.type]


class _Frame:
    def __init__(self, n):
        self.scopes = [{}]
        self.returned = np.zeros(n, bool)
        self.result = None


class Interpreter:
    """Evaluate functions of a parsed :class:`~lighting.files.glsl.parser.Program` over ``n`` lanes.

    Parameters
    ----------
    program : Program
        The parsed shader.
    filename : str
        For error messages.
    n : int
        The number of lanes (direction pairs).
    dtype : numpy dtype
        The float dtype of every value.
    uniforms : dict of str to Value
        The parameter block's values, visible to every function.
    check : bool
        Execute every statement even where no lane is active (empty masks change nothing), so that
        type errors in code the sample directions do not reach are found too (the loader's probe).
    """

    def __init__(self, program, filename, n, dtype, uniforms, check=False):
        self.file, self.n, self.dt, self.check = filename, n, np.dtype(dtype), check
        self.functions: dict[str, list] = {}
        for f in program.functions:
            self.functions.setdefault(f.name, []).append(f)
        self.depth = 0
        self.steps = 0
        self.last = None
        self.functions_stack: list[str] = []
        self.globals = dict(uniforms)
        frame = _Frame(n)
        frame.scopes = [self.globals]
        for d in program.globals:
            self.declare(frame, d, np.ones(n, bool))

    # -- errors and helpers
    def fail(self, node, message):
        raise error(self.file, node.line, node.col, message)

    def value(self, type_, x) -> Value:
        """A value of ``type_`` in the interpreter's dtype (a built-in's result)."""
        return Value(type_, np.asarray(x, self.dt))

    def const(self, type_, x):
        return Value(type_, np.asarray(x, self.dt))

    def tick(self, node):
        self.last = node  # where a RecursionError is reported
        self.steps += 1
        if self.steps > MAX_STEPS:
            self.fail(node, f"expected at most {MAX_STEPS} statements executed per evaluation")

    def convert(self, node, value: Value, type_: str, what: str) -> Value:
        if value.type == type_:
            return value
        if value.type == "int" and type_ == "float":
            return Value("float", value.a)
        self.fail(node, f"type mismatch in {what}: expected {type_}, got {value.type}")

    def where(self, mask, new: Value, old: Value) -> Value:
        m = mask if new.size == 1 else mask[:, None]
        return Value(old.type, np.where(m, new.a, old.a).astype(self.dt, copy=False))

    # -- functions
    def call(self, name, args: list[Value], node, mask=None):
        """Call the user function ``name`` (overloads by argument types) with values; built-ins if none."""
        mask = np.ones(self.n, bool) if mask is None else mask
        f = self.resolve(name, args, node)
        if f is None:
            return None
        self.depth += 1
        if self.depth > MAX_CALLS:
            self.fail(node, f"expected calls nested at most {MAX_CALLS} deep (recursion is not allowed)")
        frame = _Frame(self.n)
        frame.scopes = [self.globals, {}]
        for p, a in zip(f.params, args, strict=True):
            a = self.convert(node, a, p.type, f"argument {p.name!r} of {name}")
            frame.scopes[-1][p.name] = a if p.qualifier != "out" else Value(p.type, np.zeros_like(a.a))
        self.functions_stack.append(f.type)
        self.block(frame, f.body, mask)
        self.functions_stack.pop()
        self.depth -= 1
        if f.type != "void" and frame.result is None:  # no lane reached a return: undefined in GLSL, 0 here
            size = TYPES[f.type]
            frame.result = Value(f.type, np.zeros((self.n,) + ((size,) if size > 1 else ()), self.dt))
        outs = [frame.scopes[1][p.name] if p.qualifier != "in" else None for p in f.params]
        result = frame.result if f.type != "void" else Value("void", None)
        return result, outs

    def resolve(self, name, args, node):
        cands = self.functions.get(name)
        if not cands:
            return None
        types = [a.type for a in args]
        for f in cands:
            if [p.type for p in f.params] == types:
                return f
        for f in cands:  # GLSL's one implicit conversion: int to float
            if len(f.params) == len(args) and all(
                p.type == t or (p.type == "float" and t == "int") for p, t in zip(f.params, types, strict=True)
            ):
                return f
        sigs = "; ".join(f"{name}(" + ", ".join(p.type for p in f.params) + ")" for f in cands)
        self.fail(node, f"expected arguments matching {sigs}, got {name}(" + ", ".join(types) + ")")

    # -- statements
    def block(self, frame, stmts, mask):
        frame.scopes.append({})
        try:
            for s in stmts:
                active = mask & ~frame.returned
                if not active.any() and not self.check:
                    break
                self.statement(frame, s, active)
        finally:
            frame.scopes.pop()

    def declare(self, frame, d: Decl, mask):
        if d.name in TYPES or d.name in frame.scopes[-1]:
            self.fail(d, f"expected a new name, got {d.name!r} declared twice in one scope")
        if d.init is None:
            value = Value(d.type, np.zeros((self.n,) + ((TYPES[d.type],) if TYPES[d.type] > 1 else ()), self.dt))
        else:
            value = self.convert(d, self.expr(frame, d.init, mask), d.type, f"the declaration of {d.name!r}")
        frame.scopes[-1][d.name] = value

    def statement(self, frame, s, mask):
        self.tick(s)
        if isinstance(s, Decl):
            self.declare(frame, s, mask)
        elif isinstance(s, ExprStmt):
            if isinstance(s.expr, Call):
                self.call_expr(frame, s.expr, mask, statement=True)
            else:
                self.expr(frame, s.expr, mask)
        elif isinstance(s, Return):
            if s.value is None:
                if self.functions_stack and self.functions_stack[-1] != "void":
                    self.fail(s, f"expected a {self.functions_stack[-1]} value after return, got ';'")
                frame.returned = frame.returned | mask
                return
            v = self.expr(frame, s.value, mask)
            if frame.result is None:
                frame.result = Value(v.type, np.zeros((self.n,) + ((v.size,) if v.size > 1 else ()), self.dt))
            elif v.type != frame.result.type:
                v = self.convert(s, v, frame.result.type, "return")
            if self.functions_stack and v.type != self.functions_stack[-1]:
                v = self.convert(s, v, self.functions_stack[-1], "return")
            frame.result = self.where(mask, v, frame.result)
            frame.returned = frame.returned | mask
        elif isinstance(s, If):
            c = self.condition(frame, s.cond, mask)
            if (mask & c).any() or self.check:
                self.block(frame, s.then, mask & c)
            if (mask & ~c).any() or self.check:
                self.block(frame, s.other, mask & ~c)
        elif isinstance(s, For):
            frame.scopes.append({})
            try:
                for d in s.init:
                    self.statement(frame, d, mask)
                live = mask.copy()
                for i in range(MAX_LOOP + 1):
                    live = live & ~frame.returned
                    if s.cond is not None:
                        live = live & self.condition(frame, s.cond, live)
                    if not live.any():
                        break
                    if i == MAX_LOOP:
                        self.fail(s, f"expected a loop that ends within {MAX_LOOP} iterations")
                    self.block(frame, s.body, live)
                    live = live & ~frame.returned
                    if s.step is not None:
                        self.expr(frame, s.step, live)
            finally:
                frame.scopes.pop()

    def condition(self, frame, node, mask):
        c = self.expr(frame, node, mask)
        if c.type != "bool":
            self.fail(node, f"type mismatch: expected a bool condition, got {c.type}")
        return np.broadcast_to(c.a != 0, (self.n,))

    # -- variables
    def lookup(self, frame, node):
        for scope in reversed(frame.scopes):
            if node.name in scope:
                return scope
        self.fail(node, f"expected a declared variable, got unknown identifier {node.name!r}")

    def swizzle_index(self, node, size):
        for letters in _SWIZZLE_SETS:
            if all(c in letters for c in node.fields) and 1 <= len(node.fields) <= 4:
                idx = [letters.index(c) for c in node.fields]
                if max(idx) < size:
                    return idx
        self.fail(node, f"expected a swizzle of a {_VEC.get(size, 'vector')} (letters from xyzw, rgba or stpq), "
                        f"got {node.fields!r}")  # fmt: skip

    def store(self, frame, target, value: Value, mask):
        """Assign ``value`` to a variable or a (nested) swizzle of one, in the lanes of ``mask``."""
        if isinstance(target, Var):
            scope = self.lookup(frame, target)
            old = scope[target.name]
            if scope is self.globals:
                self.fail(target, f"expected a local variable, got {target.name!r} (globals and parameters are const)")
            scope[target.name] = self.where(mask, self.convert(target, value, old.type, "assignment"), old)
            return
        base = self.expr(frame, target.base, mask)
        if base.size == 1:
            self.fail(target, f"expected a vector before '.', got {base.type}")
        idx = self.swizzle_index(target, base.size)
        if len(set(idx)) != len(idx):
            self.fail(target, f"expected distinct letters in a swizzle that is written, got {target.fields!r}")
        value = self.convert(target, value, _VEC[len(idx)], "swizzle assignment")
        new = np.array(np.broadcast_to(base.a, (self.n, base.size)))
        v = value.a if len(idx) > 1 else value.a[..., None]
        new[:, idx] = np.broadcast_to(v, (self.n, len(idx)))
        self.store(frame, target.base, Value(base.type, new), mask)

    # -- expressions
    def expr(self, frame, e, mask) -> Value:
        if isinstance(e, Num):
            return self.const(e.type, e.value)
        if isinstance(e, Var):
            return self.lookup(frame, e)[e.name]
        if isinstance(e, Swizzle):
            base = self.expr(frame, e.base, mask)
            if base.size == 1:
                self.fail(e, f"expected a vector before '.', got {base.type}")
            idx = self.swizzle_index(e, base.size)
            a = base.a[..., idx] if len(idx) > 1 else base.a[..., idx[0]]
            return Value(_VEC[len(idx)], a)
        if isinstance(e, Assign):
            value = self.expr(frame, e.value, mask)
            if e.op != "=":
                value = self.arith(e, e.op[0], self.expr(frame, e.target, mask), value)
            self.store(frame, e.target, value, mask)
            return value
        if isinstance(e, IncDec):
            old = self.expr(frame, e.target, mask)
            if old.type == "bool":
                self.fail(e, f"expected a number for {e.op!r}, got bool")
            new = self.arith(e, e.op[0], old, self.const("int", 1))
            self.store(frame, e.target, new, mask)
            return new if e.prefix else old
        if isinstance(e, Unary):
            v = self.expr(frame, e.operand, mask)
            if e.op == "!":
                if v.type != "bool":
                    self.fail(e, f"type mismatch: expected bool after '!', got {v.type}")
                return Value("bool", (v.a == 0).astype(self.dt))
            if v.type == "bool":
                self.fail(e, f"type mismatch: expected a number after {e.op!r}, got bool")
            return Value(v.type, -v.a if e.op == "-" else v.a)
        if isinstance(e, Ternary):
            c = self.condition(frame, e.cond, mask)
            a, b = self.expr(frame, e.then, mask & c), self.expr(frame, e.other, mask & ~c)
            if a.type != b.type:
                if {a.type, b.type} == {"int", "float"}:
                    a, b = Value("float", a.a), Value("float", b.a)
                else:
                    self.fail(e, f"type mismatch: expected both sides of ?: alike, got {a.type} and {b.type}")
            m = c if a.size == 1 else c[:, None]
            return Value(a.type, np.where(m, a.a, b.a).astype(self.dt, copy=False))
        if isinstance(e, Binary):
            if e.op in ("&&", "||", "^^"):
                a = self.expr(frame, e.left, mask)
                if a.type != "bool":
                    self.fail(e, f"type mismatch: expected bool operands of {e.op!r}, got {a.type} on the left")
                # GLSL evaluates the right side of && only where the left holds (of || where it fails):
                # side effects there happen in those lanes only.
                left = np.broadcast_to(a.a != 0, (self.n,))
                sub = mask & left if e.op == "&&" else mask & ~left if e.op == "||" else mask
                b = self.expr(frame, e.right, sub)
                if b.type != "bool":
                    self.fail(e, f"type mismatch: expected bool operands of {e.op!r}, got {a.type} and {b.type}")
                x, y = a.a != 0, b.a != 0
                r = x & y if e.op == "&&" else (x | y if e.op == "||" else x ^ y)
                return Value("bool", r.astype(self.dt))
            a, b = self.expr(frame, e.left, mask), self.expr(frame, e.right, mask)
            if e.op in ("==", "!="):
                if a.type != b.type and {a.type, b.type} != {"int", "float"}:
                    self.fail(e, f"type mismatch: expected alike operands of {e.op!r}, got {a.type} and {b.type}")
                eq = a.a == b.a
                if a.size > 1:
                    eq = eq.all(axis=-1)
                return Value("bool", (eq if e.op == "==" else ~eq).astype(self.dt))
            if e.op in ("<", ">", "<=", ">="):
                if a.size > 1 or b.size > 1 or "bool" in (a.type, b.type):
                    self.fail(e, f"type mismatch: expected scalar numbers around {e.op!r}, got {a.type} and {b.type}")
                r = {"<": np.less, ">": np.greater, "<=": np.less_equal, ">=": np.greater_equal}[e.op](a.a, b.a)
                return Value("bool", r.astype(self.dt))
            return self.arith(e, e.op, a, b)
        if isinstance(e, Call):
            return self.call_expr(frame, e, mask)
        self.fail(e, "expected an expression")  # pragma: no cover - the parser makes no other nodes

    def arith(self, node, op, a: Value, b: Value) -> Value:
        if "bool" in (a.type, b.type):
            self.fail(node, f"type mismatch: expected numbers around {op!r}, got {a.type} and {b.type}")
        if a.size > 1 and b.size > 1 and a.type != b.type:
            self.fail(node, f"type mismatch: expected alike vectors around {op!r}, got {a.type} and {b.type}")
        if op == "%":
            self.fail(node, "expected mod(x, y) for a remainder, got '%'")
        ty = a.type if a.size > 1 else b.type if b.size > 1 else ("int" if a.type == b.type == "int" else "float")
        x, y = _lift(a, ty), _lift(b, ty)
        if op == "+":
            r = x + y
        elif op == "-":
            r = x - y
        elif op == "*":
            r = x * y
        else:
            r = np.where(y != 0, x / np.where(y != 0, y, 1), 0)  # x / 0 is undefined in GLSL: 0 here
            if ty == "int":
                r = np.trunc(r)
        return Value(ty, np.asarray(r, self.dt))

    def call_expr(self, frame, e, mask, statement=False) -> Value:
        args = [self.expr(frame, a, mask) for a in e.args]
        user = self.call(e.name, args, e, mask)
        if user is not None:
            result, outs = user
            for arg_node, out in zip(e.args, outs, strict=True):
                if out is not None:
                    if not isinstance(arg_node, (Var, Swizzle)):
                        self.fail(arg_node, "expected a variable for an out/inout argument")
                    self.store(frame, arg_node, out, mask)
            if result.type == "void" and not statement:
                self.fail(e, f"expected a value, got a call of the void function {e.name!r}")
            return result
        if e.name in TYPES:
            return self.construct(e, args)
        from .builtins import BUILTINS

        fn = BUILTINS.get(e.name)
        if fn is None:
            self.fail(e, f"expected a known function, got unknown identifier {e.name!r}")
        return fn(self, e, args)

    def construct(self, e, args) -> Value:
        size = TYPES[e.name]
        if size == 1:
            if len(args) != 1:
                self.fail(e, f"expected 1 argument to {e.name}, got {len(args)}")
            x = args[0].a if args[0].size == 1 else args[0].a[..., 0]
            if e.name == "bool":
                return Value("bool", (x != 0).astype(self.dt))
            return Value(e.name, np.trunc(x) if e.name == "int" else x)
        if len(args) == 1 and args[0].size == 1:
            return Value(e.name, np.repeat(np.asarray(args[0].a)[..., None], size, axis=-1))
        parts = [a.a[..., None] if a.size == 1 else a.a for a in args]
        total = sum(a.size for a in args)
        if total < size or (args and total - args[-1].size >= size):
            self.fail(e, f"expected {size} components in {e.name}(...), got {total}")
        shape = np.broadcast_shapes(*(p.shape[:-1] for p in parts))
        joined = np.concatenate([np.broadcast_to(p, shape + p.shape[-1:]) for p in parts], axis=-1)
        return Value(e.name, joined[..., :size].astype(self.dt, copy=False))


def _lift(v: Value, ty: str):
    """A scalar's array given a trailing axis where it meets a vector."""
    return v.a[..., None] if v.size == 1 and TYPES[ty] > 1 else v.a

"""The GLSL built-in functions of the subset, with GLSL's semantics over NumPy arrays.

Component-wise functions take scalars or vectors and broadcast a scalar argument against a vector
one (as GLSL's ``genType``/``float`` overloads do).  Where GLSL leaves a result undefined the value is
0 (see :mod:`lighting.files.glsl.interpret`).
"""

from __future__ import annotations

import numpy as np

from .parser import TYPES

__all__ = ["BUILTINS"]


def _defined(cond, value):
    """``value`` where ``cond`` (GLSL defines the result), else 0."""
    return np.where(cond, value, 0)


def _componentwise(fn, arity, undefined=None):
    def call(it, node, args):
        _arity(it, node, args, arity)
        ty = _common(it, node, args)
        xs = [a.a[..., None] if a.size == 1 and TYPES[ty] > 1 else a.a for a in args]
        with np.errstate(all="ignore"):
            r = fn(*xs)
            if undefined is not None:
                r = _defined(~undefined(*xs), r)
        return it.value(ty, r)

    return call


def _arity(it, node, args, counts):
    counts = (counts,) if isinstance(counts, int) else counts
    if len(args) not in counts:
        want = " or ".join(map(str, counts))
        it.fail(node, f"expected {want} argument{'s' if counts != (1,) else ''} to {node.name}, got {len(args)}")


def _common(it, node, args, vectors_only=False):
    types = [a.type for a in args]
    if "bool" in types:
        it.fail(node, f"type mismatch: expected numbers in {node.name}(...), got " + ", ".join(types))
    vec = {t for t in types if TYPES[t] > 1}
    if len(vec) > 1:
        it.fail(node, f"type mismatch: expected alike vectors in {node.name}(...), got " + ", ".join(types))
    if vectors_only and (len(vec) != 1 or any(TYPES[t] == 1 for t in types)):
        it.fail(node, f"type mismatch: expected vectors of one size in {node.name}(...), got " + ", ".join(types))
    return vec.pop() if vec else "float"


def _dot(it, node, args):
    _arity(it, node, args, 2)
    _common(it, node, args)
    if args[0].type != args[1].type:
        it.fail(node, f"type mismatch: expected alike arguments to dot, got {args[0].type} and {args[1].type}")
    a, b = args[0].a, args[1].a
    return it.value("float", (a * b).sum(axis=-1) if args[0].size > 1 else a * b)


def _length(it, node, args):
    _arity(it, node, args, 1)
    _common(it, node, args)
    a = args[0].a
    return it.value("float", np.sqrt((a * a).sum(axis=-1)) if args[0].size > 1 else np.abs(a))


def _normalize(it, node, args):
    _arity(it, node, args, 1)
    ty = _common(it, node, args)
    a = args[0].a
    if args[0].size == 1:
        return it.value(ty, np.sign(a))
    n = np.sqrt((a * a).sum(axis=-1, keepdims=True))
    with np.errstate(all="ignore"):
        return it.value(ty, _defined(n > 0, a / np.where(n > 0, n, 1)))  # normalize(0) is undefined: 0


def _cross(it, node, args):
    _arity(it, node, args, 2)
    if args[0].type != "vec3" or args[1].type != "vec3":
        it.fail(node, f"type mismatch: expected vec3, vec3 in cross, got {args[0].type} and {args[1].type}")
    return it.value("vec3", np.cross(args[0].a, args[1].a))


def _reflect(it, node, args):
    _arity(it, node, args, 2)
    ty = _common(it, node, args, vectors_only=True)
    i, n = args[0].a, args[1].a
    return it.value(ty, i - 2 * (i * n).sum(axis=-1, keepdims=True) * n)  # GLSL: I - 2 dot(N, I) N


def _atan(it, node, args):
    _arity(it, node, args, (1, 2))
    ty = _common(it, node, args)
    xs = [a.a[..., None] if a.size == 1 and TYPES[ty] > 1 else a.a for a in args]
    if len(xs) == 1:
        return it.value(ty, np.arctan(xs[0]))
    y, x = xs
    return it.value(ty, _defined((x != 0) | (y != 0), np.arctan2(y, x)))  # atan(0, 0) is undefined


def _clamp(x, lo, hi):
    return np.minimum(np.maximum(x, lo), hi)


def _smoothstep(e0, e1, x):
    t = _clamp((x - e0) / (e1 - e0), 0, 1)
    return t * t * (3 - 2 * t)


BUILTINS = {
    "dot": _dot,
    "cross": _cross,
    "normalize": _normalize,
    "length": _length,
    "reflect": _reflect,
    "atan": _atan,
    "pow": _componentwise(np.power, 2, lambda x, y: (x < 0) | ((x == 0) & (y <= 0))),
    "exp": _componentwise(np.exp, 1),
    "exp2": _componentwise(np.exp2, 1),
    "log": _componentwise(np.log, 1, lambda x: x <= 0),
    "log2": _componentwise(np.log2, 1, lambda x: x <= 0),
    "sqrt": _componentwise(np.sqrt, 1, lambda x: x < 0),
    "inversesqrt": _componentwise(lambda x: 1 / np.sqrt(x), 1, lambda x: x <= 0),
    "sin": _componentwise(np.sin, 1),
    "cos": _componentwise(np.cos, 1),
    "tan": _componentwise(np.tan, 1),
    "asin": _componentwise(np.arcsin, 1, lambda x: np.abs(x) > 1),
    "acos": _componentwise(np.arccos, 1, lambda x: np.abs(x) > 1),
    "min": _componentwise(np.minimum, 2),
    "max": _componentwise(np.maximum, 2),
    "clamp": _componentwise(_clamp, 3),
    "mix": _componentwise(lambda x, y, a: x * (1 - a) + y * a, 3),
    "step": _componentwise(lambda e, x: np.where(x < e, 0.0, 1.0), 2),
    "smoothstep": _componentwise(_smoothstep, 3, lambda e0, e1, x: e0 >= e1),
    "abs": _componentwise(np.abs, 1),
    "sign": _componentwise(np.sign, 1),
    "floor": _componentwise(np.floor, 1),
    "ceil": _componentwise(np.ceil, 1),
    "fract": _componentwise(lambda x: x - np.floor(x), 1),
    "mod": _componentwise(lambda x, y: x - y * np.floor(x / y), 2, lambda x, y: y == 0),
    "radians": _componentwise(np.radians, 1),
    "degrees": _componentwise(np.degrees, 1),
}

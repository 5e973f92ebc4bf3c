r"""BRDF Explorer's analytic ``.brdf`` files, read into a NumPy evaluator (nothing in them runs as Python).

A file (Disney's BRDF Explorer, 2012):

    # comments outside the shader start with '#'
    analytic

    ::begin parameters
    float n 1 1000 100          # name, min, max, default
    bool normalized 1           # name, default (0 or 1)
    color Kd 0.8 0.2 0.1        # name, r, g, b
    ::end parameters

    ::begin shader
    vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)
    {
        ...                     // GLSL; returns f_r (BRDF Explorer multiplies by n·l itself)
    }
    ::end shader

The shader is read by :mod:`lighting.files.glsl` (a lexer, a parser and a vectorised interpreter of a
GLSL subset; see ``docs/brdf-files.md``).  ``load(path, **params)`` returns a :class:`FileBRDF`, a
BRDF like the built-in ones: ``eval`` gives ``f_r`` in 1/sr, zero below the horizon.
"""

from __future__ import annotations

import math
import os
import re

import numpy as np

from .._budget import check_budget, memory_budget
from ..models.base import BRDF, BRDFFlags
from ..models.protocol import Parameter
from ..numerics import saturate_to
from .glsl import Interpreter, Value, parse, tokenize
from .glsl.lexer import error

__all__ = ["FileBRDF", "load", "MAX_FILE_BYTES"]

#: The largest file read (checked with ``os.stat`` before reading).
MAX_FILE_BYTES = 1 << 20
#: Lanes evaluated at once: memory is bounded per chunk, whatever the number of direction pairs.
CHUNK = 1 << 14
_NAME = re.compile(r"[A-Za-z_][A-Za-z_0-9]*\Z")
_SIGNATURE = ["vec3"] * 5


def _number(filename, lineno, col, text, what):
    try:
        x = float(text)
    except ValueError:
        x = math.nan
    if not math.isfinite(x):
        raise error(filename, lineno, col, f"expected a finite number for {what}, got {text!r}")
    return x


def _columns(line: str):
    """The words of a line and their 1-based columns, up to a ``#`` comment."""
    line = line.split("#", 1)[0]
    return [(m.group(), m.start() + 1) for m in re.finditer(r"\S+", line)]


def parse_file(text: str, filename: str):
    """The parameter table and the shader of a ``.brdf`` file's text.

    Parameters
    ----------
    text : str
        The file's contents.
    filename : str
        For error messages.

    Returns
    -------
    parameters : list of Parameter
        In the file's order.
    shader : str
        The shader block's text.
    first_line : int
        The file line the shader starts on.

    Raises
    ------
    ValueError
        ``"FILE:LINE:COL: expected X, got Y"``: a line outside the blocks that is not ``analytic``, a
        comment or blank; an unterminated block; a malformed parameter line; a missing shader.

    Examples
    --------
    >>> params, shader, first = parse_file("analytic\\n::begin parameters\\nfloat k 0 1 0.5\\n::end parameters\\n"
    ...                                    "::begin shader\\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)"
    ...                                    "{ return vec3(k); }\\n::end shader\\n", "f.brdf")
    >>> params[0].name, params[0].default, first
    ('k', 0.5, 6)
    """
    lines = text.split("\n")
    params, shader, first_line = [], None, 0
    i = 0
    while i < len(lines):
        raw = lines[i]
        stripped = raw.strip()
        lineno = i + 1
        col = len(raw) - len(raw.lstrip()) + 1
        if not stripped or stripped.startswith("#") or stripped == "analytic":
            i += 1
            continue
        words = stripped.split()
        if words[0] == "::begin" and len(words) == 2 and words[1] in ("parameters", "shader"):
            block = words[1]
            end = next((j for j in range(i + 1, len(lines)) if lines[j].split() == ["::end", block]), None)
            if end is None:
                raise error(filename, lineno, col, f"expected '::end {block}' closing this block, got end of file")
            if block == "shader":
                if shader is not None:
                    raise error(filename, lineno, col, "expected one shader block, got a second")
                shader, first_line = "\n".join(lines[i + 1 : end]), i + 2
            else:
                for j in range(i + 1, end):
                    p = _parameter(lines[j], j + 1, filename, params)
                    if p is not None:
                        params.append(p)
            i = end + 1
            continue
        raise error(filename, lineno, col, f"expected 'analytic', '::begin parameters', '::begin shader', a '#' "
                                           f"comment or a blank line, got {stripped[:40]!r}")  # fmt: skip
    if shader is None:
        raise error(filename, len(lines), 1, "expected a '::begin shader' block, got end of file")
    return params, shader, first_line


def _parameter(line, lineno, filename, params):
    words = _columns(line)
    if not words:
        return None
    kind, col = words[0]
    counts = {"float": 5, "bool": 3, "color": 5}
    if kind not in counts:
        raise error(filename, lineno, col, f"expected a parameter line (float, bool or color), got {kind!r}")
    if len(words) != counts[kind]:
        form = {"float": "float NAME MIN MAX DEFAULT", "bool": "bool NAME DEFAULT", "color": "color NAME R G B"}[kind]
        raise error(filename, lineno, col, f"expected '{form}', got {len(words)} words")
    name, ncol = words[1]
    if not _NAME.match(name) or name in ("BRDF", "L", "V", "N", "X", "Y"):
        raise error(filename, lineno, ncol, f"expected a GLSL name other than BRDF, L, V, N, X, Y, got {name!r}")
    if any(p.name == name for p in params):
        raise error(filename, lineno, ncol, f"expected a new parameter name, got {name!r} twice")
    nums = [_number(filename, lineno, c, t, f"{name}") for t, c in words[2:]]
    if kind == "float":
        lo, hi, default = nums
        if not lo <= default <= hi:
            raise error(filename, lineno, words[4][1], f"expected MIN <= DEFAULT <= MAX for {name}, got "
                                                       f"{lo:g} {hi:g} {default:g}")  # fmt: skip
        return Parameter(name, "float", default, lo, hi)
    if kind == "bool":
        if nums[0] not in (0.0, 1.0):
            raise error(filename, lineno, words[2][1], f"expected 0 or 1 for {name}, got {words[2][0]!r}")
        return Parameter(name, "bool", bool(nums[0]))
    if min(nums) < 0:
        raise error(
            filename, lineno, ncol, f"expected r, g, b >= 0 for {name}, got {' '.join(t for t, _ in words[2:])}"
        )
    return Parameter(name, "color", tuple(nums))


class FileBRDF(BRDF):
    """A BRDF defined by a ``.brdf`` file's shader, evaluated by the GLSL interpreter.

    Made by :func:`load`; ``parameters`` is the file's parameter block, ``values`` the values in use.

    Parameters
    ----------
    filename : str
        The file (for messages).
    program : lighting.files.glsl.parser.Program
        The parsed shader.
    parameters : tuple of Parameter
        The file's parameter table.
    values : dict
        Name → value (float, bool or an RGB tuple) for every parameter.
    """

    name = None
    flags = BRDFFlags.SPECULAR | BRDFFlags.OWN_DIFFUSE  # the whole material, as in BRDF Explorer: no Lambert term added

    def __init__(self, filename, program, parameters, values):
        self.filename, self.program = filename, program
        self.parameters = tuple(parameters)
        self.values = dict(values)
        self._size = sum(1 for _ in _walk(program))

    def __getattr__(self, name):
        values = self.__dict__.get("values")
        if values is not None and name in values:  # the parameters read as attributes, as a built-in model's
            return values[name]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def _params(self):
        return dict(self.values)

    def __repr__(self):
        return (
            f"FileBRDF({os.path.basename(self.filename)!r}, "
            + ", ".join(f"{k}={v!r}" for k, v in self.values.items())
            + ")"
        )

    def summary(self):
        """See :meth:`BRDF.summary`.

        Returns
        -------
        str
            ``"file.brdf: name=value, ..."``.
        """
        return os.path.basename(self.filename) + ": " + ", ".join(f"{k}={v}" for k, v in self.values.items())

    def _uniforms(self, dt):
        out = {}
        for p in self.parameters:
            v = self.values[p.name]
            if p.kind == "color":
                out[p.name] = Value("vec3", np.asarray(v, dt))
            else:
                out[p.name] = Value("bool" if p.kind == "bool" else "float", np.asarray(float(v), dt))
        return out

    def run(self, l, v, n, x, y, dt, check=False):  # noqa: E741
        """``BRDF(L, V, N, X, Y)`` over rows of unit vectors ``(M, 3)``: the shader's raw RGB result.

        Parameters
        ----------
        l, v, n, x, y : ndarray, shape (M, 3)
            Light, view, normal, tangent, bitangent.
        dt : numpy dtype
            The float dtype of the evaluation.
        check : bool
            Execute every statement whether or not a lane reaches it (finds type errors everywhere).

        Returns
        -------
        ndarray, shape (M, 3)
            What the shader returns (not yet clipped to the horizon or to finite values).
        """
        m = l.shape[0]
        # Each AST node may hold one live (lanes, 4) temporary: that bounds a chunk's memory.
        per_lane = max(1, self._size) * 4 * np.dtype(dt).itemsize * 2
        chunk = int(max(1, min(CHUNK, memory_budget() // (4 * per_lane))))
        check_budget("FileBRDF lanes", chunk * per_lane, what=f"{self._size} shader nodes")
        out = np.empty((m, 3), dt)
        for s in range(0, m, chunk):
            e = min(m, s + chunk)
            it = Interpreter(self.program, self.filename, e - s, dt, self._uniforms(dt), check)
            args = [Value("vec3", a[s:e]) for a in (l, v, n, x, y)]
            try:
                with np.errstate(all="ignore"):
                    result, _ = it.call("BRDF", args, _main(self.program))
            except RecursionError:  # nesting within the parser's bounds, times calls within theirs
                at = it.last or _main(self.program)
                raise error(
                    self.filename, at.line, at.col, "expected less deeply nested expressions and calls"
                ) from None
            out[s:e] = np.broadcast_to(result.a, (e - s, 3))
        return out

    def _f(self, g):
        dt = g.dtype
        shape = np.broadcast_shapes(g.n.shape, g.l.shape, g.v.shape)
        rows = [np.ascontiguousarray(np.broadcast_to(a, shape)).reshape(-1, 3) for a in (g.l, g.v, g.n, g.t, g.b)]
        f = self.run(*rows, dt).reshape(shape)
        f = np.where(np.isfinite(f) | (f > 0), f, 0)  # NaN and -inf: 0; +inf saturates below
        f = np.where(g.above[..., None], np.maximum(f, 0), 0)
        return saturate_to(f, dt)

    def _f_cos(self, g):
        with np.errstate(over="ignore"):
            return saturate_to(self._f(g) * np.maximum(g.n_dot_l, 0)[..., None], g.dtype)


def _walk(node):
    """Every node of a parsed tree (for the memory estimate)."""
    stack = [node]
    while stack:
        x = stack.pop()
        yield x
        if isinstance(x, list):
            stack.extend(x)
        elif hasattr(x, "__dataclass_fields__"):
            stack.extend(getattr(x, f) for f in x.__dataclass_fields__ if not isinstance(getattr(x, f), str | float))


def _main(program):
    return next(f for f in program.functions if f.name == "BRDF")


def load(path, **params):
    """A :class:`FileBRDF` from a ``.brdf`` file; keyword arguments set the file's parameters.

    Parameters
    ----------
    path : str or os.PathLike
        The file (at most :data:`MAX_FILE_BYTES`, UTF-8 text).
    **params
        Parameter values by name: a number for ``float`` (within the file's range), ``True``/``False``
        for ``bool``, a scalar or an RGB triple for ``color``.

    Returns
    -------
    FileBRDF
        ``eval`` gives the shader's ``BRDF(L, V, N, X, Y)`` (``f_r``), 0 below the horizon.

    Raises
    ------
    ValueError
        One error naming the file and the place: a file too large or not text, a malformed block or
        parameter line, GLSL outside the subset, a type error, a missing ``vec3 BRDF(vec3 L, vec3 V,
        vec3 N, vec3 X, vec3 Y)``; or an unknown parameter name (listing the file's) or a value out
        of range.

    Notes
    -----
    The shader is checked at load time by evaluating it once on a few direction pairs: the
    interpreter evaluates both sides of every branch, so type errors anywhere but in a loop body
    that never runs are found then.  Where GLSL leaves a result undefined the interpreter gives 0
    (see :mod:`lighting.files.glsl.interpret`); the loader then maps NaN to 0, clamps negative
    values to 0 and saturates infinities at the dtype's largest number.

    References
    ----------
    Walt Disney Animation Studios, *BRDF Explorer* (2012), https://github.com/wdas/brdf.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (d / "lambert.brdf").write_text(
    ...     "analytic\\n::begin parameters\\ncolor kd 0.5 0.5 0.5\\n::end parameters\\n::begin shader\\n"
    ...     "vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return kd / 3.14159265358979; }\\n::end shader\\n")
    >>> load(d / "lambert.brdf", kd=(1.0, 0.5, 0.25)).eval((0, 0, 1.0), (0, 0, 1.0), (0, 0, 1.0)).round(4).tolist()
    [0.3183, 0.1592, 0.0796]
    """
    filename = os.fspath(path)
    return from_text(_read_text(filename), filename, **params)


def _read_text(filename: str) -> str:
    """The file's text: a regular file of at most :data:`MAX_FILE_BYTES` bytes of UTF-8."""
    try:
        size = os.stat(filename).st_size
        if not os.path.isfile(filename):
            raise ValueError(f"{filename}: expected a regular file")
    except OSError as exc:
        raise ValueError(f"{filename}: cannot read the file ({exc.strerror})") from None
    if size > MAX_FILE_BYTES:
        raise ValueError(f"{filename}: expected at most {MAX_FILE_BYTES} bytes, got {size}")
    with open(filename, "rb") as fh:
        data = fh.read(MAX_FILE_BYTES + 1)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ValueError(
            f"{filename}: byte {exc.start}: expected UTF-8 text, got byte 0x{data[exc.start]:02x}"
        ) from None


def from_text(text: str, filename: str = "<string>", **params) -> FileBRDF:
    """A :class:`FileBRDF` from a ``.brdf`` file's text (what :func:`load` calls after reading).

    Parameters
    ----------
    text : str
        The file's contents.
    filename : str
        The name errors give.
    **params
        As :func:`load`.

    Returns
    -------
    FileBRDF
        The model.

    Examples
    --------
    >>> src = ("::begin shader\\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)"
    ...        " { return vec3(dot(N, L) > 0.5 ? 1.0 : 0.0); }\\n::end shader\\n")
    >>> from_text(src).eval((0, 0, 1.0), (0, 0, 1.0), (0, 0, 1.0)).tolist()
    [1.0, 1.0, 1.0]
    """
    table, program = _compile(text, filename)
    brdf = FileBRDF(filename, program, table, _values(filename, table, params))
    _probe(brdf)
    return brdf


def _compile(text: str, filename: str):
    """The parameter table and the parsed shader of a file's text, its ``BRDF`` function checked."""
    table, shader, first = parse_file(text, filename)
    program = parse(tokenize(shader, filename, first), filename)
    mains = [f for f in program.functions if f.name == "BRDF"]
    if not mains:
        raise error(filename, first, 1, "expected a function vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y), "
                                        "got none")  # fmt: skip
    ok = [f for f in mains if f.type == "vec3" and [p.type for p in f.params] == _SIGNATURE]
    if not ok or any(p.qualifier != "in" for p in ok[0].params):
        f = mains[0]
        got = f"{f.type} BRDF(" + ", ".join(f"{p.qualifier} {p.type}" for p in f.params) + ")"
        raise error(filename, f.line, f.col, f"expected vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y), got {got}")
    return table, program


def _values(filename, table, params) -> dict:
    """Every parameter's value: the file's defaults, then ``params`` by name, each checked."""
    values = {p.name: p.default for p in table}
    names = {p.name: p for p in table}
    for key, value in params.items():
        if key not in names:
            listed = ", ".join(names) or "(none)"
            raise ValueError(f"{filename}: unknown parameter {key!r}; the file's parameters are {listed}")
        values[key] = _checked(filename, names[key], value)
    return values


def model_class(path) -> type:
    """A model class from a ``.brdf`` file: read and parsed once, each instance setting the parameters.

    What :func:`lighting.files.file_model` calls for ``.brdf`` files.

    Parameters
    ----------
    path : str or os.PathLike
        The file (as :func:`load`).

    Returns
    -------
    type
        A :class:`FileBRDF` subclass whose ``parameters`` are the file's block; ``cls(**values)``
        checks the values as :func:`load` does, and shares the parsed shader.

    Raises
    ------
    ValueError
        As :func:`load`.
    """
    filename = os.fspath(path)
    table, program = _compile(_read_text(filename), filename)
    _probe(FileBRDF(filename, program, table, _values(filename, table, {})))

    def __init__(self, **values):
        FileBRDF.__init__(self, filename, program, table, _values(filename, table, values))

    return type("BRDFFileModel", (FileBRDF,), {"parameters": tuple(table), "__init__": __init__,
                                                "__doc__": f"The model of {filename!r}."})  # fmt: skip


def _checked(filename, p: Parameter, value):
    if p.kind == "bool":
        if not isinstance(value, bool | np.bool_):
            raise ValueError(f"{filename}: parameter {p.name!r} must be True or False; got {value!r}")
        return bool(value)
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        arr = np.array(math.nan)
    if p.kind == "color":
        if arr.shape == ():
            arr = np.repeat(arr, 3)
        if arr.shape != (3,) or not np.isfinite(arr).all() or (arr < 0).any():
            raise ValueError(
                f"{filename}: parameter {p.name!r} must be a finite scalar or RGB triple >= 0; got {value!r}"
            )
        return tuple(float(x) for x in arr)
    if arr.shape != () or not (p.low <= float(arr) <= p.high):
        raise ValueError(f"{filename}: parameter {p.name!r} must be a number in [{p.low:g}, {p.high:g}]; got {value!r}")
    return float(arr)


def _probe(brdf: FileBRDF):
    """Evaluate the shader on a few direction pairs so that errors show at load time."""
    z = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, -0.8, 0.6]])
    x = np.array([[1.0, 0.0, 0.0]] * 3)
    y = np.array([[0.0, 1.0, 0.0]] * 3)
    brdf.run(z, z[::-1].copy(), np.repeat(z[:1], 3, axis=0), x, y, np.float64, check=True)

"""Wavefront OBJ files read with NumPy alone: positions, texture coordinates, normals and polygon faces.

:func:`~lighting.render.mesh.load_mesh` reads ``.obj`` files here, so that a scene with an OBJ mesh
needs neither trimesh nor its long import; the other formats still go through trimesh.

What is read
------------
``v x y z [w]`` (a trailing ``w`` or a vertex colour ``r g b`` is ignored), ``vt u [v [w]]``,
``vn x y z``, and ``f`` with corners ``i``, ``i/t``, ``i//n`` or ``i/t/n`` (1-based; negative indices
count back from the last element defined so far, as the format says).  A polygon of ``k`` corners
becomes the fan of ``k − 2`` triangles ``(c₀, c_j, c_{j+1})``.  Lines ``o``, ``g``, ``s``, ``usemtl``,
``mtllib``, ``l``, ``p``, comments and blank lines are skipped; so is any other keyword (the format
has many, none of which changes the triangles).

Vertices
--------
When each position is used with one texture coordinate and one normal at most (or none), the vertices
are the positions, in file order.  Otherwise a mesh vertex is one distinct corner ``(position, texture
coordinate, normal)``, numbered in the order of first use, as trimesh does with ``process=False``:
a position used with two normals becomes two vertices (the cube's sharp edges).  If some corners lack
a normal (or a texture coordinate), the file's normals (or coordinates) are not used at all and the
mesh computes its own.

Errors
------
A file is untrusted input: every problem is one ``ValueError`` naming the file and the line, e.g.
``mesh file 'a.obj' could not be read as OBJ: line 12: face position index 9 out of range (8 positions
defined)``.
"""

from __future__ import annotations

import numpy as np

from .._text import abbreviate

__all__ = ["read_obj"]

_SKIPPED = frozenset({"o", "g", "s", "usemtl", "mtllib", "l", "p", "vp", "cstype", "deg", "curv", "surf"})


def _fail(name: str, lineno: int, detail: str):
    raise ValueError(f"mesh file {name} could not be read as OBJ: line {lineno}: {detail}")


def _numbers(name, lineno, tokens, key, low, high):
    if not low <= len(tokens) <= high:
        want = f"{low}" if low == high else f"{low} to {high}"
        _fail(name, lineno, f"'{key}' takes {want} numbers; got {len(tokens)}")
    try:
        return [float(t) for t in tokens]
    except ValueError:
        _fail(name, lineno, f"'{key}' takes numbers; got {abbreviate(' '.join(tokens))!r}")


def _index(name, lineno, text, count, what):
    try:
        i = int(text)
    except ValueError:
        _fail(name, lineno, f"a face corner's {what} index must be an integer; got {abbreviate(text)!r}")
    j = i - 1 if i > 0 else count + i
    if i == 0 or not 0 <= j < count:
        _fail(name, lineno, f"face {what} index {i} out of range ({count} {what}s defined)")
    return j


def read_obj(path, text: str | None = None):
    """The triangles of an OBJ file: positions, faces, and normals and texture coordinates when given.

    Parameters
    ----------
    path : str or os.PathLike
        The file (its name is used in messages; read as UTF-8, undecodable bytes replaced).
    text : str, optional
        The file's text, if already read.

    Returns
    -------
    vertices : ndarray, float64, shape (V, 3)
        The positions in file order, or one per distinct corner (module notes).
    faces : ndarray, int64, shape (F, 3)
        Triangles (polygons fanned from their first corner).
    normals : ndarray, float64, shape (V, 3), or None
        The file's normals at the vertices (as written: not normalized), when every corner has one.
    uvs : ndarray, float64, shape (V, 2), or None
        Texture coordinates, when every corner has one.

    Raises
    ------
    ValueError
        Naming the file and the line: a malformed number, a face with fewer than 3 corners, an index
        that is 0 or out of range; or a file with no face.

    Examples
    --------
    >>> import os, tempfile
    >>> p = os.path.join(tempfile.mkdtemp(), "quad.obj")
    >>> with open(p, "w") as f:
    ...     _ = f.write("v 0 0 0\\nv 1 0 0\\nv 1 1 0\\nv 0 1 0\\nf 1 2 3 4\\n")
    >>> v, f, n, uv = read_obj(p)
    >>> f.tolist(), n is None, uv is None
    ([[0, 1, 2], [0, 2, 3]], True, True)
    """
    name = abbreviate(repr(str(path)))
    if text is None:
        with open(path, "rb") as fh:
            text = fh.read().decode("utf-8", errors="replace")
    positions: list[list[float]] = []
    coords: list[list[float]] = []
    normals: list[list[float]] = []
    corners: dict[tuple[int, int, int], int] = {}
    faces: list[tuple[int, int, int]] = []
    for lineno, line in enumerate(text.splitlines(), 1):
        tokens = line.split("#", 1)[0].split()
        if not tokens:
            continue
        key, rest = tokens[0], tokens[1:]
        if key == "v":
            positions.append(_numbers(name, lineno, rest, "v", 3, 7)[:3])
        elif key == "vt":
            coords.append((_numbers(name, lineno, rest, "vt", 1, 3) + [0.0])[:2])
        elif key == "vn":
            normals.append(_numbers(name, lineno, rest, "vn", 3, 3))
        elif key == "f":
            if len(rest) < 3:
                _fail(name, lineno, f"a face needs at least 3 corners; got {len(rest)}")
            ids = []
            for corner in rest:
                parts = corner.split("/")
                if len(parts) > 3:
                    _fail(name, lineno, f"a face corner is i, i/t, i//n or i/t/n; got {abbreviate(corner)!r}")
                vi = _index(name, lineno, parts[0], len(positions), "position")
                has_t, has_n = len(parts) > 1 and parts[1], len(parts) > 2 and parts[2]
                ti = _index(name, lineno, parts[1], len(coords), "texture coordinate") if has_t else -1
                ni = _index(name, lineno, parts[2], len(normals), "normal") if has_n else -1
                ids.append(corners.setdefault((vi, ti, ni), len(corners)))
            faces.extend((ids[0], ids[j], ids[j + 1]) for j in range(1, len(ids) - 1))
        elif key not in _SKIPPED and not key.isidentifier():
            _fail(name, lineno, f"expected a keyword (v, vt, vn, f, ...); got {abbreviate(key)!r}")
    if not positions:
        raise ValueError(f"mesh file {name} contains no geometry (empty or unreadable OBJ: no 'v' line)")
    if not faces:
        raise ValueError(f"mesh file {name} contains no triangles (no 'f' line)")
    keys = np.array(list(corners), dtype=np.int64).reshape(-1, 3)
    pos = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
    if len(np.unique(keys[:, 0])) == len(keys):  # one corner per position: the file's vertices, in its order
        per = np.full((len(pos), 3), -1, dtype=np.int64)
        per[keys[:, 0]] = keys
        used = per[:, 0] >= 0
        vn = vt = None
        if normals and (per[used, 2] >= 0).all():
            vn = np.zeros_like(pos)  # an unused position keeps a zero normal, as an isolated vertex does
            vn[used] = np.asarray(normals, dtype=np.float64)[per[used, 2]]
        if coords and (per[used, 1] >= 0).all():
            vt = np.zeros((len(pos), 2))
            vt[used] = np.asarray(coords, dtype=np.float64)[per[used, 1]]
        return pos, keys[np.asarray(faces), 0], vn, vt
    vertices = pos[keys[:, 0]]
    vn = np.asarray(normals, dtype=np.float64)[keys[:, 2]] if normals and (keys[:, 2] >= 0).all() else None
    uv = np.asarray(coords, dtype=np.float64)[keys[:, 1]] if coords and (keys[:, 1] >= 0).all() else None
    return vertices, np.asarray(faces, dtype=np.int64).reshape(-1, 3), vn, uv

"""Triangle meshes: normals, sphere generators and file loading.

A :class:`TriangleMesh` is an indexed triangle list: ``vertices`` ``(V, 3)``
float64, ``faces`` ``(F, 3)`` int64 (counter-clockwise seen from outside, so the
right-hand rule gives the outward normal), and per-vertex unit ``normals``
``(V, 3)``.

Normals
-------
Face normal of triangle ``(p0, p1, p2)``: ``n_f = (p1 - p0) × (p2 - p0) / |…|``,
and ``|(p1 - p0) × (p2 - p0)| / 2`` is its area.  A vertex normal is a weighted
sum of the unit normals of the faces around the vertex, normalized:

* ``"angle"`` (the default): weight = the face's interior angle at the vertex
  (Thürmer & Wüthrich, "Computing vertex normals from polygonal facets",
  JGT 3(1), 1998).  It depends only on the surface, not on how it is
  triangulated: splitting a face into several changes nothing.  On a cube corner
  it gives ``(1, 1, 1)/√3`` whatever the diagonals.  It is the common best
  default, hence ours.
* ``"area"``: weight = the face's area (the plain sum of the unnormalized cross
  products, Gouraud's mean with large faces counting more).  Cheap and smooth
  on evenly tessellated meshes but biased by long thin triangles.

Zero-area triangles have a zero face normal and zero weight: they are kept
(face indices stay those of the file) and are harmless everywhere, the
rasterizer covers no pixel with them.  A vertex whose weighted sum vanishes
(two faces back to back) takes the normal of its largest incident face; a vertex
with no non-degenerate face (isolated) keeps the zero normal.  No NaN anywhere.

Tangents
--------
Per-vertex unit ``tangents`` ``(V, 3)`` perpendicular to the normals orient anisotropic
models: given (the spheres: ``∂p/∂φ`` about their polar axis ``+y``), else along ``∂p/∂u``
from texture coordinates ``uvs``, else the models' default frame (:mod:`lighting.render.tangents`).

Examples
--------
>>> m = icosphere(2)
>>> m.n_triangles, len(m.vertices)
(320, 162)
>>> round(4 * np.pi - m.area, 3)  # the inscribed polyhedron falls short of 4π
0.237
"""

from __future__ import annotations

import math
import os
import stat

import numpy as np

from .._budget import BudgetError, check_budget
from .._text import abbreviate, quote_path
from .._validate import check_choice, check_count, check_positive
from ..vec import normalize
from .obj import read_obj
from .tangents import default_tangents, orthonormal_tangents, sphere_tangents, uv_tangents

__all__ = [
    "TriangleMesh",
    "uv_sphere",
    "icosphere",
    "sphere_for_triangles",
    "load_mesh",
]


def _readonly(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a


def _as_points(name: str, value, shape_text: str) -> np.ndarray:
    try:
        a = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be {shape_text} of finite numbers; got {value!r}") from None
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{name} must be {shape_text}; got shape {a.shape}")
    bad = ~np.isfinite(a).all(axis=1)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"{name} must be finite; {int(bad.sum())} of {len(a)} rows are not (first: row {i} = {a[i].tolist()})"
        )
    return a


class TriangleMesh:
    """An indexed triangle mesh with per-vertex normals.

    Parameters
    ----------
    vertices : array_like, shape (V, 3)
        Vertex positions (stored as float64).
    faces : array_like of int, shape (F, 3)
        Vertex indices of each triangle, counter-clockwise seen from outside.
    normals : array_like, shape (V, 3), optional
        Per-vertex normals (normalized on input; zero rows stay zero and are
        replaced by computed ones).  When omitted they are computed on first use
        with :meth:`vertex_normals` (angle-weighted).
    tangents : array_like, shape (V, 3), optional
        Per-vertex tangents that orient anisotropic models (made unit and perpendicular to the
        normals on first use; a zero row, or one along the normal, takes the default frame).
        When omitted: from ``uvs`` if given, else the default frame (:attr:`tangents`).
    uvs : array_like, shape (V, 2), optional
        Texture coordinates ``(u, v)`` per vertex; the tangents follow ``∂p/∂u``.

    Notes
    -----
    The arrays are read-only: a mesh is a value, derived quantities are cached.

    Examples
    --------
    >>> tri = TriangleMesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> tri.face_normals.tolist(), tri.face_areas.tolist()
    ([[0.0, 0.0, 1.0]], [0.5])
    """

    def __init__(self, vertices, faces, normals=None, tangents=None, uvs=None):
        v = _as_points("vertices", vertices, "an array of shape (V, 3)")
        try:
            f = np.array(faces)
        except (TypeError, ValueError):
            raise ValueError(f"faces must be an integer array of shape (F, 3); got {faces!r}") from None
        if f.size == 0:
            f = f.reshape(0, 3)
        if f.ndim != 2 or f.shape[1] != 3:
            raise ValueError(f"faces must be an integer array of shape (F, 3); got shape {f.shape}")
        if f.dtype.kind not in "iu":
            if f.dtype.kind == "f" and np.all(np.isfinite(f)) and np.all(f == np.round(f)):
                f = f.astype(np.int64)
            else:
                raise ValueError(f"faces must hold integer vertex indices; got dtype {f.dtype}")
        f = f.astype(np.int64, copy=True)
        if f.size and (f.min() < 0 or f.max() >= len(v)):
            bad = int(f.max()) if f.max() >= len(v) else int(f.min())
            raise ValueError(
                f"faces index vertices out of range: index {bad} with {len(v)} vertices (allowed 0..{len(v) - 1})"
            )
        self._vertices = _readonly(v)
        self._faces = _readonly(f)
        self._cache: dict = {}
        if normals is not None:
            n = _as_points("normals", normals, f"an array of shape ({len(v)}, 3)")
            if n.shape != v.shape:
                raise ValueError(f"normals must have the shape of vertices {v.shape}; got {n.shape}")
            n = normalize(n)
            zero = ~n.any(axis=1)
            if zero.any():
                n[zero] = self.vertex_normals()[zero]
            self._normals = _readonly(n)
        else:
            self._normals = None
        self._normals_given = normals is not None
        self._face_columns = None
        self._tangents_given = None
        if tangents is not None:
            t = _as_points("tangents", tangents, f"an array of shape ({len(v)}, 3)")
            if t.shape != v.shape:
                raise ValueError(f"tangents must have the shape of vertices {v.shape}; got {t.shape}")
            self._tangents_given = _readonly(t)
        self._uvs = None
        if uvs is not None:
            allowed = f"an array of shape ({len(v)}, 2) of finite numbers"
            try:
                uv = np.array(uvs, dtype=np.float64)
            except (TypeError, ValueError):
                raise ValueError(f"uvs must be {allowed}; got {uvs!r}") from None
            if uv.shape != (len(v), 2) or not np.all(np.isfinite(uv)):
                raise ValueError(f"uvs must be {allowed}; got shape {uv.shape}")
            self._uvs = _readonly(uv)

    # ------------------------------------------------------------------ data
    @property
    def vertices(self) -> np.ndarray:
        """Vertex positions, ``(V, 3)`` float64 (read-only)."""
        return self._vertices

    @property
    def faces(self) -> np.ndarray:
        """Triangle vertex indices, ``(F, 3)`` int64 (read-only)."""
        return self._faces

    @property
    def normals(self) -> np.ndarray:
        """Unit per-vertex normals ``(V, 3)``: the given ones, else angle-weighted ones."""
        if self._normals is None:
            self._normals = self.vertex_normals("angle")
        return self._normals

    @property
    def tangents(self) -> np.ndarray:
        """Unit per-vertex tangents ``(V, 3)`` ``⊥`` :attr:`normals`: given, from :attr:`uvs`, or the default frame.

        See :mod:`lighting.render.tangents`; the default frame is ``ẑ × n / |ẑ × n|`` (``x̂`` where ``n``
        is along ±z), what a model uses when given no tangent.
        """
        if "tangents" not in self._cache:
            if self._tangents_given is not None:
                t = orthonormal_tangents(self._tangents_given, self.normals)
            elif self._uvs is not None:
                t = uv_tangents(self._vertices, self._faces, self._uvs, self.normals, self.corner_angles())
            else:
                t = default_tangents(self.normals)
            self._cache["tangents"] = _readonly(np.ascontiguousarray(t, dtype=np.float64))
        return self._cache["tangents"]

    @property
    def uvs(self) -> np.ndarray | None:
        """Texture coordinates ``(V, 2)`` float64 (read-only), or ``None``."""
        return self._uvs

    @property
    def face_columns(self) -> list[np.ndarray]:
        """``faces[:, k]`` for ``k = 0, 1, 2``, each contiguous (what per-corner lookups gather with fastest)."""
        if self._face_columns is None:
            self._face_columns = [_readonly(np.ascontiguousarray(self._faces[:, k])) for k in range(3)]
        return self._face_columns

    @property
    def has_given_normals(self) -> bool:
        """True when the normals came from the caller (a generator, a file), False when computed."""
        return self._normals_given

    @property
    def n_triangles(self) -> int:
        """Number of triangles ``F``."""
        return len(self._faces)

    @property
    def n_vertices(self) -> int:
        """Number of vertices ``V``."""
        return len(self._vertices)

    def __repr__(self) -> str:
        return f"TriangleMesh({self.n_vertices} vertices, {self.n_triangles} triangles)"

    # ------------------------------------------------------------------ geometry
    def _scaled_cross(self):
        """``(p1 − p0) × (p2 − p0) = s² c`` as ``(c, s)``: edges divided by their largest entry ``s``.

        Scaling keeps the cross product free of overflow and underflow for any
        finite coordinates (1e160 or 1e-160 alike).
        """
        if "cross" not in self._cache:
            p = self._vertices[self._faces]
            with np.errstate(over="ignore", invalid="ignore"):
                e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
                m = np.maximum(np.abs(e1).max(axis=1), np.abs(e2).max(axis=1))
                m = np.where(np.isfinite(m) & (m > 0), m, 1.0)[:, None]
                c = np.cross(e1 / m, e2 / m)
            self._cache["cross"] = (_readonly(np.nan_to_num(c)), _readonly(m[:, 0]))
        return self._cache["cross"]

    @property
    def face_normals(self) -> np.ndarray:
        """Unit face normals ``(F, 3)``: ``(p1 - p0) × (p2 - p0)`` normalized; zero for degenerate faces."""
        if "face_normals" not in self._cache:
            self._cache["face_normals"] = _readonly(normalize(self._scaled_cross()[0]))
        return self._cache["face_normals"]

    @property
    def face_areas(self) -> np.ndarray:
        """Triangle areas ``|(p1 - p0) × (p2 - p0)| / 2``, shape ``(F,)`` (saturating, never inf)."""
        if "face_areas" not in self._cache:
            c, m = self._scaled_cross()
            with np.errstate(over="ignore"):
                a = 0.5 * np.linalg.norm(c, axis=1) * m * m
            self._cache["face_areas"] = _readonly(np.minimum(a, np.finfo(np.float64).max))
        return self._cache["face_areas"]

    @property
    def area(self) -> float:
        """Total surface area."""
        return float(self.face_areas.sum())

    def corner_angles(self) -> np.ndarray:
        """Interior angle of each triangle at each of its corners, ``(F, 3)`` radians.

        ``atan2(|a × b|, a·b)`` rather than ``acos`` of a normalized dot product:
        accurate for angles near 0 and π, and 0 (not NaN) for zero-length edges.

        Returns
        -------
        numpy.ndarray
            ``(F, 3)`` ``float64`` angles in ``[0, π]``, column ``k`` at vertex ``faces[:, k]`` (a new array).
        """
        p = self._vertices[self._faces]
        out = np.empty(self._faces.shape)
        with np.errstate(over="ignore", invalid="ignore"):
            for k in range(3):
                a = p[:, (k + 1) % 3] - p[:, k]
                b = p[:, (k + 2) % 3] - p[:, k]
                # The angle does not change with scale: divide each edge by its largest entry first.
                a = a / np.where(np.abs(a).max(axis=1) > 0, np.abs(a).max(axis=1), 1)[:, None]
                b = b / np.where(np.abs(b).max(axis=1) > 0, np.abs(b).max(axis=1), 1)[:, None]
                out[:, k] = np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.einsum("ij,ij->i", a, b))
        return np.nan_to_num(out)

    def vertex_normals(self, weighting: str = "angle") -> np.ndarray:
        """Unit per-vertex normals computed from the faces (ignores given normals).

        ``n_v = normalize(Σ_f w_f n_f)`` over the faces ``f`` around vertex ``v``,
        with ``w_f`` the interior angle at ``v`` (``"angle"``, Thürmer & Wüthrich
        1998, the default) or the face area (``"area"``).

        Parameters
        ----------
        weighting : {"angle", "area"}

        Returns
        -------
        ndarray, shape (V, 3)
            Unit normals; a vertex whose sum vanishes takes the normal of its
            largest incident face, an isolated vertex gets the zero vector.

        Examples
        --------
        >>> corner = TriangleMesh(  # the three faces of the unit cube [0, 1]³ at its corner 0
        ...     [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], [[0, 2, 1], [0, 3, 2], [0, 1, 3]])
        >>> (corner.vertex_normals()[0] * np.sqrt(3)).round(12).tolist()
        [-1.0, -1.0, -1.0]
        """
        weighting = check_choice("weighting", weighting, ("angle", "area"))
        key = "vn_" + weighting
        if key in self._cache:
            return self._cache[key]
        nv = self.n_vertices
        if weighting == "angle":
            w = self.corner_angles()[:, :, None] * self.face_normals[:, None, :]  # (F, 3 corners, 3)
        else:
            w = np.broadcast_to((self.face_normals * self.face_areas[:, None])[:, None, :], (self.n_triangles, 3, 3))
        idx = self._faces.reshape(-1)
        wf = w.reshape(-1, 3)
        acc = np.stack([np.bincount(idx, weights=wf[:, c], minlength=nv) for c in range(3)], axis=1)
        n = normalize(acc)
        zero = ~n.any(axis=1)
        if zero.any() and self.n_triangles:
            # Fallback for vanishing sums: the largest incident face's normal.
            areas = self.face_areas
            corner_face = np.repeat(np.arange(self.n_triangles), 3)
            order = np.lexsort((areas[corner_face], idx))  # by vertex, then by area
            last = np.r_[idx[order][1:] != idx[order][:-1], True]
            best = np.zeros(nv, dtype=np.int64)
            best[idx[order][last]] = corner_face[order][last]
            has = np.zeros(nv, dtype=bool)
            has[idx] = True
            fill = zero & has
            n[fill] = self.face_normals[best[fill]]
        self._cache[key] = _readonly(n)
        return self._cache[key]

    # ------------------------------------------------------------------ transforms
    def transformed(self, matrix) -> TriangleMesh:
        """The mesh under an affine 4×4 transform (column vectors: ``p' = M p``).

        Points map by ``M``; normals by the inverse transpose of its upper-left
        3×3 block ``A`` (``n' ∝ A^{-T} n``, which keeps them perpendicular to the
        transformed surface), renormalized.  A mirroring transform (``det A < 0``)
        also reverses each face's vertex order so faces stay counter-clockwise
        seen from outside.

        Parameters
        ----------
        matrix : array_like, (4, 4)
            Finite, affine (last row ``0, 0, 0, 1``) and invertible; the transformed vertices must stay finite.

        Returns
        -------
        TriangleMesh
            A new mesh; normals given with this mesh are transformed, computed ones are recomputed;
            given tangents map by ``A`` (they are directions along the surface), texture coordinates stay.

        Examples
        --------
        >>> m = icosphere(0).transformed(np.diag([2.0, 1.0, 1.0, 1.0]))
        >>> float(m.vertices[:, 0].max()) == 2 * float(icosphere(0).vertices[:, 0].max())
        True
        """
        try:
            M = np.array(matrix, dtype=np.float64)
        except (TypeError, ValueError):
            raise ValueError(f"matrix must be a 4x4 array of finite numbers; got {matrix!r}") from None
        if M.shape != (4, 4) or not np.all(np.isfinite(M)):
            raise ValueError(f"matrix must be a 4x4 array of finite numbers; got shape {M.shape}")
        if not np.array_equal(M[3], [0.0, 0.0, 0.0, 1.0]):
            raise ValueError(f"matrix must be affine (last row 0, 0, 0, 1); got last row {M[3].tolist()}")
        A = M[:3, :3]
        scale = float(np.abs(A).max())
        # Invertibility is judged on A / scale: the determinant of A itself overflows for entries near
        # 1e103 (and scale**3 raised OverflowError for a scale of 1e300).
        det_unit = float(np.linalg.det(A / scale)) if scale > 0 else 0.0
        if not abs(det_unit) > 1e-12:
            raise ValueError(f"matrix must be invertible; its 3x3 block, divided by its largest entry {scale!r}, "
                             f"has determinant {det_unit!r}")  # fmt: skip
        det = det_unit
        with np.errstate(over="ignore", invalid="ignore"):
            v = self._vertices @ A.T + M[:3, 3]
        if not np.all(np.isfinite(v)):
            big = float(np.abs(self._vertices).max()) if self._vertices.size else 0.0
            raise ValueError(f"matrix moves vertices beyond the float range (largest matrix entry {scale!r}, "
                             f"largest vertex coordinate {big!r}); the transformed mesh must be finite")  # fmt: skip
        f = self._faces if det > 0 else self._faces[:, ::-1]
        n = None
        if self._normals_given:  # computed normals are recomputed on the new geometry instead
            # row vectors: (A^{-T} n)^T = n^T A^{-1}; the positive scale drops out when normalized
            n = self._normals @ np.linalg.inv(A / scale)
        t = None if self._tangents_given is None else self._tangents_given @ (A / scale).T
        return TriangleMesh(v, f, n, tangents=t, uvs=self._uvs)


# ---------------------------------------------------------------------- generators
#: Peak bytes per triangle while a sphere is generated (measured with tracemalloc: 160–170 for uv and icospheres).
BYTES_PER_GENERATED_TRIANGLE = 192
#: Peak bytes per byte of a mesh file while trimesh reads it (measured 5–23 for OBJ, PLY, STL, OFF and GLB).
BYTES_PER_FILE_BYTE = 32


def _sphere_center(center) -> np.ndarray:
    """The ``center`` of :func:`uv_sphere` and :func:`icosphere`: a finite 3-vector, float64."""
    c = np.asarray(center, dtype=np.float64)
    if c.shape != (3,) or not np.all(np.isfinite(c)):
        raise ValueError(f"center must be a finite 3-vector; got {center!r}")
    return c


def _sphere_mesh(unit: np.ndarray, faces: np.ndarray, r: float, c: np.ndarray) -> TriangleMesh:
    """The unit sphere ``unit`` scaled by a checked radius ``r`` about a checked centre ``c``."""
    return TriangleMesh(c + r * unit, faces, normals=unit, tangents=sphere_tangents(unit))


def uv_sphere(n_lat: int, n_lon: int, radius: float = 1.0, center=(0.0, 0.0, 0.0)) -> TriangleMesh:
    """Latitude–longitude sphere with poles on the ±y axis (the default camera up).

    ``n_lat`` bands between the poles (polar angle ``θ_i = π i / n_lat`` from +y)
    and ``n_lon`` sectors.  One vertex per pole (no seam, no duplicates) and
    ``n_lon`` per inner ring: ``V = 2 + n_lon (n_lat - 1)``; the polar caps are
    fans of ``n_lon`` triangles (no degenerate triangle at the poles), the other
    bands are quads split in two: ``F = 2 n_lon (n_lat - 1)``.

    Vertex ``(sin θ sin φ, cos θ, sin θ cos φ)`` scaled by ``radius`` around
    ``center``; normals are the exact sphere normals, tangents ``∂p/∂φ`` normalized
    (``ŷ × n / |ŷ × n|``, along the parallels; the default frame at the poles).

    Parameters
    ----------
    n_lat : int >= 2
        Latitude bands between the poles.
    n_lon : int >= 3
        Longitude sectors.
    radius : float > 0, default 1
        Sphere radius.
    center : 3-vector, default (0, 0, 0)
        Sphere centre (finite).

    Returns
    -------
    TriangleMesh
        ``2 + n_lon (n_lat - 1)`` vertices, ``2 n_lon (n_lat - 1)`` triangles.

    Raises
    ------
    BudgetError
        A ValueError, when the mesh would need more than the memory budget.

    Examples
    --------
    >>> m = uv_sphere(4, 8)
    >>> len(m.vertices), m.n_triangles
    (26, 48)
    """
    n_lat = check_count("n_lat", n_lat, 2)
    n_lon = check_count("n_lon", n_lon, 3)
    triangles = 2 * n_lon * (n_lat - 1)
    check_budget(f"n_lat = {n_lat}, n_lon = {n_lon}", float(min(triangles * BYTES_PER_GENERATED_TRIANGLE, 1e300)),
                 what=f"{triangles} triangles")  # fmt: skip
    radius, center = check_positive("radius", radius), _sphere_center(center)
    theta = np.pi * np.arange(1, n_lat) / n_lat
    phi = 2 * np.pi * np.arange(n_lon) / n_lon
    st, ct = np.sin(theta)[:, None], np.cos(theta)[:, None]
    ring = np.stack(np.broadcast_arrays(st * np.sin(phi), ct, st * np.cos(phi)), axis=-1).reshape(-1, 3)
    unit = np.concatenate([[[0.0, 1.0, 0.0]], ring, [[0.0, -1.0, 0.0]]])
    # Renormalize: sin²+cos² rounds to 1 within an ulp or two; this makes |v| = 1 to ~1e-16.
    unit = unit / np.linalg.norm(unit, axis=1, keepdims=True)
    south = len(unit) - 1
    j = np.arange(n_lon)
    jn = (j + 1) % n_lon

    def ring_index(i, jj):
        return 1 + i * n_lon + jj

    # φ grows from +z toward +x: seen from outside, (top, lower-left, lower-right) is counter-clockwise
    # when "left" is the smaller φ.  Verified by the outward-normal test.
    top = np.stack([np.zeros(n_lon, dtype=np.int64), ring_index(0, j), ring_index(0, jn)], axis=1)
    bottom = np.stack([np.full(n_lon, south), ring_index(n_lat - 2, jn), ring_index(n_lat - 2, j)], axis=1)
    i = np.arange(n_lat - 2)[:, None]
    a, b = ring_index(i, j), ring_index(i, jn)
    c, d = ring_index(i + 1, j), ring_index(i + 1, jn)
    quads = np.concatenate([np.stack([a, c, d], -1).reshape(-1, 3), np.stack([a, d, b], -1).reshape(-1, 3)])
    faces = np.concatenate([top, quads, bottom]).astype(np.int64)
    return _sphere_mesh(unit, faces, radius, center)


_PHI = (1 + math.sqrt(5)) / 2
_ICO_V = np.array(
    [
        [-1, _PHI, 0],
        [1, _PHI, 0],
        [-1, -_PHI, 0],
        [1, -_PHI, 0],
        [0, -1, _PHI],
        [0, 1, _PHI],
        [0, -1, -_PHI],
        [0, 1, -_PHI],
        [_PHI, 0, -1],
        [_PHI, 0, 1],
        [-_PHI, 0, -1],
        [-_PHI, 0, 1],
    ]
)
_ICO_F = np.array(
    [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ],
    dtype=np.int64,
)


def _unit_rows(p: np.ndarray) -> np.ndarray:
    return p / np.sqrt(np.einsum("ij,ij->i", p, p))[:, None]


def icosphere(level: int, radius: float = 1.0, center=(0.0, 0.0, 0.0)) -> TriangleMesh:
    """Geodesic sphere: the icosahedron with each triangle split in 4, ``level`` times.

    Each split puts a vertex at every edge midpoint, pushed out onto the sphere.
    Level ``k`` has ``F = 20·4^k`` faces, ``E = 30·4^k`` edges and
    ``V = 10·4^k + 2`` vertices (Euler: ``V − E + F = 2``).  Triangles are
    nearly equilateral, so an icosphere approximates the sphere more uniformly
    than a uv sphere with as many triangles.  Normals are the exact sphere normals, tangents
    ``∂p/∂φ`` about ``+y`` as on :func:`uv_sphere` (so that either of :func:`sphere_for_triangles`'
    spheres orients an anisotropic lobe the same way).

    Parameters
    ----------
    level : int in [0, 9]
        Number of 4-way splits of the icosahedron.
    radius : float > 0, default 1
        Sphere radius.
    center : 3-vector, default (0, 0, 0)
        Sphere centre (finite).

    Returns
    -------
    TriangleMesh
        ``10·4^level + 2`` vertices, ``20·4^level`` triangles.

    Examples
    --------
    >>> [icosphere(k).n_triangles for k in range(3)]
    [20, 80, 320]
    """
    level = check_count("level", level, 0)
    if level > 9:
        raise ValueError(f"level must be an integer in 0..9 (level 9 has 5,242,880 triangles); got {level!r}")
    triangles = 20 * 4**level
    check_budget(f"level = {level}", triangles * BYTES_PER_GENERATED_TRIANGLE, what=f"{triangles} triangles")
    radius, center = check_positive("radius", radius), _sphere_center(center)
    unit = _unit_rows(_ICO_V)
    faces = _ICO_F
    for _ in range(level):
        edges = np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 3, 2), axis=2).reshape(-1, 2)
        uniq, inv = np.unique(edges, axis=0, return_inverse=True)
        mid = _unit_rows(unit[uniq[:, 0]] + unit[uniq[:, 1]])
        m = (len(unit) + inv.reshape(-1)).reshape(-1, 3)  # midpoints of edges (01, 12, 20)
        a, b, c = faces[:, 0], faces[:, 1], faces[:, 2]
        ab, bc, ca = m[:, 0], m[:, 1], m[:, 2]
        faces = np.concatenate(
            [np.stack(t, axis=1) for t in ((a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca))]
        ).astype(np.int64)
        unit = np.concatenate([unit, mid])
    return _sphere_mesh(unit, faces, radius, center)


def sphere_for_triangles(n: int, radius: float = 1.0, center=(0.0, 0.0, 0.0)) -> TriangleMesh:
    """A sphere mesh with about ``n`` triangles (``n >= 8``).

    The icosphere whose ``20·4^k`` triangles is nearest ``n`` if that is within
    10 % of ``n`` (the better-shaped tessellation); otherwise the uv sphere with
    ``2 n_lon (n_lat − 1)`` triangles nearest ``n`` among those with
    ``1.5 n_lat ≤ n_lon ≤ 2.5 n_lat`` (near-square quads at the equator need
    ``n_lon ≈ 2 n_lat``; ties go to the squarest).

    Parameters
    ----------
    n : int >= 8
        Wanted number of triangles.
    radius : float > 0, default 1
        Sphere radius.
    center : 3-vector, default (0, 0, 0)
        Sphere centre (finite).

    Returns
    -------
    TriangleMesh
        An :func:`icosphere` or a :func:`uv_sphere`.

    Examples
    --------
    >>> [sphere_for_triangles(n).n_triangles for n in (80, 100, 1000, 5000, 20000)]
    [80, 100, 992, 5120, 20480]
    """
    n = check_count("n", n, 8)
    k = max(0, round(math.log(n / 20, 4)))
    if k <= 9 and abs(20 * 4**k - n) <= 0.1 * n:
        return icosphere(k, radius, center)
    best = (math.inf, math.inf, 2, 4)
    for n_lat in range(2, math.isqrt(n) + 2):
        lo, hi = max(3, math.ceil(1.5 * n_lat)), math.floor(2.5 * n_lat)
        for n_lon in {min(max(round(n / (2 * (n_lat - 1))), lo), hi), lo, hi}:
            cand = (abs(2 * n_lon * (n_lat - 1) - n), abs(n_lon - 2 * n_lat), n_lat, n_lon)
            best = min(best, cand)
    return uv_sphere(best[2], best[3], radius, center)


# ---------------------------------------------------------------------- loading
_FORMATS = (".obj", ".ply", ".stl", ".glb", ".gltf", ".off")


def _weld(vertices: np.ndarray, faces: np.ndarray):
    """Merge exactly coincident vertices, keeping first occurrences in file order."""
    _, first, inv = np.unique(vertices, axis=0, return_index=True, return_inverse=True)
    if len(first) == len(vertices):
        return vertices, faces
    order = np.argsort(first)
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    return vertices[np.sort(first)], rank[inv.reshape(-1)][faces]


def load_mesh(path, *, weld: bool = True) -> TriangleMesh:
    """Read a triangle mesh from an OBJ (NumPy, :mod:`lighting.render.obj`), PLY, STL, GLB/glTF or OFF file (trimesh).

    A scene (GLB with several nodes) is flattened into one mesh with each
    node's transform applied.  Vertex normals stored in the file are used
    (normalized); otherwise they are computed angle-weighted.  Texture coordinates of a
    single-mesh file orient the tangents (``∂p/∂u``); without them, the default frame.  Without file
    normals, exactly coincident vertices are merged first (``weld=True``) so that
    STL files, which store every triangle separately, shade smoothly.
    Degenerate triangles are kept (they are harmless, see the module notes).

    Parameters
    ----------
    path : str or os.PathLike
        A regular file with extension ``.obj``, ``.ply``, ``.stl``, ``.glb``, ``.gltf`` or ``.off``
        (case-insensitive); a file too large for the memory budget is refused (``BudgetError``) before reading.
    weld : bool, default True
        Merge exactly coincident vertices when the file has no normals.

    Returns
    -------
    TriangleMesh
        ``float64`` vertices in file order (after welding), ``int64`` faces.

    Raises
    ------
    ValueError
        Naming the file and the problem: missing file, unsupported or unreadable
        format, no geometry, no triangles, non-finite vertices, face indices out
        of range, or only zero-area triangles.
    """
    p = os.fspath(path)
    name = quote_path(p)
    try:
        st = os.stat(p)
    except (OSError, ValueError):  # missing, a dangling link, a NUL in the name
        raise ValueError(f"mesh file {name} does not exist") from None
    if stat.S_ISDIR(st.st_mode):
        raise ValueError(f"mesh file {name} is a directory, not a file")
    if not stat.S_ISREG(st.st_mode):  # a FIFO or a device: reading would block or never end
        raise ValueError(f"mesh file {name} is not a regular file")
    ext = os.path.splitext(p)[1].lower()
    if ext not in _FORMATS:
        raise ValueError(f"mesh file {name}: unsupported format {abbreviate(repr(ext or '(no extension)'))}; "
                         f"allowed: {_FORMATS}")  # fmt: skip
    # Before a byte is parsed: a 1 GB file (even a sparse one, all zeros) needs many times that to read.
    try:
        check_budget(f"mesh file {name}", st.st_size * BYTES_PER_FILE_BYTE, what=f"{st.st_size} bytes to read")
    except BudgetError as e:
        raise BudgetError(str(e)) from None
    if ext == ".obj":  # NumPy alone: no trimesh import (seconds) for the format scenes use most
        vertices, faces, normals, uvs = read_obj(p)
    else:
        vertices, faces, normals, uvs = _load_with_trimesh(p, name, ext)
    return _checked_mesh(name, vertices, faces, normals, uvs, weld)


def _load_with_trimesh(p: str, name: str, ext: str):
    """``(vertices, faces, normals or None, uvs or None)`` of a PLY, STL, GLB/glTF or OFF file, read by trimesh."""
    import trimesh  # heavy: only when a file is actually loaded

    try:
        loaded = trimesh.load(p, process=False)
    except Exception as e:  # trimesh raises many kinds on corrupt input
        raise ValueError(f"mesh file {name} could not be read as {ext[1:].upper()}: {type(e).__name__}: {e}") from e

    normals = uvs = None
    if isinstance(loaded, trimesh.Scene):
        parts = [g for g in loaded.dump() if isinstance(g, trimesh.Trimesh) and len(g.faces)]
        if not loaded.geometry:
            raise ValueError(f"mesh file {name} contains no geometry (empty or unreadable {ext[1:].upper()})")
        if not parts:
            raise ValueError(f"mesh file {name} contains no triangles")
        offsets = np.cumsum([0] + [len(g.vertices) for g in parts])
        vertices = np.concatenate([np.asarray(g.vertices, dtype=np.float64) for g in parts])
        faces = np.concatenate([np.asarray(g.faces, dtype=np.int64) + o for g, o in zip(parts, offsets, strict=False)])
    elif isinstance(loaded, trimesh.Trimesh):
        vertices = np.asarray(loaded.vertices, dtype=np.float64)
        faces = np.asarray(loaded.faces, dtype=np.int64).reshape(-1, 3)
        try:  # normals read from the file sit in trimesh's cache; computed ones don't exist yet
            if "vertex_normals" in loaded._cache:
                normals = np.asarray(loaded._cache["vertex_normals"], dtype=np.float64)
        except Exception:  # pragma: no cover - trimesh internals changed
            normals = None
        uvs = getattr(getattr(loaded, "visual", None), "uv", None)
    else:
        raise ValueError(f"mesh file {name} contains no triangles (it holds a {type(loaded).__name__})")
    return vertices, faces, normals, uvs


def _checked_mesh(name, vertices, faces, normals, uvs, weld) -> TriangleMesh:
    """The mesh of what a reader returned, every array checked (module notes on welding and normals)."""
    if len(vertices) == 0:
        raise ValueError(f"mesh file {name} contains no vertices")
    if len(faces) == 0:
        raise ValueError(f"mesh file {name} contains no triangles")
    bad = ~np.isfinite(vertices).all(axis=1)
    if bad.any():
        raise ValueError(f"mesh file {name} has {int(bad.sum())} vertices with NaN or infinite coordinates")
    if faces.min() < 0 or faces.max() >= len(vertices):
        worst = int(faces.max()) if faces.max() >= len(vertices) else int(faces.min())
        raise ValueError(f"mesh file {name} has face indices out of range: index {worst} with {len(vertices)} vertices")
    if normals is not None and (normals.shape != vertices.shape or not np.all(np.isfinite(normals))):
        normals = None
    if uvs is not None:
        uvs = np.asarray(uvs, dtype=np.float64)
        if uvs.shape != (len(vertices), 2) or not np.all(np.isfinite(uvs)):
            uvs = None
    if normals is None and weld:
        n_before = len(vertices)
        vertices, faces = _weld(vertices, faces)
        if len(vertices) != n_before:
            uvs = None  # a merged vertex has no one texture coordinate (the seams): the default frame
    mesh = TriangleMesh(vertices, faces, normals, uvs=uvs)
    if not np.any(mesh.face_areas > 0):
        raise ValueError(f"mesh file {name}: all {mesh.n_triangles} triangles are degenerate (zero area)")
    return mesh

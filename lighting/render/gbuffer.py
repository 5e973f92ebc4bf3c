"""The geometry buffer: per-pixel visibility and attributes of one view.

:func:`~lighting.render.raster.rasterize` (triangle meshes) and
:func:`~lighting.render.raycast.raycast_sphere` (the exact sphere) both fill a
:class:`GBuffer`; lighting then runs on the buffer alone
(``shade(gb.position[gb.coverage], gb.normal[gb.coverage], ...)``), so moving a
light or changing a material re-shades without re-rasterizing; flat, Gouraud
and Phong interpolation are all reads of the same buffer (:meth:`GBuffer.per_face`,
:meth:`GBuffer.interpolate`, :attr:`GBuffer.normal`).  A renderer that needs
only the covered pixels reads them without images through the ``covered_*``
accessors and :meth:`GBuffer.interpolate_covered`.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np

from .._budget import check_budget
from .._validate import real_array
from ..numerics import working_dtype
from ..vec import normalize
from .camera import Camera
from .mesh import TriangleMesh

__all__ = ["GBuffer"]


class GBuffer:
    """Per-pixel geometry of one view: everything a lighting pass needs.

    All arrays are ``(H, W, ...)``; pixels that no triangle covers hold zeros
    (``triangle_id`` holds ``-1`` there).  Float arrays have the dtype asked of
    :func:`rasterize`.

    The rasterizer stores *visibility* (which triangle, where on it) and the
    attributes are resolved from it on first use and then cached (a
    "visibility buffer"): :attr:`position`, :attr:`normal`,
    :attr:`normal_unnormalized` and :attr:`face_normal` cost nothing until read,
    and a lighting pass that reads them once re-shades for free afterwards.
    The images themselves are laid out the same way: :func:`rasterize` keeps
    the visible fragments as one row per covered pixel, and each ``(H, W)``
    image below is scattered from them on first read (a renderer that reads
    only the covered pixels never builds them).  A buffer is read-only.

    Attributes
    ----------
    triangle_id : (H, W) int32
        Index into ``mesh.faces`` of the visible triangle, ``-1`` where empty.
    barycentric : (H, W, 3)
        Perspective-correct barycentric coordinates ``b`` of the sample point
        on that triangle, in the order of its vertices in ``mesh.faces``
        (``Σ b_i = 1``; the point is ``Σ b_i p_i``).
    depth : (H, W)
        View-space depth ``f·(p − eye)`` of the visible point.
    coverage : (H, W) bool
        True where a triangle covers the pixel centre.
    front_facing : (H, W) bool
        True where the visible triangle faces the camera (always, when back
        faces are culled).
    overdraw : (H, W) int32
        How many triangles passed the coverage test at the pixel before the
        depth test (1 everywhere on a closed convex mesh with culling).
    camera : Camera
    mesh : TriangleMesh or None
        ``None`` for the analytic sphere of :func:`raycast_sphere`.
    attributes : dict
        Per-pixel arrays given directly instead of interpolated from the mesh
        (``"position"``, ``"normal"``, … for the analytic sphere).
    shape : (int, int)
        Image shape ``(H, W)``.
    dtype : numpy.dtype
        Float dtype of the buffer.
    """

    def __init__(
        self, triangle_id, barycentric, depth, coverage, front_facing, overdraw, camera, mesh, attributes=None
    ):
        d = self.__dict__
        d.update(triangle_id=triangle_id, barycentric=barycentric, depth=depth, coverage=coverage,
                 front_facing=front_facing, overdraw=overdraw)  # fmt: skip
        d.update(camera=camera, mesh=mesh, attributes={} if attributes is None else attributes)
        d.update(shape=coverage.shape, dtype=depth.dtype)

    @classmethod
    def _from_fragments(cls, shape, pixels, triangle_id, barycentric, depth, front, overdraw, camera, mesh):
        """A buffer held as its covered pixels: flat indices (increasing) and, per pixel, the mesh face id,
        the barycentric planes ``(3, n)``, the depth, whether the face is front-facing (``None``: all
        are) and the overdraw counts of the whole image (flat)."""
        gb = cls.__new__(cls)
        gb.__dict__.update(
            shape=shape, dtype=depth.dtype, camera=camera, mesh=mesh, attributes={}, pixels=pixels,
            _compact=(triangle_id, list(barycentric)), _depth_compact=depth, _front_compact=front,
            _overdraw_flat=overdraw,
        )  # fmt: skip
        return gb

    def __setattr__(self, name, value):
        raise AttributeError(f"GBuffer is read-only (cannot set {name!r})")

    # ------------------------------------------------------------------ images, from the covered pixels
    @cached_property
    def triangle_id(self) -> np.ndarray:
        return self._scatter(self._compact[0], -1, np.int32)

    @cached_property
    def barycentric(self) -> np.ndarray:
        planes = np.zeros((3, self.shape[0] * self.shape[1]), dtype=self.dtype)
        for k in range(3):
            planes[k][self.pixels] = self._compact[1][k]
        # (H, W, 3) view of the planes: each barycentric coordinate stays one contiguous image.
        return planes.reshape((3,) + self.shape).transpose(1, 2, 0)

    @cached_property
    def depth(self) -> np.ndarray:
        return self._scatter(self._depth_compact)

    @cached_property
    def coverage(self) -> np.ndarray:
        return self._scatter(True, False, bool)

    @cached_property
    def front_facing(self) -> np.ndarray:
        front = self._front_compact
        return self.coverage if front is None else self._scatter(front, False, bool)

    @cached_property
    def overdraw(self) -> np.ndarray:
        return self._overdraw_flat.astype(np.int32).reshape(self.shape)

    # ------------------------------------------------------------------ basics
    def __repr__(self) -> str:
        H, W = self.shape
        source = "analytic sphere" if self.mesh is None else repr(self.mesh)
        return f"GBuffer({W}x{H}, {len(self.pixels)} pixels covered, {self.dtype}, {source})"

    @cached_property
    def pixels(self) -> np.ndarray:
        """Flat (row-major) indices of the covered pixels, increasing."""
        return np.flatnonzero(self.coverage)

    @cached_property
    def _compact(self):
        """At :attr:`pixels`: the triangle ids and the three barycentric columns (contiguous)."""
        p = self.pixels
        tid = self.triangle_id.reshape(-1).take(p)
        b = [self.barycentric[..., k].take(p) for k in range(3)]
        return tid, b

    @cached_property
    def _depth_compact(self):
        return self.depth.reshape(-1).take(self.pixels)

    @property
    def covered_triangle_ids(self) -> np.ndarray:
        """The visible triangle's index at each covered pixel (in :attr:`pixels` order), int32 ``(n,)``."""
        return self._compact[0]

    @property
    def covered_depth(self) -> np.ndarray:
        """View-space depth at each covered pixel (in :attr:`pixels` order), ``(n,)``."""
        return self._depth_compact

    @property
    def covered_positions(self) -> np.ndarray:
        """World position at each covered pixel (in :attr:`pixels` order), ``(n, 3)`` (cached)."""
        return self._position_compact

    def interpolate_covered(self, vertex_values: np.ndarray, rows=None) -> np.ndarray:
        """``Σ b_i a[f_i]`` at the covered pixels only, without building an image (the renderer's path).

        Parameters
        ----------
        vertex_values : numpy.ndarray, (V,) or (V, k)
            One float value (or row) per mesh vertex, already in the wanted float dtype (not checked:
            :meth:`interpolate` is the checked form).
        rows : slice or array of int, optional
            Only these of the covered pixels (positions in :attr:`pixels`).

        Returns
        -------
        numpy.ndarray, (n,) or (n, k)
            In the dtype of ``vertex_values``, saturated at its largest finite value.
        """
        return self._interp_compact(vertex_values, rows)

    def _scatter(self, values, fill=0, dtype=None) -> np.ndarray:
        """An image holding ``values`` (one row per covered pixel, or one value for all) and ``fill`` elsewhere."""
        values = np.asarray(values)
        out = np.full((self.shape[0] * self.shape[1],) + values.shape[1:], fill, dtype=dtype or values.dtype)
        if values.shape[1:] == (3,):
            # One 1-D scatter per channel (a strided column of the image): several times faster
            # than assigning rows of three.
            for c in range(3):
                out[:, c][self.pixels] = values[:, c]
        else:
            out[self.pixels] = values
        return out.reshape(self.shape + values.shape[1:])

    def _need_mesh(self, what: str) -> TriangleMesh:
        if self.mesh is None:
            raise ValueError(f"{what} needs a mesh; this buffer comes from an analytic sphere (mesh is None)")
        return self.mesh

    def _interp_compact(self, a: np.ndarray, rows=None) -> np.ndarray:
        """``Σ b_i a[f_i]`` at the covered pixels (or at ``rows`` of them: a slice or indices).

        ``a`` is ``(V,)`` or ``(V, k)``.
        """
        mesh = self._need_mesh("interpolate")
        tid, b = self._compact
        if rows is not None:
            tid, b = tid[rows], [bk[rows] for bk in b]
        b = [bk.astype(a.dtype, copy=False) for bk in b]
        flat = a.reshape(len(a), int(np.prod(a.shape[1:])))
        out = np.empty((len(tid), flat.shape[1]), dtype=a.dtype, order="F")  # columns contiguous
        big = np.finfo(a.dtype).max
        for c in range(flat.shape[1]):
            # One contiguous column at a time (1-D gathers are several times faster than row gathers),
            # looked up per triangle corner first: a[f_i] = (a[faces[:, i]])[triangle id], exactly.
            col = np.ascontiguousarray(flat[:, c])
            corner = [col.take(f) for f in mesh.face_columns]
            # The weights sum to 1 only up to rounding, so three values at the dtype's largest finite
            # number (saturated Gouraud colours) can sum past it: the sum saturates instead.  Each
            # b_i a_i is finite (0 <= b_i <= 1 up to rounding), so the sum is finite or ±inf, never NaN.
            with np.errstate(over="ignore"):
                acc = b[0] * corner[0].take(tid)
                acc += b[1] * corner[1].take(tid)
                acc += b[2] * corner[2].take(tid)
            np.clip(acc, -big, big, out=out[:, c])
        return out.reshape((len(tid),) + a.shape[1:])

    # ------------------------------------------------------------------ attribute access
    def interpolate(self, vertex_values) -> np.ndarray:
        """Interpolate a per-vertex attribute across the image: ``Σ b_i a[f_i]``.

        Parameters
        ----------
        vertex_values : array_like, shape (V,) or (V, k)
            One value (or row) per mesh vertex, e.g. Gouraud vertex colours.

        Returns
        -------
        ndarray, shape (H, W) or (H, W, k)
            Zero where nothing is covered.  dtype: float64 if either the buffer
            or the values are float64, else float32.

        Examples
        --------
        >>> from lighting.render.camera import Camera
        >>> from lighting.render.mesh import icosphere
        >>> from lighting.render.raster import rasterize
        >>> m = icosphere(1)
        >>> gb = rasterize(m, Camera((0, 0, 4), (0, 0, 0), width=8, height=8))
        >>> round(gb.interpolate(np.ones(len(m.vertices)))[4, 4].item(), 12)  # barycentrics sum to 1
        1.0
        """
        mesh = self._need_mesh("interpolate")
        a = real_array("vertex_values", vertex_values)
        dt = working_dtype(self.barycentric, a)
        a = a.astype(dt, copy=False)
        if a.ndim == 0 or a.shape[0] != mesh.n_vertices:
            raise ValueError(
                f"vertex_values must have one row per vertex ({mesh.n_vertices}); got shape {np.shape(vertex_values)}"
            )
        return self._scatter(self._interp_compact(a))

    def per_face(self, face_values) -> np.ndarray:
        """Look up a per-triangle attribute at each pixel (flat shading): ``a[triangle_id]``.

        Parameters
        ----------
        face_values : array_like, shape (F,) or (F, k)

        Returns
        -------
        ndarray, shape (H, W) or (H, W, k)
            The attribute of each pixel's triangle, zero where nothing is covered. Float values come
            back as float64 if either the buffer or the values are float64, else float32.
        """
        n_faces = self.mesh.n_triangles if self.mesh is not None else 1
        a = np.asarray(face_values)
        if a.dtype.kind != "b":
            real_array("face_values", face_values)  # text, complex, NaN and inf refused; integers stay integers
        if a.dtype.kind in "fc":
            a = a.astype(working_dtype(self.barycentric, face_values), copy=False)
        if a.ndim == 0 or a.shape[0] != n_faces:
            raise ValueError(
                f"face_values must have one row per triangle ({n_faces}); got shape {np.shape(face_values)}"
            )
        return self._scatter(a[self._compact[0]])

    @cached_property
    def _position_compact(self) -> np.ndarray:
        if "position" in self.attributes:
            return self.attributes["position"].reshape(-1, 3)[self.pixels]
        return self._interp_compact(self._need_mesh("position").vertices.astype(self.dtype))

    @cached_property
    def position(self) -> np.ndarray:
        """World position ``Σ b_i p_i`` of the visible point, ``(H, W, 3)``."""
        if "position" in self.attributes:
            return self.attributes["position"]
        return self._scatter(self._position_compact)

    @cached_property
    def _normal_raw_compact(self) -> np.ndarray:
        return self._interp_compact(self._need_mesh("normal").normals.astype(self.dtype))

    @cached_property
    def normal_unnormalized(self) -> np.ndarray:
        """``Σ b_i n_i`` as interpolated, ``(H, W, 3)``.

        Shorter than 1 inside a triangle whose vertex normals differ; its length
        shows how much they differ.
        """
        if "normal_unnormalized" in self.attributes:
            return self.attributes["normal_unnormalized"]
        return self._scatter(self._normal_raw_compact)

    @cached_property
    def normal(self) -> np.ndarray:
        """**Unit** interpolated vertex normal ``normalize(Σ b_i n_i)``, ``(H, W, 3)``.

        The normal of Phong interpolation, ready for shading.
        """
        if "normal" in self.attributes:
            return self.attributes["normal"]
        return self._scatter(normalize(self._normal_raw_compact))

    @cached_property
    def face_normal(self) -> np.ndarray:
        """Unit geometric normal of the visible triangle (flat shading), ``(H, W, 3)``."""
        if "face_normal" in self.attributes:
            return self.attributes["face_normal"]
        return self.per_face(self._need_mesh("face_normal").face_normals.astype(self.dtype))

    def view_direction(self) -> np.ndarray:
        """The slides' ``v`` at every covered pixel (unit, toward the eye), ``(H, W, 3)``, zero elsewhere.

        Returns
        -------
        numpy.ndarray, (H, W, 3)
        """
        return self._scatter(self.camera.view_direction(self._position_compact))


def check_image_budget(camera: Camera, bytes_per_pixel: float, what: str) -> None:
    """Refuse (:class:`lighting._budget.BudgetError`) an image whose per-pixel work exceeds the memory budget.

    Parameters
    ----------
    camera : Camera
        Its ``width × height`` is the number of pixels.
    bytes_per_pixel : float
        Peak bytes of the work per pixel.
    what : str
        What is refused, for the message.

    Returns
    -------
    None
    """
    n = camera.width * camera.height
    check_budget(f"camera width x height ({camera.width}x{camera.height} pixels)", n * bytes_per_pixel,
                 what=f"{what}, about {bytes_per_pixel:g} bytes per pixel")  # fmt: skip

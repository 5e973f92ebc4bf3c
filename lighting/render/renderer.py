"""Images from the engine: flat, Gouraud and Phong-interpolated shading.

The decks' question is *when* to compute lighting:

* **flat** — once per triangle (at its centroid, with its geometric normal);
* **Gouraud** — once per vertex, then interpolate the *colours* across each
  triangle ("lose sharp highlights, subject to Mach banding");
* **Phong interpolation** — interpolate the *normals* and light every pixel.

A :class:`Renderer` rasterizes its geometry once into a geometry buffer
(:class:`lighting.render.raster.GBuffer`) and then lights it as often as asked: moving a
light, changing a material or switching the shading mode re-shades without
re-rasterizing, which is what makes a slider interactive.  Every colour comes
from :func:`lighting.shading.equation.shade_terms`, so all models, lights and the
classic / physical forms work in every mode.

The geometry is a :class:`lighting.render.mesh.TriangleMesh` or an :class:`AnalyticSphere`
(ray-cast, exact per-pixel normals: the ground truth that tessellated renderings
are measured against; it supports only per-pixel shading).

Anisotropic models are oriented by the surface tangents (:mod:`lighting.render.tangents`): the
mesh's vertex tangents, interpolated like the normals and made unit and perpendicular to the
interpolated normal per pixel (phong), the vertex tangents themselves (gouraud), or the tangent at
each triangle's centroid made perpendicular to its geometric normal (flat); on the analytic sphere
the exact ``∂p/∂φ`` about ``+y``, as on the generated spheres.  They are computed only for a
material with a part whose :meth:`~lighting.models.brdf.BRDF.lobe` is anisotropic (or unknown):
isotropic models never read them, and their images do not change.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._text import quote
from .._validate import (
    ArgumentTypeError,
    check_bool,
    check_choice,
    check_color,
    check_float_dtype,
    check_positive,
    real_array,
)
from ..lights.envlight import environment_terms, split_environment_lights
from ..shading.batch import each_chunk, shade_prepared, shade_prepared_into, shade_prepared_terms
from ..shading.inputs import TERMS, check_lights, positional_lights, view_vectors
from ..shading.material import Material, check_material
from ..vec import normalize
from .camera import Camera, check_camera
from .gbuffer import GBuffer, check_image_budget
from .linear_image import LinearImage
from .mesh import TriangleMesh
from .raster import rasterize
from .raycast import raycast_sphere
from .tangents import orthonormal_tangents, sphere_tangents

__all__ = ["SHADING_MODES", "FACING_COS", "AnalyticSphere", "Renderer", "face_toward", "render", "needs_tangents"]

SHADING_MODES = ("flat", "gouraud", "phong")

#: Peak bytes per image pixel of a first render (geometry buffer, per-pixel normals and view vectors,
#: shading temporaries and the image; measured with tracemalloc at 1024², rounded up).
RENDER_BYTES_PER_PIXEL = 320


@dataclass(frozen=True)
class AnalyticSphere:
    """A true sphere, ray-cast per pixel (exact positions and normals)."""

    center: tuple = (0.0, 0.0, 0.0)
    radius: float = 1.0

    def __post_init__(self):
        c = real_array("center", self.center, allowed="one finite 3-vector (x, y, z)", dtype=np.float64)
        if c.shape != (3,):
            raise ValueError(f"center must be one finite 3-vector (x, y, z); got shape {c.shape}: {quote(self.center)}")
        object.__setattr__(self, "center", tuple(float(x) for x in c))
        object.__setattr__(self, "radius", check_positive("radius", self.radius))


#: The cosine to the viewer a normal is turned to where interpolation tipped it away (``Renderer(face_viewer=True)``).
FACING_COS = 0.02


def face_toward(n: np.ndarray, v: np.ndarray, cos_min: float = FACING_COS) -> np.ndarray:
    """Unit normals turned toward ``v`` where ``n·v < cos_min``, in the plane of ``n`` and ``v``; others unchanged.

    ``n' = normalize(n + (cos_min − c) v)`` with ``c = n·v``: the bent vector has length
    ``√(1 + cos_min² − c²)``, so ``n'·v = cos_min / √(1 + cos_min² − c²)``, at least
    ``cos_min / √(1 + cos_min²)``: just inside the visible hemisphere, whatever ``c``.  Where ``n = −v``
    exactly (no plane to turn in) the normal becomes ``v``.

    Parameters
    ----------
    n : ndarray, (N, 3)
        Unit normals.
    v : ndarray, (N, 3) or (3,)
        Unit directions toward the viewer.
    cos_min : float
        The smallest cosine kept.

    Returns
    -------
    ndarray, (N, 3)
        The normals, in ``n``'s dtype.

    Examples
    --------
    >>> face_toward(np.array([[1.0, 0.0, -0.1]]) / np.hypot(1.0, 0.1), np.array([0.0, 0.0, 1.0])).round(4)
    array([[0.9998, 0.    , 0.0201]])
    """
    c = n @ v if v.ndim == 1 else np.einsum("ij,ij->i", n, v)
    away = c < cos_min
    if not np.any(away):
        return n
    out = np.array(n, copy=True)
    vv = v if v.ndim == 1 else v[away]
    bent = n[away] + (cos_min - c[away])[:, None] * vv
    # The bent vector's length is at least sqrt(1 - c²) > 0 unless n = −v exactly; keep v there.
    length = np.sqrt(np.einsum("ij,ij->i", bent, bent))
    safe = length > 1e-12
    out[np.flatnonzero(away)[safe]] = bent[safe] / length[safe, None]
    out[np.flatnonzero(away)[~safe]] = vv if v.ndim == 1 else vv[~safe]
    return out


class Renderer:
    """Rasterize once, shade many times.

    Parameters
    ----------
    geometry : TriangleMesh or AnalyticSphere
    camera : Camera
    dtype : {numpy.float64, numpy.float32}
        Working precision of the geometry buffer and of shading.  float32
        shading costs a relative error of 2.3e-7 to 2.6e-7 of the brightest
        pixel (measured in the accuracy report and on the benchmark scene) and
        is about twice as fast.
    cull_backfaces : bool
    face_viewer : bool
        Phong mode on a mesh: where an interpolated normal tips away from the viewer (a smooth mesh's
        silhouette, ``n·v < 0`` on a triangle that faces the eye), turn it toward the viewer just enough
        that ``n·v`` = :data:`FACING_COS`, as production renderers keep shading normals in the visible
        hemisphere.  Default False: the interpolated normal as the slides define Phong interpolation (and
        as OpenGL shades), whose silhouette pixels can be black.

    Examples
    --------
    >>> from lighting import Lambert, Material, DirectionalLight
    >>> from lighting.render.mesh import icosphere
    >>> cam = Camera((0, 0, 5.0), (0, 0, 0), width=32, height=32)
    >>> r = Renderer(icosphere(2), cam)
    >>> img = r.render(Material(Lambert(0.8)), [DirectionalLight((0, 0, 1.0))], mode="gouraud")
    >>> img.shape, r.rasterizations
    ((32, 32, 3), 1)
    >>> img2 = r.render(Material(Lambert(0.8)), [DirectionalLight((1, 0, 1.0))], mode="phong")
    >>> r.rasterizations  # moving the light did not re-rasterize
    1
    """

    def __init__(self, geometry, camera: Camera, *, dtype=np.float64, cull_backfaces: bool = True,
                 face_viewer: bool = False):  # fmt: skip
        _check_geometry(geometry)
        check_camera(camera)
        dt = check_float_dtype(dtype)
        self._geometry, self._camera, self.dtype = geometry, camera, dt.type
        self.cull_backfaces = check_bool("cull_backfaces", cull_backfaces)
        self.face_viewer = check_bool("face_viewer", face_viewer)
        self._gbuffer: GBuffer | None = None
        self._cache: dict = {}
        self._subset: np.ndarray | None = None
        #: How many times the geometry was rasterized (or ray-cast) so far.
        self.rasterizations = 0

    # ------------------------------------------------------------------ state
    @property
    def geometry(self):
        return self._geometry

    @geometry.setter
    def geometry(self, value):
        """Replace the geometry; a different object drops the geometry buffer and every cached sample.

        Parameters
        ----------
        value : TriangleMesh or AnalyticSphere
        """
        _check_geometry(value)
        if value is not self._geometry:
            self._geometry = value
            self._invalidate()

    @property
    def camera(self) -> Camera:
        return self._camera

    @camera.setter
    def camera(self, value: Camera):
        """Replace the camera; a different object drops the geometry buffer and every cached sample.

        Parameters
        ----------
        value : Camera
        """
        check_camera(value)
        if value is not self._camera:
            self._camera = value
            self._invalidate()

    def _invalidate(self):
        self._gbuffer = None
        self._cache = {}
        self._subset = None

    def restrict(self, subset) -> None:
        """Light only some covered pixels in ``"phong"`` mode: indices into ``gbuffer.pixels``, or ``None`` for all.

        A scene renderer passes the pixels where this object is not hidden
        behind another; per-vertex and per-face samples are unaffected.

        Parameters
        ----------
        subset : array_like of int, (M,), or None
            Positions in ``gbuffer.pixels`` (integers in ``[0, len(gbuffer.pixels))``); ``None`` lights every
            covered pixel.  A change drops the cached ``"phong"`` samples.
        """
        if subset is not None:
            n = len(self.gbuffer.pixels)
            arr = np.asarray(subset) if isinstance(subset, np.ndarray) else None
            if arr is None or arr.dtype.kind not in "iu":
                arr = real_array("subset", subset, allowed=f"indices into gbuffer.pixels (integers in [0, {n}))")
            if arr.ndim != 1 or (arr.size and (arr.min() < 0 or arr.max() >= n or np.any(arr != np.floor(arr)))):
                raise ValueError(f"subset must be a 1-D array of indices into gbuffer.pixels (integers in [0, {n})) "
                                 f"or None; got {quote(subset)}")  # fmt: skip
            subset = arr.astype(np.int64, copy=False)
        same = (subset is None and self._subset is None) or (
            subset is not None and self._subset is not None and np.array_equal(subset, self._subset)
        )
        if not same:
            self._subset = subset
            for key in [k for k in self._cache if k[1] == "phong"]:
                del self._cache[key]

    @property
    def gbuffer(self) -> GBuffer:
        """The geometry buffer, rasterized on first use and reused until geometry or camera change."""
        if self._gbuffer is None:
            check_image_budget(self._camera, RENDER_BYTES_PER_PIXEL, "rendering")
            g = self._geometry
            if isinstance(g, AnalyticSphere):
                self._gbuffer = raycast_sphere(self._camera, g.center, g.radius, dtype=self.dtype)
            else:
                self._gbuffer = rasterize(g, self._camera, cull_backfaces=self.cull_backfaces, dtype=self.dtype)
            self.rasterizations += 1
        return self._gbuffer

    def _cached(self, key, make):
        if key not in self._cache:
            self._cache[key] = make()
        return self._cache[key]

    def _need_mesh(self, mode):
        if not isinstance(self._geometry, TriangleMesh):
            raise ValueError(f"mode {mode!r} needs a triangle mesh; an analytic sphere supports only 'phong'")
        return self._geometry

    def sample_points(self, mode: str) -> np.ndarray:
        """Where lighting is evaluated in ``mode``: covered pixels, vertices, or triangle centroids, ``(N, 3)``.

        Like every sample array here it is cached until geometry or camera change,
        and column-major (one contiguous plane per component), the layout the
        per-component shading arithmetic runs fastest on.

        Parameters
        ----------
        mode : {"flat", "gouraud", "phong"}
            ``"flat"`` and ``"gouraud"`` need a triangle mesh.

        Returns
        -------
        numpy.ndarray
            ``(N, 3)`` Fortran-ordered, in the renderer's dtype: one row per lit pixel (phong), vertex (gouraud)
            or triangle (flat).  Cached: do not modify.
        """
        mode = check_choice("mode", mode, SHADING_MODES)

        def make():
            if mode == "phong":
                pts = self._take(self.gbuffer.covered_positions)
            elif mode == "gouraud":
                pts = self._need_mesh(mode).vertices
            else:  # flat: one sample per triangle, at its centroid
                mesh = self._need_mesh(mode)
                pts = mesh.vertices[mesh.faces].mean(axis=1)
            return np.asfortranarray(pts, dtype=self.dtype)

        return self._cached(("points", mode), make)

    def sample_normals(self, mode: str) -> np.ndarray:
        """Unit normals at :meth:`sample_points`: interpolated (phong), vertex (gouraud) or face (flat).

        Parameters
        ----------
        mode : {"flat", "gouraud", "phong"}

        Returns
        -------
        numpy.ndarray
            ``(N, 3)`` Fortran-ordered, in the renderer's dtype, row for row with :meth:`sample_points`
            (zero rows for degenerate faces or isolated vertices).  Cached: do not modify.
        """
        mode = check_choice("mode", mode, SHADING_MODES)
        if mode == "phong" and self.gbuffer.mesh is not None:
            return self._pixel_samples()[0]

        def make():
            if mode == "phong":
                nrm = self.gbuffer.normal.reshape(-1, 3).take(self.lit_pixels(), axis=0)
            elif mode == "gouraud":
                nrm = self._need_mesh(mode).normals
            else:
                nrm = self._need_mesh(mode).face_normals
            return np.asfortranarray(nrm, dtype=self.dtype)

        return self._cached(("normals", mode), make)

    def sample_view(self, mode: str):
        """The slides' ``v`` at :meth:`sample_points` and the eye distances (``None`` for orthographic).

        Parameters
        ----------
        mode : {"flat", "gouraud", "phong"}

        Returns
        -------
        v : numpy.ndarray
            ``(N, 3)`` unit vectors toward the eye in the renderer's dtype, or one ``(3,)`` vector for an
            orthographic camera.
        dist : numpy.ndarray or None
            ``(N,)`` ``float64`` eye distances; ``None`` for an orthographic camera.
        """
        mode = check_choice("mode", mode, SHADING_MODES)

        if mode == "phong":
            return self._pixel_samples()[1]

        def make():
            cam = self._camera
            pts = self.sample_points(mode)
            if cam.is_perspective:
                v, dist = view_vectors(pts, eye=cam.eye, dtype=self.dtype)
                return np.asfortranarray(v), dist
            return view_vectors(pts, view_dir=-cam.forward, dtype=self.dtype)

        return self._cached(("view", mode), make)

    def _pixel_samples(self):
        """``(unit normals or None, (v, eye distances))`` at the lit pixels, built by the shading threads.

        Each thread fills its own rows (those it will later shade) of arrays made
        here: interpolating and normalizing the normals and looking up the pixel
        rays are per-pixel work like shading itself.  The normals are ``None``
        for an analytic sphere (it has them exactly; see :meth:`sample_normals`).
        """

        def make():
            gb, cam, dt = self.gbuffer, self._camera, self.dtype
            pixels = self.lit_pixels()
            rows = self._subset
            depth = self._take(gb.covered_depth)
            n = len(pixels)
            normals = None
            if gb.mesh is not None:
                vertex_normals = gb.mesh.normals.astype(dt)
                normals = np.empty((n, 3), dtype=dt, order="F")
            if cam.is_perspective:
                v, dist = np.empty((n, 3), dtype=dt, order="F"), np.empty(n)
            else:
                v, dist = cam._pixel_view_vectors(pixels, dtype=dt)

            def fill(sl):
                if cam.is_perspective:
                    # The point seen at a pixel lies on that pixel's ray: v needs no interpolated position.
                    v[sl], dist[sl] = cam._pixel_view_vectors(pixels[sl], depth[sl], dtype=dt)
                if normals is not None:
                    n = normalize(gb.interpolate_covered(vertex_normals, sl if rows is None else rows[sl]))
                    normals[sl] = face_toward(n, v[sl] if v.ndim == 2 else v) if self.face_viewer else n

            each_chunk(n, fill)
            return normals, (v, dist)

        return self._cached(("pixel samples", "phong"), make)

    def sample_tangents(self, mode: str) -> np.ndarray:
        """Unit tangents ``⊥`` :meth:`sample_normals` that orient anisotropic models (see the module notes).

        Parameters
        ----------
        mode : {"flat", "gouraud", "phong"}

        Returns
        -------
        numpy.ndarray
            ``(N, 3)`` Fortran-ordered, in the renderer's dtype, row for row with :meth:`sample_points`:
            interpolated and re-orthonormalized per lit pixel (phong; the exact ``∂p/∂φ`` on the analytic
            sphere), the mesh's vertex tangents (gouraud) or the centroid's tangent made perpendicular to
            the face normal (flat).  Cached: do not modify.
        """
        mode = check_choice("mode", mode, SHADING_MODES)

        def make():
            dt = self.dtype
            if mode == "phong":
                normals = self.sample_normals(mode)
                gb = self.gbuffer
                if gb.mesh is None:  # the analytic sphere: its exact ∂p/∂φ about +y
                    return np.asfortranarray(sphere_tangents(normals), dtype=dt)
                vertex_tangents = gb.mesh.tangents.astype(dt)
                rows = self._subset
                out = np.empty(normals.shape, dtype=dt, order="F")

                def fill(sl):
                    # Interpolated like the normals, then made unit and perpendicular to the pixel's normal.
                    raw = gb.interpolate_covered(vertex_tangents, sl if rows is None else rows[sl])
                    out[sl] = orthonormal_tangents(raw, normals[sl])

                each_chunk(len(normals), fill)
                return out
            mesh = self._need_mesh(mode)
            if mode == "gouraud":
                return np.asfortranarray(mesh.tangents, dtype=dt)
            centroid = mesh.tangents[mesh.faces].mean(axis=1)
            return np.asfortranarray(orthonormal_tangents(centroid, mesh.face_normals), dtype=dt)

        return self._cached(("tangents", mode), make)

    def _samples(self, mode: str, lights=None, material=None):
        """Points, normals, view vectors, eye distances and tangents; points are ``None`` when ``lights`` need
        none, tangents when no part of ``material`` reads them."""
        v, dist = self.sample_view(mode)
        pts = self.sample_points(mode) if lights is None or _needs_points(lights) else None
        tangents = self.sample_tangents(mode) if material is not None and needs_tangents(material) else None
        return pts, self.sample_normals(mode), v, dist, tangents

    def _take(self, compact: np.ndarray) -> np.ndarray:
        return compact if self._subset is None else compact[self._subset]

    def lit_pixels(self) -> np.ndarray:
        """Flat indices of the pixels lit in ``"phong"`` mode (all covered ones unless restricted).

        Returns
        -------
        numpy.ndarray
            Increasing flat (row-major) pixel indices, one per sample of ``"phong"`` mode.
        """
        gb = self.gbuffer
        return gb.pixels if self._subset is None else gb.pixels[self._subset]

    def spread_pixels(self, mode: str, colours: np.ndarray):
        """Colours at :meth:`sample_points` as ``(flat pixel indices, (M, 3) values)``, without a full image.

        Parameters
        ----------
        mode : {"flat", "gouraud", "phong"}
        colours : numpy.ndarray
            ``(N, 3)``, one row per sample of ``mode``.

        Returns
        -------
        pixels : numpy.ndarray
            ``(M,)`` increasing flat row-major pixel indices (the lit pixels in ``"phong"`` mode, else all covered).
        values : numpy.ndarray
            ``(M, 3)`` colours at those pixels (``colours`` itself in ``"phong"`` mode; Gouraud-interpolated
            or per-face looked up otherwise, keeping the colours' float dtype).
        """
        mode = check_choice("mode", mode, SHADING_MODES)
        gb = self.gbuffer
        if mode == "phong":
            return self.lit_pixels(), colours
        if mode == "gouraud":
            return gb.pixels, gb.interpolate_covered(np.asarray(colours))
        return gb.pixels, np.asarray(colours)[gb.covered_triangle_ids]

    def _image_sink(self, dtype=None):
        """A zero ``(H, W, 3)`` image and ``put(row_slice, planes)`` that writes channel planes ``(3, m)``
        of the lit pixels ``row_slice`` into it (disjoint slices may be put from different threads)."""
        gb = self.gbuffer
        img = np.zeros(gb.shape + (3,), dtype=self.dtype if dtype is None else dtype)
        columns = img.reshape(-1, 3)
        pixels = self.lit_pixels()

        def put(rows, planes):
            for c in range(3):
                columns[:, c][pixels[rows]] = planes[c]

        return img, put

    def spread(self, mode: str, colours: np.ndarray) -> np.ndarray:
        """Turn colours at :meth:`sample_points` into an ``(H, W, 3)`` image (zero off the geometry).

        Parameters
        ----------
        mode : {"flat", "gouraud", "phong"}
        colours : numpy.ndarray
            ``(N, 3)``, one row per sample of ``mode``.

        Returns
        -------
        numpy.ndarray
            ``(H, W, 3)``: per pixel (phong, the colours' dtype), Gouraud-interpolated (gouraud) or looked up per
            triangle (flat); the latter two in float64 if the buffer or the colours are float64, else float32.
        """
        mode = check_choice("mode", mode, SHADING_MODES)
        gb = self.gbuffer
        if mode == "phong":
            colours = np.asarray(colours)
            img, put = self._image_sink(colours.dtype)
            put(slice(None), colours.T)
            return img
        if mode == "gouraud":
            return gb.interpolate(colours)
        return gb.per_face(colours)

    # ------------------------------------------------------------------ shading
    def render_terms(
        self,
        material: Material,
        lights,
        *,
        mode: str = "phong",
        form: str = "classic",
        terms=TERMS,
    ) -> dict[str, np.ndarray]:
        """Each term of the illumination equation as an ``(H, W, 3)`` image (zero off the object).

        Parameters
        ----------
        material, lights, mode, form, terms
            As :meth:`render`.

        Returns
        -------
        dict of str to numpy.ndarray
            One ``(H, W, 3)`` image per requested term.
        """
        mode = check_choice("mode", mode, SHADING_MODES)
        lights, envs = split_environment_lights(lights)
        lights = check_lights(lights)
        pts, nrm, v, dist, tan = self._samples(mode, lights, material)
        colours = shade_prepared_terms(pts, nrm, v, material, lights, eye_distance=dist, form=form, terms=terms,
                                       tangents=tan)  # fmt: skip
        images = {name: self.spread(mode, c) for name, c in colours.items()}
        for name, extra in self._environment_terms(material, envs, mode, form, images).items():
            images[name] = images[name] + extra
        return images

    def _environment_terms(self, material, envs, mode, form, wanted) -> dict:
        """The environment lights' diffuse and specular terms as images, for the terms in ``wanted``."""
        if not envs:
            return {}
        check_material(material)
        nrm = self.sample_normals(mode)
        sums = environment_terms(envs, material.brdf, nrm, self.sample_view(mode)[0], form=form, terms=wanted,
                                 dtype=self.dtype)  # fmt: skip
        return {t: self.spread(mode, c).astype(self.dtype, copy=False) for t, c in sums.items()}

    def _environment_background(self, envs, form):
        """The environment seen along each pixel's camera ray (``(H, W, 3)``), or None without one to show."""
        shown = [lt for lt in envs if lt.background]
        if not shown:
            return None
        _, dirs = self._camera.rays(dtype=self.dtype)
        total = sum(lt.radiance(dirs).astype(self.dtype, copy=False) for lt in shown)
        return total * (self.dtype(math.pi) if form == "classic" else self.dtype(1))

    def render(
        self,
        material: Material,
        lights,
        *,
        mode: str = "phong",
        form: str = "classic",
        terms=TERMS,
        background=0.0,
    ) -> np.ndarray:
        """Linear RGB image ``(H, W, 3)`` of the geometry under ``lights``.

        Parameters
        ----------
        material : Material
        lights : sequence of lights
            Punctual and area lights, and environment lights (:class:`~lighting.lights.envlight.EnvironmentLight`: their
            diffuse and specular terms join the others'; the environment is shown behind the geometry
            when the light's ``background`` is on, in place of ``background``).
        mode : {"flat", "gouraud", "phong"}
            When lighting is computed: per triangle, per vertex (colours
            interpolated), or per pixel (normals interpolated).
        form : {"classic", "physical"}
        terms : iterable of {"emission", "ambient", "diffuse", "specular"}
            Which terms of the illumination equation to include (the slides'
            decomposition, shown one at a time).
        background : scalar or RGB
            Colour of pixels the geometry does not cover.

        Returns
        -------
        LinearImage
            ``(H, W, 3)`` linear RGB in the renderer's dtype (an ``ndarray`` that shows itself
            sRGB-encoded in Jupyter; ``np.asarray(img)`` is the plain array).
        """
        bg = check_color("background", background)
        mode = check_choice("mode", mode, SHADING_MODES)
        lights, envs = split_environment_lights(lights)
        lights = check_lights(lights)
        pts, nrm, v, dist, tan = self._samples(mode, lights, material)
        if mode == "phong":
            img, put = self._image_sink()
            shade_prepared_into(
                put, pts, nrm, v, material, lights, eye_distance=dist, form=form, terms=terms,
                view_cache=self._cached(("view terms", mode), dict), tangents=tan,
            )  # fmt: skip
        else:
            colours = shade_prepared(pts, nrm, v, material, lights, eye_distance=dist, form=form, terms=terms,
                                     tangents=tan)  # fmt: skip
            img = self.spread(mode, colours)
        terms = tuple(terms) if not isinstance(terms, str) else (terms,)
        for extra in self._environment_terms(material, envs, mode, form, terms).values():
            img = img + extra
        behind = self._environment_background(envs, form)
        if behind is not None:
            img = np.where(self.gbuffer.coverage[..., None], img, behind + bg.astype(self.dtype))
        elif np.any(bg):
            img = np.where(self.gbuffer.coverage[..., None], img, bg.astype(self.dtype))
        return LinearImage(img.astype(self.dtype, copy=False))


def _check_geometry(geometry) -> None:
    if not isinstance(geometry, (TriangleMesh, AnalyticSphere)):
        raise ArgumentTypeError(f"geometry must be a TriangleMesh or an AnalyticSphere; got {type(geometry).__name__} "
                                f"{quote(geometry)}")  # fmt: skip


def needs_tangents(material: Material) -> bool:
    """Whether shading ``material`` may read surface tangents: a part's lobe is anisotropic, or unknown.

    Parameters
    ----------
    material : Material

    Returns
    -------
    bool
        False when every part describes an isotropic lobe (:attr:`lighting.models.protocol.Lobe.isotropic`):
        such models never read a tangent, so a renderer need not interpolate any.
    """
    # Checked here because the renderer asks before it shades: a wrong material gets the shading path's named error.
    for part in check_material(material).brdf.parts:
        lobe = part.lobe()
        if lobe is None or not lobe.isotropic:
            return True
    return False


def _needs_points(lights) -> bool:
    """Whether any light depends on where the surface point is (not ambient, not directional)."""
    return bool(positional_lights(lights))


def render(geometry, camera: Camera, material: Material, lights, **kwargs) -> np.ndarray:
    """One-shot :meth:`Renderer.render` (rasterizes, shades, returns the image).

    Parameters
    ----------
    geometry : TriangleMesh or AnalyticSphere
    camera : Camera
    material : Material
    lights : sequence of lights
    **kwargs
        ``dtype`` (of the :class:`Renderer`) and the keywords of :meth:`Renderer.render`.

    Returns
    -------
    LinearImage
        The ``(H, W, 3)`` linear RGB image (:class:`~lighting.render.linear_image.LinearImage`).
    """
    dtype = kwargs.pop("dtype", np.float64)
    return Renderer(geometry, camera, dtype=dtype).render(material, lights, **kwargs)

"""A pinhole (perspective) or orthographic camera: world → image and per-pixel rays.

World → image, step by step
---------------------------
1. Camera frame (right-handed, as OpenGL's ``gluLookAt``): forward
   ``f = (target − eye)/|…|``, right ``r = (f × up)/|…|``, true up ``u = r × f``.
2. Camera coordinates: ``x_c = r·(p − eye)``, ``y_c = u·(p − eye)``,
   ``z_c = −f·(p − eye)`` (the camera looks down its ``−z`` axis).  The
   view-space *depth* is ``d = −z_c = f·(p − eye)``, the distance along the
   viewing axis (not the Euclidean distance to the eye).
3. Image plane, in pixels, ``x`` to the right, ``y`` **down**, origin at the
   top-left corner of the image:

   * perspective: ``x = W/2 + F x_c / d``, ``y = H/2 − F y_c / d`` with the focal
     length in pixels ``F = (H/2) / tan(fov_y/2)``;
   * orthographic: ``x = W/2 + S x_c``, ``y = H/2 − S y_c`` with
     ``S = H / ortho_height`` pixels per world unit.

   Pixels are square.  Pixel ``(row i, column j)`` covers ``x ∈ [j, j+1]``,
   ``y ∈ [i, i+1]``; its centre, where it is sampled, is ``(j + ½, i + ½)``.
   The target projects to ``(W/2, H/2)``, the centre of the image.

:meth:`Camera.rays` inverts step 3 at the pixel centres: one ray per pixel,
from the eye (perspective) or from the image plane through the eye
(orthographic, all rays parallel to ``f``).  :meth:`Camera.project` of any point
on pixel ``(i, j)``'s ray returns ``(j + ½, i + ½)``.

The near and far distances bound the visible depths ``near ≤ d ≤ far``; the
rasterizer clips against them (:mod:`lighting.render.raster`).

Examples
--------
>>> cam = Camera(eye=(0, 0, 5), target=(0, 0, 0), width=64, height=48)
>>> xy, depth = cam.project((0, 0, 0))
>>> xy.tolist(), float(depth)
([32.0, 24.0], 5.0)
"""

from __future__ import annotations

import math

import numpy as np

from .._budget import check_budget
from .._text import quote
from .._validate import (
    ArgumentTypeError,
    check_choice,
    check_float_dtype,
    check_positive,
    check_range,
    check_vectors,
    real_array,
)
from ..numerics import as_float, cos_sin_deg, working_dtype
from ..vec import length, normalize

__all__ = ["Camera", "MAX_IMAGE_SIDE"]

#: Largest image width or height in pixels (the memory budget usually refuses far smaller images first).
MAX_IMAGE_SIDE = 1 << 16

_BIG = float(np.finfo(np.float64).max)


def _vec3(name: str, value) -> np.ndarray:
    a = real_array(name, value, allowed="a finite 3-vector (x, y, z)", dtype=np.float64)
    if a.shape != (3,):
        raise ValueError(f"{name} must be a finite 3-vector (x, y, z); got shape {a.shape}: {quote(value)}")
    a = a.copy()
    a.setflags(write=False)
    return a


def _size(name: str, value) -> int:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise ArgumentTypeError(f"{name} must be an integer >= 1 (pixels); got {type(value).__name__} {quote(value)}")
    if value < 1:
        raise ValueError(f"{name} must be an integer >= 1 (pixels); got {quote(value)}")
    if value > MAX_IMAGE_SIDE:
        raise ValueError(f"{name} must be an integer <= {MAX_IMAGE_SIDE} (pixels); got {quote(value)}")
    return int(value)


class Camera:
    """A look-at camera producing a ``width × height`` image.

    Parameters
    ----------
    eye, target : 3-vectors
        Camera position and the point it looks at (must differ).
    up : 3-vector, default (0, 1, 0)
        Roughly "up" in the image; must not be parallel to ``target − eye``.
    projection : {"perspective", "orthographic"}
    fov_y_deg : float, default 30
        Vertical field of view of the perspective camera, in (0, 180) degrees.
    ortho_height : float, default 2.5
        World height of the orthographic image (the default frames a unit sphere
        with a small margin).
    width, height : int, default 512
        Image size in pixels.
    near, far : float, optional
        Visible depth range.  Defaults: ``near = |target − eye| / 1000``,
        ``far = 1000 |target − eye|``.  ``0 < near < far``.

    Examples
    --------
    >>> cam = Camera.look_at((0, 0, 4), fov_y_deg=90, width=4, height=4)
    >>> round(cam.focal_px, 12)
    2.0
    >>> (cam.project((0, 4, 0))[0].round(12) + 0.0).tolist()  # 45° above the axis: the top edge of the image
    [2.0, 0.0]
    """

    def __init__(
        self,
        eye,
        target,
        up=(0.0, 1.0, 0.0),
        projection: str = "perspective",
        fov_y_deg: float = 30.0,
        ortho_height: float = 2.5,
        width: int = 512,
        height: int = 512,
        near: float | None = None,
        far: float | None = None,
    ):
        self.eye = _vec3("eye", eye)
        self.target = _vec3("target", target)
        self.up = _vec3("up", up)
        self.projection = check_choice("projection", projection, ("perspective", "orthographic"))
        self.fov_y_deg = check_range("fov_y_deg", fov_y_deg)
        if not 0 < self.fov_y_deg < 180:
            raise ValueError(f"fov_y_deg must be in (0, 180) degrees; got {quote(fov_y_deg)}")
        self.ortho_height = check_positive("ortho_height", ortho_height)
        self.width = _size("width", width)
        self.height = _size("height", height)

        with np.errstate(over="ignore", invalid="ignore"):
            d = self.target - self.eye
        # length() scales before squaring: eye 1e308 from the target is a distance, not an overflow.
        dist = float(length(d)) if np.all(np.isfinite(d)) else math.inf
        if not dist <= _BIG:
            raise ValueError(
                f"eye and target must be less than {_BIG:.3g} apart (target - eye overflows float64); "
                f"got eye={self.eye.tolist()}, target={self.target.tolist()}"
            )
        if not dist > 0:
            raise ValueError(f"eye and target must differ; got eye={self.eye.tolist()}, target={self.target.tolist()}")
        f = normalize(d)
        if not np.any(self.up != 0):
            raise ValueError(f"up must be a non-zero vector; got {self.up.tolist()}")
        s = np.cross(f, normalize(self.up))
        s_len = float(length(s))
        if not s_len > 1e-9:
            raise ValueError(
                f"up must not be parallel to the view direction target - eye = {d.tolist()}; got up={self.up.tolist()}"
            )
        r = s / s_len
        u = np.cross(r, f)
        for a in (f, r, u):
            a.setflags(write=False)
        self.forward, self.right, self.true_up = f, r, u
        self.distance = dist

        # The default depth range spans 1000× either way, within the float64 range.
        self.near = check_positive("near", near) if near is not None else max(dist / 1000, 5e-324)
        self.far = check_positive("far", far) if far is not None else min(dist * 1000, _BIG)
        if not self.far > self.near:
            raise ValueError(f"far must be > near = {self.near!r}; got far={quote(self.far)}")
        self._memo = {}  # quantities derived from the (immutable) camera alone, made on first use
        self._frozen = True

    def __setattr__(self, name, value):
        # A camera is a value (its derived frame would go stale): change it with replace().
        if getattr(self, "_frozen", False):
            raise AttributeError(f"Camera is immutable; use camera.replace({name}=...) instead")
        object.__setattr__(self, name, value)

    # ------------------------------------------------------------------ constructors
    @classmethod
    def look_at(cls, eye, target=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0), **options) -> Camera:
        """A camera at ``eye`` looking at ``target`` (default the origin); options as for :class:`Camera`.

        Parameters
        ----------
        eye, target : 3-vectors
            Camera position and the point it looks at (must differ); ``target`` defaults to the origin.
        up : 3-vector, default (0, 1, 0)
            Roughly "up" in the image; must not be parallel to ``target − eye``.
        **options
            The other keywords of :class:`Camera` (``projection``, ``fov_y_deg``, ``width``, ...).

        Returns
        -------
        Camera
        """
        return cls(eye, target, up, **options)

    @classmethod
    def orbit(
        cls,
        target=(0.0, 0.0, 0.0),
        *,
        distance: float = 5.0,
        azimuth_deg: float = 0.0,
        elevation_deg: float = 0.0,
        **options,
    ) -> Camera:
        """A y-up camera on a sphere around ``target``.

        ``eye = target + distance (cos e sin a, sin e, cos e cos a)``: azimuth
        ``a = 0``, elevation ``e = 0`` looks from ``+z`` toward ``−z``; azimuth
        turns toward ``+x``; elevation must stay inside (−90, 90) degrees (the
        view direction would be parallel to up).

        Parameters
        ----------
        target : 3-vector, default (0, 0, 0)
            The point looked at, the centre of the orbit.
        distance : float > 0, default 5
            Eye–target distance; the eye must stay finite in float64.
        azimuth_deg : float, default 0
            Turn about the y axis, in degrees, from ``+z`` toward ``+x``.
        elevation_deg : float in (-90, 90), default 0
            Angle above the xz plane, in degrees.
        **options
            The other keywords of :class:`Camera` (``up`` included, default ``(0, 1, 0)``).

        Returns
        -------
        Camera

        Examples
        --------
        >>> Camera.orbit(distance=2, azimuth_deg=90).eye.round(12).tolist()
        [2.0, 0.0, 0.0]
        """
        dist = check_positive("distance", distance)
        az = check_range("azimuth_deg", azimuth_deg)
        el = check_range("elevation_deg", elevation_deg)
        if not abs(el) < 90:
            raise ValueError(f"elevation_deg must be in (-90, 90); got {quote(elevation_deg)}")
        t = _vec3("target", target)
        # Exact at multiples of 90° (azimuth 90 puts the eye exactly on +x).
        ca, sa = (float(x) for x in cos_sin_deg(az))
        ce, se = (float(x) for x in cos_sin_deg(el))
        with np.errstate(over="ignore"):
            eye = t + dist * np.array([ce * sa, se, ce * ca])
        if not np.all(np.isfinite(eye)):
            raise ValueError(f"distance must keep the eye inside the float64 range around target={quote(t)}; "
                             f"got distance={quote(dist)}")  # fmt: skip
        return cls(eye, t, options.pop("up", (0.0, 1.0, 0.0)), **options)

    def replace(self, **changes) -> Camera:
        """A copy with some constructor arguments changed (e.g. ``width=128``).

        Changing ``eye`` or ``target`` without giving ``near``/``far`` resets them
        to their defaults for the new distance.

        Parameters
        ----------
        **changes
            Keywords of :class:`Camera`; an unknown name is a ValueError.

        Returns
        -------
        Camera
            A new camera (this one is immutable and unchanged).
        """
        args = dict(
            eye=self.eye,
            target=self.target,
            up=self.up,
            projection=self.projection,
            fov_y_deg=self.fov_y_deg,
            ortho_height=self.ortho_height,
            width=self.width,
            height=self.height,
            near=self.near,
            far=self.far,
        )
        unknown = set(changes) - set(args)
        if unknown:
            raise ValueError(f"unknown Camera parameter(s) {quote(sorted(unknown))}; allowed: {sorted(args)}")
        if ("eye" in changes or "target" in changes) and not {"near", "far"} & set(changes):
            args["near"] = args["far"] = None  # keep the defaults relative to the new distance
        args.update(changes)
        return Camera(**args)

    def __repr__(self) -> str:
        extra = (
            f"fov_y_deg={self.fov_y_deg}" if self.projection == "perspective" else f"ortho_height={self.ortho_height}"
        )
        return (
            f"Camera(eye={self.eye.tolist()}, target={self.target.tolist()}, up={self.up.tolist()}, "
            f"projection={self.projection!r}, {extra}, width={self.width}, height={self.height}, "
            f"near={self.near}, far={self.far})"
        )

    # ------------------------------------------------------------------ derived numbers
    @property
    def is_perspective(self) -> bool:
        return self.projection == "perspective"

    @property
    def focal_px(self) -> float:
        """Perspective focal length in pixels, ``F = (H/2) / tan(fov_y/2)``."""
        return (self.height / 2) / math.tan(math.radians(self.fov_y_deg) / 2)

    @property
    def pixels_per_unit(self) -> float:
        """Orthographic scale ``S = H / ortho_height`` (pixels per world unit)."""
        return self.height / self.ortho_height

    @property
    def shape(self) -> tuple[int, int]:
        """Image shape ``(height, width)``."""
        return (self.height, self.width)

    def view_matrix(self) -> np.ndarray:
        """4×4 world → camera matrix (column vectors), rows ``r``, ``u``, ``−f``.

        ``[x_c, y_c, z_c, 1]ᵀ = V [p, 1]ᵀ``, exactly the ``gluLookAt`` matrix.

        Returns
        -------
        numpy.ndarray
            ``(4, 4)`` ``float64``, a new array.

        Examples
        --------
        >>> V = Camera((0, 0, 5), (0, 0, 0)).view_matrix()
        >>> (V @ [0, 0, 0, 1]).tolist()
        [0.0, 0.0, -5.0, 1.0]
        """
        V = np.eye(4)
        R = np.stack([self.right, self.true_up, -self.forward])
        V[:3, :3] = R
        V[:3, 3] = -R @ self.eye
        return V

    def _check_image_budget(self, what: str, bytes_per_pixel: float) -> None:
        """Refuse (BudgetError) work whose per-pixel arrays would exceed the memory budget."""
        n = self.width * self.height
        check_budget(f"{what} of a {self.width}x{self.height} camera", n * bytes_per_pixel,
                     what=f"{n} pixels x {bytes_per_pixel:g} bytes")  # fmt: skip

    # ------------------------------------------------------------------ mappings
    def world_to_camera(self, points) -> np.ndarray:
        """Camera coordinates ``(x_c, y_c, z_c)`` of world points, shape ``(..., 3)``; keeps the dtype.

        Parameters
        ----------
        points : array_like, (..., 3)
            Finite world points; float32 (or smaller float) input gives float32, anything else float64.

        Returns
        -------
        numpy.ndarray
            ``(..., 3)`` camera coordinates (``−z_c`` is the view depth), in the input's float dtype;
            values beyond that dtype's range saturate at its largest finite number.
        """
        return self._world_to_camera(check_vectors("points", points))

    def _world_to_camera(self, points) -> np.ndarray:
        """:meth:`world_to_camera` on checked points (the rasterizer's path); saturates instead of overflowing."""
        dt = working_dtype(points)
        p = as_float(points, dt)
        R = np.stack([self.right, self.true_up, -self.forward]).astype(dt)
        with np.errstate(over="ignore", invalid="ignore"):
            q = (p - self.eye.astype(dt)) @ R.T
        big = np.finfo(dt).max
        if not np.all(np.isfinite(q)):
            # Points beyond the float range of the eye (1e38 in float32): their coordinates saturate.
            q = np.clip(np.nan_to_num(q, nan=0.0, posinf=big, neginf=-big), -big, big)
        return q

    def camera_to_pixels(self, cam_points):
        """Step 3 of the module notes on camera coordinates: ``(xy (..., 2), depth (...))``.

        Perspective points with depth ``≤ 0`` (at or behind the eye) have no image:
        their ``xy`` is returned as 0; check ``depth >= near`` before using it.

        Parameters
        ----------
        cam_points : array_like, (..., 3)
            Finite camera-space points, as :meth:`world_to_camera` returns them.

        Returns
        -------
        xy : numpy.ndarray, (..., 2)
            Pixel coordinates (``x`` right, ``y`` down), as in :meth:`project`, in the input's float dtype.
        depth : numpy.ndarray, (...)
            View depth ``−z_c``, same dtype.
        """
        c = check_vectors("cam_points", cam_points)
        return self._camera_to_pixels(c)

    def _camera_to_pixels(self, c):
        depth = -c[..., 2]
        cx, cy = self.width / 2, self.height / 2
        if self.is_perspective:
            F = self.focal_px
            ok = depth > 0
            with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                inv = np.where(ok, F / np.where(ok, depth, 1), 0)
            x = np.where(ok, cx + c[..., 0] * inv, 0)
            y = np.where(ok, cy - c[..., 1] * inv, 0)
        else:
            S = self.pixels_per_unit
            with np.errstate(over="ignore"):
                x = cx + S * c[..., 0]
                y = cy - S * c[..., 1]
        xy = np.stack([x, y], axis=-1).astype(c.dtype, copy=False)
        return xy, depth

    def project(self, points):
        """Pixel coordinates and view-space depth of world points.

        Parameters
        ----------
        points : array_like, shape (..., 3)

        Returns
        -------
        xy : ndarray, shape (..., 2)
            ``(x, y)`` in pixels, ``x`` right, ``y`` down, pixel ``(i, j)``
            centred at ``(j + ½, i + ½)``.  Perspective: ``x = W/2 + F x_c/d``,
            ``y = H/2 − F y_c/d``; orthographic: ``x = W/2 + S x_c``,
            ``y = H/2 − S y_c``.  Zero for perspective points with ``d ≤ 0``.
        depth : ndarray, shape (...)
            ``d = f·(p − eye)``.

        Examples
        --------
        >>> cam = Camera((0, 0, 10), (0, 0, 0), projection="orthographic", ortho_height=4, width=8, height=8)
        >>> cam.project([[1.0, 1.0, 0.0], [1.0, 1.0, 3.0]])[0].tolist()  # orthographic: depth does not matter
        [[6.0, 2.0], [6.0, 2.0]]
        """
        return self._camera_to_pixels(self.world_to_camera(points))

    def pixel_centers(self, dtype=np.float64) -> np.ndarray:
        """``(H, W, 2)`` pixel-centre coordinates ``(j + ½, i + ½)``.

        Parameters
        ----------
        dtype : float32 or float64, default float64
            Of the result; an image over the memory budget is refused (``BudgetError``, a ValueError).

        Returns
        -------
        numpy.ndarray
            ``(H, W, 2)`` in ``dtype``: ``[..., 0]`` is ``x = j + ½``, ``[..., 1]`` is ``y = i + ½``.
        """
        dtype = check_float_dtype(dtype).type
        self._check_image_budget("pixel_centers", 2 * 3 * np.dtype(dtype).itemsize)
        jj, ii = np.meshgrid(np.arange(self.width, dtype=dtype), np.arange(self.height, dtype=dtype))
        return np.stack([jj + 0.5, ii + 0.5], axis=-1)

    def rays(self, dtype=np.float64):
        """One ray per pixel through the pixel centre: ``(origins, directions)``, each ``(H, W, 3)``.

        Perspective: origin ``eye``, direction
        ``normalize(f + ((x − W/2) r − (y − H/2) u) / F)``.  Orthographic: origin
        ``eye + ((x − W/2) r − (y − H/2) u) / S`` on the plane through the eye,
        direction ``f``.  Directions are unit vectors; a point at parameter ``t``
        has depth ``t (dir·f)``.

        Parameters
        ----------
        dtype : float32 or float64, default float64
            Of both arrays (computed in float64 and rounded once); an image over the memory budget is refused
            (``BudgetError``, a ValueError).

        Returns
        -------
        origins : numpy.ndarray
            ``(H, W, 3)`` in ``dtype``.
        directions : numpy.ndarray
            ``(H, W, 3)`` unit vectors in ``dtype``.

        Examples
        --------
        >>> o, d = Camera((0, 0, 5), (0, 0, 0), width=3, height=3).rays()
        >>> d[1, 1].tolist(), o[1, 1].tolist()  # the centre pixel looks straight at the target
        ([0.0, 0.0, -1.0], [0.0, 0.0, 5.0])
        """
        dtype = check_float_dtype(dtype).type
        self._check_image_budget("rays", 6 * np.dtype(dtype).itemsize + 7 * 8)
        o, d = self.ray_components()
        shape = (self.height, self.width, 3)
        origins = np.empty(shape, dtype=dtype)
        directions = np.empty(shape, dtype=dtype)
        for c in range(3):
            origins[..., c] = o[c]
            directions[..., c] = d[c]
        return origins, directions

    def ray_components(self):
        """:meth:`rays` as per-component float64 arrays: ``([ox, oy, oz], [dx, dy, dz])``.

        Each component broadcasts to ``(H, W)``: perspective origins are
        scalars, orthographic directions too.  Cheaper than :meth:`rays` for
        code that works component by component.

        Returns
        -------
        origins : list of 3
            ``float64`` scalars (perspective) or arrays broadcasting to ``(H, W)`` (orthographic).
        directions : list of 3
            ``float64`` arrays broadcasting to ``(H, W)`` (perspective) or scalars (orthographic).
        """
        dx = (np.arange(self.width) + 0.5 - self.width / 2)[None, :]
        dy = (np.arange(self.height) + 0.5 - self.height / 2)[:, None]
        f, r, u = self.forward, self.right, self.true_up
        if self.is_perspective:
            F = self.focal_px
            d = [f[c] + (dx * r[c] - dy * u[c]) / F for c in range(3)]
            inv = 1 / np.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
            return [np.float64(e) for e in self.eye], [dc * inv for dc in d]
        S = self.pixels_per_unit
        o = [self.eye[c] + (dx * r[c] - dy * u[c]) / S for c in range(3)]
        return o, [np.float64(fc) for fc in f]

    def pixel_view_vectors(self, pixels, depth=None, *, dtype=np.float64):
        """The slides' ``v`` at the surface points seen through ``pixels``, and their eye distances.

        Perspective: the point seen at pixel ``(i, j)`` lies on that pixel's ray
        (:meth:`rays`), so ``v = −normalize(f + ((x − W/2) r − (y − H/2) u) / F)``
        at ``x = j + ½``, ``y = i + ½`` exactly, whatever surface is there: no
        position is needed.  The unnormalized ray has component 1 along ``f``,
        so a point at view depth ``d`` is ``d |f + …|`` from the eye.
        Orthographic: ``v = −f`` everywhere and there are no eye distances.

        Parameters
        ----------
        pixels : (M,) int
            Flat row-major pixel indices ``i W + j``.
        depth : (M,) float, optional
            View-space depths of the points (for the eye distances).
        dtype : float32 or float64
            Of ``v`` (computed in float64 and rounded once).

        Returns
        -------
        v : (M, 3) column-major array, or (3,) for an orthographic camera
        dist : (M,) float64, or None (orthographic, or no depth)

        Examples
        --------
        >>> cam = Camera((0, 0, 5), (0, 0, 0), width=3, height=3)
        >>> v, dist = cam.pixel_view_vectors([4], depth=[5.0])  # the centre pixel
        >>> (v + 0.0).tolist(), dist.tolist()  # (+ 0.0 turns the -0.0 components into 0.0)
        ([[0.0, 0.0, 1.0]], [5.0])
        """
        dt = check_float_dtype(dtype).type
        n_pix = self.width * self.height
        p = real_array("pixels", pixels, allowed=f"integer pixel indices in [0, {n_pix})")
        if p.ndim != 1 or not np.all((p >= 0) & (p < n_pix) & (p == np.floor(p))):
            raise ValueError(f"pixels must be a 1-D array of integer pixel indices in [0, {n_pix}); "
                             f"got {quote(pixels)}")  # fmt: skip
        if depth is not None:
            depth = real_array("depth", depth)
            if depth.shape != p.shape or np.any(depth < 0):
                raise ValueError(f"depth must be finite depths >= 0, one per pixel ({len(p)}); got {quote(depth)}")
        return self._pixel_view_vectors(np.asarray(pixels).astype(np.int64), depth, dtype=dt)

    def _pixel_view_vectors(self, pixels, depth=None, *, dtype=np.float64):
        """:meth:`pixel_view_vectors` on checked arguments (the renderer's path)."""
        dt = np.dtype(dtype).type
        if not self.is_perspective:
            return (-self.forward).astype(dt), None
        p = np.asarray(pixels, dtype=np.int64)
        planes, length = self._pixel_view_planes(dt)
        v = np.empty((len(p), 3), dtype=dt, order="F")
        for c in range(3):
            planes[c].take(p, out=v[:, c])
        if depth is None:
            return v, None
        with np.errstate(over="ignore"):
            dist = np.minimum(np.asarray(depth, dtype=np.float64) * length.take(p), _BIG)
        return v, dist

    def _pixel_view_planes(self, dt):
        """``−ray`` direction per pixel as three flat ``(H W,)`` planes in ``dt``, and the unnormalized ray lengths.

        Computed once per camera and dtype (a camera is immutable): the image's
        rays are a property of the camera alone, like its matrices.
        """
        key = ("view planes", np.dtype(dt).str)
        if key not in self._memo:
            o, d = self.ray_components()
            shape = (self.height, self.width)
            planes = [np.ascontiguousarray(np.broadcast_to(-dc, shape), dtype=dt).reshape(-1) for dc in d]
            x = (np.arange(self.width) + 0.5 - self.width / 2)[None, :] / self.focal_px
            y = (np.arange(self.height) + 0.5 - self.height / 2)[:, None] / self.focal_px
            # f, r, u are orthonormal: |f + x r − y u|² = 1 + x² + y².
            length = np.sqrt(1 + (x * x + y * y)).reshape(-1)
            self._memo[key] = (planes, length)
        return self._memo[key]

    def view_direction(self, points) -> np.ndarray:
        """The slides' ``v``: unit vectors from ``points`` toward the viewer, ``(..., 3)``.

        Perspective: ``normalize(eye − p)`` (zero at the eye itself);
        orthographic: the constant ``−f`` (the viewer is at infinity).

        Parameters
        ----------
        points : array_like, (..., 3)
            Finite world points; float32 (or smaller float) input gives float32, anything else float64.

        Returns
        -------
        numpy.ndarray
            ``(..., 3)`` unit vectors (a new array) in the input's float dtype.

        Examples
        --------
        >>> Camera((0, 0, 5), (0, 0, 0)).view_direction([[3.0, 0.0, 1.0]]).tolist()
        [[-0.6, 0.0, 0.8]]
        """
        p = check_vectors("points", points)
        dt = p.dtype.type
        if self.is_perspective:
            return normalize(self.eye.astype(dt) - p)
        return np.broadcast_to((-self.forward).astype(dt), p.shape).copy()


def check_camera(camera) -> Camera:
    """``camera`` itself if it is a :class:`Camera`, else an ``ArgumentTypeError`` naming what was given.

    Parameters
    ----------
    camera : Camera

    Returns
    -------
    Camera
        The same object.
    """
    if not isinstance(camera, Camera):
        raise ArgumentTypeError(f"camera must be a Camera; got {type(camera).__name__} {quote(camera)}")
    return camera

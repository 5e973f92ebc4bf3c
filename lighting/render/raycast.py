"""Ray casting the exact sphere into a geometry buffer: the ground truth of tessellated renderings."""

from __future__ import annotations

import numpy as np

from .._text import quote
from .._validate import check_float_dtype, check_positive, real_array
from .camera import Camera, check_camera
from .gbuffer import GBuffer, check_image_budget

__all__ = ["raycast_sphere"]

#: Peak bytes per image pixel of ray casting (about twenty float64 planes; measured with tracemalloc at
#: 1024², rounded up).
RAYCAST_BYTES_PER_PIXEL = 224


def raycast_sphere(camera: Camera, center=(0.0, 0.0, 0.0), radius: float = 1.0, dtype=np.float64) -> GBuffer:
    """Ray-cast the exact sphere ``|p − c| = r`` into a :class:`GBuffer` (the ground truth).

    For the unit-direction ray ``o + t d``, with ``f = o − c``:
    ``t² + 2 (f·d) t + |f|² − r² = 0``.  Following Haines et al., "Precision
    Improvements for Ray/Sphere Intersection" (Ray Tracing Gems, 2019), the
    discriminant is computed as ``r² − |f − (f·d) d|²`` (no cancellation for
    small spheres far away) and the roots as ``q = −(f·d) − sign(f·d) √disc``,
    ``t₁ = q``, ``t₀ = (|f|² − r²) / q`` (no cancellation between ``−(f·d)`` and
    ``√disc``).  The nearest root with depth in ``[near, far]`` is kept.

    Position ``p = o + t d``, normal ``(p − c) / r``; ``triangle_id`` is 0 on the
    sphere and −1 elsewhere, ``barycentric`` is zero, ``face_normal`` equals
    ``normal``.  Computed in float64, returned in ``dtype``.

    Parameters
    ----------
    camera : Camera
    center : 3-vector
        The sphere's centre ``c``.
    radius : float > 0
        The sphere's radius ``r``.
    dtype : {numpy.float64, numpy.float32}
        Float dtype of the buffer.

    Returns
    -------
    GBuffer
        With ``mesh = None`` and the exact positions and normals as attributes.

    Examples
    --------
    >>> from lighting.render.camera import Camera
    >>> cam = Camera((0, 0, 5), (0, 0, 0), projection="orthographic", ortho_height=3, width=5, height=5)
    >>> gb = raycast_sphere(cam)  # pixel centres at x, y = 0, ±0.6, ±1.2
    >>> gb.coverage.astype(int)
    array([[0, 0, 0, 0, 0],
           [0, 1, 1, 1, 0],
           [0, 1, 1, 1, 0],
           [0, 1, 1, 1, 0],
           [0, 0, 0, 0, 0]])
    >>> float(gb.depth[2, 2])  # the centre ray hits (0, 0, 1)
    4.0
    """
    check_camera(camera)
    dt = check_float_dtype(dtype)
    r = check_positive("radius", radius)
    c = real_array("center", center, allowed="one finite 3-vector (x, y, z)", dtype=np.float64)
    if c.shape != (3,):
        raise ValueError(f"center must be one finite 3-vector (x, y, z); got shape {c.shape}: {quote(center)}")
    check_image_budget(camera, RAYCAST_BYTES_PER_PIXEL, "ray casting a sphere")
    # Spheres and cameras near the float range (radius 1e200, an eye 1e308 away) overflow the quadratic's
    # terms: such pixels are misses (or their hits are dropped below), never NaN in the buffer.
    with np.errstate(over="ignore", invalid="ignore", under="ignore"):
        return _raycast_sphere(camera, c, r, dt)


def _raycast_sphere(camera, c, r, dt):
    H, W = camera.height, camera.width
    o, d = camera.ray_components()
    o = [np.broadcast_to(oc, (H, W)) for oc in o]
    d = [np.broadcast_to(dc, (H, W)) for dc in d]
    f = [o[k] - c[k] for k in range(3)]
    b = f[0] * d[0] + f[1] * d[1] + f[2] * d[2]
    closest2 = sum((f[k] - b * d[k]) ** 2 for k in range(3))
    disc = r * r - closest2
    # Everything else only where the line meets the sphere.
    pix = np.flatnonzero(disc >= 0)
    b, disc = b.reshape(-1)[pix], disc.reshape(-1)[pix]
    f = [fk.reshape(-1)[pix] for fk in f]
    d = [dk.reshape(-1)[pix] for dk in d]
    o = [ok.reshape(-1)[pix] for ok in o]
    sq = np.sqrt(disc)
    q = -(b + np.where(b >= 0, sq, -sq))
    cc = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - r * r
    # q = 0 is replaced by 1 before dividing; overflow and NaN are silenced by raycast_sphere's errstate.
    t_other = np.where(q != 0, cc / np.where(q != 0, q, 1), 0)
    t_near = np.minimum(q, t_other)
    t_far = np.maximum(q, t_other)
    fw = camera.forward
    cosf = d[0] * fw[0] + d[1] * fw[1] + d[2] * fw[2]
    base = (o[0] - camera.eye[0]) * fw[0] + (o[1] - camera.eye[1]) * fw[1] + (o[2] - camera.eye[2]) * fw[2]
    dn, df = base + t_near * cosf, base + t_far * cosf
    ok_n = (dn >= camera.near) & (dn <= camera.far)
    ok_f = ~ok_n & (df >= camera.near) & (df <= camera.far)
    keep = np.flatnonzero(ok_n | ok_f)
    t = np.where(ok_n, t_near, t_far)[keep]
    pix = pix[keep]
    p = np.stack([o[k][keep] + t * d[k][keep] for k in range(3)], axis=1)
    n = (p - c) / r
    finite = np.all(np.isfinite(p), axis=1) & np.all(np.isfinite(n), axis=1)
    finite &= np.all(np.abs(p) <= np.finfo(dt).max, axis=1)  # representable in the buffer's dtype
    if not np.all(finite):
        keep, t, pix, p, n = keep[finite], t[finite], pix[finite], p[finite], n[finite]
    z = (base[keep] + t * cosf[keep]).astype(dt)
    facing = n[:, 0] * d[0][keep] + n[:, 1] * d[1][keep] + n[:, 2] * d[2][keep] < 0

    def image(values, fill=0):
        out = np.full((H * W,) + values.shape[1:], fill, dtype=values.dtype)
        out[pix] = values
        return out.reshape((H, W) + values.shape[1:])

    p, n = image(p.astype(dt)), image(n.astype(dt))
    cov = image(np.ones(len(pix), dtype=bool), False)
    return GBuffer(
        triangle_id=image(np.zeros(len(pix), dtype=np.int32), -1),
        barycentric=np.zeros((H, W, 3), dtype=dt),
        depth=image(z),
        coverage=cov,
        front_facing=image(facing, False),
        overdraw=cov.astype(np.int32),
        camera=camera,
        mesh=None,
        attributes={"position": p, "normal": n, "normal_unnormalized": n, "face_normal": n},
    )

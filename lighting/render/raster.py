"""A vectorized NumPy rasterizer producing a geometry buffer for a separate lighting pass.

:func:`rasterize` turns a :class:`~lighting.render.mesh.TriangleMesh` seen by a
:class:`~lighting.render.camera.Camera` into a :class:`~lighting.render.gbuffer.GBuffer`:
for every pixel, which triangle is visible there, where on it (barycentric
coordinates), at what depth, and the interpolated position and normals.

:func:`~lighting.render.raycast.raycast_sphere` fills the same buffer for the exact
sphere by ray casting (both names are importable from here too).

How a pixel is decided
----------------------
* Sampling: one sample per pixel, at its centre ``(j + ½, i + ½)`` (see
  :mod:`lighting.render.camera` for pixel coordinates).
* Edge functions (Pineda, "A parallel algorithm for polygon rasterization",
  SIGGRAPH 1988): for the edge from ``a`` to ``b``,
  ``E(p) = (b_x − a_x)(p_y − a_y) − (b_y − a_y)(p_x − a_x)``, signed so the
  triangle's interior is where all three are positive.  Each edge is evaluated
  from a canonical endpoint (the lexicographically smaller screen point) and
  then negated as needed, so two triangles sharing an edge compute bit-identical
  values of opposite sign: no pixel along a shared edge is missed or covered
  twice, whatever the rounding.
* Fill rule for samples exactly on an edge (``E = 0``): top-left, as Direct3D
  specifies and GPUs implement — a sample on a *left* edge (interior to its
  right) or a *top* edge (horizontal, interior below, ``y`` down) belongs to the
  triangle, on a right or bottom edge it does not.  An axis-aligned square with
  corners on pixel centres therefore covers exactly (side)² pixels, and a sample
  on a vertex shared by a fan of triangles goes to exactly one of them.
* Back faces: a triangle whose projected vertices run clockwise on screen (with
  ``y`` up; counter-clockwise in pixel coordinates, ``y`` down) faces away from
  the camera and is dropped when ``cull_backfaces`` (the default; a closed mesh
  then draws each visible pixel exactly once).
* Near and far planes: triangles entirely nearer than ``camera.near`` or entirely
  farther than ``camera.far`` are dropped; triangles crossing the near plane are
  **clipped** against it in camera space (one or two sub-triangles that keep the
  original triangle id and report barycentrics of the original triangle), so a
  camera close to or inside a mesh shows no holes.  Samples farther than
  ``camera.far`` are discarded per pixel.
* Depth test: the smallest view-space depth wins; exact ties go to the
  triangle that comes first in ``mesh.faces``.
* Perspective-correct interpolation: with screen-space barycentrics
  ``λ_i = E_i / Σ E`` and vertex depths ``d_i``, the depth is
  ``d = 1 / Σ (λ_i / d_i)`` and the barycentrics of the 3-D triangle are
  ``b_i = (λ_i / d_i) d`` (the screen-linear ``λ`` are exact for an
  orthographic camera, ``b = λ``, ``d = Σ λ_i d_i``).

Speed: every triangle's bounding box is cut into row spans, and each span is
narrowed to the columns its row can cover (from the edge functions, widened by
one pixel; the exact test below decides).  A batch of spans (about 65,000
candidate pixels) is expanded into all its (triangle, pixel) candidates at once
with ``np.repeat`` and tested with the edge functions.  The depth test runs once
over all fragments: a pixel with one fragment keeps it, pixels with several
settle the nearest (then the lowest face index) with two running minima
(``np.minimum.at``), no sort.  The winners are then put in pixel order (one
int32 scatter of their indices, gathers in the output dtype) and kept as the
buffer's covered pixels; its images are scattered from them when first read.
The loop runs over batches only, never over pixels or triangles (docs/images.md
gives the timings).

Examples
--------
>>> from lighting.render.camera import Camera
>>> from lighting.render.mesh import icosphere
>>> cam = Camera((0, 0, 5), (0, 0, 0), width=64, height=64)
>>> gb = rasterize(icosphere(3), cam)
>>> gb.coverage.shape, bool(gb.coverage[32, 32]), int(gb.overdraw.max())
((64, 64), True, 1)
>>> bool(np.allclose(gb.interpolate(icosphere(3).vertices), gb.position))
True
"""

from __future__ import annotations

import numpy as np

from .._text import quote
from .._validate import ArgumentTypeError, check_bool, check_float_dtype
from .camera import Camera, check_camera
from .gbuffer import GBuffer, check_image_budget
from .mesh import TriangleMesh
from .raycast import raycast_sphere

__all__ = ["GBuffer", "rasterize", "raycast_sphere"]

#: Peak bytes per image pixel of rasterizing (a few (H, W) index and depth arrays; measured with
#: tracemalloc at 1024², rounded up).
RASTER_BYTES_PER_PIXEL = 128

# Candidate (triangle, pixel) pairs per batch.  Small batches keep the temporaries (~20 arrays of
# this length) in cache and reuse the allocator's memory; the fastest of 2^14..2^18 on the benchmark.
_BATCH = 1 << 16


# ---------------------------------------------------------------------- rasterizer
def _lex_less(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a < b`` lexicographically over the last axis (rows of 2 or 3 numbers)."""
    less = a[..., -1] < b[..., -1]
    for c in range(a.shape[-1] - 2, -1, -1):
        less = (a[..., c] < b[..., c]) | ((a[..., c] == b[..., c]) & less)
    return less


def _clip_near(cam_tri: np.ndarray, near: float):
    """Clip triangles (n, 3, 3) in camera space against the plane ``depth = near``.

    Each triangle has one or two vertices nearer than ``near``.  Returns the
    sub-triangles (m, 3, 3), the index of their source triangle (m,), and their
    vertices' barycentric weights over the source triangle's vertices (m, 3, 3).
    The point where an edge crosses the plane is computed from the edge's
    lexicographically smaller endpoint, so neighbours sharing the edge get
    identical points (no crack at the near plane).
    """
    n = len(cam_tri)
    depth = -cam_tri[..., 2]
    behind = depth < near
    one_front = behind.sum(axis=1) == 2
    # Rotate (keeping the winding) so slot 0 holds the odd vertex out: the front one of
    # a triangle with two behind, the behind one of a triangle with one behind.
    odd = np.where(one_front, np.argmin(behind, axis=1), np.argmax(behind, axis=1))
    rot = (odd[:, None] + np.arange(3)) % 3
    rows = np.arange(n)[:, None]
    P = cam_tri[rows, rot]
    d = depth[rows, rot]
    eye3 = np.eye(3)
    W = eye3[rot]  # weights of the rotated vertices over the source vertices

    def crossing(k):
        lo_first = _lex_less(P[:, 0], P[:, k])
        plo = np.where(lo_first[:, None], P[:, 0], P[:, k])
        phi = np.where(lo_first[:, None], P[:, k], P[:, 0])
        dlo = np.where(lo_first, d[:, 0], d[:, k])
        dhi = np.where(lo_first, d[:, k], d[:, 0])
        t = (near - dlo) / (dhi - dlo)  # one endpoint is in front, the other behind: dhi != dlo
        pt = plo + t[:, None] * (phi - plo)
        wlo = np.where(lo_first[:, None], W[:, 0], W[:, k])
        whi = np.where(lo_first[:, None], W[:, k], W[:, 0])
        return pt, (1 - t)[:, None] * wlo + t[:, None] * whi

    A, wA = crossing(1)
    B, wB = crossing(2)
    f1 = np.flatnonzero(one_front)
    f2 = np.flatnonzero(~one_front)
    tris = [
        np.stack([P[f1, 0], A[f1], B[f1]], axis=1),
        np.stack([A[f2], P[f2, 1], P[f2, 2]], axis=1),
        np.stack([A[f2], P[f2, 2], B[f2]], axis=1),
    ]
    weights = [
        np.stack([W[f1, 0], wA[f1], wB[f1]], axis=1),
        np.stack([wA[f2], W[f2, 1], W[f2, 2]], axis=1),
        np.stack([wA[f2], W[f2, 2], wB[f2]], axis=1),
    ]
    return np.concatenate(tris), np.concatenate([f1, f2, f2]), np.concatenate(weights)


class _Setup:
    """Per raster triangle data, column-wise (contiguous 1-D arrays gather fast).

    ``x[k], y[k], d[k]``: screen position and depth of vertex ``k`` of each triangle.
    ``coef[k]``: for edge ``k`` (vertex ``k`` → ``k + 1``) the canonical endpoint
    ``(ax, ay)`` and the signed direction ``(ex, ey)`` of
    ``E'_k(p) = ex (p_y − a_y) − ey (p_x − a_x)``, positive inside.
    """

    def __init__(self, x, y, d, area2, source, weights, front, dt):
        self.n = len(source)
        self.inv_area = (1 / np.abs(area2)).astype(dt)
        orient = np.where(area2 < 0, -1, 1).astype(dt)  # sign that makes the interior positive
        coef = np.empty((3, 4, self.n), dtype=dt)
        topleft = np.empty((self.n, 3), dtype=bool)
        for k in range(3):
            k1 = (k + 1) % 3
            # Canonical endpoint: the lexicographically smaller (x, y); a neighbour sharing the
            # edge picks the same one and computes bit-identical values.
            swap = (x[k1] < x[k]) | ((x[k1] == x[k]) & (y[k1] < y[k]))
            ax, ay = np.where(swap, x[k1], x[k]), np.where(swap, y[k1], y[k])
            bx, by = np.where(swap, x[k], x[k1]), np.where(swap, y[k], y[k1])
            sgn = np.where(swap, -orient, orient)
            ex = sgn * (bx - ax)
            ey = sgn * (by - ay)
            coef[k, 0], coef[k, 1], coef[k, 2], coef[k, 3] = ax, ay, ex, ey
            # The gradient (-ey, ex) of E' points inward.  Top-left rule: keep E' = 0 when it points
            # right (a left edge), or straight down (a top edge: y grows downward).
            topleft[:, k] = (-ey > 0) | ((ey == 0) & (ex > 0))
        self.coef = coef
        self.topleft = topleft
        self.depth = [np.asarray(dk, dtype=dt) for dk in d]
        self.inv_area_depth = [(self.inv_area / dk).astype(dt) for dk in d]
        self.source = source
        self.weights = weights
        self.clipped = None if weights is None else ~np.all(weights == np.eye(3), axis=(1, 2))
        self.front = front


def _depth_of(setup: _Setup, t, e, perspective: bool):
    """View depth at samples from their edge functions, and the barycentric weights.

    ``λ_i = E'_{i+1} / |2A|`` (vertex ``i`` is opposite edge ``i + 1``).
    Perspective: ``w_i = λ_i / d_i``, ``d = 1 / Σ w_i`` and ``b_i = w_i d``;
    orthographic: ``b_i = λ_i``, ``d = Σ λ_i d_i``.  Returns ``(d, [w_0, w_1, w_2])``
    (``w = λ`` for orthographic).  The z-test and the final buffer both use this,
    so the stored depth is the one that won the test.
    """
    if perspective:
        # w_i = E'_{i+1} / (|2A| d_i), with 1 / (|2A| d_i) formed once per triangle.
        w = [e[(i + 1) % 3] * setup.inv_area_depth[i].take(t) for i in range(3)]
        return 1 / (w[0] + w[1] + w[2]), w
    inv_a = setup.inv_area.take(t)
    lam = [e[1] * inv_a, e[2] * inv_a, e[0] * inv_a]
    return lam[0] * setup.depth[0].take(t) + lam[1] * setup.depth[1].take(t) + lam[2] * setup.depth[2].take(t), lam


def rasterize(mesh: TriangleMesh, camera: Camera, *, cull_backfaces: bool = True, dtype=np.float64) -> GBuffer:
    """Rasterize ``mesh`` as seen by ``camera`` into a :class:`GBuffer`.

    Parameters
    ----------
    mesh : TriangleMesh
    camera : Camera
    cull_backfaces : bool, default True
        Drop triangles facing away from the camera (see the module notes).
        With False, both sides are drawn; :attr:`GBuffer.front_facing` tells which
        side is seen (the normals are not flipped).
    dtype : float32 or float64
        Float type of the buffer.  Coverage, depth test and barycentrics are
        computed in float64 either way (the same pixels are covered).

    Returns
    -------
    GBuffer

    Examples
    --------
    >>> from lighting.render.camera import Camera
    >>> from lighting.render.mesh import TriangleMesh
    >>> square = TriangleMesh([[-2, -2, 0], [2, -2, 0], [2, 2, 0], [-2, 2, 0]], [[0, 1, 2], [0, 2, 3]])
    >>> cam = Camera((0, 0, 5), (0, 0, 0), projection="orthographic", ortho_height=8, width=8, height=8)
    >>> gb = rasterize(square, cam)  # the square spans pixels 2..5 in x and y
    >>> gb.coverage.astype(int)[1:7, 1:7]
    array([[0, 0, 0, 0, 0, 0],
           [0, 1, 1, 1, 1, 0],
           [0, 1, 1, 1, 1, 0],
           [0, 1, 1, 1, 1, 0],
           [0, 1, 1, 1, 1, 0],
           [0, 0, 0, 0, 0, 0]])
    """
    if not isinstance(mesh, TriangleMesh):
        raise ArgumentTypeError(f"mesh must be a TriangleMesh; got {type(mesh).__name__} {quote(mesh)}")
    check_camera(camera)
    cull_backfaces = check_bool("cull_backfaces", cull_backfaces)
    out_dt = check_float_dtype(dtype)
    check_image_budget(camera, RASTER_BYTES_PER_PIXEL, "rasterizing")
    # Screen-space arithmetic is float64 whatever the output dtype: coverage is decided identically
    # for float32 and float64 buffers.  Triangles whose screen quantities overflow are dropped; the
    # local errstate keeps such extreme (finite) inputs free of warnings.
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        return _rasterize(mesh, camera, cull_backfaces, out_dt)


def _rasterize(mesh: TriangleMesh, camera: Camera, cull_backfaces: bool, out_dt: np.dtype) -> GBuffer:
    dt = np.dtype(np.float64)
    H, W = camera.height, camera.width
    perspective = camera.is_perspective

    # ---- geometry: camera space, near/far culling, near clipping
    cam_v = camera._world_to_camera(mesh.vertices)  # float64
    fcol = [np.ascontiguousarray(mesh.faces[:, k]) for k in range(3)]
    vdepth = -cam_v[:, 2]
    fd = [vdepth.take(f) for f in fcol]
    n_behind = sum((dk < camera.near).astype(np.int8) for dk in fd)
    visible = (n_behind < 3) & (np.minimum(np.minimum(fd[0], fd[1]), fd[2]) <= camera.far)
    whole = np.flatnonzero(visible & (n_behind == 0))
    cut = np.flatnonzero(visible & (n_behind > 0))
    # Project each vertex once: triangles sharing a vertex see bit-identical screen coordinates.
    xy_v, _ = camera._camera_to_pixels(cam_v)
    X, Y = xy_v[:, 0].astype(dt), xy_v[:, 1].astype(dt)
    idx = [f.take(whole) for f in fcol]
    x = [X.take(i) for i in idx]
    y = [Y.take(i) for i in idx]
    d = [dk.take(whole) for dk in fd]
    source = whole
    weights = None
    if len(cut):
        sub, sub_src, sub_w = _clip_near(cam_v[mesh.faces[cut]], camera.near)
        sub_xy, sub_d = camera._camera_to_pixels(sub)
        sub_xy = sub_xy.astype(dt)
        x = [np.concatenate([x[k], sub_xy[:, k, 0]]) for k in range(3)]
        y = [np.concatenate([y[k], sub_xy[:, k, 1]]) for k in range(3)]
        d = [np.concatenate([d[k], sub_d[:, k]]) for k in range(3)]
        source = np.concatenate([whole, cut[sub_src]])
        weights = np.concatenate([np.broadcast_to(np.eye(3), (len(whole), 3, 3)), sub_w])
    area2 = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0])
    # With y down, a triangle counter-clockwise seen from the camera (y up), i.e. facing it, has area2 < 0.
    front = area2 < 0
    keep = (front if cull_backfaces else area2 != 0) & np.isfinite(area2)
    # Pixel-centre bounding box: columns j with j + ½ in [min x, max x], clipped to the image.
    j0 = np.maximum(np.ceil(np.minimum(np.minimum(x[0], x[1]), x[2]) - 0.5), 0)
    j1 = np.minimum(np.floor(np.maximum(np.maximum(x[0], x[1]), x[2]) - 0.5), W - 1)
    i0 = np.maximum(np.ceil(np.minimum(np.minimum(y[0], y[1]), y[2]) - 0.5), 0)
    i1 = np.minimum(np.floor(np.maximum(np.maximum(y[0], y[1]), y[2]) - 0.5), H - 1)
    keep &= (j1 >= j0) & (i1 >= i0)
    kept = np.flatnonzero(keep)
    setup = _Setup(
        [a.take(kept) for a in x],
        [a.take(kept) for a in y],
        [a.take(kept) for a in d],
        area2.take(kept),
        source.take(kept),
        None if weights is None else weights[kept],
        front.take(kept),
        dt,
    )
    j0, j1, i0, i1 = (a.take(kept).astype(np.int64) for a in (j0, j1, i0, i1))

    # ---- candidates: one "span" per (triangle, pixel row of its bounding box); a batch is a run of
    # spans with about _BATCH candidate pixels, generated at once with np.repeat.
    half = dt.type(0.5)
    ny = i1 - i0 + 1
    stri = np.repeat(np.arange(setup.n), ny)
    srow = np.repeat(i0 - (np.cumsum(ny) - ny), ny) + np.arange(len(stri))
    spy = srow.astype(dt) + half
    # Per edge k: E'_k = ex (py - ay) - ey (px - ax).  The first product is constant along a span.
    rowterm, sax, sey = [], [], []
    for k in range(3):
        ax, ay, ex, ey = (setup.coef[k, c].take(stri) for c in range(4))
        rowterm.append(ex * (spy - ay))
        sax.append(ax)
        sey.append(ey)
    # Tighten each span to the columns its row can cover, widened by one pixel each way.  The
    # coverage test below stays the exact edge-function test, so any superset of the covered
    # columns gives the same image; the bounds only spare candidates (2.5x fewer on a sphere).
    sj0, sj1 = _span_columns(j0[stri], j1[stri], rowterm, sax, sey, dt)
    live = np.flatnonzero(sj1 >= sj0)
    stri, srow, sj0, sj1 = stri[live], srow[live], sj0[live], sj1[live]
    rowterm, sax, sey = ([a[live] for a in arrs] for arrs in (rowterm, sax, sey))
    scount = sj1 - sj0 + 1
    spx0 = sj0.astype(dt) + half
    spix0 = srow * W + sj0
    pix, z, t, w = _raster_spans(scount, spx0, sax, sey, rowterm, stri, spix0, setup, perspective, camera, dt)

    # ---- depth test, once over all fragments.  Overdraw counts every sample that passed the coverage
    # test; a pixel with one fragment keeps it, and among several the nearest wins, then the lowest
    # mesh face index (two running minima, no sort).
    counts = np.bincount(pix, minlength=H * W)
    multi = counts.take(pix) > 1
    if multi.any():
        m = np.flatnonzero(multi)
        pm, zm = pix[m], z[m]
        nearest = np.full(H * W, np.inf, dtype=dt)
        np.minimum.at(nearest, pm, zm)
        m = m[zm == nearest.take(pm)]
        src = setup.source.take(t[m])
        first = np.full(H * W, np.iinfo(np.int64).max, dtype=np.int64)
        np.minimum.at(first, pix[m], src)
        m = m[src == first.take(pix[m])]
        _, once = np.unique(pix[m], return_index=True)  # (one raster triangle per face and pixel)
        win = np.concatenate([np.flatnonzero(~multi), m[once]])
        pix, z, t, w = pix[win], z[win], t[win], [wk[win] for wk in w]

    # The buffer keeps the winners in pixel order (its images are scattered from them only when
    # read): one int32 scatter of the winners' indices, then gathers in the output dtype (float32
    # gathers cost a fraction of float64 ones here, the arrays then fit in cache).
    slot = np.full(H * W, -1, dtype=np.int32)
    slot[pix] = np.arange(len(pix), dtype=np.int32)
    pixels = np.flatnonzero(slot >= 0)  # (a boolean scan: several times faster than one over counts)
    order = slot.take(pixels)

    def in_pixel_order(a):
        return a.take(order)

    # The barycentrics b_i = w_i d (perspective; orthographic b_i = λ_i = w_i), clipped
    # sub-triangles' converted to their source triangle's, rounded once to the output dtype.
    bary = np.empty((3, len(pix)), dtype=dt)
    for k in range(3):
        if perspective:
            np.multiply(w[k], z, out=bary[k])
        else:
            bary[k] = w[k]
    if setup.weights is not None:
        p = np.flatnonzero(setup.clipped.take(t))
        bary[:, p] = np.einsum("in,nij->jn", bary[:, p], setup.weights[t.take(p)])
    return GBuffer._from_fragments(
        (H, W),
        pixels,
        in_pixel_order(setup.source.take(t).astype(np.int32)),
        [in_pixel_order(bary[k].astype(out_dt, copy=False)) for k in range(3)],
        in_pixel_order(z.astype(out_dt)),
        None if setup.front.all() else in_pixel_order(setup.front.take(t)),  # with back faces culled, all are
        counts,
        camera,
        mesh,
    )


def _span_columns(j0, j1, rowterm, sax, sey, dt):
    """First and last candidate column of each span: where its row can lie inside all three edges.

    ``E'_k(p_x) = rowterm_k − e_y (p_x − a_x) ≥ 0`` bounds ``p_x`` from above where
    ``e_y > 0`` and from below where ``e_y < 0`` at ``a_x + rowterm_k / e_y``; an edge
    with ``e_y = 0`` covers the whole row or none of it.  Each bound is widened by
    one column (rounding of the quotient) and clipped to the bounding box ``[j0, j1]``;
    a span nobody covers comes back with ``j1 < j0``.
    """
    lo, hi = j0.astype(dt), j1.astype(dt)
    empty = np.zeros(len(j0), dtype=bool)
    for r, ax, ey in zip(rowterm, sax, sey, strict=True):
        x = r / np.where(ey == 0, 1, ey)
        x += ax
        # fmin / fmax ignore a NaN bound (no constraint); the box clips infinite ones.
        hi = np.where(ey > 0, np.fmin(hi, np.floor(x - 0.5) + 1), hi)
        lo = np.where(ey < 0, np.fmax(lo, np.ceil(x - 0.5) - 1), lo)
        empty |= (ey == 0) & (r < 0)
    lo = np.minimum(lo, j1 + 1)  # finite and in the box before the integer conversion
    hi = np.where(empty, lo - 1, np.maximum(hi, lo - 1))
    return lo.astype(np.int64), hi.astype(np.int64)


def _raster_spans(scount, spx0, sax, sey, rowterm, stri, spix0, setup, perspective, camera, dt):
    """All fragments of the spans, generated in batches of about ``_BATCH`` candidate pixels.

    Returns the covered samples nearer than ``camera.far``: pixel indices, depths,
    raster triangle indices and the three barycentric weights.
    """
    cum = np.cumsum(scount)
    total = int(cum[-1]) if len(cum) else 0
    batch = max(_BATCH, camera.width)
    bounds = np.unique(np.r_[0, np.searchsorted(cum, np.arange(batch, total, batch), side="right"), len(cum)])
    longest = int(np.max(cum[bounds[1:] - 1] - np.r_[0, cum[bounds[1:-1] - 1]])) if total else 0
    k_int = np.arange(longest, dtype=np.int64)
    k_flt = k_int.astype(dt)
    out = []
    for s, e in zip(bounds[:-1], bounds[1:], strict=False):
        if e <= s:
            continue
        c = scount[s:e]
        n = int(c.sum())
        first = np.cumsum(c) - c
        # Exact in float: small integers and halves.
        px = np.repeat(spx0[s:e] - first.astype(dt), c)
        px += k_flt[:n]
        edge = []
        for k in range(3):
            term = px - np.repeat(sax[k][s:e], c)
            term *= np.repeat(sey[k][s:e], c)
            r = np.repeat(rowterm[k][s:e], c)
            r -= term
            edge.append(r)
        e0, e1, e2 = edge
        sel = np.flatnonzero((e0 >= 0) & (e1 >= 0) & (e2 >= 0))
        t = np.repeat(stri[s:e], c)[sel]
        e0, e1, e2 = e0[sel], e1[sel], e2[sel]
        # Samples exactly on an edge: only top-left edges own them.
        on = (e0 == 0) | (e1 == 0) | (e2 == 0)
        if on.any():
            tl = setup.topleft[t]
            ok = ~(((e0 == 0) & ~tl[:, 0]) | ((e1 == 0) & ~tl[:, 1]) | ((e2 == 0) & ~tl[:, 2]))
            sel, e0, e1, e2, t = sel[ok], e0[ok], e1[ok], e2[ok], t[ok]
        pix = np.repeat(spix0[s:e] - first, c)[sel] + k_int[sel]
        z, w = _depth_of(setup, t, (e0, e1, e2), perspective)
        ok = z <= camera.far
        if not ok.all():
            pix, z, t, w = pix[ok], z[ok], t[ok], [wk[ok] for wk in w]
        out.append((pix, z, t, w))
    if not out:
        empty = np.zeros(0, dtype=dt)
        return np.zeros(0, dtype=np.int64), empty, np.zeros(0, dtype=np.int64), [empty] * 3
    if len(out) == 1:
        return out[0]
    cat = np.concatenate
    return (cat([o[0] for o in out]), cat([o[1] for o in out]), cat([o[2] for o in out]),
            [cat([o[3][k] for o in out]) for k in range(3)])  # fmt: skip

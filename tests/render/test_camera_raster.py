"""Camera mappings, the rasterizer's coverage/depth/interpolation, and the ray-cast analytic sphere."""

import math

import mpmath
import numpy as np
import pytest

from lighting.render.camera import Camera
from lighting.render.mesh import TriangleMesh, icosphere
from lighting.render.raster import GBuffer, rasterize, raycast_sphere


def pixel_centres(cam):
    jj, ii = np.meshgrid(np.arange(cam.width) + 0.5, np.arange(cam.height) + 0.5)
    return jj, ii


def quad(p0, p1, p2, p3, diagonal=0):
    """Two triangles (counter-clockwise p0 p1 p2 p3) sharing the diagonal p0-p2 (0) or p1-p3 (1)."""
    faces = [[0, 1, 2], [0, 2, 3]] if diagonal == 0 else [[0, 1, 3], [1, 2, 3]]
    return TriangleMesh([p0, p1, p2, p3], faces)


# One pixel per world unit: world (x, y) lands on pixel coordinates (32 + x, 32 - y).
ORTHO64 = Camera((0, 0, 10), (0, 0, 0), projection="orthographic", ortho_height=64, width=64, height=64)


# ====================================================================== camera
CAMERAS = [
    Camera((0.3, 0.4, 5.0), (0.0, 0.0, 0.0), width=96, height=64),
    Camera((2.0, -1.0, 3.0), (0.5, 0.2, -0.3), up=(0.2, 1.0, 0.1), fov_y_deg=55, width=80, height=81),
    Camera((-4.0, 2.0, 1.0), (0.0, 0.0, 0.0), projection="orthographic", ortho_height=3.0, width=70, height=50),
]


@pytest.mark.parametrize("cam", CAMERAS)
def test_target_projects_to_the_image_centre_and_up_is_up(cam):
    xy, depth = cam.project(cam.target)
    np.testing.assert_allclose(xy, [cam.width / 2, cam.height / 2], atol=1e-12)
    assert depth == pytest.approx(np.linalg.norm(cam.target - cam.eye), rel=1e-15)
    (xu, yu), _ = cam.project(cam.target + 0.1 * cam.true_up)
    (xr, yr), _ = cam.project(cam.target + 0.1 * cam.right)
    assert xu == pytest.approx(cam.width / 2, abs=1e-12) and yu < cam.height / 2  # above: smaller y
    assert xr > cam.width / 2 and yr == pytest.approx(cam.height / 2, abs=1e-12)
    # The frame is right-handed and orthonormal, with up as close to the given up as possible.
    R = np.stack([cam.right, cam.true_up, -cam.forward])
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-15)
    assert np.linalg.det(R) == pytest.approx(1, abs=1e-15)
    assert np.dot(cam.true_up, cam.up) > 0


@pytest.mark.parametrize("cam", CAMERAS)
def test_view_matrix_is_look_at_and_matches_world_to_camera(cam):
    rng = np.random.default_rng(1)
    p = rng.normal(size=(20, 3))
    V = cam.view_matrix()
    hom = np.c_[p, np.ones(len(p))] @ V.T
    np.testing.assert_allclose(hom[:, :3], cam.world_to_camera(p), atol=1e-14)
    np.testing.assert_allclose(V @ np.r_[cam.eye, 1], [0, 0, 0, 1], atol=1e-14)
    # The target lies on the -z axis at its distance.
    np.testing.assert_allclose(V @ np.r_[cam.target, 1], [0, 0, -cam.distance, 1], atol=1e-14)


def test_perspective_and_orthographic_size_relations():
    pers = Camera((0, 0, 4), (0, 0, 0), fov_y_deg=40, width=200, height=100)
    F = 50 / math.tan(math.radians(20))
    assert pers.focal_px == pytest.approx(F, rel=1e-15)
    for depth in (2.0, 4.0, 8.0):
        (x0, y0), _ = pers.project((0.0, 0.0, 4 - depth))
        (x1, y1), _ = pers.project((0.0, 0.5, 4 - depth))
        assert y0 - y1 == pytest.approx(F * 0.5 / depth, rel=1e-14)  # size ∝ 1 / depth
    # A point at half the field of view above the axis lands on the top edge (y = 0).
    (x, y), _ = pers.project((0.0, 3 * math.tan(math.radians(20)), 1.0))
    assert y == pytest.approx(0, abs=1e-12) and x == pytest.approx(100, abs=1e-12)
    ortho = Camera((0, 0, 4), (0, 0, 0), projection="orthographic", ortho_height=2.5, width=200, height=100)
    assert ortho.pixels_per_unit == 40
    for z in (-3.0, 0.0, 3.0):
        xy, _ = ortho.project([(0.0, 0.0, z), (0.5, 0.5, z)])
        np.testing.assert_allclose(xy[1] - xy[0], [20, -20], rtol=1e-15)  # independent of depth
    # The orthographic image is ortho_height tall: the top edge is at y = +1.25.
    assert ortho.project((0.0, 1.25, 0.0))[0][1] == pytest.approx(0, abs=1e-12)


@pytest.mark.parametrize("cam", CAMERAS)
def test_rays_hit_what_project_says(cam):
    o, d = cam.rays()
    assert o.shape == d.shape == (cam.height, cam.width, 3)
    np.testing.assert_allclose(np.linalg.norm(d, axis=-1), 1, atol=1e-15)
    jj, ii = pixel_centres(cam)
    for t in (0.5, 3.0, 10.0):
        xy, depth = cam.project(o + t * d)
        np.testing.assert_allclose(xy[..., 0], jj, atol=1e-11)
        np.testing.assert_allclose(xy[..., 1], ii, atol=1e-11)
        np.testing.assert_allclose(depth, t * (d @ cam.forward), rtol=1e-13)
    if cam.is_perspective:
        np.testing.assert_array_equal(o, np.broadcast_to(cam.eye, o.shape))
    else:
        np.testing.assert_allclose(d, np.broadcast_to(cam.forward, d.shape), atol=0)
        np.testing.assert_allclose((o - cam.eye) @ cam.forward, 0, atol=1e-14)  # origins on the eye plane


def test_view_direction():
    p = np.array([[3.0, 0.0, 1.0], [0.0, -4.0, 2.0]])
    pers = Camera((0, 0, 5), (0, 0, 0))
    np.testing.assert_allclose(pers.view_direction(p), [[-0.6, 0, 0.8], [0, 0.8, 0.6]], rtol=1e-15)
    ortho = Camera((0, 0, 5), (0, 0, 0), projection="orthographic")
    np.testing.assert_array_equal(ortho.view_direction(p), [[0, 0, 1.0]] * 2)
    assert pers.view_direction(p.astype(np.float32)).dtype == np.float32
    assert pers.project(p.astype(np.float32))[0].dtype == np.float32


def test_orbit_and_replace():
    cam = Camera.orbit((1.0, 0.0, 0.0), distance=2.0, azimuth_deg=90.0, elevation_deg=30.0, width=32, height=16)
    np.testing.assert_allclose(cam.eye, [1 + 2 * math.cos(math.pi / 6), 1.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(cam.project(cam.target)[0], [16, 8], atol=1e-12)
    small = cam.replace(width=8, projection="orthographic")
    assert (small.width, small.height, small.projection) == (8, 16, "orthographic")
    np.testing.assert_array_equal(small.eye, cam.eye)
    with pytest.raises(ValueError, match=r"unknown Camera parameter\(s\) \['zoom'\]"):
        cam.replace(zoom=2)
    with pytest.raises(AttributeError, match=r"Camera is immutable; use camera.replace\(width=...\)"):
        cam.width = 3
    moved = cam.replace(eye=(1.0, 0.0, 10.0))
    assert moved.near == pytest.approx(moved.distance / 1000) and moved.far == pytest.approx(1000 * moved.distance)


def test_camera_validation_messages():
    with pytest.raises(ValueError, match=r"eye and target must differ; got eye=\[1.0, 2.0, 3.0\]"):
        Camera((1, 2, 3), (1, 2, 3))
    with pytest.raises(ValueError, match="up must not be parallel to the view direction"):
        Camera((0, 5, 0), (0, 0, 0))
    with pytest.raises(ValueError, match="up must be a non-zero vector"):
        Camera((0, 0, 5), (0, 0, 0), up=(0, 0, 0))
    for fov in (0, 180, -5, float("nan"), 200):
        with pytest.raises(ValueError, match="fov_y_deg must be"):
            Camera((0, 0, 5), (0, 0, 0), fov_y_deg=fov)
    with pytest.raises(ValueError, match=r"fov_y_deg must be in \(0, 180\) degrees; got 180"):
        Camera((0, 0, 5), (0, 0, 0), fov_y_deg=180)
    with pytest.raises(ValueError, match="ortho_height must be a finite number > 0; got 0.0"):
        Camera((0, 0, 5), (0, 0, 0), ortho_height=0)
    with pytest.raises(ValueError, match=r"width must be an integer >= 1 \(pixels\); got 0"):
        Camera((0, 0, 5), (0, 0, 0), width=0)
    with pytest.raises(ValueError, match="height must be an integer >= 1"):
        Camera((0, 0, 5), (0, 0, 0), height=12.5)
    with pytest.raises(ValueError, match="far must be > near = 2.0; got far=1.0"):
        Camera((0, 0, 5), (0, 0, 0), near=2, far=1)
    with pytest.raises(ValueError, match="projection must be one of 'perspective', 'orthographic'; got 'fisheye'"):
        Camera((0, 0, 5), (0, 0, 0), projection="fisheye")
    with pytest.raises(ValueError, match="eye must be a finite 3-vector"):
        Camera((0, np.inf, 5), (0, 0, 0))
    with pytest.raises(ValueError, match=r"elevation_deg must be in \(-90, 90\)"):
        Camera.orbit(elevation_deg=90)


# ====================================================================== rasterizer: coverage
def test_axis_aligned_square_covers_exactly_its_area():
    for diagonal in (0, 1):
        # Corners on pixel centres (x, y ∈ {10.5, 20.5}): the top-left rule keeps the left and top
        # edges, drops the right and bottom ones: exactly 10 x 10 pixels, rows and columns 10..19.
        # The diagonal runs through pixel centres too; each is covered once.
        gb = rasterize(quad((-21.5, 21.5, 0), (-21.5, 11.5, 0), (-11.5, 11.5, 0), (-11.5, 21.5, 0), diagonal), ORTHO64)
        assert gb.coverage.sum() == 100
        assert np.array_equal(np.argwhere(gb.coverage).min(0), [10, 10])
        assert np.array_equal(np.argwhere(gb.coverage).max(0), [19, 19])
        assert gb.overdraw.max() == 1
        # Corners on pixel corners: also 100 pixels.
        gb = rasterize(quad((-22, 22, 0), (-22, 12, 0), (-12, 12, 0), (-12, 22, 0), diagonal), ORTHO64)
        assert gb.coverage.sum() == 100 and gb.overdraw.max() == 1
        # General position: x ∈ [10.3, 30.7] holds centres 10.5..30.5 (21), y ∈ [5.2, 9.9] holds 5.5..9.5 (5).
        gb = rasterize(quad((-21.7, 26.8, 0), (-21.7, 22.1, 0), (-1.3, 22.1, 0), (-1.3, 26.8, 0), diagonal), ORTHO64)
        assert gb.coverage.sum() == 21 * 5 and gb.overdraw.max() == 1
        assert np.array_equal(np.argwhere(gb.coverage).min(0), [5, 10])


def test_fill_rule_on_a_fan_around_a_pixel_centre():
    # Eight triangles meeting at a vertex that sits exactly on the pixel centre (32.5, 32.5), with
    # spokes through other pixel centres: every pixel of the octagon is drawn exactly once.
    c = np.array([0.5, -0.5, 0.0])
    ring = [c + [8 * math.cos(a), 8 * math.sin(a), 0] for a in np.arange(8) * math.pi / 4]
    ring = [np.round(p * 2) / 2 for p in ring]  # on the half-integer grid: spokes pass through centres
    V = np.vstack([c, ring])
    F = [[0, 1 + k, 1 + (k + 1) % 8] for k in range(8)]
    gb = rasterize(TriangleMesh(V, F), ORTHO64)
    both = rasterize(TriangleMesh(V, F), ORTHO64, cull_backfaces=False)
    assert gb.overdraw.max() == 1 and gb.coverage[32, 32]
    np.testing.assert_array_equal(both.overdraw, gb.overdraw)
    # Same set of pixels as the octagon drawn as a fan from a ring vertex instead.
    G = [[1, 1 + k, 2 + k] for k in range(1, 7)]
    alt = rasterize(TriangleMesh(V, G), ORTHO64)
    np.testing.assert_array_equal(alt.coverage, gb.coverage)
    assert alt.overdraw.max() == 1


def test_shared_edges_through_pixel_centres_are_decided_consistently():
    # Edges passing (up to rounding) through the pixel centre (32.5, 32.5).  Evaluated naively from
    # each triangle's own start vertex, the two triangles' edge functions round differently and can
    # both claim (or both reject) the centre; the rasterizer evaluates a shared edge once, from a
    # canonical endpoint, so the centre is drawn exactly once.
    rng = np.random.default_rng(11)
    p = np.array([32.5, 32.5])
    cases = 0
    for _ in range(400):
        a_px = rng.uniform(0, 64, 2)
        b_px = p + rng.uniform(0.3, 3) * (p - a_px)
        # World points whose projections are these pixel positions (x = X - 32, y = 32 - Y here).
        a = np.array([a_px[0] - 32, 32 - a_px[1], 0.0])
        b = np.array([b_px[0] - 32, 32 - b_px[1], 0.0])
        (ax, ay), (bx, by) = ORTHO64.project(np.stack([a, b]))[0]
        e_from_a = (bx - ax) * (p[1] - ay) - (by - ay) * (p[0] - ax)
        e_from_b = (ax - bx) * (p[1] - by) - (ay - by) * (p[0] - bx)
        if not (e_from_a * e_from_b > 0):  # naive evaluation consistent: not an interesting case
            continue
        normal = np.array([-(b - a)[1], (b - a)[0], 0.0]) / np.linalg.norm(b - a) * 20
        mid = (a + b) / 2
        m = TriangleMesh(np.stack([a, b, mid + normal, mid - normal]), [[0, 1, 2], [1, 0, 3]])
        gb = rasterize(m, ORTHO64, cull_backfaces=False)
        assert gb.overdraw[32, 32] == 1 and gb.overdraw.max() == 1
        cases += 1
        if cases == 12:
            break
    assert cases == 12


def test_jittered_grid_tiles_exactly_like_two_triangles():
    rng = np.random.default_rng(7)
    n = 12
    u = np.linspace(-1, 1, n + 1)
    X, Y = np.meshgrid(u, u)
    interior = (np.abs(X) < 1) & (np.abs(Y) < 1)
    X = X + interior * rng.uniform(-0.3, 0.3, X.shape) * (2 / n)
    Y = Y + interior * rng.uniform(-0.3, 0.3, Y.shape) * (2 / n)
    V = np.stack([X.ravel(), Y.ravel(), np.zeros(X.size)], axis=1)
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel()
    flip = rng.random(a.size) < 0.5  # random diagonals
    F = np.concatenate(
        [
            np.where(flip[:, None], np.stack([a, b, d], 1), np.stack([a, b, c], 1)),
            np.where(flip[:, None], np.stack([a, d, c], 1), np.stack([b, d, c], 1)),
        ]
    )
    grid = TriangleMesh(V, F)
    square = quad((-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0))
    cam = Camera((0.4, -0.7, 2.5), (0.05, 0.02, 0.0), fov_y_deg=60, width=160, height=120)
    g, s = rasterize(grid, cam), rasterize(square, cam)
    assert s.coverage.sum() > 5000
    assert g.overdraw.max() == 1  # nothing drawn twice along the 400 shared edges ...
    np.testing.assert_array_equal(g.coverage, s.coverage)  # ... and nothing missed
    np.testing.assert_allclose(g.position[g.coverage], s.position[s.coverage], atol=1e-13)


def convex_hull_inside(points_xy, jj, ii, margin=1e-9):
    from scipy.spatial import ConvexHull

    eq = ConvexHull(points_xy).equations  # a x + b y + c <= 0 inside
    s = jj[..., None] * eq[:, 0] + ii[..., None] * eq[:, 1] + eq[:, 2]
    return np.all(s < -margin, axis=-1), np.any(s > margin, axis=-1)


@pytest.mark.parametrize(
    "cam",
    [
        Camera((0.3, 0.4, 5), (0, 0, 0), width=200, height=150),
        Camera((0.3, 0.4, 5), (0, 0, 0), projection="orthographic", ortho_height=2.4, width=160, height=150),
    ],
    ids=["perspective", "orthographic"],
)
def test_closed_convex_mesh_draws_a_solid_silhouette_once(cam):
    m = icosphere(3)
    gb = rasterize(m, cam)
    jj, ii = pixel_centres(cam)
    inside, outside = convex_hull_inside(cam.project(m.vertices)[0], jj, ii)
    # The front faces tile the projected convex hull: exactly the pixel centres inside it, once each.
    assert np.all(gb.coverage[inside]) and not np.any(gb.coverage[outside])
    np.testing.assert_array_equal(gb.overdraw, gb.coverage.astype(np.int32))
    assert np.all(gb.front_facing == gb.coverage)
    # Both sides drawn: every covered pixel has exactly one front and one back fragment; the front wins.
    both = rasterize(m, cam, cull_backfaces=False)
    np.testing.assert_array_equal(both.overdraw, 2 * gb.coverage.astype(np.int32))
    np.testing.assert_array_equal(both.triangle_id, gb.triangle_id)
    # It is the near side that is drawn: the centre is at depth |eye| - 1 (a little farther: the
    # polyhedron is inscribed) and faces the camera.
    h, w = cam.height // 2, cam.width // 2
    assert 0 < gb.depth[h, w] - (cam.distance - 1) < 0.01
    assert gb.normal[h, w] @ -cam.forward > 0.99


def test_coverage_matches_the_analytic_silhouette():
    cam = Camera((0.3, 0.4, 5), (0, 0, 0), width=320, height=240)
    ref = raycast_sphere(cam)
    gb = rasterize(icosphere(5), cam)
    iou = (gb.coverage & ref.coverage).sum() / (gb.coverage | ref.coverage).sum()
    assert iou >= 0.999
    # The inscribed polyhedron's silhouette lies inside the sphere's.
    assert not np.any(gb.coverage & ~ref.coverage)


def test_tessellation_normals_converge_at_second_order():
    # Against the exact sphere: interpolated vertex normals (Phong interpolation) err by O(h²), the
    # face normals of flat shading by O(h); each icosphere level halves the edge length h.
    cam = Camera((0.3, 0.4, 5), (0, 0, 0), width=200, height=200)
    ref = raycast_sphere(cam)
    smooth, flat = [], []
    for level in (3, 4, 5):
        gb = rasterize(icosphere(level), cam)
        both = gb.coverage & ref.coverage
        for out, n in ((smooth, gb.normal), (flat, gb.face_normal)):
            cos = np.clip(np.einsum("ijk,ijk->ij", n, ref.normal)[both], -1, 1)
            out.append(np.mean(np.arccos(cos)))
    smooth_ratio = np.array(smooth[:-1]) / smooth[1:]
    flat_ratio = np.array(flat[:-1]) / flat[1:]
    assert np.all((smooth_ratio > 3.5) & (smooth_ratio < 4.5))
    assert np.all((flat_ratio > 1.8) & (flat_ratio < 2.2))


# ====================================================================== depth and interpolation
def test_depth_test_keeps_the_nearer_triangle_in_either_order():
    near = quad((-8, -8, 0.5), (8, -8, 0.5), (8, 8, 0.5), (-8, 8, 0.5))
    far = quad((-4, -12, 0), (12, -12, 0), (12, 4, 0), (-4, 4, 0))
    for first, second, near_ids in ((near, far, (0, 1)), (far, near, (2, 3))):
        V = np.vstack([first.vertices, second.vertices])
        F = np.vstack([first.faces, second.faces + 4])
        gb = rasterize(TriangleMesh(V, F), ORTHO64)
        on_near = np.isin(gb.triangle_id, near_ids)
        assert on_near.sum() == 16 * 16
        np.testing.assert_array_equal(gb.depth[on_near], 9.5)
        np.testing.assert_array_equal(gb.depth[gb.coverage & ~on_near], 10.0)
        assert (gb.overdraw == 2).sum() == 12 * 12  # the overlap: both drawn, the near one kept


def test_exact_depth_ties_go_to_the_first_face(monkeypatch):
    import lighting.render.raster as raster

    # Every face listed twice (duplicated geometry): equal depths everywhere, the first copy wins.
    m = icosphere(2)
    n = m.n_triangles
    for faces in (np.vstack([m.faces, m.faces]), np.vstack([m.faces[::-1], m.faces])):
        twice = TriangleMesh(m.vertices, faces)
        for batch in (1 << 16, 64):  # one batch, and many small ones (ties across batches)
            monkeypatch.setattr(raster, "_BATCH", batch)
            gb = rasterize(twice, Camera((0.3, 0.4, 4), (0, 0, 0), width=48, height=40))
            cov = gb.coverage
            np.testing.assert_array_equal(gb.overdraw[cov], 2)
            assert np.all(gb.triangle_id[cov] < n)


def test_batching_does_not_change_the_result(monkeypatch):
    import lighting.render.raster as raster

    m = icosphere(3)
    cam = Camera((0.3, 0.4, 3), (0, 0, 0), fov_y_deg=50, width=96, height=80)
    ref = rasterize(m, cam, cull_backfaces=False)
    monkeypatch.setattr(raster, "_BATCH", 50)
    small = rasterize(m, cam, cull_backfaces=False)
    for name in ("triangle_id", "barycentric", "depth", "coverage", "front_facing", "overdraw"):
        np.testing.assert_array_equal(getattr(small, name), getattr(ref, name), err_msg=name)


def test_interpenetrating_triangles_resolve_per_pixel():
    # Two big triangles on the planes z = 0.3 x and z = -0.3 x cross along x = 0.
    a = [(-20, -20, -6), (20, -20, 6), (0, 25, 0)]
    b = [(-20, -20, 6), (20, -20, -6), (0, 25, 0)]
    m = TriangleMesh(np.array(a + b, float), [[0, 1, 2], [3, 4, 5]])
    cam = Camera((3, 2, 40), (0, 0, 0), fov_y_deg=60, width=64, height=64)
    gb = rasterize(m, cam, cull_backfaces=False)
    o, d = cam.rays()
    depths = []
    for n, p in (((-0.3, 0, 1), a[2]), ((0.3, 0, 1), b[2])):  # plane normals and a point on each
        n = np.array(n)
        t = ((np.array(p) - o) @ n) / (d @ n)
        depths.append(t * (d @ cam.forward))
    both = gb.overdraw == 2
    assert both.sum() > 500
    np.testing.assert_allclose(gb.depth[both], np.minimum(*depths)[both], rtol=1e-13)
    clear = both & (np.abs(depths[0] - depths[1]) > 1e-9)
    np.testing.assert_array_equal(gb.triangle_id[clear], np.where(depths[0] < depths[1], 0, 1)[clear])


def test_positions_lie_on_the_pixel_rays_and_barycentrics_are_valid():
    m = icosphere(3)
    cam = Camera((1.0, 2.0, 3.0), (0.1, 0.0, -0.2), fov_y_deg=50, width=90, height=70)
    gb = rasterize(m, cam)
    cov = gb.coverage
    jj, ii = pixel_centres(cam)
    xy, depth = cam.project(gb.position[cov])
    np.testing.assert_allclose(xy[:, 0], jj[cov], atol=1e-10)
    np.testing.assert_allclose(xy[:, 1], ii[cov], atol=1e-10)
    np.testing.assert_allclose(depth, gb.depth[cov], rtol=1e-14)
    b = gb.barycentric[cov]
    np.testing.assert_allclose(b.sum(axis=1), 1, atol=1e-15)
    assert b.min() >= 0 and b.max() <= 1
    # position is the barycentric combination of the triangle's vertices; empty pixels are zero
    P = m.vertices[m.faces[gb.triangle_id[cov]]]
    np.testing.assert_allclose(np.einsum("nk,nkc->nc", b, P), gb.position[cov], atol=1e-15)
    np.testing.assert_array_equal(gb.interpolate(m.vertices), gb.position)
    for a in (gb.position, gb.normal, gb.barycentric, gb.face_normal, gb.depth):
        assert np.all(a[~cov] == 0)
    assert np.all(gb.triangle_id[~cov] == -1)


def test_perspective_correct_interpolation_on_a_tilted_quad():
    # The plane z = -2 y through the origin, strongly tilted toward the camera: depths from 4 to 8.
    P = np.array([(-1.0, -1.0, 2.0), (1.0, -1.0, 2.0), (1.0, 1.0, -2.0), (-1.0, 1.0, -2.0)])
    m = quad(*P)
    cam = Camera((0, 0, 6), (0, 0, 0), fov_y_deg=40, width=120, height=120)
    gb = rasterize(m, cam)
    cov = gb.coverage
    assert cov.sum() > 3000
    o, d = cam.rays()
    n = np.array([0.0, 2.0, 1.0])
    t = -(o @ n) / (d @ n)
    hit = o + t[..., None] * d
    np.testing.assert_allclose(gb.position[cov], hit[cov], rtol=0, atol=1e-13)
    np.testing.assert_allclose(gb.depth[cov], (t * (d @ cam.forward))[cov], rtol=1e-14)
    # Barycentrics of the ray–plane hit in its triangle (least squares on the 3-D triangle).
    tid = gb.triangle_id[cov]
    corners = P[m.faces[tid]]  # (n, 3, 3)
    A = np.stack([corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]], axis=2)  # (n, 3, 2)
    rhs = hit[cov] - corners[:, 0]
    uv = np.linalg.solve(np.einsum("nki,nkj->nij", A, A), np.einsum("nki,nk->ni", A, rhs)[..., None])[..., 0]
    exact = np.c_[1 - uv.sum(1), uv]
    np.testing.assert_allclose(gb.barycentric[cov], exact, atol=1e-12)
    # Screen-space (affine) barycentrics would be visibly wrong here: the test can tell the difference.
    xy = cam.project(corners)[0]
    jj, ii = pixel_centres(cam)
    q = np.stack([jj[cov], ii[cov]], axis=1)
    M = np.stack([xy[:, 1] - xy[:, 0], xy[:, 2] - xy[:, 0]], axis=2)
    st = np.linalg.solve(M, (q - xy[:, 0])[..., None])[..., 0]
    affine = np.c_[1 - st.sum(1), st]
    assert np.max(np.abs(affine - exact)) > 0.05
    # Attribute interpolation: any affine function of position is reproduced exactly.
    f = m.vertices @ [0.3, -1.2, 2.0] + 0.7
    np.testing.assert_allclose(gb.interpolate(f)[cov], hit[cov] @ [0.3, -1.2, 2.0] + 0.7, atol=1e-12)


def test_near_plane_clipping_of_a_floor_under_the_camera():
    n = 4
    u = np.linspace(-50, 50, n + 1)
    X, Z = np.meshgrid(u, u)
    V = np.stack([X.ravel(), -np.ones(X.size), Z.ravel()], axis=1)
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel()
    floor = TriangleMesh(V, np.concatenate([np.stack([a, c, b], 1), np.stack([b, c, d], 1)]))
    assert np.all(floor.face_normals[:, 1] == 1)
    cam = Camera((0.1, 0.0, -0.5), (0.1, -0.3, -1.7), fov_y_deg=90, width=160, height=120, near=0.05, far=200)
    # Some triangles straddle the near plane (they extend behind the camera) ...
    fdepth = -cam.world_to_camera(floor.vertices)[floor.faces][..., 2]
    straddling = np.flatnonzero((fdepth.min(1) < cam.near) & (fdepth.max(1) > cam.near))
    gb = rasterize(floor, cam)
    assert np.isin(straddling, gb.triangle_id).any()  # ... and are drawn, clipped
    o, dirs = cam.rays()
    t = np.where(dirs[..., 1] < 0, -1 / np.where(dirs[..., 1] < 0, dirs[..., 1], -1), 0)
    hit = o + t[..., None] * dirs
    expected = (dirs[..., 1] < 0) & (np.abs(hit[..., 0]) < 50) & (np.abs(hit[..., 2]) < 50)
    np.testing.assert_array_equal(gb.coverage, expected)
    assert gb.overdraw.max() == 1
    np.testing.assert_allclose(gb.position[gb.coverage], hit[gb.coverage], atol=1e-12)
    b = gb.barycentric[gb.coverage]
    assert b.min() >= 0 and np.max(np.abs(b.sum(1) - 1)) < 1e-15
    np.testing.assert_array_equal(gb.interpolate(floor.vertices), gb.position)
    # The far plane cuts per pixel: nothing beyond it.
    cut = rasterize(floor, cam.replace(far=20.0))
    np.testing.assert_array_equal(cut.coverage, gb.coverage & (gb.depth <= 20.0))


def test_camera_behind_and_inside_geometry():
    # Eye inside a sphere: with culling the inside (back faces) is invisible; without it, all of it shows.
    cam = Camera((0.0, 0.0, 0.2), (0.0, 0.0, -1.0), fov_y_deg=60, width=40, height=30)
    m = icosphere(3)
    assert not rasterize(m, cam).coverage.any()
    inside = rasterize(m, cam, cull_backfaces=False)
    assert inside.coverage.all() and not inside.front_facing.any()
    # Everything behind the eye: nothing drawn, no warning.
    away = Camera((0.0, 0.0, 3.0), (0.0, 0.0, 6.0), width=16, height=16)
    assert not rasterize(m, away).coverage.any()


def test_float32_buffers():
    m = icosphere(3)
    cam = Camera((0.3, 0.4, 5), (0, 0, 0), width=128, height=96)
    g64 = rasterize(m, cam)
    g32 = rasterize(m, cam, dtype=np.float32)
    for name in ("barycentric", "depth", "position", "normal", "normal_unnormalized", "face_normal"):
        assert getattr(g32, name).dtype == np.float32, name
    assert g32.interpolate(np.ones(m.n_vertices, np.float32)).dtype == np.float32
    assert g32.interpolate(np.ones(m.n_vertices)).dtype == np.float64
    # Coverage and the depth test are decided in float64 for both: the same pixels, the same triangles.
    np.testing.assert_array_equal(g32.coverage, g64.coverage)
    np.testing.assert_array_equal(g32.triangle_id, g64.triangle_id)
    np.testing.assert_array_equal(g32.barycentric, g64.barycentric.astype(np.float32))
    np.testing.assert_allclose(g32.position, g64.position, atol=1e-6)
    r32 = raycast_sphere(cam, dtype=np.float32)
    assert r32.position.dtype == r32.normal.dtype == r32.depth.dtype == np.float32


def test_huge_but_finite_coordinates_raise_no_warning():
    # Screen coordinates around 1e160: their products overflow float64.  Such triangles are dropped
    # quietly (the suite turns warnings into errors); ordinary triangles of the same mesh still draw.
    V = [(-1e160, -1e160, 0.0), (1e160, -1e160, 0.0), (0.0, 1e160, 0.0), (-5, -5, 1), (5, -5, 1), (0, 5, 1)]
    gb = rasterize(TriangleMesh(V, [[0, 1, 2], [3, 4, 5]]), ORTHO64)
    assert set(np.unique(gb.triangle_id)) == {-1, 1}
    assert np.all(np.isfinite(gb.position)) and np.all(np.isfinite(gb.depth))


def test_gbuffer_attribute_access():
    m = icosphere(2)
    cam = Camera((0.0, 0.0, 4.0), (0.0, 0.0, 0.0), width=48, height=40)
    gb = rasterize(m, cam)
    cov = gb.coverage
    colours = np.random.default_rng(3).random((m.n_vertices, 3))
    g = gb.interpolate(colours)
    assert g.shape == (40, 48, 3) and np.all(g[~cov] == 0)
    b, tid = gb.barycentric[cov], gb.triangle_id[cov]
    np.testing.assert_allclose(g[cov], np.einsum("nk,nkc->nc", b, colours[m.faces[tid]]), atol=1e-15)
    flat = gb.per_face(np.arange(m.n_triangles) * 2)
    np.testing.assert_array_equal(flat[cov], 2 * tid)
    np.testing.assert_array_equal(gb.per_face(m.face_normals), gb.face_normal)
    np.testing.assert_allclose(np.linalg.norm(gb.normal[cov], axis=-1), 1, atol=1e-15)
    np.testing.assert_allclose(
        gb.normal[cov],
        gb.normal_unnormalized[cov] / np.linalg.norm(gb.normal_unnormalized[cov], axis=-1, keepdims=True),
        atol=1e-15,
    )
    assert np.all(np.linalg.norm(gb.normal_unnormalized[cov], axis=-1) <= 1 + 1e-15)
    v = gb.view_direction()
    np.testing.assert_allclose(v[cov], cam.view_direction(gb.position[cov]), atol=0)
    assert np.all(v[~cov] == 0)
    with pytest.raises(ValueError, match=r"vertex_values must have one row per vertex \(162\); got shape \(5, 3\)"):
        gb.interpolate(np.zeros((5, 3)))
    with pytest.raises(ValueError, match=r"face_values must have one row per triangle \(320\)"):
        gb.per_face(np.zeros(3))


@pytest.mark.parametrize(("eye_z", "cull"), [(4.0, True), (0.2, False)])  # outside, culled; inside, not
def test_gbuffer_images_and_covered_pixels_agree(eye_z, cull):
    # The rasterizer keeps one row per covered pixel and scatters the images from them on first
    # read; both views must describe the same buffer, and the buffer cannot be changed.
    cam = Camera((0.0, 0.0, eye_z), (0.0, 0.0, -1.0), fov_y_deg=60, width=40, height=30)
    gb = rasterize(icosphere(3), cam, cull_backfaces=cull)
    assert gb.shape == (30, 40) and gb.dtype == np.float64
    cov = gb.coverage
    assert 0 < cov.sum() < cov.size if cull else cov.all()
    np.testing.assert_array_equal(gb.pixels, np.flatnonzero(cov))
    np.testing.assert_array_equal(gb.triangle_id >= 0, cov)
    tid, b = gb._compact
    np.testing.assert_array_equal(gb.triangle_id[cov], tid)
    np.testing.assert_array_equal(gb.barycentric[cov], np.stack(b, axis=1))
    np.testing.assert_array_equal(gb.depth[cov], gb._depth_compact)
    assert np.all(gb.depth[~cov] == 0) and np.all(gb.barycentric[~cov] == 0) and not gb.front_facing[~cov].any()
    assert np.all(gb.overdraw[~cov] == 0) and np.all(gb.overdraw[cov] >= 1)
    np.testing.assert_array_equal(gb.front_facing, cov if cull else False)  # from inside: back faces only
    with pytest.raises(AttributeError, match="read-only"):
        gb.depth = np.zeros((30, 40))


def test_gbuffer_supports_a_separate_lighting_pass():
    # Lambert under two lights from one buffer: the buffer is computed once, lights move freely.
    gb = rasterize(icosphere(4), Camera((0, 0, 5), (0, 0, 0), width=64, height=64))
    n = gb.normal
    for l_dir in ((0.0, 0.0, 1.0), (0.6, 0.0, 0.8)):
        lit = np.maximum(n @ np.array(l_dir), 0)
        assert np.all(lit[~gb.coverage] == 0) and lit.max() > 0.99


def test_rasterize_validation():
    cam = Camera((0, 0, 5), (0, 0, 0), width=8, height=8)
    with pytest.raises(ValueError, match="mesh must be a TriangleMesh; got ndarray"):
        rasterize(np.zeros((3, 3)), cam)
    with pytest.raises(ValueError, match="camera must be a Camera; got tuple"):
        rasterize(icosphere(0), (0, 0, 5))
    with pytest.raises(ValueError, match="dtype must be float32 or float64; got <class 'numpy.int32'>"):
        rasterize(icosphere(0), cam, dtype=np.int32)


def test_degenerate_triangles_draw_nothing():
    V = [(-5, -5, 0), (5, -5, 0), (5, 5, 0), (0, 0, 0), (1, 1, 0), (2, 2, 0)]
    m = TriangleMesh(V, [[0, 1, 2], [3, 4, 5], [3, 3, 4]])
    gb = rasterize(m, ORTHO64, cull_backfaces=False)
    assert set(np.unique(gb.triangle_id)) == {-1, 0}


def test_empty_view():
    m = icosphere(1, center=(100, 0, 0))
    gb = rasterize(m, Camera((0, 0, 5), (0, 0, 0), width=10, height=10))
    assert not gb.coverage.any() and gb.position.shape == (10, 10, 3) and np.all(gb.triangle_id == -1)
    empty = rasterize(
        TriangleMesh(np.zeros((0, 3)), np.zeros((0, 3), int)), Camera((0, 0, 5), (0, 0, 0), width=8, height=6)
    )
    assert empty.normal.shape == (6, 8, 3) and not empty.normal.any() and empty.interpolate(np.zeros(0)).shape == (6, 8)


# ====================================================================== analytic sphere
def test_raycast_sphere_orthographic_closed_form():
    D = 5.0
    cam = Camera((0, 0, D), (0, 0, 0), projection="orthographic", ortho_height=2.5, width=101, height=99)
    gb = raycast_sphere(cam)
    jj, ii = pixel_centres(cam)
    x = (jj - cam.width / 2) / cam.pixels_per_unit
    y = (cam.height / 2 - ii) / cam.pixels_per_unit
    r2 = x * x + y * y
    np.testing.assert_array_equal(gb.coverage, r2 <= 1)
    z = np.sqrt(1 - r2[gb.coverage])
    np.testing.assert_allclose(gb.depth[gb.coverage], D - z, rtol=1e-15)
    np.testing.assert_allclose(gb.position[gb.coverage], np.c_[x[gb.coverage], y[gb.coverage], z], atol=1e-15)
    np.testing.assert_allclose(gb.normal[gb.coverage], gb.position[gb.coverage], atol=0)
    assert np.all(gb.triangle_id[gb.coverage] == 0) and np.all(gb.triangle_id[~gb.coverage] == -1)
    assert np.all(gb.barycentric == 0) and gb.mesh is None
    with pytest.raises(ValueError, match="interpolate needs a mesh"):
        gb.interpolate(np.ones(3))


def test_raycast_sphere_perspective_against_high_precision_roots():
    c, r = np.array([0.2, -0.1, 0.3]), 0.9
    cam = Camera((0.5, 1.0, 4.0), (0.0, 0.0, 0.0), fov_y_deg=35, width=64, height=48)
    gb = raycast_sphere(cam, center=c, radius=r)
    o, d = cam.rays()
    cov = gb.coverage
    assert cov.sum() > 1000
    q = gb.position[cov] - c
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), r, rtol=2e-16 * 8)
    np.testing.assert_allclose(gb.normal[cov], q / r, atol=0)
    np.testing.assert_allclose(np.linalg.norm(gb.normal[cov], axis=1), 1, atol=1e-15)
    mpmath.mp.dps = 40
    rng = np.random.default_rng(5)
    for i, j in np.argwhere(cov)[rng.choice(int(cov.sum()), 25, replace=False)]:
        oo = [mpmath.mpf(float(v)) for v in o[i, j] - c]
        dd = [mpmath.mpf(float(v)) for v in d[i, j]]
        b = sum(a * e for a, e in zip(oo, dd, strict=True))
        cc = sum(a * a for a in oo) - mpmath.mpf(r) ** 2
        dlen2 = sum(e * e for e in dd)
        t = (-b - mpmath.sqrt(b * b - dlen2 * cc)) / dlen2
        depth = t * sum(e * mpmath.mpf(float(f)) for e, f in zip(dd, cam.forward, strict=True))
        assert gb.depth[i, j] == pytest.approx(float(depth), rel=1e-14)
    # Front side only, and a stable root for a tiny sphere far away.
    assert np.all(gb.front_facing == cov)
    far = Camera(
        (0.0, 0.0, 1000.0), (0.0, 0.0, 0.0), fov_y_deg=2 * math.degrees(math.atan(0.012 / 1000)), width=32, height=32
    )
    tiny = raycast_sphere(far, radius=0.01)
    assert tiny.coverage.sum() > 400
    dist = np.linalg.norm(tiny.position[tiny.coverage], axis=1)
    assert np.max(np.abs(dist - 0.01)) <= 4 * np.spacing(1000.0)  # a few ulps of the coordinates (~1000)


def test_gbuffer_is_the_public_type():
    cam = Camera((0, 0, 5), (0, 0, 0), width=4, height=4)
    assert isinstance(raycast_sphere(cam), GBuffer) and isinstance(rasterize(icosphere(0), cam), GBuffer)


# ============================================================== the camera: checked arguments and extremes
def test_an_eye_1e308_away_is_a_distance_not_an_up_problem():
    # eye[0] = -1e308: |target - eye|² overflows float64, and the camera used to blame `up`.
    cam = Camera((-1e308, 0.0, 5.0), (0, 0, 0), width=16, height=16)
    assert cam.distance == 1e308 and cam.forward.tolist() == [1.0, 0.0, -5e-308]
    assert cam.near == 1e305 and cam.far == np.finfo(np.float64).max  # 1000 × 1e308, saturated
    xy, depth = cam.project([[0.0, 0.0, 0.0]])
    assert xy.tolist() == [[8.0, 8.0]] and depth.tolist() == [1e308]
    # When target - eye itself overflows, the error names eye and target, never up.
    with pytest.raises(ValueError, match=r"^eye and target must be less than 1.8e\+308 apart") as info:
        Camera((-1e308, 0, 0), (1e308, 0, 0))
    assert "up" not in str(info.value)
    assert Camera.orbit(distance=2, azimuth_deg=90).eye.tolist() == [2.0, 0.0, 0.0]  # exact at right angles


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(eye=5.0), r"^eye must be a finite 3-vector \(x, y, z\); got shape \(\)"),
        (dict(eye=("0", "0", "5")), "^eye must be a finite 3-vector"),
        (dict(target=(0, 0, 1j)), "^target must be a finite 3-vector"),
        (dict(up=b"010"), "^up must be a finite 3-vector"),
        (dict(width=10**6), r"^width must be an integer <= 65536 \(pixels\); got 1000000"),
        (dict(width="8"), r"^width must be an integer >= 1 \(pixels\); got str '8'"),
        (dict(fov_y_deg="30"), "^fov_y_deg must be a finite number; got str '30'"),
        (dict(near=float("nan")), "^near must be a finite number > 0"),
    ],
)
def test_camera_arguments_are_named(kwargs, message):
    args = dict(eye=(0, 0, 5.0), target=(0, 0, 0.0)) | kwargs
    with pytest.raises(ValueError, match=message):
        Camera(**args)


def test_camera_methods_check_their_arguments_and_budget():
    cam = Camera((0, 0, 5.0), (0, 0, 0), width=4, height=4)
    with pytest.raises(ValueError, match="^points must be finite"):
        cam.project([[0, 0, float("nan")]])
    with pytest.raises(ValueError, match=r"^pixels must be a 1-D array of integer pixel indices in \[0, 16\)"):
        cam.pixel_view_vectors([16])
    with pytest.raises(TypeError, match="^dtype must be float32 or float64; got None"):
        cam.rays(dtype=None)
    huge = Camera((0, 0, 5.0), (0, 0, 0), width=60000, height=60000)
    with pytest.raises(ValueError, match="^rays of a 60000x60000 camera needs about"):
        huge.rays()
    with pytest.raises(ValueError, match=r"^camera width x height \(60000x60000 pixels\) needs about"):
        rasterize(icosphere(0), huge)
    with pytest.raises(ValueError, match=r"^camera width x height \(60000x60000 pixels\) needs about"):
        raycast_sphere(huge)


def test_raycast_sphere_near_the_float_range_is_finite():
    for radius, distance in ((1e150, 1e151), (1.0, 1e300), (1e-150, 1e-149)):
        cam = Camera((0, 0, distance), (0, 0, 0), width=9, height=9, fov_y_deg=60)
        gb = raycast_sphere(cam, radius=radius)
        assert np.all(np.isfinite(gb.position)) and np.all(np.isfinite(gb.normal)) and np.all(np.isfinite(gb.depth))
        if radius > distance / 100:  # the sphere fills the view's centre
            assert gb.coverage[4, 4] and gb.normal[4, 4].tolist() == pytest.approx([0, 0, 1], abs=1e-12)

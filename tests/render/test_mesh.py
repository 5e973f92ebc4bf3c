"""Meshes: counts, exactness and topology of the sphere generators, vertex normals, transforms, file loading."""

import math

import numpy as np
import pytest

from lighting.render.mesh import TriangleMesh, icosphere, load_mesh, sphere_for_triangles, uv_sphere

trimesh = pytest.importorskip("trimesh")


def edge_use(faces):
    """Map undirected edge -> number of faces using it; and the number of distinct directed edges."""
    directed = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    undirected, counts = np.unique(np.sort(directed, axis=1), axis=0, return_counts=True)
    return undirected, counts, len(np.unique(directed, axis=0))


# ---------------------------------------------------------------------- generators
@pytest.mark.parametrize("level", range(5))
def test_icosphere_counts_follow_the_subdivision_formulas(level):
    m = icosphere(level)
    edges, counts, n_directed = edge_use(m.faces)
    assert m.n_triangles == 20 * 4**level
    assert len(edges) == 30 * 4**level
    assert m.n_vertices == 10 * 4**level + 2
    assert m.n_vertices - len(edges) + m.n_triangles == 2  # Euler characteristic of the sphere


@pytest.mark.parametrize(("n_lat", "n_lon"), [(2, 3), (3, 4), (8, 16), (17, 5)])
def test_uv_sphere_counts_and_no_degenerate_triangles(n_lat, n_lon):
    m = uv_sphere(n_lat, n_lon)
    assert m.n_vertices == 2 + n_lon * (n_lat - 1)
    assert m.n_triangles == 2 * n_lon * (n_lat - 1)
    assert m.face_areas.min() > 0  # the poles are fans of real triangles
    top = m.face_areas[:n_lon]
    # Exact area of a cap triangle: pole P, ring points A, B at polar angle θ = π/n_lat, azimuths 2π/n_lon apart.
    theta, dphi = math.pi / n_lat, 2 * math.pi / n_lon
    a = np.array([math.sin(theta), math.cos(theta), 0.0])
    b = np.array([math.sin(theta) * math.cos(dphi), math.cos(theta), math.sin(theta) * math.sin(dphi)])
    exact = 0.5 * np.linalg.norm(np.cross(a - [0, 1, 0], b - [0, 1, 0]))
    np.testing.assert_allclose(top, exact, rtol=1e-13)


@pytest.mark.parametrize("make", [lambda: icosphere(4), lambda: uv_sphere(24, 48)], ids=["icosphere", "uv"])
def test_sphere_vertices_are_on_the_sphere_and_normals_exact_and_outward(make):
    m = make()
    r = np.linalg.norm(m.vertices, axis=1)
    assert np.max(np.abs(r - 1)) <= 1e-15
    np.testing.assert_allclose(m.normals, m.vertices, rtol=0, atol=1e-15)  # unit sphere: n = p
    assert m.has_given_normals
    centroids = m.vertices[m.faces].mean(axis=1)
    assert np.all(np.einsum("ij,ij->i", m.face_normals, centroids) > 0)  # counter-clockwise seen from outside
    # Vertex normals computed from the faces agree with the exact ones (fine meshes).
    assert np.min(np.einsum("ij,ij->i", m.vertex_normals(), m.normals)) > 0.999


def test_generators_place_and_scale_the_sphere():
    c, r = np.array([1.0, -2.0, 3.0]), 2.5
    for m in (icosphere(3, radius=r, center=c), uv_sphere(10, 20, radius=r, center=c)):
        d = np.linalg.norm(m.vertices - c, axis=1)
        assert np.max(np.abs(d - r)) <= 4 * np.finfo(float).eps * r
        np.testing.assert_allclose(m.normals, (m.vertices - c) / r, atol=1e-15)


@pytest.mark.parametrize("make", [lambda: icosphere(3), lambda: uv_sphere(9, 13)], ids=["icosphere", "uv"])
def test_sphere_meshes_are_closed_oriented_manifolds(make):
    m = make()
    edges, counts, n_directed = edge_use(m.faces)
    assert np.all(counts == 2)  # every edge shared by exactly two faces
    assert n_directed == 2 * len(edges)  # ... traversed once in each direction: consistent orientation


def test_icosahedron_area_and_second_order_convergence_to_4pi():
    # Level 0: the regular icosahedron inscribed in the unit sphere, edge a = 1 / sin(2π/5), area 5√3 a².
    a = 1 / math.sin(2 * math.pi / 5)
    assert icosphere(0).area == pytest.approx(5 * math.sqrt(3) * a * a, rel=1e-14)
    areas = [icosphere(k).area for k in range(7)]
    errors = 4 * math.pi - np.array(areas)
    assert np.all(errors > 0)  # inscribed convex polyhedra have less area than the sphere ...
    assert np.all(np.diff(areas) > 0)  # ... and each refinement contains the previous one
    ratios = errors[:-1] / errors[1:]
    # Edge length halves at each level; the area error is O(h²): ratio → 4.
    assert np.all(np.abs(ratios[3:] - 4) < 0.015)
    assert abs(ratios[-1] - 4) < abs(ratios[3] - 4)


def test_uv_sphere_area_converges_at_second_order():
    errors = np.array([4 * math.pi - uv_sphere(n, 2 * n).area for n in (16, 32, 64)])
    ratios = errors[:-1] / errors[1:]
    np.testing.assert_allclose(ratios, 4, atol=0.02)


@pytest.mark.parametrize("n", [8, 80, 100, 500, 1000, 3000, 5000, 20000])
def test_sphere_for_triangles_is_close_to_the_request(n):
    m = sphere_for_triangles(n)
    assert abs(m.n_triangles - n) <= 0.05 * n
    assert np.max(np.abs(np.linalg.norm(m.vertices, axis=1) - 1)) <= 1e-15
    if n in (80, 5000, 20000):  # an icosphere within 10 % exists: it is preferred
        assert m.n_triangles == 20 * 4 ** round(math.log(n / 20, 4))


def test_generator_arguments_are_validated():
    with pytest.raises(ValueError, match="level must be an integer >= 0; got -1"):
        icosphere(-1)
    with pytest.raises(ValueError, match="n_lat must be an integer >= 2; got 1"):
        uv_sphere(1, 8)
    with pytest.raises(ValueError, match="n_lon must be an integer >= 3"):
        uv_sphere(4, 2.5)
    with pytest.raises(ValueError, match="radius must be a finite number > 0; got -1.0"):
        icosphere(1, radius=-1)
    with pytest.raises(ValueError, match="center must be a finite 3-vector"):
        uv_sphere(4, 8, center=(0, np.nan, 0))


# ---------------------------------------------------------------------- normals
def cube_corner():
    """The three faces of the unit cube [0, 1]³ at the corner 0, each square split in two.

    The z = 0 face is split along the diagonal through the corner, the other two
    along the diagonal that misses it: the corner touches a full unit square on
    z = 0 but only a half square on x = 0 and y = 0.
    """
    V = [
        [0, 0, 0],  # 0 O
        [1, 0, 0],  # 1 X
        [0, 1, 0],  # 2 Y
        [0, 0, 1],  # 3 Z
        [1, 1, 0],  # 4 XY
        [0, 1, 1],  # 5 YZ
        [1, 0, 1],  # 6 XZ
    ]
    F = [
        [0, 4, 1],
        [0, 2, 4],  # z = 0 (outward -z), diagonal O-XY
        [0, 3, 2],
        [2, 3, 5],  # x = 0 (outward -x), diagonal Y-Z
        [0, 1, 3],
        [1, 6, 3],  # y = 0 (outward -y), diagonal X-Z
    ]
    return TriangleMesh(V, F)


def test_cube_corner_angle_weighted_normal_is_the_diagonal():
    m = cube_corner()
    np.testing.assert_allclose(m.face_normals[[0, 1]], [[0, 0, -1]] * 2, atol=0)
    np.testing.assert_allclose(m.face_normals[[2, 3]], [[-1, 0, 0]] * 2, atol=0)
    np.testing.assert_allclose(m.face_normals[[4, 5]], [[0, -1, 0]] * 2, atol=0)
    # Angles at the corner: 45° + 45° on z = 0, 90° on each of the other two faces.
    np.testing.assert_allclose(m.corner_angles()[:, 0][[0, 1, 2, 4]], [np.pi / 4, np.pi / 4, np.pi / 2, np.pi / 2])
    np.testing.assert_allclose(m.vertex_normals("angle")[0], -np.ones(3) / np.sqrt(3), rtol=1e-15)
    # Area weighting sees a unit square on z = 0 and half squares on x = 0, y = 0: (1/2, 1/2, 1) normalized.
    np.testing.assert_allclose(m.vertex_normals("area")[0], -np.array([1, 1, 2]) / np.sqrt(6), rtol=1e-15)
    assert not m.has_given_normals
    np.testing.assert_array_equal(m.normals, m.vertex_normals("angle"))


def test_angle_weighting_ignores_how_a_face_is_split():
    base = cube_corner()
    # Split the x = 0 triangle (O, Z, Y) at the midpoint of ZY: the corner now has two 45° wedges there.
    V = np.vstack([base.vertices, [0, 0.5, 0.5]])
    F = np.vstack([base.faces[[0, 1, 3, 4, 5]], [[0, 3, 7], [0, 7, 2]]])
    split = TriangleMesh(V, F)
    np.testing.assert_allclose(split.vertex_normals("angle")[0], base.vertex_normals("angle")[0], rtol=1e-15)


def test_degenerate_isolated_and_back_to_back_vertices_get_finite_normals():
    V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [2, 2, 2], [5, 5, 5], [0.5, 0, 0]]
    F = [
        [0, 1, 2],
        [0, 2, 1],  # the same triangle facing the other way
        [0, 1, 5],  # zero area (three collinear points)
        [0, 2, 1],
    ]  # vertex 3 and 4 isolated
    m = TriangleMesh(V, F)
    assert m.face_areas[2] == 0 and np.all(m.face_normals[2] == 0)
    for weighting in ("angle", "area"):
        n = m.vertex_normals(weighting)
        assert np.all(np.isfinite(n))
        np.testing.assert_array_equal(n[3], 0)  # isolated: zero
        np.testing.assert_array_equal(n[4], 0)
        np.testing.assert_allclose(np.linalg.norm(n[[0, 1, 2]], axis=1), 1, rtol=1e-15)
    # Vertex 5 only touches the zero-area triangle: no face to fall back on.
    np.testing.assert_array_equal(m.vertex_normals()[5], 0)


def test_back_to_back_faces_fall_back_to_the_largest_face():
    V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 2, 0]]
    m = TriangleMesh(V, [[0, 1, 2], [0, 3, 1]])  # +z (area 0.5) and -z (area 1) sharing vertices 0 and 1
    n = m.vertex_normals("angle")
    np.testing.assert_array_equal(n[2], [0, 0, 1])
    np.testing.assert_array_equal(n[3], [0, 0, -1])
    # At vertices 0 and 1 the two faces cancel (angle-weighted 90° vs 90° at 0; 45° vs 63.4° at 1).
    np.testing.assert_array_equal(n[0], [0, 0, -1])  # sum vanishes: the larger face wins
    np.testing.assert_array_equal(n[1], [0, 0, -1])  # larger angle on the -z face


def test_given_normals_are_normalized_and_zero_rows_replaced():
    m = TriangleMesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], normals=[[0, 0, 2], [0, 0, 0], [3, 0, 4]])
    np.testing.assert_allclose(m.normals, [[0, 0, 1], [0, 0, 1], [0.6, 0, 0.8]], rtol=1e-15)


def test_mesh_validation_messages():
    with pytest.raises(ValueError, match=r"vertices must be finite; 1 of 3 rows are not \(first: row 1"):
        TriangleMesh([[0, 0, 0], [np.nan, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    with pytest.raises(ValueError, match=r"index 3 with 3 vertices \(allowed 0..2\)"):
        TriangleMesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 3]])
    with pytest.raises(ValueError, match="index -1"):
        TriangleMesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, -1]])
    with pytest.raises(ValueError, match=r"vertices must be an array of shape \(V, 3\); got shape \(3, 2\)"):
        TriangleMesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]])
    with pytest.raises(ValueError, match=r"faces must be an integer array of shape \(F, 3\); got shape \(1, 4\)"):
        TriangleMesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2, 0]])
    with pytest.raises(ValueError, match="faces must hold integer vertex indices"):
        TriangleMesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 1.5]])
    with pytest.raises(ValueError, match=r"weighting must be one of 'angle', 'area'; got 'mean'"):
        icosphere(0).vertex_normals("mean")


def test_extreme_coordinates_give_finite_normals_and_areas():
    big, tiny = 1e160, 1e-160
    m = TriangleMesh(
        [(-big, -big, 0), (big, -big, 0), (0, big, 0), (tiny, 0, 0), (0, tiny, 0), (0, 0, 0)], [[0, 1, 2], [5, 3, 4]]
    )
    np.testing.assert_array_equal(m.face_normals, [[0, 0, 1], [0, 0, 1]])
    assert m.face_areas[0] == np.finfo(float).max  # 4e320 saturates
    assert m.face_areas[1] == pytest.approx(0.5 * tiny * tiny, rel=1e-3)  # subnormal, not 0
    for weighting in ("angle", "area"):
        np.testing.assert_array_equal(m.vertex_normals(weighting), [[0, 0, 1]] * 6)
    np.testing.assert_allclose(m.corner_angles()[1], [np.pi / 2, np.pi / 4, np.pi / 4], rtol=1e-15)


def test_mesh_arrays_are_read_only():
    m = icosphere(1)
    with pytest.raises(ValueError):
        m.vertices[0, 0] = 2.0


# ---------------------------------------------------------------------- transforms
def test_transform_maps_normals_by_the_inverse_transpose():
    m = icosphere(3)
    S = np.diag([2.0, 1.0, 1.0, 1.0])
    S[:3, 3] = [1.0, 2.0, 3.0]
    e = m.transformed(S)
    np.testing.assert_allclose(e.vertices, m.vertices * [2, 1, 1] + [1, 2, 3], rtol=1e-15)
    # Ellipsoid ((x−1)/2)² + (y−2)² + (z−3)² = 1: the normal is the gradient ∝ ((x−1)/4, y−2, z−3).
    q = e.vertices - [1, 2, 3]
    grad = q * [0.25, 1, 1]
    np.testing.assert_allclose(e.normals, grad / np.linalg.norm(grad, axis=1, keepdims=True), atol=1e-15)
    assert e.has_given_normals


def test_mirroring_transform_keeps_faces_outward():
    m = icosphere(2)
    e = m.transformed(np.diag([-1.0, 1.0, 1.0, 1.0]))
    centroids = e.vertices[e.faces].mean(axis=1)
    assert np.all(np.einsum("ij,ij->i", e.face_normals, centroids) > 0)
    np.testing.assert_allclose(e.normals, e.vertices, atol=1e-15)


def test_rotation_rotates_normals():
    c, s = math.cos(0.3), math.sin(0.3)
    R = np.eye(4)
    R[:3, :3] = [[c, -s, 0], [s, c, 0], [0, 0, 1]]
    m = uv_sphere(6, 12)
    r = m.transformed(R)
    np.testing.assert_allclose(r.normals, m.normals @ R[:3, :3].T, atol=1e-15)
    np.testing.assert_allclose(r.face_areas, m.face_areas, rtol=1e-13)


def test_transform_validation():
    m = icosphere(0)
    with pytest.raises(ValueError, match="matrix must be a 4x4 array"):
        m.transformed(np.eye(3))
    with pytest.raises(ValueError, match="matrix must be affine"):
        m.transformed(np.ones((4, 4)))
    with pytest.raises(ValueError, match="matrix must be invertible"):
        m.transformed(np.diag([1.0, 0.0, 1.0, 1.0]))


# ---------------------------------------------------------------------- loading
def triangle_coordinates(m):
    return m.vertices[m.faces]


@pytest.mark.parametrize("ext", ["obj", "ply", "stl", "glb"])
def test_load_round_trips_each_format(tmp_path, ext):
    src = icosphere(2)
    path = tmp_path / f"sphere.{ext}"
    trimesh.Trimesh(src.vertices, src.faces, process=False).export(path)
    m = load_mesh(path)
    assert m.n_triangles == src.n_triangles
    # STL stores each triangle's corners separately; loading welds them back into 162 vertices.
    assert m.n_vertices == src.n_vertices
    # Files store float32 (PLY, STL, GLB) or 8 decimals (OBJ).
    np.testing.assert_allclose(triangle_coordinates(m), triangle_coordinates(src), rtol=0, atol=1e-7)
    if ext != "stl":
        np.testing.assert_allclose(m.vertices, src.vertices, rtol=0, atol=1e-7)
        np.testing.assert_array_equal(m.faces, src.faces)
    # No normals in these files: computed, angle-weighted, close to the sphere's.
    assert not m.has_given_normals
    np.testing.assert_allclose(m.normals, m.vertex_normals("angle"))
    unit = m.vertices / np.linalg.norm(m.vertices, axis=1, keepdims=True)  # the sphere's normal
    assert np.min(np.einsum("ij,ij->i", m.normals, unit)) > 0.998


def test_load_uses_normals_stored_in_the_file(tmp_path):
    src = icosphere(1)
    path = tmp_path / "n.obj"
    tm = trimesh.Trimesh(src.vertices, src.faces, vertex_normals=src.normals * [1, 1, 1], process=False)
    tm.export(path, include_normals=True)
    assert "vn " in path.read_text()
    m = load_mesh(path)
    assert m.has_given_normals
    np.testing.assert_allclose(m.normals, src.normals, atol=1e-7)


def test_load_flattens_a_glb_scene_with_transforms(tmp_path):
    scene = trimesh.Scene()
    a, b = icosphere(1), icosphere(0)
    scene.add_geometry(trimesh.Trimesh(a.vertices, a.faces, process=False), geom_name="a")
    move = np.eye(4)
    move[:3, 3] = [3.0, 0.0, 0.0]
    scene.add_geometry(trimesh.Trimesh(b.vertices, b.faces, process=False), geom_name="b", transform=move)
    path = tmp_path / "scene.glb"
    scene.export(path)
    m = load_mesh(path)
    assert m.n_triangles == a.n_triangles + b.n_triangles
    assert m.n_vertices == a.n_vertices + b.n_vertices
    # The second sphere moved to x = 3.
    assert m.vertices[:, 0].min() == pytest.approx(a.vertices[:, 0].min(), abs=1e-6)
    assert m.vertices[:, 0].max() == pytest.approx(3 + b.vertices[:, 0].max(), abs=1e-6)
    assert m.area == pytest.approx(a.area + b.area, rel=1e-6)


def write(path, text):
    path.write_text(text)
    return path


def test_load_error_messages(tmp_path):
    with pytest.raises(ValueError, match=r"mesh file '.*nothere\.obj' does not exist"):
        load_mesh(tmp_path / "nothere.obj")
    with pytest.raises(ValueError, match=r"unsupported format '\.xyz'"):
        load_mesh(write(tmp_path / "a.xyz", "1 2 3\n"))
    with pytest.raises(ValueError, match=r"'.*bad\.ply' could not be read as PLY"):
        load_mesh(write(tmp_path / "bad.ply", "ply\nformat ascii 1.0\nelement vertex 3\n"))
    with pytest.raises(ValueError, match=r"'.*bad\.glb' could not be read as GLB"):
        load_mesh(write(tmp_path / "bad.glb", "glTF junk"))
    with pytest.raises(ValueError, match=r"'.*empty\.obj' contains no geometry"):
        load_mesh(write(tmp_path / "empty.obj", ""))
    with pytest.raises(ValueError, match=r"'.*garbage\.stl' contains no geometry"):
        load_mesh(write(tmp_path / "garbage.stl", "this is not an STL file"))
    with pytest.raises(ValueError, match=r"'.*points\.obj' contains no triangles"):
        load_mesh(write(tmp_path / "points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"))
    with pytest.raises(ValueError, match=r"'.*nan\.obj' has 1 vertices with NaN or infinite coordinates"):
        load_mesh(write(tmp_path / "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"))
    ply = (
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"
    )
    with pytest.raises(ValueError, match=r"'.*range\.ply' has face indices out of range: index 7 with 3 vertices"):
        load_mesh(write(tmp_path / "range.ply", ply))
    with pytest.raises(ValueError, match=r"'.*flat\.obj': all 1 triangles are degenerate \(zero area\)"):
        load_mesh(write(tmp_path / "flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"))
    with pytest.raises(ValueError, match="is a directory"):
        load_mesh(tmp_path)


def test_load_keeps_degenerate_triangles_harmlessly(tmp_path):
    text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n"  # second face: collinear
    m = load_mesh(write(tmp_path / "deg.obj", text))
    assert m.n_triangles == 2
    np.testing.assert_array_equal(m.face_areas, [0.5, 0.0])
    assert np.all(np.isfinite(m.normals))
    np.testing.assert_array_equal(m.normals[3], 0)  # only on the degenerate face
    np.testing.assert_array_equal(m.normals[:3], [[0, 0, 1]] * 3)


# --------------------------------------------------------------------------------- untrusted sizes and files
def test_generators_refuse_over_the_budget_before_allocating():
    import tracemalloc

    from lighting._budget import BudgetError

    tracemalloc.start()
    try:
        with pytest.raises(BudgetError, match=r"^n_lat = 1000000, n_lon = 32 needs about 11\.4 GiB \(63999936 "):
            uv_sphere(1_000_000, 32)
        with pytest.raises(BudgetError, match=r"^n_lat = 10{30}, n_lon = 3 needs about"):
            uv_sphere(10**30, 3)  # beyond the float range as a product: still an estimate, no OverflowError
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 1024**2
    assert uv_sphere(4, 8).n_triangles == 48  # small ones unaffected


def test_transforms_with_huge_scales_are_judged_scale_free():
    m = icosphere(1)
    big = m.transformed(np.diag([1e300, 1e300, 1e300, 1.0]))  # scale**3 raised OverflowError before
    assert np.all(np.isfinite(big.vertices)) and np.allclose(big.normals, m.normals)
    with pytest.raises(ValueError, match=r"^matrix must be invertible; its 3x3 block, divided by its largest entry"):
        m.transformed(np.diag([1e300, 1.0, 1.0, 1.0]))
    M = np.diag([1e308, 1e308, 1e308, 1.0])
    M[0, 3] = 1e308
    with pytest.raises(ValueError, match=r"^matrix moves vertices beyond the float range"):
        m.transformed(M)


def test_load_mesh_reads_only_regular_files_and_checks_the_size_first(tmp_path, monkeypatch):
    import os

    from lighting._budget import BudgetError

    monkeypatch.chdir(tmp_path)  # names as given, whole: a long temporary folder would be abbreviated
    os.mkfifo("fifo.obj")
    with pytest.raises(ValueError, match=r"fifo\.obj' is not a regular file"):
        load_mesh("fifo.obj")
    with open("sparse.obj", "wb") as f:  # 1 GB of zeros, sparse: 2-5 GB to parse before
        f.truncate(1 << 30)
    with pytest.raises(BudgetError, match=r"sparse\.obj' needs about 32\.0 GiB \(1073741824 bytes to read\)"):
        load_mesh("sparse.obj")
    # A long name is shortened to its end, where the file's name is.
    with pytest.raises(ValueError, match=r"mesh file '…\(\+99965 chars\)x{35}\.obj' does not exist$"):
        load_mesh("x" * 100_000 + ".obj")

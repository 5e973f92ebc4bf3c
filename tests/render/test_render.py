import math

import numpy as np
import pytest

from lighting import AmbientLight, BlinnPhong, DirectionalLight, Lambert, Material, Phong, PointLight, shade
from lighting.analysis.machband import edge_jump_metric, luminance, scanline_profile
from lighting.render.camera import Camera
from lighting.render.image import encode_srgb8
from lighting.render.mesh import TriangleMesh, icosphere, uv_sphere
from lighting.render.renderer import AnalyticSphere, Renderer, render
from lighting.render.sphere import sphere_camera

CAM = Camera((0, 0, 6.0), (0, 0, 0), fov_y_deg=22, width=96, height=96)
MAT = Material(Lambert((0.7, 0.3, 0.2)) + Phong(0.5, 40.0))
LIGHTS = [AmbientLight(intensity=0.1), DirectionalLight((-1, 1, 1.5)), PointLight((3, 2, 4.0), intensity=20.0)]


def test_analytic_sphere_is_kd_max_n_dot_l_per_pixel():
    kd = np.array([0.8, 0.6, 0.1])
    l_dir = np.array([0.2, -0.4, 0.9]) / np.linalg.norm([0.2, -0.4, 0.9])
    r = Renderer(AnalyticSphere(), CAM)
    img = r.render(Material(Lambert(kd)), [DirectionalLight(l_dir)])
    gb = r.gbuffer
    expected = kd * np.maximum(gb.normal @ l_dir, 0)[..., None]
    np.testing.assert_allclose(img, np.where(gb.coverage[..., None], expected, 0), rtol=1e-13, atol=1e-15)


def _sphere_error(mesh, mode, cam=CAM):
    ref = Renderer(AnalyticSphere(), cam).render(MAT, LIGHTS)
    r = Renderer(mesh, cam)
    img = r.render(MAT, LIGHTS, mode=mode)
    both = r.gbuffer.coverage & Renderer(AnalyticSphere(), cam).gbuffer.coverage
    return float(np.sqrt(np.mean((img[both] - ref[both]) ** 2)))


def test_phong_interpolation_error_falls_with_tessellation():
    errors = [_sphere_error(icosphere(level), "phong") for level in (1, 2, 3, 4)]
    assert all(b < a for a, b in zip(errors, errors[1:], strict=False))
    assert errors[-1] < errors[0] / 8


def test_gouraud_error_falls_with_tessellation_and_stays_above_phong():
    g = [_sphere_error(icosphere(level), "gouraud") for level in (1, 2, 3)]
    p = [_sphere_error(icosphere(level), "phong") for level in (1, 2, 3)]
    assert g[0] > g[1] > g[2]
    assert all(gi > pi for gi, pi in zip(g, p, strict=True))


def test_gouraud_misses_highlight_inside_a_large_triangle_phong_catches_it():
    # One big triangle facing the viewer, with vertex normals tilted outward (a coarse sphere cap):
    # the mirror direction lies inside the triangle, so the highlight peaks at no vertex.
    verts = np.array([[-1.0, -0.8, 0.0], [1.0, -0.8, 0.0], [0.0, 1.0, 0.0]])
    normals = verts * [0.6, 0.6, 0] + [0, 0, 1.0]
    mesh = TriangleMesh(verts, [[0, 1, 2]], normals=normals)
    cam = Camera((0, 0, 4.0), (0, 0, 0), projection="orthographic", ortho_height=2.2, width=80, height=80)
    mat = Material(Lambert(0.0) + Phong(1.0, 50.0), ambient=0.0)
    lights = [DirectionalLight((0, 0, 1.0))]
    r = Renderer(mesh, cam)
    gouraud = luminance(r.render(mat, lights, mode="gouraud"))
    phong = luminance(r.render(mat, lights, mode="phong"))
    # The interpolated normal is (0, 0, 1) at the origin, where l = v = +z gives the full highlight k_s = 1;
    # the nearest pixel centre is 0.014 away from it (cos^50 of the resulting angle: 0.98).
    assert phong.max() > 0.95
    vertex_values = Phong(1.0, 50.0).classic(normals, (0, 0, 1.0), (0, 0, 1.0))[:, 0]
    assert gouraud.max() <= vertex_values.max() + 1e-12 < 0.05


@pytest.mark.parametrize("mesh", [uv_sphere(10, 16), icosphere(2), icosphere(3)], ids=["uv288", "ico320", "ico1280"])
@pytest.mark.parametrize("specular", [0.0, 0.4])
def test_mach_band_metric_separates_gouraud_from_phong(mesh, specular):
    cam = Camera((0, 0, 6.0), (0, 0, 0), fov_y_deg=22, width=200, height=200)
    mat = Material(Lambert(0.8 - specular) + BlinnPhong(specular, 30.0), ambient=0.0)
    lights = [DirectionalLight((-0.6, 0.5, 1.0))]
    r = Renderer(mesh, cam)
    tid = r.gbuffer.triangle_id
    gouraud = edge_jump_metric(r.render(mat, lights, mode="gouraud"), tid)
    phong = edge_jump_metric(r.render(mat, lights, mode="phong"), tid)
    exact = edge_jump_metric(Renderer(AnalyticSphere(), cam).render(mat, lights), tid)
    assert gouraud > 2.5 * phong  # measured 3.4–45 over these meshes and materials
    assert exact < phong / 10  # the true sphere has no edges: what remains is the noise floor


def test_gouraud_profile_is_piecewise_linear():
    mesh = uv_sphere(10, 16)
    cam = Camera((0, 0, 6.0), (0, 0, 0), fov_y_deg=22, width=200, height=200)
    mat = Material(Lambert(0.8), ambient=0.0)
    r = Renderer(mesh, cam)
    tid = r.gbuffer.triangle_id
    img = r.render(mat, [DirectionalLight((-0.6, 0.5, 1.0))], mode="gouraud")
    prof = scanline_profile(img, 100, coverage=r.gbuffer.coverage)
    t = tid[100, prof.x]
    interior = (t[:-2] == t[1:-1]) & (t[1:-1] == t[2:])
    assert np.max(np.abs(prof.d2[interior])) < 5e-3 * np.max(np.abs(prof.d1))


def test_reshading_cached_buffer_equals_full_render():
    mesh = icosphere(3)
    r = Renderer(mesh, CAM)
    for mode in ("flat", "gouraud", "phong"):
        r.render(MAT, LIGHTS, mode=mode)
    moved = [AmbientLight(intensity=0.1), DirectionalLight((1, 0.2, 1.0)), PointLight((-3, 1, 4.0), intensity=15.0)]
    for mode in ("flat", "gouraud", "phong"):
        np.testing.assert_array_equal(r.render(MAT, moved, mode=mode), render(mesh, CAM, MAT, moved, mode=mode))
    assert r.rasterizations == 1
    r.camera = CAM.replace(width=64)
    assert r.render(MAT, moved).shape == (96, 64, 3) and r.rasterizations == 2


def test_flat_shading_is_one_evaluation_per_triangle_at_its_centroid():
    mesh = icosphere(1)
    r = Renderer(mesh, CAM)
    img = r.render(MAT, LIGHTS, mode="flat")
    tid = r.gbuffer.triangle_id
    centroids = mesh.vertices[mesh.faces].mean(axis=1)
    expected = shade(centroids, mesh.face_normals, MAT, LIGHTS, eye=CAM.eye)
    covered = tid >= 0
    np.testing.assert_allclose(img[covered], expected[tid[covered]], rtol=1e-14)


def test_gouraud_interpolates_vertex_colours():
    mesh = icosphere(2)
    r = Renderer(mesh, CAM)
    img = r.render(MAT, LIGHTS, mode="gouraud")
    vcol = shade(mesh.vertices, mesh.normals, MAT, LIGHTS, eye=CAM.eye)
    np.testing.assert_allclose(img, r.gbuffer.interpolate(vcol), rtol=1e-14, atol=1e-15)


def test_terms_add_up_and_float32_close():
    r = Renderer(icosphere(3), CAM)
    parts = r.render_terms(MAT, LIGHTS)
    np.testing.assert_allclose(sum(parts.values()), r.render(MAT, LIGHTS), rtol=1e-15)
    only_spec = r.render(MAT, LIGHTS, terms=["specular"])
    np.testing.assert_array_equal(only_spec, parts["specular"])
    r32 = Renderer(icosphere(3), CAM, dtype=np.float32)
    img32 = r32.render(MAT, LIGHTS)
    assert img32.dtype == np.float32
    np.testing.assert_allclose(img32, r.render(MAT, LIGHTS), atol=2e-5)


def test_bad_modes_and_geometry():
    with pytest.raises(ValueError, match="mode"):
        Renderer(icosphere(1), CAM).render(MAT, LIGHTS, mode="toon")
    with pytest.raises(ValueError, match="needs a triangle mesh"):
        Renderer(AnalyticSphere(), CAM).render(MAT, LIGHTS, mode="gouraud")
    with pytest.raises(ValueError, match="geometry"):
        Renderer("sphere", CAM)


def test_srgb_png_pipeline_counts_clipping():
    img = Renderer(AnalyticSphere(), sphere_camera(64)).render(
        Material(Lambert(0.5) + BlinnPhong(1.0, 20.0)), [DirectionalLight((0, 0, 1.0), intensity=1.5)]
    )
    rgb8, rep = encode_srgb8(img)
    assert rep.clipped_pixels == int(np.count_nonzero(np.any(img > 1, axis=-1))) > 0
    assert rgb8.dtype == np.uint8 and rgb8.max() == 255


def test_parallel_chunks_give_identical_pixels(monkeypatch):
    import lighting.shading.batch as il

    def frames():
        # Fresh renderers: their per-pixel samples (normals, view vectors) are built in chunks too.
        whole, part = Renderer(icosphere(3), CAM), Renderer(icosphere(3), CAM)
        part.restrict(np.arange(0, len(part.gbuffer.pixels), 3))
        return whole.render(MAT, LIGHTS), part.render(MAT, LIGHTS)

    monkeypatch.setattr(il, "_MIN_ROWS_PER_THREAD", 10**9)
    serial = frames()
    monkeypatch.setattr(il, "_MIN_ROWS_PER_THREAD", 500)
    monkeypatch.setattr(il, "_threads", lambda: 3)
    assert len(il._chunks(len(Renderer(icosphere(3), CAM).gbuffer.pixels) // 3)) == 3
    for parallel, one in zip(frames(), serial, strict=True):
        np.testing.assert_array_equal(parallel, one)
    assert serial[1].any() and np.count_nonzero(serial[1].any(axis=-1)) < np.count_nonzero(serial[0].any(axis=-1))


def test_view_vectors_at_pixels_are_the_pixel_rays():
    """The point seen at a pixel lies on its ray: v from the ray equals normalize(eye − p) of the buffer."""
    cam = Camera((0.7, 0.4, 3.0), (0, 0.1, 0), fov_y_deg=50, width=90, height=70)
    gb = Renderer(icosphere(3), cam).gbuffer
    cov = gb.coverage
    v, dist = cam.pixel_view_vectors(gb.pixels, gb.depth[cov])
    to_eye = cam.eye - gb.position[cov]
    length = np.linalg.norm(to_eye, axis=1)
    np.testing.assert_allclose(v, to_eye / length[:, None], rtol=0, atol=2e-14)
    np.testing.assert_allclose(dist, length, rtol=1e-14)
    _, directions = cam.rays()
    np.testing.assert_array_equal(v, -directions.reshape(-1, 3)[gb.pixels])
    v32, _ = cam.pixel_view_vectors(gb.pixels, dtype=np.float32)
    assert v32.dtype == np.float32 and np.array_equal(v32, v.astype(np.float32))
    ortho = cam.replace(projection="orthographic")
    v_o, dist_o = ortho.pixel_view_vectors(gb.pixels, gb.depth[cov])
    assert dist_o is None and v_o.tolist() == (-ortho.forward).tolist()


def test_directional_lights_need_no_interpolated_positions():
    from lighting.shading.equation import shade_prepared

    r = Renderer(icosphere(3), CAM)
    directional = [AmbientLight(intensity=0.1), DirectionalLight((1, 0.2, 1.0)), DirectionalLight((-1, 1, 0.5))]
    img = r.render(MAT, directional)
    assert ("points", "phong") not in r._cache  # the lights never asked where the points are
    gb = r.gbuffer
    cov = gb.coverage
    expected = shade(gb.position[cov], gb.normal[cov], MAT, directional, eye=CAM.eye)
    np.testing.assert_allclose(img[cov], expected, rtol=1e-12, atol=1e-14)
    positional = directional + [PointLight((-3, 1, 4.0), intensity=15.0)]
    img = r.render(MAT, positional)
    assert ("points", "phong") in r._cache
    expected = shade(gb.position[cov], gb.normal[cov], MAT, positional, eye=CAM.eye)
    np.testing.assert_allclose(img[cov], expected, rtol=1e-12, atol=1e-14)
    # points=None is refused, naming the light, when a light depends on the point.
    _, nrm, v, dist, _ = r._samples("phong")
    with pytest.raises(ValueError, match="points=None.*PointLight"):
        shade_prepared(None, nrm, v, MAT, positional, eye_distance=dist)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_gouraud_interpolating_saturated_vertex_colours_stays_finite(dtype):
    # Vertex colours at the dtype's largest value: barycentrics sum to 1 only up to rounding, so
    # Σ b_i c_i overflowed to inf (with a warning).  The interpolated image saturates instead.
    big = np.finfo(dtype).max
    hot = [DirectionalLight((0, 0, 1.0), intensity=1e308)] * 2
    r = Renderer(icosphere(2), Camera((0, 0, 5.0), (0, 0, 0), width=64, height=64), dtype=dtype)
    img = r.render(Material(Lambert(1.0)), hot, mode="gouraud")
    assert img.dtype == dtype and np.all(np.isfinite(img))
    assert img.max() == big and np.count_nonzero(img == big) > 100
    # GBuffer.interpolate of values at ± the largest float: within [-max, max], to rounding of Σ b_i = 1.
    gb = r.gbuffer
    vals = np.full((len(icosphere(2).vertices), 2), big, dtype=dtype)
    vals[:, 1] = -big
    out = gb.interpolate(vals)[gb.coverage]
    eps = np.finfo(dtype).eps
    assert out.dtype == dtype and np.all(np.isfinite(out))
    assert out[:, 0].min() >= big * (1 - 4 * eps) and out[:, 1].max() <= -big * (1 - 4 * eps)


def test_renderer_arguments_and_memory_are_checked_before_work():
    from lighting._budget import BudgetError
    from lighting._validate import ArgumentTypeError
    from lighting.render.sphere import render_sphere

    with pytest.raises(BudgetError, match=r"^size needs about .* \(a 60000x60000 image\), over the memory budget"):
        render_sphere(MAT, LIGHTS, size=60000)
    big = Renderer(icosphere(1), Camera((0, 0, 5.0), (0, 0, 0), width=40000, height=40000))
    with pytest.raises(BudgetError, match=r"^camera width x height \(40000x40000 pixels\)"):
        big.render(MAT, LIGHTS)
    assert big.rasterizations == 0
    with pytest.raises(ArgumentTypeError, match="^cull_backfaces must be True or False; got int 1"):
        Renderer(icosphere(1), CAM, cull_backfaces=1)
    with pytest.raises(ArgumentTypeError, match="^geometry must be a TriangleMesh or an AnalyticSphere; got str"):
        Renderer("sphere", CAM)
    r = Renderer(icosphere(1), CAM)
    with pytest.raises(ArgumentTypeError, match=r"^lights\[1\] must be a light"):
        r.render(MAT, [DirectionalLight(), None])
    with pytest.raises(ValueError, match=r"^subset must be a 1-D array of indices into gbuffer.pixels"):
        r.restrict([len(r.gbuffer.pixels)])
    with pytest.raises(ValueError, match="^background must be"):
        r.render(MAT, LIGHTS, background=-1.0)
    with pytest.raises(ValueError, match="^vertex_values must be finite"):
        r.gbuffer.interpolate(np.full(len(icosphere(1).vertices), np.nan))
    img = np.zeros((8, 8, 3))
    with pytest.raises(ValueError, match=r"^row must be an integer in \[0, 7\]; got 8"):
        scanline_profile(img, 8)
    with pytest.raises(TypeError, match="^channel must be 'luminance', 'r', 'g', 'b' or an integer 0..2; got bool"):
        scanline_profile(img, 0, channel=True)
    with pytest.raises(ValueError, match=r"^triangle_id must have the image's shape \(8, 8\)"):
        edge_jump_metric(img, np.zeros((4, 4), int))
    with pytest.raises(ValueError, match="^image must be finite linear RGB"):
        luminance(np.full((2, 3), np.nan))


# ----------------------------------------------------------------------------- normals facing the viewer
def test_face_viewer_turns_silhouette_normals_toward_the_eye_and_nothing_else():
    # A coarse sphere seen in perspective: Phong interpolation tips some silhouette normals away from the eye
    # (n·v < 0 on a triangle that faces it), and those pixels shade black under a sky.  face_viewer=True turns
    # exactly those normals into the visible hemisphere and leaves every other pixel's normal as it was.
    from lighting.render.renderer import FACING_COS, face_toward

    mesh = uv_sphere(6, 12)
    cam = Camera((0.0, 0.0, 3.2), (0.0, 0.0, 0.0), fov_y_deg=40.0, width=96, height=96)
    plain = Renderer(mesh, cam, face_viewer=False)
    faced = Renderer(mesh, cam, face_viewer=True)
    n0, n1 = plain.sample_normals("phong"), faced.sample_normals("phong")
    v, _ = plain.sample_view("phong")
    c0, c1 = np.einsum("ij,ij->i", n0, v), np.einsum("ij,ij->i", n1, v)
    away = c0 < FACING_COS
    assert away.sum() > 0  # the coarse sphere has such pixels
    np.testing.assert_array_equal(n1[~away], n0[~away])
    bound = FACING_COS / math.sqrt(1.0 + FACING_COS**2)
    assert np.all(c1[away] >= bound * (1 - 1e-12))
    np.testing.assert_allclose(np.linalg.norm(n1, axis=1), 1.0, rtol=1e-12)
    # A light at the eye (l = v at every point): the plain normals leave those pixels black, the turned ones lit.
    mat = Material(Lambert(0.8), ambient=0.0)
    lights = [PointLight((0.0, 0.0, 3.2), intensity=1.0)]
    cov = faced.gbuffer.coverage
    dark = plain.render(mat, lights, mode="phong")[cov].max(axis=1) == 0
    lit = faced.render(mat, lights, mode="phong")[cov].max(axis=1)
    assert dark.sum() == (c0 <= 0).sum() > 0 and np.all(lit > 0)
    # n = −v exactly has no plane to turn in: the normal becomes v.
    np.testing.assert_array_equal(face_toward(np.array([[0.0, 0.0, -1.0]]), np.array([0.0, 0.0, 1.0])),
                                  [[0.0, 0.0, 1.0]])  # fmt: skip


def test_a_shading_thread_that_asks_for_chunks_computes_them_itself(monkeypatch):
    """Work split into chunks from within a shading thread runs in that thread, every row once: handed to the pool
    that thread belongs to, it would wait forever once every thread of the pool waits so."""
    import threading

    import lighting.shading.batch as il

    monkeypatch.setattr(il, "_MIN_ROWS_PER_THREAD", 10)
    seen = np.zeros(1000, dtype=int)
    where = set()

    def mark(rows):
        seen[rows] += 1
        where.add(threading.current_thread().name)

    inner = threading.Thread(target=il.each_chunk, args=(1000, mark), name=il._THREAD_PREFIX + "_inner")
    inner.start()
    inner.join(timeout=20)
    assert where == {inner.name} and np.all(seen == 1)
    where.clear()
    il.each_chunk(1000, mark)  # from any other thread: on the pool's threads
    assert where and all(name.startswith(il._THREAD_PREFIX + "_") and name != inner.name for name in where)
    assert np.all(seen == 2)

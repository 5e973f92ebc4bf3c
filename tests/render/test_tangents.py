"""Tangents on meshes and through the renderer: anisotropic highlights oriented by the surface.

* mesh tangents: the spheres' ``∂p/∂φ`` about ``+y`` (exact), the default frame elsewhere and at the
  poles, ``∂p/∂u`` from texture coordinates (rotated and mirrored charts), transforms;
* the renderer's per-sample tangents: unit, perpendicular to the sample normals, within the
  tessellation's error of the exact ``∂p/∂φ``;
* images: every pixel equals the model evaluated directly at that pixel's geometry
  (``classic(n, l, v, tangent=t)``, through :func:`shade_reference`), in every mode; the highlight
  of an anisotropic Ward sphere is stretched along the parallels (``t``) or the meridians (``b``) as
  ``α_x`` and ``α_y`` say, by the extents the model predicts;
* isotropic materials never ask for tangents (their images are unchanged, bit for bit).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from lighting import DirectionalLight, Lambert, Material
from lighting.lights.punctual import PointLight
from lighting.models.cook_torrance import CookTorrance
from lighting.models.geometry import Geometry
from lighting.models.ward import Ward
from lighting.render.camera import Camera
from lighting.render.mesh import TriangleMesh, icosphere, load_mesh, uv_sphere
from lighting.render.renderer import AnalyticSphere, Renderer, needs_tangents
from lighting.render.tangents import default_tangents, orthonormal_tangents, sphere_tangents
from lighting.shading.reference import shade_reference


def _rows_dot(a, b):
    return np.einsum("ij,ij->i", a, b)


def _exact_dphi(n):
    """``ŷ × n / |ŷ × n|`` = ``(n_z, 0, −n_x) / √(n_x² + n_z²)``."""
    s = np.hypot(n[:, 0], n[:, 2])
    return np.stack([n[:, 2] / s, np.zeros_like(s), -n[:, 0] / s], axis=1)


# --------------------------------------------------------------------------- mesh tangents
@pytest.mark.parametrize("mesh", [uv_sphere(12, 24), icosphere(2)], ids=["uv", "ico"])
def test_sphere_tangents_are_d_dphi_and_the_default_frame_at_the_poles(mesh):
    n, t = mesh.normals, mesh.tangents
    np.testing.assert_allclose(np.linalg.norm(t, axis=1), 1.0, rtol=0, atol=4e-16)
    assert np.max(np.abs(_rows_dot(t, n))) < 4e-16
    pole = np.hypot(n[:, 0], n[:, 2]) < 1e-12
    np.testing.assert_allclose(t[~pole], _exact_dphi(n[~pole]), rtol=0, atol=4e-16)
    # At the poles (n = ±ŷ) the models' default frame: ẑ × n / |ẑ × n| = ∓x̂.
    np.testing.assert_array_equal(t[pole], default_tangents(n[pole]))
    assert pole.sum() == 2  # one vertex on each of ±ŷ
    # The uv sphere's φ grows from +z toward +x: the tangent at the vertex on +z is +x̂.
    front = np.argmax(n[:, 2])
    if n[front, 2] == 1.0:
        np.testing.assert_allclose(t[front], [1.0, 0.0, 0.0], atol=1e-16)


def test_default_frame_is_the_models_own():
    rng = np.random.default_rng(1)
    n = rng.normal(size=(500, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    n[:3] = [[0, 0, 1.0], [0, 0, -1.0], [0, 1.0, 0]]
    t = default_tangents(n)
    np.testing.assert_array_equal(t, Geometry(n, n, n, unit=True).t)
    np.testing.assert_array_equal(t[:3], [[1.0, 0, 0], [1.0, 0, 0], [-1.0, 0, 0]])
    # A mesh without tangents or texture coordinates carries the default frame at its vertices.
    m = TriangleMesh(icosphere(1).vertices, icosphere(1).faces)
    np.testing.assert_array_equal(m.tangents, default_tangents(m.normals))


def test_orthonormal_tangents_gram_schmidt_and_fallback():
    n = np.array([[0, 0, 1.0], [0, 0, 1.0], [0, 0, 1.0], [0.6, 0, 0.8]])
    t = np.array([[3.0, 4.0, 7.0], [0, 0, 2.0], [0, 0, 0], [0.8, 0, -0.6]])
    out = orthonormal_tangents(t, n)
    np.testing.assert_allclose(out, [[0.6, 0.8, 0], [1.0, 0, 0], [1.0, 0, 0], [0.8, 0, -0.6]], atol=1e-16)
    assert orthonormal_tangents(t.astype(np.float32), n.astype(np.float32)).dtype == np.float32


def _quad(uvs):
    v = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    return TriangleMesh(v, [[0, 1, 2], [0, 2, 3]], normals=[[0, 0, 1.0]] * 4, uvs=uvs)


def test_uv_tangents_follow_dp_du():
    square = [[0, 0], [1, 0], [1, 1], [0, 1]]
    np.testing.assert_allclose(_quad(square).tangents, [[1.0, 0, 0]] * 4, atol=1e-16)
    # u along +y (the chart turned by 90°): t = ŷ; a mirrored chart (u decreasing along x): t = −x̂.
    np.testing.assert_allclose(_quad([[0, 0], [0, 1], [1, 1], [1, 0]]).tangents, [[0, 1.0, 0]] * 4, atol=1e-16)
    np.testing.assert_allclose(_quad([[1, 0], [0, 0], [0, 1], [1, 1]]).tangents, [[-1.0, 0, 0]] * 4, atol=1e-16)
    # A chart turned by 30° and stretched: still ∂p/∂u's direction.
    c, s = math.cos(math.pi / 6), math.sin(math.pi / 6)
    uv = [[3 * (c * x + s * y), 0.5 * (-s * x + c * y)] for x, y in square]
    np.testing.assert_allclose(_quad(uv).tangents, [[c, s, 0]] * 4, atol=1e-15)
    # Degenerate texture coordinates: the default frame.
    np.testing.assert_array_equal(_quad([[0.5, 0.5]] * 4).tangents, [[1.0, 0, 0]] * 4)


def test_load_mesh_reads_texture_coordinates(tmp_path):
    obj = tmp_path / "quad.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 0 1\nvt 1 1\nvt 1 0\n"
                   "vn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nf 1/1/1 2/2/2 3/3/3\nf 1/1/1 3/3/3 4/4/4\n")  # fmt: skip
    m = load_mesh(obj)
    assert m.uvs is not None
    np.testing.assert_allclose(m.tangents, [[0, 1.0, 0]] * 4, atol=1e-16)


def test_transformed_tangents_map_with_the_surface():
    m = uv_sphere(6, 12)
    a = np.diag([2.0, 1.0, 0.5, 1.0])
    a[:3, :3] = a[:3, :3] @ np.array([[0, -1.0, 0], [1.0, 0, 0], [0, 0, 1.0]])  # scale after a quarter turn
    mt = m.transformed(a)
    t, n = mt.tangents, mt.normals
    assert np.max(np.abs(_rows_dot(t, n))) < 1e-15
    want = orthonormal_tangents(m.tangents @ a[:3, :3].T, n)
    np.testing.assert_allclose(t, want, atol=1e-15)
    with pytest.raises(ValueError, match="tangents"):
        TriangleMesh(m.vertices, m.faces, tangents=np.zeros((3, 3)))
    with pytest.raises(ValueError, match="uvs"):
        TriangleMesh(m.vertices, m.faces, uvs=np.full((m.n_vertices, 2), np.nan))


# --------------------------------------------------------------------------- through the renderer
CAM = Camera((0.0, 0.0, 5.0), (0.0, 0.0, 0.0), width=96, height=96)
ANISO = Material(Lambert(0.1) + Ward(0.8, 0.35, 0.06))


def test_only_anisotropic_materials_ask_for_tangents():
    assert needs_tangents(ANISO)
    assert needs_tangents(Material(CookTorrance(1.0, 0.2, ndf="ggx", geometry="smith", alpha_x=0.4, alpha_y=0.1)))
    assert not needs_tangents(Material(Lambert(0.5) + Ward(0.5, 0.2) + CookTorrance(0.5, 0.3)))


def test_renderer_tangents_are_unit_perpendicular_and_near_the_exact_ones():
    for geometry, tol in ((uv_sphere(48, 96), 0.02), (AnalyticSphere(), 1e-15)):
        r = Renderer(geometry, CAM)
        for mode in ("phong",) if isinstance(geometry, AnalyticSphere) else ("phong", "gouraud", "flat"):
            t, n = r.sample_tangents(mode), r.sample_normals(mode)
            np.testing.assert_allclose(np.linalg.norm(t, axis=1), 1.0, atol=2e-15)
            assert np.max(np.abs(_rows_dot(t, n))) < 2e-15
            away = np.hypot(n[:, 0], n[:, 2]) > 0.2  # the pole's neighbourhood turns through every direction
            err = np.linalg.norm(t[away] - _exact_dphi(n[away]), axis=1).max()
            assert err < (tol if mode == "phong" else 0.1), (mode, err)


@pytest.mark.parametrize("mode", ["phong", "gouraud", "flat"])
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_every_pixel_is_the_model_at_that_pixels_geometry(mode, dtype):
    r = Renderer(uv_sphere(16, 32), Camera((0.5, 1.0, 4.0), (0, 0, 0), width=48, height=48), dtype=dtype)
    lights = [DirectionalLight((0.3, 0.4, 1.0), color=(1.0, 0.9, 0.8)), PointLight((2.0, 1.0, 3.0), color=0.5)]
    colours = r.spread(mode, shade_reference(r.sample_points(mode), r.sample_normals(mode), ANISO, lights,
                                             eye=r.camera.eye, tangents=r.sample_tangents(mode)))  # fmt: skip
    img = r.render(ANISO, lights, mode=mode)
    assert img.dtype == dtype
    np.testing.assert_allclose(img, colours, rtol=4 * np.finfo(dtype).eps * 8, atol=4 * np.finfo(dtype).eps)
    # Without the surface's tangents (the default frame about z) the image differs: the tangents were used.
    plain = r.spread(mode, shade_reference(r.sample_points(mode), r.sample_normals(mode), ANISO, lights,
                                           eye=r.camera.eye))  # fmt: skip
    assert np.max(np.abs(plain - colours)) > 0.05


def _half_max_extent(profile):
    """Pixels at or above half the peak along a line through it, counted contiguously from the peak."""
    k = int(np.argmax(profile))
    half = profile[k] / 2
    lo = k
    while lo > 0 and profile[lo - 1] >= half:
        lo -= 1
    hi = k
    while hi < len(profile) - 1 and profile[hi + 1] >= half:
        hi += 1
    return hi - lo + 1


def _predicted_extent(model, axis, cam):
    """The half-maximum extent in pixels along the image's ``x`` (axis 0) or ``y`` (axis 1) through the centre.

    The unit sphere lit and seen along +z: along the equator ``n = (sin a, 0, cos a)``, along the
    meridian ``n = (0, sin a, cos a)``, with the sphere's ``t = ŷ × n/|ŷ × n|``; the model's own
    ``classic`` there, the half-maximum angle by bisection, and the pixel scale of the camera.
    """
    z = np.array([0.0, 0.0, 1.0])

    def value(a):
        n = np.array([math.sin(a), 0.0, math.cos(a)]) if axis == 0 else np.array([0.0, math.sin(a), math.cos(a)])
        return float(model.classic(n, z, z, tangent=sphere_tangents(n[None])[0])[0])

    peak = value(0.0)
    lo, hi = 0.0, 1.2
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if value(mid) >= peak / 2 else (lo, mid)
    x = math.sin(lo)  # the point's distance from the centre on the image plane
    p = cam.project(np.array([[x, 0.0, math.cos(lo)], [0.0, 0.0, 1.0]]))[0] if axis == 0 else \
        cam.project(np.array([[0.0, x, math.cos(lo)], [0.0, 0.0, 1.0]]))[0]  # fmt: skip
    return 2 * abs(p[0, axis] - p[1, axis])


@pytest.mark.parametrize("axes", [(0.4, 0.1), (0.1, 0.4)])
def test_highlight_is_stretched_along_the_chosen_direction(axes):
    cam = Camera((0.0, 0.0, 6.0), (0.0, 0.0, 0.0), width=241, height=241, projection="orthographic", ortho_height=2.4)
    ward = Ward(1.0, *axes)
    img = Renderer(AnalyticSphere(), cam).render(Material(ward), [DirectionalLight((0.0, 0.0, 1.0))])[..., 0]
    cy, cx = np.unravel_index(np.argmax(img), img.shape)
    assert (cy, cx) == (120, 120)
    along_x, along_y = _half_max_extent(img[cy]), _half_max_extent(img[:, cx])
    # Predicted from the model at the sphere's exact geometry (measured 71 and 17 px, predicted 71.0 and 16.8).
    want_x, want_y = _predicted_extent(ward, 0, cam), _predicted_extent(ward, 1, cam)
    assert abs(along_x - want_x) <= 2 and abs(along_y - want_y) <= 2, (along_x, want_x, along_y, want_y)
    # α_x along t (the parallels: the image's x here), α_y along b (the meridians: y).
    assert (along_x > 3 * along_y) == (axes[0] > axes[1]) and (along_y > 3 * along_x) == (axes[1] > axes[0])


def test_isotropic_materials_shade_without_tangents():
    r = Renderer(uv_sphere(16, 32), CAM)
    mat = Material(Lambert(0.5) + Ward(0.5, 0.2) + CookTorrance(0.5, 0.3, ndf="ggx", geometry="smith"))
    for mode in ("phong", "gouraud", "flat"):
        r.render(mat, [DirectionalLight((0.2, 0.3, 1.0))], mode=mode)
    assert not any(key[0] == "tangents" for key in r._cache)

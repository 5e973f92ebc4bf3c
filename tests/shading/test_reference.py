"""shade() and the renderer against the reference loop (lighting.shading.reference) on random scenes.

The fast path (lighting.shading.batch) sums the same terms in another order: channel planes, stacked
directional lights, tangent forms of the lobes, and in the working dtype.  So the two agree to rounding,
not bitwise.  The tolerance is ``K · eps(dtype) · (1 + e) · (|ref| + peak/10)`` per channel, where ``e``
is the sharpest lobe's exponent (``Δ(x^e) ≈ e x^(e−1) Δx``: an error of a few ulps in a cosine is
multiplied by ``e`` in a highlight) and ``peak`` the scene's brightest value (an error in a highlight's
cosine is absolute in the cosine, so it scales with the highlight, not with a dim neighbour).  The
reference runs in float64 on the same (dtype-rounded) inputs, so float32 is held to float32's eps.
"""

import numpy as np
import pytest

from lighting import Material
from lighting.lights import AmbientLight, DirectionalLight, PointLight, RectLight, SpotLight
from lighting.models import BlinnPhong, CookTorrance, Lambert, Phong
from lighting.render.camera import Camera
from lighting.render.mesh import icosphere
from lighting.render.renderer import Renderer
from lighting.shading.equation import shade
from lighting.shading.reference import shade_reference

K = 4  # ulps per unit of (1 + e): the worst case over these seeds uses about a sixth of it


def _unit(rng, n):
    x = rng.normal(size=(n, 3))
    return x / np.linalg.norm(x, axis=1, keepdims=True)


def _material(rng):
    """A random surface: Lambert plus one specular model, and its sharpest exponent."""
    kd = rng.uniform(0, 1, 3)
    e = float(rng.uniform(1, 120))
    alpha = float(rng.uniform(0.15, 0.8))
    specular = [
        (Phong(rng.uniform(0, 1, 3), e), e),
        (BlinnPhong(rng.uniform(0, 1, 3), e), e),
        (BlinnPhong(rng.uniform(0, 1, 3), e, normalized=True), e),
        (CookTorrance(rng.uniform(0, 1), alpha, rng.uniform(0.02, 0.9, 3), ndf=str(rng.choice(["beckmann", "ggx"])),
                      geometry=str(rng.choice(["v-cavity", "smith"])),
                      fresnel=str(rng.choice(["schlick", "dielectric", "none"]))), 2 / alpha**2),  # fmt: skip
    ]
    model, sharp = specular[rng.integers(len(specular))]
    return Material(Lambert(kd) + model, emission=rng.uniform(0, 0.1, 3)), sharp


def _lights(rng):
    lights = [AmbientLight(rng.uniform(0, 1, 3), 0.1)]
    lights += [DirectionalLight(_unit(rng, 1)[0], color=rng.uniform(0, 1, 3)) for _ in range(rng.integers(1, 4))]
    lights.append(PointLight(rng.normal(size=3) * 3, intensity=float(rng.uniform(1, 10)),
                             attenuation=tuple(rng.uniform(0, 1, 3) + [0, 0, 0.1])))  # fmt: skip
    lights.append(SpotLight(position=rng.normal(size=3) * 3, direction=-_unit(rng, 1)[0], intensity=5.0,
                            cutoff_deg=float(rng.uniform(20, 90)), exponent=float(rng.uniform(0, 20))))  # fmt: skip
    lights.append(RectLight(center=(0.5, 0.5, 4.0), edge_u=(1.0, 0, 0), edge_v=(0, -1.0, 0), intensity=3.0,
                            samples=4, seed=int(rng.integers(100))))  # fmt: skip
    return lights


def _check(got, ref, dtype, sharp):
    peak = float(np.max(ref))
    tol = K * np.finfo(dtype).eps * (1 + sharp) * (np.abs(ref) + peak / 10)
    err = np.abs(np.asarray(got, np.float64) - ref)
    assert got.dtype == dtype
    assert np.all(err <= tol), f"worst error {float(np.max(err / tol)):.3g} × tolerance"


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("form", ["classic", "physical"])
@pytest.mark.parametrize("seed", range(6))
def test_shade_matches_the_reference_loop(seed, form, dtype):
    rng = np.random.default_rng(seed)
    material, sharp = _material(rng)
    lights = _lights(rng)
    n = 400
    points = (rng.normal(size=(n, 3)) * 0.8).astype(dtype)
    normals = _unit(rng, n).astype(dtype)
    viewer = dict(eye=rng.normal(size=3) + [0, 0, 6]) if seed % 2 else dict(view_dir=_unit(rng, 1)[0])
    got = shade(points, normals, material, lights, form=form, **viewer)
    ref = shade_reference(points, normals, material, lights, form=form, **viewer)
    assert ref.dtype == np.float64 and np.all(np.isfinite(ref)) and np.max(ref) > 0
    _check(got, ref, dtype, sharp)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("form", ["classic", "physical"])
@pytest.mark.parametrize("seed", range(3))
def test_renderer_matches_the_reference_loop(seed, form, dtype):
    rng = np.random.default_rng(100 + seed)
    material, sharp = _material(rng)
    lights = _lights(rng)
    mesh = icosphere(int(rng.integers(1, 4)))
    cam = Camera(tuple(rng.normal(size=3) * 0.5 + [0, 0, 4.0]), (0, 0, 0), fov_y_deg=45, width=48, height=40)
    r = Renderer(mesh, cam, dtype=dtype)
    for mode in ("phong", "gouraud", "flat"):
        img = r.render(material, lights, mode=mode, form=form)
        ref = shade_reference(r.sample_points(mode), r.sample_normals(mode), material, lights, eye=cam.eye, form=form)
        if mode == "phong":
            _check(img[r.gbuffer.coverage], ref, dtype, sharp)
        else:
            # Colours at the vertices (gouraud) or faces (flat), spread by the same interpolation.
            _check(img, r.spread(mode, ref).astype(np.float64), dtype, sharp)


def test_shade_takes_one_view_direction_and_names_any_other_shape():
    mat = Material(Lambert(0.5))
    light = [DirectionalLight((0, 0, 1.0))]
    one = shade(None, (0, 0, 1.0), mat, light, view_dir=(1.0, 2.0, 3.0))
    np.testing.assert_allclose(one, [0.5, 0.5, 0.5], rtol=1e-15)  # k_d (n·l) with n = l
    for bad, shape in ((((1.0, 2.0, 3.0),), r"\(1, 3\)"), (np.ones((4, 3)), r"\(4, 3\)")):
        with pytest.raises(ValueError, match=rf"^view_dir must be one finite nonzero 3-vector .*got shape {shape}"):
            shade(None, (0, 0, 1.0), mat, light, view_dir=bad)

"""Fuzz probe of the public API of lights, the illumination equation, the renderer, camera and rasterizer.

Finite in, finite out, checked arguments and the camera's extremes kept as seeded, bounded probes (hypothesis with
``derandomize=True``):

(a) legal extremes, float32 and float64: lights at huge and tiny distances, attenuations from 1e-300
    to 1e300, spot cutoffs 0/90/180 and exponents 0..128 and beyond, colours and intensities up to
    1e300, points near the dtype's float range, grazing, zero and huge normals, zero spot factors,
    viewers near and far.  Through :func:`shade`, :func:`shade_terms`, :func:`render_sphere` and the
    :class:`Renderer` (flat, Gouraud, Phong): every result finite, >= 0, of the input dtype, and no
    warning;
(b) illegal values, one per call, to every public function and constructor of lights, illumination,
    render, camera, raster, analytic, machband and plan: each must raise ``ValueError``/``TypeError``
    whose message names the parameter.

Failures are counted by kind rather than stopping at the first, and each test prints one summary
line (``pytest -s`` shows it) before asserting that there are none.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from probes import PROBE_SETTINGS, IllegalTally, LegalTally

from lighting import (
    AmbientLight,
    BlinnPhong,
    CookTorrance,
    DirectionalLight,
    DiskLight,
    Lambert,
    Material,
    Phong,
    PointLight,
    RectLight,
    SpotLight,
    shade,
    shade_terms,
)
from lighting._text import quote
from lighting.analysis.machband import edge_jump_metric, luminance, scanline_profile
from lighting.render.camera import Camera
from lighting.render.mesh import icosphere
from lighting.render.plan import bounding_sphere, compile_plan, evaluate_full
from lighting.render.raster import rasterize, raycast_sphere
from lighting.render.renderer import AnalyticSphere, Renderer, render
from lighting.render.sphere import render_sphere, sphere_camera

pytestmark = pytest.mark.slow  # seeded probe: many generated calls of the shading API

SETTINGS = PROBE_SETTINGS | dict(suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
DTYPES = (np.float32, np.float64)
BIG = {np.float32: float(np.finfo(np.float32).max), np.float64: float(np.finfo(np.float64).max)}
MESH = icosphere(1)

# --------------------------------------------------------------------------- legal values
SCALES = [0.0, 1e-300, 1e-30, 1e-8, 0.5, 1.0, 1e8, 1e30, 1e300]
ATTENUATION = [0.0, 1e-300, 1e-30, 1.0, 1e30, 1e300]
DISTANCES = [1e-300, 1e-170, 1e-30, 1e-8, 1e-3, 1.0, 10.0, 1e8, 1e30, 1e150, 1e300, 1e308]
CUTOFFS = [0.0, 1e-8, 1.0, 30.0, 45.0, 89.999, 90.0, 180.0]
EXPONENTS = [0.0, 1e-300, 0.5, 1.0, 2.0, 16.0, 128.0, 129.0, 1e6, 1e300]

scales = st.sampled_from(SCALES)
colours = st.one_of(scales, st.tuples(scales, scales, scales))


@st.composite
def directions(draw, allow_zero=False):
    """Unit, grazing (1e-30 above the horizon), exactly horizontal, below, tiny and huge directions."""
    picks = [(0, 0, 1.0), (1.0, 0, 0), (0.6, 0, 0.8), (-0.6, 0, 0.8), (1.0, 0, 1e-30), (0, 1.0, -1e-8),
             (0, 0, -1.0), (3e-30, 0, 4e-30), (1e30, 1e30, 1e30), (1e-300, 0, 1e-300), (1e300, -1e300, 1e300)]
    if allow_zero:
        picks.append((0, 0, 0.0))
    rnd = draw(st.tuples(*[st.floats(-1, 1)] * 3))
    if any(rnd):
        picks.append(rnd)
    return draw(st.sampled_from(picks))


@st.composite
def lights(draw):
    kind = draw(st.sampled_from(["ambient", "directional", "point", "spot", "rect", "disk"]))
    colour, intensity = draw(colours), draw(scales)
    if kind == "ambient":
        return AmbientLight(colour, intensity)
    if kind == "directional":
        return DirectionalLight(draw(directions()), colour, intensity)
    dist = draw(st.sampled_from(DISTANCES))
    unit = draw(st.sampled_from([(0, 0, 1.0), (0.6, 0, 0.8), (-0.48, 0.6, 0.64), (1.0, 0, 0), (0, -1.0, 0)]))
    position = tuple(dist * x for x in unit)
    att = draw(st.tuples(*[st.sampled_from(ATTENUATION)] * 3).filter(any))
    if kind == "point":
        return PointLight(position, colour, intensity, att)
    if kind == "spot":
        cutoff, exponent = draw(st.sampled_from(CUTOFFS)), draw(st.sampled_from(EXPONENTS))
        return SpotLight(position, colour, intensity, att, direction=draw(directions()), cutoff_deg=cutoff,
                         exponent=exponent)  # fmt: skip
    size = draw(st.sampled_from([1e-100, 1e-3, 1.0, 1e3, 1e100]))
    samples, seed, two = draw(st.integers(1, 6)), draw(st.one_of(st.none(), st.integers(0, 99))), draw(st.booleans())
    if kind == "rect":
        return RectLight(center=position, edge_u=(size, 0, 0), edge_v=(0, -size, 0), color=colour, intensity=intensity,
                         samples=samples, seed=seed, two_sided=two)  # fmt: skip
    return DiskLight(center=position, normal_dir=draw(directions()), radius=size, color=colour, intensity=intensity,
                     samples=samples, seed=seed, two_sided=two)  # fmt: skip


models = st.one_of(
    st.builds(Lambert, colours),
    st.builds(lambda kd, ks, e: Lambert(kd) + Phong(ks, e), colours, colours, st.sampled_from(EXPONENTS)),
    st.builds(lambda ks, e, nz: BlinnPhong(ks, e, nz), colours, st.sampled_from(EXPONENTS), st.booleans()),
    st.builds(lambda ks, a: CookTorrance(ks, a, 0.04, ndf="ggx", geometry="smith"), colours,
              st.sampled_from([1e-6, 1e-3, 0.3, 1.0, 3.0])),  # fmt: skip
)
materials = st.builds(lambda b, ka, ke: Material(b, ambient=ka, emission=ke), models, st.one_of(st.none(), colours),
                      colours)  # fmt: skip


@st.composite
def surfaces(draw, dtype):
    """Points (some near the dtype's float range), normals (grazing, zero, huge) and a viewer."""
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    k = 12
    top = 0.25 * BIG[dtype]
    mags = np.array([0.0, 1e-30, 1.0, 1e10, 1e30, top], dtype=np.float64)
    pts = rng.normal(size=(k, 3)) * mags[rng.integers(0, len(mags), (k, 1))]
    pts = np.clip(pts, -top, top).astype(dtype)
    normal_pool = np.array([[0, 0, 1.0], [0, 0, 1e-30], [1.0, 0, 1e-30], [0, 0, 0], [0, 0, 1e30], [0.6, 0, 0.8],
                            [0, 0, -1.0], [1e-30, 1e-30, 1e-30]])  # fmt: skip
    nrm = normal_pool[rng.integers(0, len(normal_pool), k)]
    nrm = np.where((rng.random(k) < 0.3)[:, None], rng.normal(size=(k, 3)), nrm).astype(dtype)
    if draw(st.booleans()):
        eye = tuple(float(x) * draw(st.sampled_from([1e-30, 1.0, 1e10, top])) for x in draw(directions()))
        eye = tuple(float(np.clip(x, -top, top)) for x in eye)
        return pts, nrm, dict(eye=eye)
    return pts, nrm, dict(view_dir=draw(directions()))


def test_probe_shading_legal_extremes():
    tally = LegalTally()

    @settings(max_examples=400, **SETTINGS)
    @given(st.data(), materials, st.lists(lights(), min_size=1, max_size=4), st.sampled_from(DTYPES),
           st.sampled_from(["classic", "physical"]))  # fmt: skip
    def run(data, material, lts, dtype, form):
        pts, nrm, viewer = data.draw(surfaces(dtype))
        what = f"{material!r} {lts!r} {viewer} {np.dtype(dtype).name} {form}"
        tally.check("shade " + what, lambda: shade(pts, nrm, material, lts, form=form, **viewer), dtype=dtype)
        tally.check("shade_terms " + what, lambda: shade_terms(pts, nrm, material, lts, form=form, **viewer),
                    dtype=dtype)  # fmt: skip
        tally.check("light+viewer " + what,
                    lambda: shade(pts, nrm, material, lts, eye=(0, 0, 1e30), attenuation_distance="light+viewer"),
                    dtype=dtype)  # fmt: skip
        for lt in lts:
            if not isinstance(lt, AmbientLight):
                tally.check("incident " + what, lambda lt=lt: [i.irradiance for i in lt.incident(pts)], dtype=dtype)

    run()

    @settings(max_examples=60, **SETTINGS)
    @given(materials, st.lists(lights(), min_size=1, max_size=3), st.sampled_from(DTYPES),
           st.sampled_from(["flat", "gouraud", "phong"]), st.sampled_from([1e-3, 3.0, 1e10, 1e150, 1e300]),
           st.sampled_from(["perspective", "orthographic"]), st.integers(1, 14))  # fmt: skip
    def run_images(material, lts, dtype, mode, distance, projection, size):
        what = f"{material!r} {lts!r} {np.dtype(dtype).name} {mode} eye at {distance} {projection} {size}px"
        cam = Camera((0, distance * 0.6, distance * 0.8), (0, 0, 0), projection=projection, width=size, height=size,
                     ortho_height=2.5)  # fmt: skip
        tally.check("render_sphere " + what, lambda: render_sphere(material, lts, size=size).astype(np.float64),
                    dtype=np.float64)  # fmt: skip
        tally.check("Renderer(mesh) " + what, lambda: Renderer(MESH, cam, dtype=dtype).render(material, lts, mode=mode),
                    dtype=dtype)  # fmt: skip
        tally.check("Renderer(sphere) " + what,
                    lambda: Renderer(AnalyticSphere(radius=distance / 4), cam, dtype=dtype).render(material, lts),
                    dtype=dtype)  # fmt: skip
        r = Renderer(MESH, cam, dtype=dtype)
        tally.check("compile_plan.execute " + what,
                    lambda: compile_plan(material, lts, mode=mode, bounds=bounding_sphere(MESH)).execute(r),
                    dtype=dtype)  # fmt: skip
        tally.check("evaluate_full " + what, lambda: evaluate_full(r, material, lts, mode=mode), dtype=dtype)

    run_images()
    # A diffuse surface under directional lights takes the plan's own path (no light loop).
    for dtype in DTYPES:
        r = Renderer(MESH, Camera((0, 0, 5.0), (0, 0, 0), width=12, height=12), dtype=dtype)
        for kd in SCALES:
            for intensity in SCALES:
                lts = [AmbientLight(kd, intensity), DirectionalLight((0, 0.6, 0.8), kd, intensity)]
                tally.check(f"diffuse-directional plan kd={kd} I={intensity} {np.dtype(dtype).name}",
                            lambda kd=kd, lts=lts, r=r: compile_plan(Material(Lambert(kd)), lts).execute(r),
                            dtype=dtype)  # fmt: skip
    print(f"\nprobe shading (legal extremes): {tally.summary()}")
    assert tally.cases >= 1500
    assert not tally.failures, tally.examples


# --------------------------------------------------------------------------- illegal values
NAN, INF = float("nan"), float("inf")
BAD_NUMBERS = [NAN, INF, -INF, 1j, "1", b"1", None, [1, 2], {"a": 1}]
BAD_VECTORS = [(0, NAN, 1.0), (INF, 0, 0), (1j, 0, 0), ("1", "2", "3"), b"123", "abc", None, 5.0, (1.0, 2.0),
               [[0, 0, 1.0], [0, NAN, 1.0]], {"x": 1}]  # fmt: skip
MAT = Material(Lambert(0.5) + Phong(0.5, 10))
LIGHTS = [AmbientLight(), DirectionalLight(), PointLight((1, 2, 3.0))]
P, N = np.zeros((2, 3)), np.array([[0, 0, 1.0], [0, 1.0, 0]])
CAM = Camera((0, 0, 5.0), (0, 0, 0), width=8, height=8)


def _illegal_calls():
    """``(label, parameter, call)``: one illegal argument per call, everything else legal."""
    calls = []

    def add(label, param, fn):
        calls.append((label, param, fn))

    # -- shade / shade_terms
    for f in (shade, shade_terms):
        name = f.__name__
        for bad in BAD_VECTORS:
            add(f"{name}(points={bad!r})", "points", lambda f=f, b=bad: f(b, N, MAT, LIGHTS, view_dir=(0, 0, 1.0)))
            add(f"{name}(normals={bad!r})", "normals", lambda f=f, b=bad: f(P, b, MAT, LIGHTS, view_dir=(0, 0, 1.0)))
            if bad is not None:
                add(f"{name}(eye={bad!r})", "eye", lambda f=f, b=bad: f(P, N, MAT, LIGHTS, eye=b))
                add(f"{name}(view_dir={bad!r})", "view_dir", lambda f=f, b=bad: f(P, N, MAT, LIGHTS, view_dir=b))
        add(f"{name}(view_dir=0)", "view_dir", lambda f=f: f(P, N, MAT, LIGHTS, view_dir=(0, 0, 0)))
        add(f"{name}(points=None, point light)", "points", lambda f=f: f(None, N, MAT, LIGHTS, view_dir=(0, 0, 1.0)))
        add(f"{name}(points=(5, 3))", "points", lambda f=f: f(np.zeros((5, 3)), N, MAT, LIGHTS, view_dir=(0, 0, 1.0)))
        add(f"{name}(eye and view_dir)", "eye", lambda f=f: f(P, N, MAT, LIGHTS, eye=(0, 0, 5.0), view_dir=(0, 0, 1.0)))
        add(f"{name}(neither eye nor view_dir)", "view_dir", lambda f=f: f(P, N, MAT, LIGHTS))
        for bad in ["lambert", Lambert(0.5), None, 1.0]:
            add(f"{name}(material={bad!r})", "material", lambda f=f, b=bad: f(P, N, b, LIGHTS, view_dir=(0, 0, 1.0)))
        for bad in [None, 5, "sun", DirectionalLight(), [DirectionalLight(), "sun"], [None], {"a": 1}]:
            add(f"{name}(lights={bad!r})", "lights", lambda f=f, b=bad: f(P, N, MAT, b, view_dir=(0, 0, 1.0)))
        for bad in ["pbr", 1, None, b"classic"]:
            add(f"{name}(form={bad!r})", "form", lambda f=f, b=bad: f(P, N, MAT, LIGHTS, view_dir=(0, 0, 1.0), form=b))
            add(f"{name}(attenuation_distance={bad!r})", "attenuation_distance",
                lambda f=f, b=bad: f(P, N, MAT, LIGHTS, view_dir=(0, 0, 1.0), attenuation_distance=b))  # fmt: skip
        for bad in ["diffuse", {"diffuse"}, {"diffuse": 1}, ["glow"], [1], None, 5]:
            add(f"{name}(terms={bad!r})", "terms",
                lambda f=f, b=bad: f(P, N, MAT, LIGHTS, view_dir=(0, 0, 1.0), terms=b))  # fmt: skip

    # -- Material and lights
    for bad in ["lambert", None, 0.5, Material]:
        add(f"Material(brdf={bad!r})", "brdf", lambda b=bad: Material(b))
    for key in ("ambient", "emission"):
        for bad in BAD_NUMBERS + [-1.0, (1, 0, -1e-300), (1, 2)]:
            if not (key == "ambient" and bad is None):
                add(f"Material({key}={bad!r})", key, lambda k=key, b=bad: Material(Lambert(0.5), **{k: b}))
    vector_params = [(DirectionalLight, "direction", {}), (PointLight, "position", {}), (SpotLight, "position", {}),
                     (SpotLight, "direction", {}), (RectLight, "center", {}), (RectLight, "edge_u", {}),
                     (RectLight, "edge_v", {}), (DiskLight, "center", {}), (DiskLight, "normal_dir", {})]  # fmt: skip
    for cls, key, extra in vector_params:
        for bad in BAD_VECTORS + [(1e400, 0, 0)]:
            add(f"{cls.__name__}({key}={bad!r})", key, lambda c=cls, k=key, b=bad, e=extra: c(**{k: b}, **e))
    for cls, key in [(DirectionalLight, "direction"), (SpotLight, "direction"), (DiskLight, "normal_dir")]:
        add(f"{cls.__name__}({key}=0)", key, lambda c=cls, k=key: c(**{k: (0, 0, 0)}))
    for cls in (AmbientLight, DirectionalLight, PointLight, SpotLight, RectLight, DiskLight):
        for bad in BAD_NUMBERS + [-1.0, -1e-300, True]:
            add(f"{cls.__name__}(intensity={bad!r})", "intensity", lambda c=cls, b=bad: c(intensity=b))
        for bad in BAD_NUMBERS + [-1.0, (1, 0, -1.0), (1, 2), (1, 2, 3, 4)]:
            if bad is not None:
                add(f"{cls.__name__}(color={bad!r})", "color", lambda c=cls, b=bad: c(color=b))
    for cls in (PointLight, SpotLight):
        for bad in BAD_NUMBERS + [(0, 0, 0), (1, -1, 0), (1, 0), (NAN, 0, 1), (1, INF, 0), 1.0, "(1, 0, 0)"]:
            add(f"{cls.__name__}(attenuation={bad!r})", "attenuation", lambda c=cls, b=bad: c(attenuation=b))
    for bad in BAD_NUMBERS + [-1.0, 90.0001, 120.0, 179.9, 180.1, 360.0, True]:
        add(f"SpotLight(cutoff_deg={bad!r})", "cutoff_deg", lambda b=bad: SpotLight(cutoff_deg=b))
    for bad in BAD_NUMBERS + [-1.0, -1e-300, True]:
        add(f"SpotLight(exponent={bad!r})", "exponent", lambda b=bad: SpotLight(exponent=b))
    for cls in (RectLight, DiskLight):
        for bad in [0, -1, 1.5, "16", b"16", None, True, 10**9, 2**63, NAN]:
            add(f"{cls.__name__}(samples={bad!r})", "samples", lambda c=cls, b=bad: c(samples=b))
        for bad in [-1, 1.5, "1", True, NAN]:
            add(f"{cls.__name__}(seed={bad!r})", "seed", lambda c=cls, b=bad: c(seed=b))
        for bad in [1, 0, "yes", None, 1.0]:
            add(f"{cls.__name__}(two_sided={bad!r})", "two_sided", lambda c=cls, b=bad: c(two_sided=b))
    for bad in BAD_NUMBERS + [0.0, -1.0, 1e-400]:
        add(f"DiskLight(radius={bad!r})", "radius", lambda b=bad: DiskLight(radius=b))
    add("RectLight(edge_u parallel to edge_v)", "edge_u", lambda: RectLight(edge_u=(1, 0, 0), edge_v=(2, 0, 0)))
    for key in ("elevation_deg", "azimuth_deg"):
        for bad in BAD_NUMBERS:
            args = dict(elevation_deg=30.0, azimuth_deg=0.0) | {key: bad}
            add(f"DirectionalLight.from_angles({key}={bad!r})", key, lambda a=args: DirectionalLight.from_angles(**a))
    for bad in BAD_VECTORS:
        add(f"PointLight.incident(points={bad!r})", "points", lambda b=bad: next(PointLight().incident(b)))
    for bad in ["float16", np.int32, "x", 5, np.complex64]:
        add(f"PointLight.incident(dtype={bad!r})", "dtype", lambda b=bad: next(PointLight().incident(P, dtype=b)))
    for bad in [-1.0, NAN, "1", 1j]:
        add(f"PointLight.incident(extra_distance={bad!r})", "extra_distance",
            lambda b=bad: next(PointLight().incident(P, extra_distance=b)))  # fmt: skip
    for bad in [NAN, "0.5", 1j, None]:
        add(f"SpotLight.spot_factor(cos_angle={bad!r})", "cos_angle", lambda b=bad: SpotLight().spot_factor(b))

    # -- camera (item 16: the offending quantity is blamed, never up)
    for key in ("eye", "target", "up"):
        for bad in BAD_VECTORS + [(1e400, 0, 0)]:
            args = dict(eye=(0, 0, 5.0), target=(0, 0, 0.0)) | {key: bad}
            add(f"Camera({key}={bad!r})", key, lambda a=args: Camera(**a))
    add("Camera(eye=-1e308, target=1e308)", "eye", lambda: Camera((-1e308, 0, 0), (1e308, 0, 0)))
    add("Camera(eye=target)", "eye", lambda: Camera((1, 2, 3), (1, 2, 3)))
    add("Camera(up=0)", "up", lambda: Camera((0, 0, 5), (0, 0, 0), up=(0, 0, 0)))
    add("Camera(up parallel)", "up", lambda: Camera((0, 5, 0), (0, 0, 0)))
    for key, bads in [("fov_y_deg", BAD_NUMBERS + [0.0, 180.0, -5.0, True]),
                      ("ortho_height", BAD_NUMBERS + [0.0, -1.0]),
                      ("width", [0, -1, 1.5, "8", b"8", None, True, NAN, 10**6, 2**70]),
                      ("height", [0, 12.5, "8", None, False, 10**6]),
                      ("near", [0.0, -1.0, NAN, "1", 1j]), ("far", [0.0, -1.0, INF, "1"]),
                      ("projection", ["fisheye", 1, None, b"perspective"])]:  # fmt: skip
        for bad in bads:
            add(f"Camera({key}={bad!r})", key, lambda k=key, b=bad: Camera((0, 0, 5.0), (0, 0, 0), **{k: b}))
    add("Camera(far < near)", "far", lambda: Camera((0, 0, 5), (0, 0, 0), near=2, far=1))
    for key, bads in [("distance", BAD_NUMBERS + [0.0, -1.0]), ("azimuth_deg", BAD_NUMBERS),
                      ("elevation_deg", BAD_NUMBERS + [90.0, -90.0, 100.0])]:  # fmt: skip
        for bad in bads:
            add(f"Camera.orbit({key}={bad!r})", key, lambda k=key, b=bad: Camera.orbit(**{k: b}))
    for bad in BAD_VECTORS:
        add(f"Camera.look_at(eye={bad!r})", "eye", lambda b=bad: Camera.look_at(b))
        add(f"Camera.project(points={bad!r})", "points", lambda b=bad: CAM.project(b))
        add(f"Camera.world_to_camera(points={bad!r})", "points", lambda b=bad: CAM.world_to_camera(b))
        add(f"Camera.view_direction(points={bad!r})", "points", lambda b=bad: CAM.view_direction(b))
        add(f"Camera.camera_to_pixels(cam_points={bad!r})", "cam_points", lambda b=bad: CAM.camera_to_pixels(b))
    add("Camera.replace(zoom=2)", "zoom", lambda: CAM.replace(zoom=2))
    add("Camera.replace(width=0)", "width", lambda: CAM.replace(width=0))
    for bad in [[-1], [64], [1.5], ["1"], [[1, 2]], None, NAN]:
        add(f"Camera.pixel_view_vectors(pixels={bad!r})", "pixels", lambda b=bad: CAM.pixel_view_vectors(b))
    for bad in [[-1.0], [NAN], ["1"], [1.0, 2.0]]:
        add(f"Camera.pixel_view_vectors(depth={bad!r})", "depth", lambda b=bad: CAM.pixel_view_vectors([0], b))
    for f in ("rays", "pixel_centers", "pixel_view_vectors"):
        for bad in [np.int32, "x", None, 5]:
            args = ([0],) if f == "pixel_view_vectors" else ()
            add(f"Camera.{f}(dtype={bad!r})", "dtype", lambda f=f, a=args, b=bad: getattr(CAM, f)(*a, dtype=b))
    huge = Camera((0, 0, 5.0), (0, 0, 0), width=60000, height=60000)
    add("Camera.rays() of 60000x60000", "rays", lambda: huge.rays())

    # -- renderer, raster, analytic sphere
    for bad in ["sphere", None, np.zeros((3, 3)), CAM]:
        add(f"Renderer(geometry={bad!r})", "geometry", lambda b=bad: Renderer(b, CAM))
        add(f"rasterize(mesh={bad!r})", "mesh", lambda b=bad: rasterize(b, CAM))
        add(f"bounding_sphere(geometry={bad!r})", "geometry", lambda b=bad: bounding_sphere(b))
    for bad in [None, (0, 0, 5), "cam", MESH]:
        add(f"Renderer(camera={bad!r})", "camera", lambda b=bad: Renderer(MESH, b))
        add(f"rasterize(camera={bad!r})", "camera", lambda b=bad: rasterize(MESH, b))
        add(f"raycast_sphere(camera={bad!r})", "camera", lambda b=bad: raycast_sphere(b))
    for bad in [np.int32, "float16", "x", None, 5, np.complex128]:
        add(f"Renderer(dtype={bad!r})", "dtype", lambda b=bad: Renderer(MESH, CAM, dtype=b))
        add(f"rasterize(dtype={bad!r})", "dtype", lambda b=bad: rasterize(MESH, CAM, dtype=b))
        add(f"raycast_sphere(dtype={bad!r})", "dtype", lambda b=bad: raycast_sphere(CAM, dtype=b))
        add(f"render(dtype={bad!r})", "dtype", lambda b=bad: render(MESH, CAM, MAT, LIGHTS, dtype=b))
    for bad in [1, 0, "yes", None, 1.0]:
        add(f"Renderer(cull_backfaces={bad!r})", "cull_backfaces", lambda b=bad: Renderer(MESH, CAM, cull_backfaces=b))
        add(f"rasterize(cull_backfaces={bad!r})", "cull_backfaces",
            lambda b=bad: rasterize(MESH, CAM, cull_backfaces=b))  # fmt: skip
    for bad in BAD_VECTORS:
        add(f"raycast_sphere(center={bad!r})", "center", lambda b=bad: raycast_sphere(CAM, center=b))
        add(f"AnalyticSphere(center={bad!r})", "center", lambda b=bad: AnalyticSphere(center=b))
    for bad in BAD_NUMBERS + [0.0, -1.0]:
        add(f"raycast_sphere(radius={bad!r})", "radius", lambda b=bad: raycast_sphere(CAM, radius=b))
        add(f"AnalyticSphere(radius={bad!r})", "radius", lambda b=bad: AnalyticSphere(radius=b))
    big_cam = Camera((0, 0, 5.0), (0, 0, 0), width=40000, height=40000)
    add("Renderer(40000x40000).render", "camera", lambda: Renderer(MESH, big_cam).render(MAT, LIGHTS))
    add("rasterize(40000x40000)", "camera", lambda: rasterize(MESH, big_cam))
    add("raycast_sphere(40000x40000)", "camera", lambda: raycast_sphere(big_cam))
    r = Renderer(MESH, CAM)
    r.render(MAT, LIGHTS)
    gb = r.gbuffer
    for bad in [None, "lambert", Lambert(0.5)]:
        add(f"Renderer.render(material={bad!r})", "material", lambda b=bad: r.render(b, LIGHTS))
        add(f"Renderer.render_terms(material={bad!r})", "material", lambda b=bad: r.render_terms(b, LIGHTS))
    for bad in [None, 5, "sun", DirectionalLight(), [None]]:
        add(f"Renderer.render(lights={bad!r})", "lights", lambda b=bad: r.render(MAT, b))
        add(f"Renderer.render_terms(lights={bad!r})", "lights", lambda b=bad: r.render_terms(MAT, b))
    for bad in ["smooth", 1, None]:
        add(f"Renderer.render(mode={bad!r})", "mode", lambda b=bad: r.render(MAT, LIGHTS, mode=b))
        add(f"Renderer.sample_points(mode={bad!r})", "mode", lambda b=bad: r.sample_points(b))
        add(f"Renderer.spread(mode={bad!r})", "mode", lambda b=bad: r.spread(b, np.zeros((1, 3))))
    for bad in ["pbr", None]:
        add(f"Renderer.render(form={bad!r})", "form", lambda b=bad: r.render(MAT, LIGHTS, form=b))
    for bad in ["diffuse", ["glow"], {"diffuse"}]:
        add(f"Renderer.render(terms={bad!r})", "terms", lambda b=bad: r.render(MAT, LIGHTS, terms=b))
    for bad in BAD_NUMBERS + [-1.0, (1, 0, -1.0), (1, 2)]:
        if bad is not None:
            add(f"Renderer.render(background={bad!r})", "background", lambda b=bad: r.render(MAT, LIGHTS, background=b))
    n_pix = len(gb.pixels)
    for bad in [[-1], [n_pix], [1.5], ["1"], [[0, 1]], NAN, "0"]:
        add(f"Renderer.restrict(subset={bad!r})", "subset", lambda b=bad: r.restrict(b))
    for bad in [np.full((len(MESH.vertices), 3), NAN), np.zeros((3, 3)), "abc", None, np.zeros(5, complex)]:
        add(f"GBuffer.interpolate(vertex_values={quote(bad)})", "vertex_values", lambda b=bad: gb.interpolate(b))
    for bad in [np.full(MESH.n_triangles, NAN), np.zeros(3), "abc", None]:
        add(f"GBuffer.per_face(face_values={quote(bad)})", "face_values", lambda b=bad: gb.per_face(b))
    for bad in [0, -1, 1.5, "64", None, True, 10**6, 60000]:
        add(f"render_sphere(size={bad!r})", "size", lambda b=bad: render_sphere(MAT, LIGHTS, size=b))
        add(f"sphere_camera(size={bad!r})", "size", lambda b=bad: sphere_camera(b) if b != 60000 else
            render_sphere(MAT, LIGHTS, size=b))  # fmt: skip
    for bad in BAD_NUMBERS + [0.0, -1.0]:
        add(f"sphere_camera(margin={bad!r})", "margin", lambda b=bad: sphere_camera(8, margin=b))
    for bad in [None, "lambert"]:
        add(f"render_sphere(material={bad!r})", "material", lambda b=bad: render_sphere(b, LIGHTS, size=4))
    for bad in [None, "sun", [1]]:
        add(f"render_sphere(lights={bad!r})", "lights", lambda b=bad: render_sphere(MAT, b, size=4))
    add("render_sphere(form='pbr')", "form", lambda: render_sphere(MAT, LIGHTS, size=4, form="pbr"))
    add("render_sphere(background=-1)", "background", lambda: render_sphere(MAT, LIGHTS, size=4, background=-1))

    # -- machband
    img = np.zeros((8, 8, 3))
    tid = np.zeros((8, 8), int)
    for bad in ["abc", None, np.zeros((8, 8, 2)), np.full((8, 8, 3), NAN), np.zeros(8, complex), b"12"]:
        add(f"luminance(image={quote(bad)})", "image", lambda b=bad: luminance(b))
        add(f"scanline_profile(image={quote(bad)})", "image", lambda b=bad: scanline_profile(b, 0))
        add(f"edge_jump_metric(image={quote(bad)})", "image", lambda b=bad: edge_jump_metric(b, tid))
    for bad in [-1, 8, 1.5, "0", None, True]:
        add(f"scanline_profile(row={bad!r})", "row", lambda b=bad: scanline_profile(img, b))
    for bad in [np.ones((4, 4), bool), "abc", np.full((8, 8), NAN)]:
        add(f"scanline_profile(coverage={quote(bad)})", "coverage", lambda b=bad: scanline_profile(img, 0, coverage=b))
    for bad in ["x", 5, -1, True, 1.5, b"r"]:
        add(f"scanline_profile(channel={bad!r})", "channel", lambda b=bad: scanline_profile(img, 0, channel=b))
        add(f"edge_jump_metric(channel={bad!r})", "channel", lambda b=bad: edge_jump_metric(img, tid, channel=b))
    for bad in [np.zeros((4, 4), int), "abc", None, np.full((8, 8), 0.5), np.full((8, 8), NAN)]:
        add(f"edge_jump_metric(triangle_id={quote(bad)})", "triangle_id", lambda b=bad: edge_jump_metric(img, b))
    for bad in [[8], [-1], [1.5], "0", 5]:
        add(f"edge_jump_metric(rows={bad!r})", "rows", lambda b=bad: edge_jump_metric(img, tid, rows=b))
    for bad in [0, -1, 1.5, "16", None]:
        add(f"edge_jump_metric(min_run={bad!r})", "min_run", lambda b=bad: edge_jump_metric(img, tid, min_run=b))

    # -- plan
    for bad in [None, "lambert", Lambert(0.5)]:
        add(f"compile_plan(material={bad!r})", "material", lambda b=bad: compile_plan(b, LIGHTS))
        add(f"evaluate_full(material={bad!r})", "material", lambda b=bad: evaluate_full(r, b, LIGHTS))
    for bad in [None, 5, "sun", [None]]:
        add(f"compile_plan(lights={bad!r})", "lights", lambda b=bad: compile_plan(MAT, b))
        add(f"evaluate_full(lights={bad!r})", "lights", lambda b=bad: evaluate_full(r, MAT, b))
    for key, bad in [("mode", "smooth"), ("mode", None), ("form", "pbr"), ("terms", "diffuse"), ("terms", ["x"])]:
        add(f"compile_plan({key}={bad!r})", key, lambda k=key, b=bad: compile_plan(MAT, LIGHTS, **{k: b}))
        add(f"evaluate_full({key}={bad!r})", key, lambda k=key, b=bad: evaluate_full(r, MAT, LIGHTS, **{k: b}))
    for bad in [5, "ball", ((0, 0, NAN), 1.0), ((0, 0, 0), -1.0), ((0, 0), 1.0), ((0, 0, 0), "1")]:
        add(f"compile_plan(bounds={bad!r})", "bounds", lambda b=bad: compile_plan(MAT, LIGHTS, bounds=b))
    for bad in [None, CAM, "r"]:
        add(f"evaluate_full(renderer={bad!r})", "renderer", lambda b=bad: evaluate_full(b, MAT, LIGHTS))
        add(f"Plan.execute(renderer={bad!r})", "renderer", lambda b=bad: compile_plan(MAT, LIGHTS).execute(b))
    for bad in [-1.0, NAN, "red", (1, 2)]:
        add(f"Plan.execute(background={bad!r})", "background",
            lambda b=bad: compile_plan(MAT, LIGHTS).execute(r, background=b))  # fmt: skip
    return calls


def test_probe_shading_illegal_values():
    tally = IllegalTally()
    for label, param, call in _illegal_calls():
        tally.classify(label, param, call)

    # Then hypothesis-drawn ones: a NaN, inf or complex value at a random place of a random-shape array
    # of points, normals or a view direction; random out-of-range numbers for the lights.
    @settings(max_examples=300, **SETTINGS)
    @given(st.integers(0, 2**32 - 1), st.sampled_from(DTYPES), st.sampled_from([NAN, INF, -INF]),
           st.floats(-1e300, -1e-300), st.floats(90.0001, 179.999), st.integers(2**16 + 1, 2**62),
           st.sampled_from([shade, shade_terms]))  # fmt: skip
    def run(seed, dtype, bad, negative, cutoff, samples, fn):
        rng = np.random.default_rng(seed)
        shape = tuple(int(x) for x in rng.integers(1, 4, rng.integers(0, 3))) + (3,)
        arr = rng.normal(size=shape).astype(dtype)
        arr[tuple(rng.integers(0, s) for s in shape)] = bad
        which = ("points", "normals", "view_dir")[seed % 3]
        args = dict(points=np.zeros(shape, dtype), normals=np.ones(shape, dtype), view_dir=(0, 0, 1.0)) | {which: arr}
        tally.classify(f"{fn.__name__}({which}={bad} at random)", which,
                  lambda: fn(args["points"], args["normals"], MAT, LIGHTS, view_dir=args["view_dir"]))  # fmt: skip
        rows = arr.reshape(-1, 3)
        eye = rows[~np.all(np.isfinite(rows), axis=-1)][0]  # the row holding the bad value
        tally.classify(f"{fn.__name__}(eye={eye})", "eye", lambda: fn(P, N, MAT, LIGHTS, eye=eye))
        tally.classify(f"PointLight(intensity={negative})", "intensity", lambda: PointLight(intensity=negative))
        tally.classify(f"SpotLight(cutoff_deg={cutoff})", "cutoff_deg", lambda: SpotLight(cutoff_deg=cutoff))
        tally.classify(f"SpotLight(exponent={negative})", "exponent", lambda: SpotLight(exponent=negative))
        tally.classify(f"RectLight(samples={samples})", "samples", lambda: RectLight(samples=samples))
        tally.classify(f"PointLight(attenuation=({negative}, 0, 1))", "attenuation",
                  lambda: PointLight(attenuation=(negative, 0, 1)))  # fmt: skip

    run()
    print("\n" + tally.summary("shading"))
    assert tally.calls >= 1500
    assert tally.named == tally.calls and tally.failures() == 0, tally.examples


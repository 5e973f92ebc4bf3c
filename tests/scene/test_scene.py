"""Scene files: the shipped examples render what the slides show, the format round-trips,
objects composite by depth, re-lighting re-uses the rasterization, and every malformed
input is a SceneError naming the file, the key and what is allowed."""

import math
import os
import re
import subprocess
import sys
import tomllib
from dataclasses import replace

import numpy as np
import pytest

from explorer.commands import render as render_cmd
from lighting import gl
from lighting.lights.punctual import AmbientLight, DirectionalLight, PointLight
from lighting.models.brdf import BlinnPhong, Lambert, Phong
from lighting.render.image import read_png
from lighting.scene import (
    GLLight,
    SceneError,
    SceneRenderer,
    example_path,
    gl_material_to_engine,
    list_examples,
    load_scene,
    object_matrix,
    parse_scene,
    render_scene,
    scene_to_toml,
)
from lighting.scene.examples import EXAMPLES_DIR
from lighting.scene.schema import LIGHT_KEYS, OBJECT_KEYS, model_keys
from lighting.shading.equation import Material, shade

DOCS = os.path.join(os.path.dirname(__file__), "..", "..", "docs", "scenes.md")
EXAMPLES = [
    "ambient_only",
    "directional_ambient",
    "point_ambient",
    "spotlight",
    "lambert_angles",
    "gouraud_vs_phong",
    "cube",
    "opengl_lights",
    "environment",
    "studio",
]


def raw(name):
    """The example file as tomllib reads it: expected values come from the file, not from the parser."""
    with open(example_path(name), "rb") as f:
        return tomllib.load(f)


def small(name, width=128, height=None):
    scene = load_scene(example_path(name))
    h = height or max(8, round(width * scene.camera.height / scene.camera.width))
    return scene.with_size(width, h)


def rendered(scene):
    sr = SceneRenderer(scene)
    image, info = sr.render()
    return sr, image, info


def ray_sphere(camera, center, radius):
    """Independent ray/sphere intersection at the pixel centres: (hit, t, point, normal)."""
    o, d = camera.rays()
    f = o - np.asarray(center)
    b = np.einsum("...k,...k", f, d)
    c = np.einsum("...k,...k", f, f) - radius**2
    disc = b * b - c
    hit = disc >= 0
    t = np.where(hit, -b - np.sqrt(np.where(hit, disc, 0)), 0.0)
    p = o + t[..., None] * d
    n = (p - np.asarray(center)) / radius
    return hit, np.where(hit, t, np.inf), p, n


def material_from_raw(m):
    brdf = None
    classes = {"lambert": Lambert, "phong": Phong, "blinn-phong": BlinnPhong}
    for part in m["parts"]:
        kw = {k: v for k, v in part.items() if k != "model"}
        model = classes[part["model"]](**kw)
        brdf = model if brdf is None else brdf + model
    return Material(brdf)


def view_kwargs(camera):
    return {"eye": camera.eye} if camera.is_perspective else {"view_dir": -camera.forward}


# ------------------------------------------------------------------ the shipped examples
def test_loading_a_scene_without_meshes_imports_nothing_heavy():
    code = (
        "import sys, lighting.scene as s;"
        "s.render_scene(s.load_scene(s.example_path('lambert_angles')).with_size(16, 8));"
        "heavy = {'matplotlib', 'pyvista', 'vtk', 'vtkmodules', 'trimesh', 'scipy'};"
        "print(sorted(m for m in sys.modules if m.split('.')[0] in heavy))"
    )
    root = os.path.join(os.path.dirname(__file__), "..", "..")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=root)
    assert run.stdout.strip() == "[]"


def test_the_examples_listed_are_the_examples_shipped():
    assert list_examples() == sorted(EXAMPLES)
    assert os.path.exists(os.path.join(EXAMPLES_DIR, "cube.obj"))


def test_parsing_the_tomllib_dict_equals_parsing_the_text():
    path = example_path("directional_ambient")
    with open(path) as f:
        a = parse_scene(f.read(), base_dir=EXAMPLES_DIR)
    b = parse_scene(raw("directional_ambient"), base_dir=EXAMPLES_DIR)
    assert a.to_dict() == b.to_dict() == load_scene(path).to_dict()


def test_ambient_only_is_the_constant_ia_ka_on_every_object():
    r = raw("ambient_only")
    ia = r["lights"][0]["intensity"]
    sr, image, info = rendered(small("ambient_only", 160))
    owner = sr.visibility()
    for i, ob in enumerate(r["objects"]):
        kd = np.broadcast_to(r["materials"][ob["material"]]["parts"][0]["kd"], 3)
        px = image[owner == i]
        assert len(px) > 20
        np.testing.assert_allclose(px, np.broadcast_to(ia * kd, px.shape), rtol=1e-14)  # k_a defaults to k_d
    np.testing.assert_array_equal(
        image[owner == -1], np.broadcast_to(r["image"]["background"], image[owner == -1].shape)
    )


@pytest.mark.parametrize("name", ["directional_ambient", "point_ambient"])
def test_analytic_sphere_matches_shade_on_independently_traced_geometry(name):
    r = raw(name)
    scene = small(name, 160)
    sr, image, _ = rendered(scene)
    i = next(k for k, ob in enumerate(r["objects"]) if ob["type"] == "sphere")
    ob = r["objects"][i]
    hit, _, p, n = ray_sphere(scene.camera, ob["center"], ob["radius"])
    mine = sr.visibility() == i
    assert mine.sum() > 200 and np.all(hit[mine])
    lights = [
        AmbientLight(intensity=lt["intensity"])
        if lt["type"] == "ambient"
        else DirectionalLight(lt["direction"], intensity=lt["intensity"])
        if lt["type"] == "directional"
        else PointLight(lt["position"], intensity=lt["intensity"], attenuation=lt["attenuation"])
        for lt in r["lights"]
    ]
    expected = shade(p[mine], n[mine], material_from_raw(r["materials"][ob["material"]]), lights, eye=scene.camera.eye)
    np.testing.assert_allclose(image[mine], expected, rtol=1e-9, atol=1e-12)


def test_point_light_falls_off_with_the_inverse_square_on_the_floor():
    r = raw("point_ambient")
    scene = small("point_ambient", 160)
    sr, image, _ = rendered(scene)
    gb = sr.renderer(0).gbuffer  # the floor
    top = (sr.visibility() == 0) & np.isclose(gb.normal[..., 1], 1.0)
    assert top.sum() > 500
    lt = r["lights"][1]
    d = np.asarray(lt["position"]) - gb.position[top]
    dist2 = np.einsum("ij,ij->i", d, d)
    kd = r["materials"]["floor"]["parts"][0]["kd"]
    expected = kd * lt["intensity"] / dist2 * d[:, 1] / np.sqrt(dist2) + kd * r["lights"][0]["intensity"]
    np.testing.assert_allclose(image[top][:, 0], expected, rtol=1e-9)


def test_spotlight_is_black_outside_the_cone_and_lit_inside():
    r = raw("spotlight")
    spot = r["lights"][0]
    scene = small("spotlight", 160)
    sr, image, _ = rendered(scene)
    owner = sr.visibility()
    pos = np.zeros(image.shape)
    for i in range(len(scene.objects)):
        pos[owner == i] = sr.renderer(i).gbuffer.position[owner == i]
    to_point = pos - spot["position"]
    cos_a = to_point @ np.asarray(spot["direction"]) / np.linalg.norm(to_point, axis=-1)
    angle = np.degrees(np.arccos(np.clip(cos_a, -1, 1)))
    outside = (owner >= 0) & (angle > spot["cutoff_deg"] + 0.5)
    inside_floor = (owner == 0) & (angle < spot["cutoff_deg"] - 0.5)
    assert outside.sum() > 1000 and inside_floor.sum() > 300
    assert np.all(image[outside] == 0)  # no ambient light: exactly black
    # Inside, on the floor's top: k_d I / d² (n·l) with exponent 0.
    d2 = np.einsum("...k,...k", to_point, to_point)[inside_floor]
    kd = r["materials"]["floor"]["parts"][0]["kd"]
    expected = kd * spot["intensity"] / d2 * (-to_point[inside_floor][:, 1] / np.sqrt(d2))
    np.testing.assert_allclose(image[inside_floor][:, 1], expected, rtol=1e-9)
    assert np.all(image[owner == -1] == np.asarray(r["image"]["background"]))


def test_lambert_angles_each_sphere_is_kd_cos_under_its_own_light():
    r = raw("lambert_angles")
    scene = small("lambert_angles", 320)
    sr, image, info = rendered(scene)
    kd = r["materials"]["lambert"]["parts"][0]["kd"]
    owner = sr.visibility()
    centre_values = []
    for i, ob in enumerate(r["objects"]):
        l_dir = np.asarray(ob["lights"][0]["direction"])
        hit, _, _, n = ray_sphere(scene.camera, ob["center"], 1.0)
        mine = owner == i
        assert np.all(hit[mine]) and np.array_equal(mine, hit)  # orthographic row, no overlap
        np.testing.assert_allclose(image[mine], kd * np.maximum(n[mine] @ l_dir, 0)[:, None] * np.ones(3), atol=1e-12)
        centre_values.append(kd * l_dir[2])  # the normal facing the viewer sees kd cos(theta)
    angles = [math.degrees(math.acos(v / kd)) for v in centre_values]
    np.testing.assert_allclose(angles, [0, 22.5, 45, 67.5, 90], atol=1e-9)
    assert info["lights"] == 5


def test_gouraud_object_interpolates_vertex_colours_phong_object_lights_pixels():
    scene = small("gouraud_vs_phong", 192)
    sr, image, _ = rendered(scene)
    owner = sr.visibility()
    (left, right), lights = scene.objects, scene.lights
    view = view_kwargs(scene.camera)
    gb0 = sr.renderer(0).gbuffer
    vertex_colours = shade(left.geometry.vertices, left.geometry.normals, left.material, lights, **view)
    np.testing.assert_allclose(image[owner == 0], gb0.interpolate(vertex_colours)[owner == 0], rtol=1e-12)
    gb1 = sr.renderer(1).gbuffer
    m = owner == 1
    np.testing.assert_allclose(
        image[m], shade(gb1.position[m], gb1.normal[m], right.material, lights, **view), rtol=1e-12
    )
    # The highlight lost between vertices: the per-pixel peak is higher.
    assert image[owner == 1].max() > image[owner == 0].max() + 0.05


def test_cube_from_obj_with_opengl_material_under_engine_lights():
    r = raw("cube")
    scene = small("cube", 120)
    sr, image, _ = rendered(scene)
    m = r["materials"]["brass"]
    material = Material(
        Lambert(m["diffuse"][:3]) + BlinnPhong(m["specular"][:3], m["shininess"]), ambient=m["ambient"][:3]
    )
    lights = [AmbientLight(intensity=r["lights"][0]["intensity"])]
    lights.append(DirectionalLight(r["lights"][1]["direction"], intensity=r["lights"][1]["intensity"]))
    a = math.radians(r["objects"][0]["rotate_deg"][1])
    R = np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])
    face_normals = np.vstack([np.eye(3), -np.eye(3)]) @ R.T
    gb = sr.renderer(0).gbuffer
    mine = sr.visibility() == 0
    which = np.argmax(gb.normal[mine] @ face_normals.T, axis=1)
    n = face_normals[which]
    np.testing.assert_allclose(gb.normal[mine], n, atol=1e-12)
    assert len(np.unique(which)) == 3  # three faces in view
    expected = shade(gb.position[mine], n, material, lights, eye=scene.camera.eye)
    np.testing.assert_allclose(image[mine], expected, rtol=1e-12)


def test_opengl_lights_scene_is_the_fixed_function_equation_in_eye_space():
    r = raw("opengl_lights")
    scene = small("opengl_lights", 160)
    sr, image, _ = rendered(scene)
    V = scene.camera.view_matrix()
    m = r["materials"]["ruby"]
    material = gl.Material(m["ambient"], m["diffuse"], m["specular"], shininess=m["shininess"])
    keys = ("ambient", "diffuse", "specular", "spot_direction", "spot_cutoff", "spot_exponent")
    lights = []
    for lt in r["lights"]:
        kw = {k: lt[k] for k in keys + ("constant_attenuation", "quadratic_attenuation") if k in lt}
        kw["position"] = tuple(V @ np.asarray(lt["position"]))
        if "spot_direction" in kw:
            kw["spot_direction"] = tuple(V[:3, :3] @ np.asarray(kw["spot_direction"]))
        lights.append(gl.Light(**kw))
    amb = r["opengl"]["scene_ambient"]
    owner = sr.visibility()

    def eye(points, normals):
        return points @ V[:3, :3].T + V[:3, 3], normals @ V[:3, :3].T

    per_vertex = gl.shade_vertices(*eye(scene.objects[0].geometry.vertices, scene.objects[0].geometry.normals),
                                   material, lights, scene_ambient=amb)  # fmt: skip
    gb0 = sr.renderer(0).gbuffer
    np.testing.assert_allclose(image[owner == 0], gb0.interpolate(per_vertex[:, :3])[owner == 0], atol=1e-12)
    gb1 = sr.renderer(1).gbuffer
    px = owner == 1
    per_pixel = gl.shade_vertices(*eye(gb1.position[px], gb1.normal[px]), material, lights, scene_ambient=amb)
    np.testing.assert_allclose(image[px], per_pixel[:, :3], atol=1e-12)
    assert image[px].max() == 1.0  # GL clamps; the white highlight saturates


def test_opengl_terms_select_material_colours():
    r = raw("opengl_lights")
    scene = small("opengl_lights", 96)
    scene = replace(scene, render=replace(scene.render, terms=("emission", "ambient")))
    sr, image, _ = rendered(scene)
    # e_cm + a_cm a_cs + a_cm a_cl0 (directional: no attenuation, no spot); the spot light's ambient is 0.
    a_cm = np.asarray(r["materials"]["ruby"]["ambient"][:3])
    expected = a_cm * (r["opengl"]["scene_ambient"][0] + r["lights"][0]["ambient"][0])
    covered = sr.visibility() >= 0
    np.testing.assert_allclose(image[covered], np.broadcast_to(expected, image[covered].shape), rtol=1e-14)


def test_physical_form_is_classic_over_pi_and_terms_select():
    scene = small("directional_ambient", 64)
    classic = render_scene(scene)[0]
    physical = render_scene(replace(scene, render=replace(scene.render, form="physical")))[0]
    sr = SceneRenderer(scene)
    covered = sr.visibility() >= 0
    np.testing.assert_allclose(physical[covered], classic[covered] / math.pi, rtol=1e-12)
    amb = render_scene(replace(scene, render=replace(scene.render, terms=("ambient",))))[0]
    reference = render_scene(small("ambient_only", 64))[0]
    np.testing.assert_allclose(amb[covered], reference[covered] * 0.15 / 0.6, rtol=1e-12)


def test_gl_material_mapping():
    m = gl.Material(ambient=(0.1, 0.2, 0.3), diffuse=(0.4, 0.5, 0.6), specular=(0.7, 0.8, 0.9), shininess=12)
    e = gl_material_to_engine(m)
    lam, bp = e.brdf.parts
    np.testing.assert_array_equal(lam.kd, [0.4, 0.5, 0.6])
    np.testing.assert_array_equal(bp.ks, [0.7, 0.8, 0.9])
    assert bp.shininess == 12 and not bp.normalized
    np.testing.assert_array_equal(e.ambient, [0.1, 0.2, 0.3])
    # Under a white light of intensity 1 it is OpenGL's bracket with d_cli = s_cli = 1 (local viewer, no clamp).
    n, l_dir = np.array([0, 0, 1.0]), np.array([0.6, 0, 0.8])
    p = np.array([0.0, 0, -3.0])
    ours = shade(p, n, e, [DirectionalLight(l_dir)], eye=(0, 0, 0))
    theirs = gl.shade_vertices(p, n, m, [gl.Light(position=(*l_dir, 0))], scene_ambient=(0, 0, 0), local_viewer=True)
    np.testing.assert_allclose(ours, theirs[:3], rtol=1e-12)


# ------------------------------------------------------------------ compositing and caching
TWO_SPHERES = """
[camera]
eye = [0, 0, 8]
fov_y_deg = 30
[image]
width = 96
height = 96
background = [0.0, 0.0, 1.0]
[materials.red]
parts = [{{model = "lambert", kd = 0}}]
ambient = 0
emission = [1, 0, 0]
[materials.green]
parts = [{{model = "lambert", kd = 0}}]
ambient = 0
emission = [0, 1, 0]
{first}
{second}
"""
FAR = '[[objects]]\ntype = "sphere"\ncenter = [-0.5, 0, 0]\nmaterial = "red"\n'
NEAR = '[[objects]]\ntype = "sphere"\ncenter = [0.6, 0.2, 1.5]\nradius = 0.9\nmaterial = "green"\n'


@pytest.mark.parametrize("order", ["far first", "near first"])
def test_depth_compositing_nearest_object_wins(order):
    first, second = (FAR, NEAR) if order == "far first" else (NEAR, FAR)
    scene = parse_scene(TWO_SPHERES.format(first=first, second=second))
    image, info = render_scene(scene)
    hit_far, t_far, _, _ = ray_sphere(scene.camera, [-0.5, 0, 0], 1.0)
    hit_near, t_near, _, _ = ray_sphere(scene.camera, [0.6, 0.2, 1.5], 0.9)
    overlap = hit_far & hit_near
    assert overlap.sum() > 100
    assert np.all(t_near[overlap] < t_far[overlap])
    green, red, blue = np.eye(3)[1], np.eye(3)[0], np.eye(3)[2]
    assert np.all(image[hit_near] == green)  # the near sphere wins wherever it is
    assert np.all(image[hit_far & ~hit_near] == red)
    assert np.all(image[~hit_far & ~hit_near] == blue)
    assert info["covered_pixels"] == int((hit_far | hit_near).sum())


def test_mesh_in_front_of_analytic_sphere():
    text = TWO_SPHERES.format(
        first='[[objects]]\ntype = "sphere"\nmaterial = "red"\n',
        second='[[objects]]\ntype = "icosphere"\nlevel = 2\nradius = 0.3\ncenter = [0, 0, 1.5]\nmaterial = "green"\n',
    )
    image, info = render_scene(parse_scene(text))
    assert np.all(image[48, 48] == [0, 1, 0]) and np.all(image[48, 30] == [1, 0, 0])
    assert np.all(image[2, 2] == [0, 0, 1])


def test_relighting_does_not_rerasterize():
    scene = small("directional_ambient", 64)
    sr = SceneRenderer(scene)
    first, info = sr.render()
    assert info["rasterized"] == len(scene.objects)
    sr.scene = scene.with_lights([AmbientLight(intensity=0.3), DirectionalLight((1.0, 1.0, 0.0))])
    second, info2 = sr.render()
    assert info2["rasterized"] == 0 and not np.array_equal(first, second)
    assert all(sr.renderer(i).rasterizations == 1 for i in range(len(scene.objects)))
    # Re-reading the edited file (only a light changed): the geometry keys match, still no rasterization.
    with open(example_path("directional_ambient")) as f:
        text = f.read().replace("direction = [-1.0, 2.0, 1.5]", "direction = [1.0, 2.0, 1.5]")
    sr.scene = parse_scene(text, base_dir=EXAMPLES_DIR).with_size(64, scene.camera.height)
    third, info3 = sr.render()
    assert info3["rasterized"] == 0 and not np.array_equal(third, first)
    # A moved camera does re-rasterize.
    sr.scene = scene.with_size(48, 24)
    assert sr.render()[1]["rasterized"] == len(scene.objects)


def test_object_transform_order_and_analytic_sphere_transform():
    M = object_matrix(translate=(1, 2, 3), rotate_deg=(90, 0, 0), scale=(2, 1, 1))
    np.testing.assert_allclose(M @ [1, 1, 0, 1], [3, 2, 4, 1], atol=1e-15)  # scale x, then y → z, then move
    s = parse_scene('[camera]\neye = [0, 0, 9]\n[[objects]]\ntype = "sphere"\ncenter = [1, 0, 0]\nradius = 0.5\n'
                    'scale = 2\nrotate_deg = [0, 0, 90]\ntranslate = [0, 0, 1]\n')  # fmt: skip
    g = s.objects[0].geometry
    np.testing.assert_allclose(g.center, (0, 2, 1), atol=1e-15)
    assert g.radius == 1.0


# ------------------------------------------------------------------ malformed input
BASE = '[camera]\neye = [0, 0, 5]\n[[objects]]\ntype = "sphere"\n'


def error_of(text, tmp_path, name="bad.toml"):
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(SceneError) as exc:
        load_scene(path)
    assert isinstance(exc.value, ValueError)
    msg = str(exc.value)
    assert msg.startswith(str(path) + ": ")
    return msg


def test_unknown_key_suggests_the_closest(tmp_path):
    msg = error_of(BASE + '[[lights]]\ntype = "spot"\nposition = [0, 1, 0]\ndirection = [0, -1, 0]\ncuttoff_deg = 20\n',
                   tmp_path)  # fmt: skip
    assert "lights[0].cuttoff_deg: unknown key" in msg
    assert "did you mean 'cutoff_deg'?" in msg and "allowed keys: type, position, direction, cutoff_deg" in msg
    msg = error_of(BASE.replace("eye = [0, 0, 5]", "eye = [0, 0, 5]\nfov_deg = 40"), tmp_path)
    assert "camera.fov_deg: unknown key" in msg and "did you mean 'fov_y_deg'?" in msg
    msg = error_of(BASE + '[[lightz]]\ntype = "ambient"\n', tmp_path)
    assert "lightz: unknown key for a scene file; did you mean 'lights'?" in msg


def test_wrong_type(tmp_path):
    msg = error_of(BASE + '[[lights]]\ntype = "ambient"\nintensity = "bright"\n', tmp_path)
    assert msg.endswith('lights[0].intensity: must be a finite number <= 1e+30; got a string "bright"')
    msg = error_of(BASE.replace("[0, 0, 5]", "[0, 5]"), tmp_path)
    assert "camera.eye: must be a 3-vector (an array of 3 numbers); got 2 entries [0, 5]" in msg
    msg = error_of(BASE + "[image]\nwidth = 10.5\n", tmp_path)
    assert "image.width: must be an integer in [1, 16384]; got a float 10.5" in msg
    msg = error_of(BASE.replace('type = "sphere"', 'type = "sphere"\nmaterial = 3'), tmp_path)
    assert (
        "objects[0].material: must be a material name (a string) or an inline material table; got an integer 3" in msg
    )


def test_out_of_range_cutoff_names_what_is_allowed(tmp_path):
    msg = error_of(
        BASE + '[[lights]]\ntype = "ambient"\n[[lights]]\ntype = "point"\nposition = [0, 1, 0]\n'
        '[[lights]]\ntype = "spot"\nposition = [0, 1, 0]\ndirection = [0, -1, 0]\ncutoff_deg = 120\n',
        tmp_path,
    )
    assert "lights[2].cutoff_deg: " in msg and "[0, 90] degrees or exactly 180" in msg and "got 120" in msg
    msg = error_of(BASE + '[[lights]]\ntype = "opengl"\nspot_cutoff = 120\n', tmp_path)
    assert "lights[0].spot_cutoff: " in msg and "[0, 90], or exactly 180" in msg
    msg = error_of(BASE.replace('type = "sphere"', 'type = "sphere"\nmaterial = {parts = [{model = "lambert", '
                                                   'kd = [0.5, -1, 0]}]}'), tmp_path)  # fmt: skip
    assert "objects[0].material.parts[0].kd: kd must be a finite scalar or RGB triple with every entry >= 0" in msg


@pytest.mark.parametrize("literal", ["nan", "inf", "-inf", "+nan"])
def test_nan_and_inf_literals_are_rejected(tmp_path, literal):
    msg = error_of(BASE.replace("[0, 0, 5]", f"[0, 0, {literal}]"), tmp_path)
    assert f"camera.eye[2]: must be a finite number; got {literal.lstrip('+')}" in msg
    msg = error_of(BASE + f'[[lights]]\ntype = "ambient"\nintensity = {literal}\n', tmp_path)
    assert "lights[0].intensity: must be a finite number" in msg and "nan and inf are not allowed" in msg


def test_missing_mesh_file(tmp_path):
    msg = error_of(BASE + '[[objects]]\ntype = "mesh"\npath = "nothere.obj"\n', tmp_path)
    assert "objects[1].path: mesh file" in msg and "nothere.obj" in msg and "does not exist" in msg


def test_unreadable_mesh(tmp_path):
    (tmp_path / "garbage.obj").write_bytes(bytes(range(256)) * 3)
    msg = error_of(BASE.replace('type = "sphere"', 'type = "mesh"\npath = "garbage.obj"'), tmp_path)
    assert "objects[0].path: mesh file" in msg and "garbage.obj" in msg
    assert "no geometry" in msg or "could not be read" in msg


def test_degenerate_mesh(tmp_path):
    (tmp_path / "flat.obj").write_text("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3\nf 2 3 4\n")
    msg = error_of(BASE.replace('type = "sphere"', 'type = "mesh"\npath = "flat.obj"'), tmp_path)
    assert "objects[0].path: mesh file" in msg and "all 2 triangles are degenerate (zero area)" in msg


def test_invalid_toml_reports_the_line(tmp_path):
    msg = error_of("[camera]\neye = [0, 0, 5]\n\n[[objects]\ntype = 'sphere'\n", tmp_path)
    assert "invalid TOML" in msg and "line 4" in msg


def test_other_malformed_scenes(tmp_path):
    sphere_with = lambda extra: BASE.replace('"sphere"', '"sphere"\n' + extra)  # noqa: E731
    gl_light = '[[lights]]\ntype = "opengl"\n'
    cases = [
        (BASE.replace("[0, 0, 5]\n", "[0, 0, 5]\nup = [0, 0, 1]\n"), "camera.up: up must not be parallel"),
        ("[camera]\neye = [0, 0, 5]\n", "objects: is required"),
        (BASE + "version = 2\n", "unknown key"),  # after a table header it belongs to the object
        ("version = 2\n" + BASE, "version: must be 1"),
        (BASE + '[render]\nmode = "gouraud"\n', "render.mode: an analytic sphere (objects[0]) is ray-cast per pixel"),
        (BASE + '[[lights]]\ntype = "ambient"\n' + gl_light, "lights[0].type: cannot mix"),
        (
            sphere_with('material = {parts = [{model = "lambert"}]}') + gl_light,
            "objects[0].material: this object is lit by OpenGL lights (lights), so its material must have model = "
            "'opengl'",
        ),
        (
            sphere_with('material = {model = "opengl"}') + '[render]\nform = "physical"\n' + gl_light,
            "render.form: 'physical' is not available",
        ),
        (sphere_with("scale = [1, 2, 1]"), "objects[0].scale: an analytic sphere takes only"),
        (BASE.replace('"sphere"', '"icosphere"\nscale = [1, 0, 1]'), "objects[0].scale: must be nonzero"),
        (
            BASE.replace('"sphere"', '"spher"'),
            "objects[0].type: must be one of 'sphere', 'uv_sphere', 'icosphere', 'mesh'; got \"spher\" "
            "(did you mean 'sphere'?)",
        ),
        (
            sphere_with('material = "rd"') + '[materials.red]\nparts = [{model = "lambert"}]\n',
            "objects[0].material: no material named 'rd' in [materials]; did you mean 'red'?",
        ),
        (BASE + '[materials.m]\nmodel = "lambert"\n', "materials.m.model: a material's own model can only be 'opengl'"),
        (
            BASE + '[materials.m]\nparts = [{model = "cook-torrance", roughness = 0}]\n',
            "materials.m.parts[0].roughness: roughness",
        ),
        (
            BASE + '[[lights]]\ntype = "directional"\ndirection = [0, 0, 0]\n',
            "lights[0].direction: direction must be finite real vectors of shape (..., 3) and non-zero length",
        ),
        (
            BASE + '[[lights]]\ntype = "rect"\ncenter = [0, 0, 1]\nedge_u = [1, 0, 0]\nedge_v = [2, 0, 0]\n',
            "lights[0].edge_u: edge_u and edge_v must span a rectangle",
        ),
        (
            BASE + '[[lights]]\ntype = "disk"\ncenter = [0, 0, 1]\nsamples = 0\n',
            "lights[0].samples: must be an integer >= 1",
        ),
        (BASE + "[[lights]]\ndirection = [0, 0, 1]\n", "lights[0].type: is required: one of 'ambient', 'directional'"),
    ]
    for text, expected in cases:
        assert expected in error_of(text, tmp_path), text
    with pytest.raises(SceneError, match=r"scene file does not exist"):
        load_scene(tmp_path / "missing.toml")
    (tmp_path / "latin1.toml").write_bytes(b"description = '\xe9'\n")
    with pytest.raises(SceneError, match=r"latin1.toml: invalid TOML: not UTF-8 text \(byte 15, line 1\)"):
        load_scene(tmp_path / "latin1.toml")


def test_every_light_type_and_model_parses(tmp_path):
    text = (
        BASE.replace('type = "sphere"', 'type = "uv_sphere"\nn_lat = 6\nn_lon = 10\nmode = "flat"')
        + """
[materials.all]
parts = [{model = "lambert", kd = 0.2}, {model = "phong", ks = 0.1, shininess = 5},
         {model = "blinn-phong", ks = 0.1, shininess = 50, normalized = true},
         CT_PART]
emission = 0.01
[[lights]]
type = "ambient"
[[lights]]
type = "directional"
direction = [0, 1, 1]
[[lights]]
type = "point"
position = [1, 2, 3]
attenuation = [0, 0, 1]
[[lights]]
type = "spot"
position = [0, 3, 0]
direction = [0, -1, 0]
exponent = 4
[[lights]]
type = "rect"
center = [0, 3, 0]
edge_u = [1, 0, 0]
edge_v = [0, 0, 1]
samples = 4
seed = 7
two_sided = true
[[lights]]
type = "disk"
center = [0, 3, 0]
normal_dir = [0, -1, 0]
radius = 0.3
samples = 5
"""
    )
    ct_part = (
        '{model = "cook-torrance", ks = 1, roughness = 0.2, f0 = [0.9, 0.6, 0.3], ndf = "ggx", geometry = "smith", '
        'fresnel = "dielectric", denominator = "pi"}'
    )
    text = text.replace("CT_PART", ct_part)
    scene = parse_scene(text.replace('n_lon = 10\nmode = "flat"', 'n_lon = 10\nmode = "flat"\nmaterial = "all"'))
    kinds = [type(lt).__name__ for lt in scene.lights]
    assert kinds == ["AmbientLight", "DirectionalLight", "PointLight", "SpotLight", "RectLight", "DiskLight"]
    ct = scene.objects[0].material.brdf.parts[3]
    assert (ct.ndf, ct.geometry, ct.fresnel, ct.denominator) == ("ggx", "smith", "dielectric", "pi")
    assert scene.objects[0].material.brdf.parts[2].normalized
    assert scene.lights[4].seed == 7 and scene.lights[4].two_sided
    assert parse_scene(scene_to_toml(scene)).to_dict() == scene.to_dict()
    image, _ = render_scene(scene.with_size(24, 24))
    assert np.all(np.isfinite(image)) and image.max() > 0
    gl_scene = parse_scene(BASE.replace('"sphere"', '"sphere"\nmaterial = {model = "opengl"}') +
                           '[[lights]]\ntype = "opengl"\nspace = "eye"\n')  # fmt: skip
    assert isinstance(gl_scene.lights[0], GLLight) and gl_scene.lights[0].space == "eye"


def test_docs_name_every_key():
    with open(DOCS) as f:
        doc = f.read()
    from lighting.scene.schema import CAMERA_KEYS, GL_MATERIAL_KEYS, IMAGE_KEYS, MATERIAL_KEYS, OPENGL_KEYS, RENDER_KEYS

    tables = [CAMERA_KEYS, IMAGE_KEYS, RENDER_KEYS, OPENGL_KEYS, MATERIAL_KEYS, GL_MATERIAL_KEYS]
    tables += list(model_keys().values()) + list(LIGHT_KEYS.values()) + list(OBJECT_KEYS.values())
    missing = sorted({k for t in tables for k in t if f"`{k}`" not in doc})
    assert not missing, missing
    for name in list(model_keys()) + list(LIGHT_KEYS) + list(OBJECT_KEYS):
        assert f'"{name}"' in doc, name


# ------------------------------------------------------------------ the command
def test_cli_renders_a_png(tmp_path, capsys):
    out = tmp_path / "spot.png"
    assert render_cmd.main(["spotlight", "-o", str(out), "--size", "80x60", "--exposure", "-1"]) == 0
    line = capsys.readouterr().out.strip()
    assert re.fullmatch(
        rf"wrote {re.escape(str(out))} \(80x60, 2 objects, 1 light, [0-9.]+ s\); .*pixels clipped.*", line
    )
    img = read_png(out)
    assert img.shape == (60, 80, 3)
    assert render_cmd.main([example_path("ambient_only"), "-o", str(tmp_path / "a.png"), "--size", "40x25",
                            "--explain"]) == 0  # fmt: skip
    text = capsys.readouterr().out
    assert "strategy 'constant'" in text
    assert "left out: normals, view vectors and the light loop — no light reaches the surface directly" in text


def test_cli_error_exits_2_and_leaves_outputs_alone(tmp_path, capsys):
    scene = tmp_path / "bad.toml"
    scene.write_text(
        BASE + '[[lights]]\ntype = "spot"\nposition = [0, 1, 0]\ndirection = [0, -1, 0]\ncutoff_deg = 120\n'
    )
    new = tmp_path / "new.png"
    assert render_cmd.main([str(scene), "-o", str(new)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("lighting-explorer: error: ") and "bad.toml: lights[0].cutoff_deg" in err
    assert "Traceback" not in err and not new.exists()
    old = tmp_path / "old.png"
    old.write_bytes(b"previous picture")
    assert render_cmd.main([str(scene), "-o", str(old)]) == 2
    assert old.read_bytes() == b"previous picture"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml", "old.png"]  # no temporary left behind
    for argv, text in [
        ([str(tmp_path / "none.toml")], "none.toml: scene file does not exist"),
        (["spotlight", "--size", "0x5"], "--size must be WIDTHxHEIGHT"),
        (["spotlight", "--bogus"], "unrecognized arguments: --bogus"),
        (["spotlight", "-o", str(tmp_path / "no" / "dir.png")], "does not exist"),
        (["spotlight", "--exposure", "nan"], "expected a finite number"),
    ]:
        assert render_cmd.main(argv) == 2, argv
        err = capsys.readouterr().err
        assert err.startswith("lighting-explorer: error: ") and text in err and "Traceback" not in err


def test_the_full_example_in_the_docs_renders():
    with open(DOCS) as f:
        text = re.search(r"```toml\n(.*?)```", f.read(), re.S).group(1)
    scene = parse_scene(text, source="docs example", base_dir=EXAMPLES_DIR)
    assert [o.name for o in scene.objects] == ["floor", "sphere", "cube"] and len(scene.lights) == 3
    image, info = render_scene(scene.with_size(64, 40))
    assert all(v > 0 for v in info["visible_pixels"]) and np.all(np.isfinite(image))


# ----------------------------------------------------------------------------- untrusted scene files
SMALL = '[camera]\neye = [0, 0, 5]\n[image]\nwidth = 8\nheight = 8\n[[objects]]\ntype = "sphere"\n'


def run_cli(argv, capsys):
    """``render_cmd.main(argv)``: (status, stdout, stderr) with stderr checked to be at most one line."""
    status = render_cmd.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert "Traceback" not in err and err.count("\n") <= 1, err
    return status, out, err


@pytest.fixture
def sandbox(tmp_path, monkeypatch):
    """A scene folder as the current folder, with a decoy folder beside it holding a file and a link target."""
    work, decoy = tmp_path / "work", tmp_path / "decoy"
    work.mkdir()
    decoy.mkdir()
    (decoy / "victim.png").write_bytes(b"precious")
    monkeypatch.chdir(work)
    return work, decoy


@pytest.mark.parametrize(
    "output",
    ["{decoy}/victim.png", "../decoy/victim.png", "sub/../../decoy/victim.png", "link_out.png", "link_dir/victim.png",
     "link_in.png", "/", ".", ""],
)  # fmt: skip
def test_a_scene_cannot_write_outside_its_folder_or_the_current_folder(sandbox, capsys, output):
    work, decoy = sandbox
    (work / "sub").mkdir()
    (work / "inside.png").write_bytes(b"mine")
    os.symlink(decoy / "victim.png", work / "link_out.png")
    os.symlink(decoy, work / "link_dir")
    os.symlink(work / "inside.png", work / "link_in.png")  # even a link to a file inside: never write through it
    scene = work / "s.toml"
    scene.write_text(SMALL.replace("height = 8\n", f'height = 8\noutput = "{output.format(decoy=decoy)}"\n'))
    status, out, err = run_cli([scene], capsys)
    assert status == 2 and out == ""
    assert err.startswith(f"lighting-explorer: error: {scene}: image.output: "), err
    assert "current folder" in err and "-o" in err
    assert (decoy / "victim.png").read_bytes() == b"precious" and os.listdir(decoy) == ["victim.png"]
    assert (work / "inside.png").read_bytes() == b"mine" and os.path.islink(work / "link_in.png")
    assert sorted(os.listdir(work)) == ["inside.png", "link_dir", "link_in.png", "link_out.png", "s.toml", "sub"]


def test_a_scene_output_inside_the_allowed_folders_is_written_and_minus_o_goes_anywhere(sandbox, tmp_path, capsys):
    work, decoy = sandbox
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    scene = scenes / "s.toml"
    # relative to the current folder (work): allowed; absolute into the scene's own folder: allowed
    for output, where in [("here.png", work / "here.png"), (str(scenes / "there.png"), scenes / "there.png"),
                          ("../scenes/up.png", scenes / "up.png")]:  # fmt: skip
        scene.write_text(SMALL.replace("height = 8\n", f'height = 8\noutput = "{output}"\n'))
        status, out, err = run_cli([scene], capsys)
        assert status == 0 and err == "" and out.startswith(f"wrote {output} (8x8"), (output, err)
        assert read_png(where).shape == (8, 8, 3)
    scene.write_text(SMALL.replace("height = 8\n", f'height = 8\noutput = "{decoy}/victim.png"\n'))
    status, out, err = run_cli([scene, "-o", decoy / "mine.png"], capsys)  # the user's -o: anywhere
    assert status == 0 and read_png(decoy / "mine.png").shape == (8, 8, 3)
    assert (decoy / "victim.png").read_bytes() == b"precious"


def test_scene_output_path_resolves_links_and_names_the_key(tmp_path):
    from lighting.scene import scene_output_path

    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    os.symlink(tmp_path / "b", tmp_path / "a" / "to_b")
    scene = tmp_path / "a" / "s.toml"
    assert scene_output_path("x.png", scene, cwd=tmp_path / "a") == str(tmp_path / "a" / "x.png")
    assert scene_output_path("../a/y.png", scene, cwd=tmp_path / "b") == str(tmp_path / "a" / "y.png")
    with pytest.raises(SceneError, match=r"image\.output: \"to_b/x\.png\" resolves to .*/b/x\.png; it must be"):
        scene_output_path("to_b/x.png", scene, cwd=tmp_path / "a")
    with pytest.raises(SceneError, match="got an integer 5"):
        scene_output_path(5, scene)


@pytest.mark.parametrize("where", ["eye = {v}", "scale = {v}", "material = {t}", "x = {v}", "name = {t}"])
def test_arrays_and_tables_nested_500_deep_are_one_line_naming_the_key(tmp_path, capsys, where):
    deep_array, deep_table = "[" * 500 + "]" * 500, "{a = " * 500 + "1" + "}" * 500
    line = where.format(v=deep_array, t=deep_table)
    text = SMALL.replace("eye = [0, 0, 5]", line) if line.startswith("eye") else SMALL + line + "\n"
    scene = tmp_path / "deep.toml"
    scene.write_text(text)
    key = {"eye": "camera.eye", "x": "objects[0].x"}.get(where.split()[0], "objects[0]." + where.split()[0])
    status, out, err = run_cli([scene, "-o", tmp_path / "o.png"], capsys)
    assert status == 2 and not (tmp_path / "o.png").exists()
    assert err.startswith(f"lighting-explorer: error: {scene}: {key}: arrays or tables nested more than 32 deep")
    # and as a dict (what Scene.to_dict gives): walked without recursion
    nested = 1
    for _ in range(5000):
        nested = [nested]
    with pytest.raises(SceneError, match=r"^<string>: camera\.eye(\[0\])+: arrays or tables nested more than 32"):
        parse_scene({"camera": {"eye": nested}, "objects": [{"type": "sphere"}]})


def test_nesting_scan_ignores_brackets_in_strings_and_comments():
    text = "description = '''" + "[" * 100 + "\n'''\n" + SMALL + 'name = "' + "[" * 100 + '"  # ' + "{" * 100 + "\n"
    scene = parse_scene(text)
    assert scene.objects[0].name == "[" * 100 and scene.description == "[" * 100 + "\n"


def test_overflowing_transforms_and_camera_distances_name_their_key(tmp_path, capsys):
    ico = SMALL.replace('type = "sphere"', 'type = "icosphere"\nlevel = 1')
    cases = [
        (ico + "scale = [1e300, 1, 1]\n", "objects[0].scale", "must be invertible"),  # OverflowError before
        (ico + "scale = 1e308\ntranslate = [1e308, 0, 0]\n", "objects[0].scale", "beyond the float range"),
        (SMALL.replace("eye = [0, 0, 5]", "eye = [-1e308, 0, 5]"), "camera.eye", "finite distance apart"),
        (SMALL.replace("eye = [0, 0, 5]", "eye = [0, 0, 5]\ntarget = [1e308, 0, -1e308]"), "camera.target",
         "finite distance apart"),
    ]  # fmt: skip
    for text, key, what in cases:
        scene = tmp_path / "s.toml"
        scene.write_text(text)
        status, out, err = run_cli([scene, "-o", tmp_path / "o.png"], capsys)
        assert status == 2 and err.startswith(f"lighting-explorer: error: {scene}: {key}: ") and what in err, err
        assert not (tmp_path / "o.png").exists()


def test_long_values_and_keys_are_abbreviated(tmp_path, capsys):
    long = "x" * 100_000
    for text, key in [
        (SMALL.replace("[camera]", f'[camera]\nprojection = "{long}"'), "camera.projection"),
        (SMALL.replace("[camera]", f"[camera]\n{long} = 1"), "camera.xxxx"),
        (SMALL + f'material = "{long}"\n', "objects[0].material"),
        (SMALL + f'type_ = "{long}"\n', "objects[0].type_"),
        (SMALL + "n = " + "9" * 5000 + "\n", ""),  # tomllib refuses > 4300 digits with a plain ValueError
        (SMALL.replace("width = 8", "width = " + "9" * 4000), "image.width"),
    ]:
        scene = tmp_path / "s.toml"
        scene.write_text(text)
        status, out, err = run_cli([scene], capsys)
        assert status == 2 and err.startswith(f"lighting-explorer: error: {scene}: {key}") and len(err) < 1000, err


def budget_error(text, tmp_path, capsys, *extra):
    scene = tmp_path / "s.toml"
    scene.write_text(text)
    status, out, err = run_cli([scene, "-o", tmp_path / "o.png", *extra], capsys)
    assert status == 2 and not (tmp_path / "o.png").exists()
    assert "over the memory budget of 2.0 GiB; reduce it or raise the budget (--memory-budget)" in err, err
    return err


def test_image_size_samples_and_meshes_are_refused_before_allocating(tmp_path, capsys):
    import tracemalloc

    from lighting._budget import memory_budget

    assert memory_budget() == 2 * 1024**3
    tracemalloc.start()
    try:
        err = budget_error(SMALL.replace("width = 8", "width = 16384").replace("height = 8", "height = 16384"),
                           tmp_path, capsys)  # fmt: skip
        assert ": image.width × image.height: the scene needs about 88.0 GiB (16384x16384 pixels" in err
        rect = '[[lights]]\ntype = "rect"\ncenter = [0, 2, 2]\nsamples = 65536\n'
        err = budget_error(SMALL.replace("width = 8", "width = 512").replace("height = 8", "height = 512") + rect,
                           tmp_path, capsys)  # fmt: skip
        assert ": lights[0].samples: the lighting needs about 128.0 GiB (1.72e+10 light-sample evaluations" in err
        err = budget_error(SMALL.replace('"sphere"', '"uv_sphere"\nn_lat = 1000000'), tmp_path, capsys)
        assert ": objects[0].n_lat: this value needs about 38.1 GiB (a uv sphere of 63999936 triangles)" in err
        err = budget_error(SMALL.replace('"sphere"', '"icosphere"\nlevel = 9') + '[[objects]]\ntype = "icosphere"\n'
                           "level = 8\n", tmp_path, capsys)  # fmt: skip
        assert ": objects[0].level: this value needs about 3.1 GiB (an icosphere of 5242880 triangles)" in err
        with open(tmp_path / "sparse.obj", "wb") as f:  # 1 GB, no disk used
            f.truncate(1 << 30)
        err = budget_error(SMALL.replace('"sphere"', '"mesh"\npath = "sparse.obj"'), tmp_path, capsys)
        assert ": objects[0].path: this value needs about 32.0 GiB (reading a mesh file of 1073741824 bytes)" in err
        err = budget_error(SMALL, tmp_path, capsys, "--size", "16000x16000")
        assert err.startswith("lighting-explorer: error: --size 16000x16000: the image needs about 83.9 GiB")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 64 * 1024**2  # every refusal came before the allocation


def test_the_budget_is_the_shared_one_and_raising_it_lets_a_scene_through(tmp_path):
    from lighting._budget import set_memory_budget
    from lighting.scene import SceneBudgetError, check_scene_budget, scene_estimate

    scene = parse_scene(SMALL.replace("width = 8", "width = 300").replace("height = 8", "height = 200"))
    est = scene_estimate(scene)
    assert est["bytes"] == 300 * 200 * (256 + 96) and est["evaluations"] == 0 and est["work_key"] == "lights"
    previous = set_memory_budget(est["bytes"] - 1)
    try:
        with pytest.raises(SceneBudgetError, match=r"^<string>: image\.width × image\.height: the scene needs"):
            SceneRenderer(scene)
        with pytest.raises(SceneBudgetError, match=r"^big: the scene text \(400000 bytes\) needs about 24\.4 MiB"):
            parse_scene(SMALL + "#" * (400_000 - len(SMALL)), source="big")  # 64 bytes per byte of text
        set_memory_budget(est["bytes"])
        assert check_scene_budget(scene) == est
        SceneRenderer(scene).render()
    finally:
        set_memory_budget(previous)


def test_inputs_a_scene_names_are_read_only_when_they_are_regular_files(tmp_path, capsys):
    os.mkfifo(tmp_path / "fifo.obj")  # reading it would block forever
    os.symlink("/dev/zero", tmp_path / "zero.obj")  # reading it would never end
    for name, what in [("fifo.obj", "is not a regular file"), ("zero.obj", "is not a regular file"),
                       (".", "is a directory"), ("none.obj", "does not exist")]:  # fmt: skip
        msg = error_of(SMALL.replace('"sphere"', f'"mesh"\npath = "{name}"'), tmp_path)
        assert "objects[0].path: mesh file" in msg and what in msg, msg
    os.mkfifo(tmp_path / "fifo.toml")
    status, out, err = run_cli([tmp_path / "fifo.toml"], capsys)
    assert status == 2 and "fifo.toml: is not a regular file" in err


def test_the_installed_command_answers_a_500_deep_scene_in_one_line(tmp_path):
    scene = tmp_path / "deep.toml"
    scene.write_text(SMALL + "scale = " + "[" * 500 + "]" * 500 + "\n")
    done = subprocess.run([sys.executable, "-m", "explorer.cli", "render", str(scene), "-o", str(tmp_path / "o.png")],
                          capture_output=True, text=True, timeout=120, cwd=tmp_path)  # fmt: skip
    assert done.returncode == 2 and done.stdout == "" and not (tmp_path / "o.png").exists()
    assert done.stderr == (f"lighting-explorer: error: {scene}: objects[0].scale: arrays or tables nested more than 32 "
                           "deep (line 8); a scene needs fewer than 10 levels\n")  # fmt: skip


def test_command_line_values_are_abbreviated_and_exposure_bounded(capsys):
    for argv, text in [
        (["spotlight", "--size", "x" * 100_000], "--size must be WIDTHxHEIGHT or N (a square) in pixels, both >= 1 "
                                                 "(e.g. 640x480 or 512); got '" + "x" * 39 + "…(+99962 chars)"),
        (["spotlight", "--exposure", "y" * 100_000], "expected a number; got 'yyyyyyy"),
        (["spotlight", "--exposure", "1e308"], "argument --exposure: must be a number of stops in [-100, 100]; got "
                                               "'1e308'"),
    ]:  # fmt: skip
        status, out, err = run_cli(argv, capsys)
        assert status == 2 and text in err and len(err) < 300, err


@pytest.mark.parametrize("out", ["", "x.svg", "missing/x.png"])
def test_render_checks_the_output_before_rendering(out, tmp_path, monkeypatch, capsys):
    from explorer.commands import render as render_cmd
    from lighting import scene as scene_mod

    def no_render(self):
        raise AssertionError("rendered before the output was checked")

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(scene_mod.SceneRenderer, "render", no_render)
    assert render_cmd.main(["spotlight", "-o", out]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("lighting-explorer: error: -o")
    assert os.listdir(tmp_path) == []

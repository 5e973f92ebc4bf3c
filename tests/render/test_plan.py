import numpy as np
import pytest

from lighting import (
    AmbientLight,
    BlinnPhong,
    CookTorrance,
    DirectionalLight,
    Lambert,
    Material,
    Phong,
    PointLight,
    RectLight,
    SpotLight,
)
from lighting.render.camera import Camera
from lighting.render.mesh import icosphere, uv_sphere
from lighting.render.plan import bounding_sphere, compile_plan, evaluate_full
from lighting.render.renderer import AnalyticSphere, Renderer

PERSP = Camera((0.3, 0.2, 6.0), (0, 0, 0), fov_y_deg=24, width=64, height=64)
ORTHO = Camera((0, 0, 6.0), (0, 0, 0), projection="orthographic", ortho_height=2.4, width=64, height=64)


def _check(renderer, material, lights, mode, form="classic", terms=("emission", "ambient", "diffuse", "specular")):
    plan = compile_plan(material, lights, mode=mode, form=form, terms=terms, bounds=bounding_sphere(renderer.geometry))
    got = plan.execute(renderer)
    ref = evaluate_full(renderer, material, lights, mode=mode, form=form, terms=terms)
    np.testing.assert_allclose(got, ref, rtol=1e-12, atol=1e-12)
    return plan


@pytest.mark.parametrize("camera", [PERSP, ORTHO], ids=["perspective", "orthographic"])
@pytest.mark.parametrize("mode", ["flat", "gouraud", "phong"])
def test_strategies_match_full_evaluation(camera, mode):
    r = Renderer(icosphere(2), camera)
    amb = [AmbientLight((0.2, 0.3, 0.4), 0.5)]
    plan = _check(r, Material(Lambert((0.8, 0.2, 0.1)), emission=0.05), amb, mode)
    assert plan.strategy == "constant"
    dirs = amb + [DirectionalLight((-1, 1, 1.0)), DirectionalLight((1, 0, 0.3), color=(0.2, 0.2, 1.0))]
    plan = _check(r, Material(Lambert((0.8, 0.2, 0.1)) + Phong(0.0, 30.0)), dirs, mode)
    assert plan.strategy == "diffuse-directional"
    full = dirs + [PointLight((2, 2, 3.0), intensity=10.0), SpotLight((0, 0, 4.0), (1, 1, 1), 20.0, cutoff_deg=25)]
    plan = _check(r, Material(Lambert(0.5) + BlinnPhong(0.5, 40.0)), full, mode)
    assert plan.strategy == "general"


def test_random_scenes_match_full_evaluation():
    rng = np.random.default_rng(2024)
    geoms = [icosphere(1), uv_sphere(6, 9), AnalyticSphere((0.1, 0, 0), 0.9)]
    for trial in range(40):
        geom = geoms[trial % 3]
        modes = ["phong"] if isinstance(geom, AnalyticSphere) else ["flat", "gouraud", "phong"]
        parts = []
        if rng.random() < 0.8:
            parts.append(Lambert(rng.random(3) * (rng.random() < 0.85)))
        k = rng.integers(0, 4)
        ks = rng.random(3) * (rng.random() < 0.8)
        parts.append(
            [Phong(ks, 30.0), BlinnPhong(ks, 20.0, normalized=True), CookTorrance(ks, 0.3, 0.5), Lambert(ks)][k]
        )
        material = Material(sum(parts[1:], parts[0]), emission=rng.random(3) * (rng.random() < 0.3))
        lights = []
        for _ in range(rng.integers(0, 5)):
            kind = rng.integers(0, 5)
            colour = rng.random(3) * (rng.random() < 0.85)
            if kind == 0:
                lights.append(AmbientLight(colour, 0.3))
            elif kind == 1:
                lights.append(DirectionalLight(rng.normal(size=3), colour))
            elif kind == 2:
                lights.append(PointLight(rng.normal(size=3) * 3, colour, 5.0, attenuation=(1, 0.1, 0.5)))
            elif kind == 3:
                pos = rng.normal(size=3) * 3
                aim = rng.normal(size=3) * 2 - pos  # sometimes at the sphere, sometimes away from it
                lights.append(SpotLight(pos, colour, 9.0, direction=aim, cutoff_deg=rng.uniform(0, 90)))
            else:
                lights.append(RectLight(rng.normal(size=3) * 3, (0.3, 0, 0), (0, 0.3, 0), intensity=30.0, samples=4))
        cam = PERSP if trial % 2 else ORTHO
        r = Renderer(geom, cam)
        form = "classic" if trial % 4 < 2 else "physical"
        terms = ("emission", "ambient", "diffuse", "specular") if trial % 5 else ("diffuse",)
        for mode in modes:
            _check(r, material, lights, mode, form, terms)


def test_spot_cone_that_misses_the_object_is_dropped_and_changes_nothing():
    r = Renderer(AnalyticSphere(), PERSP)
    away = SpotLight((0, 0, 4.0), direction=(0, 1.0, 0.0), cutoff_deg=30)  # points sideways, past the sphere
    at = SpotLight((0, 0, 4.0), direction=(0, 0, -1.0), cutoff_deg=5)
    plan = _check(r, Material(Lambert(0.7) + Phong(0.3, 20.0)), [away, at], "phong")
    assert plan.kept_lights == [at]
    assert any("cone does not reach" in s.why for s in plan.skipped)
    # The sphere subtends asin(1/4) = 14.5° from the apex: a 60° cone aimed 70° off the centre just reaches it.
    grazing = SpotLight((0, 0, 4.0), direction=(np.sin(np.radians(70)), 0, -np.cos(np.radians(70))), cutoff_deg=60)
    assert compile_plan(Material(Lambert(1.0)), [grazing], bounds=bounding_sphere(AnalyticSphere())).kept_lights
    shy = SpotLight((0, 0, 4.0), direction=(np.sin(np.radians(80)), 0, -np.cos(np.radians(80))), cutoff_deg=60)
    assert not compile_plan(Material(Lambert(1.0)), [shy], bounds=bounding_sphere(AnalyticSphere())).kept_lights


def test_describe_names_what_was_left_out():
    lights = [AmbientLight(), DirectionalLight(color=0.0), DirectionalLight()]
    plan = compile_plan(Material(Lambert(0.5) + Phong(0.0, 10.0)), lights, mode="gouraud")
    text = plan.describe()
    assert "per vertex" in text
    assert "light 1 (DirectionalLight) — its colour × intensity is zero" in text
    assert "Phong(ks=0, shininess=10) — its coefficient is zero" in text
    assert "view vectors and half vectors" in text
    ambient_only = compile_plan(Material(Lambert(0.5)), [AmbientLight()])
    assert ambient_only.strategy == "constant"
    assert "the image is one constant colour" in ambient_only.describe()


def test_plans_do_not_rasterize_again():
    r = Renderer(icosphere(2), PERSP)
    mat = Material(Lambert(0.5))
    for az in range(5):
        compile_plan(mat, [DirectionalLight((np.cos(az), np.sin(az), 1.0))]).execute(r)
    assert r.rasterizations == 1


# ------------------------------------------------------------------ scenes
from lighting.scene import SceneRenderer, example_path, list_examples, load_scene, parse_scene  # noqa: E402


def _example_params():
    """Every example; those lit by an environment (seconds of work each) only in the full run."""
    lit_by_sky = {n for n in list_examples() if any(getattr(lt, "is_environment", False)
                                                    for lt in load_scene(example_path(n)).lights)}  # fmt: skip
    return [pytest.param(n, marks=[pytest.mark.slow] if n in lit_by_sky else []) for n in list_examples()]


@pytest.mark.parametrize("name", _example_params())
def test_every_example_scene_planned_equals_full(name):
    scene = load_scene(example_path(name)).with_size(96, 64)
    planned, _ = SceneRenderer(scene, plan=True).render()
    full, _ = SceneRenderer(scene, plan="full").render()
    general, _ = SceneRenderer(scene, plan=False).render()
    np.testing.assert_allclose(planned, full, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(general, full, rtol=1e-12, atol=1e-12)


def _random_scene(rng) -> dict:
    models = [
        lambda: {"model": "lambert", "kd": (rng.random(3) * (rng.random() < 0.8)).tolist()},
        lambda: {"model": "phong", "ks": float(rng.random() * (rng.random() < 0.7)), "shininess": 30.0},
        lambda: {"model": "blinn-phong", "ks": float(rng.random()), "shininess": 60.0, "normalized": True},
        lambda: {"model": "cook-torrance", "ks": 1.0, "roughness": 0.3, "f0": 0.5},
    ]
    materials = {f"m{k}": {"parts": [models[j]() for j in rng.choice(4, rng.integers(1, 3), replace=False)]}
                 for k in range(3)}  # fmt: skip
    objects = []
    for _ in range(rng.integers(1, 5)):
        kind = ["sphere", "icosphere", "uv_sphere"][rng.integers(0, 3)]
        ob = {"type": kind, "material": f"m{rng.integers(0, 3)}"}
        if kind == "sphere":
            ob.update(center=(rng.normal(size=3) * [1.5, 1.0, 0.5]).tolist(), radius=float(rng.uniform(0.3, 0.9)))
        else:
            ob.update(translate=(rng.normal(size=3) * [1.5, 1.0, 0.5]).tolist(), scale=float(rng.uniform(0.3, 0.9)))
            ob["mode"] = ["flat", "gouraud", "phong"][rng.integers(0, 3)]
            if kind == "icosphere":
                ob["level"] = 2
            else:
                ob.update(n_lat=8, n_lon=12)
        objects.append(ob)
    lights = []
    for _ in range(rng.integers(0, 4)):
        colour = (rng.random(3) * (rng.random() < 0.85)).tolist()
        kind = rng.integers(0, 4)
        if kind == 0:
            lights.append({"type": "ambient", "color": colour, "intensity": 0.3})
        elif kind == 1:
            lights.append({"type": "directional", "direction": rng.normal(size=3).tolist(), "color": colour})
        elif kind == 2:
            lights.append({"type": "point", "position": (rng.normal(size=3) * 3).tolist(), "intensity": 8.0,
                           "color": colour})  # fmt: skip
        else:
            pos = rng.normal(size=3) * 3
            lights.append({"type": "spot", "position": pos.tolist(), "direction": (rng.normal(size=3) - pos).tolist(),
                           "cutoff_deg": float(rng.uniform(0, 90)), "intensity": 9.0, "color": colour})  # fmt: skip
    return {
        "camera": {"eye": [0.5, 0.3, 7.0], "target": [0, 0, 0], "fov_y_deg": 35.0},
        "image": {"width": 64, "height": 48},
        "render": {"form": ["classic", "physical"][rng.integers(0, 2)]},
        "materials": materials,
        "objects": objects,
        "lights": lights,
    }


def test_random_scenes_planned_equals_full():
    rng = np.random.default_rng(7)
    for _ in range(25):
        scene = parse_scene(_random_scene(rng))
        planned, _ = SceneRenderer(scene, plan=True).render()
        full, _ = SceneRenderer(scene, plan="full").render()
        np.testing.assert_allclose(planned, full, rtol=1e-12, atol=1e-12)


def test_hidden_objects_and_shared_materials_in_explain():
    scene = parse_scene(
        {
            "camera": {"eye": [0, 0, 6.0], "target": [0, 0, 0]},
            "image": {"width": 64, "height": 64},
            "materials": {"red": {"parts": [{"model": "lambert", "kd": [0.8, 0.1, 0.1]}]}},
            "objects": [
                {"type": "sphere", "center": [-0.6, 0, 0], "radius": 0.5, "material": "red"},
                {"type": "sphere", "center": [0.6, 0, 0], "radius": 0.5, "material": "red"},
                {"type": "sphere", "center": [-0.6, 0, -3.0], "radius": 0.2, "material": "red"},  # behind object 0
            ],
            "lights": [{"type": "directional", "direction": [0, 0, 1]}],
        }
    )
    sr = SceneRenderer(scene)
    planned, info = sr.render()
    assert info["visible_pixels"][2] == 0
    text = sr.explain()
    assert "object 2 (sphere): left out — hidden behind other objects" in text
    assert "objects 0 (sphere), 1 (sphere) — one material, one evaluation for all" in text
    full, _ = SceneRenderer(scene, plan="full").render()
    np.testing.assert_allclose(planned, full, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_diffuse_directional_plan_saturates_like_the_general_path(dtype):
    # Finite in, finite out: a saturated colour times a zero weight (the far side) is 0, the lit side saturates.
    from lighting.render.mesh import icosphere
    from lighting.render.renderer import Renderer

    mat = Material(Lambert(1e308))
    lights = [AmbientLight(1e308, 1e308), DirectionalLight((0, 0, 1.0), intensity=1e308)]
    r = Renderer(icosphere(2), Camera((0, 0, 5.0), (0, 0, 0), width=24, height=24), dtype=dtype)
    plan = compile_plan(mat, lights)
    assert plan.strategy == "diffuse-directional"
    img = plan.execute(r)
    assert img.dtype == dtype and np.all(np.isfinite(img)) and img.max() == np.finfo(dtype).max
    np.testing.assert_array_equal(img, evaluate_full(r, mat, lights))
    with pytest.raises(ValueError, match=r"^bounds must be None or \(centre, radius\)"):
        compile_plan(mat, lights, bounds="ball")
    with pytest.raises(TypeError, match="^renderer must be a lighting.render.renderer.Renderer; got NoneType"):
        plan.execute(None)

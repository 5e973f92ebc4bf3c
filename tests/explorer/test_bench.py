import functools
import json

import numpy as np

from explorer import bench
from explorer.commands.bench import main as bench_main


def test_bench_scene_is_the_stated_one():
    mesh, camera, material, lights = bench.bench_scene()
    assert 4500 <= mesh.n_triangles <= 5500
    assert (camera.width, camera.height) == (512, 512)
    assert sum(1 for lt in lights if hasattr(lt, "direction")) == 3
    assert [p.term for p in material.brdf.parts] == ["diffuse", "specular"]


def test_bench_json_line_is_consistent(capsys, monkeypatch):
    monkeypatch.setattr(bench, "SIZE", 64)
    assert bench_main(["--json", "--repeat", "1"]) == 0
    line = capsys.readouterr().out.strip().splitlines()[-1]
    r = json.loads(line)
    for key in ("reshade_ms", "raster_ms", "raster_shade_ms", "vtk_ms", "reshade_f32_ms"):
        assert r[key] > 0
    assert np.isclose(r["reshade_over_vtk"], r["reshade_ms"] / r["vtk_ms"])
    assert r["size"] == 64


_FAULTS = """
import resource, sys
if sys.argv[1] == "tune":
    from explorer._allocator import tune_allocator
    assert tune_allocator()
from explorer.bench import bench_scene
from lighting.render.renderer import Renderer
mesh, camera, material, lights = bench_scene(size=192)
for _ in range(3):
    Renderer(mesh, camera).render(material, lights)
before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
for _ in range(4):
    Renderer(mesh, camera).render(material, lights)
print((resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before) / 4)
"""


def test_tuned_allocator_stops_page_faults_per_frame():
    import subprocess
    import sys

    if not sys.platform.startswith("linux"):
        import pytest

        pytest.skip("glibc allocator tuning is Linux-only")

    def faults(mode):
        out = subprocess.run([sys.executable, "-c", _FAULTS, mode], capture_output=True, text=True, check=True)
        return float(out.stdout.strip().splitlines()[-1])

    default, tuned = faults("default"), faults("tune")
    # Every frame's temporaries page-fault anew with glibc's defaults; with the thresholds raised, none do.
    assert tuned < 50 < default


def test_bench_ibl_json_line_is_consistent(capsys, monkeypatch):
    from lighting.render import AnalyticSphere, Renderer, sphere_camera

    monkeypatch.setattr(bench, "SIZE", 32)
    # A 64×32 sky instead of the bench's 512×256 (ibl_frames' own env_height): the same JSON, a fraction
    # of the prefiltering and the Monte-Carlo pass.
    monkeypatch.setattr(bench, "ibl_frames", functools.partial(bench.ibl_frames, env_height=32))
    assert bench_main(["--ibl", "--json", "--repeat", "1"]) == 0
    r = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    for key in ("ibl_reshade_ms", "ibl_reshade_f64_ms", "ibl_dominant_ms", "ibl_dominant_studio_ms",
                "ibl_dominant_sun_ms", "ibl_dominant_pixels_ms", "ibl_dominant_narrow_ms", "ibl_dominant_setup_ms",
                "ibl_prefilter_ms", "ibl_mc64_ms"):  # fmt: skip
        assert r[key] > 0
    assert np.isclose(r["ibl_dominant_over_reshade"], r["ibl_dominant_ms"] / r["ibl_reshade_ms"])
    assert np.isclose(r["ibl_pixels_over_grid"], r["ibl_dominant_pixels_ms"] / r["ibl_dominant_ms"])
    assert np.isclose(r["ibl_reshade_over_f64"], r["ibl_reshade_ms"] / r["ibl_reshade_f64_ms"])
    assert np.isclose(r["ibl_mc64_over_reshade"], r["ibl_mc64_ms"] / r["ibl_reshade_ms"])
    # The targets the bench holds the image-based lighting to, and the sphere's pixel count as the renderer
    # covers it.
    assert r["targets"] == {"ibl_reshade_ms": 50.0, "ibl_dominant_ms": 50.0, "ibl_dominant_studio_ms": 50.0,
                            "ibl_dominant_sun_ms": 50.0, "ibl_dominant_narrow_ms": 50.0, "ibl_prefilter_ms": 300.0,
                            "ibl_mc64_ms": 5000.0}
    assert r["size"] == 32
    assert r["pixels"] == int(Renderer(AnalyticSphere(), sphere_camera(32)).gbuffer.coverage.sum())
    table = bench.format_ibl(r)
    assert f"{r['ibl_prefilter_ms']:9.1f}" in table and "<= 300" in table


def test_bench_ibl_and_plan_are_exclusive(capsys):
    assert bench_main(["--ibl", "--plan"]) == 2
    assert "--plan and --ibl" in capsys.readouterr().err

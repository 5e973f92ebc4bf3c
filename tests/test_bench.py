import json

import numpy as np

from explorer import bench


def test_bench_scene_is_the_stated_one():
    mesh, camera, material, lights = bench.bench_scene()
    assert 4500 <= mesh.n_triangles <= 5500
    assert (camera.width, camera.height) == (512, 512)
    assert sum(1 for lt in lights if hasattr(lt, "direction")) == 3
    assert [p.term for p in material.brdf.parts] == ["diffuse", "specular"]


def test_bench_json_line_is_consistent(capsys, monkeypatch):
    monkeypatch.setattr(bench, "SIZE", 64)
    assert bench.main(["--json", "--repeat", "1"]) == 0
    line = capsys.readouterr().out.strip().splitlines()[-1]
    r = json.loads(line)
    for key in ("reshade_ms", "raster_shade_ms", "vtk_ms", "reshade_f32_ms"):
        assert r[key] > 0
    assert np.isclose(r["reshade_over_vtk"], r["reshade_ms"] / r["vtk_ms"])
    assert r["size"] == 64

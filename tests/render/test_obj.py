"""The NumPy OBJ reader: the same triangles, normals and texture coordinates as trimesh, errors with lines, a fuzz."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

from lighting.render.mesh import icosphere, load_mesh, uv_sphere
from lighting.render.obj import read_obj
from lighting.scene.examples import example_path

CUBE = Path(example_path("cube")).with_suffix(".obj")  # the example scenes' cube


def corners(vertices, faces, values):
    """Per-triangle corner values, rows sorted: independent of how either reader numbers its vertices."""
    rows = np.concatenate([vertices[faces].reshape(len(faces), -1), values[faces].reshape(len(faces), -1)], axis=1)
    return rows[np.lexsort(rows.T[::-1])]


def trimesh_arrays(path):
    m = trimesh.load(path, process=False)
    normals = m._cache["vertex_normals"] if "vertex_normals" in m._cache else None
    uv = getattr(getattr(m, "visual", None), "uv", None)
    return np.asarray(m.vertices), np.asarray(m.faces), normals, uv


@pytest.mark.parametrize("kind", ["cube", "normals", "uvs", "plain"])
def test_the_reader_gives_trimeshs_triangles_normals_and_coordinates(tmp_path, kind):
    path = tmp_path / f"{kind}.obj"
    if kind == "cube":
        path.write_text(CUBE.read_text())
    else:
        src = icosphere(2) if kind != "uvs" else uv_sphere(8, 16)
        tm = trimesh.Trimesh(src.vertices, src.faces, vertex_normals=src.normals, process=False)
        if kind == "uvs":
            uv = np.stack([np.arctan2(src.vertices[:, 0], src.vertices[:, 2]) / (2 * np.pi) + 0.5,
                           src.vertices[:, 1] * 0.5 + 0.5], axis=1)  # fmt: skip
            tm.visual = trimesh.visual.TextureVisuals(uv=uv)
        tm.export(path, include_normals=(kind != "plain"))
    v, f, n, uv = read_obj(path)
    tv, tf, tn, tuv = trimesh_arrays(path)
    assert f.shape == tf.shape and v.shape == tv.shape
    np.testing.assert_array_equal(corners(v, f, v), corners(tv, tf, tv))
    if kind == "plain":
        assert n is None and uv is None
        np.testing.assert_array_equal(v, tv)  # positions only: the file's order, as trimesh keeps it
        np.testing.assert_array_equal(f, tf)
    else:
        np.testing.assert_allclose(corners(v, f, n), corners(tv, tf, np.asarray(tn)), rtol=0, atol=1e-12)
    if kind == "uvs":
        np.testing.assert_allclose(corners(v, f, uv), corners(tv, tf, np.asarray(tuv)), rtol=0, atol=1e-12)


def test_polygons_are_fans_and_negative_indices_count_back(tmp_path):
    text = ("v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\n"
            "f 1 2 3 4 5\n"         # a pentagon: the fan (1 2 3) (1 3 4) (1 4 5)
            "v 0 0 1\nv 1 0 1\nv 0 1 1\n"
            "f -3 -2 -1  # the last three positions\n")  # fmt: skip
    (tmp_path / "p.obj").write_text(text)
    v, f, n, uv = read_obj(tmp_path / "p.obj")
    assert f.tolist() == [[0, 1, 2], [0, 2, 3], [0, 3, 4], [5, 6, 7]] and n is None and uv is None
    m = load_mesh(tmp_path / "p.obj")
    assert m.area == pytest.approx(2.5 + 0.5, rel=1e-15)  # the pentagon's area (shoelace: 2.5) and the triangle's


def test_normals_are_split_per_corner_and_dropped_when_some_corner_lacks_one(tmp_path):
    (tmp_path / "a.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nvn 0 0 2\n"
                                    "f 1//1 2//1 3//1\nf 2//2 4//2 3//2\n")  # fmt: skip
    v, f, n, _ = read_obj(tmp_path / "a.obj")
    assert len(v) == 6 and n.tolist().count([0.0, 0.0, 2.0]) == 3  # 2 and 3 used with two normals: split
    np.testing.assert_allclose(load_mesh(tmp_path / "a.obj").normals, [[0, 0, 1]] * 6)  # normalized by the mesh
    (tmp_path / "b.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 2 4 3\n")
    assert read_obj(tmp_path / "b.obj")[2] is None and not load_mesh(tmp_path / "b.obj").has_given_normals


@pytest.mark.parametrize(
    ("text", "line", "words"),
    [
        ("v 0 0 0\nv 1 0 x\n", 2, "'v' takes numbers; got '1 0 x'"),
        ("v 0 0\n", 1, "'v' takes 3 to 7 numbers; got 2"),
        ("v 0 0 0\nv 1 0 0\nf 1 2\n", 3, "a face needs at least 3 corners; got 2"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, "face position index 0 out of range (3 positions defined)"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", 4, "face position index 4 out of range"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", 4, "face position index -4 out of range"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n", 4, "face normal index 1 out of range (0 normals defined)"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n", 4, "a face corner is i, i/t, i//n or i/t/n"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 a\n", 4, "a face corner's position index must be an integer; got 'a'"),
        ("v 0 0 0\n\x01\x02 3\n", 2, "expected a keyword (v, vt, vn, f, ...)"),
    ],
)
def test_each_malformed_line_is_one_error_naming_file_and_line(tmp_path, monkeypatch, text, line, words):
    (tmp_path / "bad.obj").write_text(text)
    monkeypatch.chdir(tmp_path)  # the name as given, whole: a long temporary folder would be abbreviated
    with pytest.raises(ValueError) as exc:
        load_mesh("bad.obj")
    msg = str(exc.value)
    head = f"mesh file 'bad.obj' could not be read as OBJ: line {line}: "
    assert msg.startswith(head) and words in msg
    assert "\n" not in msg


def test_fuzzed_obj_files_give_a_mesh_or_one_value_error(tmp_path):
    base = CUBE.read_bytes()
    rng = np.random.default_rng(17)
    outcomes = {"mesh": 0, "error": 0}
    for i in range(300):
        data = bytearray(base)
        for _ in range(rng.integers(1, 4)):
            op, at = rng.integers(0, 3), int(rng.integers(0, len(data)))
            if op == 0:
                data[at] = int(rng.integers(0, 256))
            elif op == 1:
                del data[at : at + int(rng.integers(1, 40))]
            else:
                data[at:at] = bytes(rng.choice(list(b"0123456789 -/.\nvfn#e"), int(rng.integers(1, 12))))
        path = tmp_path / f"f{i}.obj"
        path.write_bytes(bytes(data))
        try:
            m = load_mesh(path)
        except ValueError as e:
            assert str(e).startswith("mesh file ") and "\n" not in str(e)
            outcomes["error"] += 1
        else:
            assert np.isfinite(m.vertices).all() and np.isfinite(m.normals).all()
            outcomes["mesh"] += 1
    assert outcomes["mesh"] > 30 and outcomes["error"] > 30  # both paths exercised


def test_a_scene_with_an_obj_mesh_does_not_import_trimesh():
    code = ("import sys; from lighting.scene import load_scene, examples; "
            "s = load_scene(examples.example_path('cube')); "
            "print('trimesh' in sys.modules, len(s.objects))")  # fmt: skip
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert out[0] == "False" and int(out[1]) >= 1

"""Each command run without each optional extra, in a fresh interpreter (slow set; fast: test_cli_conventions.py)."""

import subprocess
import sys

import pytest

pytestmark = pytest.mark.slow  # thirteen fresh interpreters

PLY = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n" \
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"  # fmt: skip
SCENE = ('[camera]\neye = [0, 0, 5]\n[image]\nwidth = 8\nheight = 8\n[[lights]]\ntype = "ambient"\n'
         '[[objects]]\ntype = "mesh"\npath = "tri.ply"\n')  # fmt: skip


def _without(module: str, argv, cwd):
    code = f"import sys; sys.modules[{module!r}] = None\nfrom explorer.cli import main\nsys.exit(main(sys.argv[1:]))"
    return subprocess.run([sys.executable, "-c", code, *argv], capture_output=True, text=True, timeout=300, cwd=cwd)


def test_commands_that_need_no_extra_run_without_them(tmp_path):
    for module in ("matplotlib", "trimesh", "pyvista"):
        done = _without(module, ["sphere", "--size", "8", "-o", "s.png"], tmp_path)
        assert done.returncode == 0 and done.stdout.startswith("wrote s.png (8x8, PNG)"), done.stderr
        done = _without(module, ["render", "cube", "--size", "8", "-o", "c.png"], tmp_path)  # an OBJ: NumPy reads it
        assert done.returncode == 0 and done.stdout.startswith("wrote c.png (8x8, 1 object,"), done.stderr


@pytest.mark.parametrize(
    ("module", "argv", "line"),
    [
        ("matplotlib", ["figures", "--list"],
         "lighting-explorer: error: figures needs Matplotlib: pip install 'lighting-explorer[figures]'"),
        ("cycler", ["figures", "--list"],
         "lighting-explorer: error: figures needs Matplotlib: pip install 'lighting-explorer[figures]'"),
        ("matplotlib", ["report", "accuracy", "--quick"],
         "lighting-explorer: error: report accuracy needs Matplotlib: pip install 'lighting-explorer[figures]'"),
        ("mpmath", ["report", "stability", "--quick"],
         "lighting-explorer: error: report stability needs mpmath: pip install 'lighting-explorer[figures]'"),
        ("pyvista", ["explore", "--off-screen"],
         "lighting-explorer: error: explore needs PyVista: pip install 'lighting-explorer[app]'"),
        ("pyvista", ["--off-screen"],
         "lighting-explorer: error: explore needs PyVista: pip install 'lighting-explorer[app]'"),
        ("trimesh", ["render", "s.toml", "-o", "o.png"],
         "lighting-explorer: error: render needs trimesh: pip install 'lighting-explorer[figures]'"),
    ],
)  # fmt: skip
def test_a_missing_extra_is_one_line_naming_it(module, argv, line, tmp_path):
    (tmp_path / "tri.ply").write_text(PLY)
    (tmp_path / "s.toml").write_text(SCENE)
    done = _without(module, argv, tmp_path)
    assert (done.returncode, done.stderr) == (2, line + "\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml", "tri.ply"]  # nothing written

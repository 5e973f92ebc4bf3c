"""Commands that need no optional extra, run without each (slow set; fast: test_cli_conventions.py)."""

import pytest
from test_cli_conventions import _without

pytestmark = pytest.mark.slow  # six fresh interpreters, each rendering


def test_commands_that_need_no_extra_run_without_them(tmp_path):
    for module in ("matplotlib", "trimesh", "pyvista"):
        done = _without(module, ["sphere", "--size", "8", "-o", "s.png"], tmp_path)
        assert done.returncode == 0 and done.stdout.startswith("wrote s.png (8x8, PNG)"), done.stderr
        done = _without(module, ["render", "cube", "--size", "8", "-o", "c.png"], tmp_path)  # an OBJ: NumPy reads it
        assert done.returncode == 0 and done.stdout.startswith("wrote c.png (8x8, 1 object,"), done.stderr

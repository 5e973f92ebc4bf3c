"""The package as a user installs it: a wheel built from the checkout, installed into a fresh virtual environment.

Everything the installed commands need (the example scenes, their meshes and sky files) must be in the wheel:
a file missing from the package data shows here as a scene that fails to render, never only on a user's machine.
The environment sees this interpreter's site-packages for the dependencies (NumPy, Matplotlib, …), so the test
needs no network; the package itself is the wheel's copy, which the test checks.
"""

from __future__ import annotations

import os
import subprocess
import zipfile
from pathlib import Path

import pytest
from installed_wheel import ROOT, shared_install
from installed_wheel import run_command as _run

from explorer.cli import main
from lighting.scene.examples import EXAMPLES_DIR, list_examples

pytestmark = pytest.mark.slow

#: Each scene is rendered at this size in both installations: small, and the same in both.
SIZE = "96x72"


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """``(bin folder, work folder, wheel)`` of a virtual environment with the checkout's wheel installed."""
    return shared_install(tmp_path_factory)


def test_the_wheel_holds_every_file_the_packages_ship(installed):
    # Every tracked file under lighting/ and explorer/ that is not Python source is package data.
    _, _, wheel = installed
    tracked = subprocess.run(["git", "ls-files", "lighting", "explorer"], cwd=ROOT, capture_output=True, text=True)
    if tracked.returncode != 0:
        pytest.skip("not a git checkout")
    data = {p for p in tracked.stdout.split() if not p.endswith(".py")}
    with zipfile.ZipFile(wheel) as z:
        names = set(z.namelist())
    assert data and data <= names, sorted(data - names)


def test_the_installed_package_is_the_wheels_copy(installed):
    bin_dir, work, _ = installed
    code = "import lighting, explorer; print(lighting.__file__, explorer.__file__)"
    out = _run([str(bin_dir / "python"), "-c", code], cwd=work).stdout.split()
    venv = bin_dir.parent.resolve()
    assert all(Path(p).resolve().is_relative_to(venv) for p in out), out


@pytest.mark.parametrize("name", list_examples())
def test_every_example_scene_renders_from_the_installed_package_as_from_the_checkout(installed, tmp_path, name):
    bin_dir, work, _ = installed
    out = work / f"{name}.png"
    _run([str(bin_dir / "lighting-explorer"), "render", name, "--size", SIZE, "-o", str(out)], cwd=work)
    here = tmp_path / f"{name}.png"
    assert main(["render", name, "--size", SIZE, "-o", str(here)]) == 0
    assert out.read_bytes() == here.read_bytes()
    assert os.path.isfile(os.path.join(EXAMPLES_DIR, f"{name}.toml"))

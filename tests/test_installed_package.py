"""The package as a user installs it: a wheel built from the checkout, installed into a fresh virtual environment.

Everything the installed commands need (the example scenes, their meshes and sky files) must be in the wheel:
a file missing from the package data shows here as a scene that fails to render, never only on a user's machine.
The environment sees this interpreter's site-packages for the dependencies (NumPy, Matplotlib, …), so the test
needs no network; the package itself is the wheel's copy, which the test checks.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from explorer.cli import main
from explorer.figures import figure_names
from lighting.scene.examples import EXAMPLES_DIR, list_examples

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[1]
#: Each scene is rendered at this size in both installations: small, and the same in both.
SIZE = "96x72"


def _run(args, cwd, **kw):
    res = subprocess.run(args, cwd=cwd, capture_output=True, text=True, timeout=600, **kw)
    assert res.returncode == 0, f"{' '.join(map(str, args))}\n{res.stdout}\n{res.stderr}"
    return res


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """``(bin folder, work folder)`` of a virtual environment with the checkout's wheel installed."""
    tmp = tmp_path_factory.mktemp("installed")
    wheels = tmp / "wheels"
    _run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "--no-build-isolation",
          "--disable-pip-version-check", "-w", str(wheels), str(ROOT)], cwd=tmp)  # fmt: skip
    (wheel,) = wheels.glob("lighting_explorer-*.whl")
    venv = tmp / "venv"
    _run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], cwd=tmp)
    bin_dir = venv / "bin"
    _run([str(bin_dir / "python"), "-m", "pip", "install", "--quiet", "--no-deps", "--no-index",
          "--disable-pip-version-check", "--force-reinstall", str(wheel)], cwd=tmp)  # fmt: skip
    work = tmp / "work"  # not the checkout: nothing can be imported from the working tree
    work.mkdir()
    return bin_dir, work, wheel


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


def test_the_quick_figure_set_draws_from_the_installed_package(installed):
    bin_dir, work, _ = installed
    out = work / "figures"
    env = dict(os.environ, LIGHTING_EXPLORER_CACHE=str(work / "cache"))
    res = _run([str(bin_dir / "lighting-explorer"), "figures", "--quick", "--out", str(out)], cwd=work, env=env)
    names = figure_names()
    assert f"wrote {len(names)} figures" in res.stdout
    manifest = json.loads((out / "figures.json").read_text(encoding="utf-8"))
    assert [r["name"] for r in manifest["figures"]] == names
    for rec in manifest["figures"]:
        png = (out / rec["files"]["png"]).read_bytes()
        assert png[:8] == b"\x89PNG\r\n\x1a\n"
        assert (int.from_bytes(png[16:20], "big"), int.from_bytes(png[20:24], "big")) == tuple(rec["size_px"])

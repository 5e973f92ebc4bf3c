"""The package as a user installs it: the checkout's wheel in a fresh virtual environment (a helper for tests).

The environment sees this interpreter's site-packages for the dependencies (NumPy, Matplotlib, …), so building it
needs no network; the package itself is the wheel's copy (``tests/test_installed_package.py`` checks that).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from run_once import run_root_locked

ROOT = Path(__file__).resolve().parents[1]


def run_command(args, cwd, **kw):
    """Run a command; its failure fails the test with the command line and both streams."""
    res = subprocess.run(args, cwd=cwd, capture_output=True, text=True, timeout=600, **kw)
    assert res.returncode == 0, f"{' '.join(map(str, args))}\n{res.stdout}\n{res.stderr}"
    return res


def shared_install(tmp_path_factory):
    """``(bin folder, work folder, wheel)``: the checkout's wheel in a virtual environment, built once per test run.

    Under pytest-xdist the workers share the run's temporary root: the first to get there builds the wheel and the
    environment (a file lock holds the others), the rest use them.  Each caller gets a fresh work folder.
    """
    with run_root_locked(tmp_path_factory, "installed-wheel") as root:
        shared = root / "installed-wheel"
        done = shared / "done.txt"
        if done.is_file():
            bin_dir, wheel = (Path(p) for p in done.read_text(encoding="utf-8").splitlines())
        else:
            shared.mkdir(exist_ok=True)
            bin_dir, wheel = _build_and_install(shared)
            done.write_text(f"{bin_dir}\n{wheel}\n", encoding="utf-8")
    work = tmp_path_factory.mktemp("work")  # not the checkout: nothing can be imported from the working tree
    return bin_dir, work, wheel


def _build_and_install(tmp: Path):
    """``(bin folder, wheel)``: the checkout's wheel built under ``tmp``, installed in a virtual environment there."""
    wheels = tmp / "wheels"
    run_command([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "--no-build-isolation",
         "--disable-pip-version-check", "-w", str(wheels), str(ROOT)], cwd=tmp)  # fmt: skip
    (wheel,) = wheels.glob("lighting_explorer-*.whl")
    venv = tmp / "venv"
    # No pip of its own (ensurepip would install one, seconds of work): this interpreter's pip, seen through the
    # system site-packages, installs into the environment it runs in.
    run_command([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip", str(venv)], cwd=tmp)
    bin_dir = venv / "bin"
    run_command([str(bin_dir / "python"), "-m", "pip", "install", "--quiet", "--no-deps", "--no-index",
         "--disable-pip-version-check", "--force-reinstall", str(wheel)], cwd=tmp)  # fmt: skip
    return bin_dir, wheel

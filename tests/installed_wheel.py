"""The package as a user installs it: the checkout's wheel in a fresh virtual environment (a helper for tests).

The environment sees this interpreter's site-packages for the dependencies (NumPy, Matplotlib, …), so building it
needs no network; the package itself is the wheel's copy (``tests/test_installed_package.py`` checks that).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def run_command(args, cwd, **kw):
    """Run a command; its failure fails the test with the command line and both streams."""
    res = subprocess.run(args, cwd=cwd, capture_output=True, text=True, timeout=600, **kw)
    assert res.returncode == 0, f"{' '.join(map(str, args))}\n{res.stdout}\n{res.stderr}"
    return res


def install_wheel(tmp: Path):
    """``(bin folder, work folder, wheel)`` of a virtual environment under ``tmp`` holding the checkout's wheel."""
    wheels = tmp / "wheels"
    run_command([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "--no-build-isolation",
         "--disable-pip-version-check", "-w", str(wheels), str(ROOT)], cwd=tmp)  # fmt: skip
    (wheel,) = wheels.glob("lighting_explorer-*.whl")
    venv = tmp / "venv"
    run_command([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], cwd=tmp)
    bin_dir = venv / "bin"
    run_command([str(bin_dir / "python"), "-m", "pip", "install", "--quiet", "--no-deps", "--no-index",
         "--disable-pip-version-check", "--force-reinstall", str(wheel)], cwd=tmp)  # fmt: skip
    work = tmp / "work"  # not the checkout: nothing can be imported from the working tree
    work.mkdir()
    return bin_dir, work, wheel

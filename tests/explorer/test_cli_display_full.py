"""The window command in a fresh interpreter where no display answers (slow set; fast: test_cli_display.py)."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

pytestmark = pytest.mark.slow  # a fresh interpreter loading the explorer

HEADLESS = "for images instead run `lighting-explorer --off-screen --screenshot out.png`"


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the window needs X or Wayland on Linux only")
def test_the_window_command_with_a_dead_wayland_name_exits_1_with_one_line(tmp_path):
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "QT_QPA_PLATFORM")}
    env["WAYLAND_DISPLAY"] = "/nonexistent"
    run = subprocess.run([sys.executable, "-m", "explorer.cli"], env=env, capture_output=True, text=True, timeout=60,
                         cwd=tmp_path)  # fmt: skip
    assert (run.returncode, run.stdout) == (1, "")
    assert run.stderr == (
        "lighting-explorer: DISPLAY is unset and no Wayland compositor answers at WAYLAND_DISPLAY=/nonexistent, so "
        f"no window can open; {HEADLESS} (any control options work too) or `lighting-explorer sphere -o sphere.png`\n"
    )
    assert list(tmp_path.iterdir()) == []

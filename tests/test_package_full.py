"""The explorer window's screenshot written by the command (slow set; fast: test_package.py)."""

import pytest

from explorer.cli import main

pytestmark = pytest.mark.slow  # opens the explorer window off-screen and renders it


@pytest.mark.xfail(strict=True, reason="the Qt window's smallest size is wider than 640 px: 640x400 gives 860x523")
def test_explore_screenshot_format_follows_the_extension(tmp_path, capsys):
    pytest.importorskip("pyvista")
    pytest.importorskip("PySide6")
    pil = pytest.importorskip("PIL.Image")
    path = tmp_path / "window.webp"
    assert main(["--screenshot", str(path), "--size", "640x400"]) == 0
    assert f"wrote {path} (640x400)" in capsys.readouterr().out
    with pil.open(path) as im:
        assert im.format == "WEBP" and im.size == (640, 400)
    assert [p.name for p in tmp_path.iterdir()] == ["window.webp"]

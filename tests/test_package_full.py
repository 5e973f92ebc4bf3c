"""The explorer window's screenshot written by the command (slow set; fast: test_package.py)."""

import pytest

from explorer.cli import main

pytestmark = pytest.mark.slow  # opens the explorer window off-screen and renders it


def test_explore_screenshot_format_follows_the_extension(tmp_path, capsys):
    pytest.importorskip("pyvista")
    pytest.importorskip("PySide6")
    pil = pytest.importorskip("PIL.Image")
    path = tmp_path / "window.webp"
    assert main(["--screenshot", str(path), "--size", "800x500"]) == 0
    assert f"wrote {path} (800x500)" in capsys.readouterr().out
    with pil.open(path) as im:
        assert im.format == "WEBP" and im.size == (800, 500)
    assert [p.name for p in tmp_path.iterdir()] == ["window.webp"]

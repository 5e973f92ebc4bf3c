"""The window command (``lighting-explorer`` with no sub-command) where no display answers: one line, exit 1.

A Wayland name where no compositor listens made Qt abort with a page of plugin messages; the command now
asks the compositor's socket first, as it asks an X server (``explorer.app.display``).
"""

from __future__ import annotations

import socket

import pytest

from explorer.app import display


@pytest.fixture
def linux_without_x(monkeypatch):
    monkeypatch.setattr(display.sys, "platform", "linux")
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("QT_QPA_PLATFORM", raising=False)
    return monkeypatch


def test_a_wayland_name_where_no_compositor_listens_is_the_problem_named(linux_without_x, tmp_path):
    linux_without_x.setenv("WAYLAND_DISPLAY", "/nonexistent")
    assert display.display_problem(timeout=1.0) == (
        "DISPLAY is unset and no Wayland compositor answers at WAYLAND_DISPLAY=/nonexistent"
    )
    linux_without_x.setenv("WAYLAND_DISPLAY", "wayland-7")
    linux_without_x.setenv("XDG_RUNTIME_DIR", str(tmp_path))
    assert display.display_problem(timeout=1.0) == (
        "DISPLAY is unset and no Wayland compositor answers at WAYLAND_DISPLAY=wayland-7"
    )
    linux_without_x.delenv("XDG_RUNTIME_DIR")
    assert display.display_problem(timeout=1.0) == (
        "DISPLAY is unset and WAYLAND_DISPLAY=wayland-7 needs XDG_RUNTIME_DIR, which is unset"
    )


def test_a_listening_wayland_socket_or_a_platform_that_needs_none_lets_the_window_open(linux_without_x, tmp_path):
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as server:
        server.bind(str(tmp_path / "wayland-1"))
        server.listen(1)
        linux_without_x.setenv("XDG_RUNTIME_DIR", str(tmp_path))
        linux_without_x.setenv("WAYLAND_DISPLAY", "wayland-1")
        assert display.display_problem(timeout=1.0) is None
        linux_without_x.setenv("WAYLAND_DISPLAY", str(tmp_path / "wayland-1"))  # an absolute name is the socket
        assert display.display_problem(timeout=1.0) is None
    linux_without_x.setenv("WAYLAND_DISPLAY", "/nonexistent")
    linux_without_x.setenv("QT_QPA_PLATFORM", "offscreen")  # a platform that does not use the compositor
    assert display.display_problem(timeout=1.0) is None
    linux_without_x.setenv("QT_QPA_PLATFORM", "wayland")  # the one that does
    assert display.display_problem(timeout=1.0) == (
        "DISPLAY is unset and no Wayland compositor answers at WAYLAND_DISPLAY=/nonexistent"
    )
    linux_without_x.delenv("WAYLAND_DISPLAY")
    assert display.display_problem(timeout=1.0) == "no display (DISPLAY/WAYLAND_DISPLAY unset)"

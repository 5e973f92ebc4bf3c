"""Whether a window can open here (an X server that answers, or Wayland), and the one line said when none can."""

from __future__ import annotations

import os
import sys

__all__ = ["DISPLAY_TIMEOUT", "NO_DISPLAY_MESSAGE", "display_problem", "has_display", "no_display_message"]


def no_display_message(problem: str) -> str:
    """The one line the command prints when no window can open: why, and how to get images instead.

    Parameters
    ----------
    problem : str
        Why no window can open (:func:`display_problem`).

    Returns
    -------
    str
        One line, without a newline.
    """
    return (
        f"lighting-explorer: {problem}, so no window can open; for images instead run "
        "`lighting-explorer --off-screen --screenshot out.png` (any control options work too) "
        "or `lighting-explorer sphere -o sphere.png`"
    )


NO_DISPLAY_MESSAGE = no_display_message("no display (DISPLAY/WAYLAND_DISPLAY unset)")
#: Seconds to wait for an X server to accept a connection before saying that none answers.
DISPLAY_TIMEOUT = 2.0


def has_display() -> bool:
    """Whether a window can open: on Linux and BSD an X server must answer (see :func:`display_problem`).

    Returns
    -------
    bool
        True when :func:`display_problem` finds nothing in the way.
    """
    return display_problem() is None


def display_problem(timeout: float = DISPLAY_TIMEOUT) -> str | None:
    """Why no window can open, in a few words (``None`` when one can).

    On Linux and BSD the window is an X11 window (VTK's X render window), so ``DISPLAY`` must name
    an X server that answers: a ``DISPLAY`` where nobody listens made the window fail only after
    VTK had set everything up (no message of ours, exit status 0).  The server is asked as
    Xlib asks it, first its socket (``/tmp/.X11-unix/X<n>`` or TCP port ``6000 + n``, within
    ``timeout`` seconds), then ``XOpenDisplay`` (which also checks the X authority).  Without
    ``DISPLAY``, the Wayland compositor that ``WAYLAND_DISPLAY`` names must answer on its socket (a
    name where nobody listens made Qt abort with a page of plugin messages), unless ``QT_QPA_PLATFORM``
    names another Qt platform, which does not use it.  Other systems: ``None``.

    Parameters
    ----------
    timeout : float
        Seconds to wait for the X server's socket, and again for ``XOpenDisplay``.

    Returns
    -------
    str or None
        The problem, or None when a window can open.
    """
    if not sys.platform.startswith(("linux", "freebsd", "openbsd", "netbsd")):
        return None
    display = os.environ.get("DISPLAY")
    if not display:
        wayland = os.environ.get("WAYLAND_DISPLAY")
        if not wayland:
            return "no display (DISPLAY/WAYLAND_DISPLAY unset)"
        platform = os.environ.get("QT_QPA_PLATFORM", "").strip().lower()
        if platform and not platform.startswith("wayland"):
            return None  # a Qt platform chosen by name (offscreen, eglfs, ...) does not connect to the compositor
        return _wayland_problem(wayland, timeout)
    return _x_server_problem(display, timeout)


def _wayland_problem(name: str, timeout: float) -> str | None:
    import socket

    # libwayland's rule: an absolute name is the socket itself, else it lies in XDG_RUNTIME_DIR.
    runtime = os.environ.get("XDG_RUNTIME_DIR")
    if not os.path.isabs(name) and not runtime:
        return f"DISPLAY is unset and WAYLAND_DISPLAY={name} needs XDG_RUNTIME_DIR, which is unset"
    path = name if os.path.isabs(name) else os.path.join(runtime, name)
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as sock:
        sock.settimeout(timeout)
        try:
            sock.connect(path)
        except OSError:
            return f"DISPLAY is unset and no Wayland compositor answers at WAYLAND_DISPLAY={name}"
    return None


def _x_server_problem(display: str, timeout: float) -> str | None:
    import ctypes
    import socket
    import threading

    host, sep, rest = display.rpartition(":")
    number = rest.split(".")[0]
    if not sep or not number.isdigit():
        return f"DISPLAY={display!r} is not an X display name (such as :0 or host:0)"
    n = int(number)
    try:
        if host in ("", "unix"):
            path = f"/tmp/.X11-unix/X{n}"
            candidates = [path] + (["\0" + path] if sys.platform.startswith("linux") else [])  # Linux: abstract too
            for k, address in enumerate(candidates):
                with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as sock:
                    sock.settimeout(timeout)
                    try:
                        sock.connect(address)
                        break
                    except OSError:
                        if k == len(candidates) - 1:
                            raise
        else:
            socket.create_connection((host, 6000 + n), timeout=timeout).close()
    except OSError:
        return f"no X server answers at DISPLAY={display}"
    try:
        xlib = ctypes.CDLL("libX11.so.6")
    except OSError:  # the socket answered; without Xlib here the window will tell more
        return None
    xlib.XOpenDisplay.restype = ctypes.c_void_p
    xlib.XOpenDisplay.argtypes = [ctypes.c_char_p]
    xlib.XCloseDisplay.argtypes = [ctypes.c_void_p]
    # XOpenDisplay waits as long as the server is silent (a socket that accepts and never replies):
    # it runs in a daemon thread (ctypes releases the GIL), given ``timeout`` seconds.
    result = {}

    def opener():
        handle = xlib.XOpenDisplay(display.encode())
        result["handle"] = handle
        if handle:
            xlib.XCloseDisplay(handle)

    worker = threading.Thread(target=opener, name="lighting-explorer X probe", daemon=True)
    worker.start()
    worker.join(timeout)
    if "handle" not in result:
        return f"no X server answers at DISPLAY={display} (it accepted the connection, then said nothing)"
    if not result["handle"]:
        return f"the X server at DISPLAY={display} refused the connection (check its X authority, xauth)"
    return None

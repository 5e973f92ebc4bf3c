"""The desktop explorer on Qt: a window of linked views over the toolkit-free core.

The window (:class:`~explorer.qt.window.ExplorerWindow`) maps the controls' state
(:class:`explorer.app.state.AppState`) onto Qt widgets and the widgets' events back onto the state, as
napari's Qt layer does over its models; every view's data comes from
:class:`explorer.app.views.ExplorerModel`, every colour from the engine. Modules:

* :mod:`~explorer.qt.window` — :class:`ExplorerWindow`: the views, menus, key actions, status bar, timers;
* :mod:`~explorer.qt.images` — the engine's images shown as images (lit sphere, coarse spheres, lit object);
* :mod:`~explorer.qt.plots` — the Matplotlib panels on Qt canvases;
* :mod:`~explorer.qt.view3d` — the 3D BRDF lobe (pyvistaqt, or VTK off-screen where Qt has no OpenGL);
* :mod:`~explorer.qt.controls` — the control panel generated from the controls' and models' tables;
* :mod:`~explorer.qt.lists` — the lights and the comparison list;
* :mod:`~explorer.qt.app` — the QApplication, Ctrl-C and SIGTERM.

Nothing is imported with the package: Qt loads when a window is built.
"""

from __future__ import annotations

import importlib

_HOMES = {
    "ExplorerWindow": "window",
    "qt_application": "app",
    "run_window": "app",
}


def __getattr__(name):
    if name not in _HOMES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{_HOMES[name]}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_HOMES))


__all__ = sorted(_HOMES)

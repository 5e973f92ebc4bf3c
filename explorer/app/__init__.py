"""The explorer's core, free of any toolkit: the controls, the views' data, the captions and the ``explore`` command.

The desktop window is Qt's, in :mod:`explorer.qt` (:class:`explorer.qt.window.ExplorerWindow`, also reachable as
``explorer.app.ExplorerApp``); the notebook explorer (:mod:`explorer.notebook`) is another front end on the same
core.  The package, by topic:

* :mod:`~explorer.app.state` — the controls (:class:`~explorer.app.state.AppState`), validated; the
  model list is the engine's registry; :mod:`~explorer.app.params` — a model's parameter table as controls;
* :mod:`~explorer.app.scenes` — a scene file as a starting state; :mod:`~explorer.app.lights` — the scene's
  extra lights; :mod:`~explorer.app.environment` — the environment and its Monte-Carlo reference;
* :mod:`~explorer.app.views` — :class:`~explorer.app.views.ExplorerModel`, every view's data from the
  engine, recomputed only when its inputs change; :mod:`~explorer.app.comparing` — the comparison list's views;
  :mod:`~explorer.app.encode` — 8-bit sRGB codes;
* :mod:`~explorer.app.captions` — every caption and title the window shows, and the key table;
  :mod:`~explorer.app.plots` — the Matplotlib figures of the plot panels;
* :mod:`~explorer.app.display` — whether a window can open; :mod:`~explorer.app.command` — the ``explore``
  command (:func:`main`, :func:`build_parser`, :func:`add_parser`, :func:`run`).

Nothing is imported with the package: each public name loads its module on first use, and Qt, PyVista
and Matplotlib load when a window is built.
"""

from __future__ import annotations

import importlib

#: Where each public name lives; a name is imported on first use (PEP 562), so ``explorer.app.command``
#: (the ``explore`` options, built into the command tree for every run) loads no window code.
_HOMES = {
    "add_parser": "command",
    "build_parser": "command",
    "main": "command",
    "run": "command",
    "display_problem": "display",
    "has_display": "display",
    "no_display_message": "display",
    "albedo_caption": "captions",
    "DEFAULT_WINDOW_SIZE": ".command",
    "IDLE_MS": "..qt.window",
    "ExplorerApp": "..qt.window",
}
#: Names whose home has another name there: the desktop window is :class:`explorer.qt.window.ExplorerWindow`.
_RENAMED = {"ExplorerApp": "ExplorerWindow"}


def __getattr__(name):
    if name not in _HOMES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    home = _HOMES[name]
    module = importlib.import_module(home if home.startswith(".") else f".{home}", __name__)
    value = getattr(module, _RENAMED.get(name, name))
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_HOMES))


__all__ = [
    "DEFAULT_WINDOW_SIZE",
    "IDLE_MS",
    "ExplorerApp",
    "albedo_caption",
    "build_parser",
    "add_parser",
    "run",
    "has_display",
    "display_problem",
    "no_display_message",
    "main",
]

"""The window's menus and keys: every key is a ``QAction`` with a shortcut, listed in the menus and in Help.

A key changes the state at once (it is cheap) and asks the window for an update that runs when Qt's
loop is next idle, so a burst of presses (twelve quick ``m``) costs one update of the views, not twelve.
The key table (:data:`explorer.app.captions.KEYS`) is data: the menus, the shortcuts and the help dialog are
made from it.
"""

from __future__ import annotations

import os

from PySide6 import QtCore, QtGui, QtWidgets

from ..app.captions import KEYS
from ..app.state import CHANNELS, CONTROLS, ENVIRONMENTS, FORMS, LIGHT_TYPES, MODELS, TERM_NAMES

__all__ = ["KEY_ACTIONS", "build_actions", "do_key", "show_help", "FILE_FILTERS"]


#: What each key of the key table (:data:`explorer.app.captions.KEYS`, where their words live) does here:
#: the menu it is listed in and the action it performs.
KEY_ACTIONS = {
    "H": ("Help", "help"),
    "S": ("File", "screenshot"),
    "Q": ("File", "quit"),
    "R": ("View", "reset"),
    "M": ("Model", "model+"),
    "Shift+M": ("Model", "model-"),
    "P": ("Model", "pin"),
    "Shift+F": ("Model", "fit"),
    "T": ("Light", "light+"),
    "X": ("Light", "environment+"),
    "K": ("Light", "reference"),
    "I": ("View", "mode+"),
    "F": ("View", "form+"),
    "1": ("View", "term1"),
    "2": ("View", "term2"),
    "3": ("View", "term3"),
    "C": ("View", "channel+"),
    "L": ("View", "log"),
    "N": ("View", "times_cos"),
    "E": ("View", "edges"),
    "A": ("View", "panel"),
    "V": ("View", "split"),
    "O": ("View", "view3d"),
    "Up": ("View", "scan-"),
    "Down": ("View", "scan+"),
    "Left": ("View", "tess-"),
    "Right": ("View", "tess+"),
}

#: File dialogs' filters by kind of file.
FILE_FILTERS = {
    "scene": "Scene files (*.toml)",
    "brdf": "BRDF files (*.brdf *.binary)",
    "environment": "Environment images (*.hdr *.pfm *.npy *.exr)",
    "mesh": "Meshes (*.obj *.ply *.stl *.glb *.gltf *.off)",
}

_CYCLES = {
    "model": lambda: tuple(MODELS),
    "light": lambda: LIGHT_TYPES,
    "mode": lambda: ("flat", "gouraud", "phong"),
    "channel": lambda: CHANNELS,
    "form": lambda: FORMS,
}


def do_key(window, action: str) -> None:
    """Perform the key action ``action`` on ``window`` (what the shortcut and the menu item call)."""
    s = window.state
    name, _, step = action.partition("+") if "+" in action else action.partition("-")
    if action.endswith(("+", "-")) and name in _CYCLES:
        options = _CYCLES[name]()
        delta = 1 if action.endswith("+") else -1
        current = getattr(s, name)
        value = options[(options.index(current) + delta) % len(options)] if current in options else options[0]
        window.apply({name: value})
        return
    if action == "environment+":
        options = [e for e in ENVIRONMENTS if e != "file" or window.model.environment_file is not None]
        current = options.index(s.environment) if s.environment in options else -1
        window.apply({"environment": options[(current + 1) % len(options)]})
    elif action.startswith("term"):
        term = TERM_NAMES[int(action[-1]) - 1]
        window.apply({"terms": tuple(set(s.terms) ^ {term})})
    elif action in ("log", "times_cos", "split", "reference"):
        window.apply({action: not getattr(s, action)})
    elif action == "panel":
        window.apply({"panel": "angles" if s.panel == "albedo" else "albedo"})
    elif action == "view3d":
        window.apply({"view3d": "lobe" if s.view3d == "object" else "object"})
    elif action in ("scan-", "scan+"):
        spec = CONTROLS["scanline"]
        window.apply({"scanline": min(max(s.scanline + (0.02 if action == "scan+" else -0.02), spec.lo), spec.hi)})
    elif action in ("tess-", "tess+"):
        spec = CONTROLS["tessellation"]
        t = min(max(s.tessellation + (1 if action == "tess+" else -1), int(spec.lo)), int(spec.hi))
        window.apply({"tessellation": t})
    elif action == "pin":
        window.compare_action("pin")
    elif action == "fit":
        window.fit()
    elif action == "edges":
        window.show_edges = not window.show_edges
        window.gouraud_panel.canvas.update()
        window.phong_panel.canvas.update()
    elif action == "reset":
        window.reset()
    elif action == "screenshot":
        try:
            window.screenshot()
        except (ValueError, OSError) as exc:  # a full disk or a read-only folder: say so, keep the window
            window.show_error(f"screenshot not saved: {exc}")
    elif action == "help":
        show_help(window)
    elif action == "quit":
        window.close()


def show_help(window) -> QtWidgets.QDialog:
    """The keys dialog (non-modal; a second press of the key closes it)."""
    dialog = getattr(window, "help_dialog", None)
    if dialog is not None and dialog.isVisible():
        dialog.close()
        return dialog
    dialog = QtWidgets.QDialog(window)
    dialog.setWindowTitle("lighting-explorer: keys and mouse")
    table = QtWidgets.QTableWidget(len(KEYS), 2, dialog)
    table.setHorizontalHeaderLabels(["Key", "What it does"])
    table.verticalHeader().setVisible(False)
    table.setEditTriggers(QtWidgets.QAbstractItemView.EditTrigger.NoEditTriggers)
    for row, k in enumerate(KEYS):
        table.setItem(row, 0, QtWidgets.QTableWidgetItem(QtGui.QKeySequence(k.key).toString(
            QtGui.QKeySequence.SequenceFormat.NativeText)))
        table.setItem(row, 1, QtWidgets.QTableWidgetItem(k.description))
    table.resizeColumnsToContents()
    table.horizontalHeader().setStretchLastSection(True)
    note = QtWidgets.QLabel("Mouse: drag in the 3D lobe to turn it, the wheel zooms. "
                            "Drag a slider, or click its track. Hover over a control for what it does.")  # fmt: skip
    note.setWordWrap(True)
    lay = QtWidgets.QVBoxLayout(dialog)
    lay.addWidget(table)
    lay.addWidget(note)
    # Rows one line high, and the dialog as wide as the longest description and tall enough for every key
    # (as the screen allows): no scrolling in the help.
    row = table.fontMetrics().height() + 8
    table.verticalHeader().setDefaultSectionSize(row)
    bar = table.style().pixelMetric(QtWidgets.QStyle.PixelMetric.PM_ScrollBarExtent, None, table)
    margins = lay.contentsMargins()
    wide = max(620, table.horizontalHeader().length() + 2 * table.frameWidth() + bar + margins.left() + margins.right())
    tall = (table.horizontalHeader().sizeHint().height() + len(KEYS) * row + 2 * table.frameWidth()
            + lay.spacing() + note.heightForWidth(wide - margins.left() - margins.right())
            + margins.top() + margins.bottom())  # fmt: skip
    screen = window.screen().availableGeometry().height() if window.screen() is not None else tall
    dialog.resize(wide, min(tall, int(0.9 * screen)))
    # The dialog is a window of its own, where the window's shortcuts do not reach: its key closes it there too.
    help_action = getattr(window, "actions_by_key", {}).get("help")
    if help_action is not None:
        dialog.addAction(help_action)
    window.help_dialog = dialog
    dialog.show()
    return dialog


def build_actions(window) -> dict[str, QtGui.QAction]:
    """The menus (File, Model, Light, View, Help) with an action for every key and every file to open.

    Returns
    -------
    dict
        Action name → QAction.
    """
    bar = window.menuBar()
    menus = {name: bar.addMenu(f"&{name}") for name in ("File", "Model", "Light", "View", "Help")}
    actions: dict[str, QtGui.QAction] = {}
    file_menu = menus["File"]
    for kind, label in (("scene", "Open &scene…"), ("brdf", "Open &BRDF file…"),
                        ("environment", "Open &environment image…"), ("mesh", "Open &mesh…")):  # fmt: skip
        act = QtGui.QAction(label, window)
        act.triggered.connect(lambda checked=False, k=kind: open_dialog(window, k))
        file_menu.addAction(act)
        actions[f"open-{kind}"] = act
    file_menu.addSeparator()
    export = QtGui.QAction("E&xport the views as figures…", window)
    export.triggered.connect(lambda checked=False: export_dialog(window))
    file_menu.addAction(export)
    actions["export"] = export
    for k in KEYS:
        menu, name = KEY_ACTIONS[k.key]
        act = QtGui.QAction(k.description[:1].upper() + k.description[1:], window)
        act.setShortcut(QtGui.QKeySequence(k.key))
        act.setShortcutContext(QtCore.Qt.ShortcutContext.WindowShortcut)
        act.triggered.connect(lambda checked=False, a=name: do_key(window, a))
        menus[menu].addAction(act)
        window.addAction(act)
        actions[name] = act
    about = QtGui.QAction("&About lighting-explorer", window)
    about.triggered.connect(lambda checked=False: about_dialog(window))
    menus["Help"].addAction(about)
    actions["about"] = about
    return actions


def open_dialog(window, kind: str) -> bool:
    """Ask for a file of ``kind`` and open it (a bad file: one line in the status bar)."""
    path, _ = QtWidgets.QFileDialog.getOpenFileName(window, f"Open {kind}", os.getcwd(), FILE_FILTERS[kind])
    return bool(path) and window.open_file(kind, path)


def export_dialog(window) -> list[str]:
    """Ask for a folder and a format and write the current views as figures there."""
    folder = QtWidgets.QFileDialog.getExistingDirectory(window, "Export the views into a folder", os.getcwd())
    if not folder:
        return []
    fmt, ok = QtWidgets.QInputDialog.getItem(window, "Format", "Figure format:", ["png", "svg", "pdf"], 0, False)
    if not ok:
        return []
    return window.export_views(folder, fmt)


def about_dialog(window) -> None:
    """The version and where the documentation is."""
    from lighting import __version__

    QtWidgets.QMessageBox.about(window, "lighting-explorer",
                                f"lighting-explorer {__version__}\nTeach and explore local illumination.\n"
                                "Every colour on screen is computed by the lighting engine.")  # fmt: skip

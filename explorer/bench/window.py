"""Timing of the desktop window as a student meets it: a dragged slider, its release, a model switch, a 3D redraw.

Each measurement goes through the real widgets and Qt's event loop, and stops when the panels that follow
have painted: a light slider's value change until the lit sphere's panel has repainted; the release until
the lobe and the plots have; a model chosen in the model box until every view has.  Run by
``lighting-explorer bench --app``, once on Qt's ``offscreen`` platform and once in a real X server (the
running one, or Xvfb when it is installed), each in a process of its own.
"""

from __future__ import annotations

import math
import statistics
import time

from PySide6 import QtCore, QtWidgets
from PySide6.QtCore import Qt
from PySide6.QtTest import QTest

__all__ = ["benchmark_window", "TARGETS_MS"]

#: What a student should wait at most (ms): a drag frame at the display's rate, the rest at once.
TARGETS_MS = {"drag_ms": 16.0, "release_ms": 100.0, "model_switch_ms": 150.0}

#: Longest wait (s) for a panel to paint before the bench gives up on that sample.
_PAINT_TIMEOUT = 5.0


def _wait(predicate) -> None:
    app = QtWidgets.QApplication.instance()
    end = time.perf_counter() + _PAINT_TIMEOUT
    while not predicate():
        app.processEvents(QtCore.QEventLoop.ProcessEventsFlag.AllEvents)
        if time.perf_counter() > end:
            raise RuntimeError("a panel did not repaint within 5 s")


def benchmark_window(repeat: int = 15, window_size=(1280, 768), *, interactive_3d: bool | None = None) -> dict:
    """Median times (ms) of the window's interactions at ``window_size`` on the current Qt platform.

    Keys:

    * ``drag_ms`` — the elevation slider moved while held (its value changed) until the lit sphere's panel
      has repainted: validation, the engine's re-shade of the sphere and the coarse spheres, the paint;
    * ``release_ms`` — the slider released until the lobe, the polar slice and the angle plots have painted;
    * ``model_switch_ms`` — another model chosen in the model box until every view has painted;
    * ``lobe_redraw_ms`` — the 3D lobe's render alone (VTK: in the window on X, off-screen otherwise);
    * ``platform``, ``window``, ``opengl_3d`` — where it was measured.

    Parameters
    ----------
    repeat : int
        Samples per measurement (the median is reported).
    window_size : (int, int)
        The window's width and height in pixels.
    interactive_3d : bool, optional
        The 3D view as pyvistaqt's OpenGL widget (True) or VTK off-screen images (False); default: the window's.

    Returns
    -------
    dict
        The keys above.
    """
    from ..qt.app import qt_application
    from ..qt.window import ExplorerWindow

    app = qt_application()
    window = ExplorerWindow(window_size=window_size, interactive_3d=interactive_3d)
    window.show()
    _wait(lambda: window.sphere_panel.canvas.paints > 0)
    try:
        editor = window.controls.widget("elevation")
        slider = editor.slider
        sphere = window.sphere_panel.canvas
        polar, angles = window.polar_canvas, window.angle_canvas
        out = {"platform": app.platformName(), "window": [window.width(), window.height()],
               "opengl_3d": bool(window.lobe_view.interactive)}  # fmt: skip
        drags, releases = [], []
        y = slider.height() // 2

        def x_of(fraction):
            return int(round(8 + fraction * (slider.width() - 16)))

        for k in range(repeat + 2):
            # A press on the track (the knob jumps there), four moves while held, the release: as a hand does.
            QTest.mousePress(slider, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier,
                             QtCore.QPoint(x_of(0.55), y))  # fmt: skip
            _wait(lambda: True)
            for step in range(4):
                before = sphere.paints
                t0 = time.perf_counter()
                QTest.mouseMove(slider, QtCore.QPoint(x_of(0.6 + 0.05 * step + 0.02 * math.sin(k)), y))
                _wait(lambda before=before: sphere.paints > before)
                drags.append(1e3 * (time.perf_counter() - t0))
            lobe_before, polar_before, angles_before = window.lobe_view.renders, polar.paints, angles.paints
            t0 = time.perf_counter()
            QTest.mouseRelease(slider, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier,
                               QtCore.QPoint(x_of(0.75 + 0.02 * math.sin(k)), y))  # fmt: skip
            _wait(lambda a=lobe_before, b=polar_before, c=angles_before: window.lobe_view.renders > a
                  and polar.paints > b and angles.paints > c)  # fmt: skip
            releases.append(1e3 * (time.perf_counter() - t0))
        out["drag_ms"] = statistics.median(drags[8:])
        out["release_ms"] = statistics.median(releases[2:])
        box = window.controls.widget("model")
        models = [box.itemText(i) for i in range(box.count())]
        switches = []
        for _ in range(repeat):
            before = (sphere.paints, polar.paints, window.lobe_view.renders)
            t0 = time.perf_counter()
            box.setCurrentIndex((box.currentIndex() + 1) % len(models))
            _wait(lambda b=before: sphere.paints > b[0] and polar.paints > b[1] and window.lobe_view.renders > b[2])
            switches.append(1e3 * (time.perf_counter() - t0))
        out["model_switch_ms"] = statistics.median(switches)
        redraws = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            window.lobe_view.redraw()
            app.processEvents()
            redraws.append(1e3 * (time.perf_counter() - t0))
        out["lobe_redraw_ms"] = statistics.median(redraws)
        return out
    finally:
        window.close()


def main(argv=None) -> int:
    """``python -m explorer.bench.window [--repeat N] [--opengl-3d]``: one JSON line of :func:`benchmark_window`.

    ``lighting-explorer bench --app`` runs this in processes of their own, one per Qt platform.
    """
    import argparse
    import json

    p = argparse.ArgumentParser(prog="python -m explorer.bench.window")
    p.add_argument("--repeat", type=int, default=15)
    p.add_argument("--opengl-3d", dest="opengl_3d", action="store_true")
    args = p.parse_args(argv)
    print(json.dumps(benchmark_window(args.repeat, interactive_3d=True if args.opengl_3d else False)))
    return 0


if __name__ == "__main__":  # pragma: no cover
    import sys

    sys.exit(main())

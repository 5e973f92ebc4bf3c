"""The explorer page's screenshots: ``docs/images/explorer_*.png``, each the whole window at 1280 × 768.

Run from anywhere, with the ``app`` extra installed (no display needed: Qt's ``offscreen`` platform)::

    python docs/make_screenshots.py                 # every picture of docs/explorer.md
    python docs/make_screenshots.py default split   # some of them
    python docs/make_screenshots.py --list          # their names and what each shows

Each picture is an :class:`explorer.qt.window.ExplorerWindow` shown on Qt's ``offscreen`` platform, its
controls set by ``lighting-explorer`` options (read by the command's own parser, so the options a caption
gives open the same window); pins, fits, the tab on top and the selected light are done as the buttons
do them.  Every pending update is finished before :meth:`ExplorerWindow.image` is written.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
IMAGES = ROOT / "docs" / "images"
SIZE = (1280, 768)

# A scene lit by a key light and a rect light: the Lights tab lists both (and the ambient light).
RECT_SCENE = """\
description = "A sphere under a directional key light and a rect light to its right"

[camera]
eye = [0.0, 0.0, 8.0]
target = [0.0, 0.0, 0.0]
fov_y_deg = 20.0

[image]
width = 256
height = 256

[[objects]]
type = "sphere"
center = [0.0, 0.0, 0.0]
radius = 1.0
material = {parts = [{model = "lambert", kd = [0.55, 0.6, 0.7]}, {model = "blinn-phong", ks = 0.4, shininess = 60}]}

[[lights]]
type = "ambient"
intensity = 0.05

[[lights]]
type = "directional"
direction = [-1.0, 1.0, 1.2]
intensity = 0.6

[[lights]]
type = "rect"
center = [2.0, -0.6, 2.4]
edge_u = [0.0, 1.6, 0.0]
edge_v = [-1.0, 0.0, 0.8]
color = [1.0, 0.75, 0.45]
intensity = 3.0
samples = 64
two_sided = true
"""


def _window(args: list[str]):
    """An off-screen ExplorerWindow at :data:`SIZE` whose controls start as ``lighting-explorer ARGS`` sets them."""
    from explorer.app.command import build_parser
    from explorer.app.state import AppState
    from explorer.qt.app import qt_application
    from explorer.qt.window import ExplorerWindow

    qt_application(off_screen=True)
    state = AppState.from_args(build_parser().parse_args(args))
    window = ExplorerWindow(state, window_size=SIZE)
    window.show()
    return window


def _settle(window) -> None:
    """Every pending view update done and painted (as the event loop would, once idle)."""
    from PySide6 import QtWidgets

    for _ in range(3):
        QtWidgets.QApplication.processEvents()
        window.flush()
    QtWidgets.QApplication.processEvents()


def _write(window, path: Path) -> None:
    from explorer.output import write_image

    _settle(window)
    write_image(str(path), rgb8=window.image(), flag="--screenshot")
    window.close()


# --------------------------------------------------------------------------- the pictures
def shot_default(path):
    """The window at its defaults: Blinn-Phong, a directional light upper left, the Controls tab."""
    _write(_window([]), path)


def shot_coarse(path):
    """Phong e = 80 on the coarse sphere of 5 bands: Gouraud loses the highlight."""
    _write(_window(["--model", "phong", "--shininess", "80", "--tessellation", "5"]), path)


def shot_grazing(path):
    """Cook-Torrance (Beckmann α = 0.35, F0 = 0.9) under a light 15° above the horizon, plotted × n·l."""
    _write(_window(["--model", "cook-torrance", "--roughness", "0.35", "--f0", "0.9", "--elevation", "15",
                    "--times-cos", "--exposure", "-1"]), path)  # fmt: skip


def shot_anisotropic(path):
    """Ward, anisotropic (α_x = 0.08, α_y = 0.4), the BRDF views' light at φ_l = 150°."""
    _write(_window(["--model", "ward", "--param", "alpha_x=0.08", "--param", "alpha_y=0.4", "--phi", "150",
                    "--elevation", "35"]), path)  # fmt: skip


def _pinned_window(args):
    """Three pinned entries (Blinn-Phong e = 20 and 200, GGX α = 0.2), the second hidden; current GGX α = 0.45."""
    window = _window(args)
    for changes in ({"model": "blinn-phong", "shininess": 20.0}, {"model": "blinn-phong", "shininess": 200.0},
                    {"model": "cook-torrance", "ndf": "ggx", "roughness": 0.2}):  # fmt: skip
        if not window.apply(changes):
            raise SystemExit(f"make_screenshots: the window refused {changes}: {window.last_error}")
        window.flush()
        window.compare_action("pin")
    window.apply({"roughness": 0.45})
    second = window.model.compare[1].key
    window.compare_action("visible", (second, False))
    window.docks["Compare"].raise_()
    return window


def shot_compare(path):
    """Cook-Torrance GGX α = 0.45 against three pinned entries, one hidden; the Compare tab."""
    _write(_pinned_window(["--model", "cook-torrance", "--ndf", "ggx"]), path)


def shot_albedo(path):
    """The same list with the albedo panel (key A): ρ(θ_v) of the current model and the shown entries."""
    window = _pinned_window(["--model", "cook-torrance", "--ndf", "ggx", "--panel", "albedo"])
    _write(window, path)


def shot_split(path):
    """Cook-Torrance GGX (α = 0.25, F0 = 0.9), a normalized Blinn-Phong fitted to it, the split sphere."""
    window = _window(["--model", "cook-torrance", "--ndf", "ggx", "--roughness", "0.25", "--f0", "0.9",
                      "--kd", "0.05", "--fit", "blinn-phong", "--split"])  # fmt: skip
    window.fit()
    window.docks["Compare"].raise_()
    _write(window, path)


def _sky(window, environment: str) -> None:
    """Choose ``environment`` in the Environment row, as a student does: the exposure then follows the sky."""
    if not window.apply({"environment": environment}):
        raise SystemExit(f"make_screenshots: the window refused {environment!r}: {window.last_error}")
    window.flush()


def shot_environment(path):
    """A glossy sphere and the lit object under the daylight sky (chosen in the window: automatic exposure)."""
    window = _window(["--env-rotation", "60", "--view3d", "object", "--model", "cook-torrance", "--roughness", "0.05",
                      "--f0", "0.5", "--kd", "0.15", "--form", "physical", "--intensity", "0.5"])  # fmt: skip
    _sky(window, "daylight")
    _write(window, path)


def shot_reference(path, spp: int = 256, seconds: float = 300.0):
    """The Monte-Carlo reference under the studio sky, refined to ``spp`` = 256 samples per pixel."""
    window = _window(["--view3d", "object", "--model", "cook-torrance", "--roughness", "0.12", "--form", "physical"])
    _sky(window, "studio")
    window.apply({"reference": True})
    _settle(window)
    end = time.perf_counter() + seconds
    while window.model.refining and window.model.refinement.samples < spp and time.perf_counter() < end:
        window.refine_tick()
    _write(window, path)


def shot_lights(path):
    """A scene with a key light and a rect light opened (File ▸ Open scene), the Lights tab, the rect light selected."""
    with tempfile.TemporaryDirectory() as folder:
        scene = Path(folder) / "rect_light.toml"
        scene.write_text(RECT_SCENE, encoding="utf-8")
        window = _window([])
        if not window.open_file("scene", str(scene)):
            raise SystemExit(f"make_screenshots: the scene was refused: {window.last_error}")
    window.flush()
    window.docks["Lights"].raise_()
    panel = window.lights_panel
    panel.list.setCurrentRow(panel.list.count() - 1)  # the last row: the rect light
    _write(window, path)


SHOTS = {
    "default": shot_default,
    "coarse": shot_coarse,
    "grazing": shot_grazing,
    "anisotropic": shot_anisotropic,
    "compare": shot_compare,
    "albedo": shot_albedo,
    "split": shot_split,
    "environment": shot_environment,
    "reference": shot_reference,
    "lights": shot_lights,
}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python docs/make_screenshots.py", description=__doc__.splitlines()[0])
    p.add_argument("names", nargs="*", metavar="NAME", help=f"pictures to take (default: all): {', '.join(SHOTS)}")
    p.add_argument("--list", action="store_true", help="list the pictures and exit")
    p.add_argument("--out", default=str(IMAGES), help="folder of the PNGs (default: docs/images)")
    args = p.parse_args(argv)
    if args.list:
        for name, shot in SHOTS.items():
            print(f"explorer_{name}.png  {shot.__doc__.splitlines()[0]}")
        return 0
    unknown = [n for n in args.names if n not in SHOTS]
    if unknown:
        p.error(f"picture {unknown[0]!r} is not one of {', '.join(SHOTS)}")
    os.makedirs(args.out, exist_ok=True)
    for name in args.names or SHOTS:
        path = Path(args.out) / f"explorer_{name}.png"
        start = time.perf_counter()
        SHOTS[name](path)
        print(f"make_screenshots: wrote {path} ({time.perf_counter() - start:.1f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())

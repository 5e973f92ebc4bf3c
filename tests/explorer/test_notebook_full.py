"""The notebook explorer in a kernel and without PyVista, its check box of a parameter without a default; the docs
notebook run (slow set; fast: test_notebook.py)."""

from __future__ import annotations

import io
import subprocess
import sys
import textwrap

import numpy as np
import pytest

pytest.importorskip("ipywidgets")
pytest.importorskip("matplotlib")
PIL = pytest.importorskip("PIL.Image")

from test_notebook import SIZES  # noqa: E402

from explorer.app.params import offered_parameters  # noqa: E402
from explorer.app.state import AppState  # noqa: E402
from explorer.notebook import NotebookExplorer  # noqa: E402

pytestmark = pytest.mark.slow  # a Jupyter kernel, a fresh interpreter, the desktop window, a notebook explorer's plots


def decode(png: bytes) -> np.ndarray:
    with PIL.open(io.BytesIO(png)) as im:
        return np.asarray(im.convert("RGB"))


def test_docs_notebook_runs_headless(tmp_path):
    """docs/notebooks/first-steps.ipynb run by a python3 kernel: its outputs against the engine and closed forms."""
    import base64
    import math
    import pathlib
    import re
    import time

    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    from lighting import DirectionalLight, Lambert, Material, Phong
    from lighting.render import render_sphere

    path = pathlib.Path(__file__).parents[2] / "docs" / "notebooks" / "first-steps.ipynb"
    nb = nbformat.read(path, as_version=4)
    t0 = time.perf_counter()
    nbclient.NotebookClient(nb, timeout=120, kernel_name="python3", allow_errors=False,
                            resources={"metadata": {"path": str(tmp_path)}}).execute()  # fmt: skip
    seconds = time.perf_counter() - t0
    cells = {c.metadata["tags"][0]: c for c in nb.cells if c.cell_type == "code" and c.metadata.get("tags")}

    def text(tag):
        return "".join(o.get("text", "") for o in cells[tag].outputs if o.output_type == "stream")

    def png(tag):
        data = [o["data"]["image/png"] for o in cells[tag].outputs if "image/png" in o.get("data", {})]
        assert len(data) == 1, tag
        return decode(base64.b64decode(data[0]))

    light = DirectionalLight((1, 1, 1))
    sphere = render_sphere(Material(Lambert(0.8)), [light], size=201)
    shiny = render_sphere(Material(Lambert(0.8) + Phong(0.5, 32)), [light], size=201)
    # The pictures are the engine's images, sRGB-encoded: the same codes as computed here.
    assert np.array_equal(png("sphere"), sphere.srgb8())
    assert np.array_equal(png("shiny"), shiny.srgb8())
    assert np.array_equal(png("exposure"), shiny.with_exposure(-1).srgb8())
    # The printed centre pixel is k_d (n·l) = 0.8/√3, and its code the closed-form sRGB encoding.
    centre, closed = map(float, re.findall(r"\d\.\d{6}", text("centre")))
    assert centre == closed == round(0.8 / math.sqrt(3), 6)
    y = 1.055 * (0.8 / math.sqrt(3)) ** (1 / 2.4) - 0.055
    assert text("srgb").split() == ["[181", "181", "181]", "=", "181"] and round(255 * y) == 181
    assert text("shiny").splitlines() == [
        "Lambert(kd=0.8) + Phong(ks=0.5, shininess=32)",
        "DirectionalLight(direction=(0.57735, 0.57735, 0.57735), intensity=1)",
        f"brightest value {float(shiny.max()):.3f}",
    ]
    assert float(shiny.max()) > 1  # what the text says: the highlight clips
    assert text("slice").strip() == "peak at 30.0 degrees" and png("slice").shape[2] == 3
    widget = [o for o in cells["explorer"].outputs if "application/vnd.jupyter.widget-view+json" in o.get("data", {})]
    assert len(widget) == 1
    lines = text("set").splitlines()
    assert lines[0] == str(sorted(["albedo", "coarse", "halfdiff", "lobe", "polar", "profile", "sphere", "theta_d",
                                   "theta_h", "theta_v"]))  # fmt: skip
    assert lines[1] == "NotebookExplorer(Phong, light directional at elevation 30°, azimuth 135°, phong shading)"
    assert seconds < 60, seconds


def test_a_none_default_row_has_its_check_box():
    ex = NotebookExplorer(AppState(model="cook-torrance"), **SIZES)
    none_rows = [k for k in ex.controls if k.endswith(":none")]
    expected = [p.name for p in offered_parameters("cook-torrance") if p.default is None]
    assert sorted(k.split(":")[1] for k in none_rows) == sorted(expected)
    if expected:
        name = expected[0]
        assert ex.state.param(name) is None and ex.controls[f"param:{name}"].disabled
        ex.controls[f"param:{name}:none"].value = False  # take the slider's value
        assert ex.state.param(name) == pytest.approx(ex.controls[f"param:{name}"].value)
        assert not ex.controls[f"param:{name}"].disabled
        ex.controls[f"param:{name}:none"].value = True
        assert ex.state.param(name) is None and ex.controls[f"param:{name}"].disabled


def test_without_pyvista_and_without_display():
    code = textwrap.dedent(
        """
        import os, sys
        os.environ.pop("DISPLAY", None)
        sys.modules["pyvista"] = None  # PyVista absent: importing it fails
        from explorer.notebook import NotebookExplorer
        ex = NotebookExplorer(sphere_size=32, mesh_size=32, lobe_resolution=6)
        bundle = ex._repr_mimebundle_()
        assert "application/vnd.jupyter.widget-view+json" in bundle, bundle.keys()
        print(sorted(m for m in sys.modules if m.startswith(("vtk", "pyvista")) and sys.modules[m] is not None))
        """
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[]"


def test_desktop_app_displays_nothing_in_a_kernel(monkeypatch, qtbot):
    pv = pytest.importorskip("pyvista")
    pytest.importorskip("PySide6")
    display = pytest.importorskip("IPython.display")
    from explorer.app import ExplorerApp
    from explorer.qt.app import qt_application

    shown = []
    monkeypatch.setattr(display, "display", lambda *a, **k: shown.append(a))
    # As in a Jupyter kernel: PyVista's theme says "notebook", which made show() display a trame view.
    monkeypatch.setattr(pv.global_theme, "notebook", True)
    qt_application()
    app = ExplorerApp(window_size=(1200, 720))
    try:
        app.show()
        qtbot.waitExposed(app)
        img = app.image()  # the 3D view's VTK frame included
        assert img.shape[:2] == (720, 1200) and img.std() > 20
        assert app.lobe_view.plotter.off_screen and not app.lobe_view.interactive
        assert shown == []
    finally:
        app.close()

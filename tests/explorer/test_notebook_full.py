"""The documentation notebook run by a Jupyter kernel (slow set; the notebook explorer itself: test_notebook.py)."""

from __future__ import annotations

import io

import numpy as np
import pytest

pytest.importorskip("ipywidgets")
pytest.importorskip("matplotlib")
PIL = pytest.importorskip("PIL.Image")

pytestmark = pytest.mark.slow  # starts a Jupyter kernel and runs every cell of the notebook


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

"""Image-based lighting in the explorer window and the notebook: the lit object shown, refined by ticks, keys and
on request (slow set; the environment choice, the images and the reference: test_app_environment.py)."""

import numpy as np
import pytest

# ruff: noqa: E402
pytest.importorskip("pyvista")
pytest.importorskip("PySide6")
pytest.importorskip("pytestqt")

from qt_window_support import flush, open_window, shown_image
from test_app_environment import furnace_state

from explorer.app import captions
from explorer.app import environment as environment_mod
from explorer.app.environment import PASS_SAMPLES
from explorer.app.state import AppState
from explorer.qt.keys import do_key
from explorer.qt.window import REFINE_MS
from lighting.lights import SKIES, write_hdr

pytestmark = pytest.mark.slow  # the explorer window and notebook, views drawn by Qt, Matplotlib and VTK off-screen


@pytest.fixture(autouse=True, scope="module")
def _small_skies():
    """Named skies sampled into 32-row maps, not the window's 256: the same laws, a fraction of the prefiltering."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(environment_mod, "SKY_ROWS", 32)
        yield


@pytest.fixture(scope="module")
def app(tmp_path_factory):
    path = tmp_path_factory.mktemp("env") / "sky.hdr"
    sky = np.ones((16, 32, 3)) * np.linspace(0.2, 2.0, 16)[:, None, None]  # bright at the zenith
    write_hdr(path, sky)
    window = open_window((960, 600), state=AppState(environment="file", view3d="object"), environment_file=path)
    yield window
    window.close()


def test_window_shows_the_object_and_refines_it(app, qtbot):
    ov = app.model.views["object"]
    assert app.stack3d.currentWidget() is app.object_canvas and ov.coverage.any()
    assert np.array_equal(shown_image(app.object_canvas), ov.rgb8)
    assert app.controls.widget("environment").findData("file") >= 0
    app.set_control("reference", True)
    app.flush()  # the views now; the reference's timer has not ticked yet
    ref = app.model.refinement
    assert ref.samples == 0 and len(ref.tiles) > 1
    for _ in range(len(ref.tiles)):  # a pass a tick (no budget), the tile furthest behind: one round
        assert app.refine_tick(budget=0.0) == {"sphere", "object"}
    assert ref.passes == len(ref.tiles) and ref.samples == PASS_SAMPLES
    caption = app.model.refine_caption()
    assert caption.startswith(f"reference: {app.model.refinement.samples} spp, ±")
    assert app.refine_label.text() == caption and app.lobe_panel.caption.full_text().endswith(caption)
    assert app.model.views["object"].method == "reference"
    assert np.array_equal(shown_image(app.object_canvas), app.model.views["object"].rgb8)
    # The reference's timer ticks while the view rests.
    assert app._refine_timer.isActive() and app._refine_timer.interval() == REFINE_MS
    ticked = ref.passes
    qtbot.waitUntil(lambda: ref.passes > ticked, timeout=10_000)
    do_key(app, "reference")  # the reference off by its key, and on again: a new run
    app.flush()
    assert app.model.refinement is None and not app._refine_timer.isActive() and app.refine_label.text() == ""
    do_key(app, "reference")
    app.flush()
    assert app.model.refinement is not ref and app.model.refinement.samples == 0
    do_key(app, "view3d")
    flush(app)
    assert app.state.view3d == "lobe" and app.stack3d.currentWidget() is app.lobe_view
    assert app.lobe_panel.title.text() == captions.lobe_title(app.state, app.model.views["lobe"])
    app.set_control("reference", False)
    seen = [app.state.environment]
    for _ in range(len(SKIES) + 1):  # the x key goes round every choice, the file included, and back
        do_key(app, "environment+")
        seen.append(app.state.environment)
    assert seen == ["file", "none", *SKIES]
    do_key(app, "environment+")
    assert app.state.environment == "file"
    flush(app)


# ------------------------------------------------------------------ the notebook explorer
def test_notebook_shows_the_object_and_refines_on_request():
    pytest.importorskip("ipywidgets")
    from explorer.notebook import NotebookExplorer, png_of

    nb = NotebookExplorer(furnace_state(kd=0.5, form="physical"), sphere_size=48, mesh_size=48, lobe_resolution=8)
    nb.model.object_size = (48, 32)  # before the object's renderer is made: a small image, a quick test
    sv = nb.model.views["sphere"]
    assert nb.images["sphere"].value == png_of(sv.rgb8)
    albedo = nb.state.diffuse_albedo  # k_d × colour
    np.testing.assert_allclose(sv.image[sv.coverage], np.broadcast_to(albedo, (sv.coverage.sum(), 3)), rtol=2e-6)
    lobe_png = nb.images["lobe"].value
    nb.controls["view3d"].value = "object"  # as a click does
    ov = nb.model.views["object"]
    assert nb.images["lobe"].value == png_of(ov.rgb8) and "Lit object" in nb.titles["lobe"].value
    spp = nb.refine(0.3)
    assert spp >= PASS_SAMPLES and nb.model.views["object"].method == "reference"
    assert nb.images["lobe"].value == png_of(nb.model.views["object"].rgb8)
    assert f"{spp} spp" in nb.status.value
    nb.controls["environment"].value = "none"
    assert nb.model.refinement is None and nb.model.views["object"].method == "key light"
    nb.controls["view3d"].value = "lobe"
    assert nb.images["lobe"].value == lobe_png  # the same lobe picture again

"""Image-based lighting in the explorer window: the lit object shown, refined by ticks and keys (slow set; the
environment choice, the images and the reference: test_app_environment.py)."""

import numpy as np
import pytest

from explorer import app as app_mod
from explorer.app import environment as environment_mod
from explorer.app.environment import PASS_SAMPLES
from explorer.app.state import AppState
from lighting.lights import SKIES, write_hdr

pv = pytest.importorskip("pyvista")

pytestmark = pytest.mark.slow  # the explorer window, rendered off-screen by VTK


@pytest.fixture(autouse=True, scope="module")
def _small_skies():
    """Named skies sampled into 32-row maps, not the window's 256: the same laws, a fraction of the prefiltering."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(environment_mod, "SKY_ROWS", 32)
        yield


@pytest.fixture(scope="module")
def app(tmp_path_factory):
    old = pv.OFF_SCREEN
    pv.OFF_SCREEN = True
    path = tmp_path_factory.mktemp("env") / "sky.hdr"
    sky = np.ones((16, 32, 3)) * np.linspace(0.2, 2.0, 16)[:, None, None]  # bright at the zenith
    write_hdr(path, sky)
    a = app_mod.ExplorerApp(AppState(environment="file", view3d="object"), window_size=(960, 600),
                            off_screen=True, environment_file=path)  # fmt: skip
    yield a
    a.close()
    pv.OFF_SCREEN = old


def test_window_shows_the_object_and_refines_it(app):
    ov = app.model.views["object"]
    assert app._object_shown and ov.coverage.any()
    h, w = ov.coverage.shape
    texels = np.asarray(app.object_plane["pixels"]).reshape(h, w, 4)[::-1, :, :3]
    assert np.array_equal(texels, ov.rgb8)
    assert "file" in app.buttons["environment"]
    app.set_control("reference", True)
    ref = app.model.refinement
    assert ref.samples == 0 and len(ref.tiles) > 1
    for _ in range(len(ref.tiles)):  # a pass a tick (no budget), the tile furthest behind: one round
        assert app.refine_tick(budget=0.0) == {"sphere", "object"}
    assert ref.passes == len(ref.tiles) and ref.samples == PASS_SAMPLES
    caption = app.captions["object_refine"].GetInput()
    assert caption.startswith(f"reference: {app.model.refinement.samples} spp, ±")
    assert app.model.views["object"].method == "reference"

    # The interactor's timer events: the refinement timer's id runs a tick, another id (the idle timer) does not.
    class Timer:
        def __init__(self, tid):
            self.tid = tid

        def GetTimerEventId(self):  # noqa: N802 - VTK's name
            return self.tid

    app._refine_timer = 7
    app._on_timer(Timer(7))
    ticked = ref.passes
    assert ticked > len(ref.tiles) and app._refine_timer is None
    app._on_timer(Timer(3))
    assert ref.passes == ticked
    app.on_key("k")  # the reference off by its key, and on again: a new run
    assert app.model.refinement is None
    app.on_key("k")
    assert app.model.refinement is not ref and app.model.refinement.samples == 0
    app.on_key("o")
    assert app.state.view3d == "lobe" and not app._object_shown and not app.captions["object_title"].GetVisibility()
    assert app.captions["lobe_title"].GetVisibility()
    app.set_control("reference", False)
    seen = [app.state.environment]
    for _ in range(len(SKIES) + 1):  # the x key goes round every choice, the file included, and back
        app.on_key("x")
        seen.append(app.state.environment)
    assert seen == ["file", "none", *SKIES]
    app.on_key("x")
    assert app.state.environment == "file"

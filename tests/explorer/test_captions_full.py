"""The explorer's captions under a sky: the automatic exposure said (slow set; fast: test_captions.py)."""

import pytest
from test_captions import _model

from explorer.app import captions
from explorer.app.state import AppState

pytestmark = pytest.mark.slow  # the daylight sky sampled into the window's 256-row map and prefiltered


# ------------------------------------------------------------------ the lit sphere
def test_sphere_caption_under_a_sky_says_the_automatic_exposure():
    state = AppState(environment="daylight")
    model = _model(state)
    sv = model.views["sphere"]
    assert captions.exposure_note(state, sv) == f"exposure 0 stops (automatic: {sv.auto_exposure:+.1f})".replace(
        "-", "−")
    model.apply_auto_exposure()
    sv = model.views["sphere"]
    assert sv.auto_exposure == -1.6
    text = captions.sphere_caption(state, sv)
    assert text.endswith("\nexposure −1.6 stops (automatic)")
    assert "directional, elevation 45°, azimuth 135° · environment daylight" in text

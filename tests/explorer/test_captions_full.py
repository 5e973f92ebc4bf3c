"""The explorer's captions under a sky: the automatic exposure said; the scan line's, the coarse sphere's and the lit
object's (slow set; fast: test_captions.py)."""

import pytest
from test_captions import _model

from explorer.app import captions
from explorer.app.state import AppState

pytestmark = pytest.mark.slow  # the daylight and band-limited skies sampled into the window's maps and prefiltered


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


# ------------------------------------------------------------------ scan line, coarse sphere, object
def test_profile_coarse_and_object_captions():
    state = AppState(view3d="object")
    model = _model(state)
    m = model.views
    pv, cv, ov = m["profile"], m["coarse"], m["object"]
    assert captions.profile_title(state) == "Scan line: intensity (luminance Y)"
    assert captions.profile_caption(pv) == (f"Mach-band metric (slope kinks): Gouraud {pv.metric_gouraud:.2f}, "
                                            f"Phong {pv.metric_phong:.2f}")  # fmt: skip
    assert captions.coarse_caption(cv).startswith(f"{len(cv.faces)} triangles, {len(cv.vertices)} vertices")
    assert (captions.coarse_title(state), captions.phong_title(state)) == (
        "Gouraud: lit at the vertices", "Phong interpolation: lit per pixel")
    assert captions.phong_caption(state).endswith("red line: the scan line")
    assert captions.lobe_title(state, m["lobe"]) == "3D lobe: f_r (1/sr)  [luminance Y]"
    assert captions.object_caption(state, ov) == "no environment (key + ambient light) · key light"
    state.environment = "band-limited"
    model.update()
    assert captions.object_caption(state, model.views["object"]) == "sky band-limited · dominant lights"
    assert captions.object_title(state, model.views["object"]).endswith(f"{ov.triangles} triangles, Phong normals")

"""Environment lights in scene files: values (the white furnace in both forms, the background), the shipped sky
file against the sky it was made from, one-line errors, the budget before reading, saving and -D overrides."""

from __future__ import annotations

import math
import os
import shutil

import numpy as np
import pytest

from lighting._budget import set_memory_budget
from lighting.lights import envfiles
from lighting.lights.environment import LatLongEnvironment
from lighting.lights.skies import sky
from lighting.scene import SceneRenderer, parse_scene, scene_to_toml
from lighting.scene.budget import (
    DOMINANT_BYTES,
    DOMINANT_BYTES_PER_PIXEL,
    ENVIRONMENT_BYTES_PER_PIXEL,
    PREFILTER_BYTES_PER_PIXEL,
    scene_estimate,
)
from lighting.scene.envlights import declared_image_size
from lighting.scene.errors import SceneBudgetError, SceneError
from lighting.scene.examples import EXAMPLES_DIR
from lighting.scene.schema import MAX_ENVIRONMENT_VALUE

SKY_FILE = os.path.join(EXAMPLES_DIR, "daylight_sky.hdr")

FURNACE = """
[camera]
eye = [0.0, -5.0, 0.0]
up = [0.0, 0.0, 1.0]

[image]
width = 40
height = 32

[render]
form = "{form}"

[[objects]]
type = "sphere"
material = {{parts = [{{model = "lambert", kd = 0.5}}]}}

[[objects]]
type = "icosphere"
level = 2
mode = "{mode}"
translate = [1.4, 0.0, 0.0]
scale = 0.5
material = {{parts = [{{model = "lambert", kd = 0.5}}]}}

[[lights]]
type = "environment"
radiance = 1
{extra}"""


def render(scene, plan=True):
    sr = SceneRenderer(scene, plan=plan)
    image, _ = sr.render()
    return np.asarray(image), sr.visibility()


# ------------------------------------------------------------------ values
@pytest.mark.parametrize("form, scale", [("physical", 1.0), ("classic", math.pi)])
@pytest.mark.parametrize("mode", ["phong", "gouraud", "flat"])
@pytest.mark.parametrize("plan", [True, False, "full"])
def test_white_furnace_lambert_half_everywhere_and_the_sky_behind(form, scale, mode, plan):
    # A uniform sky of radiance 1 gives L_o = k_d = 0.5 at every normal and view (physical form), π·0.5 in the
    # classic form; the background is the sky itself, 1 (π in the classic form).
    scene = parse_scene(FURNACE.format(form=form, mode=mode, extra=""))
    image, owner = render(scene, plan)
    assert (owner == 0).sum() > 300 and (owner == 1).sum() > 50 and (owner < 0).sum() > 300
    np.testing.assert_allclose(image[owner >= 0], 0.5 * scale, rtol=1e-13)
    np.testing.assert_allclose(image[owner < 0], scale, rtol=1e-15)


def test_white_furnace_in_float32():
    scene = parse_scene(FURNACE.format(form="physical", mode="phong", extra=""))
    sr = SceneRenderer(scene, dtype=np.float32)
    image, _ = sr.render()
    assert image.dtype == np.float32
    np.testing.assert_allclose(np.asarray(image)[sr.visibility() >= 0], 0.5, rtol=1e-6)


def test_white_furnace_monte_carlo_is_unbiased_and_reproducible():
    # The reference integrator: each pixel an estimate of 0.5; the mean over ~550 pixels within 5 standard errors.
    text = FURNACE.format(form="physical", mode="phong", extra='method = "monte-carlo"\nsamples = 16\nseed = 3\n')
    image, owner = render(parse_scene(text))
    values = image[owner >= 0][:, 0]
    assert abs(values.mean() - 0.5) < 5 * values.std() / math.sqrt(len(values))
    assert 0.0 < values.std() < 0.2
    np.testing.assert_array_equal(render(parse_scene(text))[0], image)  # seeded: the same image again


@pytest.mark.parametrize("method", ["dominant", "split-sum", "monte-carlo"])
def test_white_furnace_at_the_bound_of_radiance_and_intensity(method):
    # Both at MAX_ENVIRONMENT_VALUE: L_o = 0.5 x 1e30 x 1e30 on the spheres, the sky 1e60 behind them, and no
    # overflow on the way (a warning is an error here).
    extra = f'intensity = {MAX_ENVIRONMENT_VALUE!r}\nmethod = "{method}"\n'
    text = FURNACE.format(form="physical", mode="phong", extra=extra).replace("radiance = 1", "radiance = 1e30")
    image, owner = render(parse_scene(text))
    np.testing.assert_allclose(image[owner < 0], 1e60, rtol=1e-15)
    values = image[owner >= 0][:, 0]
    if method == "monte-carlo":  # 64 samples a pixel: the mean within 5 standard errors
        assert abs(values.mean() - 0.5e60) < 5 * values.std() / math.sqrt(len(values))
    else:  # the dominant-light method holds the sky in float32, where 1e30 is 1.5e-8 off
        np.testing.assert_allclose(values, 0.5e60, rtol=1e-13 if method == "split-sum" else 2e-8)


def test_intensity_scales_and_background_false_shows_the_image_background():
    text = FURNACE.format(form="physical", mode="phong", extra="intensity = [1.0, 0.5, 0.25]\nbackground = false\n")
    image, owner = render(parse_scene(text.replace("height = 32", "height = 32\nbackground = 0.1")))
    np.testing.assert_allclose(image[owner >= 0], np.broadcast_to([0.5, 0.25, 0.125], image[owner >= 0].shape),
                               rtol=1e-13)  # fmt: skip
    np.testing.assert_allclose(image[owner < 0], 0.1, rtol=1e-15)


# ------------------------------------------------------------------ the shipped sky file
def test_shipped_sky_file_is_the_daylight_sky_within_rgbe_precision():
    img = envfiles.read_environment_image(SKY_FILE)
    assert img.shape == (64, 128, 3)
    made_from = sky("daylight").radiance(LatLongEnvironment.pixel_directions(64, 128))
    # RGBE keeps 8 mantissa bits against the pixel's brightest channel; the reader centres the step: half a
    # step, 2^-8 of the brightest channel at most.
    err = np.abs(img - made_from).max(axis=-1) / made_from.max(axis=-1)
    assert err.max() <= 2.0**-8
    assert err.mean() > 1e-4  # it is the file that was read, not the formula
    assert os.path.getsize(SKY_FILE) < 64 * 128 * 4 // 3  # run-length encoded: under a third of flat RGBE


def test_environment_example_explains_its_environment(capsys):
    from explorer.commands import render as render_cmd

    assert render_cmd.main(["environment", "--explain", "--size", "56x32"]) == 0
    text = capsys.readouterr().out
    assert ("environment light 'daylight_sky.hdr', a 128x64 image: dominant lights and filtered importance sampling "
            "per pixel") in text
    assert "prefiltered at 128x64 for 8 lobe widths" in text
    # Its own 64 rows prefiltered, and the dominant lights (the example's method): their tables and residual.
    mib = (128 * 64 * (PREFILTER_BYTES_PER_PIXEL + DOMINANT_BYTES_PER_PIXEL) + DOMINANT_BYTES) / 2**20
    assert f"environment lights[0]: prefiltering 128x64 needs about {mib:.1f} MiB at its peak" in text
    assert "left out: the light loop — no punctual or area light" in text


# ------------------------------------------------------------------ errors: one line each
BAD = [
    ('source = "studo"', "lights[0].source", "did you mean 'studio'?"),
    ('source = "missing.hdr"', "lights[0].source", "does not exist"),
    ('source = "."', "lights[0].source", "is not a sky name"),
    ('source = "sky.png"', "lights[0].source", "allowed: an environment image file (.hdr, .pic, .pfm, .npy, .exr)"),
    ('source = ""', "lights[0].source", "or a sky name (uniform, daylight"),
    ('source = 3', "lights[0].source", "must be a string"),
    ('source = "studio"\nradiance = 1', "lights[0]", "either source = FILE or SKY, or radiance = VALUE, not both"),
    ("radiance = -1", "lights[0].radiance", "every entry >= 0"),
    ("radiance = [1, 2]", "lights[0].radiance", "must be a colour"),
    ("intensity = -2", "lights[0].intensity", "every entry >= 0"),
    # The bound of the field specification (MAX_ENVIRONMENT_VALUE): float32 radiance and the prefilter's sums.
    ("radiance = 1e308", "lights[0].radiance", "must be a colour: a number or [r, g, b], finite and <= 1e+30; "
                                               "got 1e+308"),  # fmt: skip
    ("radiance = [1, 1.0000000000000002e30, 1]", "lights[0].radiance[1]",
     "must be a finite number <= 1e+30; got 1.0000000000000002e+30"),  # the next float above
    ("intensity = 1e308", "lights[0].intensity", "must be a colour: a number or [r, g, b], finite and <= 1e+30; "
                                                 "got 1e+308"),  # fmt: skip
    ("intensity = [1e31, 1, 1]", "lights[0].intensity[0]", "must be a finite number <= 1e+30; got 1e+31"),
    ('rotation = "a"', "lights[0].rotation", "must be a finite number"),
    ("rotation = inf", "lights[0].rotation", "nan and inf are not allowed"),
    ("background = 1", "lights[0].background", "must be true or false"),
    ('method = "mc"', "lights[0].method", "must be one of 'dominant', 'split-sum', 'monte-carlo'"),
    ("samples = 64", "lights[0].samples", "applies to method = 'monte-carlo' only"),
    ("seed = 1", "lights[0].seed", "applies to method = 'monte-carlo' only"),
    ('method = "monte-carlo"\nsamples = 1', "lights[0].samples", "an integer in [2, 65536]"),
    ('method = "monte-carlo"\nseed = -1', "lights[0].seed", "an integer >= 0"),
    ('sorce = "studio"', "lights[0].sorce", "did you mean 'source'?"),
    ('[[lights]]\ntype = "environment"', "lights[1].type", "at most one environment light (lights[0] is one)"),
    ('[[lights]]\ntype = "opengl"', "lights[0].type", "the OpenGL fixed-function equation has no environment light"),
]


@pytest.mark.parametrize("extra, key, phrase", BAD, ids=[b[0] for b in BAD])
def test_every_bad_value_is_one_line_naming_file_and_key(tmp_path, extra, key, phrase):
    text = FURNACE.format(form="physical", mode="phong", extra="").replace("radiance = 1\n", "")
    with pytest.raises(SceneError) as e:
        parse_scene(text + extra + "\n", source="s.toml", base_dir=tmp_path)
    msg = str(e.value)
    assert "\n" not in msg
    assert msg.startswith(f"s.toml: {key}: "), msg
    assert phrase in msg, msg


def test_radiance_and_intensity_at_their_bound_are_accepted():
    text = FURNACE.format(form="physical", mode="phong", extra="").replace("radiance = 1\n", "")
    light = parse_scene(text + "radiance = [1e30, 0.5, 0]\nintensity = 1e30\n").lights[0]
    assert light.is_environment and light.to_dict()["intensity"] == 1e30


def test_a_folder_or_a_malformed_file_is_named_by_its_key(tmp_path):
    (tmp_path / "dir.hdr").mkdir()
    (tmp_path / "bad.hdr").write_bytes(b"not a radiance file")
    base = FURNACE.format(form="physical", mode="phong", extra="")
    for name, phrase in (("dir.hdr", "is not a regular file"), ("bad.hdr", "not a Radiance file")):
        with pytest.raises(SceneError) as e:
            parse_scene(base.replace("radiance = 1", f'source = "{name}"'), source="s.toml", base_dir=tmp_path)
        assert str(e.value).startswith("s.toml: lights[0].source: ") and phrase in str(e.value)
        assert "\n" not in str(e.value)


# ------------------------------------------------------------------ the budget, before reading
def _header_only(path, h, w):
    path.write_bytes(f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n".encode())


def test_a_too_large_declared_image_is_refused_before_reading(tmp_path, monkeypatch):
    _header_only(tmp_path / "huge.hdr", 8192, 16384)  # a 50-byte file declaring 134 million pixels

    def never(*args, **kwargs):
        raise AssertionError("the pixels were read")

    monkeypatch.setattr(envfiles, "read_environment_image", never)
    text = FURNACE.format(form="physical", mode="phong", extra="").replace("radiance = 1", 'source = "huge.hdr"')
    with pytest.raises(SceneBudgetError) as e:
        parse_scene(text, source="s.toml", base_dir=tmp_path)
    msg = str(e.value)
    assert msg.startswith("s.toml: lights[0].source: ") and "reading a 16384x8192 environment image" in msg
    gib = 8192 * 16384 * ENVIRONMENT_BYTES_PER_PIXEL / 2**30
    assert f"{gib:.1f} GiB" in msg


def test_the_budget_counts_a_small_image_and_a_lowered_budget_refuses_it(tmp_path):
    shutil.copy(SKY_FILE, tmp_path / "sky.hdr")
    text = FURNACE.format(form="physical", mode="phong", extra="").replace("radiance = 1", 'source = "sky.hdr"')
    scene = parse_scene(text, base_dir=tmp_path)
    parts = dict((k, b) for k, b, _ in scene_estimate(scene)["parts"])
    # The file's own height, 64 rows, prefiltered; the dominant lights (the default method) add their part.
    assert parts["lights[0]"] == 64 * 128 * (PREFILTER_BYTES_PER_PIXEL + DOMINANT_BYTES_PER_PIXEL) + DOMINANT_BYTES
    previous = set_memory_budget(64 * 128 * ENVIRONMENT_BYTES_PER_PIXEL - 1)
    try:
        with pytest.raises(SceneBudgetError, match=r"lights\[0\]\.source: .*reading a 128x64 environment image"):
            parse_scene(text, source="s.toml", base_dir=tmp_path)
    finally:
        set_memory_budget(previous)


def test_declared_sizes_match_what_the_readers_read(tmp_path):
    img = np.random.default_rng(0).random((4, 8, 3)).astype(np.float32)
    envfiles.write_hdr(tmp_path / "a.hdr", img)
    np.save(tmp_path / "a.npy", img)
    with open(tmp_path / "a.pfm", "wb") as f:
        f.write(b"PF\n8 4\n-1.0\n" + img[::-1].astype("<f4").tobytes())
    for name in ("a.hdr", "a.npy", "a.pfm"):
        p = str(tmp_path / name)
        assert declared_image_size(p) == envfiles.read_environment_image(p).shape[:2] == (4, 8)
    (tmp_path / "junk.hdr").write_bytes(b"#?RADIANCE\nno end")
    assert declared_image_size(str(tmp_path / "junk.hdr")) is None  # the reader names the problem


def test_monte_carlo_samples_count_as_work():
    text = FURNACE.format(form="physical", mode="phong", extra='method = "monte-carlo"\nsamples = 1000\n')
    est = scene_estimate(parse_scene(text))
    assert est["evaluations"] == 40 * 32 * 1000 + 0  # per-pixel objects: samples × pixels
    assert est["work_key"] == "lights[0].samples"


# ------------------------------------------------------------------ saving, overrides


def test_a_light_made_in_python_saves_itself():
    from lighting.lights.envlight import EnvironmentLight

    scene = parse_scene(FURNACE.format(form="physical", mode="phong", extra=""))
    moved = scene.with_lights([EnvironmentLight("glow", rotation=45.0, method="monte-carlo", samples=4)])
    d = moved.to_dict()["lights"][0]
    assert d == {"type": "environment", "source": "glow", "rotation": 45.0, "method": "monte-carlo", "samples": 4,
                 "seed": 0}  # fmt: skip
    np.testing.assert_array_equal(render(parse_scene(scene_to_toml(moved)))[0], render(moved)[0])


def test_a_2048_by_1024_panorama_fits_the_default_budget_under_either_method():
    # The usual size of a downloaded HDR panorama: prefiltered at its 1024 rows, the levels from 256 rows down.
    from lighting._budget import DEFAULT_MEMORY_BUDGET, environment_setup_bytes
    from lighting.lights.envlight import EnvironmentLight
    from lighting.scene.budget import PREFILTER_LARGE_BYTES_PER_PIXEL, PREFILTER_LEVEL_PIXELS

    pano = LatLongEnvironment(np.ones((1024, 2048, 3)))
    pixels = 1024 * 2048
    prefilter = PREFILTER_BYTES_PER_PIXEL * PREFILTER_LEVEL_PIXELS
    prefilter += PREFILTER_LARGE_BYTES_PER_PIXEL * (pixels - PREFILTER_LEVEL_PIXELS)
    split = EnvironmentLight(pano, method="split-sum")
    default = EnvironmentLight(pano)
    assert default.method == "dominant"
    assert environment_setup_bytes(split) == prefilter
    assert environment_setup_bytes(default) == prefilter + DOMINANT_BYTES + DOMINANT_BYTES_PER_PIXEL * pixels
    assert environment_setup_bytes(split) < environment_setup_bytes(default) < DEFAULT_MEMORY_BUDGET

"""LinearImage: the renderers' image type, linear RGB that shows itself sRGB-encoded (PNG checked with PIL)."""

from __future__ import annotations

import io
import math
import pickle

import numpy as np
import pytest

from lighting import DirectionalLight, Lambert, Material, Phong
from lighting.render import AnalyticSphere, LinearImage, Renderer, render_sphere, sphere_camera

PIL = pytest.importorskip("PIL.Image")


def srgb_code(x: float) -> int:
    """The IEC 61966-2-1 sRGB encoding of a linear value in [0, 1], rounded to 8 bits (closed form)."""
    x = min(max(x, 0.0), 1.0)
    y = 12.92 * x if x <= 0.0031308 else 1.055 * x ** (1 / 2.4) - 0.055
    return int(math.floor(255 * y + 0.5))


def decode(png: bytes) -> np.ndarray:
    with PIL.open(io.BytesIO(png)) as im:
        assert im.format == "PNG" and im.mode == "RGB"
        return np.asarray(im.convert("RGB"))


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_png_decodes_to_the_closed_form_srgb_codes(dtype):
    # Every 8-bit code's midpoint neighbourhood: 0, the linear segment, the power segment, 1 and above.
    values = np.array([0.0, 0.001, 0.0031308, 0.004, 0.01, 0.05, 0.1, 0.2140, 0.5, 0.75, 0.9, 1.0, 1.5, 40.0])
    img = np.zeros((3, len(values), 3), dtype=dtype)
    img[0, :, 0] = values  # red row
    img[1, :, 1] = values[::-1]  # green row, reversed
    img[2, :, :] = values[:, None]  # grey row
    li = LinearImage(img)
    pixels = decode(li._repr_png_())
    assert pixels.shape == (3, len(values), 3)
    expected = [srgb_code(float(dtype(v))) for v in values]
    assert pixels[0, :, 0].tolist() == expected and not pixels[0, :, 1:].any()
    assert pixels[1, :, 1].tolist() == expected[::-1]
    assert (pixels[2] == np.array(expected)[:, None]).all()
    assert np.array_equal(pixels, li.srgb8())


def test_a_large_image_is_encoded_band_by_band_in_a_fraction_of_its_size():
    # Each value is encoded alone, so the bands give the closed-form codes and report of the whole (the clipped
    # pixels and the brightest value), with temporaries far below the float64 image (several times it, whole).
    import tracemalloc

    from lighting.render.image import encode_srgb8

    values = np.array([0.0, 0.001, 0.004, 0.2140, 0.5, 0.9, 1.0, 1.5, 40.0])
    img = np.resize(values, (1000, 2000, 3)).astype(np.float32)  # 24 MB; 48 MB in float64
    img[999, 1999, 2] = 41.0
    tracemalloc.start()
    try:
        rgb8, report = encode_srgb8(img)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < img.size * 8 / 2, peak  # rgb8 itself is 6 MB
    v32 = values.astype(np.float32)
    expected = np.select([img == v for v in v32], [srgb_code(float(v)) for v in v32], 255).astype(np.uint8)
    assert np.array_equal(rgb8, expected)
    assert report.max_value == 41.0 and report.total_pixels == 2_000_000
    assert report.clipped_pixels == int(np.count_nonzero((img > 1).any(axis=-1)))


def test_linear_half_is_188_not_128():
    li = LinearImage(np.full((4, 5, 3), 0.5))
    assert srgb_code(0.5) == 188
    assert (decode(li.png()) == 188).all()
    assert (li.srgb8() == 188).all() and li.srgb8().shape == (4, 5, 3)


def test_exposure_and_tonemap():
    li = LinearImage(np.full((2, 2, 3), 0.25))
    # One stop doubles the values: 0.25 shown at exposure 1 is 0.5.
    assert (decode(li.with_exposure(1)._repr_png_()) == 188).all()
    assert (li.srgb8(exposure=-2) == srgb_code(0.0625)).all()
    # Reinhard: x / (1 + x); 1.0 → 0.5.
    one = LinearImage(np.ones((1, 1, 3)), tonemap="reinhard")
    assert one.srgb8().tolist() == [[[188, 188, 188]]]
    # The display settings change nothing in the values (a view: same memory).
    bright = li.with_exposure(3)
    assert np.shares_memory(bright, li) and float(bright[0, 0, 0]) == 0.25 and li.exposure == 0.0
    with pytest.raises(ValueError, match="exposure"):
        li.with_exposure(float("nan"))
    with pytest.raises(ValueError, match="tonemap"):
        LinearImage(np.zeros((1, 1, 3)), tonemap="filmic")


def test_plain_array_and_arithmetic():
    raw = np.linspace(0.0, 1.0, 2 * 3 * 3).reshape(2, 3, 3)
    li = LinearImage(raw, exposure=1.5)
    plain = np.asarray(li)
    assert type(plain) is np.ndarray and np.shares_memory(plain, raw) and np.array_equal(plain, raw)
    doubled = 2 * li
    assert isinstance(doubled, LinearImage) and doubled.exposure == 1.5
    assert np.array_equal(np.asarray(doubled), 2 * raw)
    # What is no longer an RGB picture is a plain array or scalar.
    assert type(li.max()) is np.float64 and float(li.max()) == 1.0
    assert type(li > 0.5) is np.ndarray and type(li[..., 0]) is np.ndarray and type(li.mean(axis=-1)) is np.ndarray
    assert isinstance(li[:1, :2], LinearImage) and li[:1, :2].exposure == 1.5
    back = pickle.loads(pickle.dumps(li))
    assert isinstance(back, LinearImage) and back.exposure == 1.5 and np.array_equal(back, raw)
    assert repr(li) == "LinearImage(3x2 linear RGB, float64, max 1, exposure 1.5)"


def test_not_a_picture_has_no_png():
    bad = LinearImage(np.full((1, 2, 3), 0.5))
    bad[0, 0, 0] = np.nan
    assert bad._repr_png_() is None
    with pytest.raises(ValueError, match=r"shape \(H, W, 3\)"):
        LinearImage(np.zeros((4, 4)))


def test_renderers_return_linear_images(tmp_path):
    material, lights = Material(Lambert(0.8)), [DirectionalLight((0.0, 0.0, 1.0))]
    img = render_sphere(material, lights, size=32)
    assert isinstance(img, LinearImage) and img.shape == (32, 32, 3) and img.dtype == np.float64
    # The centre pixel faces the light head on: classic k_d (n·l) = 0.8 + ambient 0.8 * 0 (no ambient light).
    assert float(img[16, 16, 0]) == pytest.approx(0.8, abs=0.01)
    r = Renderer(AnalyticSphere(), sphere_camera(16), dtype=np.float32)
    img32 = r.render(Material(Phong(0.5, 20)), lights)
    assert isinstance(img32, LinearImage) and img32.dtype == np.float32
    img.save(tmp_path / "sphere.png")
    assert np.array_equal(decode((tmp_path / "sphere.png").read_bytes()), img.srgb8())


def test_render_scene_image_carries_the_scene_exposure():
    from dataclasses import replace

    from lighting.scene import SceneRenderer, example_path, load_scene, render_scene

    scene = load_scene(example_path("lambert_angles"))
    scene = replace(scene, image=replace(scene.image, exposure=1.5, tonemap="reinhard"))
    image, info = render_scene(scene)
    assert isinstance(image, LinearImage)
    assert (image.exposure, image.tonemap) == (1.5, "reinhard")
    # Two paths to the same pixels: the scene renderer's encoding and the image's own.
    assert np.array_equal(SceneRenderer(scene).encode(image)[0], image.srgb8())
    assert decode(image._repr_png_()).shape == (info["height"], info["width"], 3)

"""Analysis results show themselves in a notebook: ``_repr_png_`` gives a PNG of the stated size.

A half-difference image is its own pixels (the engine's sRGB encoding and PNG writer, NumPy only); curves, slices,
lobes, albedo curves and scan lines are 400 × 300 plots drawn by Matplotlib, imported only for the picture.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from lighting import Lambert, Phong
from lighting.analysis import half_diff_image, lobe_mesh, polar_slice, theta_h_curve, theta_v_curve
from lighting.analysis.machband import scanline_profile
from lighting.integrate import albedo_curve
from lighting.models.blinn_phong import BlinnPhong
from lighting.render.image import read_png
from lighting.render.linear_image import LinearImage

SIGNATURE = b"\x89PNG\r\n\x1a\n"
ROOT = Path(__file__).resolve().parents[2]


def decode(data: bytes, tmp_path) -> np.ndarray:
    """The engine's own PNG reader, on the bytes written to a file."""
    path = tmp_path / "shown.png"
    path.write_bytes(data)
    return read_png(path)


def srgb8(linear: float) -> int:
    """The sRGB code of a linear value in [0, 1] (IEC 61966-2-1), written out here."""
    s = 12.92 * linear if linear <= 0.0031308 else 1.055 * linear ** (1 / 2.4) - 0.055
    return int(np.floor(255 * s + 0.5))


def test_half_diff_image_is_its_own_pixels(tmp_path):
    # Lambert with kd = (0.8, 0.4, 0.2): every valid sample is kd/π, so the brightest channel shows white and the
    # others keep their ratios (0.5 → 188, 0.25 → 137); at φ_d = 0 only θ_h + θ_d < 90° has a value.
    im = half_diff_image(Lambert((0.8, 0.4, 0.2)), phi_d=0.0)
    pixels = im.srgb8()
    assert pixels.shape == (91, 91, 3) and pixels.dtype == np.uint8
    colour = [srgb8(1.0), srgb8(0.5), srgb8(0.25)]
    assert colour == [255, 188, 137]
    # θ_d grows upward: the bottom row is θ_d = 0 (valid up to θ_h < 90°), the top row θ_d = 90° (no value).
    assert pixels[-1, 0].tolist() == colour and pixels[-1, -1].tolist() == [72, 88, 120]
    assert (pixels[0] == [72, 88, 120]).all()
    td, th = np.meshgrid(np.arange(91), np.arange(91), indexing="ij")
    has_value = (td + th < 90)[::-1]
    assert (pixels[has_value] == colour).all() and (pixels[~has_value] == [72, 88, 120]).all()

    data = im._repr_png_()
    assert data[:8] == SIGNATURE
    shown = decode(data, tmp_path)
    assert shown.shape == (273, 273, 3)  # 91 samples a side, each a 3 × 3 block: the longer side reaches 256
    assert np.array_equal(shown, np.repeat(np.repeat(pixels, 3, axis=0), 3, axis=1))


def test_half_diff_image_shows_its_99th_percentile_white(tmp_path):
    # One channel, a graded image: white is the 99th percentile of the valid values, brighter values clip.
    im = half_diff_image(BlinnPhong(1.0, 40, normalized=True), n_h=300, n_d=40, channel=0)
    values = np.asarray(im.values, dtype=np.float64)
    white = np.percentile(values[im.valid], 99)
    expect = np.array(
        [
            [srgb8(min(x / white, 1.0)) if ok else -1 for x, ok in zip(row, vr, strict=True)]
            for row, vr in zip(values, im.valid, strict=True)
        ]
    )[::-1]
    pixels = im.srgb8()
    has_value = expect >= 0
    assert has_value.sum() == 39 * 299 and np.array_equal(pixels[..., 0][has_value], expect[has_value])
    grey = pixels[has_value]
    assert (grey[:, 0] == grey[:, 1]).all() and (grey[:, 1] == grey[:, 2]).all()
    assert (pixels[~has_value] == [72, 88, 120]).all()
    assert (pixels[..., 0] == 255).sum() >= 0.01 * has_value.sum()  # the brightest percent shows white
    shown = decode(im._repr_png_(), tmp_path)
    assert shown.shape == (40, 300, 3) and np.array_equal(shown, pixels)  # 300 columns: no enlargement


def test_rendered_image_is_its_own_pixels(tmp_path):
    img = LinearImage(np.linspace(0.0, 1.0, 24).reshape(2, 4, 3))
    shown = decode(img._repr_png_(), tmp_path)
    assert shown.shape == (2, 4, 3)
    assert shown.reshape(-1).tolist() == [srgb8(x) for x in np.linspace(0.0, 1.0, 24)]


def plots():
    m = Lambert((0.6, 0.3, 0.1)) + BlinnPhong(0.4, 60, normalized=True)
    img = np.zeros((3, 60, 3))
    img[1] = 0.8 * np.abs(np.linspace(-1, 1, 60))[:, None] ** 1.5
    return {
        "theta_h curve": lambda: theta_h_curve(m, n=91),
        "theta_v curve": lambda: theta_v_curve(Phong(0.5, 20), 0.5, n=91),
        "polar slice": lambda: polar_slice(Phong(0.5, 20), 0.5, n=91),
        "lobe mesh": lambda: lobe_mesh(Phong(0.5, 20), (0.6, 0.0, 0.8), resolution=12),
        "albedo curve": lambda: albedo_curve(Phong(0.5, 1.0), np.linspace(0, 1.5, 16), samples=256),
        "scan line": lambda: scanline_profile(img, 1),
    }


@pytest.mark.parametrize("name", list(plots()))
def test_plots_are_400_by_300(name):
    image = pytest.importorskip("matplotlib.image")
    import io

    data = plots()[name]()._repr_png_()
    assert data[:8] == SIGNATURE
    rgba = image.imread(io.BytesIO(data), format="png")
    assert rgba.shape[:2] == (300, 400)
    # Something is drawn: more than the white page and a few lines of text.
    dark = (rgba[..., :3].mean(axis=-1) < 0.5).sum()
    assert dark > 500, dark


def test_without_matplotlib_plots_give_none_and_images_still_show(monkeypatch):
    for key in [k for k in sys.modules if k == "matplotlib" or k.startswith(("matplotlib.", "mpl_toolkits"))]:
        monkeypatch.setitem(sys.modules, key, None)
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    for make in plots().values():
        assert make()._repr_png_() is None
    assert half_diff_image(Lambert(0.5), n_h=8, n_d=8)._repr_png_()[:8] == SIGNATURE


def test_results_print_without_importing_matplotlib():
    code = (
        "import sys, numpy as np, lighting\n"
        "from lighting.analysis import half_diff_image, lobe_mesh, polar_slice, theta_h_curve\n"
        "from lighting.integrate import albedo_curve\n"
        "p = lighting.Phong(0.5, 20)\n"
        "for r in (theta_h_curve(p, n=9), polar_slice(p, 0.5, n=9), half_diff_image(p, n_h=8, n_d=8),\n"
        "          lobe_mesh(p, (0.6, 0.0, 0.8), resolution=4), albedo_curve(p, [0.0, 1.0], samples=64)):\n"
        "    assert len(repr(r)) <= 300, repr(r)\n"
        "assert half_diff_image(p, n_h=8, n_d=8)._repr_png_()[:4] == b'\\x89PNG'\n"
        "assert 'matplotlib' not in sys.modules, sorted(k for k in sys.modules if 'matplotlib' in k)\n"
    )
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr

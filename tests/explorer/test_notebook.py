"""The notebook explorer (ipywidgets on ExplorerModel) and the desktop window's quiet construction in Jupyter."""

from __future__ import annotations

import io

import numpy as np
import pytest

pytest.importorskip("ipywidgets")
pytest.importorskip("matplotlib")
PIL = pytest.importorskip("PIL.Image")

from explorer.app.captions import albedo_caption  # noqa: E402
from explorer.app.params import offered_parameters  # noqa: E402
from explorer.app.state import AppState  # noqa: E402
from explorer.app.views import ExplorerModel  # noqa: E402
from explorer.notebook import SCANLINE_RGB, NotebookExplorer, png_of  # noqa: E402
from lighting.render import encode_srgb8  # noqa: E402

SIZES = {"sphere_size": 48, "mesh_size": 48, "lobe_resolution": 8}
PHONG_FILE = (
    "::begin parameters\ncolor ks 0.5 0.4 0.3\nfloat n 0 1000 20\n::end parameters\n::begin shader\n"
    "const float PI = 3.14159265358979323846;\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)\n"
    "{\n vec3 R = reflect(-L, N);\n return ks * pow(max(dot(R, V), 0.0), n) / (PI * dot(N, L));\n}\n::end shader\n"
)


def decode(png: bytes) -> np.ndarray:
    with PIL.open(io.BytesIO(png)) as im:
        return np.asarray(im.convert("RGB"))


@pytest.fixture
def ex():
    return NotebookExplorer(AppState(model="phong", shininess=20.0, elevation=60.0), **SIZES)


def test_images_are_the_engine_views(ex):
    m = ex.model.views
    sphere = decode(ex.images["sphere"].value)
    assert sphere.shape == (48, 48, 3)
    # The PNG holds the view's 8-bit codes, which are the engine's sRGB encoding of its linear image.
    assert np.array_equal(sphere, m["sphere"].rgb8)
    assert np.array_equal(sphere, encode_srgb8(m["sphere"].image, exposure=ex.state.exposure)[0])
    row = m["profile"].row
    for name, codes in (("gouraud", m["coarse"].gouraud_rgb8), ("phong", m["coarse"].phong_rgb8)):
        img = decode(ex.images[name].value)
        assert (img[row] == SCANLINE_RGB).all()  # the scan line the profile reads
        others = np.arange(48) != row
        assert np.array_equal(img[others], codes[others])
    assert ex.albedo.value.endswith(albedo_caption(m["albedo"]))
    for name in ("profile", "lobe", "polar", "angles"):
        assert decode(ex.images[name].value).shape[2] == 3 and ex.titles[name].value.startswith("<b>")


def test_updates_only_the_stale_views(ex):
    twin = ExplorerModel(AppState(model="phong", shininess=20.0, elevation=60.0), **SIZES)
    twin.update()
    plots = {k: ex.images[k].value for k in ("lobe", "polar", "angles", "profile", "sphere")}
    # Turning the light about the view axis: the images and the profile follow, the BRDF plots stay.
    ex.controls["azimuth"].value = 10.0
    twin.state.azimuth = 10.0
    views, seconds = ex.timings[-1]
    assert views == twin.update() == {"sphere", "coarse", "profile"} and seconds > 0
    assert all(ex.images[k].value is plots[k] for k in ("lobe", "polar", "angles"))
    assert ex.images["sphere"].value != plots["sphere"] and ex.images["profile"].value is not plots["profile"]
    assert np.array_equal(decode(ex.images["sphere"].value), twin.views["sphere"].rgb8)
    # A new incident angle: what depends on it follows (the same set as the model computes).
    ex.controls["elevation"].value = 30.0
    twin.state.elevation = 30.0
    assert ex.timings[-1][0] == twin.update()
    assert ex.images["polar"].value is not plots["polar"]
    # Shading mode: the lit sphere alone.
    ex.controls["mode"].value = "gouraud"
    assert ex.timings[-1][0] == {"sphere"} and ex.state.mode == "gouraud"


def test_model_dropdown_builds_the_parameter_table(ex):
    ex.controls["model"].value = "cook-torrance"
    names = sorted(k.split(":")[1] for k in ex.controls if k.startswith("param:") and k.count(":") == 1)
    assert names == sorted(p.name for p in offered_parameters("cook-torrance"))
    ex.controls["param:roughness"].value = 0.1
    assert ex.state.param("roughness") == pytest.approx(0.1)
    assert ex.model.views["lobe"].peak == pytest.approx(
        ExplorerModel(ex.state.copy(), **SIZES).compute()["lobe"].peak, rel=1e-12
    )
    ex.controls["param:ndf"].value = "ggx"
    assert ex.state.param("ndf") == "ggx" and "lobe" in ex.timings[-1][0]
    # Terms: unchecking the specular term leaves the lit sphere with k_d (n·l) only.
    ex.controls["term_specular"].value = False
    assert ex.state.terms == ("ambient", "diffuse")
    # set() changes the state as the widgets do and shows it in them.
    views = ex.set(model="phong", shininess=80.0, elevation=45.0)
    assert ex.controls["model"].value == "phong" and ex.controls["param:shininess"].value == pytest.approx(80.0)
    assert ex.controls["elevation"].value == 45.0 and "polar" in views
    with pytest.raises(ValueError, match="shininess must be"):
        ex.set(shininess=-1)
    assert ex.state.param("shininess") == 80.0


def test_open_brdf_joins_the_model_list(tmp_path):
    path = tmp_path / "phong-file.brdf"
    path.write_text(PHONG_FILE)
    ex = NotebookExplorer(**SIZES)
    name = ex.open_brdf(path)
    assert ex.state.model == name and ex.controls["model"].value == name
    assert name in [v for _, v in ex.controls["model"].options]
    assert "param:n" in ex.controls and ex.state.param("n") == 20.0


def test_png_of_composites_alpha_over_the_background():
    rgba = np.zeros((2, 2, 4), np.uint8)
    rgba[0, 0] = (255, 0, 0, 255)  # opaque red
    rgba[0, 1] = (255, 255, 255, 0)  # fully transparent: the background
    rgba[1] = (200, 100, 0, 128)  # half: (c · 128 + bg · 127) / 255, rounded
    out = decode(png_of(rgba))
    from explorer.notebook import _BG8

    bg = np.array(_BG8)
    assert out[0, 0].tolist() == [255, 0, 0] and out[0, 1].tolist() == list(_BG8)
    expected = (np.array([200, 100, 0]) * 128 + bg * 127 + 127) // 255
    assert out[1, 0].tolist() == expected.tolist()

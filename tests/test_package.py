import subprocess
import sys

import numpy as np

from explorer.cli import main
from lighting import AmbientLight, DirectionalLight, Lambert, Material
from lighting.analytic import render_sphere, sphere_camera
from lighting.image import encode_srgb8, read_png, srgb_to_linear
from lighting.raster import raycast_sphere


def test_import_lighting_loads_nothing_heavy():
    code = (
        "import sys, lighting, lighting.brdf, lighting.lights, lighting.illumination, lighting.gl, lighting.image;"
        "heavy = {'matplotlib', 'pyvista', 'vtk', 'vtkmodules', 'trimesh', 'scipy'};"
        "print(sorted(m for m in sys.modules if m.split('.')[0] in heavy))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out == "[]"


def test_analytic_sphere_lambert_is_kd_max_n_dot_l():
    kd = np.array([0.9, 0.5, 0.1])
    l_dir = np.array([0.3, 0.5, 0.8]) / np.linalg.norm([0.3, 0.5, 0.8])
    img = render_sphere(Material(Lambert(kd)), [DirectionalLight(l_dir)], size=64)
    gb = raycast_sphere(sphere_camera(64))
    mask = gb.coverage
    expected = kd * np.maximum(gb.normal @ l_dir, 0)[..., None]
    np.testing.assert_allclose(img[mask], expected[mask], rtol=1e-14, atol=1e-15)
    assert np.all(img[~mask] == 0) and 0.6 < mask.mean() < 0.7  # π/4 / 1.08² of the frame


def test_srgb_encoding_and_clip_report():
    lin = np.array([[[0.0, 0.0031308, 0.5], [1.0, 2.0, 0.2]]])
    img, rep = encode_srgb8(lin)
    assert img[0, 0].tolist() == [0, 10, 188]
    assert img[0, 1].tolist() == [255, 255, 124]
    assert rep.clipped_pixels == 1 and rep.total_pixels == 2 and rep.max_value == 2.0
    img2, rep2 = encode_srgb8(lin, tonemap="reinhard")
    assert rep2.clipped_pixels == 0 and img2.max() < 255
    np.testing.assert_allclose(srgb_to_linear(img[0, 0] / 255), [0, 0.0031308, 0.5], atol=3e-3)


def test_cli_sphere_writes_the_engine_image(tmp_path):
    out = tmp_path / "s.png"
    assert main(["sphere", "-o", str(out), "--size", "48", "--elevation", "90", "--ks", "0"]) == 0
    img = read_png(out)
    assert img.shape == (48, 48, 3)
    expected = render_sphere(
        Material(Lambert((0.8, 0.25, 0.2)), ambient=(0.8, 0.25, 0.2)),
        [AmbientLight(intensity=0.1), DirectionalLight.from_angles(90, 135)],
        size=48,
    )
    np.testing.assert_array_equal(img, encode_srgb8(expected)[0])
    # Lit from overhead (+z, toward the viewer): the centre is the brightest point.
    lum = img.astype(float).sum(-1)
    assert lum[23:25, 23:25].min() == lum.max()
    assert lum[24, 40] < lum[24, 30] < lum[24, 24]


def test_cli_reports_bad_values(tmp_path, capsys):
    assert main(["sphere", "-o", str(tmp_path / "x.png"), "--kd", "-1"]) == 2
    assert "kd must be" in capsys.readouterr().err
    assert not (tmp_path / "x.png").exists()


def test_cli_routes_sub_commands(capsys, monkeypatch):
    import explorer.app
    import explorer.cli as cli

    seen = []
    monkeypatch.setattr(explorer.app, "main", lambda argv: seen.append(argv) or 0)
    assert cli.main([]) == 0 and cli.main(["--off-screen", "--screenshot", "x.png"]) == 0
    assert seen == [[], ["--off-screen", "--screenshot", "x.png"]]
    assert cli.main(["report"]) == 0
    assert "accuracy" in capsys.readouterr().out

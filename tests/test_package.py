import os
import signal
import stat
import subprocess
import sys
import time

import numpy as np
import pytest

from explorer.cli import main
from lighting import AmbientLight, BlinnPhong, DirectionalLight, Lambert, Material
from lighting.render.image import encode_srgb8, read_png, srgb_to_linear, write_png
from lighting.render.raster import raycast_sphere
from lighting.render.sphere import render_sphere, sphere_camera


def test_import_lighting_loads_nothing_heavy():
    code = (
        "import sys, lighting, lighting.brdf, lighting.gl, lighting.sampling, lighting.microfacet, lighting.fresnel;"
        "heavy = {'matplotlib', 'pyvista', 'vtk', 'vtkmodules', 'trimesh', 'scipy'};"
        "print(sorted(m for m in sys.modules if m.split('.')[0] in heavy or m.startswith('lighting.validation')))"
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
    import explorer.app.command
    import explorer.cli as cli

    seen = []
    monkeypatch.setattr(explorer.app.command, "run", lambda args: seen.append(args) or 0)
    assert cli.main([]) == 0 and cli.main(["--off-screen", "--screenshot", "x.png"]) == 0
    assert cli.main(["explore", "--model", "phong"]) == 0
    assert [(a.command, a.off_screen, a.screenshot, a.model) for a in seen] == [
        ("explore", False, None, None), ("explore", True, "x.png", None), ("explore", False, None, "phong")
    ]
    assert cli.main(["report"]) == 2  # which report? the names go to standard error
    assert "accuracy" in capsys.readouterr().err


# ----------------------------------------------------------------------------- the command line's outputs
def _one_error_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("lighting-explorer: error: "), err
    assert "Traceback" not in err
    return lines[0]


@pytest.mark.parametrize(
    ("argv", "expected", "absent"),
    [
        (["--size", "20000"], ["--size 20000 needs about", "GiB", "memory budget of 2.0 GiB"], []),
        (["--size", "100000"], ["--size must be at most 65536x65536 pixels; got 100000x100000"], ["budget"]),
        (["--size", "0"], ["--size must be WIDTHxHEIGHT or N (a square) in pixels, both >= 1 (e.g. 384 or 640x480); "
                           "got '0'"], []),
        (["--exposure", "1e308"], ["--exposure must be a finite number >= -100 and <= 100; got 1e+308"], []),
        (["--kd", "red"], ["--kd must be one number or three comma-separated numbers", "'red'"], ["_rgb"]),
        (["--kd", "1,2"], ["--kd must be one number or three"], []),
        (["--kd", "nan"], ["--kd must be"], []),
        (["--ambient", "-1"], ["--ambient must be a finite number >= 0; got -1.0"], ["intensity"]),
        (["--shininess", "inf"], ["--shininess must be a finite number >= 0"], []),
        (["--elevation", "nan"], ["--elevation must be a finite number >= -90 and <= 90; got nan"], []),
        (["--size", "12", "--bogus"], ["unrecognized arguments: --bogus"], []),
    ],
)
def test_cli_sphere_refuses_bad_values_in_the_words_of_the_flag(tmp_path, capsys, monkeypatch, argv, expected, absent):
    import lighting.render.sphere

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(lighting.render.sphere, "render_sphere", lambda *a, **k: pytest.fail("rendered a bad request"))
    assert main(["sphere", "-o", "x.png", *argv]) == 2
    line = _one_error_line(capsys.readouterr().err)
    for text in expected:
        assert text in line
    for text in absent:
        assert text not in line
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("out", "expected"),
    [
        ("", "-o: the output path is empty"),
        ("missing/x.png", "-o: cannot write 'missing/x.png': folder "),
        (".", "-o: '.' is a folder; give a file name ending in .png"),
        ("x.svg", "-o: cannot write 'x.svg': unknown image format '.svg'; formats: .png, "),
        ("x.pdf", "unknown image format '.pdf'"),
        ("x", "-o: cannot write 'x': no extension; formats: .png"),
    ],
)
def test_cli_sphere_refuses_outputs_it_cannot_write_before_rendering(tmp_path, capsys, monkeypatch, out, expected):
    import lighting.render.sphere

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(lighting.render.sphere, "render_sphere", lambda *a, **k: pytest.fail("rendered a bad request"))
    assert main(["sphere", "-o", out, "--size", "12"]) == 2
    assert expected in _one_error_line(capsys.readouterr().err)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_cli_sphere_refuses_a_read_only_folder(tmp_path, capsys):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        assert main(["sphere", "-o", str(ro / "x.png"), "--size", "12"]) == 2
        assert "is not writable" in _one_error_line(capsys.readouterr().err)
        assert list(ro.iterdir()) == []
    finally:
        ro.chmod(0o755)


def _sphere_image(size):
    return render_sphere(
        Material(Lambert((0.8, 0.25, 0.2)) + BlinnPhong(0.5, 40.0), ambient=(0.8, 0.25, 0.2)),
        [AmbientLight(intensity=0.1), DirectionalLight.from_angles(45.0, 135.0)],
        size=size,
    )


def test_the_format_follows_the_extension(tmp_path, capsys):
    size = 20
    linear = _sphere_image(size)
    rgb8 = encode_srgb8(linear)[0]
    for ext in ("png", "npy", "pfm"):
        assert main(["sphere", "-o", str(tmp_path / f"s.{ext}"), "--size", str(size)]) == 0
    np.testing.assert_array_equal(read_png(tmp_path / "s.png"), rgb8)
    npy = np.load(tmp_path / "s.npy")
    assert npy.dtype == np.float64
    np.testing.assert_array_equal(npy, linear)  # linear: no exposure, no tone map, no clipping
    assert npy.max() > 1.0
    raw = (tmp_path / "s.pfm").read_bytes()
    head = b"PF\n%d %d\n-1.0\n" % (size, size)  # colour, width height, little-endian
    assert raw.startswith(head) and len(raw) == len(head) + 4 * 3 * size * size
    pfm = np.frombuffer(raw[len(head) :], "<f4").reshape(size, size, 3)[::-1]  # rows stored bottom to top
    np.testing.assert_array_equal(pfm, linear.astype(np.float32))
    out = capsys.readouterr().out
    assert "wrote " + str(tmp_path / "s.npy") + f" ({size}x{size}, linear float64)" in out

    pil = pytest.importorskip("PIL.Image")
    for ext, fmt in (("jpg", "JPEG"), ("tiff", "TIFF"), ("webp", "WEBP")):
        path = tmp_path / f"s.{ext}"
        assert main(["sphere", "-o", str(path), "--size", str(size)]) == 0
        with pil.open(path) as im:
            assert im.format == fmt and im.size == (size, size)
            px = np.asarray(im.convert("RGB"))
        if fmt == "JPEG":
            assert np.abs(px.astype(int) - rgb8).mean() < 3  # quality 95, no chroma subsampling (4:2:0 gives 4.4)
        else:  # lossless
            np.testing.assert_array_equal(px, rgb8)


def test_exr_is_written_only_with_openexr(tmp_path, capsys):
    from explorer.output import available_formats

    code = main(["sphere", "-o", str(tmp_path / "s.exr"), "--size", "12"])
    if ".exr" in available_formats():
        assert code == 0 and (tmp_path / "s.exr").read_bytes()[:4] == b"\x76\x2f\x31\x01"
    else:
        assert code == 2
        line = _one_error_line(capsys.readouterr().err)
        assert "writing .exr needs OpenEXR, which is not installed; formats: .png" in line
        assert list(tmp_path.iterdir()) == []


@pytest.fixture
def umask_027():
    old = os.umask(0o027)
    try:
        yield
    finally:
        os.umask(old)


def test_outputs_keep_the_umask_and_the_mode_of_the_file_they_replace(tmp_path, umask_027):
    new = tmp_path / "new.png"
    assert main(["sphere", "-o", str(new), "--size", "12"]) == 0
    assert stat.S_IMODE(new.stat().st_mode) == 0o640  # 0o666 minus the umask, as open() would give
    old = tmp_path / "old.png"
    old.write_bytes(b"old")
    old.chmod(0o644)
    assert main(["sphere", "-o", str(old), "--size", "12"]) == 0
    assert stat.S_IMODE(old.stat().st_mode) == 0o644 and old.read_bytes()[:4] == b"\x89PNG"
    write_png(tmp_path / "api.png", np.zeros((2, 2, 3), np.uint8))  # the engine's own writer too
    assert stat.S_IMODE((tmp_path / "api.png").stat().st_mode) == 0o640
    assert sorted(p.name for p in tmp_path.iterdir()) == ["api.png", "new.png", "old.png"]


def test_writing_through_a_symbolic_link_updates_its_target(tmp_path):
    target = tmp_path / "real.png"
    target.write_bytes(b"old")
    link = tmp_path / "link.png"
    link.symlink_to(target)
    assert main(["sphere", "-o", str(link), "--size", "12"]) == 0
    assert link.is_symlink() and target.read_bytes()[:4] == b"\x89PNG"


def test_a_failed_write_names_the_users_path_and_leaves_the_old_file(tmp_path, monkeypatch, capsys):
    import explorer.output

    path = tmp_path / "keep.png"
    path.write_bytes(b"old")

    def refuse(src, dst):
        raise PermissionError(13, "Permission denied", src)  # the temporary file's name, as os.replace gives it

    monkeypatch.setattr(explorer.output.os, "replace", refuse)
    # The path as the user typed it, relative: a long temporary folder (a test worker's) would be shortened.
    monkeypatch.chdir(tmp_path)
    given = path.name
    assert main(["sphere", "-o", given, "--size", "12"]) == 2
    line = _one_error_line(capsys.readouterr().err)
    assert line == f"lighting-explorer: error: -o: cannot write {given!r}: Permission denied"
    assert ".part" not in line and "tmp" not in line.replace(str(tmp_path), "")
    assert path.read_bytes() == b"old" and [p.name for p in tmp_path.iterdir()] == ["keep.png"]


@pytest.mark.parametrize("interrupt", [KeyboardInterrupt, "Terminated", OSError, RuntimeError])
def test_an_interrupted_write_leaves_the_old_files_and_no_temporary_file(tmp_path, interrupt):
    from explorer.output import Terminated, atomic_write_many

    exc = Terminated if interrupt == "Terminated" else interrupt
    (tmp_path / "a.png").write_bytes(b"old a")

    def half_written(tmp):
        with open(tmp, "wb") as f:
            f.write(b"half")
        raise exc()

    with pytest.raises((exc, ValueError)):
        atomic_write_many([(tmp_path / "a.png", b"new a"), (tmp_path / "a.json", half_written)])
    assert [p.name for p in tmp_path.iterdir()] == ["a.png"]  # neither file replaced: they go as a pair
    assert (tmp_path / "a.png").read_bytes() == b"old a"


def test_sigterm_during_a_write_unwinds_and_removes_the_temporary_file(tmp_path):
    from explorer.output import Terminated, atomic_write, signals_as_exceptions

    def killed_midway(tmp):
        with open(tmp, "wb") as f:
            f.write(b"half")
            os.kill(os.getpid(), signal.SIGTERM)
            for _ in range(1000):  # the handler runs at the next bytecode boundary
                f.write(b"more")

    with signals_as_exceptions(), pytest.raises(Terminated):
        atomic_write(tmp_path / "x.png", killed_midway)
    assert list(tmp_path.iterdir()) == []
    assert signal.getsignal(signal.SIGTERM) == signal.SIG_DFL


def test_memory_budget_flag_sets_the_budget_for_the_command_and_restores_it(tmp_path, capsys):
    from lighting._budget import memory_budget

    out = str(tmp_path / "s.png")
    # 100 x 100 pixels at 320 bytes each: 3.1 MiB.
    assert main(["--memory-budget", "2M", "sphere", "-o", out, "--size", "100"]) == 2
    line = _one_error_line(capsys.readouterr().err)
    assert "--size 100 needs about 3.1 MiB (a 100x100 sphere image), over the memory budget of 2.0 MiB" in line
    assert not os.path.exists(out)
    assert main(["sphere", "-o", out, "--size", "100", "--memory-budget=4M"]) == 0
    assert os.path.exists(out) and memory_budget() == 2 * 1024**3
    for bad in ("lots", "0", "1k", "-1G", "nanG", ""):
        assert main(["--memory-budget", bad, "sphere", "-o", out]) == 2
        assert "--memory-budget must be a size such as 2G" in _one_error_line(capsys.readouterr().err)
    assert main(["sphere", "--memory-budget"]) == 2
    assert "--memory-budget: expected one argument" in _one_error_line(capsys.readouterr().err)


def test_unknown_report_and_bad_bench_options_are_one_line(capsys):
    assert main(["report", "nonsense"]) == 2
    assert "unknown report 'nonsense' (choose from accuracy, stability)" in _one_error_line(capsys.readouterr().err)
    for argv, text in ((["--repeat", "0"], "--repeat must be an integer in [1, 10000]; got 0"),
                       (["--repeat", "x"], "argument --repeat: invalid int value: 'x'")):  # fmt: skip
        assert main(["bench", *argv]) == 2
        assert text in _one_error_line(capsys.readouterr().err)


@pytest.mark.parametrize(
    ("shot", "expected"),
    [
        ("", "--screenshot: the output path is empty"),
        ("missing/w.png", "--screenshot: cannot write 'missing/w.png': folder "),
        (".", "--screenshot: '.' is a folder; give a file name ending in .png"),
        ("w.npy", "--screenshot: cannot write 'w.npy': .npy holds a linear float image, which --screenshot does"),
        ("w.svg", "unknown image format '.svg'"),
    ],
)
def test_explore_screenshot_refuses_paths_before_building_the_window(tmp_path, monkeypatch, capsys, shot, expected):
    pytest.importorskip("pyvista")
    import explorer.app

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(explorer.app, "ExplorerApp", lambda *a, **k: pytest.fail("built a window for a bad path"))
    assert main(["--off-screen", "--screenshot", shot]) == 2
    captured = capsys.readouterr()
    assert expected in _one_error_line(captured.err) and "wrote" not in captured.out
    assert list(tmp_path.iterdir()) == []


def test_a_signal_between_the_renames_of_a_pair_waits_until_both_are_in_place(tmp_path, monkeypatch):
    import threading

    import explorer.output
    from explorer.output import Terminated, atomic_write_many, signals_as_exceptions

    stop = threading.Event()
    bystander = threading.Thread(target=stop.wait)  # an engine or executor thread: the kernel may pick it
    bystander.start()
    real_replace = os.replace
    renamed = []

    def replace_then_signal(src, dst):
        real_replace(src, dst)
        renamed.append(os.path.basename(dst))
        if len(renamed) == 1:
            signal.pthread_kill(bystander.ident, signal.SIGTERM)
            # Wait until the main thread has run the Python handler (it notes the signal as pending):
            # on a loaded machine the bystander may be scheduled, and the signal delivered, only later,
            # and after the block the default handler would end the process.
            deadline = time.monotonic() + 30
            while explorer.output._deferral["pending"] is None and time.monotonic() < deadline:
                time.sleep(0.001)

    monkeypatch.setattr(explorer.output.os, "replace", replace_then_signal)
    try:
        with signals_as_exceptions(), pytest.raises(Terminated):
            atomic_write_many([(tmp_path / "fig.png", b"png"), (tmp_path / "fig.json", b"{}")])
    finally:
        stop.set()
        bystander.join()
    assert renamed == ["fig.png", "fig.json"]  # the signal was held until the pair was complete
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fig.json", "fig.png"]


def test_a_stop_signal_swallowed_by_a_library_still_stops_the_command_before_it_writes(tmp_path, monkeypatch, capsys):
    import lighting.render.sphere

    real = lighting.render.sphere.render_sphere

    def render_with_a_greedy_library(*args, **kwargs):
        try:  # trimesh wraps its optional imports in "except BaseException": Ctrl-C there is lost
            os.kill(os.getpid(), signal.SIGTERM)
            for _ in range(100_000):
                pass
        except BaseException:
            pass
        return real(*args, **kwargs)

    monkeypatch.setattr(lighting.render.sphere, "render_sphere", render_with_a_greedy_library)
    out = tmp_path / "s.png"
    assert main(["sphere", "-o", str(out), "--size", "12"]) == 143
    assert capsys.readouterr().err == "lighting-explorer: terminated\n"
    assert list(tmp_path.iterdir()) == []
    monkeypatch.setattr(lighting.render.sphere, "render_sphere", real)
    assert main(["sphere", "-o", str(out), "--size", "12"]) == 0  # the next command starts afresh


def test_a_stop_signal_raised_inside_a_garbage_collector_callback_is_noted_not_printed(capsys):
    # Matplotlib's transform tree drops weak references in callbacks; a SIGTERM handled there raises
    # where Python cannot propagate it ("Exception ignored in ..." and a traceback on stderr).
    import gc
    import weakref

    from explorer.output import Terminated, raise_if_signalled, received_signal, signals_as_exceptions

    class Node:
        pass

    with signals_as_exceptions():
        target = Node()
        weakref.finalize(target, os.kill, os.getpid(), signal.SIGTERM)
        keep = weakref.ref(target, lambda _: [None for _ in range(100_000)])  # the handler runs in here
        del target
        gc.collect()
        deadline = time.monotonic() + 10
        while received_signal() is None and time.monotonic() < deadline:
            time.sleep(0.001)
        assert received_signal() == signal.SIGTERM
        with pytest.raises(Terminated):
            raise_if_signalled()
    assert keep() is None
    assert "Traceback" not in capsys.readouterr().err

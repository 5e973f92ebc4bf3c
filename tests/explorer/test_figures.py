"""The lecture-note figure set: every figure is written, valid, not blank, reproducible; the command's errors.

The whole set is drawn once in quick mode (module fixture) and a second time from the installed wheel; the
numbers each figure measured while drawing are checked against the laws they illustrate.
"""

from __future__ import annotations

import csv
import json
import math
import os
from pathlib import Path

import numpy as np
import pytest

pytestmark = pytest.mark.slow  # draws the whole lecture-note figure set

PIL = pytest.importorskip("PIL.Image")
pytest.importorskip("matplotlib")

from installed_wheel import run_command, shared_install  # noqa: E402

from explorer import figures  # noqa: E402


def _run(argv, capsys=None):
    rc = figures.main(argv)
    out = capsys.readouterr() if capsys is not None else None
    return rc, out


def _docs_quick_set():
    """The quick set the docs build drew from these very sources, when the run checks that build (``.ci/run``).

    ``LIGHTING_DOCS_SITE`` names a site built from this tree (tests/docs/test_site.py checks it); its build drew the
    quick set into ``build/gallery-quick`` beside it, stamped with the digest of the sources the figures are drawn
    from (``explorer/figures/mkdocs_hook.py``).  Drawn from the same sources, it is this module's first draw.
    """
    site = os.environ.get("LIGHTING_DOCS_SITE")
    if not site:
        return None
    from explorer.figures.mkdocs_hook import _sources_digest

    folder = Path(site).resolve().parent / "gallery-quick"
    stamp = folder / "sources.txt"
    if not (stamp.is_file() and (folder / "figures.json").is_file()):
        return None
    if stamp.read_text(encoding="utf-8").strip() != _sources_digest():
        return None
    return folder


@pytest.fixture(scope="module")
def quick_set(tmp_path_factory):
    """``(folder, manifest)`` of the whole set drawn in quick mode: by this process (PNG), or by the docs build (PNG
    for the pages, SVG and PDF for slides)."""
    out, formats = _docs_quick_set(), ["png", "svg", "pdf"]
    if out is None:
        out, formats = tmp_path_factory.mktemp("figures"), ["png"]
        figures.generate(out, formats=tuple(formats), quick=True)
    manifest = json.loads((out / "figures.json").read_text(encoding="utf-8"))
    assert manifest["formats"] == formats
    return out, manifest


def _pixels(path):
    with PIL.open(path) as im:
        im.load()
        return np.asarray(im.convert("RGB"))


def test_manifest_lists_every_registered_figure_in_order(quick_set):
    out, manifest = quick_set
    names = figures.figure_names()
    assert [r["name"] for r in manifest["figures"]] == names
    assert manifest["quick"] is True
    assert len(names) == len(set(names)) >= 20
    for rec in manifest["figures"]:
        assert rec["caption"] and "{" not in rec["caption"], rec["name"]  # every measured field filled in
        assert rec["title"] and rec["slides"]
        assert isinstance(rec["parameters"], dict)
        sidecar = json.loads((out / f"{rec['name']}.json").read_text(encoding="utf-8"))
        assert sidecar == rec


def test_every_file_is_a_valid_image_of_the_stated_size_and_not_blank(quick_set):
    out, manifest = quick_set
    for rec in manifest["figures"]:
        path = out / rec["files"]["png"]
        with PIL.open(path) as im:
            im.verify()  # a well-formed PNG
        px = _pixels(path)
        w, h = rec["size_px"]
        assert px.shape == (h, w, 3), rec["name"]
        # The stated size is the figure's registered size in inches times the dpi, cut to whole pixels as
        # Matplotlib's Agg canvas cuts it.
        size_in = figures.REGISTRY[rec["name"]].size_in
        assert (w, h) == tuple(int(x * rec["quality"]["dpi"]) for x in size_in), rec["name"]
        assert float(px.std()) > 8.0, f"{rec['name']} looks blank (pixel std {px.std():.2f})"
        packed = px.reshape(-1, 3).astype(np.int32) @ np.array([65536, 256, 1], dtype=np.int32)
        assert np.unique(packed).size > 16, rec["name"]


def test_the_installed_package_draws_the_same_set_pixel_for_pixel(quick_set, tmp_path_factory):
    # A second run, from the wheel installed in a fresh virtual environment: the whole set draws from the
    # package's own files, and every deterministic figure is the same image, byte for byte, as this process drew.
    out, manifest = quick_set
    bin_dir, work, _ = shared_install(tmp_path_factory)
    again = work / "figures"
    env = dict(os.environ, LIGHTING_EXPLORER_CACHE=str(work / "cache"))
    command = [str(bin_dir / "lighting-explorer"), "figures", "--quick", "--out", str(again)]
    res = run_command(command, cwd=work, env=env)
    names = figures.figure_names()
    assert f"wrote {len(names)} figures" in res.stdout
    installed = json.loads((again / "figures.json").read_text(encoding="utf-8"))
    assert [r["name"] for r in installed["figures"]] == names
    for rec in installed["figures"]:
        png = (again / rec["files"]["png"]).read_bytes()
        assert png[:8] == b"\x89PNG\r\n\x1a\n"
        assert (int.from_bytes(png[16:20], "big"), int.from_bytes(png[20:24], "big")) == tuple(rec["size_px"])
    deterministic = {r["name"] for r in installed["figures"] if r["deterministic"]}
    same = [r["name"] for r in manifest["figures"] if r["deterministic"] and r["name"] in deterministic]
    assert len(same) >= len(names) - 6  # only the figures that plot measured run times may differ
    for name in same:
        a, b = out / f"{name}.png", again / f"{name}.png"
        assert np.array_equal(_pixels(a), _pixels(b)), name
        assert a.read_bytes() == b.read_bytes(), name  # no date or version stamp either


#: The figures of the accuracy studies, in lecture order (explorer.figures.accuracy).
ACCURACY_FIGURES = ["accuracy_integration", "accuracy_area_light", "accuracy_tessellation", "accuracy_precision",
                    "accuracy_ibl"]  # fmt: skip


def test_only_the_timed_figures_are_nondeterministic(quick_set):
    _, manifest = quick_set
    nondet = {r["name"]: r["nondeterministic_reason"] for r in manifest["figures"] if not r["deterministic"]}
    measured = {r["name"]: r["measured"] for r in manifest["figures"]}
    # Both plot measured run times: an accuracy figure only when it measured its study while drawing (drawn
    # from the studies report accuracy saved in this test run's cache, it is reproducible).
    timed = [n for n in ACCURACY_FIGURES if measured[n]["source_kind"] == "measured now"]
    assert list(nondet) == [*timed, "ibl_error"]
    assert all("wall-clock" in reason for reason in nondet.values())
    for name in ACCURACY_FIGURES:
        assert measured[name]["reproducible"] is (measured[name]["source_kind"] != "measured now"), name


def test_measured_values_follow_the_laws_the_figures_show(quick_set):
    _, manifest = quick_set
    m = {r["name"]: r["measured"] for r in manifest["figures"]}
    # Lambert: the engine's k_d (n·l) is max(cos θ, 0).
    assert m["lambert_cosine_law"]["max_abs_difference_from_cos"] < 1e-15
    # In the plane of incidence the Phong angle is twice the Blinn-Phong one: φ = 2 θ_h.
    g = m["reflection_geometry"]
    assert math.isclose(g["phi_deg"], 2 * g["theta_h_deg"], rel_tol=1e-5)
    # Light is linear, and the illumination terms add up to the full render.
    assert m["light_is_linear"]["max_difference"] < 1e-12
    assert m["illumination_terms"]["max_difference"] < 1e-12
    # Reciprocity: exact for normalized Blinn-Phong, broken by exactly (n·v)/(n·l) for Phong.
    r = m["reciprocity"]
    assert r["bp_difference"] < 1e-12
    assert r["phong_difference"] > 0.1
    assert r["phong_ratio_error"] < 1e-6
    # The plots' scale is the lobes' (the Phong peak at the mirror is ks / (π cos 50°) = 0.495), not the
    # unbounded 1/(n·l) at the horizon that the view-fixed Phong slice samples; both ratio curves are drawn.
    assert 0.1 < r["phong_plot_scale"] < 1.0 and r["phong_ratio_points"] >= 20 and r["bp_ratio_points"] >= 20
    # A small bright patch acts as a point light: difference of order Ω (here 2e-3 sr).
    assert m["rendering_equation"]["point_difference"] < 0.02
    # Gouraud's slope jumps at edges are much larger than Phong interpolation's.
    gp = m["gouraud_vs_phong"]
    assert gp["metric_gouraud"] > 5 * gp["metric_phong"]
    # The audit fails exactly the models the decks call implausible.
    fails = m["plausibility_table"]["failures"]
    assert any(f.startswith("Phong") for f in fails) and "Lambert" not in fails
    assert all(not f.startswith("C-T beckmann") for f in fails)


def test_accuracy_figure_from_a_csv_is_reproducible(tmp_path):
    rows = []
    for method, scale in (("quadrature", 1e-3), ("uniform", 1e-1)):
        for k, cost in enumerate((16, 64, 256)):
            rows.append({"study": "integration", "case": "a case", "method": method, "cost": cost,
                         "cost_unit": "samples", "error": scale / 4**k, "error_spread": 0.0,
                         "seconds": 1e-4 * 2**k, "reference": "closed form"})  # fmt: skip
    path = tmp_path / "accuracy.csv"
    with open(path, "w", newline="", encoding="utf-8") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    outs = []
    for run in ("a", "b"):
        d = tmp_path / run
        assert figures.main(["--out", str(d), "--only", "accuracy_integration", "--quick", "--accuracy-csv",
                             str(path)]) == 0  # fmt: skip
        outs.append(d)
        rec = json.loads((d / "accuracy_integration.json").read_text(encoding="utf-8"))
        assert rec["deterministic"] is True and rec["measured"]["points"] == 6
        assert rec["measured"]["source_kind"] == "csv" and "read from an accuracy.csv" in rec["caption"]
    a, b = (d / "accuracy_integration.png" for d in outs)
    assert a.read_bytes() == b.read_bytes()


def test_cli_only_and_vector_formats(quick_set, tmp_path, capsys):
    # model_gallery_half_vector clips its panels to circles: Matplotlib names such clip paths after the path
    # objects' id(), which the writer renames by their order of use so that the SVG is the same on every run.
    # Its polar panels are also what constrained layout moves a little at each save: every file must still be
    # the same whichever formats were asked for, and in whatever order.
    names = ("light_colour", "reflection_geometry", "model_gallery_half_vector")
    rc, out = _run(["--out", str(tmp_path / "a"), "--only", *names, "--format", "svg,pdf,png", "--quick"], capsys)
    assert rc == 0, out.err
    assert "wrote 3 figures (9 files" in out.out
    a = tmp_path / "a"
    # The same figures in the order png, svg, pdf: the docs build's set where this run checks it, else drawn here.
    b, manifest = quick_set
    if manifest["formats"] != ["png", "svg", "pdf"]:
        b = tmp_path / "b"
        rc, out = _run(["--out", str(b), "--only", *names, "--format", "png,svg,pdf", "--quick"], capsys)
        assert rc == 0, out.err
        assert "wrote 3 figures (9 files" in out.out
    assert sorted(p.name for p in a.iterdir()) == sorted(
        [f"{n}.{e}" for n in names for e in ("svg", "pdf", "png", "json")] + ["figures.json"]
    )
    svg = (a / "light_colour.svg").read_text(encoding="utf-8")
    assert svg.lstrip().startswith("<?xml") and "<dc:date>" not in svg
    assert (a / "light_colour.pdf").read_bytes().startswith(b"%PDF")
    clipped = (a / "model_gallery_half_vector.svg").read_text(encoding="utf-8")
    assert '<clipPath id="p0000000000">' in clipped and 'clip-path="url(#p0000000000)"' in clipped
    for name in names:
        for ext in ("svg", "pdf", "png"):
            assert (a / f"{name}.{ext}").read_bytes() == (b / f"{name}.{ext}").read_bytes(), (name, ext)
    manifest = json.loads((a / "figures.json").read_text(encoding="utf-8"))
    # lecture order
    assert [r["name"] for r in manifest["figures"]] == [n for n in figures.figure_names() if n in names]
    # A PDF asked for alone is the one drawn with the others.
    rc, out = _run(["--out", str(tmp_path / "c"), "--only", names[-1], "--format", "pdf", "--quick"], capsys)
    assert rc == 0, out.err
    assert (tmp_path / "c" / f"{names[-1]}.pdf").read_bytes() == (a / f"{names[-1]}.pdf").read_bytes()


def test_dpi_sets_the_pixel_size(tmp_path):
    assert figures.main(["--out", str(tmp_path), "--only", "light_is_linear", "--dpi", "40", "--quick"]) == 0
    rec = json.loads((tmp_path / "light_is_linear.json").read_text(encoding="utf-8"))
    w, h = rec["size_px"]
    size_in = figures.REGISTRY[rec["name"]].size_in
    assert (w, h) == (int(size_in[0] * 40), int(size_in[1] * 40))
    assert _pixels(tmp_path / "light_is_linear.png").shape == (h, w, 3)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--only", "lambert_cosine"], "unknown figure 'lambert_cosine'; did you mean 'lambert_cosine_law'?"),
        (["--only", "nothing_like_it"], "unknown figure 'nothing_like_it'; available: local_vs_global"),
        (["--format", "png,gif"], "unknown format 'gif'; allowed: png, svg, pdf"),
        (["--dpi", "3"], "dpi must be an integer >= 10; got 3"),
        (["--dpi", "many"], "argument --dpi: invalid int value: 'many'"),
        (["--accuracy-csv", "/no/such/file.csv"], "--accuracy-csv: no such file: /no/such/file.csv"),
    ],
)
def test_cli_errors_exit_2_with_one_clear_line(tmp_path, capsys, argv, message):
    rc, out = _run(["--out", str(tmp_path / "x"), "--quick", *argv], capsys)
    assert rc == 2
    assert out.err.startswith("lighting-explorer: error: ")
    assert message in out.err
    assert len(out.err.strip().splitlines()) == 1
    assert not (tmp_path / "x" / "figures.json").exists()


def test_cli_list_names_every_figure(capsys):
    rc, out = _run(["--list"], capsys)
    assert rc == 0
    listed = [line.split()[0] for line in out.out.splitlines()]
    assert listed == figures.figure_names()


# ----------------------------------------------------------------------------- checked before drawing
def _no_drawing(monkeypatch):
    monkeypatch.setattr(figures, "make_figure", lambda *a, **k: pytest.fail("drew a figure for a bad request"))


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--dpi", "100000"], "--dpi 100000 makes light_colour 1333334x750000 pixels; Matplotlib draws at most"),
        (["--dpi", "2000"], "--dpi 2000 needs about 3.0 GiB (light_colour at 26667x15000 pixels), over the"),
        (["--dpi", "0"], "dpi must be an integer >= 10; got 0"),
        (["--jobs", "0"], "--jobs must be an integer in [1, 64]; got 0"),
        (["--jobs", "-1"], "--jobs must be an integer in [1, 64]; got -1"),
        (["--jobs", "1000"], "--jobs must be an integer in [1, 64]; got 1000"),
        (["--jobs", "2", "--only", "light_colour", "light_is_linear"], None),  # the control: accepted
    ],
)
def test_sizes_and_counts_are_refused_before_anything_is_drawn(tmp_path, capsys, monkeypatch, argv, message):
    if message is None:
        rc, out = _run(["--out", str(tmp_path / "x"), "--quick", *argv], capsys)
        assert rc == 0, out.err
        return
    _no_drawing(monkeypatch)
    rc, out = _run(["--out", str(tmp_path / "x"), "--quick", "--only", "light_colour", *argv], capsys)
    assert rc == 2 and message in out.err, out.err
    assert len(out.err.strip().splitlines()) == 1 and "Traceback" not in out.err
    assert not (tmp_path / "x").exists()


def test_out_that_is_a_file_is_refused_and_kept(tmp_path, capsys, monkeypatch):
    _no_drawing(monkeypatch)
    taken = tmp_path / "figures"
    taken.write_bytes(b"not a folder")
    monkeypatch.chdir(tmp_path)  # the name as given, whole: a long temporary folder would be abbreviated
    rc, out = _run(["--out", taken.name, "--quick", "--only", "light_colour"], capsys)
    assert rc == 2
    assert f"--out: {taken.name!r} exists and is not a folder" in out.err
    assert len(out.err.strip().splitlines()) == 1
    assert taken.read_bytes() == b"not a folder"


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (b"\x89PNG\r\n\x1a\n\x00\x00\xff\xfe", "is not a UTF-8 text file"),
        (b"a,b\n1,2\n", "is not an accuracy.csv of 'lighting-explorer report accuracy': missing columns study, "),
        (b"study,case,method,cost,cost_unit,error,error_spread,seconds,reference\n", "has no data rows"),
        (b"study,case,method,cost,cost_unit,error,error_spread,seconds,reference\ns,c,m,lots,n,1,0,1,r\n",
         "line 2: cost must be an integer; got 'lots'"),
        (b"study,case,method,cost,cost_unit,error,error_spread,seconds,reference\ns,c,m,4,n,nan,0,1,r\n",
         "line 2: error must be finite and >= 0; got 'nan'"),
        (b"study,case,method,cost,cost_unit,error,error_spread,seconds,reference\ns,c,m,4,n,1,0\n",
         "line 2: no value for 'seconds'"),
    ],
)
def test_accuracy_csv_that_is_not_one_is_named_in_one_line(tmp_path, capsys, monkeypatch, content, message):
    _no_drawing(monkeypatch)
    path = tmp_path / "accuracy.csv"
    path.write_bytes(content)
    monkeypatch.chdir(tmp_path)  # the name as given, whole: a long temporary folder would be abbreviated
    rc, out = _run(["--out", "x", "--quick", "--only", "accuracy_integration", "--accuracy-csv", path.name], capsys)
    assert rc == 2
    assert out.err.startswith(f"lighting-explorer: error: --accuracy-csv: {path.name!r}"), out.err
    assert message in out.err and len(out.err.strip().splitlines()) == 1
    assert not (tmp_path / "x").exists()


def test_only_merges_into_the_manifest_in_lecture_order(tmp_path):
    out = tmp_path / "set"
    names = figures.figure_names()
    first, second, third = names[2], names[5], names[0]
    figures.generate(out, only=[second], quick=True, dpi=20)
    figures.generate(out, only=[first, third], quick=True, dpi=20, formats=("svg",))
    manifest = json.loads((out / "figures.json").read_text(encoding="utf-8"))
    assert [r["name"] for r in manifest["figures"]] == [third, first, second]  # lecture order, none dropped
    assert manifest["formats"] == ["png", "svg"] and manifest["quick"] is True
    # Drawing one again replaces its entry, the others stay as they were.
    before = {r["name"]: r for r in manifest["figures"]}
    figures.generate(out, only=[second], quick=True, dpi=24)
    after = json.loads((out / "figures.json").read_text(encoding="utf-8"))
    assert [r["name"] for r in after["figures"]] == [third, first, second]
    got = {r["name"]: r for r in after["figures"]}
    assert got[second]["quality"]["dpi"] == 24 and before[second]["quality"]["dpi"] == 20
    assert got[first] == before[first] and got[third] == before[third]
    for rec in after["figures"]:  # every entry has its files and its sidecar
        assert json.loads((out / f"{rec['name']}.json").read_text(encoding="utf-8")) == rec
        assert all((out / f).is_file() for f in rec["files"].values())


def test_files_keep_the_umask_and_no_temporary_file_is_left(tmp_path):
    import os
    import stat

    old = os.umask(0o022)
    try:
        figures.generate(tmp_path, only=["light_colour"], quick=True, dpi=20, formats=("png", "svg"))
    finally:
        os.umask(old)
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == ["figures.json", "light_colour.json", "light_colour.png", "light_colour.svg"]
    assert {stat.S_IMODE(p.stat().st_mode) for p in tmp_path.iterdir()} == {0o644}


def test_lecture_order_does_not_depend_on_which_module_is_imported_first():
    """A doctest run or a notebook may import a figure module before explorer.figures: same order."""
    import subprocess
    import sys

    code = ("import explorer.figures.rendering, explorer.figures.zoo, explorer.figures.brdf, explorer.figures.lights\n"
            "from explorer.figures import figure_names\nprint(','.join(figure_names()))")  # fmt: skip
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out.split(",") == figures.figure_names()
    # The rendering equation's figure is followed by the accuracy studies' figures, then image-based lighting.
    assert out.split(",")[0] == "local_vs_global"
    assert out.split(",")[-7:] == ["rendering_equation", *ACCURACY_FIGURES, "ibl_error"]


#: A figure fills a 1280-pixel-wide slide: its smallest text must then be at least this many pixels tall.
READABLE_PX_AT_1280 = 10.0


def test_every_figure_is_slide_shaped_and_readable_at_1280_pixels(quick_set):
    # The rule a lecturer needs: each figure drops onto a 16:9 or a 4:3 slide as it is, at the size it was
    # registered with, and its smallest text is legible when the figure is shown 1280 pixels wide.
    _, manifest = quick_set
    shapes = {16 / 9: "16:9", 4 / 3: "4:3"}
    for rec in manifest["figures"]:
        spec = figures.REGISTRY[rec["name"]]
        w, h = rec["size_in"]
        assert spec.size_in is not None, f"{rec['name']} is registered without a size"
        assert (w, h) == pytest.approx(spec.size_in, abs=1e-3), rec["name"]
        assert any(abs(w / h - r) < 0.005 * r for r in shapes), f"{rec['name']}: {w} x {h} in is not 16:9 or 4:3"
        px_per_pt = 1280 / (72 * w)
        assert rec["smallest_text_pt"] * px_per_pt >= READABLE_PX_AT_1280, (
            f"{rec['name']}: {rec['smallest_text_pt']} pt text is "
            f"{rec['smallest_text_pt'] * px_per_pt:.1f} px at 1280 px wide"
        )


def test_dpi_is_checked_against_each_selected_figures_own_size(tmp_path, capsys):
    # A resolution that fits a 4:3 figure but not a 16:9 one is refused for the wider figure only,
    # from the declared sizes, before anything is drawn or any folder is made.
    names = figures.figure_names()
    wide = next(n for n in names if figures.REGISTRY[n].size_in == figures.base.SLIDE_SIZES["16:9"])
    dpi = int(figures.AGG_MAX_PIXELS / figures.base.SLIDE_SIZES["16:9"][0]) + 1
    out = tmp_path / "never"
    rc, res = _run(["--out", str(out), "--only", wide, "--dpi", str(dpi)], capsys)
    assert rc == 2
    assert f"--dpi {dpi}" in res.err and wide in res.err and len(res.err.strip().splitlines()) == 1
    assert not out.exists()

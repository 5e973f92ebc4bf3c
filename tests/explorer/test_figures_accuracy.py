"""The accuracy studies' figures and the cache they draw from (explorer.figures.accuracy, explorer.reports.cache)."""

from __future__ import annotations

import csv
import dataclasses
import json
import math
import os

import pytest

pytest.importorskip("matplotlib")

from explorer import figures  # noqa: E402
from explorer.reports import cache  # noqa: E402
from lighting.validation import accuracy  # noqa: E402
from lighting.validation.accuracy import STUDY_NAMES, Point, Study  # noqa: E402

#: Figure name of each study, in the order of STUDY_NAMES.
FIGURES = {name: "accuracy_" + name.replace("-", "_") for name in STUDY_NAMES}


@pytest.fixture
def folder(tmp_path, monkeypatch):
    """An empty cache folder of its own for each test."""
    d = tmp_path / "cache"
    monkeypatch.setenv(cache.CACHE_ENV, str(d))
    return d


def _bits(points):
    """Every field of every point, floats by their exact hexadecimal form (NaN equals NaN here)."""
    return [tuple(v.hex() if isinstance(v, float) else (type(v).__name__, v) for v in dataclasses.astuple(p))
            for p in points]  # fmt: skip


def _studies():
    """Small studies shaped like the real ones (cases, methods, costs), with awkward floats."""
    integ = []
    for case in ("a radiance case", "an albedo case"):
        for method, scale, spread in (("quadrature", 1e-3, 0.0), ("uniform", 1e-1, 2e-2), ("importance", 3e-2, 5e-3)):
            for k, cost in enumerate((16, 64, 256)):
                integ.append(Point("integration", case, method, cost, "samples", scale / 4**k, spread / 2**k,
                                   1e-4 * 2**k + 1e-7 * len(method), "closed form", scale / 3**k, 0.95))  # fmt: skip
    integ.append(Point("integration", "an albedo case", "cosine", 64, "samples", 0.0, 0.0, 3.3e-4, "closed form"))
    area = [Point("area-light", "Lambert sphere, rectangular light", "R2 low-discrepancy samples", n, "samples",
                  0.2 / n**0.9, 0.0, 1e-3 * n + 5e-4, "the same image with 4,096 light samples (RMS relative error)")
            for n in (1, 4, 16, 64)]  # fmt: skip
    tess = [Point("tessellation", "icosphere vs analytic sphere", mode, tri, "triangles", err / 2**k, 0.0,
                  2e-3 + 1e-6 * tri, "ray-cast analytic sphere")
            for k, tri in enumerate((20, 80, 320)) for mode, err in (("flat", 0.3), ("gouraud", 0.4), ("phong", 0.2))]
    prec = [Point("precision", "re-shading 64x64, float32 vs 64", "float64", 2000, "pixels", 0.0, 0.0, 1.1e-3, "f64"),
            Point("precision", "re-shading 64x64, float32 vs 64", "float32", 2000, "pixels", 2.1e-7, 0.0, 6.5e-4,
                  "f64")]  # fmt: skip
    ibl = []
    ref = "Monte Carlo with MIS at 512 spp in 8 passes (256 pixels of a 32² sphere)"
    for env in ("smooth sky", "studio"):
        ibl.append(Point("ibl", f"SH9 irradiance · {env}", "SH9 irradiance", 9, "coefficients", 0.01, 0.0, 6e-5,
                         "exact irradiance (times: 256 pixels of a 32² sphere, float32)", error_p95=0.02))  # fmt: skip
        for model, split in (("Lambert", 0.02), ("GGX α=0.2, F=1", 0.05)):
            case = f"{model} · {env}"
            ibl.append(Point("ibl", case, "split sum", 1, "lookup per lobe", split, 0.0, 4e-4, ref, error_p95=0.1,
                             reference_error=0.01))  # fmt: skip
            for spp in (8, 32):
                ibl.append(Point("ibl", case, "Monte Carlo, MIS", spp, "samples per pixel", 0.3 / spp**0.5, 0.0,
                                 1e-3 * spp, ref, 0.25 / spp**0.5, 0.9, error_p95=0.6 / spp**0.5,
                                 reference_error=0.01))  # fmt: skip
    # Floats that a text round trip would lose: NaN, a negative zero, subnormal and 17-digit values.
    prec[0].estimated_error = -0.0
    prec[1].coverage = 5e-324
    prec[1].error_p95 = 0.1 + 0.2
    pts = {"integration": integ, "area-light": area, "tessellation": tess, "precision": prec, "ibl": ibl}
    return {name: Study(name, f"the {name} study", pts[name]) for name in STUDY_NAMES}


def _no_study(monkeypatch):
    monkeypatch.setattr(accuracy, "run_studies", lambda **kw: pytest.fail(f"ran a study: {kw}"))


# --------------------------------------------------------------------------- the cache
def test_the_cache_round_trips_every_point_exactly(folder):
    for name, study in _studies().items():
        for quick in (True, False):
            path = cache.save_study(study, quick=quick, by="lighting-explorer report accuracy")
            assert path == cache.cache_path(name, quick) and os.path.dirname(path) == str(folder)
            saved = cache.load_study(name, quick=quick)
            assert _bits(saved.study.points) == _bits(study.points), name
            assert saved.study.name == name and saved.study.description == study.description
            assert saved.quick is quick and saved.by == "lighting-explorer report accuracy" and saved.path == path
    # One file per (study, settings, engine): ten files, named by study and settings.
    names = sorted(os.listdir(folder))
    assert len(names) == 2 * len(STUDY_NAMES)
    assert {n.rsplit("-", 1)[0] for n in names} == {f"accuracy-{s}-{q}" for s in STUDY_NAMES for q in ("quick", "full")}


def test_the_folder_is_the_variable_else_xdg_else_home(monkeypatch, tmp_path):
    monkeypatch.setenv(cache.CACHE_ENV, str(tmp_path / "own"))
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert cache.cache_dir() == str(tmp_path / "own")
    monkeypatch.setenv(cache.CACHE_ENV, "")
    assert cache.cache_dir() == str(tmp_path / "xdg" / "lighting-explorer")
    monkeypatch.setenv("XDG_CACHE_HOME", "relative/path")  # the XDG specification: absolute paths only
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert cache.cache_dir() == str(tmp_path / "home" / ".cache" / "lighting-explorer")


def test_a_changed_setting_or_engine_misses(folder, monkeypatch):
    study = _studies()["precision"]
    cache.save_study(study, quick=True, by="x")
    assert cache.load_study("precision", quick=True) is not None
    assert cache.load_study("precision", quick=False) is None  # the full settings: another key
    before = cache.cache_path("precision", True)

    real = accuracy._settings
    monkeypatch.setattr(accuracy, "_settings", lambda quick: {**real(quick), "precision_size": 64})
    assert cache.cache_path("precision", True) != before and cache.load_study("precision", quick=True) is None
    # A setting another study reads changes nothing for this one.
    monkeypatch.setattr(accuracy, "_settings", lambda quick: {**real(quick), "ibl_spp": [8]})
    assert cache.cache_path("precision", True) == before and cache.load_study("precision", quick=True) is not None
    monkeypatch.setattr(accuracy, "_settings", real)

    key = cache.engine_key()
    assert key["version"] and len(key["source_sha256"]) == 64
    for other in ({**key, "source_sha256": "0" * 64}, {**key, "version": key["version"] + ".post1"}):
        monkeypatch.setattr(cache, "engine_key", lambda other=other: other)
        assert cache.cache_path("precision", True) != before and cache.load_study("precision", quick=True) is None
        # The other engine's file put where this engine looks is refused too: the file repeats its key.
        cache.save_study(study, quick=True, by="x")
        os.replace(cache.cache_path("precision", True), before)
        monkeypatch.setattr(cache, "engine_key", lambda: key)
        assert cache.load_study("precision", quick=True) is None
        cache.save_study(study, quick=True, by="x")
        assert cache.load_study("precision", quick=True) is not None


@pytest.mark.parametrize(
    "content",
    [
        b"",
        b"\x89PNG\r\n\x1a\n not json",
        b"[1, 2, 3]",
        b'{"format": "something else", "points": []}',
        None,  # ours, but a point has a field of the wrong type
        "missing",  # ours, but a point lacks a field
        "foreign study",  # ours, but its points are of another study
    ],
)
def test_a_corrupt_or_foreign_cache_file_is_ignored_and_measured_again(folder, monkeypatch, content):
    study = _studies()["precision"]
    path = cache.save_study(study, quick=True, by="lighting-explorer report accuracy")
    with open(path, encoding="utf-8") as f:
        record = json.load(f)
    if content is None:
        record["points"][0]["cost"] = "many"
        content = json.dumps(record).encode()
    elif content == "missing":
        del record["points"][1]["seconds"]
        content = json.dumps(record).encode()
    elif content == "foreign study":
        record["points"][0]["study"] = "ibl"
        content = json.dumps(record).encode()
    with open(path, "wb") as f:
        f.write(content)
    assert cache.load_study("precision", quick=True) is None
    calls = []
    real = accuracy.run_studies

    def counting(**kw):
        calls.append(kw)
        return real(**kw)

    monkeypatch.setattr(accuracy, "run_studies", counting)
    _, _, _, _, measured = figures.make_figure("accuracy_precision", quick=True)
    assert calls == [{"quick": True, "only": ["precision"]}]
    assert measured["source_kind"] == "measured now" and measured["reproducible"] is False
    # ... and the measurement replaced the bad file.
    assert cache.load_study("precision", quick=True).by == "lighting-explorer figures"


def test_a_folder_that_cannot_be_written_is_not_written(tmp_path, monkeypatch):
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    monkeypatch.setenv(cache.CACHE_ENV, str(blocker / "cache"))
    assert cache.save_study(_studies()["precision"], quick=True, by="x") is None
    assert cache.load_study("precision", quick=True) is None
    assert blocker.read_text() == "not a folder"


# --------------------------------------------------------------------------- the figures
def _write_cache(quick):
    for study in _studies().values():
        assert cache.save_study(study, quick=quick, by="lighting-explorer report accuracy")


def test_the_full_study_is_preferred_to_the_quick_one(folder, monkeypatch):
    studies = _studies()
    cache.save_study(studies["precision"], quick=True, by="lighting-explorer report accuracy --quick")
    _no_study(monkeypatch)
    m = figures.make_figure("accuracy_precision", quick=True)[4]
    assert m["settings"] == "quick" and "report accuracy --quick (quick settings)" in m["source"]
    full = Study("precision", "", [dataclasses.replace(p, seconds=2 * p.seconds) for p in studies["precision"].points])
    cache.save_study(full, quick=False, by="lighting-explorer report accuracy")
    m = figures.make_figure("accuracy_precision", quick=True)[4]
    assert m["settings"] == "full" and m["ratio"] == pytest.approx(6.5e-4 / 1.1e-3)


def _panels(fig):
    return [ax for ax in fig.axes if ax.axison]


def test_panels_hold_what_the_studies_measured(folder, monkeypatch):
    _write_cache(quick=False)
    _no_study(monkeypatch)
    fig, _, _, _, m = figures.make_figure("accuracy_integration", quick=True)
    assert len(_panels(fig)) == 2 and m["points"] == 19  # two cases; 2 × 3 methods × 3 costs + one exact zero
    assert m["samples"] == "16, 64, 256"
    fig, _, _, _, m = figures.make_figure("accuracy_ibl", quick=True)
    assert len(_panels(fig)) == 3  # one panel per environment and the table of every model
    assert m["split_sum"] == {"smooth sky": {"Lambert": 0.02, "GGX α=0.2, F=1": 0.05},
                              "studio": {"Lambert": 0.02, "GGX α=0.2, F=1": 0.05}}  # fmt: skip
    assert m["sh9"] == {"smooth sky": 0.01, "studio": 0.01} and m["models"] == 2 and m["environments"] == 2
    m = figures.make_figure("accuracy_area_light", quick=True)[4]
    assert m["slope"] == pytest.approx(-0.9, abs=1e-12)  # the points fall exactly as n^-0.9
    m = figures.make_figure("accuracy_precision", quick=True)[4]
    assert m["ulps"] == pytest.approx(2.1e-7 * 2**24) and m["pixels"] == 2000
    m = figures.make_figure("accuracy_tessellation", quick=True)[4]
    assert m["finest"] == {"flat": 0.3 / 4, "gouraud": 0.4 / 4, "phong": 0.2 / 4}


def test_report_accuracy_saves_each_study_it_ran(folder, tmp_path, capsys):
    from explorer.reports import accuracy as report

    assert report.main(["--quick", "--only", "precision", "tessellation", "--no-figure", "--out", str(tmp_path)]) == 0
    assert "saved 2 studies for 'lighting-explorer figures' in" in capsys.readouterr().out
    with open(tmp_path / "accuracy.csv", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    for study in ("precision", "tessellation"):
        saved = cache.load_study(study, quick=True)
        assert saved.by == "lighting-explorer report accuracy --quick"
        csv_rows = [r for r in rows if r["study"] == study]
        assert [(p.method, p.cost, repr(p.error), repr(p.seconds)) for p in saved.study.points] == [
            (r["method"], int(r["cost"]), r["error"], r["seconds"]) for r in csv_rows]  # fmt: skip
        assert cache.load_study(study, quick=False) is None
    assert cache.load_study("ibl", quick=True) is None  # not run, not saved
    assert all(not math.isnan(p.error) for p in cache.load_study("precision", quick=True).study.points)

"""The accuracy figures drawn whole: from a cache, from a CSV file, measured with an empty cache (slow set; fast:
test_figures_accuracy.py)."""

import csv
import dataclasses
import json
import os

import pytest

pytest.importorskip("matplotlib")

from test_figures_accuracy import FIGURES, _no_study, _panels, _studies, _write_cache  # noqa: E402

from explorer import figures  # noqa: E402
from explorer.reports import cache  # noqa: E402
from lighting.validation import accuracy  # noqa: E402

pytestmark = pytest.mark.slow  # draws each accuracy figure up to four times and measures the quick studies


@pytest.fixture
def folder(tmp_path, monkeypatch):
    """An empty cache folder of its own for each test."""
    d = tmp_path / "cache"
    monkeypatch.setenv(cache.CACHE_ENV, str(d))
    return d


def test_figures_drawn_from_the_cache_are_bit_identical_and_measure_nothing(folder, tmp_path, monkeypatch):
    _write_cache(quick=False)
    _no_study(monkeypatch)
    outs = []
    for run in ("a", "b"):
        d = tmp_path / run
        figures.generate(d, formats=("png",), only=list(FIGURES.values()), dpi=40)
        outs.append(d)
    for name in FIGURES.values():
        assert (outs[0] / f"{name}.png").read_bytes() == (outs[1] / f"{name}.png").read_bytes(), name
        rec = json.loads((outs[0] / f"{name}.json").read_text(encoding="utf-8"))
        assert rec["deterministic"] is True and rec["nondeterministic_reason"] is None, name
        m = rec["measured"]
        assert (m["source_kind"], m["settings"], m["reproducible"]) == ("cache", "full", True), name
        assert m["measured_by"] == "lighting-explorer report accuracy", name
        assert "measured by lighting-explorer report accuracy (full settings)" in rec["caption"], name


def test_accuracy_csv_draws_all_five_without_measuring(folder, tmp_path, monkeypatch):
    rows = [dataclasses.asdict(p) for st in _studies().values() for p in st.points]
    path = tmp_path / "accuracy.csv"
    with open(path, "w", newline="", encoding="utf-8") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    _no_study(monkeypatch)
    out = tmp_path / "out"
    assert figures.main(["--out", str(out), "--quick", "--only", *FIGURES.values(), "--accuracy-csv", str(path)]) == 0
    for study, name in FIGURES.items():
        rec = json.loads((out / f"{name}.json").read_text(encoding="utf-8"))
        assert rec["deterministic"] is True and rec["measured"]["source_kind"] == "csv", name
        assert rec["measured"]["points"] == len(_studies()[study].points), name
    assert not folder.exists() or os.listdir(folder) == []  # nothing measured, nothing saved


def test_with_an_empty_cache_each_figure_measures_its_quick_study_only(folder, monkeypatch, quick_accuracy_studies):
    calls = []
    real = accuracy.run_studies
    measured = {s.name: s for s in quick_accuracy_studies}  # run_studies(quick=True), once per session

    def counting(**kw):
        calls.append(kw)
        if kw.get("quick") is True and set(kw) == {"quick", "only"} and set(kw["only"]) <= set(measured):
            return [measured[name] for name in kw["only"]]  # what real(**kw) measures, already measured
        return real(**kw)

    monkeypatch.setattr(accuracy, "run_studies", counting)
    for study, name in FIGURES.items():
        fig, spec, _, _, m = figures.make_figure(name, quick=True)
        assert calls[-1] == {"quick": True, "only": [study]}, name
        assert (m["source_kind"], m["settings"], m["reproducible"]) == ("measured now", "quick", False), name
        assert m["measured_by"] == "lighting-explorer figures", name
        assert spec.nondeterministic and "wall-clock" in spec.nondeterministic
        assert 1 <= len(_panels(fig)) <= 6, name
        assert tuple(fig.get_size_inches()) == spec.size_in
        # The measurement is saved: the next drawing reads it.
        saved = cache.load_study(study, quick=True)
        assert saved.by == "lighting-explorer figures" and len(saved.study.points) == m["points"], name
    assert len(calls) == len(FIGURES)
    _no_study(monkeypatch)
    for name in FIGURES.values():
        assert figures.make_figure(name, quick=True)[4]["source_kind"] == "cache", name

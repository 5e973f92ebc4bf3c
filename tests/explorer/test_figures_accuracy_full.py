"""The accuracy figures drawn whole from a cache and from a CSV file (slow set; fast: test_figures_accuracy.py)."""

import csv
import dataclasses
import json
import os

import pytest

pytest.importorskip("matplotlib")

from test_figures_accuracy import FIGURES, _no_study, _studies, _write_cache  # noqa: E402

from explorer import figures  # noqa: E402
from explorer.reports import cache  # noqa: E402

pytestmark = pytest.mark.slow  # draws each accuracy figure three times


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

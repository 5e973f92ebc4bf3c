"""docs/lights.md's examples run as written (slow set; fast: test_envlight.py)."""

import re
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow  # the image-based lighting section of docs/lights.md, at its sizes

ROOT = Path(__file__).resolve().parents[2]


def test_docs_section_runs_and_prints_the_furnace(tmp_path, monkeypatch, capsys):
    text = (ROOT / "docs" / "lights.md").read_text(encoding="utf-8")
    section = text[text.index("## Environment lights: image-based lighting") :]
    blocks = re.findall(r"```python\n(.*?)```", section, flags=re.S)
    assert len(blocks) == 2
    monkeypatch.chdir(tmp_path)
    for code in blocks:
        exec(compile(code, "docs/lights.md", "exec"), {})
    out = capsys.readouterr().out.splitlines()
    first = [float(x) for x in out[0].split()]
    assert first[0] == pytest.approx(0.5, rel=1e-9) and first[1] == 1.0
    assert out[1].startswith("64 samples per pixel, median error ")

"""docs/lights.md's examples run as written (slow set; fast: test_envfiles.py)."""

import re
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow  # the "Environment files and skies" section of docs/lights.md, at its sizes

ROOT = Path(__file__).resolve().parents[2]


def test_docs_example_runs(tmp_path, monkeypatch):
    text = (ROOT / "docs" / "lights.md").read_text(encoding="utf-8")
    section = text[text.index("## Environment files and skies") :]
    blocks = re.findall(r"```python\n(.*?)```", section, flags=re.S)
    assert blocks
    monkeypatch.chdir(tmp_path)
    for code in blocks:
        exec(compile(code, "docs/lights.md", "exec"), {})

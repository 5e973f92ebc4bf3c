"""Numbers in the README and the documentation pages come from the product, not from a copy by hand.

A count of figures written as "N figures" must be the figure set's own count, and no page may claim how
long the figure set or the documentation build takes unless the number is generated while the site is
built (a ``{{ figures.… }}`` placeholder, filled by ``explorer/figures/mkdocs_hook.py``): such a time
depends on the machine that runs the command, which prints it itself.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from explorer.figures import figure_names

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]

FIGURE_COUNT = re.compile(r"\b(\d+)\s+(?:lecture-note\s+|slide\s+)?figures\b")
# What a time would be claimed for: the whole figure set, or the documentation build that draws it.
SUBJECT = re.compile(
    r"lighting-explorer figures(?![^\n]*--only)|figure set|the figures\b|all (?:the )?figures|\d+ figures|mkdocs build"
    r"|every figure|whole set|draws everything|docs build|documentation build|builds? (?:the|this) site|the build\b",
    re.I,
)
TIME = re.compile(
    r"\b\d+(?:[.,]\d+)?\s*(?:s|sec|secs|seconds?|min|mins|minutes?|h|hours?)\b"
    r"|\b(?:a|one|two|three|a few|several)\s+(?:seconds?|minutes?|hours?)\b|\bin seconds\b",
    re.I,
)
PLACEHOLDER = re.compile(r"(?<!\\)\{\{\s*figures\.[^}]*\}\}")


def _paragraphs(text: str):
    """The text's paragraphs (blank-line separated) with the line each starts on; each code line on its own."""
    start, lines, in_code = None, [], False
    for i, line in enumerate(text.splitlines() + [""], 1):
        if line.lstrip().startswith(("```", "~~~")):
            in_code = not in_code
            if lines:
                yield start, " ".join(lines)
            start, lines = None, []
            continue
        if in_code:
            yield i, line
            continue
        if not line.strip():
            if lines:
                yield start, " ".join(lines)
            start, lines = None, []
        else:
            start = start or i
            lines.append(line.strip())


def figure_counts(text: str) -> list[tuple[int, int]]:
    """Each "N figures" written in ``text``, as (line, N)."""
    return [(line, int(m.group(1))) for line, para in _paragraphs(text) for m in FIGURE_COUNT.finditer(para)]


def timing_claims(text: str) -> list[tuple[int, str]]:
    """Each time claimed for the figure set or the docs build in ``text`` (not generated), as (line, text)."""
    found = []
    for line, para in _paragraphs(text):
        para = PLACEHOLDER.sub("", para)
        if SUBJECT.search(para):
            found += [(line, " ".join(para[max(0, m.start() - 60) : m.end() + 20].split()))
                      for m in TIME.finditer(para)]  # fmt: skip
    return found


# --------------------------------------------------------------------------- the checks themselves


def test_finders_see_counts_and_times_and_pass_generated_or_unrelated_text():
    text = (
        "Writes 36 figures (47 s on 2 cores).\n\n"
        "```bash\nlighting-explorer figures --out f   # all of them, ~1 min\n```\n\n"
        "The build draws the figure set (about a minute on two cores).\n\n"
        "The gallery has {{ figures.count }} figures; `lighting-explorer figures` prints the time it took.\n\n"
        "lighting-explorer figures --only ibl_error   # one figure, 3 s\n\n"
        "A re-shade takes 14 ms; the report takes 2 min."
    )
    assert figure_counts(text) == [(1, 36)]
    assert [line for line, _ in timing_claims(text)] == [1, 4, 7]
    assert "47 s" in timing_claims(text)[0][1]


@pytest.mark.parametrize("path", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_figure_counts_agree_with_the_figure_set(path):
    n = len(figure_names())
    wrong = [f"line {line}: {count} figures" for line, count in figure_counts(path.read_text(encoding="utf-8"))
             if count != n]  # fmt: skip
    assert wrong == [], f"{path.name}: the figure set has {n} figures (explorer.figures.figure_names())"


@pytest.mark.parametrize("path", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_no_hand_copied_time_for_the_figure_set_or_the_docs_build(path):
    claims = [f"line {line}: {snippet}" for line, snippet in timing_claims(path.read_text(encoding="utf-8"))]
    assert claims == [], (
        f"{path.name}: a time for the figure set or the docs build depends on the machine; say which command "
        "prints it (lighting-explorer figures does) or generate it"
    )


def test_every_generated_number_names_a_figure_of_the_set():
    # The values themselves exist only once the figures are drawn (the docs build stops, naming the page and the
    # placeholder, when one is missing); here, without drawing, every placeholder must name a registered figure.
    names = set(figure_names())
    used = {
        (path.name, m.group(1).split(".")[0])
        for path in PAGES
        for m in re.finditer(r"(?<!\\)\{\{\s*figures\.([\w.]+)", path.read_text(encoding="utf-8"))
    }
    assert {page for page, _ in used} >= {"lights.md", "getting-started.md"}
    assert sorted((page, name) for page, name in used if name != "count" and name not in names) == []

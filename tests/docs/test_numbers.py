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
PLACEHOLDER = re.compile(r"(?<!\\)\{\{\s*(?:figures|measured)\.[^}]*\}\}")


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


def test_every_measured_number_names_a_measurement_and_a_value_it_returns():
    # The pages' {{ measured.NAME.KEY:FORMAT }} are filled while the site is built; each must name one of the hook's
    # measurements and a value it returns, in a format that value takes.
    from explorer.figures.mkdocs_hook import MEASUREMENTS, measured

    used = [
        (path.name, m.group(0), m.group(1), m.group(2), m.group(3))
        for path in PAGES
        for m in re.finditer(
            r"(?<!\\)\{\{\s*measured\.(\w+)\.(\w+)(?::([^}]*?))?\s*\}\}", path.read_text(encoding="utf-8")
        )
    ]
    assert {name for _, _, name, _, _ in used} == set(MEASUREMENTS)
    for page, text, name, key, spec in used:
        values = measured(name)
        assert key in values, (page, text, sorted(values))
        format(values[key], spec or "")


# --------------------------------------------------------------------------- samples of a command's output


def _block_after(text: str, intro: str) -> list[str]:
    """The lines of the first fenced block after the sentence ``intro``."""
    start = text.index(intro)
    lines = text[start:].split("```", 2)[1].splitlines()
    return lines[1:]  # the fence's language tag


def test_the_stability_sample_has_the_rows_and_counts_the_report_prints():
    # A run takes minutes (80-digit references), so the page shows one run's output; what does not depend on the
    # run must still be what the report prints today: its rows in order, the values per row, the summary's counts.
    import collections

    from explorer.reports.stability import CASE_ORDER, MODEL_ORDER
    from lighting.validation import stability as st

    text = (ROOT / "docs" / "stability.md").read_text(encoding="utf-8")
    block = _block_after(text, "one default run of `lighting-explorer report stability`")
    assert block[:4] == [
        "Numerical stability on stiff and extreme cases: engine vs an 80-digit mpmath reference",
        "computed from the same binary inputs.  Bound: relative error <= 8 max(κ,1) u,",
        "u = 2^-24 (float32), 2^-53 (float64); κ = condition number of the formula at that point",
        "(amplification of relative input perturbations).  err/κu is the worst ratio err / (max(κ,1) u).",
    ]
    dtypes = 2
    cases = st.brdf_cases(False)
    lcases, lspecs = st.light_cases(False), st.light_specs()
    specs = st.brdf_specs()
    per_case = collections.Counter(c.family for c in cases)
    per_model = collections.Counter(s.family for s in specs)
    expected = {(m, f): per_case[f] * per_model[m] * 3 * dtypes for m in per_model for f in per_case}
    for c in lcases:
        key = (lspecs[c.spec].family, c.family)
        expected[key] = expected.get(key, 0) + 2 * dtypes
    order = sorted(expected, key=lambda k: (MODEL_ORDER.index(k[0]), CASE_ORDER.index(k[1])))

    rows, model = [], None
    for line in block:
        m = re.match(r"(.{19}) (.{11}) +(\d+) +(\d+) \|", line)
        if m:
            model = m.group(1).strip() or model
            rows.append((model, m.group(2).strip(), int(m.group(3))))
    assert [(a, b) for a, b, _ in rows] == order
    assert {(a, b): n for a, b, n in rows} == expected
    total = sum(expected.values())
    summary = (f"{total} values in 2 dtypes: per dtype {len(cases)} (n, l, v) inputs x {len(specs)} BRDF variants "
               f"x 3 forms and {len(lcases)} light inputs x 2 forms;")  # fmt: skip
    assert any(line.startswith(summary) for line in block), summary

    # The prose after the table quotes the same run: the worst ratio, the ill-conditioned and edge counts, and
    # the six classes of values add up to the run's total.
    worst = re.search(r"worst err/\(max\(κ,1\) u\): ([\d.]+)", "\n".join(block)).group(1)
    edge, ill = re.search(r"edge points .*?: (\d+); ill-conditioned points .*?: (\d+)", "\n".join(block)).groups()
    after = " ".join(text[text.index("In that run every row met the bound") :].split("\n\n")[0].split())
    assert f"worst ratio was {worst} " in after
    counts = {name: int(n.replace(" ", "")) for n, name in re.findall(
        r"(\d[\d ]*\d|\d) (normal values|ill-conditioned|edge points|exact zeros|below the normal range|beyond)",
        after)}  # fmt: skip
    assert counts["ill-conditioned"] == int(ill) and counts["edge points"] == int(edge)
    assert sum(counts.values()) == total and len(counts) == 6
    beyond = {"Oren-Nayar", "Ward", "Ashikhmin-Shirley", "Disney", "CT correlated", "CT anisotropic", "CT conductor"}
    assert beyond <= set(per_model)
    assert f"the {sum(per_model[f] for f in beyond)} variants of the models beyond the slides" in after


def test_the_analysis_page_generates_both_audits_and_they_split_the_default_cases():
    import html as html_lib

    from explorer.figures.mkdocs_hook import audit_markdown
    from lighting.analysis.audit import audit, beyond_slides_cases, default_cases

    text = (ROOT / "docs" / "analysis.md").read_text(encoding="utf-8")
    assert "<!-- audit: slides -->" in text and "<!-- audit: beyond_slides -->" in text
    table = audit(samples=64)

    def labels(cases):
        return [
            html_lib.unescape(x) for x in re.findall(r"<tr><td>(.*?)</td>", audit_markdown(cases=cases, table=table))
        ]

    beyond = [c.label for c in beyond_slides_cases()]
    assert labels("beyond_slides") == beyond
    assert labels("slides") + beyond == labels("default") == [c.label for c in default_cases()]


# --------------------------------------------------------------------------- sizes: the code's own budget constants

SIZE = re.compile(r"\d[\d,. ]*\s?(?:bytes?|KB|MB|GB|MiB|GiB)\b(?: per)?")


def _prose(name: str) -> str:
    """A page with its whitespace collapsed (so a phrase may break across lines)."""
    return " ".join((ROOT / "docs" / name).read_text(encoding="utf-8").split())


def _size_phrases() -> dict[str, list[str]]:
    """Each page's sizes, written from the constants the code checks them with (what the page must say)."""
    import math

    import explorer.figures as figures
    from explorer.commands.sphere import SPHERE_BYTES_PER_PIXEL
    from explorer.reports import options
    from lighting import _budget
    from lighting.files import brdf_format, merl
    from lighting.render.raster import RASTER_BYTES_PER_PIXEL
    from lighting.render.raycast import RAYCAST_BYTES_PER_PIXEL
    from lighting.render.renderer import RENDER_BYTES_PER_PIXEL
    from lighting.scene import budget as b

    gib, mib = 1024**3, 1024**2
    default = _budget.DEFAULT_MEMORY_BUDGET
    merl_per_byte, _ = b.BRDF_FILE_BYTES[".binary"]
    brdf_per_byte, brdf_fixed = b.BRDF_FILE_BYTES[".brdf"]
    brdf_limit = "lighting.files.brdf_format.MAX_FILE_BYTES"
    largest_figure_px = default / figures.BYTES_PER_PIXEL / math.prod(figures.UNDECLARED_FIGURE_IN)

    def image(side):
        return side**2 * (b.BYTES_PER_PIXEL + 2 * b.BYTES_PER_PIXEL_PER_OBJECT)

    def _panorama_bytes(rows):
        """A ``2 rows × rows`` file's part of a scene's estimate under the dominant lights: prefiltered, and the
        dominant lights' own (reading the file is checked alone, before)."""
        px = 2 * rows * rows
        prefilter = b.PREFILTER_BYTES_PER_PIXEL * min(px, b.PREFILTER_LEVEL_PIXELS)
        prefilter += b.PREFILTER_LARGE_BYTES_PER_PIXEL * max(px - b.PREFILTER_LEVEL_PIXELS, 0)
        return prefilter + b.DOMINANT_BYTES + b.DOMINANT_BYTES_PER_PIXEL * px

    return {
        "scenes.md": [
            f"a MERL table {merl_per_byte} bytes per byte of the file, a `.brdf` file {brdf_per_byte} bytes per byte "
            f"plus {brdf_fixed // mib} MiB (`lighting.scene.budget.BRDF_FILE_BYTES`",
            f"memory budget: **{default // gib} GiB** by default (`lighting._budget.DEFAULT_MEMORY_BUDGET`",
            f"{b.BYTES_PER_SCENE_FILE_BYTE} bytes per byte (`BYTES_PER_SCENE_FILE_BYTE`)",
            f"{b.BYTES_PER_TRIANGLE} bytes per triangle (`BYTES_PER_TRIANGLE`;",
            f"{b.BYTES_PER_MESH_FILE_BYTE} bytes per byte of the file to read it (`BYTES_PER_MESH_FILE_BYTE`;",
            f"then {b.BYTES_PER_TRIANGLE} bytes per triangle held (`BYTES_PER_TRIANGLE`)",
            f"MERL `.binary`: {merl_per_byte} bytes per byte of the file; `.brdf`: {brdf_per_byte} bytes per byte plus "
            f"{brdf_fixed // mib} MiB (`BRDF_FILE_BYTES`)",
            f"{b.ENVIRONMENT_BYTES_PER_PIXEL} bytes per pixel its header declares to read it "
            f"(`ENVIRONMENT_BYTES_PER_PIXEL`), then {b.ENVIRONMENT_HELD_BYTES_PER_PIXEL} held "
            "(`ENVIRONMENT_HELD_BYTES_PER_PIXEL`)",
            f"{b.PREFILTER_BYTES_PER_PIXEL} bytes per pixel of the prefiltered image up to "
            f"{b.PREFILTER_LEVEL_PIXELS // 256} × 256 pixels (`PREFILTER_BYTES_PER_PIXEL`, `PREFILTER_LEVEL_PIXELS`), "
            f"{b.PREFILTER_LARGE_BYTES_PER_PIXEL} bytes per pixel beyond (`PREFILTER_LARGE_BYTES_PER_PIXEL`:",
            f"add {b.DOMINANT_BYTES // mib} MiB and {b.DOMINANT_BYTES_PER_PIXEL} bytes per pixel (`DOMINANT_BYTES`, "
            "`DOMINANT_BYTES_PER_PIXEL`:",
            # a 2048 × 1024 panorama under the default method fits the default budget
            "or a 2048 × 1024 panorama" * (_panorama_bytes(1024) <= default),
            f"`width × height × ({b.BYTES_PER_PIXEL} + {b.BYTES_PER_PIXEL_PER_OBJECT} × objects)` bytes plus the "
            "meshes (`BYTES_PER_PIXEL`, `BYTES_PER_PIXEL_PER_OBJECT`)",
            f"counts {b.BYTES_PER_SAMPLE_EVALUATION} bytes (`BYTES_PER_SAMPLE_EVALUATION`)",
            # the examples the default budget allows (two objects at 2048² fit; at 2560² they would not)
            "a 2048 × 2048 image of two objects" * (image(2048) <= default < image(2560)),
            f"a {default / b.BYTES_PER_TRIANGLE / 1e6:.1f}-million-triangle mesh",
            f"{default // b.BYTES_PER_SAMPLE_EVALUATION // 10**6} million light-sample evaluations",
            # a file of the examples
            "8 KB" * (round((ROOT / "lighting/scene/examples/daylight_sky.hdr").stat().st_size / 1000) == 8),
        ],
        "images.md": [
            f"{RASTER_BYTES_PER_PIXEL}, {RAYCAST_BYTES_PER_PIXEL} and {RENDER_BYTES_PER_PIXEL} bytes per pixel: "
            "`lighting.render.raster.RASTER_BYTES_PER_PIXEL`, `lighting.render.raycast.RAYCAST_BYTES_PER_PIXEL` and "
            "`lighting.render.renderer.RENDER_BYTES_PER_PIXEL`",
            f"({default // gib} GiB, `lighting._budget.DEFAULT_MEMORY_BUDGET`,",
            f"about {round(math.sqrt(default / RENDER_BYTES_PER_PIXEL), -1):,.0f}² pixels for a first render",
        ],
        "cli.md": [
            f"over the budget: {default // gib} GiB (`lighting._budget.DEFAULT_MEMORY_BUDGET`)",
            f"({SPHERE_BYTES_PER_PIXEL} bytes per pixel, `explorer.commands.sphere.SPHERE_BYTES_PER_PIXEL`)",
            f"({figures.BYTES_PER_PIXEL} bytes per pixel, `explorer.figures.BYTES_PER_PIXEL`: up to about "
            f"{math.floor(math.sqrt(largest_figure_px) / 10) * 10:,} "
            f"dpi at {default // gib} GiB)",
            f"{figures.WORKER_BYTES // mib} MiB per worker (`explorer.figures.WORKER_BYTES`)",
            f"({options.WORKER_BYTES // mib} MiB each, `explorer.reports.options.WORKER_BYTES`,",
        ],
        "brdf-files.md": [
            f"at most {brdf_format.MAX_FILE_BYTES // mib} MiB of UTF-8 text (`{brdf_limit}`",
            f"at most {brdf_format.CHUNK} direction pairs (`lighting.files.brdf_format.CHUNK`)",
        ],
        "merl.md": [
            f"{12 + 8 * 3 * merl.BINS:,} bytes".replace(",", " "),
            f"(4 × 8 bytes per value of the file, about {round(4 * 8 * 3 * merl.BINS / 1e6)} MB, at the peak)",
            f"2 × 8 bytes per value of the file: about {round(2 * 8 * 3 * merl.BINS / 1e6)} MB held",
            f"the table is charged at {merl_per_byte} bytes per byte of the file "
            "(`lighting.scene.budget.BRDF_FILE_BYTES`)",
            f"# {round(8 * 3 * merl.BINS / 1e6)} MB",
        ],
    }


# Sizes that are definitions or a message's own words, not figures of the code's budget.
SIZE_ALLOWED = {
    "scenes.md": ["a 1 GB sparse file", "a 50-byte `.hdr`"],
    "merl.md": ["8015 bytes; a MERL file has 34992012", "byte 8015: the file is truncated: 8015 bytes"],
}


@pytest.mark.parametrize("name", ["scenes.md", "images.md", "cli.md", "brdf-files.md", "merl.md"])
def test_memory_sizes_on_the_pages_are_the_codes_constants(name):
    text = _prose(name)
    phrases = _size_phrases()[name]
    missing = [p for p in phrases if not p or p not in text]
    assert missing == [], f"{name}: these sizes are not what the code's constants give"
    # Every size on the page is one of those phrases, an allowed definition, or inside a command's sample output
    # checked elsewhere (the refusals below and in test_the_size_refusal_samples_are_the_messages_printed).
    covered = [
        (m.start(), m.end()) for p in phrases + SIZE_ALLOWED.get(name, []) for m in re.finditer(re.escape(p), text)
    ]
    samples = [(m.start(), m.end()) for m in re.finditer(r"over the memory budget of[^`]*?\(--memory-budget\)", text)]
    samples += [(m.start(), m.end()) for m in re.finditer(r"needs about [\d.]+ GiB \(", text)]
    samples += [(m.start(), m.end()) for m in re.finditer(r"counted as \d+ bytes each", text)]
    loose = [m.group(0) for m in SIZE.finditer(text)
             if not any(a <= m.start() and m.end() <= b for a, b in covered + samples)]  # fmt: skip
    assert loose == [], f"{name}: sizes that name no constant of the code and no command that measures them"


def test_the_size_refusal_samples_are_the_messages_printed(capsys):
    from explorer.cli import main
    from tests.scene import test_scene

    assert main(["sphere", "--size", "100000"]) == 2
    err = capsys.readouterr().err.strip()
    assert f"$ lighting-explorer sphere --size 100000\n{err}\n" in (ROOT / "docs" / "cli.md").read_text(
        encoding="utf-8"
    )
    # scenes.md shows the refusals test_scene's budget test provokes; its expected messages are the page's lines.
    import inspect

    source = inspect.getsource(test_scene.test_image_size_samples_and_meshes_are_refused_before_allocating)
    expected = re.findall(r'assert "(: [^"]+)" in err', source)
    text = (ROOT / "docs" / "scenes.md").read_text(encoding="utf-8")
    block = _block_after(text, "the messages\n`tests/scene/test_scene.py::test_image_size_samples_and_meshes")
    assert len(block) == 3
    for line, want in zip(block, expected, strict=False):
        assert line.startswith("scene.toml" + want), (line, want)
        assert line.endswith("over the memory budget of 2.0 GiB; reduce it or raise the budget (--memory-budget)")


# --------------------------------------------------------------------------- errors measured by a test


def _agrees(page: str, value: float) -> bool:
    """Whether ``value`` is the page's number ``page`` ("1.6e-6", "64 %") to the digits the page prints.

    Below 1e-9 the reference itself is not converged (its change when every count doubles is about 1e-10), so
    there the page's number and the value need only both be below it.
    """
    page = page.strip()
    if page.endswith("%"):
        number, scale = float(page[:-1]), 0.01
        digits = page[:-1].strip()
    else:
        number, scale, digits = float(page), 1.0, page
    number *= scale
    if abs(number) < 1e-9:
        return abs(value) < 1e-9
    mantissa = digits.split("e")[0]
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    exponent = int(digits.split("e")[1]) if "e" in digits else 0
    half_unit = 0.5 * 10.0 ** (exponent - decimals) * scale
    return abs(value - number) <= 1.05 * half_unit


@pytest.mark.slow
def test_the_anisotropic_quadrature_table_is_what_the_engine_measures():
    import dataclasses
    import math

    from lighting.integrate import directional_albedo
    from lighting.models.base import BRDF
    from tests.integrate.test_quadrature_aniso import MODELS, reference_albedo

    class Round(BRDF):
        """``model`` reporting its lobe without the ellipse: the round rule's nodes on the same function."""

        def __init__(self, model):
            self.model = model

        def lobe(self):
            return dataclasses.replace(self.model.lobe(), widths=None, quadrature_widths=None)

        def eval_cos_geometry(self, g):
            return self.model.eval_cos_geometry(g)

    text = (ROOT / "docs" / "numerics.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| (\d+):1 \| ([^|]+) \| ([^|]+) \| ([^|]+) \| ([^|]+) \|$", text, re.M)
    assert [r[0] for r in rows] == ["1", "10", "100", "1000"]
    wrong = []
    for ratio, *cells in rows:
        ax, ay = 0.3, 0.3 / int(ratio)
        worst_round = 0.0
        for name, cell in zip(MODELS, cells[:3], strict=True):
            model, err = MODELS[name](ax, ay), 0.0
            for theta in map(math.radians, (0.0, 45.0, 80.0)):
                ref = reference_albedo(model, ax, ay, theta)
                err = max(err, abs(directional_albedo(model, theta)[0] - ref) / ref)
                if ratio != "1":
                    worst_round = max(worst_round, abs(directional_albedo(Round(model), theta)[0] - ref) / ref)
            if not _agrees(cell, err):
                wrong.append(f"{ratio}:1 {name}: page {cell.strip()}, measured {err:.2g}")
        if ratio == "1":
            assert cells[3].strip() == "the same rule"
        elif not _agrees(cells[3], worst_round):
            wrong.append(f"{ratio}:1 round rule: page {cells[3].strip()}, measured {worst_round:.2g}")
    assert wrong == []


@pytest.mark.slow
def test_the_accuracy_sample_has_the_cases_methods_and_units_the_report_prints():
    # A full run takes minutes, so the page shows one run's summary (the docs build shows the saved studies'
    # instead when there are any); its cases, thresholds, methods and units must still be what the report prints.
    from explorer.reports.accuracy import format_summary
    from lighting.validation.accuracy import run_studies, summary

    text = (ROOT / "docs" / "accuracy.md").read_text(encoding="utf-8")
    block = _block_after(text, "one run of `lighting-explorer report accuracy` with the full settings")
    studies = run_studies(quick=True, only=["integration", "area-light", "tessellation", "precision"])
    rows = summary(studies)
    assert block[:2] == format_summary(rows).splitlines()[1:3]

    def size_free(case):
        return re.sub(r"\d+x\d+", "NxN", case)

    methods = {}
    for st in studies:
        for p in st.points:
            methods.setdefault(size_free(p.case), set()).add(p.method)
    units = {size_free(r["case"]): r["cost_unit"] for r in rows if r["method"] is not None}
    sample = [
        (size_free(line[2:64].strip()), line[65:71].strip(), line[73:101].strip(), line[102:116].split()[-1])
        for line in block[2:]
    ]
    assert [(c, t) for c, t, _, _ in sample] == [(size_free(r["case"]), f"{100 * r['threshold']:g} %") for r in rows]
    for case, _, method, unit in sample:
        assert method in methods[case], (case, method, sorted(methods[case]))
        assert unit == units[case], (case, unit)


def test_the_accuracy_summary_falls_back_to_the_pages_run_without_saved_studies(tmp_path):
    from explorer.figures.mkdocs_hook import _ACCURACY_RE, accuracy_summary

    text = (ROOT / "docs" / "accuracy.md").read_text(encoding="utf-8")
    inside = _ACCURACY_RE.search(text).group(1)
    assert "one run of `lighting-explorer report accuracy`" in inside and "Cheapest method" in inside
    assert accuracy_summary(inside, folder=str(tmp_path)) == inside  # an empty cache: nothing saved


def _module_constants(path: str) -> dict:
    """The module-level constants (``NAME = literal``) of a source file, read without importing it (no Qt)."""
    import ast

    tree = ast.parse((ROOT / path).read_text(encoding="utf-8"))
    found = {}
    for node in tree.body:
        if isinstance(node, (ast.Assign, ast.AnnAssign)) and node.value is not None:
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for target in targets:
                if isinstance(target, ast.Name):
                    try:
                        found[target.id] = ast.literal_eval(node.value)
                    except ValueError:
                        pass
    return found


def test_the_explorers_timing_constants_and_targets_on_its_page_are_the_codes():
    window = _module_constants("explorer/qt/window.py")
    targets = _module_constants("explorer/bench/window.py")["TARGETS_MS"]
    text = _prose("explorer.md")
    for phrase in (
        f"rested for {window['IDLE_MS']} ms with the button still held (`explorer.qt.window.IDLE_MS`)",
        f"(`explorer.qt.window.REFINE_MS`, {window['REFINE_MS']} ms), each tick spends "
        f"`REFINE_BUDGET` ({window['REFINE_BUDGET']:g} s)",
        f"The ticks begin once the views have rested for `IDLE_MS` ({window['IDLE_MS']} ms) after their last change",
        f"| drag | a light slider's value changed while held … the lit sphere's panel repainted "
        f"| ≤ {targets['drag_ms']:g} ms |",
        f"| release | the slider released … the lobe and the plots repainted | ≤ {targets['release_ms']:g} ms |",
        f"| model switch | another model chosen in the model box … every view repainted "
        f"| ≤ {targets['model_switch_ms']:g} ms |",
    ):
        assert phrase in text, phrase


def test_the_grid_of_normals_on_the_lights_page_is_the_codes():
    # The rows per lobe width, the narrow lobes' width and sample factor, and the claim that GGX α = 0.05 fits a
    # 512² sphere's grid (its points at most a quarter of the sphere's pixels, as the method decides).
    import math

    from lighting.integrate._normalgrid import GRID_DENSITY, GRID_SHARE, MAX_SPACING, grid_points, grid_spacing
    from lighting.integrate.dominant import (
        DOMINANT_SAMPLES,
        HALF_GRID_DENSITY,
        MID_FACTOR,
        MID_LOBE,
        NARROW_FACTOR,
        NARROW_GRID_DENSITY,
        ROUND_LOBE_WIDTH,
        WIDE_LOBE,
    )
    from lighting.integrate.ibl import lobe_sigma
    from lighting.models.brdf import CookTorrance
    from lighting.validation.accuracy import ibl_sphere

    text = _prose("lights.md")
    words = {2: "two", 4: "four", 8: "eight", 16: "sixteen"}
    factor = f"{words[NARROW_FACTOR]} or {words[MID_FACTOR]}"
    for phrase in (
        f"(rows every `σ/{GRID_DENSITY}`, at most {math.degrees(MAX_SPACING):g}°, from the view to the silhouette",
        f"A lobe narrower than {WIDE_LOBE:g} rad, whose points take {factor} "
        f"times the samples, has rows every `σ/{NARROW_GRID_DENSITY}` (`NARROW_GRID_DENSITY`).",
        f"A narrow GGX or Beckmann lobe has rows every `σ/{HALF_GRID_DENSITY}` (`HALF_GRID_DENSITY`): GGX at α = 0.05 "
        "then fits a 512² sphere's grid",
        f"the split sum's round lobe of `{ROUND_LOBE_WIDTH:g} σ` (`ROUND_LOBE_WIDTH`)",
        "at most a quarter of the pixels' count of points",
        f"({NARROW_FACTOR * DOMINANT_SAMPLES} for a lobe narrower than {MID_LOBE:g} rad, "
        f"{MID_FACTOR * DOMINANT_SAMPLES} from there up to {WIDE_LOBE:g} rad:",
        f"({NARROW_FACTOR * DOMINANT_SAMPLES} for a lobe narrower than {MID_LOBE:g} rad, "
        f"{MID_FACTOR * DOMINANT_SAMPLES} up to {WIDE_LOBE:g} rad)",
    ):
        assert phrase in text, phrase
    assert GRID_SHARE == 0.25
    sigma = lobe_sigma(CookTorrance(1.0, 0.05, 1.0, ndf="ggx", fresnel="none").lobe())
    _, n, _ = ibl_sphere(512)
    assert sigma < WIDE_LOBE
    assert grid_points(grid_spacing(sigma, HALF_GRID_DENSITY)) <= GRID_SHARE * n.shape[0]


def test_the_explorers_key_table_is_the_windows_key_table():
    # The page's table under "### Keys", row by row, is explorer.app.captions.KEYS: each key as its Qt key
    # sequence and its words (a "|" in the words escaped for the Markdown table).
    from explorer.app.captions import KEYS

    text = (ROOT / "docs" / "explorer.md").read_text(encoding="utf-8")
    section = text[text.index("\n### Keys\n") :].split("\n## ", 1)[0]
    rows = re.findall(r"^\| `([^`]+)` \| (.+?) \|$", section, re.M)
    assert [(key, words.replace("\\|", "|")) for key, words in rows] == [(k.key, k.description) for k in KEYS]


@pytest.mark.slow
def test_the_merl_pages_numbers_are_what_the_readers_give(tmp_path, monkeypatch, capsys):
    import numpy as np

    import lighting
    from lighting.brdf import BlinnPhong, Lambert
    from lighting.files.merl import tabulate_merl, write_merl

    text = (ROOT / "docs" / "merl.md").read_text(encoding="utf-8")
    code = text[text.index("```python\nimport numpy as np\nimport lighting\nfrom lighting.brdf import") :].split("```")[
        1
    ]
    code = code.removeprefix("python\n")
    printed = re.search(r"^# ([\d.]+) +([\d.]+) +([\d.]+) +\(nearest: ([-\d.]+) %, linear: ([-\d.]+) %\)", code, re.M)
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "merl.md", "exec"), {})  # noqa: S102 - the page's own example
    got = [float(x) for x in capsys.readouterr().out.split()]
    assert [f"{x:.8f}" for x in got] == list(printed.groups()[:3])
    for k, page in ((1, printed.group(4)), (2, printed.group(5))):
        assert _agrees(page + " %", (got[k] - got[0]) / got[0]), (page, got)

    # The statistics of the paragraph after it: 10 000 seeded pairs above 30° elevation.
    rng = np.random.default_rng(0)

    def directions(k):
        z, phi = rng.uniform(0.5, 1.0, k), rng.uniform(0.0, 2 * np.pi, k)
        s = np.sqrt(1 - z * z)
        return np.stack([s * np.cos(phi), s * np.sin(phi), z], -1)

    l, v, n = directions(10_000), directions(10_000), np.array([0.0, 0.0, 1.0])  # noqa: E741
    measured = []
    for model in (BlinnPhong(0.5, 40, normalized=True), Lambert(0.5) + BlinnPhong(0.5, 40, normalized=True)):
        write_merl(tmp_path / "t.binary", tabulate_merl(model))
        want = model.eval(n, l, v)[..., 0]
        for interpolation in ("nearest", "linear"):
            table = lighting.load_brdf(str(tmp_path / "t.binary"), interpolation=interpolation)
            err = np.abs(table.eval(n, l, v)[..., 0] - want) / want
            measured.append((float(np.median(err)), float(err.max())))
    para = " ".join(text[text.index("Over 10 000 random pairs") :].split("\n\n")[0].split())
    pct = re.findall(r"(\d+(?:\.\d+)?) %", para)
    # pure lobe: medians nearest, linear; with a diffuse part: medians nearest, linear, largest nearest, linear
    expected = [measured[0][0], measured[1][0], measured[2][0], measured[3][0], measured[2][1], measured[3][1]]
    assert len(pct) == 6
    wrong = [(p, f"{m:.2%}") for p, m in zip(pct, expected, strict=True) if not _agrees(p + " %", m)]
    assert wrong == []


def test_the_cli_pages_error_samples_are_what_the_commands_print(capsys):
    # Each "$ lighting-explorer ..." followed by its error line, in cli.md's console blocks, is run here; the
    # Matplotlib one is left out (it needs Matplotlib missing).
    import shlex

    from explorer.cli import main

    text = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    pairs = re.findall(r"^\s*\$ lighting-explorer (.+)\n\s*(lighting-explorer: error: .+)$", text, re.M)
    pairs = [(args, line) for args, line in pairs if args.strip() != "figures"]
    assert len(pairs) >= 5
    for args, line in pairs:
        assert main(shlex.split(args)) == 2, args
        assert capsys.readouterr().err.strip() == line.strip(), args

"""``lighting-explorer report stability``: numerical stability on stiff and extreme cases.

Runs :func:`lighting.validation.stability.run` (every model and light, every case family,
float32 and float64, against an 80-digit mpmath reference on the same binary
inputs) and writes, into ``--out`` (default ``out/stability``):

* ``stability.csv`` — one row per model variant × case family × dtype × form
  (every field of :class:`lighting.validation.stability.SummaryRow`, plus ``passed``, ``u``
  and the bound factor);
* ``rearrangements.csv`` — each formula the engine had to rearrange, with the
  worst ``err / (max(κ,1) u)`` on the sweep before and after;
* ``stability.txt`` — the table printed on the terminal;
* ``stability.png`` — relative error against ``κ u`` for every point, with the
  bound ``8 κ u``, and the worst ratio per model family (unless ``--no-figure``).

The exit status is 0 when every row meets the bound and every check holds, 1
otherwise.
"""

from __future__ import annotations

import argparse
import csv
import io
import math
import sys
import time
from dataclasses import fields
from pathlib import Path

import numpy as np

from lighting._text import plural
from lighting.validation import stability as st

from ..output import atomic_write
from ..progress import Progress

__all__ = ["main", "run", "build_parser", "format_table", "write_csv", "make_figure", "docs_block", "write_docs",
           "CSV_COLUMNS", "DOCS_START", "DOCS_END"]

#: The lines of a documentation page between which ``--docs`` writes the table and its numbers.
DOCS_START, DOCS_END = "<!-- stability: table -->", "<!-- /stability -->"

CSV_COLUMNS = [f.name for f in fields(st.SummaryRow)] + ["passed", "u", "bound_factor"]

MODEL_ORDER = (
    "Lambert",
    "Phong",
    "Blinn-Phong",
    "Blinn-Phong norm.",
    "CT Beckmann",
    "CT GGX",
    "CT Blinn-Phong NDF",
    "Oren-Nayar",
    "Ward",
    "Ashikhmin-Shirley",
    "Disney",
    "CT correlated",
    "CT anisotropic",
    "CT conductor",
    "Point light",
    "Spot light",
)
CASE_ORDER = st.CASE_FAMILIES + st.LIGHT_CASE_FAMILIES


def quote(x: float, spec: str = ".1e") -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    if x == 0:
        return "0"
    return format(x, spec)


def _checks(rows) -> str:
    bad = []
    if any(r.negative for r in rows):
        bad.append("negative")
    if any(r.warnings for r in rows):
        bad.append("warnings")
    if any(r.mono_fail for r in rows):
        bad.append("monotonic")
    if any(r.recip_fail for r in rows):
        bad.append("reciprocity")
    if any(r.max_ratio > st.BOUND_FACTOR for r in rows):
        bad.append("bound")
    if any(r.failures for r in rows) and "bound" not in bad:
        bad.append("zero/saturation/ill")
    return "pass" if not bad else "FAIL: " + ", ".join(bad)


def _family_summary(rows, dtypes):
    """``{(model family, case family): {...}}`` aggregated over model variants and forms."""
    out = {}
    for r in rows:
        key = (r.model_family, r.case_family)
        d = out.setdefault(key, {"rows": [], "points": 0, "nonfinite": 0, "edge": 0, "ill": 0, "by": {}})
        d["rows"].append(r)
        d["points"] += r.points
        d["nonfinite"] += r.nonfinite
        d["edge"] += r.edge
        d["ill"] += r.ill
        b = d["by"].setdefault(r.dtype, {"err": 0.0, "kappa": float("nan"), "ratio": 0.0, "row": None})
        if r.max_rel_err > b["err"] or b["row"] is None:
            if r.max_rel_err >= b["err"]:
                b["err"], b["kappa"] = r.max_rel_err, r.kappa_at_max_err
        if r.max_ratio >= b["ratio"]:
            b["ratio"], b["row"] = r.max_ratio, r
    return out


def format_table(result: st.StabilityResult) -> str:
    """The terminal table: model family × case family, per dtype the largest error, κ there, and the worst ratio.

    Parameters
    ----------
    result : StabilityResult

    Returns
    -------
    str
    """
    dtypes = result.dtypes
    summ = _family_summary(result.rows, dtypes)
    head = f"{'model family':<19} {'case family':<11} {'values':>7} {'NaN/Inf':>7}"
    sub = " " * len(head)
    for dt in dtypes:
        head += f" | {dt + ': max rel err':>22} {'κ there':>8} {'err/κu':>7}"
        sub += f" | {'':>22} {'':>8} {'(<= 8)':>7}"
    head += " | checks"
    lines = [
        "Numerical stability on stiff and extreme cases: engine vs an 80-digit mpmath reference",
        "computed from the same binary inputs.  Bound: relative error <= 8 max(κ,1) u,",
        "u = 2^-24 (float32), 2^-53 (float64); κ = condition number of the formula at that point",
        "(amplification of relative input perturbations).  err/κu is the worst ratio err / (max(κ,1) u).",
        "",
        head,
        sub,
        "-" * len(head),
    ]
    keys = sorted(
        summ,
        key=lambda k: (
            MODEL_ORDER.index(k[0]) if k[0] in MODEL_ORDER else 99,
            CASE_ORDER.index(k[1]) if k[1] in CASE_ORDER else 99,
        ),
    )
    last = None
    for key in keys:
        d = summ[key]
        name = key[0] if key[0] != last else ""
        last = key[0]
        line = f"{name:<19} {key[1]:<11} {d['points']:>7} {d['nonfinite']:>7}"
        for dt in dtypes:
            b = d["by"].get(dt)
            if b is None:
                line += f" | {'':>22} {'':>8} {'':>7}"
                continue
            line += f" | {quote(b['err']):>22} {quote(b['kappa'], '.2g'):>8} {quote(b['ratio'], '.2f'):>7}"
        line += " | " + _checks(d["rows"])
        lines.append(line)
    lines.append("-" * len(head))
    total = sum(r.points for r in result.rows)
    edge = sum(r.edge for r in result.rows)
    ill = sum(r.ill for r in result.rows)
    nonfinite = sum(r.nonfinite for r in result.rows)
    worst = max(result.rows, key=lambda r: r.max_ratio)
    lines += [
        f"{total} values in {plural(len(dtypes), 'dtype')}: per dtype {result.n_brdf_cases} (n, l, v) inputs x"
        f" {len(st.brdf_specs())} BRDF variants x 3 forms and {result.n_light_cases} light inputs x 2 forms;"
        f" NaN/Inf: {nonfinite}.",
        f"worst err/(max(κ,1) u): {worst.max_ratio:.2f} — {worst.model}, {worst.form}, {worst.dtype},"
        f" {worst.worst_ratio_case}",
        f"edge points (a horizon or cone decision flips within ±8u; finite and >= 0 required): {edge};"
        f" ill-conditioned points (8 κ u >= 1; |ln(f/f_true)| <= 8 κ u required): {ill}"
        f" (worst ratio {max(r.ill_max_ratio for r in result.rows):.2f}).",
        "RESULT: " + ("every row meets the bound and every check holds" if result.passed else "FAILURES (see CSV)"),
    ]
    if result.rearrangements:
        lines += [
            "",
            "Rearrangements the engine needed (worst err/(max(κ,1) u) on the affected models, before -> after):",
        ]
        for rr in result.rearrangements:
            parts = []
            for dt in dtypes:
                if dt in rr.before:
                    b, a = rr.before[dt], rr.after[dt]
                    parts.append(f"{dt} {b[0]:.3g} ({b[1]} failing) -> {a[0]:.3g} ({a[1]} failing)")
            lines.append(f"  * {rr.name}: " + "; ".join(parts))
    return "\n".join(lines)


def write_csv(result: st.StabilityResult, path: Path) -> None:
    """Every summary row (see :data:`CSV_COLUMNS`), written atomically.

    Parameters
    ----------
    result : StabilityResult
    path : pathlib.Path

    Returns
    -------
    None
    """
    fh = io.StringIO(newline="")
    w = csv.writer(fh)
    w.writerow(CSV_COLUMNS)
    for r in result.rows:
        vals = [getattr(r, name) for name in CSV_COLUMNS[:-3]]
        u = st.unit_roundoff(np.dtype(r.dtype))
        w.writerow([repr(v) if isinstance(v, float) else v for v in vals] + [r.passed, repr(u), st.BOUND_FACTOR])
    atomic_write(path, fh.getvalue().encode("utf-8"), flag="--out")


def write_rearrangements(result: st.StabilityResult, path: Path) -> None:
    """``rearrangements.csv``: each rearranged formula, per dtype the worst ratio and failures before and after.

    Parameters
    ----------
    result : StabilityResult
    path : pathlib.Path

    Returns
    -------
    None
    """
    fh = io.StringIO(newline="")
    w = csv.writer(fh)
    w.writerow(["rearrangement", "where", "before", "after", "dtype", "ratio_before", "failing_before",
                "ratio_after", "failing_after"])  # fmt: skip
    for rr in result.rearrangements:
        for dt in result.dtypes:
            if dt in rr.before:
                b, a = rr.before[dt], rr.after[dt]
                w.writerow([rr.name, rr.where, rr.formula_before, rr.formula_after, dt, repr(b[0]), b[1],
                            repr(a[0]), a[1]])  # fmt: skip
    atomic_write(path, fh.getvalue().encode("utf-8"), flag="--out")


def make_figure(result: st.StabilityResult, path: Path) -> None:
    """Relative error against κu (log-log, one colour per dtype, the line 8 κ u) and the worst ratio per family.

    Parameters
    ----------
    result : StabilityResult
    path : pathlib.Path
        The PNG to write (atomically).

    Returns
    -------
    None
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    colours = {"float32": "#1f77b4", "float64": "#d95f02"}
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(14, 6.2), gridspec_kw={"width_ratios": [1.15, 1]})
    p = result.points
    rng = np.random.default_rng(0)
    floor = 1e-19
    for dt in result.dtypes:
        u = st.unit_roundoff(np.dtype(dt))
        m = p["dtype"] == dt if p else np.zeros(0, bool)
        if not np.any(m):
            continue
        x = np.maximum(p["kappa"][m], 1.0) * u
        y = np.maximum(p["err"][m], floor)
        ill = p["ill"][m]
        idx = np.arange(len(x))
        if len(idx) > 25000:  # a readable cloud: a random subset plus the 200 points closest to the bound
            top = np.argsort(-(y / x))[:200]
            idx = np.union1d(rng.choice(len(x), 25000, replace=False), top)
        sel = idx[~ill[idx]]
        ax.scatter(x[sel], y[sel], s=4, alpha=0.35, color=colours.get(dt), lw=0, rasterized=True,
                   label=f"{dt} (u = 2^{int(round(math.log2(u)))})")  # fmt: skip
        sel = idx[ill[idx]]
        if len(sel):
            ax.scatter(x[sel], y[sel], s=8, facecolors="none", edgecolors=colours.get(dt), lw=0.4, alpha=0.5,
                       rasterized=True, label=f"{dt}, ill-conditioned (8κu >= 1): |ln(f / f_true)|")  # fmt: skip
    xs = np.logspace(-17, 4, 50)
    ax.plot(xs, 8 * xs, "k-", lw=1.5, label="bound: error = 8 κ u")
    ax.plot(xs, xs, "k:", lw=1, label="error = κ u (rounding the inputs alone)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(1e-17, 1e4)
    ax.set_ylim(floor / 2, 1e4)
    ax.set_xlabel("max(κ, 1) · u   (how much the inputs' own rounding can change the value)")
    ax.set_ylabel("relative error of the engine  (exact results at 1e-19)")
    ax.set_title("Every value of the sweep: below the line = within the bound")
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(loc="upper left", fontsize=8, markerscale=2)

    fams = [f for f in MODEL_ORDER if any(r.model_family == f for r in result.rows)]
    width = 0.8 / max(len(result.dtypes), 1)
    for k, dt in enumerate(result.dtypes):
        vals = []
        for f in fams:
            rs = [r for r in result.rows if r.model_family == f and r.dtype == dt]
            vals.append(max([r.max_ratio for r in rs] + [1e-3]))
        pos = np.arange(len(fams)) + (k - (len(result.dtypes) - 1) / 2) * width
        bx.bar(pos, vals, width=width, color=colours.get(dt), label=dt)
    bx.axhline(st.BOUND_FACTOR, color="k", lw=1.5, label="bound (8)")
    bx.set_yscale("log")
    bx.set_ylim(1e-2, 1e2)
    bx.set_xticks(np.arange(len(fams)))
    bx.set_xticklabels(fams, rotation=35, ha="right")
    bx.set_ylabel("worst  error / (max(κ,1) u)")
    bx.set_title("Worst ratio per model family (bars below 8 meet the bound)")
    bx.grid(True, axis="y", which="major", alpha=0.3)
    bx.legend(fontsize=8)
    fig.suptitle(
        "Numerical stability of the shading formulas on stiff and extreme inputs (reference: mpmath, 80 digits)",
        fontsize=12,
    )
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    plt.close(fig)
    atomic_write(path, buf.getvalue(), flag="--out")


def build_parser() -> argparse.ArgumentParser:
    """The standalone parser of ``lighting-explorer report stability`` (its options: :mod:`explorer.reports.options`).

    Returns
    -------
    argparse.ArgumentParser
        A :class:`~explorer.cli.OneLineParser` (errors are one-line exceptions, not ``exit(2)``).
    """
    from .options import add_report

    return add_report(None, "stability")


def check_args(args) -> None:
    """Refuse bad options before the long computation: ``--workers`` out of range or over the memory
    budget, ``--out`` that is a file or not writable.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed options; ``args.workers`` is replaced by its checked value.

    Returns
    -------
    None
    """
    from lighting._budget import check_budget
    from lighting._validate import check_count

    from ..output import check_output_dir
    from .options import MAX_WORKERS, WORKER_BYTES

    if args.workers is not None:
        args.workers = check_count("--workers", args.workers, 1, MAX_WORKERS)
        check_budget(f"--workers {args.workers}", WORKER_BYTES * args.workers,
                     what=f"{args.workers} reference processes")  # fmt: skip
    check_output_dir(args.out, flag="--out")
    if getattr(args, "docs", None) is not None:
        _docs_page(args)


def _docs_page(args) -> str:
    """The text of ``--docs PAGE``, checked: a default run, a readable file with each marker line once."""
    page = Path(args.docs)
    if args.quick or args.dtype != "both":
        given = "--quick" if args.quick else f"--dtype {args.dtype}"
        raise ValueError(f"--docs takes the default run (both dtypes, not --quick); got {given} with --docs {page}")
    try:
        text = page.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        reason = exc.__class__.__name__
        raise ValueError(f"--docs must name a readable UTF-8 page; got {str(page)!r} ({reason})") from None
    lines = text.splitlines()
    for mark in (DOCS_START, DOCS_END):
        if lines.count(mark) != 1:
            raise ValueError(f"--docs page must hold the line {mark!r} once; {str(page)!r} holds it "
                             f"{lines.count(mark)} times")  # fmt: skip
    if lines.index(DOCS_START) > lines.index(DOCS_END):
        raise ValueError(f"--docs page must hold {DOCS_START!r} before {DOCS_END!r}; {str(page)!r} has them reversed")
    return text


def _spaced(n: int) -> str:
    return f"{n:,}".replace(",", " ")


def docs_block(result: st.StabilityResult, table: str) -> str:
    """The documentation's sample of a run: the table as printed, then a paragraph of that run's numbers.

    Parameters
    ----------
    result : StabilityResult
    table : str
        :func:`format_table` of ``result``.

    Returns
    -------
    str
        Markdown: a fenced ``text`` block and one paragraph (the worst ratio and where, the count of values
        of each class), every number taken from ``result``.
    """
    rows = result.rows
    beyond = sum(1 for sp in st.brdf_specs() if sp.general)
    worst = max(rows, key=lambda r: r.max_ratio)
    count = {name: sum(getattr(r, name) for r in rows) for name in ("normal", "ill", "edge", "zero", "under", "over")}
    failed = sum(1 for r in rows if not r.passed)
    verdict = ("every row met the bound" if not failed else
               f"{_spaced(failed)} of {_spaced(len(rows))} rows missed the bound or a check (see `stability.csv`)")
    saturated = all(r.failures == 0 for r in rows if r.over)
    para = (
        f"In that run {verdict}, the {beyond} variants of the models beyond the slides included: the worst "
        f"ratio was {worst.max_ratio:.2f} ({worst.model}, `{worst.form}`, {worst.dtype}, {worst.worst_ratio_case}). "
        f"In numbers, from the same run: {_spaced(count['normal'])} normal values ({', '.join(result.dtypes)}) "
        f"checked against the bound, {_spaced(count['ill'])} ill-conditioned ones (worst `|ln(f/f_true)|` "
        f"{max(r.ill_max_ratio for r in rows):.2f} `κ u`, bound `8 κ u`), {_spaced(count['edge'])} edge points, "
        f"{_spaced(count['zero'])} exact zeros, {_spaced(count['under'])} below the normal range, "
        f"{_spaced(count['over'])} beyond the largest float ({'all saturated' if saturated else 'not all saturated'})."
    )
    return "```text\n" + table + "\n```\n\n" + para + "\n\n"


def write_docs(result: st.StabilityResult, table: str, page: Path, figure: Path | None = None) -> list[Path]:
    """Replace the text between ``page``'s :data:`DOCS_START` and :data:`DOCS_END` lines with :func:`docs_block`.

    Parameters
    ----------
    result : StabilityResult
    table : str
        :func:`format_table` of ``result``.
    page : pathlib.Path
        The documentation page (checked by ``--docs``).
    figure : pathlib.Path, optional
        The run's figure, copied to ``images/stability.png`` beside the page.

    Returns
    -------
    list of pathlib.Path
        The files written.
    """
    text = page.read_text(encoding="utf-8")
    head, rest = text.split(DOCS_START + "\n", 1)
    _, tail = rest.split(DOCS_END + "\n", 1)
    new = head + DOCS_START + "\n" + docs_block(result, table) + DOCS_END + "\n" + tail
    atomic_write(page, new.encode("utf-8"), flag="--docs")
    written = [page]
    if figure is not None:
        target = page.parent / "images" / "stability.png"
        target.parent.mkdir(exist_ok=True)
        atomic_write(target, figure.read_bytes(), flag="--docs")
        written.append(target)
    return written


def main(argv=None) -> int:
    """``lighting-explorer report stability``: 0 when every check holds, 1 when one fails, 2 for a bad request.

    Parameters
    ----------
    argv : list of str, optional
        The options (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status.
    """
    from ..cli import parse_and_run

    return parse_and_run(build_parser, run, argv)


def run(args) -> int:
    """Run the sweep for parsed options and write the table, CSVs and figure.

    Parameters
    ----------
    args : argparse.Namespace
        The options of :func:`explorer.reports.options.add_stability_arguments`.

    Returns
    -------
    int
        0 when every check holds, 1 when one fails, 2 for a bad option (one line on stderr).
    """
    from ..cli import print_error, require

    try:
        require("report stability", "mpmath", *(() if args.no_figure else ("matplotlib",)))
        check_args(args)
    except ValueError as exc:
        return print_error(exc)
    dtypes = (np.float32, np.float64) if args.dtype == "both" else (np.dtype(args.dtype).type,)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    bar: list[Progress] = []

    def start(total):
        bar.append(Progress(total, "stability: mpmath references"))

    def tick(k):
        bar[0].update(k)

    try:
        result = st.run(quick=args.quick, dtypes=dtypes, workers=args.workers, progress=tick, on_start=start)
    except BaseException:
        if bar:
            bar[0].abort()
        raise
    if bar:
        bar[0].close()
    table = format_table(result)
    print(table)
    write_csv(result, out / "stability.csv")
    write_rearrangements(result, out / "rearrangements.csv")
    atomic_write(out / "stability.txt", (table + "\n").encode("utf-8"), flag="--out")
    written = [out / "stability.csv", out / "rearrangements.csv", out / "stability.txt"]
    if not args.no_figure:
        make_figure(result, out / "stability.png")
        written.append(out / "stability.png")
    if args.docs is not None:
        figure = None if args.no_figure else out / "stability.png"
        written += write_docs(result, table, Path(args.docs), figure)
    secs = result.seconds
    print(
        f"\ntime: {time.perf_counter() - t0:.1f} s (references {secs['reference']:.1f} s,"
        f" engine and checks {secs['engine_and_checks']:.1f} s)"
    )
    print("wrote " + ", ".join(str(p) for p in written))
    return 0 if result.passed else 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

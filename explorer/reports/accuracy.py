"""``lighting-explorer report accuracy``: error against run time (table, CSV, figure)."""

from __future__ import annotations

import csv
import io
import math
import os
import sys
import time
from dataclasses import asdict

from lighting.integrate import UNCONVERGED_RELATIVE_ERROR
from lighting.validation.accuracy import GRID_METHOD, PIXEL_SUM_SUFFIX, run_studies, summary

from ..progress import Progress
from .cache import save_study

#: The command that measures the studies, as captions name it.
REPORT = "lighting-explorer report accuracy"

FLOOR = 1e-16  # errors of exactly 0 are drawn here on the log axis
#: Marks an unconverged point (relative error estimate above 2 %) in the printed tables.
UNCONVERGED_MARK = "unconverged"


def _fmt_s(seconds) -> str:
    if seconds is None:
        return "-"
    return f"{seconds * 1e3:.3g} ms"


def format_points(studies) -> str:
    """Every measured point, one block per study and case, as the terminal prints it.

    Parameters
    ----------
    studies : list of Study
        From :func:`lighting.validation.accuracy.run_studies`.

    Returns
    -------
    str
    """
    lines = []
    for st in studies:
        lines.append(f"\n{st.description}")
        cases = list(dict.fromkeys(p.case for p in st.points))
        for case in cases:
            pts = [p for p in st.points if p.case == case]
            lines.append(f"  {case}  (reference: {pts[0].reference})")
            image = any(not math.isnan(p.error_p95) for p in pts)  # per-pixel errors: median and 95th percentile
            extra = f" {'95th pct':>9s} {'ref. err':>9s}" if image else ""
            lines.append(
                f"    {'method':28s} {'cost':>10s} {'rel. error':>12s} {'± spread':>10s} {'time':>10s}"
                f" {'estimated':>10s} {'2σ covers':>9s}{extra}  flag"
            )
            for p in pts:
                spread = f"{p.error_spread:.1e}" if p.error_spread else ""
                own = "" if math.isnan(p.estimated_error) else f"{p.estimated_error:.1e}"
                cover = "" if math.isnan(p.coverage) else f"{100 * p.coverage:.0f} %"
                if image:
                    p95 = "" if math.isnan(p.error_p95) else f"{p.error_p95:.2e}"
                    ref = "" if math.isnan(p.reference_error) else f"{p.reference_error:.1e}"
                    cover += f" {p95:>9s} {ref:>9s}"
                lines.append(
                    f"    {p.method:28s} {p.cost:>10d} {p.error:12.2e} {spread:>10s} {_fmt_s(p.seconds):>10s}"
                    f" {own:>10s} {cover:>9s}  {UNCONVERGED_MARK if p.unconverged else ''}".rstrip()
                )
    lines.append(
        f"\n{UNCONVERGED_MARK}: unconverged, the estimated relative error (the method's own, else the measured one) "
        f"is above {100 * UNCONVERGED_RELATIVE_ERROR:g} %, or the reference's own error is above the measured one; "
        "'2σ covers': share of seeds (image studies: lit pixels) whose true error is within two reported errors; "
        "image studies: 'rel. error' is the median over the lit pixels, '95th pct' its 95th percentile"
    )
    return "\n".join(lines)


def format_summary(rows) -> str:
    """The cheapest method that reaches each error target, per case.

    Parameters
    ----------
    rows : list of dict
        From :func:`lighting.validation.accuracy.summary`.

    Returns
    -------
    str
    """
    lines = ["", "Cheapest method that reaches the error (fastest measured point at or below it):"]
    lines.append(f"  {'case':62s} {'error':>6s}  {'method':28s} {'cost':>14s} {'time':>10s}")
    for r in rows:
        thr = f"{100 * r['threshold']:g} %"
        if r["method"] is None:
            lines.append(f"  {r['case'][:62]:62s} {thr:>6s}  {'not reached':28s}")
        else:
            cost = f"{r['cost']} {r['cost_unit']}"
            mark = f"  {UNCONVERGED_MARK}" if r.get("unconverged") else ""
            lines.append(
                f"  {r['case'][:62]:62s} {thr:>6s}  {r['method']:28s} {cost:>14s} {_fmt_s(r['seconds']):>10s}{mark}"
            )
    return "\n".join(lines)


def write_csv(path, rows, fields) -> None:
    """The rows as CSV, written atomically (no temporary file survives an interrupt).

    Parameters
    ----------
    path : str
    rows : list of dict
    fields : list of str
        The columns, in order.

    Returns
    -------
    None
    """
    from ..output import atomic_write

    fh = io.StringIO(newline="")
    w = csv.DictWriter(fh, fieldnames=fields)
    w.writeheader()
    for r in rows:
        w.writerow(r)
    atomic_write(path, fh.getvalue().encode("utf-8"), flag="--out")


#: Methods drawn as one marker (not a line over cost) in the figure, and their marker.
_MARKED = {"split sum": "*", "dominant lights": "D", GRID_METHOD: "d", "SH9 irradiance": "s"}


def _panels(studies) -> list:
    """``[(title, [(series label, points)])]``: one panel per case and one series per method, except the
    ``ibl`` study: one panel per environment and one series per model (its split sum and Monte Carlo)."""
    panels = []
    for st in studies:
        cases = list(dict.fromkeys(p.case for p in st.points))
        if st.name != "ibl":
            for case in cases:
                pts = [p for p in st.points if p.case == case]
                panels.append(
                    (case, [(m, [p for p in pts if p.method == m]) for m in dict.fromkeys(p.method for p in pts)])
                )
            continue
        by_env = {}
        for case in cases:
            model, _, env = case.rpartition(" · ")
            # The methods judged again against the pixel sum are the same methods: drawn once, against Monte Carlo.
            pts = [p for p in st.points if p.case == case and not p.method.endswith(PIXEL_SUM_SUFFIX)]
            by_env.setdefault(env, []).append((model, pts))
        panels += [(f"IBL, {env}", series) for env, series in by_env.items()]
    return panels


def make_figure(studies, path) -> None:
    """One log-log panel per case: relative error against time, one line per method (``ibl``: per environment).

    Parameters
    ----------
    studies : list of Study
    path : str
        The PNG to write (atomically).

    Returns
    -------
    None
    """
    import matplotlib
    import matplotlib.ticker

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = _panels(studies)
    cols = 4 if len(panels) > 4 else len(panels)
    rows = (len(panels) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.6 * rows), squeeze=False, constrained_layout=True)
    methods = list(dict.fromkeys(label for _, series in panels for label, _ in series))
    cmap = plt.get_cmap("tab10" if len(methods) <= 10 else "tab20")
    colour = {m: cmap(i % cmap.N) for i, m in enumerate(methods)}
    for ax, (case, series) in zip(axes.flat, panels, strict=False):
        pts = [p for _, sp in series for p in sp]
        for m, sp in series:
            single = [p for p in sp if p.method in _MARKED]
            for p in single:  # one-point fast approximations of an image study: a star (SH9: a square)
                ax.plot(p.seconds * 1e3, max(p.error, FLOOR), _MARKED[p.method], ms=8, color=colour[m],
                        mec="k", mew=0.6, label=m if len(single) == len(sp) else None)  # fmt: skip
            mp = sorted((p for p in sp if p.method not in _MARKED), key=lambda p: p.cost)
            if not mp:
                continue
            t = [p.seconds * 1e3 for p in mp]
            e = [max(p.error, FLOOR) for p in mp]
            ax.plot(t, e, "o-", ms=3.5, lw=1.4, color=colour[m], label=m)
            flagged = [(ti, ei) for ti, ei, p in zip(t, e, mp, strict=True) if p.unconverged]
            if flagged:  # unconverged by the method's own estimate: hollow ring around the dot
                ax.plot(*zip(*flagged, strict=True), "o", ms=7, mfc="none", mec=colour[m], mew=0.9)
            if any(p.error_spread for p in mp):
                # ± one standard deviation over seeds, kept within a decade below on the log axis
                lo = [max(p.error - p.error_spread, p.error / 10, FLOOR) for p in mp]
                hi = [p.error + p.error_spread for p in mp]
                ax.fill_between(t, lo, hi, color=colour[m], alpha=0.15, lw=0)
        for thr, style in ((1e-2, "--"), (1e-3, ":")):
            ax.axhline(thr, color="0.4", ls=style, lw=0.9)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.xaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        narrow = len({round(p.seconds, 12) for p in pts}) > 1 and max(p.seconds for p in pts) < 10 * min(
            p.seconds for p in pts
        )
        minor = matplotlib.ticker.FormatStrFormatter("%g") if narrow else matplotlib.ticker.NullFormatter()
        ax.xaxis.set_minor_formatter(minor)
        ax.set_title(case, fontsize=10)
        ax.set_xlabel("time per evaluation (ms)")
        ax.set_ylabel("relative error")
        ax.grid(True, which="major", color="0.9", lw=0.6)
        ax.legend(fontsize=7 if len(series) <= 8 else 5.5, loc="best", frameon=False, ncol=1 if len(series) <= 8 else 2)
    for ax in list(axes.flat)[len(panels) :]:
        ax.axis("off")
    fig.suptitle(
        "Error against run time (dashed: 1 %, dotted: 0.1 %; exact zeros drawn at 1e-16; "
        "ringed: unconverged, own estimate > 2 %)"
        + (
            "\nIBL panels: lines Monte Carlo (MIS) by spp, stars the split sum,\n"
            "diamonds the dominant lights (thin: on the grid of normals), squares SH9, one colour per model"
            if any(st.name == "ibl" for st in studies)
            else ""
        ),
        fontsize=12,
    )
    from ..output import atomic_write

    try:
        atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png"), flag="--out")
    finally:
        plt.close(fig)


def build_parser():
    """The standalone parser of ``lighting-explorer report accuracy`` (its options: :mod:`explorer.reports.options`).

    Returns
    -------
    argparse.ArgumentParser
        A :class:`~explorer.cli.OneLineParser` (errors are one-line exceptions, not ``exit(2)``).
    """
    from .options import add_report

    return add_report(None, "accuracy")


def main(argv=None) -> int:
    """``lighting-explorer report accuracy``: 0 on success, 2 for a bad request (one line on stderr).

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
    """Run the studies for parsed options; print the tables, write the CSVs and the figure, save the studies.

    Each study run is also saved in the cache of :mod:`explorer.reports.cache` (quick or full), where
    the ``accuracy_*`` figures find it.

    Parameters
    ----------
    args : argparse.Namespace
        The options of :func:`explorer.reports.options.add_accuracy_arguments`.

    Returns
    -------
    int
        0 on success, 2 for a bad ``--out`` (one line on stderr).
    """
    from ..cli import print_error, require
    from ..output import check_output_dir

    try:
        if not args.no_figure:
            require("report accuracy", "matplotlib")
        check_output_dir(args.out, flag="--out")
    except ValueError as exc:
        return print_error(exc)
    os.makedirs(args.out, exist_ok=True)
    t0 = time.perf_counter()
    studies = run_studies(quick=args.quick, only=args.only, progress_factory=Progress)
    # Saved for the lecture-note figures (accuracy_integration, ...), which draw from them instead of
    # measuring again (explorer.reports.cache).
    cached = [save_study(st, quick=args.quick, by=f"{REPORT}{' --quick' if args.quick else ''}") for st in studies]
    rows = summary(studies)
    print(format_points(studies))
    print(format_summary(rows))
    points = [asdict(pt) for st in studies for pt in st.points]
    csv_path = os.path.join(args.out, "accuracy.csv")
    write_csv(csv_path, points, list(points[0]))
    sum_path = os.path.join(args.out, "accuracy_summary.csv")
    write_csv(sum_path, rows, list(rows[0]))
    written = [csv_path, sum_path]
    if not args.no_figure:
        fig_path = os.path.join(args.out, "accuracy.png")
        make_figure(studies, fig_path)
        written.append(fig_path)
    print(f"\nwrote {', '.join(written)} in {time.perf_counter() - t0:.1f} s")
    if any(cached):
        print(f"saved {sum(map(bool, cached))} {'study' if sum(map(bool, cached)) == 1 else 'studies'} for "
              f"'lighting-explorer figures' in {os.path.dirname(next(c for c in cached if c))}")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

"""``lighting-explorer figures``: write the lecture-note figure set (the work is :mod:`explorer.figures`).

::

    lighting-explorer figures --out DIR [--format png,svg,pdf] [--only NAME ...] [--dpi N]
                              [--quick] [--jobs N] [--accuracy-csv FILE] [--list]

This module imports no Matplotlib: building the command line (:func:`explorer.cli.build_parser`) costs
nothing; the figure set is loaded when the command runs.  Its errors are one line, ``lighting-explorer: error: …``
(:func:`explorer.cli.print_error`).
"""

from __future__ import annotations

import os
import sys
import time

__all__ = ["MAX_JOBS", "add_parser", "run", "main"]

#: More workers than this only cost memory.
MAX_JOBS = 64


def add_parser(subparsers):
    """Add ``figures`` and its options to the sub-commands of ``lighting-explorer``.

    Parameters
    ----------
    subparsers : explorer.cli.SubCommands
        The sub-parsers of the ``lighting-explorer`` command.

    Returns
    -------
    argparse.ArgumentParser
        The new sub-parser (its ``func`` default is :func:`run`).
    """
    p = subparsers.add_parser(
        "figures", help="the lecture-note figures with their captions",
        description="Write the lecture-note figures (PNG/SVG/PDF, each with a JSON sidecar).",
    )  # fmt: skip
    p.add_argument("--out", "-o", default=os.path.join("out", "figures"), metavar="DIR", help="output folder")
    p.add_argument("--format", default="png", metavar="FORMATS", help="comma-separated formats among png, svg, pdf")
    p.add_argument("--only", nargs="+", metavar="NAME",
                   help="draw only these figures (see --list); figures.json keeps the other entries")  # fmt: skip
    p.add_argument("--dpi", type=int, metavar="N", help="raster resolution (default: 150; 50 with --quick)")
    p.add_argument("--quick", action="store_true",
                   help="low resolution and sample counts (for tests and previews)")  # fmt: skip
    p.add_argument("--jobs", "-j", type=int, default=None, metavar="N",
                   help=f"worker processes, 1 to {MAX_JOBS} (default: up to 4, one per core)")  # fmt: skip
    p.add_argument("--accuracy-csv", metavar="FILE",
                   help="draw the accuracy_* figures from this accuracy.csv (lighting-explorer report accuracy) "
                        "instead of the studies report accuracy saved, or of measuring now")  # fmt: skip
    p.add_argument("--list", action="store_true", help="list the figures and exit")
    p.set_defaults(func=run)
    return p


def run(args) -> int:
    """List the figures, or check every option and then draw and write the set.

    Parameters
    ----------
    args : argparse.Namespace
        The options of :func:`add_parser`.

    Returns
    -------
    int
        0 done, 1 a file could not be written, 2 a bad request (one line on standard error).
    """
    from ..cli import print_error, require

    try:
        require("figures", "matplotlib")  # before the figure modules import it: one line naming the extra
    except ValueError as exc:
        return print_error(exc)
    from .. import figures
    from ..progress import Progress

    try:
        if args.list:
            for name, spec in figures._load_registry().items():
                print(f"{name:24s} {spec.title}")
            return 0
        formats = figures._check_formats(args.format.split(","))
        names = figures._check_names(args.only)
        # Worker processes pay for their start-up: only worth it for more than a handful of figures.
        jobs = args.jobs if args.jobs is not None else max(1, min(4, os.cpu_count() or 1, len(names) // 4))
        options = {}
        if args.accuracy_csv is not None:
            options["csv"] = figures.check_accuracy_csv(args.accuracy_csv)
    except ValueError as exc:
        return print_error(exc)
    t0 = time.perf_counter()
    try:
        records = figures.generate(
            args.out, formats=formats, only=args.only, quick=args.quick, dpi=args.dpi, jobs=jobs,
            options=options, progress=Progress,
        )  # fmt: skip
    except ValueError as exc:
        return print_error(exc)
    except OSError as exc:
        print_error(f"{exc.strerror or exc}: {exc.filename or args.out}")
        return 1
    n_files = sum(len(r["files"]) for r in records)
    print(
        f"wrote {len(records)} figures ({n_files} files, {', '.join(formats)}) and {figures.MANIFEST} to {args.out} "
        f"in {time.perf_counter() - t0:.1f} s"
    )
    return 0


def main(argv=None) -> int:
    """``lighting-explorer figures`` run alone (see :func:`explorer.cli.run_alone`).

    Parameters
    ----------
    argv : list of str, optional
        The options (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0 done, 1 a file could not be written, 2 a bad request.
    """
    from ..cli import run_alone

    return run_alone("figures", argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

"""``lighting-explorer bench``: time the engine's image pipeline against VTK (the work is :mod:`explorer.bench`).

::

    lighting-explorer bench [--json] [--repeat N] [--plan | --ibl | --app]
"""

from __future__ import annotations

import json
import sys

__all__ = ["MAX_REPEAT", "add_parser", "run", "main"]

#: Most timed runs per measurement: more only takes longer.
MAX_REPEAT = 10000


def add_parser(subparsers):
    """Add ``bench`` and its options to the sub-commands of ``lighting-explorer``.

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
        "bench", help="time the engine's shading against VTK rendering",
        description="Time the engine's re-shading and rasterizing against VTK rendering the same scene, in one run "
        "(the VTK row needs PyVista: pip install 'lighting-explorer[app]').",
    )  # fmt: skip
    p.add_argument("--json", action="store_true", help="print one JSON line instead of the table")
    p.add_argument("--repeat", type=int, default=None, metavar="N",
                   help=f"timed runs per measurement, 1 to {MAX_REPEAT} "
                        "(median; default 15, or 3 with --ibl)")  # fmt: skip
    p.add_argument("--plan", action="store_true", help="planned vs nothing-skipped evaluation of every example scene")
    p.add_argument("--ibl", action="store_true",
                   help="image-based lighting: split-sum and dominant-light re-shades, prefiltering and the 64-spp "
                   "Monte-Carlo reference against their targets (--repeat defaults to 3 here)")  # fmt: skip
    p.add_argument("--app", action="store_true",
                   help="the desktop window: a dragged light slider, its release, a model switch and the 3D redraw, "
                   "on Qt's offscreen platform and in an X server (Xvfb when there is no display), against their "
                   "targets (needs pip install 'lighting-explorer[app]')")  # fmt: skip
    p.set_defaults(func=run)
    return p


def run(args) -> int:
    """Run the benchmark the options ask for and print its table (or one JSON line).

    Parameters
    ----------
    args : argparse.Namespace
        The options of :func:`add_parser`.

    Returns
    -------
    int
        0 when done, 2 for a bad ``--repeat`` (one line on standard error).
    """
    from lighting._validate import check_count

    from .. import bench
    from .._allocator import tune_allocator
    from ..cli import print_error

    repeat = args.repeat if args.repeat is not None else (3 if getattr(args, "ibl", False) else 15)
    try:
        check_count("--repeat", repeat, 1, MAX_REPEAT)
        chosen = [f for f in ("plan", "ibl", "app") if getattr(args, f, False)]
        if len(chosen) > 1:
            raise ValueError(f"--{chosen[0]} and --{chosen[1]} are separate benchmarks: give one of them")
    except ValueError as exc:
        return print_error(exc)
    tune_allocator()
    if args.plan:
        rows = bench.time_plans(repeat)
        print(json.dumps(rows) if args.json else bench.format_plans(rows))
        return 0
    if getattr(args, "app", False):
        from ..cli import require

        try:
            require("bench --app", "PySide6", "pyvista", "pyvistaqt")
        except ValueError as exc:
            return print_error(exc)
        rows = bench.run_app(repeat)
        print(json.dumps(rows) if args.json else bench.format_app(rows))
        return 0
    if getattr(args, "ibl", False):
        result = bench.run_ibl(repeat)
        print(json.dumps(result) if args.json else bench.format_ibl(result))
        return 0
    result = bench.run(repeat)
    print(json.dumps(result) if args.json else bench.format_report(result))
    return 0


def main(argv=None) -> int:
    """``lighting-explorer bench`` run alone (see :func:`explorer.cli.run_alone`).

    Parameters
    ----------
    argv : list of str, optional
        The options (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0 when done, 2 for a bad option (one line on standard error).
    """
    from ..cli import run_alone

    return run_alone("bench", argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

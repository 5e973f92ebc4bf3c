"""The options of ``report accuracy`` and ``report stability``, apart from the reports themselves.

The command tree (:func:`explorer.cli.build_parser`) is built on every run, ``render`` included, so
this module imports nothing that the reports need only to run: no mpmath, no integrator.
"""

from __future__ import annotations

import os

from lighting.validation.accuracy import STUDY_NAMES

__all__ = ["REPORTS", "MAX_WORKERS", "WORKER_BYTES", "add_accuracy_arguments", "add_stability_arguments", "add_report"]

#: Memory one mpmath reference worker of ``report stability`` takes (interpreter, NumPy, mpmath, its cases).
WORKER_BYTES = 128 * 1024**2
#: More ``report stability`` workers than this only cost memory.
MAX_WORKERS = 64


def add_accuracy_arguments(p):
    """Add the options of ``report accuracy`` to ``p``.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The parser (standalone or a sub-parser of the command tree).

    Returns
    -------
    argparse.ArgumentParser
        ``p``.
    """
    p.add_argument("--quick", action="store_true",
                   help="small sample counts and images, for tests (the report prints its run time)")  # fmt: skip
    p.add_argument("--out", metavar="DIR", default=os.path.join("out", "accuracy"), help="output folder")
    p.add_argument("--no-figure", action="store_true", help="skip the figure (then Matplotlib is not needed)")
    p.add_argument("--only", nargs="+", choices=STUDY_NAMES, metavar="STUDY",
                   help=f"run only these studies, from {', '.join(STUDY_NAMES)} (default: all)")  # fmt: skip
    return p


def add_stability_arguments(p):
    """Add the options of ``report stability`` to ``p``.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The parser (standalone or a sub-parser of the command tree).

    Returns
    -------
    argparse.ArgumentParser
        ``p``.
    """
    p.add_argument("--quick", action="store_true",
                   help="fewer points per case family (the report prints its run time)")  # fmt: skip
    p.add_argument("--out", metavar="DIR", default="out/stability", help="output folder")
    p.add_argument("--no-figure", action="store_true", help="skip the figure (then Matplotlib is not needed)")
    p.add_argument("--dtype", choices=("float32", "float64", "both"), default="both", help="which float types")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help=f"processes for the mpmath reference, 1 to {MAX_WORKERS} (default: 2)")  # fmt: skip
    p.add_argument("--docs", metavar="PAGE", default=None,
                   help="also write the table and its numbers into PAGE (docs/stability.md) between its "
                        "'<!-- stability: table -->' and '<!-- /stability -->' lines, and the figure to "
                        "PAGE's images/stability.png; a default run only (both dtypes, not --quick)")  # fmt: skip
    return p


#: Each report: its module (loaded to run it), its one-line help, its description and its options.
REPORTS = {
    "accuracy": ("explorer.reports.accuracy", "error against run time wherever the engine trades accuracy for speed",
                 "Measure error against run time wherever the engine trades accuracy for speed.",
                 add_accuracy_arguments),
    "stability": ("explorer.reports.stability", "numerical stability on stiff and extreme cases, against mpmath",
                  "Check numerical stability of every model and light on stiff and extreme cases, in float32 and "
                  "float64, against an 80-digit mpmath reference.", add_stability_arguments),
}  # fmt: skip


def add_report(parser_or_subparsers, name: str, run=None):
    """A report's parser: standalone (``OneLineParser``) or added to the ``report`` sub-parsers.

    Parameters
    ----------
    parser_or_subparsers : explorer.cli.SubCommands or None
        ``None`` for the standalone parser of ``lighting-explorer report NAME``; else where to add it.
    name : str
        A key of :data:`REPORTS`.
    run : callable, optional
        Set as the parser's ``func`` default.

    Returns
    -------
    argparse.ArgumentParser
        The parser, with the report's options.
    """
    _, help_line, description, add_arguments = REPORTS[name]
    if parser_or_subparsers is None:
        from ..cli import OneLineParser

        p = OneLineParser(prog=f"lighting-explorer report {name}", description=description)
    else:
        p = parser_or_subparsers.add_parser(name, help=help_line, description=description)
    add_arguments(p)
    if run is not None:
        p.set_defaults(func=run)
    return p

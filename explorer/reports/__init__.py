"""``lighting-explorer report accuracy|stability``: the two accuracy reports."""

from __future__ import annotations

import importlib
import sys

from .options import REPORTS, add_report

__all__ = ["REPORTS", "add_parser", "run", "main"]


def add_parser(subparsers):
    """Add ``report`` to ``subparsers``, with the sub-commands ``accuracy`` and ``stability``.

    Parameters
    ----------
    subparsers : explorer.cli.SubCommands
        The sub-parsers of the ``lighting-explorer`` command.

    Returns
    -------
    argparse.ArgumentParser
        The ``report`` parser; each report's parser has ``func`` set to :func:`run`, which loads the
        report's module only then (building the tree loads neither mpmath nor the integrator).
    """
    p = subparsers.add_parser(
        "report", help="accuracy reports: 'report accuracy' (error vs run time), 'report stability'"
    )
    reports = p.add_subparsers(dest="report", required=True, parser_class=type(p), metavar="REPORT", title="reports")
    for name in REPORTS:
        # An argument the report does not know is reported by the report's own parser (explorer.cli.parse).
        add_report(reports, name, run=run)
    return p


def run(args) -> int:
    """Run the report named by ``args.report`` with the options parsed by :func:`add_parser`.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed options; ``args.report`` is ``"accuracy"`` or ``"stability"``.

    Returns
    -------
    int
        That report's exit status.
    """
    return importlib.import_module(REPORTS[args.report][0]).run(args)


def main(argv=None) -> int:
    """``lighting-explorer report {accuracy,stability} ...``: run one report.

    ``--help`` lists the reports (exit status 0); no report name, or an unknown one, is a bad request:
    one line on standard error naming the reports, exit status 2.

    Parameters
    ----------
    argv : list of str, optional
        The report's name and its options (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status.
    """
    from ..cli import PROG, did_you_mean, print_error

    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] in REPORTS:
        return importlib.import_module(REPORTS[argv[0]][0]).main(argv[1:])
    if argv and argv[0] in ("-h", "--help"):
        lines = [f"usage: {PROG} report {{{','.join(REPORTS)}}} [options]", "", "reports:"]
        lines += [f"  {name:10s} {text}" for name, (_, text, *_) in REPORTS.items()]
        lines += ["", f"'{PROG} report NAME --help' lists a report's options and their defaults."]
        print("\n".join(lines))
        return 0
    if not argv:
        listed = " or ".join(f"{name} ({text})" for name, (_, text, *_) in REPORTS.items())
        return print_error(f"report needs the name of a report: {listed}")
    from lighting._text import quote

    hint = did_you_mean(argv[0], REPORTS)
    return print_error(f"unknown report {quote(argv[0])}{hint} (choose from {', '.join(REPORTS)})")


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

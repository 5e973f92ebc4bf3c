"""The sub-commands of ``lighting-explorer``, one module each.

Every module offers ``add_parser(subparsers)`` (adds the command and its options to the one argparse
tree, :func:`explorer.cli.build_parser`, with ``func`` set to its ``run``), ``run(args) -> int`` (runs
it on parsed options and returns the exit status) and ``main(argv) -> int`` (runs it alone).  The
work itself lives with its topic: the engine (``sphere``, ``render``), :mod:`explorer.bench` (measurements),
:mod:`explorer.figures`.  ``explore`` (:mod:`explorer.app.command`) and ``report``
(:mod:`explorer.reports`, its options in :mod:`explorer.reports.options`) are in the same tree.
"""

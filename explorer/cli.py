"""The ``lighting-explorer`` command.

Every sub-command answers a bad request with one line on standard error,
``lighting-explorer: error: <what, the value given, what is allowed>`` (:func:`print_error`), and exit status 2;
Ctrl-C exits with 130 and ``SIGTERM`` with 143, leaving no temporary file behind (see
:mod:`explorer.output`).  ``--memory-budget SIZE`` (anywhere on the line) sets the budget that
image sizes, sample counts, worker counts and scene files are checked against before anything
is allocated (:func:`lighting._budget.set_memory_budget`; 2 GiB by default).
The parser itself (one-line errors, the help's conventions, ``--size`` and choices) is
:mod:`explorer.parser`; this module is the entry point, the command table and the error lines.
"""

from __future__ import annotations

import argparse
import functools
import os
import re
import sys

from lighting._budget import memory_budget, set_memory_budget
from lighting._text import quote

# The parser's names are importable from here too, as every command module and test imports them.
from .parser import (  # noqa: F401
    CommandTreeParser,
    OneLineParser,
    OptionGroup,
    SubCommands,
    UsageError,
    choice_type,
    command_parser,
    did_you_mean,
    leaf_commands,
    option_settings,
    options_section,
    size_type,
)

PROG = "lighting-explorer"

#: What every error line starts with, whichever command (or argparse, or a missing extra) reports it.
ERROR_PREFIX = f"{PROG}: error: "

#: The smallest ``--memory-budget`` accepted.
MIN_MEMORY_BUDGET = 1024**2


def print_error(error) -> int:
    """Print one error line on standard error, ``lighting-explorer: error: …``; every command reports through it.

    Parameters
    ----------
    error : BaseException or str
        The error (shown as :func:`error_line` makes it: one line, no traceback) or the text itself.

    Returns
    -------
    int
        2, the exit status of a bad request; 141 and nothing printed for a ``BrokenPipeError``: the reader
        of the output went away (``lighting-explorer render --list | head -2``), and a command-line tool
        then stops quietly.

    Examples
    --------
    >>> import contextlib, io
    >>> err = io.StringIO()
    >>> with contextlib.redirect_stderr(err):
    ...     status = print_error(ValueError("--size must be WIDTHxHEIGHT   or N; got 'x'"))
    >>> status, err.getvalue().splitlines()
    (2, ["lighting-explorer: error: --size must be WIDTHxHEIGHT or N; got 'x'"])
    """
    if isinstance(error, BrokenPipeError):
        _silence_stdout()
        return 141
    text = error_line(error) if isinstance(error, BaseException) else " ".join(str(error).split())
    print(ERROR_PREFIX + text, file=sys.stderr)
    return 2


def resolve_scene(arg: str, flag: str = "SCENE") -> str:
    """The scene file a command line names: a file, or the name of a shipped example (``spotlight``).

    One rule, for every option that takes a scene (``render SCENE``, ``explore --scene``): an argument
    ending in ``.toml`` or holding a path separator is a file, and must exist; a bare word is the
    name of a shipped example scene (``render --list``).  A missing file is never taken as a name.

    Parameters
    ----------
    arg : str
        A path (``my.toml``, ``./scenes/a.toml``), or an example's name.
    flag : str
        The argument named in the error (``SCENE``, ``--scene``).

    Returns
    -------
    str
        The path to load (the loader names a shipped example by its name in its messages).

    Raises
    ------
    ValueError
        One line: a file that does not exist (naming it as given), or a word that is no example's
        name (the closest name and the command that lists them).

    Examples
    --------
    >>> resolve_scene("spotlight").endswith("spotlight.toml")
    True
    >>> try:
    ...     resolve_scene("spotlite")
    ... except ValueError as e:
    ...     print(e)
    SCENE: no example scene named 'spotlite'; did you mean 'spotlight'? (list them: lighting-explorer render --list)
    """
    import os

    from lighting.scene import example_path, list_examples

    arg = str(arg)
    names = list_examples()
    if arg.endswith(".toml") or os.sep in arg or "/" in arg or (os.altsep and os.altsep in arg):
        if os.path.exists(arg):
            return arg
        from lighting.scene import SceneError

        stem = os.path.basename(arg)[:-5] if arg.endswith(".toml") else ""
        hint = f"; for the example scene, give its name alone: {stem}" if stem in names else ""
        # As the loader names a file ("x.toml: …"), with the option in front when it is one (--scene x.toml: …).
        raise SceneError(arg if flag == "SCENE" else f"{flag} {arg}", "", f"scene file does not exist{hint}")
    if arg in names:
        return example_path(arg)
    raise ValueError(f"{flag}: no example scene named {quote(arg)}{did_you_mean(arg, names)} "
                     f"(list them: {PROG} render --list)")  # fmt: skip


#: Optional modules → (what to call them, the extra that installs them).  A command that needs one says
#: so in one line (:func:`require`; :func:`main` turns any other missing one into the same line).
EXTRAS = {
    "matplotlib": ("Matplotlib", "figures"),
    "cycler": ("Matplotlib", "figures"),
    "kiwisolver": ("Matplotlib", "figures"),
    "contourpy": ("Matplotlib", "figures"),
    "fontTools": ("Matplotlib", "figures"),
    "pyparsing": ("Matplotlib", "figures"),
    "dateutil": ("Matplotlib", "figures"),
    "trimesh": ("trimesh", "figures"),
    "mpmath": ("mpmath", "figures"),
    "pyvista": ("PyVista", "app"),
    "vtk": ("PyVista", "app"),
    "vtkmodules": ("PyVista", "app"),
    "PySide6": ("Qt (PySide6)", "app"),
    "shiboken6": ("Qt (PySide6)", "app"),
    "pyvistaqt": ("pyvistaqt", "app"),
    "ipywidgets": ("ipywidgets", "notebook"),
}


class MissingExtra(UsageError):
    """An optional module a command needs is not installed: one line naming the extra, exit status 2."""


def missing_extra(command: str, module: str) -> MissingExtra:
    """The error for ``command`` needing the missing ``module``.

    Parameters
    ----------
    command : str
        The sub-command (``figures``, ``explore``, ``report stability``, …).
    module : str
        The module that could not be imported (its top-level package is looked up in :data:`EXTRAS`).

    Returns
    -------
    MissingExtra
        Its message names the command, what it needs and how to install it (printed as
        ``lighting-explorer: error: figures needs Matplotlib: pip install 'lighting-explorer[figures]'``).

    Examples
    --------
    >>> str(missing_extra("explore", "pyvista.plotting"))
    "explore needs PyVista: pip install 'lighting-explorer[app]'"
    """
    top = str(module or "").split(".")[0]
    who = f"{command} needs" if command else "needs"
    if top in EXTRAS:
        label, extra = EXTRAS[top]
        return MissingExtra(f"{who} {label}: pip install '{PROG}[{extra}]'")
    return MissingExtra(f"{who} the Python module {top!r}, which is not installed")


def require(command: str, *modules: str) -> None:
    """Import ``modules`` now, so that a missing extra is reported before any work, in one line.

    Parameters
    ----------
    command : str
        The sub-command that needs them.
    *modules : str
        Module names (``"matplotlib"``, ``"pyvista"``).

    Raises
    ------
    MissingExtra
        The first one that cannot be imported (also when one of its own dependencies is missing).
    """
    import importlib

    for name in modules:
        try:
            importlib.import_module(name)
        except ImportError as exc:
            missing = getattr(exc, "name", None) or name
            raise missing_extra(command, missing if missing.split(".")[0] in EXTRAS else name) from None


@functools.cache
def package_version() -> str:
    """The installed version of ``lighting-explorer`` (package metadata), or ``"unknown"`` when not installed.

    Read once per process: the metadata search lists every folder on the import path, and the parser that
    shows the version is built for every command run in the process.

    Returns
    -------
    str
        E.g. ``"0.1.0"``.
    """
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version(PROG)
    except PackageNotFoundError:  # pragma: no cover - a source tree that was never installed
        return "unknown"


def error_line(exc: BaseException) -> str:
    """The one line that reports ``exc`` to the user (no traceback, no temporary file names).

    Parameters
    ----------
    exc : BaseException
        The error.

    Returns
    -------
    str
        One line: an ``OSError``'s reason and file name, a fixed text for ``MemoryError`` and
        ``RecursionError``, else the message with its whitespace collapsed.
    """
    if isinstance(exc, OSError) and exc.strerror:
        name = exc.filename if exc.filename is not None else ""
        text = f"{exc.strerror}: {name}" if name != "" else exc.strerror
    elif isinstance(exc, MemoryError):
        text = "out of memory (reduce the size or the sample count)"
    elif isinstance(exc, RecursionError):
        text = "input nested too deeply"
    else:
        text = str(exc) or type(exc).__name__
    return " ".join(text.split())


#: The sub-commands in the order ``--help`` lists them: name → the module that offers ``add_parser(subparsers)``
#: and ``run(args)`` (see :mod:`explorer.commands`).
COMMANDS = {
    "sphere": "explorer.commands.sphere",
    "bench": "explorer.commands.bench",
    "render": "explorer.commands.render",
    "report": "explorer.reports",
    "explore": "explorer.app.command",
    "figures": "explorer.commands.figures",
}


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The one argparse tree of ``lighting-explorer``: every sub-command and its options.

    Each command module's ``add_parser(subparsers)`` adds its sub-parser (with ``func`` set to its
    ``run``).  Building it imports no window, figure or report code: ``render`` stays fast.

    Parameters
    ----------
    command : str, optional
        A key of :data:`COMMANDS`: the tree with that sub-command alone, which parses any line that starts
        with its name as the whole tree does (:func:`parse` builds it for such a line: the other commands'
        dozens of options are never needed there).  ``None`` (default): every sub-command, for ``--help``,
        a misspelt command and the documentation.

    Returns
    -------
    argparse.ArgumentParser
        A :class:`~explorer.parser.CommandTreeParser`: a bad command line raises
        :class:`~explorer.parser.UsageError`.
    """
    import importlib

    p = CommandTreeParser(
        prog=PROG,
        usage="%(prog)s [-h] [--version] COMMAND ...",
        description="Explore local illumination models. With no sub-command, opens the explorer window.",
        notes=f"'{PROG} COMMAND --help' lists a command's options and their defaults; they are also listed "
        "below. --memory-budget SIZE (anywhere on the line; e.g. 4G, 512M; default 2G) raises or lowers the "
        "memory any one request may use.",
    )
    p.add_argument("--version", action="version", version=f"{PROG} {package_version()}")
    # The commands are listed by the parser's own help (CommandTreeParser.format_commands), not by argparse.
    sub = p.add_subparsers(dest="command", required=True, parser_class=OneLineParser, metavar="COMMAND",
                           help=argparse.SUPPRESS, prog=PROG)  # fmt: skip
    for name, module in COMMANDS.items():
        if command is None or name == command:
            importlib.import_module(module).add_parser(sub)
    return p


def parse(argv: list[str]) -> argparse.Namespace:
    """Parse a command line with the tree of :func:`build_parser`.

    Parameters
    ----------
    argv : list of str
        The sub-command and its options.

    Returns
    -------
    argparse.Namespace
        The options; ``func`` is the sub-command's ``run``.

    Raises
    ------
    UsageError
        For a malformed line; a misspelt command gets the closest name; an unrecognized argument is
        reported by the sub-command's own parser, in its words (``(see lighting-explorer render --help)``).
    """
    parser = build_parser(argv[0] if argv and argv[0] in COMMANDS else None)
    command = command_parser(parser, argv)
    args, extras = parser.parse_known_args(argv)
    if extras:
        command.error(f"unrecognized arguments: {' '.join(extras)}")
    return args


def run_alone(name: str, argv=None) -> int:
    """Run one sub-command alone: what its module's ``main(argv)`` does.

    Unlike :func:`main`, no ``--memory-budget``, no signal handlers and no allocator tuning: the
    caller's process is left as it is.

    Parameters
    ----------
    name : str
        The sub-command (a key of :data:`COMMANDS` with a module).
    argv : list of str, optional
        Its options (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0 done, 2 a bad request (one line on standard error).
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    try:
        args = parse([name, *argv])
        return args.func(args)
    except SystemExit as exc:  # --help
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    except ImportError as exc:
        return print_error(missing_extra(name, getattr(exc, "name", None) or ""))
    except (ValueError, OSError, MemoryError, RecursionError) as exc:
        return print_error(exc)


def parse_and_run(build_parser, run, argv=None, *, errors=(ValueError,)) -> int:
    """A command's standalone ``main(argv)``: parse with its own parser, then ``run(args)``.

    A bad value raised while parsing (one of ``errors``) is printed as one line and gives status 2.

    Parameters
    ----------
    build_parser : callable
        Returns the command's ``argparse.ArgumentParser``.
    run : callable
        ``run(args) -> int``, the command itself.
    argv : list of str, optional
        The options (default: ``sys.argv[1:]``).
    errors : tuple of exception types
        What counts as a bad value while parsing.

    Returns
    -------
    int
        ``run``'s status, or 2 for a bad value.
    """
    try:
        args = build_parser().parse_args(argv)
    except errors as exc:
        return print_error(exc)
    return run(args)


_UNITS = {"": 1, "k": 1024, "m": 1024**2, "g": 1024**3, "t": 1024**4}


def parse_size(text: str, flag: str = "--memory-budget") -> int:
    """``"2G"``, ``"512M"``, ``"1.5g"``, ``"4GiB"``, ``"1000000"`` → bytes (binary units).

    Parameters
    ----------
    text : str
        The size.
    flag : str, optional
        The flag named in the error.

    Returns
    -------
    int
        Bytes, at least :data:`MIN_MEMORY_BUDGET`.

    Raises
    ------
    UsageError
        For anything else.

    Examples
    --------
    >>> parse_size("512M"), parse_size("1.5G")
    (536870912, 1610612736)
    """
    allowed = "a size such as 2G, 512M or 1.5G (K, M, G, T are powers of 1024; at least 1M)"
    m = re.fullmatch(r"\s*(\d+(?:\.\d*)?|\.\d+)\s*([kmgt]?)(?:i?b)?\s*", str(text), flags=re.IGNORECASE)
    if not m:
        raise UsageError(f"{flag} must be {allowed}; got {quote(text)}")
    value = float(m.group(1)) * _UNITS[m.group(2).lower()]
    if not MIN_MEMORY_BUDGET <= value < 2.0**62:
        raise UsageError(f"{flag} must be {allowed}; got {quote(text)}")
    return int(value)


def _take_memory_budget(argv: list[str]):
    """Remove every ``--memory-budget SIZE`` / ``--memory-budget=SIZE`` from ``argv``; the last one wins."""
    rest, budget, i = [], None, 0
    while i < len(argv):
        a = argv[i]
        if a == "--memory-budget":
            if i + 1 >= len(argv):
                raise UsageError("argument --memory-budget: expected one argument, a size such as 2G")
            budget = parse_size(argv[i + 1])
            i += 2
            continue
        if a.startswith("--memory-budget="):
            budget = parse_size(a.split("=", 1)[1])
        else:
            rest.append(a)
        i += 1
    return rest, budget


def _command_of(argv: list[str]) -> str:
    """The sub-command a command line runs (``report stability`` with its report), for a missing-extra line."""
    if not argv or argv[0].startswith("-"):
        return "explore" if not argv or argv[0] not in ("-h", "--help", "--version") else ""
    if argv[0] == "report" and len(argv) > 1 and not argv[1].startswith("-"):
        return f"report {argv[1]}"
    return argv[0]


def _dispatch(argv: list[str]) -> int:
    if not argv or (argv[0].startswith("--") and argv[0] not in ("--help", "--version")):
        # No sub-command: the explorer window, with explore's options (e.g. --off-screen --screenshot x.png).
        argv = ["explore", *argv]
    if argv[0] == "report" and (len(argv) == 1 or not argv[1].startswith("-") or argv[1] in ("-h", "--help")):
        from .reports import REPORTS
        from .reports import main as report_main

        if len(argv) == 1 or argv[1] not in REPORTS:  # the list of reports (exit 0), or "unknown report …"
            return report_main(argv[1:])
    args = parse(argv)
    return args.func(args)


def _silence_stdout() -> None:
    """Point standard output at the null device, so that Python's flush at exit does not fail on a closed pipe."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):
        pass  # no file descriptor behind sys.stdout (a test's capture): nothing will be flushed to a pipe


def main(argv=None) -> int:
    """Run ``lighting-explorer``.

    Parameters
    ----------
    argv : list of str, optional
        The command line after the program name (default: ``sys.argv[1:]``, the program's own: then a stop signal
        before the command ends the process with 143 or 130 at once, and one after it, while Python shuts down, is
        ignored: the command's status stands).

    Returns
    -------
    int
        The exit status: 0 done, 1 a check failed, 2 a bad request, 130 interrupted by Ctrl-C, 143 by
        ``SIGTERM``, 141 when the output's reader closed the pipe.
    """
    if argv is None:  # the program itself (the console script, python -m explorer.cli)
        from .output import program_stops

        # Set before the command's own handlers, which put these back when it returns: no moment without one.
        program_stops(after=False)
        try:
            return _main(list(sys.argv[1:]))
        finally:
            program_stops(after=True)
    return _main(list(argv))


def _main(argv: list) -> int:
    from ._allocator import tune_allocator
    from .output import Terminated, raise_if_signalled, signals_as_exceptions

    tune_allocator()  # see explorer/_allocator.py: the image pipeline's temporaries stop page-faulting
    previous = memory_budget()
    with signals_as_exceptions():
        try:
            argv, budget = _take_memory_budget(argv)
            if budget is not None:
                set_memory_budget(budget)
            status = _dispatch(argv)
            raise_if_signalled()  # a stop signal whose exception a library swallowed still ends as one
            return status
        except SystemExit as exc:  # --help, or a sub-command's own argparse
            return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
        except ImportError as exc:  # an optional module missing deep inside: still one line naming the extra
            return print_error(missing_extra(_command_of(argv), getattr(exc, "name", None) or ""))
        except KeyboardInterrupt:
            print(f"{PROG}: interrupted", file=sys.stderr)
            return 130
        except Terminated:
            print(f"{PROG}: terminated", file=sys.stderr)
            return 143
        except (ValueError, OSError, MemoryError, RecursionError) as exc:
            return print_error(exc)
        finally:
            set_memory_budget(previous)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

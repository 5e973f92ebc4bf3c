"""The command line's parser: argparse, with one-line errors and the help conventions of ``lighting-explorer``.

Every parser of the command tree is a :class:`OneLineParser`: a refusal is a :class:`UsageError`,
printed as one line by :func:`explorer.cli.print_error`, never argparse's usage text and ``exit(2)``.
Each option's help states its default (:func:`option_settings`), a misspelt choice, command or scene
gets the closest name (:func:`choice_type`, :func:`did_you_mean`), every ``--size`` reads the same
way (:func:`size_type`), and the top-level help lists the commands and every command's options
(:class:`CommandTreeParser`).  The entry point and the command table are :mod:`explorer.cli`'s.
"""

from __future__ import annotations

import argparse
import re
import shutil
import textwrap

from lighting._text import quote

__all__ = [
    "UsageError",
    "OneLineParser",
    "SubCommands",
    "option_settings",
    "OptionGroup",
    "choice_type",
    "CommandTreeParser",
    "leaf_commands",
    "options_section",
    "did_you_mean",
    "size_type",
    "command_parser",
]


class UsageError(ValueError):
    """A malformed command line (unknown option, missing value): one line, exit status 2."""


class OneLineParser(argparse.ArgumentParser):
    """An ``ArgumentParser`` whose errors are a :class:`UsageError` instead of usage text and ``exit(2)``.

    The caller prints the one line with :func:`explorer.cli.print_error`
    (``lighting-explorer: error: argument --dpi: invalid int value: 'x' (see lighting-explorer figures --help)``):
    every parser of the tree, a sub-command's or a report's, reports under the one prefix.  Its options follow
    the command line's conventions (:func:`option_settings`: each help states the default, a misspelt choice
    gets the closest one), and :meth:`add_subparsers` keeps each sub-command's parser and one-line help by
    name (``subcommands``, ``summaries``).
    """

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        #: Each sub-command's parser, by name, in the order they were added.
        self.subcommands: dict[str, argparse.ArgumentParser] = {}
        #: Each sub-command's one-line help, by name.
        self.summaries: dict[str, str] = {}
        #: What the sub-command is called in messages (``COMMAND``, ``REPORT``).
        self.subcommand_metavar = "COMMAND"

    def add_argument(self, *flags, **kwargs):
        """``ArgumentParser.add_argument`` with the settings of :func:`option_settings`.

        Returns
        -------
        argparse.Action
            What ``ArgumentParser.add_argument`` returns.
        """
        return super().add_argument(*flags, **option_settings(flags, kwargs, self.prefix_chars))

    def add_subparsers(self, **kwargs):
        """``ArgumentParser.add_subparsers``, whose ``add_parser`` also records each sub-command by name.

        Returns
        -------
        SubCommands
            Its ``add_parser(name, **kwargs)`` is argparse's.
        """
        self.subcommand_metavar = kwargs.get("metavar") or kwargs.get("dest") or self.subcommand_metavar
        return SubCommands(self, super().add_subparsers(**kwargs))

    def error(self, message):
        """Raise the refusal as a :class:`UsageError` (argparse calls this instead of printing usage).

        Parameters
        ----------
        message : str
            argparse's message; a quoted value over 80 characters is shortened.

        Raises
        ------
        UsageError
            The message, ending ``(see PROG COMMAND --help)`` with this parser's name.
        """
        from lighting._text import abbreviate

        # argparse quotes the whole value it refused: a 100,000-character one is cut short.
        message = re.sub(r"'[^']{81,}'", lambda m: abbreviate(m.group(0)), message)
        # A type check that names its flag itself: "argument --size: --size must be …" says it once.
        message = re.sub(r"^argument (\S+?)(?:/\S+)?: (\1 )", r"\2", message)
        raise UsageError(f"{message} (see {self.prog} --help)")


class SubCommands:
    """What :meth:`OneLineParser.add_subparsers` returns: argparse's ``add_parser``, each parser kept by name.

    Parameters
    ----------
    parent : OneLineParser
        The parser whose sub-commands these are.
    subparsers : object
        What ``ArgumentParser.add_subparsers`` returned.
    """

    def __init__(self, parent: OneLineParser, subparsers):
        self.parent = parent
        self.subparsers = subparsers

    def add_parser(self, name: str, **kwargs) -> argparse.ArgumentParser:
        """Add the sub-command ``name`` as argparse's ``add_parser`` does, and record it in the parent.

        Parameters
        ----------
        name : str
            The sub-command.
        **kwargs
            As argparse's ``add_parser``: ``help`` (its line in the list of commands), ``description``, ….

        Returns
        -------
        argparse.ArgumentParser
            The sub-command's parser (of the ``parser_class`` given to ``add_subparsers``, else the parent's class).
        """
        parser = self.subparsers.add_parser(name, **kwargs)
        self.parent.subcommands[name] = parser
        self.parent.summaries[name] = " ".join(str(kwargs.get("help") or "").split())
        return parser


def option_settings(flags, kwargs: dict, prefix_chars: str = "-") -> dict:
    """The arguments of ``add_argument(*flags, **kwargs)`` under the command line's two conventions.

    * The help states the default, ``(default: 384)``, unless it already speaks of its default, or the
      default is ``None`` or ``False`` (a flag, or "keep what the scene or the control says"), empty or
      suppressed, or the argument is positional; a ``(width, height)`` pair shows as ``WxH``, a list with
      commas.
    * An option with ``choices`` and no ``type`` is checked by :func:`choice_type`: a misspelt value gets
      the closest choice.

    Parameters
    ----------
    flags : sequence of str
        The option's names (``"-o", "--out"``) or a positional argument's name.
    kwargs : dict
        The other arguments of ``add_argument``.
    prefix_chars : str
        The parser's option prefix characters.

    Returns
    -------
    dict
        ``kwargs`` with ``help`` and ``type`` set as above (a new dict).

    Examples
    --------
    >>> option_settings(["--size"], {"default": (384, 384), "help": "image size"})["help"]
    'image size (default: 384x384)'
    >>> option_settings(["--quick"], {"action": "store_true", "help": "fewer samples"})["help"]
    'fewer samples'
    """
    out = dict(kwargs)
    if out.get("choices") is not None and out.get("type") is None and out.get("action") in (None, "store", "append"):
        out["type"] = choice_type(out["choices"])
    text, default = out.get("help"), out.get("default")
    optional = bool(flags) and str(flags[0])[:1] in prefix_chars
    if (
        text
        and text is not argparse.SUPPRESS
        and optional
        and "default" not in text.lower()
        and default is not None
        and default is not False
        and default is not argparse.SUPPRESS
        and not (isinstance(default, (list, tuple)) and len(default) == 0)
    ):
        if isinstance(default, tuple) and len(default) == 2 and all(isinstance(v, int) for v in default):
            shown = f"{default[0]}x{default[1]}"
        elif isinstance(default, (list, tuple)):
            shown = ",".join(str(v) for v in default)
        else:
            shown = str(default)
        out["help"] = f"{text} (default: {shown.replace('%', '%%')})"  # argparse expands %(…)s in help
    return out


class OptionGroup:
    """An argument group (``ArgumentParser.add_argument_group``) whose options follow :func:`option_settings`.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The parser the group belongs to.
    title : str
        The group's title in the parser's help.
    """

    def __init__(self, parser: argparse.ArgumentParser, title: str):
        self.group = parser.add_argument_group(title)
        self.prefix_chars = parser.prefix_chars

    def add_argument(self, *flags, **kwargs):
        """Add an option to the group as ``add_argument`` does, with the settings of :func:`option_settings`.

        Returns
        -------
        argparse.Action
            What ``add_argument`` returns.
        """
        return self.group.add_argument(*flags, **option_settings(flags, kwargs, self.prefix_chars))


def choice_type(choices):
    """The argparse ``type`` of an option with ``choices``: the value itself, or one line with the closest choice.

    Parameters
    ----------
    choices : sequence of str
        The values allowed.

    Returns
    -------
    callable
        ``text -> text``, raising ``argparse.ArgumentTypeError`` (argparse puts ``argument --flag:`` in front).

    Examples
    --------
    >>> pick = choice_type(("clamp", "reinhard"))
    >>> pick("clamp")
    'clamp'
    >>> try:
    ...     pick("reinhart")
    ... except argparse.ArgumentTypeError as e:
    ...     print(e)
    invalid choice: 'reinhart'; did you mean 'reinhard'? (choose from 'clamp', 'reinhard')
    """
    allowed = tuple(choices)

    def choice(text):
        if text in allowed:
            return text
        hint = did_you_mean(str(text), [str(c) for c in allowed])
        raise argparse.ArgumentTypeError(
            f"invalid choice: {quote(text)}{hint} (choose from {', '.join(repr(c) for c in allowed)})"
        )

    return choice


class CommandTreeParser(OneLineParser):
    """The top of the command tree: its help lists the commands, one line each, then every command's options.

    ``lighting-explorer --help`` thus shows each option of each command with its default (the
    sub-commands' own ``--help`` shows the same lines with the command's description).

    Parameters
    ----------
    *args, **kwargs
        As :class:`argparse.ArgumentParser`.
    notes : str
        A paragraph after the list of commands (argparse's ``epilog`` would come before the list).
    """

    def __init__(self, *args, notes: str = "", **kwargs):
        super().__init__(*args, **kwargs)
        self.notes = notes

    def format_help(self) -> str:
        """Usage, description and options; the commands; the notes; each runnable command's options.

        Returns
        -------
        str
            The help text, wrapped to the terminal's width as argparse wraps its own.
        """
        width = max(shutil.get_terminal_size().columns - 2, 40)
        parts = [super().format_help(), self.format_commands(width)]
        if self.notes:
            parts.append(textwrap.fill(" ".join(self.notes.split()), width))
        parts += [options_section(name, command) for name, command in leaf_commands(self)]
        return "\n\n".join(p.strip("\n") for p in parts if p.strip()) + "\n"

    def format_commands(self, width: int) -> str:
        """``commands:`` and a row per sub-command: its name, then its help wrapped as argparse wraps an option's.

        Parameters
        ----------
        width : int
            Characters per line.

        Returns
        -------
        str
            The section.
        """
        # The help column of the options above it ("  -h, --help  "), or further right for a longer name.
        column = min(max(len("  -h, --help  "), 4 + max(map(len, self.subcommands), default=0) + 2), 24)
        rows = ["commands:"]
        for name, text in self.summaries.items():
            lines = textwrap.wrap(text, max(width - column, 20)) or [""]
            if 4 + len(name) + 2 > column:  # a long name: its help starts on the next line
                rows.append(f"    {name}")
                rows += [" " * column + line for line in lines]
            else:
                rows.append(f"    {name}".ljust(column) + lines[0])
                rows += [" " * column + line for line in lines[1:]]
        return "\n".join(rows)


def leaf_commands(parser: argparse.ArgumentParser, prefix: str = ""):
    """``(name, parser)`` of every runnable command under ``parser`` (``report accuracy``, not ``report``).

    Parameters
    ----------
    parser : OneLineParser
        A parser whose sub-commands were added through :meth:`OneLineParser.add_subparsers`.
    prefix : str
        Put before each name.

    Yields
    ------
    (str, argparse.ArgumentParser)
        In the order the commands were added.
    """
    for name, command in getattr(parser, "subcommands", {}).items():
        if getattr(command, "subcommands", None):
            yield from leaf_commands(command, f"{prefix}{name} ")
        else:
            yield f"{prefix}{name}", command


def options_section(name: str, command: argparse.ArgumentParser) -> str:
    """``NAME options:`` and the lines of each option in ``command``'s own help (not ``--help``, not positionals).

    Parameters
    ----------
    name : str
        The command, as typed after the program's name.
    command : argparse.ArgumentParser
        Its parser.

    Returns
    -------
    str
        The section: the option lines exactly as ``command.format_help()`` prints them, its groups merged.
    """
    kept, keep = [], False
    for block in command.format_help().split("\n\n"):
        rows = block.splitlines()
        if not rows or rows[0].startswith(" ") or not rows[0].endswith(":"):  # usage, description, epilog
            continue
        for row in rows[1:]:
            if re.match(r"  \S", row):  # an argument's first line; an option's starts with its flag
                keep = row[2:].startswith("-") and not re.match(r"  -h, --help\b", row)
            if keep:
                kept.append(row)
    return "\n".join([f"{name} options:", *kept])


def did_you_mean(word: str, candidates) -> str:
    """``"; did you mean 'render'?"`` for the candidate closest to ``word`` (:mod:`difflib`), else ``""``.

    Parameters
    ----------
    word : str
        What the user typed.
    candidates : iterable of str
        The names allowed.

    Returns
    -------
    str
        The hint, to append to a message, or an empty string when nothing is close.

    Examples
    --------
    >>> did_you_mean("spotlite", ["cube", "spotlight"])
    "; did you mean 'spotlight'?"
    >>> did_you_mean("zzz", ["cube", "spotlight"])
    ''
    """
    import difflib

    names = [str(c) for c in candidates]
    folded = {n.lower().replace("_", "-"): n for n in names}
    close = difflib.get_close_matches(str(word).lower().replace("_", "-"), list(folded), n=1, cutoff=0.6)
    return f"; did you mean {folded[close[0]]!r}?" if close else ""


def size_type(flag: str = "--size", *, minimum=(1, 1), maximum=None, example: str = "640x480 or 512"):
    """The argparse ``type`` of every ``--size``: ``WxH`` (``640x480``, ``640×480``) or ``N`` for ``NxN``.

    Parameters
    ----------
    flag : str
        The flag named in the error.
    minimum, maximum : (int, int), optional
        Smallest and largest ``(width, height)`` allowed (default: at least 1x1, no upper bound).
    example : str
        Examples shown in the error.

    Returns
    -------
    callable
        ``text -> (width, height)``, raising ``argparse.ArgumentTypeError`` with one line naming the
        flag, what is allowed and what was given.

    Examples
    --------
    >>> parse = size_type()
    >>> parse("640x480"), parse("512"), parse(" 3 X 2 ")
    ((640, 480), (512, 512), (3, 2))
    """

    def parse(text: str):
        m = re.fullmatch(r"\s*(\d{1,9})\s*(?:[xX×]\s*(\d{1,9})\s*)?", str(text))
        size = (int(m.group(1)), int(m.group(2) or m.group(1))) if m else None
        ok = size is not None and size[0] >= minimum[0] and size[1] >= minimum[1]
        if ok and maximum is not None:
            ok = size[0] <= maximum[0] and size[1] <= maximum[1]
        if not ok:
            lo = "both >= 1" if tuple(minimum) == (1, 1) else f"at least {minimum[0]}x{minimum[1]}"
            hi = f" and at most {maximum[0]}x{maximum[1]}" if maximum is not None else ""
            raise argparse.ArgumentTypeError(
                f"{flag} must be WIDTHxHEIGHT or N (a square) in pixels, {lo}{hi} (e.g. {example}); got {quote(text)}"
            )
        return size

    return parse


def command_parser(parser: argparse.ArgumentParser, argv: list[str]) -> argparse.ArgumentParser:
    """The parser of the command that ``argv`` runs: the deepest sub-command its first words name.

    Parameters
    ----------
    parser : OneLineParser
        The top of a tree built through :meth:`OneLineParser.add_subparsers`.
    argv : list of str
        The command line.

    Returns
    -------
    argparse.ArgumentParser
        ``parser`` itself when ``argv`` starts with an option.

    Raises
    ------
    UsageError
        A word where a sub-command belongs that names none: the closest name and the names allowed.
    """
    node = parser
    for word in argv:
        names = getattr(node, "subcommands", None)
        if not names or word.startswith("-"):
            break
        if word not in names:
            node.error(f"argument {node.subcommand_metavar}: invalid choice: {quote(word)}{did_you_mean(word, names)} "
                       f"(choose from {', '.join(repr(n) for n in names)})")  # fmt: skip
        node = names[word]
    return node

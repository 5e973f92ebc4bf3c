"""The one argparse tree of ``lighting-explorer`` (explorer/cli.py and explorer/commands/)."""

from __future__ import annotations

import importlib
import re

import pytest

from explorer import cli
from explorer.parser import UsageError


def test_every_command_module_offers_add_parser_run_and_main():
    for module in cli.COMMANDS.values():
        mod = importlib.import_module(module)
        for attr in ("add_parser", "run", "main"):
            assert callable(getattr(mod, attr)), (module, attr)


def test_the_tree_lists_the_commands_in_order_with_their_options():
    parser = cli.build_parser()
    assert list(parser.subcommands) == list(cli.COMMANDS)
    args = cli.parse(["sphere", "--size", "12"])
    assert args.command == "sphere" and args.size == (12, 12) and args.func.__module__ == "explorer.commands.sphere"
    args = cli.parse(["render", "spotlight", "--size", "40x30"])
    assert args.scene == "spotlight" and args.size == (40, 30)
    args = cli.parse(["figures", "--only", "falloff", "-j", "1"])
    assert args.only == ["falloff"] and args.jobs == 1
    assert cli.parse(["bench", "--repeat", "3"]).repeat == 3
    args = cli.parse(["explore", "--model", "phong", "--elevation", "30"])
    assert (args.model, args.elevation) == ("phong", 30.0) and args.func.__module__ == "explorer.app.command"
    args = cli.parse(["report", "stability", "--dtype", "float32", "--workers", "1"])
    assert (args.report, args.dtype, args.workers) == ("stability", "float32", 1)
    assert args.func.__module__ == "explorer.reports"  # which loads the report's module only to run it


def test_the_top_level_help_lists_every_command_s_options_with_their_defaults(monkeypatch):
    monkeypatch.setenv("COLUMNS", "400")
    text = re.sub(r"\n {20,}", " ", cli.build_parser().format_help())  # a long option's text on its next line
    sections = re.findall(r"^(\w[\w ]*) options:$", text, re.M)
    assert sections == ["sphere", "bench", "render", "report accuracy", "report stability", "explore", "figures"]
    for line in ("--shininess E +Blinn-Phong exponent, >= 0 \\(default: 40\\.0\\)",
                 "--dtype \\{float32,float64,both\\} +which float types \\(default: both\\)",
                 "--elevation ELEVATION +light elevation above the image plane, degrees \\(default: 45\\)",
                 "--out DIR, -o DIR +output folder \\(default: out/figures\\)"):  # fmt: skip
        assert re.search("^  " + line + "$", text, re.M), line
    # The same lines as each command's own --help: one definition of each option.
    parser = cli.build_parser()
    leaves = dict(cli.leaf_commands(parser))
    assert list(leaves) == sections
    for name, command in leaves.items():
        own = re.sub(r"\n {20,}", " ", command.format_help())
        flags = re.findall(r"^  (-.+?)(?:  |$)", own, re.M)
        assert len(flags) > 1 and flags[0] == "-h, --help", (name, flags)
        for flag in flags[1:]:
            line = next(ln for ln in own.splitlines() if ln.startswith(f"  {flag}"))
            assert line in text.splitlines(), (name, line)


def _parsed(argv):
    """What :func:`cli.parse` makes of ``argv``: its options, or the one line that refuses it."""
    try:
        return vars(cli.parse(argv))
    except UsageError as exc:
        return str(exc)


def test_a_line_parses_alike_with_its_command_alone_and_with_the_whole_tree(monkeypatch):
    # parse() builds the tree with the command a line names alone: each leaf command's lines (bare, with an
    # unknown option, and with each of its options that takes a value given one no option accepts) must come out
    # with the same options, or be refused in the same words, as through the whole tree, and each command's help
    # must read the same.
    monkeypatch.setenv("COLUMNS", "400")
    build = cli.build_parser
    whole = build()
    lines = []
    for name, command in cli.leaf_commands(whole):
        path = name.split()
        alone = build(path[0])
        assert list(alone.subcommands) == [path[0]]
        assert cli.command_parser(alone, path).format_help() == command.format_help(), name
        # "  --size WxH", "  -o OUT, --out OUT", "  -D KEY=VALUE": an option that takes a value.
        flags = re.findall(r"^  (?:-\w \S+, )?(--?[\w-]+) (?! )", command.format_help(), re.M)
        assert flags, name
        lines += [path, [*path, "--no-such-option"], *([*path, flag, "§"] for flag in flags)]
    assert len(lines) > 50
    built = []
    monkeypatch.setattr(cli, "build_parser", lambda command=None: built.append(command) or build(command))
    alone_results = [_parsed(argv) for argv in lines]
    assert built == [argv[0] for argv in lines]  # each line through its command's tree alone
    monkeypatch.setattr(cli, "build_parser", lambda command=None: build())
    for argv, got in zip(lines, alone_results, strict=True):
        assert _parsed(argv) == got, argv


def test_building_the_tree_loads_no_figure_window_or_report_code():
    import subprocess
    import sys

    # Nor the window, the reports' work or what they need: the tree is built for every run, render's too.
    heavy = (
        "('matplotlib', 'explorer.figures', 'pyvista', 'vtk', 'mpmath', 'PySide6', 'explorer.qt', "
        "'explorer.app.comparing', 'lighting.integrate', 'lighting.analysis', 'lighting.validation.stability', "
        "'explorer.reports.accuracy', 'explorer.reports.stability')"
    )
    loaded = f"sorted(m for m in sys.modules if m.startswith({heavy}))"
    code = f"import sys, explorer.cli as c; c.build_parser(); print({loaded})"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out == "[]"


@pytest.mark.parametrize(
    ("argv", "line"),
    [
        (
            ["render", "x", "--bogus"],
            "lighting-explorer: error: unrecognized arguments: --bogus (see lighting-explorer render --help)",
        ),
        (
            ["bench", "extra"],
            "lighting-explorer: error: unrecognized arguments: extra (see lighting-explorer bench --help)",
        ),
        (
            ["figures", "--bogus"],
            "lighting-explorer: error: unrecognized arguments: --bogus (see lighting-explorer figures --help)",
        ),
        (
            ["figures", "--dpi", "many"],
            "lighting-explorer: error: argument --dpi: invalid int value: 'many' "
            "(see lighting-explorer figures --help)",
        ),
        (
            ["render", "x", "--tonemap", "no"],
            "lighting-explorer: error: argument --tonemap: invalid choice: 'no' "
            "(choose from 'clamp', 'reinhard') (see lighting-explorer render --help)",
        ),
    ],
)
def test_a_bad_line_is_reported_in_the_words_of_its_sub_command(argv, line, capsys):
    assert cli.main(argv) == 2
    assert capsys.readouterr().err == line + "\n"
    # Run alone (the module's main), the command reports the same line.
    assert importlib.import_module(cli.COMMANDS[argv[0]]).main(argv[1:]) == 2
    assert capsys.readouterr().err == line + "\n"

"""The command line's conventions: help with defaults, --version, one --size, did-you-mean, render --list,
-D overrides, --explain, explore --scene NAME, and one line for a missing extra."""

from __future__ import annotations

import importlib.metadata
import re
import tomllib

import numpy as np
import pytest

from explorer import cli
from explorer.commands import render as render_cmd
from lighting.scene import SceneRenderer, example_path, list_examples, parse_scene
from lighting.scene.examples import EXAMPLES_DIR


def run(argv, capsys):
    """``lighting-explorer ARGV`` in-process: (status, stdout, stderr), stderr at most one line, no traceback."""
    status = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert "Traceback" not in err and err.count("\n") <= 1, err
    return status, out, err


def help_text(argv, capsys, monkeypatch) -> str:
    monkeypatch.setenv("COLUMNS", "400")  # one line per option: the lines below are matched whole
    status, out, _ = run([*argv, "--help"], capsys)
    assert status == 0
    return out


# ----------------------------------------------------------------------------- help, version
@pytest.mark.parametrize(
    ("argv", "pattern"),
    [
        (["sphere"], r"--size WxH +image size in pixels, WIDTHxHEIGHT or N for a square; the sphere fills the "
                     r"shorter side \(default: 384x384\)"),
        (["sphere"], r"--shininess E +Blinn-Phong exponent, >= 0 \(default: 40\.0\)"),
        (["sphere"], r"--exposure STOPS +exposure in stops, -100 to 100 \(8-bit formats\) \(default: 0\.0\)"),
        (["sphere"], r"--tonemap \{clamp,reinhard\} +tone map \(8-bit formats\) \(default: clamp\)"),
        (["render"], r"--size WxH +image size in pixels, WIDTHxHEIGHT or N for a square \(default: the scene's "
                     r"\[image\] size\)"),
        (["bench"], r"--repeat N +timed runs per measurement, 1 to 10000 \(median; default 15, or 3 with --ibl\)"),
        (["figures"], r"--format FORMATS +comma-separated formats among png, svg, pdf \(default: png\)"),
        (["figures"], r"--out DIR, -o DIR +output folder \(default: out/figures\)"),
        (["explore"], r"--elevation ELEVATION +light elevation above the image plane, degrees \(default: 45\)"),
        (["explore"], r"--model \{.*\} +reflectance model .* \(default: blinn-phong\)"),
        (["explore"], r"--size WxH +window size in pixels, WIDTHxHEIGHT or N for a square \(default: 1280x768\)"),
        (["report", "accuracy"], r"--out DIR +output folder \(default: out/accuracy\)"),
        (["report", "stability"], r"--dtype \{float32,float64,both\} +which float types \(default: both\)"),
    ],
)  # fmt: skip
def test_help_lines_state_the_defaults(argv, pattern, capsys, monkeypatch):
    text = re.sub(r"\n {20,}", " ", help_text(argv, capsys, monkeypatch))  # a long option's text on its next line
    lines = [ln.strip() for ln in text.splitlines()]
    assert any(re.fullmatch(pattern, ln) for ln in lines), "\n".join(lines)


def test_every_option_with_a_default_shows_that_default(monkeypatch):
    monkeypatch.setenv("COLUMNS", "400")  # one line per option
    checked = 0
    for name, command in cli.leaf_commands(cli.build_parser()):
        lines = re.sub(r"\n {20,}", " ", command.format_help()).splitlines()  # a long option's text on its next line
        for dest, default in vars(command.parse_args([])).items():  # what each option is when not given
            if default is None or default is False or default == [] or callable(default):
                continue
            flag = "--" + dest.replace("_", "-")
            line = next(ln for ln in lines if re.match(rf"  (-\w \S+, )?{flag}\b", ln))
            shown = f"{default[0]}x{default[1]}" if isinstance(default, tuple) else str(default)
            assert line.endswith(f"(default: {shown})"), (name, flag, line)
            checked += 1
    assert checked >= 16  # sphere 10, figures 2, the reports 3, explore 1 (render's defaults are the scene's)


def test_top_level_help_lists_each_command_on_one_line_and_how_to_see_its_options(capsys, monkeypatch):
    monkeypatch.setenv("COLUMNS", "80")
    status, out, _ = run(["--help"], capsys)
    assert status == 0
    rows = {m.group(1): m.group(2) for m in re.finditer(r"^    (\w+) +(.+)$", out, re.M)}
    assert list(rows) == list(cli.COMMANDS)  # each one line, in order, even at 80 columns
    assert rows["render"] == "a scene file or an example scene to an image"
    assert "'lighting-explorer COMMAND --help' lists a command's options and their" in out


def test_version_comes_from_the_package_metadata(capsys):
    status, out, _ = run(["--version"], capsys)
    assert status == 0
    assert out == f"lighting-explorer {importlib.metadata.version('lighting-explorer')}\n"


# ----------------------------------------------------------------------------- one --size
@pytest.mark.parametrize(("text", "size"), [("12", (12, 12)), ("640x480", (640, 480)), ("3×2", (3, 2))])
def test_size_means_wxh_or_n_for_a_square_in_every_command(text, size):
    assert cli.parse(["sphere", "--size", text]).size == size
    assert cli.parse(["render", "spotlight", "--size", text]).size == size
    window = cli.size_type("--size", minimum=(1, 1))
    assert window(text) == size


SIZE = "lighting-explorer: error: --size must be WIDTHxHEIGHT or N (a square) in pixels, "


@pytest.mark.parametrize(
    ("argv", "line"),
    [
        (["sphere", "--size", "0"],
         SIZE + "both >= 1 (e.g. 384 or 640x480); got '0' (see lighting-explorer sphere --help)"),
        (["render", "spotlight", "--size", "4x"],
         SIZE + "both >= 1 (e.g. 640x480 or 512); got '4x' (see lighting-explorer render --help)"),
        (["explore", "--size", "500"],
         SIZE + "at least 800x500 and at most 8192x8192 (e.g. 1280x768); got '500' (see lighting-explorer --help)"),
    ],
)  # fmt: skip
def test_a_bad_size_is_one_line_naming_the_flag_what_is_allowed_and_what_was_given(argv, line, capsys):
    status, _, err = run(argv, capsys)
    assert status == 2 and err == line + "\n"


def test_sphere_wxh_centres_the_square_sphere_on_the_background(tmp_path, capsys):
    run(["sphere", "--size", "20", "-o", tmp_path / "sq.npy"], capsys)
    status, out, _ = run(["sphere", "--size", "30x20", "-o", tmp_path / "wide.npy"], capsys)
    assert status == 0 and out.startswith(f"wrote {tmp_path / 'wide.npy'} (30x20, linear float")
    square, wide = np.load(tmp_path / "sq.npy"), np.load(tmp_path / "wide.npy")
    assert wide.shape == (20, 30, 3)
    np.testing.assert_array_equal(wide[:, 5:25], square)  # the same sphere, 5 columns of background each side
    assert not wide[:, :5].any() and not wide[:, 25:].any()


# ----------------------------------------------------------------------------- did you mean
@pytest.mark.parametrize(
    ("argv", "hint"),
    [
        (["rendr"], "invalid choice: 'rendr'; did you mean 'render'?"),
        (["render", "spotlite"], "SCENE: no example scene named 'spotlite'; did you mean 'spotlight'?"),
        (["render", "spotlight", "--tonemap", "reinhart"], "invalid choice: 'reinhart'; did you mean 'reinhard'?"),
        (["explore", "--model", "blin-phong"], "invalid choice: 'blin-phong'; did you mean 'blinn-phong'?"),
        (["explore", "--scene", "cub"], "--scene: no example scene named 'cub'; did you mean 'cube'?"),
        (["report", "stabilty"], "unknown report 'stabilty'; did you mean 'stability'?"),
        (["figures", "--only", "faloff", "--out", "unused"], "unknown figure 'faloff'; did you mean 'falloff'?"),
    ],
)
def test_every_name_suggests_the_closest_one(argv, hint, capsys):
    status, _, err = run(argv, capsys)
    assert status == 2 and hint in err


def test_an_unknown_scene_name_without_a_close_one_names_the_command_that_lists_the_examples(capsys):
    status, _, err = run(["render", "qqqq"], capsys)
    assert status == 2
    assert err == ("lighting-explorer: error: SCENE: no example scene named 'qqqq' "
                   "(list them: lighting-explorer render --list)\n")  # fmt: skip


# ----------------------------------------------------------------------------- render --list, explore --scene
def test_render_list_prints_each_example_with_its_description(capsys):
    status, out, _ = run(["render", "--list"], capsys)
    assert status == 0
    rows = [re.split(r"\s{2,}", ln, maxsplit=1) for ln in out.splitlines()]
    assert [r[0] for r in rows] == list_examples()
    for name, description in rows:
        with open(example_path(name), "rb") as f:
            assert description == tomllib.load(f)["description"]
    assert dict(rows)["spotlight"] == "A spotlight: a bright disc with a sharp edge, black outside the cone"


class _FakeWindow:
    made: list = []

    def __init__(self, state, **kwargs):
        self.state = state
        _FakeWindow.made.append(self)

    def image(self):
        return np.zeros((8, 8, 3), np.uint8)

    def close(self):
        pass


def test_explore_scene_takes_an_example_name_as_render_does(tmp_path, monkeypatch, capsys):
    import explorer.app as app_mod
    from explorer.app.scenes import state_from_scene

    monkeypatch.setattr(app_mod, "ExplorerApp", _FakeWindow)
    _FakeWindow.made.clear()
    status, _, err = run(["explore", "--scene", "spotlight", "--screenshot", tmp_path / "s.png"], capsys)
    assert status == 0, err
    assert _FakeWindow.made[0].state == state_from_scene(example_path("spotlight"))
    assert _FakeWindow.made[0].state.light == "spot"


# ----------------------------------------------------------------------------- -D overrides
def _edited(name, edit):
    with open(example_path(name), "rb") as f:
        data = tomllib.load(f)
    edit(data)
    return parse_scene(data, source="edited", base_dir=EXAMPLES_DIR)


def test_defines_set_values_as_editing_the_file_would(tmp_path, capsys):
    defines = ["image.width=40", "image.height=30", "lights[1].intensity=2",
               "materials.red_plastic.parts[0].kd=[0.9,0.1,0.1]", "render.form=physical"]  # fmt: skip
    scene = render_cmd.load_with_defines(example_path("point_ambient"), defines)

    def edit(d):
        d["image"].update(width=40, height=30)
        d["lights"][1]["intensity"] = 2
        d["materials"]["red_plastic"]["parts"][0]["kd"] = [0.9, 0.1, 0.1]
        d["render"]["form"] = "physical"

    by_hand = _edited("point_ambient", edit)
    assert scene.to_dict() == by_hand.to_dict()
    assert (scene.camera.width, scene.camera.height) == (40, 30) and scene.render.form == "physical"
    assert scene.lights[1].intensity == 2.0
    out = tmp_path / "d.npy"
    status, _, err = run(["render", "point_ambient", *[a for d in defines for a in ("-D", d)], "-o", out], capsys)
    assert status == 0, err
    np.testing.assert_array_equal(np.load(out), SceneRenderer(by_hand).render()[0])


def test_a_later_define_wins_and_a_missing_table_is_created():
    scene = render_cmd.load_with_defines(example_path("spotlight"), ["image.width=50", "image.width=64",
                                                                     "image.exposure=1.5"])  # fmt: skip
    assert scene.camera.width == 64 and scene.image.exposure == 1.5
    from explorer.commands.defines import apply_defines

    assert apply_defines({}, ["render.mode=gouraud", "image.background=[0, 0.5, 1]"]) == {
        "render": {"mode": "gouraud"},
        "image": {"background": [0, 0.5, 1]},
    }
    with pytest.raises(ValueError, match=r"^-D 'a\.b\[0\]=1': a\.b has no entries; got \[0\]$"):
        apply_defines({}, ["a.b[0]=1"])


@pytest.mark.parametrize(
    ("define", "text"),
    [
        ("image.width=0", "image.width: must be an integer in [1, 16384]; got 0 (with -D image.width=0)"),
        ("lights[3].intensity=2", "-D 'lights[3].intensity=2': lights has 1 entry (index 0); got [3]"),
        ("image.width", "-D 'image.width': expected KEY=VALUE"),
        ("image..width=3", "the key must be names joined by '.'"),
        ("image.width=[1,", "the value must be a TOML value"),
        ("camera.eye[0].x=1", "-D 'camera.eye[0].x=1': camera.eye[0] is a number, not a table; .x needs one"),
        ("image[0]=1", "-D 'image[0]=1': image is a table, not an array; [0] needs one"),
    ],
)
def test_a_bad_define_is_one_line_naming_it(define, text, tmp_path, capsys):
    out = tmp_path / "x.png"
    status, _, err = run(["render", "spotlight", "-D", define, "-o", out], capsys)
    assert status == 2 and text in err and not out.exists()


# ----------------------------------------------------------------------------- --explain
def test_explain_prints_the_plan_and_renders_and_writes_nothing(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    plan = SceneRenderer(render_cmd.load_with_defines(example_path("spotlight"))).explain()
    monkeypatch.setattr(SceneRenderer, "render", lambda self: pytest.fail("--explain rendered"))
    status, out, _ = run(["render", "spotlight", "--explain"], capsys)
    assert status == 0 and out == plan + "\n"
    assert list(tmp_path.iterdir()) == []


def test_explain_with_an_output_also_renders_and_writes(tmp_path, capsys):
    out = tmp_path / "e.png"
    status, text, _ = run(["render", "spotlight", "--explain", "--size", "32x24", "-o", out], capsys)
    assert status == 0 and out.exists() and text.splitlines()[0] == "2 objects, 1 light, 32x24 pixels."
    assert text.splitlines()[-1].startswith(f"wrote {out} (32x24,")

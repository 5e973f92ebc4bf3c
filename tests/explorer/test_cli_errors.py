"""The command line's errors as a new user meets them: one line, one prefix, in the words the user typed.

Each test runs the real command (``explorer.cli.main``) and checks the exit status and the whole line.
"""

from __future__ import annotations

import io
import re
import subprocess
import sys
import tokenize
from pathlib import Path

import numpy as np
import pytest

from explorer import cli
from lighting._text import plural
from lighting.scene import example_path
from lighting.scene.examples import EXAMPLES_DIR

PREFIX = "lighting-explorer: error: "
SPOT_KEYS = "type, position, direction, cutoff_deg, exponent, color, intensity, attenuation"


def run(argv, capsys):
    """``lighting-explorer ARGV`` in-process: (status, stdout, stderr)."""
    status = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


def error(argv, capsys) -> str:
    """The one error line of a refused command (exit status 2, nothing on standard output), without its prefix."""
    status, out, err = run(argv, capsys)
    assert status == 2, (argv, status, out, err)
    assert out == "" and err.endswith("\n") and err.count("\n") == 1, err
    assert err.startswith(PREFIX), err
    return err[len(PREFIX):-1]


# ----------------------------------------------------------------------------- a scene: a file or a name
def test_a_toml_name_that_is_not_a_file_is_refused_not_rendered_as_the_example(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert error(["render", "spotlight.toml"], capsys) == (
        "spotlight.toml: scene file does not exist; for the example scene, give its name alone: spotlight"
    )
    assert error(["render", "./spotlight.toml"], capsys) == (
        "./spotlight.toml: scene file does not exist; for the example scene, give its name alone: spotlight"
    )
    assert error(["render", "scenes/mine"], capsys) == "scenes/mine: scene file does not exist"
    assert error(["render", "mine.toml"], capsys) == "mine.toml: scene file does not exist"
    assert error(["explore", "--scene", "spotlight.toml"], capsys) == (
        "--scene spotlight.toml: scene file does not exist; for the example scene, give its name alone: spotlight"
    )
    assert list(tmp_path.iterdir()) == []  # nothing rendered, nothing written


def test_a_toml_file_that_exists_is_read_and_a_bare_word_is_always_an_example(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "spotlight.toml").write_bytes(Path(example_path("cube")).read_bytes().replace(b"cube.obj", b"c.obj"))
    (tmp_path / "c.obj").write_bytes(Path(EXAMPLES_DIR, "cube.obj").read_bytes())
    status, out, err = run(["render", "spotlight.toml", "--size", "8", "-o", "mine.npy"], capsys)
    assert status == 0, err
    assert out.startswith("wrote mine.npy (8x8, 1 object, 2 lights, ")  # the file here: the cube, not the example
    status, out, err = run(["render", "spotlight", "--size", "8", "-o", "shipped.npy"], capsys)
    assert status == 0 and out.startswith("wrote shipped.npy (8x8, 2 objects, 1 light, "), err
    (tmp_path / "mine").write_text("not used")  # a bare word names an example, even when such a file exists
    assert error(["render", "mine"], capsys) == (
        "SCENE: no example scene named 'mine' (list them: lighting-explorer render --list)"
    )


@pytest.mark.parametrize(
    ("argv", "line"),
    [
        (["render", "spotlite"],
         "SCENE: no example scene named 'spotlite'; did you mean 'spotlight'? "
         "(list them: lighting-explorer render --list)"),
        (["explore", "--scene", "cub"],
         "--scene: no example scene named 'cub'; did you mean 'cube'? (list them: lighting-explorer render --list)"),
    ],
)  # fmt: skip
def test_an_unknown_example_name_is_one_line_with_the_closest_name_and_the_list_command(argv, line, capsys):
    assert error(argv, capsys) == line


# ----------------------------------------------------------------------------- a shipped scene by its name
def test_a_define_on_a_shipped_scene_names_the_scene_the_define_the_key_and_what_is_allowed(capsys):
    line = error(["render", "spotlight", "-D", "image.width=32", "-D", "lights[0].cutof_deg=30", "--explain"], capsys)
    assert line == (
        f"spotlight: lights[0].cutof_deg: unknown key for a 'spot' light; did you mean 'cutoff_deg'? allowed keys: "
        f"{SPOT_KEYS} (with -D lights[0].cutof_deg=30)"
    )
    assert EXAMPLES_DIR not in line and "site-packages" not in line


def test_a_define_that_names_a_table_above_the_key_at_fault_is_the_one_named(capsys):
    line = error(["render", "spotlight", "-D", "image.height=20", "-D", "lights[0]={type='spot', cutoff_deg=300}"],
                 capsys)  # fmt: skip
    assert line.startswith("spotlight: lights[0].")
    assert line.endswith("(with -D lights[0]={type='spot', cutoff_deg=300})")


def test_other_errors_about_a_shipped_scene_name_it_as_typed(capsys):
    assert error(["render", "cube", "-D", "image.width=16000", "-D", "image.height=16000"], capsys) == (
        "cube: image.width × image.height: the scene needs about 83.9 GiB (16000x16000 pixels, 1 object; "
        "12 triangles), over the memory budget of 2.0 GiB; reduce it or raise the budget (--memory-budget)"
    )
    line = error(["render", "spotlight", "-D", 'image.output="../../elsewhere.png"'], capsys)
    assert line.startswith('spotlight: image.output: "../../elsewhere.png" resolves to ')
    # Files a shipped scene names are named as the scene names them, not by the package's folder.
    assert error(["render", "spotlight", "-D", "objects[0].path=nothere.obj"], capsys) == (
        "spotlight: objects[0].path: mesh file 'nothere.obj' does not exist (with -D objects[0].path=nothere.obj)"
    )
    assert error(["render", "environment", "-D", 'lights[0].source="nope.hdr"'], capsys) == (
        'environment: lights[0].source: "nope.hdr" does not exist; an environment image must be an existing file, '
        """relative to the scene's folder (with -D lights[0].source="nope.hdr")"""
    )


# ----------------------------------------------------------------------------- report with no report
def test_report_without_a_report_exits_2_naming_the_reports_on_standard_error(capsys):
    assert error(["report"], capsys) == (
        "report needs the name of a report: accuracy (error against run time wherever the engine trades accuracy "
        "for speed) or stability (numerical stability on stiff and extreme cases, against mpmath)"
    )
    status, out, err = run(["report", "--help"], capsys)
    assert status == 0 and err == "" and "accuracy" in out and "stability" in out


# ----------------------------------------------------------------------------- one prefix
@pytest.mark.parametrize(
    ("argv", "line"),
    [
        (["figures", "--bogus"], "unrecognized arguments: --bogus (see lighting-explorer figures --help)"),
        (["figures", "--dpi", "x"], "argument --dpi: invalid int value: 'x' (see lighting-explorer figures --help)"),
        (["figures", "--jobs", "0", "--only", "falloff"], "--jobs must be an integer in [1, 64]; got 0"),
        (["report", "accuracy", "--bogus"],
         "unrecognized arguments: --bogus (see lighting-explorer report accuracy --help)"),
        (["report", "stability", "--dtype", "half"],
         "argument --dtype: invalid choice: 'half' (choose from 'float32', 'float64', 'both') "
         "(see lighting-explorer report stability --help)"),
        (["report", "stability", "--workers", "0"], "--workers must be an integer in [1, 64]; got 0"),
        (["report", "stabilty"],
         "unknown report 'stabilty'; did you mean 'stability'? (choose from accuracy, stability)"),
        (["explore", "--bogus"], "unrecognized arguments: --bogus (see lighting-explorer --help)"),
        (["--elevation", "x"], "argument --elevation: invalid float value: 'x' (see lighting-explorer --help)"),
        (["bench", "--repeat", "0"], "--repeat must be an integer in [1, 10000]; got 0"),
        (["sphere", "--kd", "red"],
         "--kd must be one number or three comma-separated numbers, each finite and >= 0; got 'red'"),
        (["render"], "the following arguments are required: SCENE (a scene file or an example name; see --list) "
                     "(see lighting-explorer render --help)"),
        (["--memory-budget", "lots", "sphere"],
         "--memory-budget must be a size such as 2G, 512M or 1.5G (K, M, G, T are powers of 1024; at least 1M); "
         "got 'lots'"),
    ],
)  # fmt: skip
def test_every_command_reports_under_the_one_prefix(argv, line, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert error(argv, capsys) == line
    assert list(tmp_path.iterdir()) == []


def test_the_prefix_is_made_in_one_place():
    import explorer

    # Every error line is printed by explorer.cli.print_error: no command prints a prefix of its own.
    root = explorer.__path__[0]
    found = subprocess.run(["grep", "-rnE", "--include=*.py", r"(print\(|prog).*: error: ", root],
                           capture_output=True, text=True)  # fmt: skip
    assert found.stdout == ""
    assert cli.ERROR_PREFIX == PREFIX


def test_a_missing_extra_is_reported_under_the_one_prefix_naming_the_command(tmp_path):
    code = "import sys; sys.modules['matplotlib'] = None\nfrom explorer.cli import main\nsys.exit(main(sys.argv[1:]))"
    done = subprocess.run([sys.executable, "-c", code, "figures", "--list"], capture_output=True, text=True,
                          timeout=300, cwd=tmp_path)  # fmt: skip
    assert (done.returncode, done.stdout, done.stderr) == (
        2, "", PREFIX + "figures needs Matplotlib: pip install 'lighting-explorer[figures]'\n"
    )


# ----------------------------------------------------------------------------- plurals
def test_plural_writes_one_light_and_two_lights():
    assert [plural(n, "light") for n in (0, 1, 2)] == ["0 lights", "1 light", "2 lights"]
    assert plural(1, "object") == "1 object" and plural(5, "object") == "5 objects"
    assert plural(2, "entry") == "2 entries" and plural(1, "entry") == "1 entry"


@pytest.mark.parametrize(("scene", "words"), [("spotlight", "2 objects, 1 light"), ("cube", "1 object, 2 lights")])
def test_render_and_explain_count_in_words(scene, words, tmp_path, capsys):
    status, out, err = run(["render", scene, "--size", "8", "--explain", "-o", tmp_path / "x.npy"], capsys)
    assert status == 0, err
    lines = out.splitlines()
    assert lines[0] == f"{words}, 8x8 pixels."
    assert lines[-1].startswith(f"wrote {tmp_path / 'x.npy'} (8x8, {words}, ")
    assert "(s)" not in out


def test_no_message_in_the_command_line_or_the_scene_loader_writes_s_in_parentheses():
    import explorer
    import lighting.scene

    # Figure modules are checked with the figures; the command line, the reports and the scenes are here.
    package = Path(explorer.__path__[0])
    files = [*package.glob("commands/*.py"), *package.glob("reports/*.py"), package / "cli.py",
             package / "app" / "command.py", *Path(lighting.scene.__path__[0]).glob("*.py")]  # fmt: skip
    found = []
    for path in files:
        for tok in tokenize.generate_tokens(io.StringIO(path.read_text(encoding="utf-8")).readline):
            if tok.type == tokenize.STRING and re.search(r"[a-z]\(s\)(?=[\s,:;'\"]|$)", tok.string):
                found.append(f"{path.name}:{tok.start[0]}: {tok.string}")
    assert len(files) > 20 and found == []


# ----------------------------------------------------------------------------- sizes named by their option or key
def test_a_size_over_the_budget_names_the_option_before_the_scene_is_read(monkeypatch, capsys):
    import lighting.scene

    monkeypatch.setattr(lighting.scene, "load_scene", lambda *a, **k: pytest.fail("read the scene first"))
    assert error(["render", "cube", "--size", "16000x16000"], capsys) == (
        "--size 16000x16000: the image needs about 83.9 GiB (16000x16000 pixels of one object; more with more "
        "objects), over the memory budget of 2.0 GiB; reduce it or raise the budget (--memory-budget)"
    )


@pytest.mark.parametrize("budget", [[], ["--memory-budget", "4T"]])
def test_a_size_over_the_largest_side_names_the_option_the_value_and_the_limit_whatever_the_budget(budget, tmp_path,
                                                                                                  monkeypatch, capsys):
    import lighting.render.sphere
    import lighting.scene

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(lighting.scene, "load_scene", lambda *a, **k: pytest.fail("read the scene"))
    monkeypatch.setattr(lighting.render.sphere, "render_sphere", lambda *a, **k: pytest.fail("rendered"))
    # No budget lifts these limits, so they are named first: the option, what was given and the largest side.
    assert error([*budget, "render", "cube", "--size", "100000x100000"], capsys) == (
        "--size must be at most 16384x16384 pixels (a scene's largest image); got 100000x100000"
    )
    assert error([*budget, "render", "cube", "--size", "16385x1"], capsys) == (
        "--size must be at most 16384x16384 pixels (a scene's largest image); got 16385x1"
    )
    assert error([*budget, "sphere", "--size", "100000", "-o", "x.png"], capsys) == (
        "--size must be at most 65536x65536 pixels; got 100000x100000"
    )
    assert list(tmp_path.iterdir()) == []


def test_a_size_within_a_raised_budget_but_too_large_names_the_option(monkeypatch, capsys):
    import lighting.render.sphere
    import lighting.scene

    monkeypatch.setattr(lighting.scene, "load_scene", lambda *a, **k: pytest.fail("read the scene"))
    monkeypatch.setattr(lighting.render.sphere, "render_sphere", lambda *a, **k: pytest.fail("rendered"))
    assert error(["--memory-budget", "4T", "render", "cube", "--size", "100000x100000"], capsys) == (
        "--size must be at most 16384x16384 pixels (a scene's largest image); got 100000x100000"
    )
    assert error(["--memory-budget", "4T", "sphere", "--size", "100000", "-o", "x.png"], capsys) == (
        "--size must be at most 65536x65536 pixels; got 100000x100000"
    )


def test_an_exposure_out_of_range_names_the_scene_and_the_key(capsys):
    assert error(["render", "cube", "-D", "image.exposure=1e308"], capsys) == (
        "cube: image.exposure: must be a number in [-100, 100] (stops); got 1e+308 (with -D image.exposure=1e308)"
    )


def test_a_scale_that_would_break_clipping_names_objects_scale(tmp_path, capsys):
    assert error(["render", "cube", "-D", "objects[0].scale=1e300"], capsys) == (
        "cube: objects[0].scale: makes triangles that cross the near plane reach 1.22e+300 from the eye; allowed: at "
        "most 1e+12 x camera.near = 6.03e+09 (beyond it, clipping in float64 loses every digit): make the object "
        "smaller or camera.near larger; got 1e+300 (with -D objects[0].scale=1e300)"
    )
    # A large cube around the camera, well inside the limit, still renders, and every pixel is finite.
    out = tmp_path / "inside.npy"
    status, _, err = run(["render", "cube", "--size", "16", "-D", "objects[0].scale=1e6", "-o", out], capsys)
    assert status == 0, err
    image = np.load(out)
    assert np.all(np.isfinite(image)) and image.max() > 0


def test_a_tiny_near_plane_is_named_when_the_object_keeps_its_size(tmp_path, capsys):
    scene = tmp_path / "room.toml"
    text = Path(example_path("cube")).read_text().replace('"cube.obj"', f'"{EXAMPLES_DIR}/cube.obj"')
    scene.write_text(text.replace("fov_y_deg = 35.0", "fov_y_deg = 35.0\nnear = 1e-15\neye = [0.2, 0.1, 0.3]", 1)
                     .replace("eye = [3.2, 2.6, 4.4]\n", ""))  # fmt: skip
    line = error(["render", scene, "--size", "8", "-o", tmp_path / "x.png"], capsys)
    assert line.startswith(f"{scene}: camera.near: makes triangles that cross the near plane reach ")
    assert line.endswith("; got 1e-15")


# ----------------------------------------------------------------------------- budgets before any work
def test_report_stability_workers_are_checked_against_the_budget_before_any_work(monkeypatch, tmp_path, capsys):
    from lighting.validation import stability

    monkeypatch.setattr(stability, "run", lambda *a, **k: pytest.fail("computed before checking --workers"))
    assert error(["--memory-budget", "1G", "report", "stability", "--workers", "64", "--out", tmp_path / "s"],
                 capsys) == (  # fmt: skip
        "--workers 64 needs about 8.0 GiB (64 reference processes), over the memory budget of 1.0 GiB; reduce it or "
        "raise the budget (--memory-budget)"
    )
    assert not (tmp_path / "s").exists()


def test_sphere_size_is_checked_against_the_budget_before_rendering(monkeypatch, tmp_path, capsys):
    import lighting.render.sphere

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(lighting.render.sphere, "render_sphere", lambda *a, **k: pytest.fail("rendered"))
    assert error(["--memory-budget", "1G", "sphere", "--size", "3000x2000"], capsys) == (
        "--size 3000x2000 needs about 1.8 GiB (a 3000x2000 sphere image), over the memory budget of 1.0 GiB; "
        "reduce it or raise the budget (--memory-budget)"
    )
    assert list(tmp_path.iterdir()) == []


def test_the_loader_names_a_shipped_scene_by_its_name_and_any_other_as_given(tmp_path):
    from lighting.scene import SceneError, load_scene, scene_label

    assert load_scene(example_path("spotlight")).source == "spotlight"
    assert scene_label(example_path("cube")) == "cube" and scene_label("my/cube.toml") == "my/cube.toml"
    bad = tmp_path / "bad.toml"
    bad.write_text("version = 2\n" + Path(example_path("cube")).read_text())
    with pytest.raises(SceneError, match=rf"^{re.escape(str(bad))}: version: must be 1"):
        load_scene(bad)
    with pytest.raises(SceneError, match=r"^my scene: version: must be 1"):
        load_scene(bad, source="my scene")


def test_a_reader_that_closes_the_pipe_ends_the_command_quietly():
    # `lighting-explorer --help | head -1`: the pipe closes before the help is written.
    import subprocess
    import sys

    code = "import sys; from explorer.cli import main; sys.exit(main(['render', '--list']))"
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.close()
    err = proc.stderr.read().decode()
    proc.stderr.close()
    assert proc.wait(timeout=60) == 141
    assert err == ""


def test_every_refusal_shown_in_the_command_line_page_is_the_line_printed(tmp_path, monkeypatch, capsys):
    import shlex

    text = (Path(__file__).resolve().parents[2] / "docs" / "cli.md").read_text(encoding="utf-8")
    samples = re.findall(r"^\$ lighting-explorer (.+)\n(lighting-explorer: error: .+)$", text, re.M)
    assert len(samples) >= 6
    monkeypatch.chdir(tmp_path)
    for argv, line in samples:
        assert error(shlex.split(argv), capsys) == line[len(PREFIX):], argv
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("argv", "line"),
    [
        (["render", "cube", "-D", "image.exposure=1e308"],
         "cube: image.exposure: must be a number in [-100, 100] (stops); got 1e+308 (with -D image.exposure=1e308)"),
        (["render", "cube", "-D", "lights[0].intensity=1e308"],
         "cube: lights[0].intensity: must be a finite number <= 1e+30; got 1e+308 (with -D lights[0].intensity=1e308)"),
        (["render", "spotlight", "-D", "lights[0].color=[1, 1, 1e31]"],
         "spotlight: lights[0].color[2]: must be a finite number <= 1e+30; got 1e+31 "
         "(with -D lights[0].color=[1, 1, 1e31])"),
        (["render", "point_ambient", "-D", 'lights[0]={type="disk", center=[0, 2, 0], intensity=1e308}'],
         "point_ambient: lights[0].intensity: must be a finite number <= 1e+30; got 1e+308 "
         """(with -D lights[0]={type="disk", center=[0, 2, 0], intensity=1e308})"""),
        (["render", "cube", "-D", 'lights[0]={type="environment", radiance=1e308}'],
         "cube: lights[0].radiance: must be a colour: a number or [r, g, b], finite and <= 1e+30; got 1e+308 "
         """(with -D lights[0]={type="environment", radiance=1e308})"""),
        (["render", "studio", "-D", "lights[0].intensity=1e308"],
         "studio: lights[0].intensity: must be a colour: a number or [r, g, b], finite and <= 1e+30; got 1e+308 "
         "(with -D lights[0].intensity=1e308)"),
    ],
)  # fmt: skip
def test_a_light_or_exposure_too_large_to_render_finitely_names_the_scene_the_key_and_the_limit(argv, line, tmp_path,
                                                                                               monkeypatch, capsys):
    import warnings

    monkeypatch.chdir(tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # refused before any arithmetic: no overflow warning on the way
        assert error([*argv, "--size", "8", "-o", "x.png"], capsys) == line
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("defines", [["lights[0].intensity=1e30"],
                                     ["lights[0].color=1e30", "lights[0].intensity=1e30"]])
def test_the_brightest_light_allowed_renders_finite_pixels_without_warnings(defines, tmp_path, capsys):
    import warnings

    out = tmp_path / "bright.npy"
    given = [a for d in [*defines, "lights[1].intensity=1e30"] for a in ("-D", d)]  # both of the cube's lights
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        status, _, err = run(["render", "cube", "--size", "12", *given, "-o", out], capsys)
    assert status == 0, err
    image = np.load(out)
    assert np.all(np.isfinite(image)) and image.max() > 1e28

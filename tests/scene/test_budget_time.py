"""The render time budget: a scene estimated to take longer than ``TIME_LIMIT`` is refused before anything is drawn,
in one line naming the key that costs it and the flag that allows it; ``--explain`` prints the estimate.

The two scenes here are the ones that used to run for minutes: the ``environment`` example under a 65 536-sample
Monte-Carlo sky, and a sphere whose material has 40 parts naming one measured (MERL) file.
"""

from __future__ import annotations

import dataclasses
import math
import re
import time

import numpy as np
import pytest

import lighting._budget as home
import lighting.numerics
import lighting.scene.budget
from explorer.commands import render as render_cmd
from explorer.commands.render import load_with_defines
from lighting._budget import (
    MEASURED_SAMPLER_BYTES,
    MEASURED_TABLE_BYTES,
    SECONDS_PER,
    TIME_LIMIT,
    check_scene_budget,
    explain_lines,
    scene_estimate,
)
from lighting.files.merl import write_merl
from lighting.scene import SceneBudgetError, example_path, load_scene, parse_scene

PROBE = ["-D", 'lights[0].method="monte-carlo"', "-D", "lights[0].samples=65536"]


def probe_scene(samples=65536, **kwargs):
    """The ``environment`` example at 48x32 under a Monte-Carlo sky of ``samples`` samples."""
    scene = load_with_defines(example_path("environment"), [PROBE[1], f"lights[0].samples={samples}"])
    return dataclasses.replace(scene.with_size(48, 32), **kwargs)


@pytest.fixture(scope="module")
def merl_folder(tmp_path_factory):
    """A folder holding ``m.binary``, a MERL file (a constant table), written once for the module."""
    folder = tmp_path_factory.mktemp("merl")
    write_merl(folder / "m.binary", np.full((3, 90, 90, 180), 0.05))
    return folder


def merl_scene(folder, samples=4, parts=40):
    """A sphere whose material has ``parts`` parts naming ``folder``'s MERL file, under a Monte-Carlo sky, 48x32."""
    listed = ", ".join(['{file = "m.binary"}'] * parts)
    return parse_scene(f"""
[camera]
eye = [0.0, -4.0, 0.0]
up = [0.0, 0.0, 1.0]
[image]
width = 48
height = 32
[materials.measured]
parts = [{listed}]
[[objects]]
type = "sphere"
material = "measured"
[[lights]]
type = "environment"
source = "daylight"
method = "monte-carlo"
samples = {samples}
""", source="merl.toml", base_dir=folder)


def run_cli(argv, capsys):
    status = render_cmd.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert "Traceback" not in err and err.count("\n") <= 1, err
    return status, out, err


def test_one_home_for_the_budget():
    # The memory check, the scene's estimate and its refusal are the same objects wherever they are imported from.
    assert lighting._budget.check_budget is home.check_budget
    assert lighting._budget.BudgetError is home.BudgetError
    assert lighting._budget.memory_budget is home.memory_budget
    assert lighting.scene.budget.check_scene_budget is home.check_scene_budget
    assert lighting.scene.budget.scene_estimate is home.scene_estimate
    assert lighting.scene.budget.PREFILTER_BYTES_PER_PIXEL is home.PREFILTER_BYTES_PER_PIXEL
    assert lighting.scene.check_scene_budget is home.check_scene_budget
    # Every unit of work the estimate counts has its measured cost, positive (or a fixed part of 0) and finite.
    kinds = home.MODEL_KINDS + ("measured", "shader")
    needed = {f"{stage} {k}" for stage in ("shade", "monte-carlo") for k in kinds}
    needed |= {"pixel", "render", "measured table", "prefilter", "prefilter pixel", "dominant", "dominant pixel",
               "dominant narrow table"}
    needed |= {f"{m} {lobe}" for m in ("split-sum", "dominant") for lobe in ("diffuse", "glossy")} | {"dominant narrow"}
    assert set(SECONDS_PER) == needed
    assert all(math.isfinite(v) and v >= 0 for v in SECONDS_PER.values())


def test_the_monte_carlo_probe_is_refused_at_once_naming_the_samples_and_the_flag(capsys):
    t0 = time.process_time()
    status, out, err = run_cli(["environment", "--size", "48x32", *PROBE, "--explain"], capsys)
    cpu = time.process_time() - t0
    assert status == 2 and out == ""
    assert cpu < 1.0, cpu
    est = scene_estimate(probe_scene())
    shown = f"{est['seconds']:.0f} s"
    assert err == (f"lighting-explorer: error: environment: lights[0].samples: the render needs about {shown} "
                   f"({est['time_parts'][0][2]}), over the time limit of {TIME_LIMIT:.0f} s; reduce it, or allow a "
                   "slow render with --allow-slow (allow_slow=True when loading the scene)\n")  # fmt: skip
    key, seconds, what = est["time_parts"][0]
    assert key == "lights[0].samples" and what.startswith("65536 Monte-Carlo samples × 2 parts of objects[1].")
    assert seconds > TIME_LIMIT


def test_the_samples_cost_in_proportion_and_the_limit_falls_between():
    # The Monte-Carlo part of the estimate is linear in the samples; everything else does not depend on them.
    small, big = (dict((k, s) for k, s, _ in scene_estimate(probe_scene(n))["time_parts"]) for n in (64, 65536))
    assert big["lights[0].samples"] == pytest.approx(1024 * small["lights[0].samples"], rel=1e-12)
    assert {k: v for k, v in big.items() if k != "lights[0].samples"} == pytest.approx(
        {k: v for k, v in small.items() if k != "lights[0].samples"}, rel=1e-12)
    assert check_scene_budget(probe_scene(64))["seconds"] < TIME_LIMIT  # the example's own 64 samples pass


def test_with_the_flag_explain_prints_the_estimate_and_renders_nothing(capsys, tmp_path):
    status, out, err = run_cli(["environment", "--size", "48x32", *PROBE, "--explain", "--allow-slow"], capsys)
    assert status == 0 and err == ""
    est = scene_estimate(probe_scene())
    line = next(ln for ln in out.splitlines() if ln.startswith("estimated time: "))
    assert line.startswith(f"estimated time: about {est['seconds']:.0f} s (lights[0].samples: ")
    assert line.endswith(f"the time limit is {TIME_LIMIT:.0f} s, lifted (--allow-slow, allow_slow=True)")
    assert not list(tmp_path.iterdir())


def test_the_loading_keyword_allows_a_slow_render_and_is_checked():
    path = example_path("environment")
    assert load_scene(path).allow_slow is False and load_scene(path, allow_slow=True).allow_slow is True
    scene = probe_scene(allow_slow=True)
    assert check_scene_budget(scene)["seconds"] > TIME_LIMIT  # admitted: allowed when it was loaded
    assert scene.with_size(40, 30).allow_slow is True  # changing the scene keeps the permission
    with pytest.raises(SceneBudgetError, match=r"^environment: lights\[0\]\.samples: the render needs about"):
        check_scene_budget(probe_scene())
    with pytest.raises(ValueError, match=r"^allow_slow must be True or False; got 'yes'$"):
        load_scene(path, allow_slow="yes")


def test_a_size_that_makes_the_render_slow_names_the_size_flag(capsys):
    previous = home.set_memory_budget(2**40)  # the memory of so large an image allowed: its time is what weighs
    try:
        status, out, err = run_cli(["spotlight", "--size", "16000x12000"], capsys)
    finally:
        home.set_memory_budget(previous)
    assert status == 2 and out == ""
    assert re.fullmatch(r"lighting-explorer: error: --size 16000x12000: the render needs about \d+ s \(16000x12000 "
                        r"pixels, 2 objects\), over the time limit of 30 s; reduce it, or allow a slow render with "
                        r"--allow-slow \(allow_slow=True when loading the scene\)\n", err), err  # fmt: skip


def test_forty_parts_naming_one_measured_file_share_one_table_and_one_sampler(merl_folder):
    scene = merl_scene(merl_folder)
    parts = scene.objects[0].material.brdf.parts
    assert len(parts) == 40 and len({id(p.sampler()) for p in parts}) == 1
    est = check_scene_budget(scene)  # admitted: the tables are built once, not 40 times
    # The memory estimate holds the table and its sampler's tables once.
    assert ("materials.measured.parts", MEASURED_TABLE_BYTES + MEASURED_SAMPLER_BYTES,
            "a measured BRDF's table and its sampler's tables") in est["parts"]  # fmt: skip
    # The time: the sampler's 90 view tables once, and 4 samples × 40 parts at each shading point.
    times = {k: (s, w) for k, s, w in est["time_parts"]}
    assert times["materials.measured.parts"] == (90 * SECONDS_PER["measured table"],
                                                 "a measured BRDF's sampler tables")  # fmt: skip
    seconds, what = times["lights[0].samples"]
    points = float(re.search(r"at about (\d+) shading points", what).group(1))
    assert what.startswith("4 Monte-Carlo samples × 40 parts of materials.measured.parts")
    assert seconds == pytest.approx(4 * 40 * SECONDS_PER["monte-carlo measured"] * points, rel=1e-3)
    assert est["seconds"] < TIME_LIMIT


def test_forty_measured_parts_under_many_samples_are_refused_naming_the_samples_and_the_parts(merl_folder):
    with pytest.raises(SceneBudgetError) as e:
        check_scene_budget(merl_scene(merl_folder, samples=1024))
    msg = str(e.value)
    assert msg.startswith("merl.toml: lights[0].samples: the render needs about ")
    assert "(1024 Monte-Carlo samples × 40 parts of materials.measured.parts at about " in msg
    assert msg.endswith("allow a slow render with --allow-slow (allow_slow=True when loading the scene)")


def test_explain_lines_end_with_the_estimated_time():
    scene = load_scene(example_path("studio"))
    lines = explain_lines(scene)
    est = scene_estimate(scene)
    assert lines[0].startswith("environment lights[0]: prefiltering 512x256 needs about ")
    assert lines[-1].startswith(f"estimated time: about {est['seconds']:.2g} s (")
    assert lines[-1].endswith(f"the time limit is {TIME_LIMIT:.0f} s")
    assert est["seconds"] == pytest.approx(sum(s for _, s, _ in est["time_parts"]), rel=1e-12)


@pytest.mark.parametrize("name", ["ambient_only", "cube", "directional_ambient", "environment", "gouraud_vs_phong",
                                  "lambert_angles", "opengl_lights", "point_ambient", "spotlight", "studio"])
def test_every_example_scene_is_within_the_time_limit(name):
    assert 0 < check_scene_budget(load_scene(example_path(name)))["seconds"] < TIME_LIMIT

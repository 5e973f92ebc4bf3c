"""The render time budget against the clock, and its modules in fresh interpreters.

pytestmark = pytest.mark.slow: the renders here take seconds (a render's estimate is checked against its measured
time), and each import check starts a new interpreter.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
import tomllib

import numpy as np
import pytest

from lighting._budget import scene_estimate
from lighting.files.merl import write_merl
from lighting.scene import SceneRenderer, example_path, parse_scene

pytestmark = pytest.mark.slow

SPHERES = """
[camera]
eye = [0.0, -3.2, 0.0]
up = [0.0, 0.0, 1.0]
fov_y_deg = 40.0
[image]
width = {size}
height = {size}
[render]
form = "physical"
[[objects]]
type = "sphere"
material = {{parts = [{parts}]}}
{lights}
"""
POINTS = "".join(f'[[lights]]\ntype = "point"\nposition = [{x}, -3.0, {z}]\nintensity = 3.0\n'
                 for x, z in ((2, 2), (-2, 2), (2, -2), (-2, -2)))  # fmt: skip
MC = '[[lights]]\ntype = "environment"\nsource = "daylight"\nmethod = "monte-carlo"\nsamples = {samples}\n'


@pytest.mark.parametrize("module", ["lighting._budget", "lighting.scene.budget", "lighting._validate",
                                    "lighting.numerics"])
def test_the_budget_modules_import_alone(module):
    # No import cycle: each module imports first in a fresh interpreter.
    done = subprocess.run([sys.executable, "-c", f"import {module}"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and done.stderr == "", done.stderr


def measured(make) -> float:
    """The faster of two renders of a scene made afresh by ``make()`` (rasterized, prefiltered and shaded anew)."""
    best = float("inf")
    for _ in range(2):
        scene = make()
        t0 = time.perf_counter()
        SceneRenderer(scene).render()
        best = min(best, time.perf_counter() - t0)
    return best


def split_sum_environment():
    """The ``environment`` example at 280x160 under the split sum."""
    path = example_path("environment")
    with open(path, "rb") as f:
        data = tomllib.load(f)
    data["lights"][0]["method"] = "split-sum"
    data["image"].update(width=280, height=160)
    return parse_scene(data, base_dir=os.path.dirname(path))


def test_a_small_render_takes_within_a_factor_of_four_of_its_estimate(tmp_path):
    write_merl(tmp_path / "m.binary", np.full((3, 90, 90, 180), 0.05))
    makers = {
        "point lights": lambda: parse_scene(SPHERES.format(
            size=160, parts='{model = "lambert"}, {model = "cook-torrance"}', lights=POINTS)),
        "Monte Carlo": lambda: parse_scene(SPHERES.format(
            size=48, parts='{model = "lambert"}, {model = "phong"}', lights=MC.format(samples=32))),
        "measured": lambda: parse_scene(SPHERES.format(
            size=32, parts=", ".join(['{file = "m.binary"}'] * 4), lights=MC.format(samples=8)), base_dir=tmp_path),
        "split sum": split_sum_environment,
    }  # fmt: skip
    for label, make in makers.items():
        estimate = scene_estimate(make())["seconds"]
        seconds = measured(make)
        assert 0.25 <= estimate / seconds <= 4, (label, estimate, seconds)

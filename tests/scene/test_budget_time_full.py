"""The time budget's modules, each in a fresh interpreter (slow: each check starts a new interpreter).

A render's estimate against its measured time is a clock, not a test: ``python -m explorer.bench.costs --check``
prints it with its target.
"""

from __future__ import annotations

import subprocess
import sys

import pytest

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

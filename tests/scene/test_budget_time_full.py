"""The time budget's modules, each in a fresh interpreter (slow: each check starts a new interpreter).

A render's estimate against its measured time is a clock, not a test: ``python -m explorer.bench.costs --check``
prints it with its target.
"""

from __future__ import annotations

import subprocess
import sys

import pytest

pytestmark = pytest.mark.slow

@pytest.mark.parametrize("module", ["lighting._budget", "lighting.scene.budget", "lighting._validate",
                                    "lighting.numerics"])
def test_the_budget_modules_import_alone(module):
    # No import cycle: each module imports first in a fresh interpreter.
    done = subprocess.run([sys.executable, "-c", f"import {module}"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and done.stderr == "", done.stderr

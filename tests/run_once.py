"""Work done once per test run and shared by its pytest-xdist workers (a helper for tests and fixtures)."""

from __future__ import annotations

import fcntl
import os
from contextlib import contextmanager
from pathlib import Path


@contextmanager
def run_root_locked(tmp_path_factory, name: str):
    """The run's temporary root, shared by every worker (this process's own root without workers), held under the
    file lock ``<name>.lock`` there: the first worker to get it does the work and leaves the result, the others
    wait for it and find the result done."""
    base: Path = tmp_path_factory.getbasetemp()
    root = base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base
    with open(root / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        yield root

"""Shared fixtures of the test suite, and the fast loop.

``python -m pytest`` runs every test, as CI does, and ``python -m pytest -m "not slow"`` is the fast loop; both on
pytest-xdist's workers, one per core (``-n auto --dist loadfile`` in pyproject.toml: each test file runs whole in
one worker, so its module fixtures are made once; ``-n 0`` runs in one process, for a single test or a debugger).
The fast loop leaves out each test file that says ``pytestmark = pytest.mark.slow`` at its top, with its reason (the
seeded probes, the figure set, the Mesa comparison, the explorer window, the 80-digit references, the full χ²
grids), and the few tests marked slow one by one. A test that would make the loop slower goes whole into such a
file, ``test_<topic>_full.py`` beside its fast ``test_<topic>.py``.
"""

import os
import re
import sys
from pathlib import Path

import pytest

# Qt's windows: in a real X server where one is given (CI runs the suite under Xvfb), else Qt's offscreen
# platform (no OpenGL widgets there: the 3D lobe is drawn by VTK off-screen into an image).
if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

# One BLAS thread per process: pytest-xdist already runs one worker per core, and OpenBLAS's own threads (one
# per core in each worker) would only compete with the other worker and spin while they wait.  Read by OpenBLAS
# when NumPy loads, so it is set here, in the process that starts the workers, before they start.  The product's
# results do not depend on it (the figure set drawn by a build with every thread is compared byte for byte with
# one drawn here).
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

# pytest keeps each test module with its assertions rewritten in __pycache__, and reads it back on the next run,
# but writes nothing where the environment sets PYTHONDONTWRITEBYTECODE: every worker of every run would then parse
# and rewrite the whole suite again, seconds of each worker's start.  The suite's own processes write those files
# (and the checkout's compiled modules, as .ci/run's compileall does); the commands the tests start keep the setting.
sys.dont_write_bytecode = False

# Let tests import the sibling helper modules `quadrature` and `probes`.
sys.path.insert(0, str(Path(__file__).parent))


#: A test file marked slow as a whole says so at the start of a line of its own.
_SLOW_FILE = re.compile(r"^pytestmark = pytest\.mark\.slow\b", re.MULTILINE)


def _slow_file(path: Path) -> bool:
    """Whether the test file ``path`` is marked slow as a whole (False for one that cannot be read)."""
    try:
        return bool(_SLOW_FILE.search(path.read_text(encoding="utf-8")))
    except (OSError, UnicodeDecodeError):
        return False


def pytest_ignore_collect(collection_path, config):
    """Under ``-m "not slow"``, a test file marked slow as a whole is not imported at all.

    Every one of its tests would be deselected anyway; importing it (PyVista, Hypothesis, the full grids
    built at import) only makes the fast loop start later.
    """
    if config.option.markexpr.strip() != "not slow" or collection_path.suffix != ".py":
        return None
    if not collection_path.name.startswith("test_"):
        return None
    return True if _slow_file(collection_path) else None


@pytest.hookimpl(wrapper=True)
def pytest_collect_file(file_path, parent):
    """The suite's files collected without a doctest search of them (``--doctest-modules`` is for the packages).

    They hold no doctests, and searching them costs every worker a second and a half at each start: doctest
    asks each module-level object whether it wraps another, and a test file's ``pv =
    pytest.importorskip("pyvista")`` answers by importing all of PyVista's plotting.
    """
    from _pytest.doctest import DoctestModule

    collectors = yield
    return [c for c in collectors if not isinstance(c, DoctestModule)]


def pytest_collection_modifyitems(config, items):
    """Files marked slow as a whole first, then the others by their number of tests, most first.

    pytest-xdist hands out whole files (``--dist loadfile``) in this order (``--no-loadscope-reorder``), each to
    the next free worker.  Its own order, by number of tests alone, leaves the files with a few long tests (the
    probes, the 16,384-spp references, the 80-digit sweep) to the end, where one worker runs them while the other
    has nothing left; taken first, the many short files fill in behind them.  Within a file the order is kept.
    """
    files: dict = {}
    for index, item in enumerate(items):
        files.setdefault(item.nodeid.split("::", 1)[0], []).append(index)

    def weight(path):
        return (0, 0) if _slow_file(config.rootpath / path) else (1, -len(files[path]))

    order = sorted(files, key=weight)  # stable: files of equal weight keep the collection's order
    items[:] = [items[i] for path in order for i in files[path]]


def pytest_collection_finish(session):
    """Once the tests are collected, the objects made so far (modules, test items, their parameters) live to the
    end of the run: ``gc.freeze()`` moves them out of the cyclic collector's sight.

    Every full collection during the run, and the five that pytest runs at the end to surface unraisable
    exceptions, would otherwise walk these hundreds of thousands of objects again.  They are still freed by
    reference counting; only a reference cycle among them would outlive the run, as they all do anyway.
    """
    import gc

    gc.freeze()


@pytest.fixture(scope="session")
def quick_accuracy_studies(tmp_path_factory):
    """``run_studies(quick=True)``: the accuracy studies at their quick settings, measured once per test run.

    Several files check what the same quick studies measured; each measuring them anew would cost the same again.
    Under pytest-xdist the workers share the run's temporary root: the first to need the studies measures them (a
    file lock holds the others) and leaves them there, pickled; the others read that file.
    """
    import pickle

    from run_once import run_root_locked

    from lighting.validation.accuracy import run_studies

    with run_root_locked(tmp_path_factory, "quick-accuracy-studies") as root:
        saved = root / "quick-accuracy-studies.pickle"
        if saved.is_file():
            return pickle.loads(saved.read_bytes())  # written by this very run's other worker, just above
        studies = run_studies(quick=True)
        part = saved.with_suffix(".part")
        part.write_bytes(pickle.dumps(studies))
        os.replace(part, saved)
        return studies


@pytest.fixture(autouse=True, scope="session")
def _accuracy_cache_in_a_temporary_folder(tmp_path_factory):
    """The saved accuracy studies (explorer.reports.cache) go to a folder of this test run, never the home folder."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("LIGHTING_EXPLORER_CACHE", str(tmp_path_factory.mktemp("lighting-explorer-cache")))
        yield


@pytest.fixture(autouse=True)
def _model_registry_restored():
    """Each test leaves the model registry as it found it.

    Tests register models (plug-ins, ``--brdf`` files, ``define_brdf``); one left behind would appear in
    every model list afterwards, e.g. in the registry-generated figure galleries of later tests.
    """
    from lighting.models import protocol

    before = dict(protocol._REGISTRY)
    yield
    if protocol._REGISTRY != before:
        protocol._REGISTRY.clear()
        protocol._REGISTRY.update(before)

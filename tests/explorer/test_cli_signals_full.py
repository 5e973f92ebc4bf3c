"""The process pool of ``figures --jobs N`` stopped as a signal stops it: nothing of the pool is left running for the
interpreter's exit to race with; and a stop signal that lands as the program shuts down leaves the command's status
(slow set; fast: test_cli_signals.py)."""

import os
import signal
import subprocess
import sys
import time

import pytest

pytestmark = pytest.mark.slow  # spawned worker processes, half a second's wait, the program started six times


def test_stopping_the_figure_workers_waits_for_the_pools_manager_thread(monkeypatch):
    # At exit, concurrent.futures wakes each process pool's manager thread through a pipe that the thread closes as
    # it finishes: a thread still finishing then races the exit into "OSError: [Errno 9] Bad file descriptor".
    # Stopping the workers (on an error, Ctrl-C or SIGTERM) therefore returns only once that thread is done.  Here
    # its last step is made slow (half a second), so that a stop that does not wait for it would return first.
    import multiprocessing
    import time
    from concurrent.futures import ProcessPoolExecutor, process

    from explorer.figures import _stop_workers

    finish = process._ExecutorManagerThread.join_executor_internals

    def slow_finish(self):
        time.sleep(0.5)
        finish(self)

    monkeypatch.setattr(process._ExecutorManagerThread, "join_executor_internals", slow_finish)
    pool = ProcessPoolExecutor(max_workers=2, mp_context=multiprocessing.get_context("spawn"))
    busy = [pool.submit(time.sleep, 60) for _ in range(3)]
    manager = pool._executor_manager_thread
    procs = list(pool._processes.values())
    start = time.monotonic()
    _stop_workers(pool)
    assert time.monotonic() - start < 10  # the sleeping workers were ended, not waited for
    assert not manager.is_alive()
    assert not any(p.is_alive() for p in procs)
    assert all(f.cancelled() or f.done() for f in busy)


def test_a_sigterm_as_the_program_shuts_down_leaves_the_commands_status(tmp_path):
    # The command has written its figure and said "done"; Python's shutdown still takes a moment, and at its end it
    # puts the default handlers back, under which a SIGTERM killed the program by the signal (status -15 here, where
    # the command's 0 or a stop's 143 belong).  Six signals, a few milliseconds apart, from the "done" on.
    pytest.importorskip("matplotlib")
    statuses = []
    for k in range(6):
        proc = subprocess.Popen([sys.executable, "-m", "explorer.cli", "figures", "--quick", "--only", "light_colour",
                                 "--out", str(tmp_path / f"f{k}")], stdout=subprocess.DEVNULL,
                                stderr=subprocess.PIPE)  # fmt: skip
        os.set_blocking(proc.stderr.fileno(), False)
        said = b""
        deadline = time.monotonic() + 60
        while b"done" not in said and proc.poll() is None and time.monotonic() < deadline:
            said += proc.stderr.read() or b""
            time.sleep(0.001)
        time.sleep(0.004 * k)
        if proc.poll() is None:
            proc.send_signal(signal.SIGTERM)
        proc.wait(timeout=60)
        said += proc.stderr.read() or b""
        proc.stderr.close()
        assert b"Traceback" not in said, said.decode(errors="replace")
        statuses.append(proc.returncode)
    assert set(statuses) <= {0, 143}, statuses

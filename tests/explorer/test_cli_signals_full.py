"""The process pool of ``figures --jobs N`` stopped as a signal stops it: nothing of the pool is left running for the
interpreter's exit to race with (slow set; fast: test_cli_signals.py)."""

import pytest

pytestmark = pytest.mark.slow  # two spawned worker processes started, and half a second's wait for the manager thread


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

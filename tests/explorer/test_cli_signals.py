"""A stop signal the instant a command's temporary output file appears: no ``.part`` file is left behind.

The file is created by ``tempfile.mkstemp`` (in :func:`lighting.files.images.write_temporary`, which
:mod:`explorer.output` calls with the stop signals held); here that call is wrapped so that the signal is sent
right after the file exists and before the writer has its name, which is the moment where a name not yet
registered for removal would be lost.  Each test runs the real command (``explorer.cli.main``).

``test_cli_signals_full.py`` stops the process pool of ``figures --jobs N`` as a signal does, and checks that
nothing of the pool is left running for the interpreter's exit to race with.
"""

from __future__ import annotations

import os
import signal
import tempfile
import threading

import pytest

from explorer import cli


def _signal_when_created(monkeypatch, send):
    """Make every temporary file call ``send()`` the instant it exists; return their names."""
    real = tempfile.mkstemp
    made = []

    def mkstemp_then_signal(*args, **kwargs):
        fd, name = real(*args, **kwargs)
        made.append(name)
        send()
        return fd, name

    monkeypatch.setattr(tempfile, "mkstemp", mkstemp_then_signal)
    return made


@pytest.fixture
def sigint_not_ignored():
    """Python's own SIGINT handler for the test, even when the run itself was started with SIGINT ignored.

    A background job of a non-interactive shell starts with SIGINT ignored, and the command keeps a signal that is
    ignored (as under ``nohup``): its interruption is tested as a terminal's Ctrl+C reaches it.
    """
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


@pytest.mark.parametrize(("sig", "status", "word"), [(signal.SIGTERM, 143, "terminated"),
                                                      (signal.SIGINT, 130, "interrupted")])  # fmt: skip
@pytest.mark.parametrize("old", [None, b"old contents"])
def test_a_signal_as_the_temporary_file_appears_leaves_no_part_file(sig, status, word, old, tmp_path, monkeypatch,
                                                                     capsys, sigint_not_ignored):  # fmt: skip
    out = tmp_path / "out.png"
    if old is not None:
        out.write_bytes(old)
    made = _signal_when_created(monkeypatch, lambda: os.kill(os.getpid(), sig))
    assert cli.main(["sphere", "--size", "8", "-o", str(out)]) == status
    assert capsys.readouterr().err == f"lighting-explorer: {word}\n"
    assert len(made) == 1 and made[0].endswith(".part")  # the file did appear, and the signal came then
    assert [p.name for p in tmp_path.iterdir()] == ([] if old is None else ["out.png"])
    if old is not None:
        assert out.read_bytes() == old  # the older output is untouched
    assert signal.getsignal(signal.SIGTERM) == signal.SIG_DFL  # the command's handlers are gone


def test_a_sigterm_delivered_to_another_thread_as_the_file_appears_leaves_no_part_file(tmp_path, monkeypatch,
                                                                                        capsys):  # fmt: skip
    # The kernel may hand a process-wide signal to any thread (an engine's or an executor's).
    stop = threading.Event()
    bystander = threading.Thread(target=stop.wait)
    bystander.start()
    try:
        made = _signal_when_created(monkeypatch, lambda: signal.pthread_kill(bystander.ident, signal.SIGTERM))
        assert cli.main(["render", "cube", "--size", "8", "-o", str(tmp_path / "cube.png")]) == 143
    finally:
        stop.set()
        bystander.join()
    assert capsys.readouterr().err == "lighting-explorer: terminated\n"
    assert len(made) == 1 and list(tmp_path.iterdir()) == []

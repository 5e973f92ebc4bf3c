"""Probes of the command line: odd command lines, and signals while files are being written.

(a) About 150 seeded command lines, each one sub-command with one flag given an odd value (huge, zero,
    negative, NaN, inf, text, empty, 100,000 characters, a missing folder, a directory, a read-only
    folder, an existing file), run in-process through :func:`explorer.cli.main` in a sandbox folder.
    Every one must end with exit 0, or exit 2 and one line ``lighting-explorer…: error: …`` (no
    traceback, no temporary file name, the value abbreviated); a refused one leaves the sandbox exactly
    as it was, an accepted one writes only inside it; no temporary file is ever left.
(b) ``render`` and ``sphere`` (writing slowed down, so that the signal lands inside the write) and
    ``figures --jobs 2`` as subprocesses, sent SIGTERM, SIGINT or (figures) SIGKILL at seeded moments:
    no temporary file, no figure without its sidecar (and each sidecar matching its figure), no worker
    left alive, and an existing output either untouched or completely new.

Each test prints one summary line (``pytest -s``) with the cases tried and the failures by kind.
"""

from __future__ import annotations

import collections
import io
import json
import os
import random
import signal
import subprocess
import sys
import time
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import numpy as np
import pytest

from explorer.cli import main

pytestmark = pytest.mark.slow  # seeded probe: many generated command lines, files and signals

# ----------------------------------------------------------------------------- (a) odd command lines
ODD = {
    "huge": "1e308",
    "huge int": "100000",
    "zero": "0",
    "negative": "-1",
    "nan": "nan",
    "inf": "inf",
    "text": "red",
    "empty": "",
    "long": "9" * 100_000,
    "missing folder": "missing/out.png",
    "directory": "dir",
    "read-only folder": "ro/out.png",
    "existing file": "existing.png",
}

# sub-command -> (base command line, flags to try); a flag in the base line has its value replaced.
COMMANDS = {
    "sphere": (["sphere", "-o", "out.png", "--size", "16"],
               ["-o", "--size", "--kd", "--ks", "--shininess", "--ambient", "--elevation", "--azimuth",
                "--exposure", "--tonemap"]),
    "render": (["render", "spotlight", "-o", "out.png", "--size", "16x12"],
               ["-o", "--size", "--exposure", "--tonemap", "SCENE"]),
    "figures": (["figures", "--out", "figs", "--quick", "--only", "light_colour", "--dpi", "20"],
                ["--out", "--dpi", "--jobs", "--format", "--only", "--accuracy-csv"]),
    "explore": (["explore", "--screenshot", "shot.png", "--size", "800x500"],
                ["--screenshot", "--size", "--elevation", "--exposure", "--tessellation", "--shininess"]),
    "report stability": (["report", "stability", "--quick", "--no-figure", "--out", "stab"], ["--workers", "--dtype"]),
    "bench": (["bench", "--repeat", "1"], ["--repeat"]),
    "global": (["--memory-budget", "2G", "sphere", "-o", "out.png", "--size", "16"], ["--memory-budget"]),
}  # fmt: skip

TEMP_MARKS = (".part", ".tmp")

# Defects found by this probe in files another part owns, while their fix is pending: counted and printed
# apart, so that everything else is held to zero.  Empty: keep it so.
KNOWN_ELSEWHERE: dict = {}


def _case_line(command: str, flag: str, value: str) -> list[str]:
    base, _ = COMMANDS[command]
    argv = list(base)
    if flag == "SCENE":
        argv[1] = value
    elif flag in argv:
        argv[argv.index(flag) + 1] = value
    else:
        argv += [flag, value]
    return argv


def all_cases(seed: int = 14, count: int = 150):
    """``count`` (command, flag, kind) triples drawn without replacement, every sub-command represented."""
    every = [(c, f, k) for c, (_, flags) in COMMANDS.items() for f in flags for k in ODD]
    rng = random.Random(seed)
    rng.shuffle(every)
    picked, seen = [], set()
    for case in every:  # one of each sub-command first, then the shuffled rest
        if case[0] not in seen:
            picked.append(case)
            seen.add(case[0])
    picked += [c for c in every if c not in picked][: count - len(picked)]
    return picked


def _snapshot(root: Path) -> dict:
    out = {}
    for p in sorted(root.rglob("*")):
        out[str(p.relative_to(root))] = p.read_bytes() if p.is_file() else None
    return out


def _old_png() -> bytes:
    from lighting.render.image import png_bytes

    return png_bytes(np.full((2, 2, 3), 7, np.uint8))


def _sandbox(root: Path) -> Path:
    root.mkdir()
    (root / "dir").mkdir()
    (root / "ro").mkdir()
    (root / "existing.png").write_bytes(_old_png())
    (root / "ro").chmod(0o555)
    return root


def _check_one(argv, box: Path, monkeypatch) -> list[str]:
    """Run one command line in ``box``; return the kinds of failure seen (empty: it held)."""
    before = _snapshot(box)
    outside_before = sorted(os.listdir(box.parent))
    monkeypatch.chdir(box)
    err, out = io.StringIO(), io.StringIO()
    problems = []
    try:
        with redirect_stderr(err), redirect_stdout(out):
            rc = main(argv)
    except BaseException as exc:  # noqa: BLE001 - any escape is a traceback for the user
        return [f"traceback {type(exc).__name__}"]
    text = err.getvalue()
    if "Traceback" in text:
        problems.append("traceback in stderr")
    if rc not in (0, 2):
        problems.append(f"exit {rc}")
    if rc == 2:
        lines = text.strip().splitlines()
        if len(lines) != 1:
            problems.append("not one line")
        elif not (lines[0].startswith("lighting-explorer") and ": error: " in lines[0]):
            problems.append("no error prefix")
        elif len(lines[0]) > 1000:
            problems.append("value not abbreviated")
        if any(m in text for m in TEMP_MARKS):
            problems.append("temporary name in message")
        if _snapshot(box) != before:
            problems.append("output after an error")
    after = _snapshot(box)
    if any(any(m in name for m in TEMP_MARKS) for name in after):
        problems.append("temporary file left")
    if sorted(os.listdir(box.parent)) != outside_before:
        problems.append("file outside the sandbox")
    return problems


def test_probe_odd_command_lines(tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    pytest.importorskip("pyvista")
    import lighting.validation.stability

    # The reports themselves are not under test here, only their option checks: never run them.
    monkeypatch.setattr(lighting.validation.stability, "run", lambda **kw: pytest.fail("report stability ran"))
    monkeypatch.setattr("explorer.bench.run", lambda *a, **k: pytest.fail("bench ran"))
    monkeypatch.setattr("explorer.bench.time_plans", lambda *a, **k: pytest.fail("bench ran"))
    cases = all_cases()
    failures = collections.Counter()
    known = collections.Counter()
    examples = {}
    t0 = time.perf_counter()
    try:
        for k, (command, flag, kind) in enumerate(cases):
            box = _sandbox(tmp_path / f"case{k:03d}")
            argv = _case_line(command, flag, ODD[kind])
            problems = _check_one(argv, box, monkeypatch)
            for p in problems:
                if (command, flag, kind, p) in KNOWN_ELSEWHERE:
                    known[(command, flag, kind, p)] += 1
                    continue
                failures[p] += 1
                examples.setdefault(p, (command, flag, kind))
            (box / "ro").chmod(0o755)
    finally:
        for ro in tmp_path.glob("case*/ro"):
            ro.chmod(0o755)
    by_command = collections.Counter(c for c, _, _ in cases)
    print(
        f"\nprobe cli odd lines: {len(cases)} cases ({', '.join(f'{c} {n}' for c, n in by_command.items())}), "
        f"{sum(failures.values())} failures"
        + (": " + ", ".join(f"{k} {v} (e.g. {examples[k]})" for k, v in failures.items()) if failures else "")
        + (f"; known, owned elsewhere: {sum(known.values())} ({'; '.join(KNOWN_ELSEWHERE[k] for k in known)})"
           if known else "")
        + f"; {time.perf_counter() - t0:.1f} s"
    )
    assert not failures, {k: (v, examples[k]) for k, v in failures.items()}


# ----------------------------------------------------------------------------- (b) signals while writing
# Runs the real command with the writer's file output slowed to 4 KiB per 2 ms, so that a signal can be
# aimed inside the write; everything else (temporary file, clean-up, rename) is the real code.
HARNESS = r"""
import sys, time
import explorer.output as o
real = o.encode_image
def slow(fmt, **kw):
    data = real(fmt, **kw)
    if callable(data):
        return data
    def write(tmp):
        with open(tmp, "wb") as f:
            for i in range(0, len(data), 4096):
                f.write(data[i:i + 4096]); f.flush(); time.sleep(0.002)
    return write
o.encode_image = slow
from explorer.cli import main
import os
open(os.environ["PROBE_STARTED"], "w").close()  # main() is next: its signal handlers are microseconds away
sys.exit(main(sys.argv[1:]))
"""


def _temps(folder: Path) -> list[str]:
    return [p.name for p in folder.rglob("*") if any(m in p.name for m in TEMP_MARKS)]


def _run_and_signal(argv, folder: Path, sig, delay: float, *, harness=True, watch=None, timeout=40.0):
    """Start the command, send ``sig`` ``delay`` s after ``watch(children seen)`` first holds; returns
    ``(exit code, stderr, children seen, whether the signal was sent, stdout)``."""
    cmd = [sys.executable, "-c", HARNESS, *argv] if harness else [sys.executable, "-m", "explorer.cli", *argv]
    env = dict(os.environ, PROBE_STARTED=str(folder.parent / f".{folder.name}.started"))
    # Output to files, not pipes: a worker that outlives the command would hold a pipe open.
    out_path, err_path = folder.parent / f".{folder.name}.out", folder.parent / f".{folder.name}.err"
    with open(out_path, "wb") as out_f, open(err_path, "wb") as err_f:
        proc = subprocess.Popen(cmd, cwd=folder, stdout=out_f, stderr=err_f, env=env)
    children: set[int] = set()
    start = time.monotonic()
    armed = watch is None
    fire_at = start + delay if armed else None
    sent = False
    while proc.poll() is None and time.monotonic() - start < timeout:
        children |= _children(proc.pid)
        now = time.monotonic()
        if not armed and watch(children):
            armed, fire_at = True, now + delay
        if armed and not sent and now >= fire_at:
            proc.send_signal(sig)
            sent = True
        time.sleep(0.001)
    if proc.poll() is None:
        proc.kill()
    proc.wait()
    out = out_path.read_text(encoding="utf-8", errors="replace")
    err = err_path.read_text(encoding="utf-8", errors="replace")
    return proc.returncode, err, children, sent, out


#: Whether this kernel keeps each thread's list of children (``/proc/PID/task/TID/children``).
_CHILDREN_LISTS = os.path.exists(f"/proc/{os.getpid()}/task/{os.getpid()}/children")


def _children(pid: int) -> set[int]:
    """The process's children, from the lists its threads keep (else :func:`_children_by_scan`).

    The probe polls every millisecond while the command runs; reading every process's ``stat`` each time kept a
    core busy beside the command it watches, where reading the process's own lists costs next to nothing.
    """
    if not _CHILDREN_LISTS:
        return _children_by_scan(pid)
    out: set[int] = set()
    try:
        threads = os.listdir(f"/proc/{pid}/task")
    except OSError:
        return out  # the process has ended
    for tid in threads:
        try:
            with open(f"/proc/{pid}/task/{tid}/children", encoding="ascii") as f:
                out.update(int(c) for c in f.read().split())
        except OSError:
            continue  # the thread has ended
    return out


def _children_by_scan(pid: int) -> set[int]:
    """:func:`_children` on a kernel without the children lists: every process's parent, from its ``stat``."""
    out = set()
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                with open(f"/proc/{d}/stat", encoding="ascii", errors="replace") as f:
                    fields = f.read().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid:
                out.add(int(d))
    return out


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii", errors="replace") as f:
            return f.read().rsplit(")", 1)[1].split()[0] not in ("Z", "X")
    except OSError:
        return False


@pytest.mark.parametrize("command", ["render", "sphere"])
def test_probe_signal_while_writing_an_image(tmp_path, command):
    rng = random.Random(18 if command == "render" else 19)
    # About 400 KB: some 100 chunks of the slowed write, a window of 0.2 s to aim at.
    argv = (["render", "gouraud_vs_phong", "--size", "128x128", "-o", "out.npy"] if command == "render"
            else ["sphere", "--size", "128", "-o", "out.npy"])  # fmt: skip
    ref_dir = tmp_path / "ref"
    ref_dir.mkdir()
    rc, err, *_ = _run_and_signal(argv, ref_dir, signal.SIGTERM, 1e9)
    assert rc == 0, err
    new = (ref_dir / "out.npy").read_bytes()
    old = b"old contents"
    failures = collections.Counter()
    outcomes = collections.Counter()
    trials = [(sig, rng.uniform(0.0, 0.12), aim) for aim in ("write", "write", "write", "write", "any", "any")
              for sig in (signal.SIGTERM, signal.SIGINT)]  # fmt: skip
    for k, (sig, delay, aim) in enumerate(trials):
        folder = tmp_path / f"t{k}"
        folder.mkdir()
        has_old = k % 4 in (1, 2)  # an older output is being replaced: under SIGTERM and SIGINT alike
        if has_old:
            (folder / "out.npy").write_bytes(old)
        if aim == "write":  # inside the write: the temporary file is there
            watch = lambda seen, folder=folder: bool(_temps(folder))  # noqa: E731
        else:  # anywhere in the command's run, from the moment main() starts
            watch = lambda seen, folder=folder: (folder.parent / f".{folder.name}.started").exists()  # noqa: E731
            delay = rng.uniform(0.01, 1.5)
        rc, err, _, sent, out_text = _run_and_signal(argv, folder, sig, delay, watch=watch)
        out = folder / "out.npy"
        got = out.read_bytes() if out.exists() else None
        if rc == -sig and got == new and "wrote out.npy" in out_text:
            rc = "after"  # the command had finished: Python, exiting, took the signal (no handler is ours by then)
        outcomes[{0: "finished", 130: "interrupted", 143: "terminated", "after": "signalled while exiting"}
                 .get(rc, f"exit {rc}")] += 1  # fmt: skip
        if rc not in (0, 130, 143, "after") or not sent and rc != 0:
            failures[f"exit {rc}"] += 1
        if "Traceback" in err:
            failures["traceback"] += 1
        if _temps(folder):
            failures["temporary file left"] += 1
        if got not in ((old if has_old else None), new):
            failures["partial or wrong output"] += 1
    print(f"\nprobe signal {command}: {len(trials)} signals ({dict(outcomes)}), {sum(failures.values())} failures"
          + (f": {dict(failures)}" if failures else ""))  # fmt: skip
    assert not failures


def _pairs_consistent(folder: Path, names) -> list[str]:
    """Each figure has its sidecar, and the sidecar describes that very file (its pixel size)."""
    from PIL import Image

    bad = []
    for name in names:
        png, side = folder / f"{name}.png", folder / f"{name}.json"
        if png.exists() != side.exists():
            bad.append(f"{name}: figure without sidecar" if png.exists() else f"{name}: sidecar without figure")
            continue
        if png.exists():
            rec = json.loads(side.read_text(encoding="utf-8"))
            with Image.open(png) as im:
                if list(im.size) != rec["size_px"]:
                    bad.append(f"{name}: sidecar of another drawing")
    return bad


def test_probe_signal_while_figures_are_written_by_workers(tmp_path):
    pytest.importorskip("matplotlib")
    pytest.importorskip("PIL")
    names = ["reflection_geometry", "light_is_linear", "light_colour", "lambert_sphere_angles"]
    argv = ["figures", "--out", "figs", "--quick", "--jobs", "2", "--only", *names]
    rng = random.Random(20)
    failures = collections.Counter()
    outcomes = collections.Counter()
    trials = [(signal.SIGTERM, "write"), (signal.SIGINT, "write"), (signal.SIGKILL, "write"),
              (signal.SIGTERM, "any"), (signal.SIGINT, "any"), (signal.SIGKILL, "any")]  # fmt: skip
    workers_seen = 0
    for k, (sig, aim) in enumerate(trials):
        folder = tmp_path / f"t{k}"
        (folder / "figs").mkdir(parents=True)
        if k % 2:  # an older set, drawn at another resolution, is being replaced
            from explorer.figures import generate

            generate(folder / "figs", only=names[:2], quick=True, dpi=20)
        figs = folder / "figs"
        # Aim at the moment the first new figure lands: workers are then mid-way through the others.
        start_names = {p.name: p.stat().st_mtime_ns for p in figs.iterdir()}

        def first_written(seen, figs=figs, start_names=start_names):
            return any(p.suffix == ".png" and start_names.get(p.name) != p.stat().st_mtime_ns
                       for p in figs.iterdir() if p.exists())  # fmt: skip

        def pool_started(seen):  # a worker process is up: the command is well inside main()
            return len(seen) >= 2

        delay = rng.uniform(0.0, 0.3) if aim == "write" else rng.uniform(0.0, 3.0)
        rc, err, children, *_ = _run_and_signal(argv, folder, sig, delay, harness=False,
                                               watch=first_written if aim == "write" else pool_started)  # fmt: skip
        workers_seen += len(children)
        outcomes[{0: "finished", 130: "interrupted", 143: "terminated", -9: "killed"}.get(rc, f"exit {rc}")] += 1
        if rc not in (0, 130, 143, -9):
            failures[f"exit {rc}"] += 1
        if "Traceback" in err:
            failures["traceback"] += 1
        deadline = time.monotonic() + 10
        while any(_alive(p) for p in children) and time.monotonic() < deadline:
            time.sleep(0.05)
        if any(_alive(p) for p in children):
            failures["worker alive"] += 1
            for p in children:
                if _alive(p):
                    os.kill(p, signal.SIGKILL)
        if _temps(folder):
            failures["temporary file left"] += 1
        for problem in _pairs_consistent(figs, names):
            failures[problem.split(": ", 1)[1]] += 1
    print(f"\nprobe signal figures --jobs 2: {len(trials)} signals ({dict(outcomes)}), {workers_seen} worker "
          f"processes watched, {sum(failures.values())} failures" + (f": {dict(failures)}" if failures else ""))
    assert not failures
    assert workers_seen >= 2  # the pool did start: the probe watched real workers

"""Probe: mutated scene files through ``lighting-explorer render`` (untrusted files, budgets, interrupted runs).

Every example scene under ``lighting/scene/examples/`` is mutated at random (seeded): keys deleted, types
swapped, huge, tiny, NaN, negative and overlong numbers, values nested 500 deep, 100k-character
strings and keys, output paths with ``..``, absolute paths, symbolic links, directories, input paths
naming FIFOs, devices and folders, huge image sizes, sample counts, sphere resolutions and sparse
mesh files, truncation and random bytes.  Each mutant is rendered in-process with
``explorer.commands.render.main`` from a work folder, with a decoy folder beside it.  A case fails when

* the command raises (any traceback, including a warning turned into an error by the test settings);
* it exits 0 without writing a PNG inside the allowed folders, or exits 2 without exactly one
  stderr line starting ``lighting-explorer: error:``, or exits with anything else;
* any file outside the scene's folder and the current folder appears or changes (the decoy folder,
  the parent folder, link targets), or a failed run leaves a file behind (no partial output);
* the traced memory peak of the run exceeds the memory budget in force (lowered to 256 MiB here).
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import random
import shutil
import tomllib
import tracemalloc

import pytest

from explorer.commands import render as render_cmd
from lighting._budget import set_memory_budget
from lighting.scene import list_examples
from lighting.scene.examples import EXAMPLES_DIR

pytestmark = pytest.mark.slow  # seeded probe: many mutated scene files rendered

SEED = 14
MUTANTS_PER_SCENE = 26
BUDGET = 256 * 1024**2
SIZE = 24  # the base image side: small, so that legal mutants render fast

NUMBERS = [1e308, -1e308, 1e-308, 5e-324, 0, 0.0, -0.0, -1, -1e300, 1e300, math.nan, math.inf, -math.inf,
           2**63, 10**30, -(10**30), 1e16, 123456789]  # fmt: skip
SWAPS = ["text", True, 1, 1.5, [], {}, [1, 2], {"a": 1}, [[1, 2, 3]], "", b"bytes".decode()]
DEEP_ARRAY = "[" * 500 + "]" * 500
DEEP_TABLE = "{a = " * 500 + "1" + "}" * 500
LONG = "x" * 100_000


# ------------------------------------------------------------------ a small TOML writer (the probe's own)
def _key(k) -> str:
    k = str(k)
    return k if k and all(c.isalnum() or c in "_-" for c in k) else json.dumps(k)


def _value(v) -> str:
    if isinstance(v, _Raw):
        return v.text
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


class _Raw:
    """TOML text put in as it is (deeply nested values the writer would not produce)."""

    def __init__(self, text):
        self.text = text


def to_toml(d: dict) -> str:
    lines = []
    tables, arrays = [], []
    for k, v in d.items():
        if isinstance(v, dict) and k in ("camera", "image", "render", "opengl", "materials"):
            tables.append((k, v))
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v) and k in ("objects", "lights"):
            arrays.append((k, v))
        else:
            lines.append(f"{_key(k)} = {_value(v)}")
    for k, v in tables:
        if k == "materials":
            scalars = {n: m for n, m in v.items() if not isinstance(m, dict)}
            if scalars:
                lines += ["", "[materials]"] + [f"{_key(n)} = {_value(m)}" for n, m in scalars.items()]
            for n, m in v.items():
                if isinstance(m, dict):
                    lines += ["", f"[materials.{_key(n)}]"] + [f"{_key(a)} = {_value(b)}" for a, b in m.items()]
        else:
            lines += ["", f"[{k}]"] + [f"{_key(a)} = {_value(b)}" for a, b in v.items()]
    for k, entries in arrays:
        for e in entries:
            lines += ["", f"[[{k}]]"] + [f"{_key(a)} = {_value(b)}" for a, b in e.items()]
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------ mutations
def leaves(d, path=()):
    """Every (container, key) pair of the nested dict/list, depth first."""
    items = d.items() if isinstance(d, dict) else enumerate(d)
    for k, v in list(items):
        yield d, k, path + (k,)
        if isinstance(v, (dict, list)):
            yield from leaves(v, path + (k,))


def mutate(rng: random.Random, scene: dict, work: dict) -> tuple[str, str]:
    """One mutant: ``(kind, toml text)``."""
    d = json.loads(json.dumps(scene))  # a deep copy of plain data
    spots = list(leaves(d))
    kind = rng.choice(["delete", "swap", "number", "long", "deep", "output", "input", "huge", "truncate", "bytes"])
    if kind == "delete":
        for _ in range(rng.randint(1, 3)):
            spots = list(leaves(d))
            c, k, _ = rng.choice(spots)
            del c[k]
    elif kind == "swap":
        c, k, _ = rng.choice(spots)
        c[k] = rng.choice(SWAPS)
    elif kind == "number":
        nums = [s for s in spots if isinstance(s[0][s[1]], (int, float)) and not isinstance(s[0][s[1]], bool)]
        for c, k, _ in rng.sample(nums, min(len(nums), rng.randint(1, 3))):
            c[k] = rng.choice(NUMBERS)
    elif kind == "long":
        c, k, _ = rng.choice(spots)
        if rng.random() < 0.5:
            c[k] = LONG
        elif isinstance(c, dict):
            c[LONG] = c.pop(k)
        else:
            c[k] = {LONG: 1}
    elif kind == "deep":
        c, k, _ = rng.choice([s for s in spots if isinstance(s[0], dict)] or spots)
        c[k] = _Raw(rng.choice([DEEP_ARRAY, DEEP_TABLE, "[" * 40 + "1" + "]" * 40]))
    elif kind == "output":
        # half of them allowed (the current folder, the scene's), half not
        d.setdefault("image", {})["output"] = rng.choice(work["outputs"][rng.random() < 0.5])
    elif kind == "input":
        d.setdefault("objects", []).append({"type": "mesh", "path": rng.choice(work["inputs"])})
    elif kind == "huge":
        choice = rng.randrange(6)
        if choice == 0:
            d.setdefault("image", {}).update(width=rng.choice([16384, 100000, 10**12]), height=16384)
        elif choice == 1:
            lt = {"type": "rect", "center": [0.0, 3.0, 3.0], "samples": rng.choice([65536, 10**6, 10**9])}
            d.setdefault("lights", []).append(lt)
        elif choice == 2:
            d.setdefault("objects", []).append({"type": "uv_sphere", "n_lat": rng.choice([10**6, 10**12]), "n_lon": 64})
        elif choice == 3:
            d.setdefault("objects", []).append({"type": "icosphere", "level": rng.choice([8, 9, 10, 10**6])})
        elif choice == 4:
            d.setdefault("objects", []).append({"type": "mesh", "path": "sparse.obj"})
        else:
            d.setdefault("objects", []).append({"type": "sphere", "scale": rng.choice([1e300, 1e308, 1e-300])})
    text = to_toml(d)
    if kind == "truncate":
        text = text[: rng.randrange(len(text))]
    elif kind == "bytes":
        b = bytearray(text.encode())
        for _ in range(rng.randint(1, 8)):
            b[rng.randrange(len(b))] = rng.randrange(256)
        return kind, bytes(b)
    return kind, text


# ------------------------------------------------------------------ the sandbox
def snapshot(*roots) -> dict:
    """Every entry under ``roots`` (not following links): kind, link target or bytes, mode."""
    out = {}
    for root in roots:
        for dirpath, dirnames, filenames in os.walk(root):
            for name in dirnames + filenames:
                p = os.path.join(dirpath, name)
                st = os.lstat(p)
                if os.path.islink(p):
                    out[p] = ("link", os.readlink(p))
                elif os.path.isfile(p):
                    with open(p, "rb") as f:
                        out[p] = ("file", f.read(), st.st_mode)
                else:
                    out[p] = ("other", st.st_mode)
    return out


def make_sandbox(tmp):
    work, scenes, decoy = tmp / "work", tmp / "work" / "scenes", tmp / "decoy"
    scenes.mkdir(parents=True)
    decoy.mkdir()
    for i in range(5):
        (decoy / f"file{i}.png").write_bytes(b"decoy %d" % i)
    (decoy / "secret.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    (tmp / "beside.png").write_bytes(b"parent")
    shutil.copy(os.path.join(EXAMPLES_DIR, "cube.obj"), scenes / "cube.obj")
    os.symlink(decoy / "file0.png", work / "link_file.png")
    os.symlink(decoy, work / "link_dir")
    os.symlink(decoy / "missing.png", work / "dangling.png")
    os.mkfifo(scenes / "fifo.obj")
    os.mkdir(scenes / "folder.obj")
    with open(scenes / "sparse.obj", "wb") as f:
        f.truncate(1 << 30)
    refused = [str(decoy / "file1.png"), "../decoy/file2.png", "../../decoy/new.png", "scenes/../../decoy/x.png",
               "link_file.png", "link_dir/file3.png", "dangling.png", "/", "", ".", "scenes", str(tmp / "beside.png"),
               "/dev/null", "~/x.png", "a\u0000b.png", "missing_dir/x.png", LONG + ".png"]  # fmt: skip
    allowed = ["ok.png", "scenes/ok2.png", str(scenes / "ok3.png"), "scenes/../ok4.png", "./ok5.png"]
    outputs = (refused, allowed)
    inputs = ["cube.obj", "../../decoy/secret.obj", str(decoy / "secret.obj"), "fifo.obj", "folder.obj",
              "/dev/zero", "/dev/null", "none.obj", "sparse.obj", "cube.toml", "../link_dir/secret.obj"]  # fmt: skip
    return work, scenes, decoy, {"outputs": outputs, "inputs": inputs}


def run_case(argv):
    out, err = io.StringIO(), io.StringIO()
    tracemalloc.reset_peak()
    base = tracemalloc.get_traced_memory()[0]
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            status = render_cmd.main(argv)
    except BaseException as e:  # noqa: BLE001 - the probe counts every escape
        status = f"raised {type(e).__name__}: {str(e)[:200]}"
    peak = tracemalloc.get_traced_memory()[1] - base
    return status, out.getvalue(), err.getvalue(), peak


def test_probe_mutated_scene_files(tmp_path, monkeypatch):
    rng = random.Random(SEED)
    work, scenes, decoy, targets = make_sandbox(tmp_path)
    monkeypatch.chdir(work)
    outside = [str(decoy), str(tmp_path / "beside.png")]
    previous = set_memory_budget(BUDGET)
    tracemalloc.start()
    counts: dict = {}
    failures: list = []
    refusals = {"budget": 0, "output": 0}
    try:
        names = list_examples()
        assert len(names) >= 8
        for name in names:
            with open(os.path.join(EXAMPLES_DIR, name + ".toml"), "rb") as f:
                scene = tomllib.load(f)
            scene.setdefault("image", {}).update(width=SIZE, height=SIZE)
            scene["image"].pop("output", None)
            for i in range(MUTANTS_PER_SCENE):
                kind, text = mutate(rng, scene, targets)
                path = scenes / f"{name}-{i}.toml"
                path.write_bytes(text if isinstance(text, bytes) else text.encode())
                before_out = snapshot(*outside)
                before_in = set(os.listdir(work)) | set(os.listdir(scenes))
                argv = [str(path)]
                if rng.random() < 0.2:  # the user's own -o (inside the work folder here)
                    argv += ["-o", rng.choice(["cli.png", str(work / "cli2.png")])]
                if rng.random() < 0.15:
                    argv += ["--size", rng.choice(["20000x20000", "16x12", "1x1", "3000x3000"])]
                status, out, err, peak = run_case(argv)
                problems = []
                if status == 0:
                    written = (set(os.listdir(work)) | set(os.listdir(scenes))) - before_in
                    if len(written) != 1 or not next(iter(written)).endswith(".png") or err:
                        problems.append(f"exit 0 but wrote {sorted(written)}; stderr {err[:200]!r}")
                    counts[(kind, "rendered")] = counts.get((kind, "rendered"), 0) + 1
                elif status == 2:
                    lines = err.splitlines()
                    if len(lines) != 1 or not lines[0].startswith("lighting-explorer: error: ") or out:
                        problems.append(f"exit 2 with stderr {err[:300]!r}")
                    if (set(os.listdir(work)) | set(os.listdir(scenes))) != before_in:
                        problems.append("a failed run left files behind")
                    refusals["budget"] += "over the memory budget" in err
                    refusals["output"] += ": image.output: " in err
                    counts[(kind, "refused")] = counts.get((kind, "refused"), 0) + 1
                else:
                    problems.append(f"status {status}; stderr {err[:300]!r}")
                if snapshot(*outside) != before_out:
                    problems.append("changed a file outside the allowed folders")
                if peak > BUDGET:
                    problems.append(f"traced memory peak {peak / 2**20:.0f} MiB over the budget")
                for p in problems:
                    failures.append((kind, path.name, p))
                for stale in set(os.listdir(work)) - {"scenes", "link_file.png", "link_dir", "dangling.png"}:
                    os.remove(work / stale)  # the outputs of successful runs
                for stale in set(os.listdir(scenes)) - {"cube.obj", "fifo.obj", "folder.obj", "sparse.obj"}:
                    if not stale.endswith(".toml"):
                        os.remove(scenes / stale)
    finally:
        tracemalloc.stop()
        set_memory_budget(previous)
    total = sum(counts.values())
    by_kind = {}
    for (kind, outcome), n in sorted(counts.items()):
        by_kind.setdefault(kind, {})[outcome] = n
    summary = ", ".join(f"{k} {v.get('rendered', 0)}/{v.get('refused', 0)}" for k, v in by_kind.items())
    fail_kinds = {}
    for kind, _, _ in failures:
        fail_kinds[kind] = fail_kinds.get(kind, 0) + 1
    print(f"\nprobe scenes: {total} cases, {len(failures)} failures {fail_kinds or ''}; rendered/refused by kind: "
          f"{summary}; budget refusals {refusals['budget']}, output refusals {refusals['output']}")  # fmt: skip
    assert total == len(names) * MUTANTS_PER_SCENE
    assert not failures, "\n".join(f"{k} {n}: {p}" for k, n, p in failures[:20])

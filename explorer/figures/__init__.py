"""``lighting-explorer figures``: the lecture-note figures, as a named, reproducible set.

::

    lighting-explorer figures --out DIR [--format png,svg,pdf] [--only NAME ...] [--dpi N]
                              [--quick] [--jobs N] [--accuracy-csv FILE] [--list]

Writes, for every figure of the set (or those named with ``--only``), one file
per format (``NAME.png``, ``NAME.svg``, ``NAME.pdf``), a JSON sidecar
``NAME.json`` (title, caption, the slide it illustrates, the parameters that made
it, what was measured while drawing it, the files and their pixel size), and at
the end a manifest ``figures.json`` listing them all in lecture order.

The same inputs give the same pixels — and the same bytes: the figures are
drawn from fixed parameters and seeds, and the files carry no date, no software
version stamp and no random SVG ids.  The two exceptions plot *measured* wall-clock
times: the ``accuracy_*`` figures, when they measure their study while drawing (drawn from the
results ``lighting-explorer report accuracy`` saved, or from an ``accuracy.csv`` given with
``--accuracy-csv``, they are reproducible too: see :mod:`explorer.figures.accuracy`), and
``ibl_error`` (the split sum's and Monte Carlo's run times in its titles).

Every figure is drawn with Matplotlib (Agg, no window) from numbers the engine
computed; every sphere and scene is the engine's own image.  ``--quick`` draws
the whole set at low resolution and sample counts in seconds (for tests).

From Python:

    from explorer.figures import generate, REGISTRY
    records = generate("out/figures", formats=("png",), only=["brdf_polar"], quick=True)
"""

from __future__ import annotations

import difflib
import json
import math
import os
import re
import sys
import time
import warnings

from lighting._budget import check_budget, memory_budget, set_memory_budget
from lighting._text import quote
from lighting._validate import check_count

from ..commands.figures import MAX_JOBS
from ..output import (
    OutputError,
    Terminated,
    atomic_write,
    atomic_write_many,
    check_output_dir,
    on_signal,
    quiet_stop_unraisable,
    raise_if_signalled,
)
from .base import REGISTRY, FigureSpec, Quality

__all__ = ["REGISTRY", "FORMATS", "figure_names", "generate", "make_figure", "main", "stable_svg_ids"]

PROG = "lighting-explorer figures"
FORMATS = ("png", "svg", "pdf")
MANIFEST = "figures.json"

# Metadata that would change from run to run (dates, versions) is left out of every file.
_SAVE_METADATA = {
    "png": {"Software": None},
    "svg": {"Date": None, "Creator": None},
    "pdf": {"CreationDate": None, "ModDate": None, "Creator": None, "Producer": None},
}


#: A clip path's name where Matplotlib defines and uses it in an SVG file.
_SVG_CLIP_NAME = re.compile(rb'(id="|url\(#)(p[0-9a-f]{10})\b')


def stable_svg_ids(data: bytes) -> bytes:
    """An SVG file whose clip paths are named by their order of first use, not by the process that drew it.

    Matplotlib names a clip path after a hash of the Python ``id()`` of the path object (``backend_svg``), so the
    same figure saved twice, in one process or two, gets other names — and other bytes — even with
    ``svg.hashsalt`` fixed.  Renamed ``p0000000000``, ``p0000000001``, … the file is the same on every run.

    Parameters
    ----------
    data : bytes
        An SVG file as Matplotlib writes it.

    Returns
    -------
    bytes
        The same file, every clip path renamed where it is defined and where it is used.

    Examples
    --------
    >>> stable_svg_ids(b'<clipPath id="p3fa9c02b1e"/><g clip-path="url(#p3fa9c02b1e)"/>')
    b'<clipPath id="p0000000000"/><g clip-path="url(#p0000000000)"/>'
    """
    names: dict = {}

    def rename(m):
        new = names.setdefault(m.group(2), b"p%010d" % len(names))
        return m.group(1) + new

    return _SVG_CLIP_NAME.sub(rename, data)


#: The figure modules in lecture order; within a module, figures keep the order they are defined in.
LECTURE_MODULES = (
    "illumination", "models", "metals", "lights", "opengl", "brdf", "audit", "zoo", "energy", "fitting", "compare",
    "rendering", "accuracy", "ibl",
)  # fmt: skip


def _load_registry() -> dict[str, FigureSpec]:
    # Registering happens on import, and any module may be imported first (a doctest run, a notebook):
    # the lecture order is imposed here, not left to the order of imports.
    from . import (  # noqa: F401
        accuracy,
        audit,
        brdf,
        compare,
        energy,
        fitting,
        ibl,
        illumination,
        lights,
        metals,
        models,
        opengl,
        rendering,
        zoo,
    )

    rank = {f"{__package__}.{name}": i for i, name in enumerate(LECTURE_MODULES)}

    def lecture_position(spec):
        return rank.get(spec.func.__module__, len(rank)), spec.func.__code__.co_firstlineno

    ordered = sorted(REGISTRY.values(), key=lecture_position)
    if list(REGISTRY) != [s.name for s in ordered]:
        REGISTRY.clear()
        REGISTRY.update((s.name, s) for s in ordered)
    return REGISTRY


def figure_names() -> list[str]:
    """Names of every figure, in lecture order.

    Returns
    -------
    list of str
        The registered names, ordered by :data:`LECTURE_MODULES`, then by definition in each module.
    """
    return list(_load_registry())


class FigureError(ValueError):
    """A bad request (unknown figure name, format, dpi): the command exits with status 2."""


def _check_names(only) -> list[str]:
    names = figure_names()
    if not only:
        return names
    unknown = [n for n in only if n not in names]
    if unknown:
        bad = unknown[0]
        close = difflib.get_close_matches(bad, names, n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        raise FigureError(f"unknown figure {quote(bad)}; {hint}available: {', '.join(names)}")
    return [n for n in names if n in set(only)]


def _check_formats(formats) -> tuple[str, ...]:
    out = []
    for f in formats:
        f = f.strip().lower().lstrip(".")
        if f not in FORMATS:
            raise FigureError(f"unknown format {quote(f)}; allowed: {', '.join(FORMATS)}")
        if f not in out:
            out.append(f)
    if not out:
        raise FigureError(f"no format given; allowed: {', '.join(FORMATS)}")
    return tuple(out)


def _jsonable(x):
    import numpy as np

    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return _jsonable(x.tolist())
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, float):
        return float(f"{x:.6g}")
    return x


def _smallest_text_pt(fig) -> float | None:
    """The size in points of the smallest text a drawn figure shows (``None`` when it shows none)."""
    from matplotlib.text import Text

    sizes = [t.get_fontsize() for t in fig.findobj(Text) if t.get_visible() and t.get_text().strip()]
    return round(float(min(sizes)), 2) if sizes else None


def _png_size(data: bytes) -> tuple[int, int]:
    return int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")


def make_figure(name: str, *, quick: bool = False, dpi: int | None = None, options: dict | None = None):
    """Draw one figure; nothing is written.

    Parameters
    ----------
    name : str
        A registered figure name (see :func:`figure_names`).
    quick : bool, optional
        Low resolution and sample counts (see :class:`~explorer.figures.base.Quality`).
    dpi : int, optional
        Raster resolution (default 150; 50 with ``quick``).
    options : dict, optional
        Values that replace the figure's registered parameters of the same name (others are ignored).

    Returns
    -------
    tuple
        ``(figure, spec, parameters, quality, measured)``: the Matplotlib figure, its
        :class:`~explorer.figures.base.FigureSpec`, the parameters it was drawn with, the
        :class:`~explorer.figures.base.Quality` and the numbers measured while drawing.
    """
    import matplotlib

    from . import base
    from .base import STYLE

    spec = _load_registry()[name]
    q = Quality(quick=quick, dpi=dpi or (50 if quick else 150))
    params = dict(spec.parameters)
    for k, v in (options or {}).items():
        if k in params:
            params[k] = v
    base._drawing_size[0] = spec.size_in
    try:
        with matplotlib.rc_context(STYLE):
            out = spec.func(q, **params)
    finally:
        base._drawing_size[0] = None
    fig, measured = out if isinstance(out, tuple) else (out, {})
    return fig, spec, params, q, measured


def _render_one(name: str, out_dir: str, formats, quick: bool, dpi, options) -> dict:
    """Draw one figure and write its files and sidecar; returns its manifest record."""
    import io

    import matplotlib

    from .base import STYLE

    fig, spec, params, q, measured = make_figure(name, quick=quick, dpi=dpi, options=options)
    w_in, h_in = (float(x) for x in fig.get_size_inches())
    _check_raster(name, w_in, h_in, q.dpi)
    # Each save lays the figure out again, starting from where the last save left it, and constrained layout
    # does not always come back to the same place (the gallery's polar panels move by a pixel or two).  So
    # every figure is saved in the order of FORMATS, up to the last format asked for, those not asked for into
    # memory only: a file is the same image whichever other formats were asked for, and in whatever order.
    saved = {}
    with matplotlib.rc_context(STYLE):
        for fmt in FORMATS[: 1 + max(FORMATS.index(f) for f in formats)]:
            buf = io.BytesIO()
            fig.savefig(buf, format=fmt, dpi=q.dpi, metadata=_SAVE_METADATA[fmt])
            if fmt in formats:
                saved[fmt] = stable_svg_ids(buf.getvalue()) if fmt == "svg" else buf.getvalue()
    files = {fmt: f"{name}.{fmt}" for fmt in formats}
    contents = [(os.path.join(out_dir, files[fmt]), saved[fmt]) for fmt in formats]
    smallest_pt = _smallest_text_pt(fig)
    if "png" in saved:
        size = list(_png_size(saved["png"]))
    else:
        size = [int(round(w_in * q.dpi)), int(round(h_in * q.dpi))]
    fig.clf()
    nondet = spec.nondeterministic
    if measured.get("reproducible"):
        nondet = None  # a timed figure drawn from saved numbers (a file, a cache): reproducible
    record = {
        "name": name,
        "title": spec.title,
        "caption": spec.caption.format(**measured) if measured else spec.caption,
        "slides": spec.slides,
        "parameters": _jsonable(params),
        "quality": {"quick": q.quick, "dpi": q.dpi},
        "measured": _jsonable(measured),
        "files": files,
        "size_px": size,
        "size_in": [round(w_in, 3), round(h_in, 3)],
        "smallest_text_pt": smallest_pt,
        "deterministic": nondet is None,
        "nondeterministic_reason": nondet,
    }
    sidecar = (json.dumps(record, indent=2, ensure_ascii=False) + "\n").encode()
    # The figure's files and its sidecar are renamed into place together, signals held: an interrupt
    # leaves the old set or the new one, never a figure without its sidecar.
    atomic_write_many([*contents, (os.path.join(out_dir, f"{name}.json"), sidecar)], flag="--out")
    return record


# --------------------------------------------------------------------------- checks before the work
#: The size assumed for a figure registered without one, in inches.
UNDECLARED_FIGURE_IN = (19.0, 12.0)
#: Peak bytes per raster pixel while saving: Agg's RGBA buffer plus the PNG encoder's copy.
BYTES_PER_PIXEL = 8
#: Agg cannot draw an image wider or taller than this many pixels.
AGG_MAX_PIXELS = 2**16 - 1
#: Memory one worker process takes (the interpreter, NumPy, Matplotlib and one figure), for the budget.
WORKER_BYTES = 256 * 1024**2


def _check_raster(what: str, w_in: float, h_in: float, dpi: int) -> None:
    """Refuse a raster over Agg's limit or the memory budget, before Matplotlib allocates it."""
    w, h = math.ceil(w_in * dpi), math.ceil(h_in * dpi)
    if max(w, h) > AGG_MAX_PIXELS:
        raise FigureError(
            f"--dpi {dpi} makes {what} {w}x{h} pixels; Matplotlib draws at most {AGG_MAX_PIXELS} pixels a side"
        )
    try:
        check_budget(f"--dpi {dpi}", BYTES_PER_PIXEL * w * h, what=f"{what} at {w}x{h} pixels")
    except ValueError as exc:
        raise FigureError(str(exc)) from None


def _check_dpi(dpi, names) -> int | None:
    """``--dpi`` checked against the declared size of each figure in ``names``, before any is drawn."""
    if dpi is None:
        return None
    try:
        dpi = check_count("--dpi", dpi, 10)
    except ValueError as exc:
        raise FigureError(str(exc)) from None
    registry = _load_registry()
    for name in names:
        _check_raster(name, *(registry[name].size_in or UNDECLARED_FIGURE_IN), dpi)
    return dpi


def _check_jobs(jobs) -> int:
    jobs = check_count("--jobs", jobs, 1, MAX_JOBS)
    if jobs > 1:
        check_budget(f"--jobs {jobs}", WORKER_BYTES * jobs, what=f"{jobs} worker processes")
    return jobs


#: The columns of ``accuracy.csv`` (``lighting-explorer report accuracy``) the figures read, and their types.
ACCURACY_COLUMNS = {"study": str, "case": str, "method": str, "cost": int, "cost_unit": str, "error": float,
                    "error_spread": float, "seconds": float, "reference": str}  # fmt: skip


def check_accuracy_csv(path) -> str:
    """Check that ``path`` is an ``accuracy.csv`` the ``accuracy_*`` figures can draw; returns its absolute path.

    Parameters
    ----------
    path : str or os.PathLike
        The file given to ``--accuracy-csv``.

    Returns
    -------
    str
        Its absolute path.

    Raises
    ------
    FigureError
        Naming the file, the line and the column for a missing file, a file that is not UTF-8 CSV, a
        missing column, a value of the wrong type or a negative or non-finite number, or a file without
        data rows.
    """
    import csv

    from lighting._text import abbreviate, quote_path

    shown = quote_path(path)
    if not os.path.isfile(path):
        raise FigureError(f"--accuracy-csv: no such file: {os.fspath(path)}")
    try:
        with open(path, newline="", encoding="utf-8") as f:
            reader = csv.DictReader(f)
            missing = [c for c in ACCURACY_COLUMNS if c not in (reader.fieldnames or [])]
            if missing:
                raise FigureError(
                    f"--accuracy-csv: {shown} is not an accuracy.csv of 'lighting-explorer report accuracy': "
                    f"missing {'column' if len(missing) == 1 else 'columns'} {', '.join(missing)}"
                )
            rows = 0
            for row in reader:
                rows += 1
                for col, kind in ACCURACY_COLUMNS.items():
                    text = row.get(col)
                    if text is None:
                        raise FigureError(f"--accuracy-csv: {shown} line {reader.line_num}: no value for {col!r}")
                    if kind is str:
                        continue
                    try:
                        value = kind(text or 0) if col == "error_spread" else kind(text)
                    except ValueError:
                        raise FigureError(
                            f"--accuracy-csv: {shown} line {reader.line_num}: {col} must be "
                            f"{'an integer' if kind is int else 'a number'}; got {abbreviate(repr(text))}"
                        ) from None
                    if not (math.isfinite(value) and value >= 0):
                        raise FigureError(
                            f"--accuracy-csv: {shown} line {reader.line_num}: {col} must be finite and >= 0; "
                            f"got {abbreviate(repr(text))}"
                        )
    except UnicodeDecodeError:
        raise FigureError(f"--accuracy-csv: {shown} is not a UTF-8 text file") from None
    except csv.Error as exc:
        raise FigureError(f"--accuracy-csv: {shown} is not a CSV file ({exc})") from None
    except OSError as exc:
        raise FigureError(f"--accuracy-csv: cannot read {shown}: {exc.strerror or exc}") from None
    if rows == 0:
        raise FigureError(f"--accuracy-csv: {shown} has no data rows")
    return os.path.abspath(path)


# --------------------------------------------------------------------------- worker processes
def _die_with_parent(parent: int) -> None:
    """Ask Linux to send this process SIGTERM when its parent dies (prctl PR_SET_PDEATHSIG)."""
    import signal

    if sys.platform.startswith("linux"):
        try:
            import ctypes

            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(1, int(signal.SIGTERM), 0, 0, 0)  # 1 = PR_SET_PDEATHSIG
        except (OSError, AttributeError):
            pass
    if os.getppid() != parent:  # the parent died before the request was in place
        os._exit(143)


# [inside a figure, this is a worker process]
_in_job = [False, False]


def _worker_signal(signum, frame):
    # Inside a figure, unwind (the writer removes its temporary files; a figure and its sidecar being
    # renamed finish first); between figures, just go.
    if _in_job[0]:
        on_signal(signum, frame)
        return
    os._exit(128 + signum)


def _worker_init(filters, parent, budget):
    import signal

    _die_with_parent(parent)
    _in_job[1] = True
    signal.signal(signal.SIGTERM, _worker_signal)
    signal.signal(signal.SIGINT, _worker_signal)
    sys.unraisablehook = quiet_stop_unraisable  # a stop raised inside a GC callback: noted, not printed
    set_memory_budget(budget)
    warnings.filters[:] = filters
    import matplotlib

    matplotlib.use("Agg")


def _run_job(args):
    t0 = time.perf_counter()
    _in_job[0] = True
    try:
        rec = _render_one(*args)
        raise_if_signalled()  # a stop that a callback swallowed (see quiet_stop_unraisable) ends the job here
    except (Terminated, KeyboardInterrupt):
        if _in_job[1]:
            os._exit(143)  # a worker: this figure's files are cleaned up, and the parent is going away
        raise
    finally:
        _in_job[0] = False
    return rec, time.perf_counter() - t0


def _stop_workers(pool) -> None:
    """Cancel what has not started and end the workers now (SIGTERM, then SIGKILL after 5 s)."""
    procs = list(getattr(pool, "_processes", {}).values())
    manager = getattr(pool, "_executor_manager_thread", None)
    pool.shutdown(wait=False, cancel_futures=True)
    for p in procs:
        if p.is_alive():
            p.terminate()
    deadline = time.monotonic() + 5.0
    for p in procs:
        p.join(max(0.0, deadline - time.monotonic()))
        if p.is_alive():
            p.kill()
            p.join(1.0)
    # The pool's manager thread closes its wake-up pipe as it finishes; at exit, concurrent.futures wakes every
    # manager thread still known through that pipe.  Were this one still finishing then, the two would race and
    # the exit would print "OSError: [Errno 9] Bad file descriptor" under "Exception ignored in" (Python 3.11).
    # Its workers are gone, so it finishes at once: wait for it here.
    if manager is not None and manager.is_alive():
        manager.join(max(0.0, deadline - time.monotonic()) + 1.0)


def _merge_records(out_dir: str, new: list[dict]) -> list[dict]:
    """``new`` merged into the manifest already in ``out_dir``: same-name entries replaced, lecture order."""
    path = os.path.join(out_dir, MANIFEST)
    old = []
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
        if isinstance(data, dict) and isinstance(data.get("figures"), list):
            old = [r for r in data["figures"] if isinstance(r, dict) and isinstance(r.get("name"), str)]
    except (OSError, ValueError):
        old = []  # no manifest yet, or not one of ours: start a new one
    records = {r["name"]: r for r in old}
    records.update({r["name"]: r for r in new})
    order = {n: i for i, n in enumerate(figure_names())}
    return sorted(records.values(), key=lambda r: (order.get(r["name"], len(order)), r["name"]))


def generate(
    out_dir,
    *,
    formats=("png",),
    only=None,
    quick: bool = False,
    dpi: int | None = None,
    jobs: int = 1,
    options: dict | None = None,
    progress=None,
    log=None,
) -> list[dict]:
    """Write the figures (all, or ``only``) into ``out_dir``; returns the manifest records in lecture order.

    Parameters
    ----------
    out_dir : str or os.PathLike
        The output folder (created if missing).
    formats : sequence of str, optional
        Among ``png``, ``svg``, ``pdf``.
    only : sequence of str, optional
        Draw only these figures: they replace their entries in an existing ``figures.json`` and the
        others are kept; without it the manifest lists the whole set.
    quick : bool, optional
        Low resolution and sample counts.
    dpi : int, optional
        Raster resolution (default 150; 50 with ``quick``).
    jobs : int, optional
        Worker processes (1 to :data:`MAX_JOBS`); the files are the same either way.
    options : dict, optional
        ``{"csv": path}`` draws the ``accuracy_*`` figures from an ``accuracy.csv``.
    progress : callable, optional
        ``progress(total, label)`` returning an object with ``update()``, ``close()`` and ``abort()``
        (e.g. :class:`explorer.progress.Progress`).
    log : callable, optional
        ``log(name, seconds)``, called as each figure is done.

    Returns
    -------
    list of dict
        The manifest records of the figures drawn, in lecture order.

    Notes
    -----
    Everything is checked before anything is drawn: unknown names or formats, a dpi below 10 or
    one whose largest figure is over Matplotlib's limit or the memory budget, ``jobs`` outside
    ``[1, 64]`` or over the budget, an ``out_dir`` that is a file or not writable, a malformed
    ``options["csv"]``: :class:`FigureError` (a ValueError) naming the option.

    Files are written atomically, each figure together with its sidecar; an interrupt (Ctrl-C,
    ``SIGTERM`` through :func:`explorer.output.signals_as_exceptions`) stops the worker processes and
    leaves no temporary file.  Workers also end when this process dies (Linux).
    """
    names = _check_names(only)
    formats = _check_formats(formats)
    dpi = _check_dpi(dpi, names)
    try:
        jobs = _check_jobs(jobs)
        out_dir = check_output_dir(os.fspath(out_dir), flag="--out")
    except (OutputError, ValueError) as exc:
        raise FigureError(str(exc)) from None
    options = dict(options or {})
    if options.get("csv"):
        options["csv"] = check_accuracy_csv(options["csv"])
    os.makedirs(out_dir, exist_ok=True)
    bar = progress(len(names), "figures") if progress else None
    records = {}
    tasks = [(n, str(out_dir), formats, quick, dpi, options) for n in names]

    def done(rec, sec):
        records[rec["name"]] = rec
        if log:
            log(rec["name"], sec)
        if bar:
            bar.update()

    try:
        if jobs > 1 and len(names) > 1:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor, as_completed

            # Figures that time the engine run first, alone, so that no other figure competes for the cores.
            timed = [t for t in tasks if REGISTRY[t[0]].nondeterministic and not options.get("csv")]
            tasks = [t for t in tasks if t not in timed]
            for t in timed:
                done(*_run_job(t))

            ctx = multiprocessing.get_context("spawn")  # no fork of a process that may hold engine threads
            pool = ProcessPoolExecutor(
                max_workers=min(jobs, len(names)), mp_context=ctx, initializer=_worker_init,
                initargs=(list(warnings.filters), os.getpid(), memory_budget()),
            )  # fmt: skip
            try:
                futures = {pool.submit(_run_job, t): t[0] for t in _heaviest_first(tasks)}
                for fut in as_completed(futures):
                    done(*fut.result())
            except BaseException:
                _stop_workers(pool)  # an error, Ctrl-C or SIGTERM: no worker goes on writing
                raise
            pool.shutdown(wait=True)
        else:
            for t in tasks:
                done(*_run_job(t))
    except BaseException:
        if bar:
            bar.abort()
        raise
    if bar:
        bar.close()
    ordered = [records[n] for n in names]
    listed = _merge_records(out_dir, ordered) if only else ordered
    manifest = {
        "generator": PROG,
        "quick": all(r.get("quality", {}).get("quick", False) for r in listed),
        "formats": [f for f in FORMATS if any(f in r.get("files", {}) for r in listed)],
        "figures": listed,
    }
    atomic_write(os.path.join(out_dir, MANIFEST), (json.dumps(manifest, indent=2, ensure_ascii=False) + "\n").encode(),
                 flag="--out")  # fmt: skip
    return ordered


# Figures that take longest go to the workers first, so the pool ends together.
_HEAVY = ("rendering_equation", "brdf_lobes_3d", "plausibility_table", "light_types", "cook_torrance_spheres")


def _heaviest_first(tasks):
    return sorted(tasks, key=lambda t: (0 if t[0] in _HEAVY else 1, _HEAVY.index(t[0]) if t[0] in _HEAVY else 0))


# --------------------------------------------------------------------------- command line
def main(argv=None) -> int:
    """``lighting-explorer figures`` run alone: the command is :mod:`explorer.commands.figures`.

    Every option is checked before anything is drawn (see :func:`generate`).

    Parameters
    ----------
    argv : list of str, optional
        The options (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0 done, 1 a file could not be written, 2 a bad request.
    """
    from ..commands.figures import main as figures_main

    return figures_main(argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

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
version stamp and no random SVG ids.  The one exception is ``accuracy``, which
plots *measured* wall-clock times; given ``--accuracy-csv`` (the ``accuracy.csv``
written by ``lighting-explorer report accuracy``) it is drawn from that file and
is reproducible too.

Every figure is drawn with Matplotlib (Agg, no window) from numbers the engine
computed; every sphere and scene is the engine's own image.  ``--quick`` draws
the whole set at low resolution and sample counts in seconds (for tests).

From Python::

    from explorer.figures import generate, REGISTRY
    records = generate("out/figures", formats=("png",), only=["brdf_polar"], quick=True)
"""

from __future__ import annotations

import argparse
import difflib
import json
import os
import sys
import time
import warnings

from .figures_base import REGISTRY, FigureSpec, Quality

__all__ = ["REGISTRY", "FORMATS", "figure_names", "generate", "make_figure", "main"]

PROG = "lighting-explorer figures"
FORMATS = ("png", "svg", "pdf")
MANIFEST = "figures.json"

# Metadata that would change from run to run (dates, versions) is left out of every file.
_SAVE_METADATA = {
    "png": {"Software": None},
    "svg": {"Date": None, "Creator": None},
    "pdf": {"CreationDate": None, "ModDate": None, "Creator": None, "Producer": None},
}


def _load_registry() -> dict[str, FigureSpec]:
    # Registering happens on import; the order of imports is the lecture order of the set.
    from . import figures_models, figures_light, figures_brdf, figures_render  # noqa: F401, I001

    return REGISTRY


def figure_names() -> list[str]:
    """Names of every figure, in lecture order."""
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
        raise FigureError(f"unknown figure {bad!r}; {hint}available: {', '.join(names)}")
    return [n for n in names if n in set(only)]


def _check_formats(formats) -> tuple[str, ...]:
    out = []
    for f in formats:
        f = f.strip().lower().lstrip(".")
        if f not in FORMATS:
            raise FigureError(f"unknown format {f!r}; allowed: {', '.join(FORMATS)}")
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


def _png_size(path: str) -> tuple[int, int]:
    with open(path, "rb") as f:
        head = f.read(24)
    return int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big")


def _atomic_write(path: str, data: bytes) -> None:
    tmp = f"{path}.tmp{os.getpid()}"
    with open(tmp, "wb") as f:
        f.write(data)
    os.replace(tmp, path)


def make_figure(name: str, *, quick: bool = False, dpi: int | None = None, options: dict | None = None):
    """Draw one figure: ``(matplotlib Figure, spec, parameters, measured)`` (nothing is written)."""
    import matplotlib

    from .figures_base import STYLE

    spec = _load_registry()[name]
    q = Quality(quick=quick, dpi=dpi or (50 if quick else 150))
    params = dict(spec.parameters)
    for k, v in (options or {}).items():
        if k in params:
            params[k] = v
    with matplotlib.rc_context(STYLE):
        out = spec.func(q, **params)
    fig, measured = out if isinstance(out, tuple) else (out, {})
    return fig, spec, params, q, measured


def _render_one(name: str, out_dir: str, formats, quick: bool, dpi, options) -> dict:
    """Draw one figure and write its files and sidecar; returns its manifest record."""
    import io

    import matplotlib

    from .figures_base import STYLE

    fig, spec, params, q, measured = make_figure(name, quick=quick, dpi=dpi, options=options)
    files = {}
    with matplotlib.rc_context(STYLE):
        for fmt in formats:
            buf = io.BytesIO()
            fig.savefig(buf, format=fmt, dpi=q.dpi, metadata=_SAVE_METADATA[fmt])
            path = os.path.join(out_dir, f"{name}.{fmt}")
            _atomic_write(path, buf.getvalue())
            files[fmt] = os.path.basename(path)
    w_in, h_in = (float(x) for x in fig.get_size_inches())
    if "png" in files:
        size = list(_png_size(os.path.join(out_dir, files["png"])))
    else:
        size = [int(round(w_in * q.dpi)), int(round(h_in * q.dpi))]
    fig.clf()
    nondet = spec.nondeterministic
    if name == "accuracy" and params.get("csv"):
        nondet = None  # drawn from a file: reproducible
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
        "deterministic": nondet is None,
        "nondeterministic_reason": nondet,
    }
    _atomic_write(
        os.path.join(out_dir, f"{name}.json"), (json.dumps(record, indent=2, ensure_ascii=False) + "\n").encode()
    )
    return record


def _worker_init(filters):
    warnings.filters[:] = filters
    import matplotlib

    matplotlib.use("Agg")


def _run_job(args):
    t0 = time.perf_counter()
    rec = _render_one(*args)
    return rec, time.perf_counter() - t0


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

    ``progress`` is a callable ``(total, label)`` returning an object with ``update()`` and
    ``close()`` (e.g. :class:`explorer.progress.Progress`); ``log(name, seconds)`` is called as
    each figure is done.  ``jobs > 1`` draws figures in that many worker processes (the
    files are the same either way).  Raises :class:`FigureError` for unknown names or
    formats or a dpi below 10.
    """
    names = _check_names(only)
    formats = _check_formats(formats)
    if dpi is not None and (isinstance(dpi, bool) or not isinstance(dpi, int) or dpi < 10):
        raise FigureError(f"dpi must be an integer >= 10; got {dpi!r}")
    os.makedirs(out_dir, exist_ok=True)
    options = dict(options or {})
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
            with ProcessPoolExecutor(
                max_workers=min(jobs, len(names)), mp_context=ctx, initializer=_worker_init,
                initargs=(list(warnings.filters),),
            ) as pool:  # fmt: skip
                futures = {pool.submit(_run_job, t): t[0] for t in _heaviest_first(tasks)}
                for fut in as_completed(futures):
                    done(*fut.result())
        else:
            for t in tasks:
                done(*_run_job(t))
    finally:
        if bar:
            bar.close()
    ordered = [records[n] for n in names]
    manifest = {
        "generator": PROG,
        "quick": quick,
        "formats": list(formats),
        "figures": ordered,
    }
    _atomic_write(os.path.join(out_dir, MANIFEST), (json.dumps(manifest, indent=2, ensure_ascii=False) + "\n").encode())
    return ordered


# Figures that take longest go to the workers first, so the pool ends together.
_HEAVY = ("rendering_equation", "brdf_lobes_3d", "plausibility_table", "light_types", "cook_torrance_spheres")


def _heaviest_first(tasks):
    return sorted(tasks, key=lambda t: (0 if t[0] in _HEAVY else 1, _HEAVY.index(t[0]) if t[0] in _HEAVY else 0))


# --------------------------------------------------------------------------- command line
class _UsageError(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # report like every other error: one line, status 2
        raise _UsageError(message)


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog=PROG, description="Write the lecture-note figures (PNG/SVG/PDF, each with a JSON sidecar).")
    p.add_argument("--out", "-o", default=os.path.join("out", "figures"), help="output folder (default: out/figures)")
    p.add_argument("--format", default="png", help="comma-separated formats among png, svg, pdf (default: png)")
    p.add_argument("--only", nargs="+", metavar="NAME", help="draw only these figures (see --list)")
    p.add_argument("--dpi", type=int, help="raster resolution (default 150; 50 with --quick)")
    p.add_argument("--quick", action="store_true", help="low resolution and sample counts: the whole set in seconds")
    p.add_argument("--jobs", "-j", type=int, default=None, help="worker processes (default: up to 4, one per core)")
    p.add_argument("--accuracy-csv", metavar="FILE",
                   help="draw the 'accuracy' figure from this accuracy.csv (lighting-explorer report accuracy) "
                        "instead of measuring now")  # fmt: skip
    p.add_argument("--list", action="store_true", help="list the figures and exit")
    return p


def main(argv=None) -> int:
    """Entry point of ``lighting-explorer figures``; returns the exit status (2 for a bad request)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    try:
        args = build_parser().parse_args(argv)
        if args.list:
            for name, spec in _load_registry().items():
                print(f"{name:24s} {spec.title}")
            return 0
        formats = _check_formats(args.format.split(","))
        names = _check_names(args.only)
        # Worker processes pay for their start-up: only worth it for more than a handful of figures.
        jobs = args.jobs if args.jobs is not None else max(1, min(4, os.cpu_count() or 1, len(names) // 4))
        if jobs < 1:
            raise FigureError(f"--jobs must be >= 1; got {jobs}")
        options = {}
        if args.accuracy_csv:
            if not os.path.isfile(args.accuracy_csv):
                raise FigureError(f"--accuracy-csv: no such file: {args.accuracy_csv}")
            options["csv"] = os.path.abspath(args.accuracy_csv)
    except (_UsageError, FigureError) as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 2
    from .progress import Progress

    t0 = time.perf_counter()
    try:
        records = generate(
            args.out, formats=formats, only=args.only, quick=args.quick, dpi=args.dpi, jobs=jobs,
            options=options, progress=Progress,
        )  # fmt: skip
    except FigureError as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 1
    n_files = sum(len(r["files"]) for r in records)
    print(
        f"wrote {len(records)} figures ({n_files} files, {', '.join(formats)}) and {MANIFEST} to {args.out} "
        f"in {time.perf_counter() - t0:.1f} s"
    )
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

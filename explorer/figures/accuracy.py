"""Error against run time: one figure per study of ``lighting-explorer report accuracy``.

Registered on import (see :mod:`explorer.figures.base`); drawn by :mod:`explorer.figures`.  The
figures ``accuracy_integration``, ``accuracy_area_light``, ``accuracy_tessellation``,
``accuracy_precision`` and ``accuracy_ibl`` plot the studies of :mod:`lighting.validation.accuracy`.
Their numbers come, in this order, from

1. an ``accuracy.csv`` given to ``lighting-explorer figures --accuracy-csv`` (its rows of that study);
2. the studies ``lighting-explorer report accuracy`` saved (:mod:`explorer.reports.cache`), the full
   settings before the quick ones, for this engine;
3. else the study's *quick* settings, measured while drawing and saved for the next time.

Only the third plots times measured now: a figure drawn from a file or the cache is reproducible
(its ``measured["reproducible"]`` is true, which the figure set reads).
"""

from __future__ import annotations

import csv
import math
from dataclasses import replace

import numpy as np

from lighting.validation.accuracy import GRID_METHOD

from .base import PALETTE, new_figure, register, series_colours

#: Error thresholds drawn on every error axis: (value, line style, label).
_THRESHOLDS = ((1e-2, "--", "1 %"), (1e-3, ":", "0.1 %"))

_SOURCE_CAPTION = "Numbers {source}."
_TIMES = "Times are medians on the machine that measured them."
_QUICK = "; with the quick settings the problems are small, and fixed costs per call weigh on the times"


# --------------------------------------------------------------------------- where the numbers come from
def _read_points(path, study):
    """The points of one study in an ``accuracy.csv`` written by ``lighting-explorer report accuracy``."""
    from lighting.validation.accuracy import Point

    pts = []
    with open(path, newline="", encoding="utf-8") as f:
        for row in csv.DictReader(f):
            if row["study"] != study:
                continue
            extra = {}
            for name in ("estimated_error", "coverage", "error_p95", "reference_error"):
                if row.get(name):
                    extra[name] = float(row[name])
            if row.get("unconverged"):
                extra["unconverged"] = row["unconverged"] == "True"
            pts.append(
                Point(row["study"], row["case"], row["method"], int(row["cost"]), row["cost_unit"],
                      float(row["error"]), float(row["error_spread"] or 0.0), float(row["seconds"]),
                      row["reference"], **extra)
            )  # fmt: skip
    return pts


def study_points(study: str, *, csv_path=None):
    """The points of one accuracy study, and where they came from.

    Parameters
    ----------
    study : str
        A study of :data:`lighting.validation.accuracy.STUDY_NAMES`.
    csv_path : str, optional
        An ``accuracy.csv`` of ``lighting-explorer report accuracy``; its rows of ``study`` are used
        when it has any.

    Returns
    -------
    points : list of lighting.validation.accuracy.Point
    source : dict
        ``text`` (for the caption), ``kind`` (``"csv"``, ``"cache"`` or ``"measured now"``),
        ``settings`` (``"full"``, ``"quick"`` or ``"as in the file"``), ``by`` (the command that
        measured them) and ``reproducible`` (false only when measured now).
    """
    from ..reports.cache import load_study, save_study

    if csv_path:
        pts = _read_points(csv_path, study)
        if pts:
            return pts, {"text": "read from an accuracy.csv of lighting-explorer report accuracy", "kind": "csv",
                         "settings": "as in the file", "by": "lighting-explorer report accuracy",
                         "reproducible": True}  # fmt: skip
    for quick in (False, True):
        saved = load_study(study, quick=quick)
        if saved is not None:
            settings = "quick" if quick else "full"
            return saved.study.points, {
                "text": f"measured by {saved.by} ({settings} settings), read from its saved results" + _QUICK * quick,
                "kind": "cache",
                "settings": settings,
                "by": saved.by,
                "reproducible": True,
            }
    from lighting.validation.accuracy import run_studies

    measured = run_studies(quick=True, only=[study])[0]
    save_study(measured, quick=True, by="lighting-explorer figures")
    return measured.points, {
        "text": "measured while drawing with the quick settings of lighting-explorer report accuracy "
        "(run 'lighting-explorer report accuracy' for the full study)" + _QUICK,
        "kind": "measured now",
        "settings": "quick",
        "by": "lighting-explorer figures",
        "reproducible": False,
    }


def _measured(points, source, **more):
    return {
        "source": source["text"],
        "source_kind": source["kind"],
        "settings": source["settings"],
        "measured_by": source["by"],
        "reproducible": source["reproducible"],
        "points": len(points),
        **more,
    }


# --------------------------------------------------------------------------- axes
def _floor(errors) -> float:
    """Where exact zeros are drawn: a decade below the smallest nonzero error."""
    nonzero = [e for e in errors if e > 0]
    return 10.0 ** (math.floor(math.log10(min(nonzero))) - 1) if nonzero else 1e-16


def _time_axis(ax, times_ms, label="time per evaluation (ms)") -> None:
    """A log time axis in milliseconds spanning at least a factor 4, so that 1-2-5 ticks fall inside it."""
    import matplotlib.ticker as mt

    lo, hi = min(times_ms) / 1.35, max(times_ms) * 1.35
    if hi / lo < 4:
        mid = math.sqrt(lo * hi)
        lo, hi = mid / 2, mid * 2
    ax.set_xscale("log")
    ax.set_xlim(lo, hi)
    subs = (1.0,) if hi / lo > 300 else (1.0, 2.0, 5.0) if hi / lo > 12 else (1.0, 1.5, 2.0, 3.0, 5.0, 7.0)
    ax.xaxis.set_major_locator(mt.LogLocator(base=10, subs=subs))
    ax.xaxis.set_major_formatter(mt.FuncFormatter(lambda x, _: f"{x:g}"))
    ax.xaxis.set_minor_formatter(mt.NullFormatter())
    ax.set_xlabel(label)


def _error_axis(ax, errors, floor=None, label="relative error") -> None:
    """A log error axis with the 1 % and 0.1 % lines (labelled at the right edge) and a '0' tick for exact zeros."""
    import matplotlib.ticker as mt

    ax.set_yscale("log")
    nonzero = [e for e in errors if e > 0]
    top = max(nonzero) if nonzero else 1.0
    bottom = floor if floor is not None and any(e == 0 for e in errors) else min(nonzero) if nonzero else 1e-3
    ax.set_ylim(bottom / 2.5, max(top * 2.5, 2e-2))
    for value, style, text in _THRESHOLDS:
        if bottom / 2.5 < value < max(top * 2.5, 2e-2):
            ax.axhline(value, color="0.45", ls=style, lw=1.0, zorder=0)
            ax.annotate(text, (1.0, value), xycoords=("axes fraction", "data"), xytext=(3, 0),
                        textcoords="offset points", va="center", ha="left", fontsize=10.5, color="0.35")  # fmt: skip
    ax.yaxis.set_major_locator(mt.LogLocator(base=10, numticks=8))
    ax.yaxis.set_minor_formatter(mt.NullFormatter())
    if floor is not None and any(e == 0 for e in errors):
        ticks = [t for t in ax.get_yticks() if t > floor * 3]

        def fmt(x, _):
            if math.isclose(x, floor, rel_tol=1e-9):
                return "0 (exact)"
            return mt.LogFormatterSciNotation()(x)

        ax.yaxis.set_major_locator(mt.FixedLocator([floor, *ticks]))
        ax.yaxis.set_major_formatter(mt.FuncFormatter(fmt))
    ax.set_ylabel(label)
    ax.grid(True, which="major")


def _cost_axis(ax, label: str, title: str, number_format: str) -> None:
    """A log-log panel of RMS relative error against a cost (samples, triangles), its legend at the lower left."""
    import matplotlib.ticker as mt

    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.xaxis.set_major_formatter(mt.FuncFormatter(lambda x, _: number_format.format(x)))
    ax.set_xlabel(label)
    ax.set_ylabel("RMS relative error")
    ax.set_title(title)
    ax.grid(True, which="major")
    ax.legend(loc="lower left")


def _label_points(ax, xs, ys, labels, colour, *, dx=6, dy=5, fontsize=10.5) -> None:
    """Small cost labels beside the points of one line (``labels`` may hold ``None`` to skip a point)."""
    import matplotlib.patheffects as pe

    halo = [pe.withStroke(linewidth=3, foreground="white")]  # readable where a line passes under the label
    for x, y, text in zip(xs, ys, labels, strict=True):
        if text is not None:
            ax.annotate(text, (x, y), textcoords="offset points", xytext=(dx, dy), fontsize=fontsize, color=colour,
                        path_effects=halo)  # fmt: skip


# --------------------------------------------------------------------------- integration
_METHOD_NAMES = {
    "quadrature": "quadrature",
    "uniform": "uniform MC",
    "cosine": "cosine-weighted MC",
    "importance": "BRDF importance MC",
    "stratified": "stratified MC",
    "environment": "environment sampling",
    "mis": "MIS (BRDF + environment)",
    "sh": "SH9 irradiance",
}


#: Why these figures may differ between runs (cleared when drawn from saved results: see ``reproducible``).
_MEASURED_TIMES = ("plots wall-clock times measured while drawing, which differ from run to run "
                   "(reproducible when drawn from report accuracy's saved results or --accuracy-csv)")


@register(
    "accuracy_integration",
    title="Hemisphere integration: error against run time",
    caption=(
        "Error against run time of the engine's hemisphere integration methods on four cases "
        "(lighting.validation.accuracy, the 'integration' study): Gauss–Legendre / lobe-centred quadrature, "
        "Monte Carlo with uniform, cosine-weighted, BRDF-importance and stratified samples, environment "
        "sampling and multiple importance sampling (radiance cases), and SH9 irradiance (Lambert). Each line is "
        "one method at increasing sample counts ({samples}); shaded bands are ± one standard deviation over "
        "seeds; dashed and dotted lines mark 1 % and 0.1 %; exact zeros sit on the '0' row. "
        + _SOURCE_CAPTION + " " + _TIMES
    ),
    slides="Accuracy report (lighting-explorer report accuracy): hemisphere integration",
    nondeterministic=_MEASURED_TIMES,
    size="16:9",
    csv=None,
)
def accuracy_integration(q, *, csv):
    """Error against run time of the hemisphere integration methods, one panel per case.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Resolution (the study's numbers do not depend on it).
    csv : str or None
        An ``accuracy.csv`` of ``lighting-explorer report accuracy``; ``None``: saved results, else the
        quick study measured now.

    Returns
    -------
    tuple
        ``(figure, measured)``: the figure and where its numbers came from (``source``,
        ``reproducible``, ``points``) with the sample counts.
    """
    points, source = study_points("integration", csv_path=csv)
    cases = list(dict.fromkeys(p.case for p in points))[:4]
    methods = list(dict.fromkeys(p.method for p in points))
    style = {m: (PALETTE[i % len(PALETTE)], "osD^vP*X"[i % 8]) for i, m in enumerate(methods)}
    fig = new_figure()
    rows = 1 if len(cases) <= 2 else 2
    cols = max(1, math.ceil(len(cases) / rows))
    axes = fig.subplots(rows, cols, squeeze=False)
    handles = {}
    for ax, case in zip(axes.flat, cases, strict=False):
        pts = [p for p in points if p.case == case]
        floor = _floor([p.error for p in pts])
        for m in dict.fromkeys(p.method for p in pts):
            mp = sorted((p for p in pts if p.method == m), key=lambda p: p.cost)
            t = np.array([p.seconds * 1e3 for p in mp])
            e = np.array([p.error if p.error > 0 else floor for p in mp])
            c, mk = style[m]
            (line,) = ax.plot(t, e, "-", marker=mk, ms=6, lw=1.8, color=c, clip_on=False)
            handles.setdefault(m, line)
            spread = np.array([p.error_spread for p in mp])
            if np.any(spread > 0):
                lo = np.maximum(np.maximum(e - spread, e / 10), floor)
                ax.fill_between(t, lo, e + spread, color=c, alpha=0.13, lw=0)
        _time_axis(ax, [p.seconds * 1e3 for p in pts])
        _error_axis(ax, [p.error for p in pts], floor)
        ax.set_title(case, fontsize=13)
    for ax in list(axes.flat)[len(cases):]:
        ax.axis("off")
    fig.legend([handles[m] for m in methods], [_METHOD_NAMES.get(m, m) for m in methods], loc="outside right center",
               fontsize=11.5, handlelength=2.2)  # fmt: skip
    samples = sorted({p.cost for p in points if p.method != "sh"})
    return fig, _measured(points, source, samples=", ".join(f"{n:,}" for n in samples), cases=len(cases))


# --------------------------------------------------------------------------- area light
@register(
    "accuracy_area_light",
    title="Area light: error against light samples and run time",
    caption=(
        "A Lambertian sphere lit by a rectangular area light, shaded with {counts} light samples per pixel "
        "(R2 low-discrepancy points on the rectangle), against {reference} (the 'area-light' study of "
        "lighting.validation.accuracy). Left: RMS relative error against the time of one image (numbers: "
        "samples per pixel). Right: the same errors against the sample count, with the slopes N^-1/2 of "
        "independent random samples and N^-1 for comparison; the measured slope (least squares, log-log) is "
        "{slope:.2f}. " + _SOURCE_CAPTION + " " + _TIMES
    ),
    slides="Accuracy report (lighting-explorer report accuracy): area lights",
    nondeterministic=_MEASURED_TIMES,
    size="16:9",
    csv=None,
)
def accuracy_area_light(q, *, csv):
    """Area-light error against run time and against the sample count.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Resolution (the study's numbers do not depend on it).
    csv : str or None
        An ``accuracy.csv``; ``None``: saved results, else the quick study measured now.

    Returns
    -------
    tuple
        ``(figure, measured)``; ``slope`` is the least-squares slope of log error against log samples.
    """
    points, source = study_points("area-light", csv_path=csv)
    pts = sorted(points, key=lambda p: p.cost)
    n = np.array([p.cost for p in pts], dtype=np.float64)
    e = np.array([max(p.error, 1e-300) for p in pts])
    t = np.array([p.seconds * 1e3 for p in pts])
    slope = float(np.polyfit(np.log(n), np.log(e), 1)[0]) if len(pts) > 1 else math.nan
    fig = new_figure()
    left, right = fig.subplots(1, 2)
    c = PALETTE[0]
    left.plot(t, e, "o-", color=c, ms=7)
    _label_points(left, t, e, [f"{int(k)}" for k in n], c)
    _time_axis(left, t, "time per image (ms)")
    _error_axis(left, e, label="RMS relative error")
    left.set_title(pts[0].case)
    right.plot(n, e, "o-", color=c, ms=7, label=f"measured (slope {slope:.2f})")
    for power, style, text in ((-0.5, "--", r"$\propto N^{-1/2}$"), (-1.0, ":", r"$\propto N^{-1}$")):
        right.plot(n, e[0] * (n / n[0]) ** power, style, color="0.35", lw=1.4, label=text)
    _cost_axis(right, "light samples per pixel", "Convergence with the sample count", "{:g}")
    reference = pts[0].reference.replace(" (RMS relative error)", "")
    return fig, _measured(points, source, counts=", ".join(str(int(k)) for k in n), reference=reference,
                          slope=slope)  # fmt: skip


# --------------------------------------------------------------------------- tessellation
_MODE_NAMES = {"flat": "flat (one normal per triangle)", "gouraud": "Gouraud (colours interpolated)",
               "phong": "Phong (normals interpolated)"}  # fmt: skip


@register(
    "accuracy_tessellation",
    title="Flat, Gouraud and Phong interpolation: error against tessellation and run time",
    caption=(
        "Icospheres of {triangles} triangles shaded flat, Gouraud and Phong, against the ray-cast analytic "
        "sphere under the same camera and lights (RMS relative error where n·v > 0.25, away from the "
        "silhouette; the 'tessellation' study of lighting.validation.accuracy). Left: error against the time "
        "of one image (numbers: triangles). Right: error against the triangle count. At the finest tessellation "
        "the errors are {finest_text}. " + _SOURCE_CAPTION + " " + _TIMES
    ),
    slides="CMSC 435: Flat, Gouraud and Phong shading; accuracy report (lighting-explorer report accuracy)",
    nondeterministic=_MEASURED_TIMES,
    size="16:9",
    csv=None,
)
def accuracy_tessellation(q, *, csv):
    """Flat / Gouraud / Phong error against run time and against the triangle count.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Resolution (the study's numbers do not depend on it).
    csv : str or None
        An ``accuracy.csv``; ``None``: saved results, else the quick study measured now.

    Returns
    -------
    tuple
        ``(figure, measured)``; ``finest`` maps each mode to its error at the finest tessellation.
    """
    points, source = study_points("tessellation", csv_path=csv)
    fig = new_figure()
    left, right = fig.subplots(1, 2)
    modes = list(dict.fromkeys(p.method for p in points))
    colours = {m: PALETTE[i % len(PALETTE)] for i, m in enumerate(modes)}
    finest = {}
    for i, m in enumerate(modes):
        mp = sorted((p for p in points if p.method == m), key=lambda p: p.cost)
        t = [p.seconds * 1e3 for p in mp]
        e = [p.error for p in mp]
        n = [p.cost for p in mp]
        mk = "osD^"[i % 4]
        left.plot(t, e, "-", marker=mk, ms=7, color=colours[m], label=_MODE_NAMES.get(m, m))
        if i == len(modes) - 1:  # one line's cost labels are enough: the costs are the same for every mode
            _label_points(left, t, e, [f"{k:,}" for k in n], colours[m], dx=7, dy=-14)
        right.plot(n, e, "-", marker=mk, ms=7, color=colours[m], label=_MODE_NAMES.get(m, m))
        finest[m] = e[-1]
    _time_axis(left, [p.seconds * 1e3 for p in points], "time per image (ms)")
    _error_axis(left, [p.error for p in points], label="RMS relative error")
    left.set_title("Error against run time")
    _cost_axis(right, "triangles", "Error against tessellation", "{:,.0f}")
    triangles = ", ".join(f"{k:,}" for k in sorted({p.cost for p in points}))
    finest_text = ", ".join(f"{m} {100 * e:.2g} %" for m, e in finest.items())
    return fig, _measured(points, source, triangles=triangles, finest=finest, finest_text=finest_text)


# --------------------------------------------------------------------------- precision
@register(
    "accuracy_precision",
    title="float32 against float64: re-shading time and error",
    caption=(
        "Re-shading the same geometry buffer ({pixels:,} pixels of a sphere of about 5,000 triangles under an "
        "ambient and three directional lights) in float64 and float32 (the 'precision' study of "
        "lighting.validation.accuracy). "
        "Left: the time of one re-shade; float32 takes {ratio:.2f}× the float64 time. Right: the largest "
        "error relative to the brightest pixel, against the float64 image: float32 costs {ulps:.1f} units of "
        "float32's rounding (2^-24 ≈ 6.0e-8), far below what an 8-bit display shows (1/255). "
        + _SOURCE_CAPTION + " " + _TIMES
    ),
    slides="Accuracy report (lighting-explorer report accuracy): precision",
    nondeterministic=_MEASURED_TIMES,
    size="16:9",
    csv=None,
)
def accuracy_precision(q, *, csv):
    """float32 against float64: re-shading time and largest relative error.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Resolution (the study's numbers do not depend on it).
    csv : str or None
        An ``accuracy.csv``; ``None``: saved results, else the quick study measured now.

    Returns
    -------
    tuple
        ``(figure, measured)``: ``ratio`` (float32 time / float64 time), ``ulps`` (float32's error in
        units of 2^-24), ``pixels``.
    """
    points, source = study_points("precision", csv_path=csv)
    by = {p.method: p for p in points}
    names = [m for m in ("float64", "float32") if m in by] + [m for m in by if m not in ("float64", "float32")]
    fig = new_figure()
    left, right = fig.subplots(1, 2)
    colours = [PALETTE[0], PALETTE[1], *PALETTE[2:]]
    x = np.arange(len(names))
    times = [by[m].seconds * 1e3 for m in names]
    bars = left.bar(x, times, color=colours[: len(names)], width=0.55)
    left.bar_label(bars, labels=[f"{t:.3g} ms" for t in times], padding=4, fontsize=12)
    left.set_xticks(x, names)
    left.set_ylabel("time per re-shade (ms)")
    left.set_ylim(0, max(times) * 1.2)
    left.set_title(f"Re-shading {by[names[0]].cost:,} pixels")
    eps32 = 2.0**-24
    errors = [by[m].error for m in names]
    nonzero = [i for i, e in enumerate(errors) if e > 0]
    bars = right.bar(x[nonzero], [errors[i] for i in nonzero], color=[colours[i] for i in nonzero], width=0.55)
    right.bar_label(bars, labels=[f"{errors[i]:.2g}" for i in nonzero], padding=4, fontsize=12)
    right.set_yscale("log")
    right.set_ylim(eps32 / 300, 1.0)
    for i, e in enumerate(errors):
        if e == 0:  # an exact zero has no place on a log axis: said in words at the foot of its column
            right.annotate("0: the reference", (x[i], eps32 / 300), xytext=(0, 8), textcoords="offset points",
                           ha="center", va="bottom", fontsize=12, color=colours[i])  # fmt: skip
    for value, text in ((eps32, "float32 rounding, 2⁻²⁴"), (1 / 255, "one 8-bit display step, 1/255")):
        right.axhline(value, color="0.4", ls="--", lw=1.0, zorder=0)
        right.annotate(text, (0.02, value), xycoords=("axes fraction", "data"), xytext=(0, 4),
                       textcoords="offset points", ha="left", fontsize=11, color="0.3")  # fmt: skip
    right.set_xticks(x, names)
    for ax in (left, right):
        ax.set_xlim(-0.6, len(names) - 0.4)
    right.set_ylabel("largest error / brightest pixel")
    right.set_title("Error against the float64 image")
    p32 = by.get("float32")
    p64 = by.get("float64")
    ratio = p32.seconds / p64.seconds if p32 and p64 and p64.seconds > 0 else math.nan
    ulps = p32.error / eps32 if p32 else math.nan
    return fig, _measured(points, source, ratio=ratio, ulps=ulps, pixels=by[names[0]].cost)


# --------------------------------------------------------------------------- image-based lighting
#: The models the ``accuracy_ibl`` figure draws as lines (those the study measured, in this order).
IBL_LINE_MODELS = ("Lambert", "Phong e=50", "GGX α=0.05, F=1", "GGX α=0.2, F=1", "GGX α=0.5, F=1")


def _model_heads(labels) -> tuple[list[str], list[int]]:
    """Column heads for the table of models: the family named over its first column only.

    Heads are drawn bottom-aligned above the table, so a family name on the top line of its first
    column may run over the neighbours' shorter heads without touching their text.  Returns the heads
    and the column indices where a new family starts.
    """
    heads, starts, last = [], [], None
    for i, label in enumerate(labels):
        family, _, rest = label.partition(" ")
        lines = [part for part in rest.replace(", ", " ").split(" ") if part]
        if family != last:
            starts.append(i)
            lines[:0] = family.replace("-", "-\n").split("\n")  # "Blinn-Phong" is wider than a column
        heads.append("\n".join(lines) if lines else family)
        last = family
    return heads, starts


@register(
    "accuracy_ibl",
    title="Image-based lighting: error against run time, and the split sum's error by model",
    caption=(
        "The 'ibl' study of lighting.validation.accuracy: a sphere under the environments {skies_text} "
        "({models} models; "
        "errors are medians over the lit pixels against a Monte-Carlo reference of {ref_spp} samples per pixel). "
        "Top, one panel per environment: Monte Carlo with multiple importance sampling at {spp_text} samples "
        "per pixel (lines; numbers: samples per pixel), the split sum (stars) and the dominant lights with "
        "filtered importance sampling, the default (diamonds; hollow markers where the reference is too noisy to "
        "measure them) and SH9 irradiance against the exact irradiance of the map (square), for "
        "{line_models}. Bottom: the split sum's median error for every model of the study and every "
        "environment. Times are for {timed} (the split sum, the dominant lights and SH9 in float32). "
        + _SOURCE_CAPTION + " " + _TIMES
    ),
    slides="Beyond the slides: image-based lighting (Ramamoorthi & Hanrahan 2001; Karis 2013)",
    nondeterministic=_MEASURED_TIMES,
    size="16:9",
    csv=None,
)
def accuracy_ibl(q, *, csv):
    """Image-based lighting: error against time per environment, and the split sum's error per model.

    The study crosses every model with every environment (16 × 3 in the full settings); the figure
    draws lines for the models of :data:`IBL_LINE_MODELS` it finds, one panel per environment, and
    the split sum of every model in a table below.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Resolution (the study's numbers do not depend on it).
    csv : str or None
        An ``accuracy.csv``; ``None``: saved results, else the quick study measured now.

    Returns
    -------
    tuple
        ``(figure, measured)``: ``split_sum`` (environment -> model -> median error), ``sh9``
        (environment -> error), the counts of models and environments.
    """
    import matplotlib.colors as mc
    import matplotlib.ticker as mt

    points, source = study_points("ibl", csv_path=csv)
    envs, models = [], []
    for p in points:
        model, _, env = p.case.rpartition(" · ")
        if env not in envs:
            envs.append(env)
        if p.method != "SH9 irradiance" and model not in models:
            models.append(model)
    lines = [m for m in IBL_LINE_MODELS if m in models] or models[:3]
    colours = dict(zip(lines, series_colours(len(lines), "viridis", 0.85), strict=True))
    fig = new_figure()
    # The top row: one panel per environment and a last column for the legend; the table spans the width.
    grid = fig.add_gridspec(2, len(envs) + 1, height_ratios=[2.1, 1.0], width_ratios=[1.0] * len(envs) + [0.8])
    split, dominant, sh9, handles = {}, {}, {}, {}
    spp_all = sorted({p.cost for p in points if p.method == "Monte Carlo, MIS"})
    drawn = [p for p in points if p.method == "SH9 irradiance" or p.case.rpartition(" · ")[0] in lines]
    share = None
    for j, env in enumerate(envs):
        ax = fig.add_subplot(grid[0, j], sharey=share)
        share = share or ax
        pts = [p for p in points if p.case.endswith(" · " + env)]
        shown = []
        for m in lines:
            mp = [p for p in pts if p.case == f"{m} · {env}"]
            mc_pts = sorted((p for p in mp if p.method == "Monte Carlo, MIS"), key=lambda p: p.cost)
            t = [p.seconds * 1e3 for p in mc_pts]
            e = [p.error for p in mc_pts]
            (h,) = ax.plot(t, e, "o-", color=colours[m], ms=5, lw=1.8)
            handles.setdefault(m, h)
            if m == lines[-1]:  # the sample counts once: the same for every model
                _label_points(ax, t, e, [str(p.cost) for p in mc_pts], "0.2", dx=5, dy=6)
            ss = next(p for p in mp if p.method == "split sum")
            noisy = ss.reference_error > ss.error
            ax.plot(ss.seconds * 1e3, ss.error, "*", ms=15, color=colours[m], mec=colours[m] if noisy else "k",
                    mfc="none" if noisy else colours[m], mew=1.0)  # fmt: skip
            dm = next((p for p in mp if p.method == "dominant lights"), None)
            if dm is not None:
                noisy = dm.reference_error > dm.error
                ax.plot(dm.seconds * 1e3, dm.error, "D", ms=8, color=colours[m], mec=colours[m] if noisy else "k",
                        mfc="none" if noisy else colours[m], mew=1.0)  # fmt: skip
            shown += [*mp]
        sh = next((p for p in pts if p.method == "SH9 irradiance"), None)
        if sh is not None:
            ax.plot(sh.seconds * 1e3, sh.error, "s", ms=9, color=PALETTE[1], mec="k")
            sh9[env] = sh.error
            shown.append(sh)
        _time_axis(ax, [p.seconds * 1e3 for p in shown], "time (ms)")
        # Every panel gets the limits of all of them (they share the error axis).
        _error_axis(ax, [p.error for p in drawn], label="median relative error" if j == 0 else "")
        ax.set_title(env)
        split[env] = {p.case.rpartition(" · ")[0]: p.error for p in pts if p.method == "split sum"}
        dominant[env] = {p.case.rpartition(" · ")[0]: p.error for p in pts if p.method == "dominant lights"}
    # The legend of the top row: models by colour, then what the marker shapes mean.
    from matplotlib.lines import Line2D

    keys = [handles[m] for m in lines] + [
        Line2D([], [], ls="none", marker="*", ms=13, color="0.4", mec="k"),
        Line2D([], [], ls="none", marker="D", ms=7, color="0.4", mec="k"),
        Line2D([], [], ls="none", marker="s", ms=8, color=PALETTE[1], mec="k"),
    ]
    names = [f"{m}: Monte Carlo" for m in lines] + ["split sum (hollow: the\nreference cannot tell)",
                                                      "dominant lights (default)", "SH9 irradiance"]
    key = fig.add_subplot(grid[0, -1])
    key.axis("off")
    key.legend(keys, names, loc="center left", fontsize=11, borderaxespad=0.0)
    # The bottom row: the split sum's error, every model × every environment, as a table of colours and numbers.
    tab = fig.add_subplot(grid[1, :])
    values = np.array([[split[env].get(m, np.nan) for m in models] for env in envs])
    norm = mc.LogNorm(1e-3, 0.3)
    tab.imshow(np.ma.masked_invalid(values), cmap="YlOrRd", norm=norm, aspect="auto", interpolation="nearest")
    for (i, j), v in np.ndenumerate(values):
        if np.isfinite(v):
            text = f"{100 * v:.1f} %" if v < 0.1 else f"{100 * v:.0f} %"
            tab.text(j, i, text, ha="center", va="center", fontsize=10.5 if len(models) > 8 else 12,
                     color="white" if norm(v) > 0.72 else "black")  # fmt: skip
    heads, starts = _model_heads(models)
    tab.set_xticks(np.arange(len(models)), heads, fontsize=10 if len(models) > 8 else 11.5)
    for j in starts[1:]:  # a white gap between model families
        tab.axvline(j - 0.5, color="white", lw=4)
    tab.xaxis.tick_top()
    tab.set_yticks(np.arange(len(envs)), envs)
    tab.tick_params(length=0)
    tab.xaxis.set_minor_locator(mt.NullLocator())
    for s in tab.spines.values():
        s.set_visible(False)
    tab.set_xlabel("split sum: median relative error per model (columns) and environment (rows)")
    ref_spp = sorted({int(p.reference.split(" spp")[0].rsplit(" ", 1)[-1]) for p in points
                      if p.reference.startswith("Monte Carlo")})  # fmt: skip
    timed = next((p.reference.split("(times: ")[-1].rstrip(")").removesuffix(", float32") for p in points
                  if "(times: " in p.reference), "the study's pixels")  # fmt: skip
    quoted = [f"'{e}'" for e in envs]
    skies_text = quoted[0] if len(quoted) == 1 else ", ".join(quoted[:-1]) + " and " + quoted[-1]
    return fig, _measured(
        points, source,
        skies_text=skies_text, models=len(models), environments=len(envs),
        ref_spp=", ".join(f"{r:,}" for r in ref_spp), spp_text=", ".join(str(s) for s in spp_all),
        line_models=", ".join(lines), timed=timed, split_sum=split, dominant=dominant, sh9=sh9,
        table=ibl_table(points), exact_table=ibl_exact_table(points),
    )  # fmt: skip


def ibl_exact_table(points) -> str:
    """The fast methods against the pixel sum (the ``ibl`` study's ``· pixel sum`` points) as a Markdown table.

    Parameters
    ----------
    points : list of Point
        The study's points; the full settings judge four models on part of the pixels by the pixel sum.

    Returns
    -------
    str
        One row per model, one column per environment; each cell ``split sum → dominant lights``, median relative
        error over the lit pixels and, in brackets, its 95th percentile; below, the largest of the pixel sum's own
        median relative errors and what they were measured on.  A sentence saying so where the study has no such
        points (the quick settings).

    Examples
    --------
    >>> from lighting.validation.accuracy import Point
    >>> methods = (("split sum · pixel sum", 0.05), ("dominant lights · pixel sum", 0.01))
    >>> pts = [Point("ibl", "Lambert · sky", m, 1, "", e, 0.0, 1e-3, "the pixel sum", error_p95=2 * e,
    ...              reference_error=1e-5) for m, e in methods]
    >>> print(ibl_exact_table(pts))
    | model | sky |
    |---|---|
    | Lambert | 5 % (10 %) → 1 % (2 %) |
    <BLANKLINE>
    Reference: the pixel sum; its own median relative error: at most 0.001 %.
    """
    from lighting.validation.accuracy import PIXEL_SUM_SUFFIX

    exact = [replace(p, method=p.method.removesuffix(PIXEL_SUM_SUFFIX)) for p in points
             if p.method.endswith(PIXEL_SUM_SUFFIX)]  # fmt: skip
    if not exact:
        return ("*(The quick study judges no method against the pixel sum: `lighting-explorer report accuracy "
                "--only ibl` does.)*")  # fmt: skip
    own = max(p.reference_error for p in exact)
    return (ibl_table(exact) + f"\n\nReference: {exact[0].reference}; its own median relative error: at most "
            f"{100 * own:.2g} %.")  # fmt: skip


#: The fast methods of the ``ibl`` tables, in the order of each cell.
_TABLE_METHODS = ("split sum", "dominant lights", GRID_METHOD)


def ibl_table(points) -> str:
    """The ``ibl`` study's fast methods as a Markdown table: per model and environment, median (95th percentile).

    Parameters
    ----------
    points : list of Point
        The study's points (any settings).

    Returns
    -------
    str
        One row per model, one column per environment; each cell ``split sum → dominant lights → dominant lights,
        normal grid`` (those the study measured), each as the median relative error over the lit pixels and, in
        brackets, its 95th percentile; the first row is SH9
        irradiance against the exact irradiance of the map.  A value the reference is too noisy to resolve
        (its own median error above it) is marked ``*``.

    Examples
    --------
    >>> from lighting.validation.accuracy import Point
    >>> pts = [Point("ibl", "Lambert · sky", m, 1, "", e, 0.0, 1e-3, "", error_p95=2 * e, reference_error=0.001)
    ...        for m, e in (("split sum", 0.05), ("dominant lights", 0.01))]
    >>> print(ibl_table(pts))
    | model | sky |
    |---|---|
    | Lambert | 5 % (10 %) → 1 % (2 %) |
    """
    def pct(p):
        star = "*" if p.reference_error > p.error else ""
        return f"{100 * p.error:.2g} %{star} ({100 * p.error_p95:.2g} %)"

    envs, models, cells = [], [], {}
    for p in points:
        model, _, env = p.case.rpartition(" · ")
        if p.method == "SH9 irradiance":
            model = "SH9 irradiance"
        elif p.method not in _TABLE_METHODS:
            continue
        envs += [env] if env not in envs else []
        models += [model] if model not in models else []
        cells.setdefault((model, env), {})[p.method] = p
    rows = [f"| model | {' | '.join(envs)} |", "|---" * (len(envs) + 1) + "|"]
    for model in models:
        out = []
        for env in envs:
            c = cells.get((model, env), {})
            if "SH9 irradiance" in c:
                out.append(pct(c["SH9 irradiance"]))
            else:
                out.append(" → ".join(pct(c[m]) for m in _TABLE_METHODS if m in c))
        rows.append(f"| {model} | {' | '.join(out)} |")
    return "\n".join(rows)

"""Error against run time: every place where the engine trades accuracy for speed.

The engine reports error against run time for each of these trade-offs.  Each
*study* measures, in one run on one machine, the error of a method against a
trusted reference and its wall time at increasing cost:

* **hemisphere integration** — quadrature, uniform / cosine / importance /
  stratified Monte Carlo, environment and multiple importance sampling, and the
  9-coefficient SH irradiance, on BRDF × environment cases with closed-form or
  converged references;
* **area lights** by sample count (a Lambertian sphere under a rectangular
  light, against a 16,384-sample image; 4,096 in the quick settings);
* **Gouraud vs Phong interpolation** (and flat) by tessellation level, against
  the ray-cast analytic sphere;
* **float32 vs float64** re-shading of the same geometry buffer;
* **image-based lighting** (``ibl``): SH9 irradiance against the exact irradiance of the pixelized
  environment, and the split sum (:func:`lighting.integrate.ibl.split_sum_radiance`), the dominant
  lights with filtered importance sampling (:func:`lighting.integrate.dominant.dominant_radiance`) and
  Monte Carlo with MIS at increasing samples per pixel against a Monte-Carlo reference — and, for four
  materials, the first two against the pixel sum (:mod:`lighting.integrate.pixelsum`) — per model and
  roughness on a sphere under five environments (:mod:`lighting.validation.ibl_study`).

Times are medians of repeated runs; errors of stochastic methods are averaged
over seeds and reported with their spread.  The reference of every case is
stated in its ``reference`` field.  :func:`summary` answers "which is the
cheapest method that reaches 1 % (0.1 %) error, and how long does it take".

Every integration point also records what the method *says* about itself: its
own error estimate (:class:`lighting.integrate.Estimate`, relative to the
value, mean over seeds) in ``estimated_error``; ``coverage``, the fraction of
seeds whose true error lies within two reported errors (the honesty contract
of :mod:`lighting.integrate.estimate`: at least 90 %); and ``unconverged``, True when
the estimated relative error is above 2 %
(:data:`lighting.integrate.UNCONVERGED_RELATIVE_ERROR`).  Studies whose
methods carry no error estimate (area light, tessellation, precision) leave
``estimated_error`` and ``coverage`` as NaN and flag ``unconverged`` from the
measured error against the reference.
"""

from __future__ import annotations

import math
import statistics
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .._text import quote
from .._validate import ArgumentTypeError, check_bool, real_array
from ..lights import AmbientLight, DirectionalLight, PointLight, RectLight
from ..lights.environment import FunctionEnvironment
from ..models.brdf import BlinnPhong, CookTorrance, Lambert, Phong
from ..render.camera import Camera
from ..render.mesh import icosphere
from ..render.renderer import AnalyticSphere, Renderer
from ..shading.equation import Material

__all__ = ["Point", "Study", "run_studies", "summary", "study_settings", "STUDY_NAMES", "STUDY_SETTINGS"]

STUDY_NAMES = ("integration", "area-light", "tessellation", "precision", "ibl")


@dataclass
class Point:
    """One measured (cost, error, time) point of one method on one case."""

    study: str
    case: str
    method: str
    cost: int  # samples, sample count, triangles, or pixels
    cost_unit: str
    error: float  # relative error (mean over seeds for stochastic methods)
    error_spread: float  # standard deviation over seeds (0 for deterministic methods)
    seconds: float  # median wall time of one evaluation
    reference: str
    estimated_error: float = math.nan  # the method's own relative error estimate (mean over seeds)
    coverage: float = math.nan  # fraction of seeds whose true error is within two reported errors
    unconverged: bool = False  # estimated (else measured) relative error above 2 %
    error_p95: float = math.nan  # 95th percentile of per-pixel relative errors (image studies: ibl)
    reference_error: float = math.nan  # the reference's own relative error (median over pixels; ibl)

    def __post_init__(self):
        from ..integrate import UNCONVERGED_RELATIVE_ERROR  # here: the command tree imports STUDY_NAMES cheaply

        if not self.unconverged:
            own = self.estimated_error if not math.isnan(self.estimated_error) else self.error
            self.unconverged = bool(own > UNCONVERGED_RELATIVE_ERROR)
        if not math.isnan(self.reference_error) and self.reference_error > self.error:
            self.unconverged = True  # the reference is too noisy to measure this error


@dataclass
class Study:
    name: str
    description: str
    points: list = field(default_factory=list)


def _median_time(fn: Callable, repeat: int):
    out = None
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return out, statistics.median(times)


def _rel(value, ref) -> float:
    value, ref = np.asarray(value, dtype=np.float64), np.asarray(ref, dtype=np.float64)
    return float(np.max(np.abs(value - ref)) / np.max(np.abs(ref)))


# ---------------------------------------------------------------------- integration
def _glow_sky(direction):
    """A smooth sky: a uniform floor plus a broad glow around a sun direction (radiance, RGB); the engine's ``glow``."""
    from ..lights.skies import SKIES

    return SKIES["glow"](direction)


INTEGRATION_CASES = {
    # name: (kind, model, extra, methods, reference description)
    "Lambert, glowing sky": (
        "radiance",
        Lambert(0.8),
        "sh",
        "Gauss–Legendre quadrature with {nodes:,} nodes (262,144 and 65,536 nodes agree to 1e-12)",
    ),
    "Lambert + Blinn-Phong e=200, glowing sky": (
        "radiance",
        Lambert(0.2) + BlinnPhong(1.0, 200.0, normalized=True),
        None,
        "Gauss–Legendre quadrature with {nodes:,} nodes (262,144 and 65,536 nodes agree to 1e-10)",
    ),
    "GGX/Smith α=0.1 albedo at θ_v = 60°": (
        "albedo",
        CookTorrance(1.0, 0.1, 1.0, ndf="ggx", geometry="smith", fresnel="none"),
        None,
        "lobe-centred quadrature with {nodes:,} nodes (262,144 and 65,536 nodes agree to 1e-13)",
    ),
    "slides' Phong e=1 albedo at θ_v = 0": (
        "albedo0",
        Phong(1.0, 1.0),
        None,
        "closed form 2 k_s/(e + 1) = 1",
    ),
}

_NORMAL = np.array([0.0, 0.0, 1.0])
_VIEW = np.array([0.45, 0.0, 0.89])


def _integration_points(samples_list, seeds, repeat, progress, reference_nodes=262144):
    from ..integrate import directional_albedo, outgoing_radiance

    env = FunctionEnvironment(_glow_sky)
    points = []
    for case, (kind, model, extra, ref_text) in INTEGRATION_CASES.items():
        methods = ["quadrature", "uniform", "cosine", "importance", "stratified"]
        if kind == "radiance":
            methods += ["environment", "mis"]
        if extra == "sh":
            methods.append("sh")

        def evaluate(method, samples, seed, kind=kind, model=model, return_error=False):
            if kind == "radiance":
                return outgoing_radiance(model, env, _NORMAL, _VIEW, method=method, samples=samples, seed=seed,
                                         return_error=return_error)  # fmt: skip
            theta = math.radians(60.0) if kind == "albedo" else 0.0
            return directional_albedo(model, theta, samples=samples, method=method, seed=seed,
                                      return_error=return_error)  # fmt: skip

        if kind == "albedo0":
            reference = np.full(3, 1.0)
        else:
            reference = np.asarray(evaluate("quadrature", reference_nodes, None))
        ref_text = ref_text.format(nodes=reference_nodes)
        for method in methods:
            counts = [4096] if method == "sh" else samples_list
            for n in counts:
                stochastic = method not in ("quadrature", "sh")
                errs, times, own, covered = [], [], [], []
                for seed in seeds if stochastic else [None]:
                    value, t = _median_time(lambda s=seed, n=n, m=method: evaluate(m, n, s), repeat)
                    errs.append(_rel(value, reference))
                    times.append(t)
                    # The same draws again (same seed), untimed, with the method's own error estimate.
                    est = evaluate(method, n, seed, return_error=True)
                    scale = float(np.max(np.abs(reference)))
                    own.append(float(np.max(est.error)) / scale)
                    true = np.abs(np.asarray(est.value, dtype=np.float64) - reference)
                    covered.append(bool(np.all(true <= 2 * np.asarray(est.error, dtype=np.float64))))
                    progress()
                points.append(
                    Point(
                        "integration",
                        case,
                        method,
                        n,
                        "samples",
                        float(np.mean(errs)),
                        float(np.std(errs)) if len(errs) > 1 else 0.0,
                        float(statistics.median(times)),
                        ref_text,
                        float(np.mean(own)),
                        float(np.mean(covered)),
                    )  # fmt: skip
                )
    return points


def _integration_work(samples_list, seeds):
    total = 0
    for kind, _model, extra, _ref in INTEGRATION_CASES.values():
        methods = 5 + (2 if kind == "radiance" else 0)
        total += methods * len(samples_list) * len(seeds) - len(samples_list) * (len(seeds) - 1)
        if extra == "sh":
            total += 1
    return total


# ---------------------------------------------------------------------- area light
def _area_points(counts, size, repeat, progress, reference_samples=16384):
    cam = Camera((0, 0, 6.0), (0, 0, 0), fov_y_deg=24.0, width=size, height=size)
    r = Renderer(AnalyticSphere(), cam)
    mat = Material(Lambert(0.8))

    def light(samples):
        return [RectLight((1.5, 2.0, 2.5), (1.2, 0, 0), (0, -0.6, 0.6), intensity=6.0, samples=samples)]

    ref = r.render(mat, light(reference_samples))
    cov = r.gbuffer.coverage
    scale = float(np.sqrt(np.mean(ref[cov] ** 2)))
    ref_text = f"the same image with {reference_samples:,} light samples (RMS relative error)"
    points = []
    for n in counts:
        img, t = _median_time(lambda n=n: r.render(mat, light(n)), repeat)
        err = float(np.sqrt(np.mean((img[cov] - ref[cov]) ** 2)) / scale)
        points.append(
            Point("area-light", "Lambert sphere, rectangular light", "R2 low-discrepancy samples", n,
                  "samples", err, 0.0, t, ref_text)
        )  # fmt: skip
        progress()
    return points


# ---------------------------------------------------------------------- tessellation
def _tessellation_points(levels, size, repeat, progress):
    cam = Camera((0, 0, 6.0), (0, 0, 0), fov_y_deg=22.0, width=size, height=size)
    mat = Material(Lambert((0.7, 0.25, 0.2)) + BlinnPhong(0.5, 40.0))
    lights = [AmbientLight(intensity=0.05), DirectionalLight((-1, 1, 1.5)), PointLight((3, 2, 4.0), intensity=20.0)]
    exact = Renderer(AnalyticSphere(), cam)
    ref = exact.render(mat, lights)
    Renderer(icosphere(0), cam).render(mat, lights, mode="flat")  # first-call costs out of the timings
    # Compare away from the silhouette (n·v > 0.25 on the true sphere), where a polygon's outline
    # differs from the circle by whole pixels and no shading mode can help.
    gb = exact.gbuffer
    interior = gb.coverage & (np.sum(gb.normal * gb.view_direction(), axis=-1) > 0.25)
    points = []
    for level in levels:
        mesh = icosphere(level)
        for mode in ("flat", "gouraud", "phong"):
            img, t = _median_time(lambda mesh=mesh, mode=mode: Renderer(mesh, cam).render(mat, lights, mode=mode),
                                  repeat)  # fmt: skip
            both = exact.gbuffer.coverage & Renderer(mesh, cam).gbuffer.coverage & interior
            scale = float(np.sqrt(np.mean(ref[both] ** 2)))
            err = float(np.sqrt(np.mean((img[both] - ref[both]) ** 2)) / scale)
            points.append(
                Point("tessellation", "icosphere vs analytic sphere", mode, mesh.n_triangles, "triangles", err,
                      0.0, t, "ray-cast analytic sphere, same camera and lights (RMS relative error where n·v > 0.25)")
            )  # fmt: skip
            progress()
    return points


# ---------------------------------------------------------------------- precision
def _precision_points(size, repeat, progress):
    from ..render.mesh import sphere_for_triangles

    cam = Camera((0, 0, 6.0), (0, 0, 0), fov_y_deg=22.0, width=size, height=size)
    mesh = sphere_for_triangles(5000)
    mat = Material(Lambert((0.7, 0.25, 0.2)) + BlinnPhong(0.5, 40.0))
    lights = [AmbientLight(intensity=0.05), DirectionalLight((-1, 1, 1.5)), DirectionalLight((1, 0.3, 0.8)),
              DirectionalLight((0, -1, 0.6), color=0.3)]  # fmt: skip
    r64 = Renderer(mesh, cam, dtype=np.float64)
    r32 = Renderer(mesh, cam, dtype=np.float32)
    ref = r64.render(mat, lights)
    cov = r64.gbuffer.coverage
    points = []
    for name, r in (("float64", r64), ("float32", r32)):
        r.render(mat, lights)  # warm the cached buffer: this measures re-shading
        img, t = _median_time(lambda r=r: r.render(mat, lights), repeat)
        err = float(np.max(np.abs(img[cov].astype(np.float64) - ref[cov])) / np.max(ref[cov]))
        points.append(
            Point("precision", f"re-shading {size}x{size}, float32 vs 64", name, int(cov.sum()),
                  "pixels", err, 0.0, t, "the float64 image (largest error relative to the brightest pixel)")
        )  # fmt: skip
        progress()
    return points


# ---------------------------------------------------------------------- image-based lighting
from .ibl_study import (  # noqa: E402, F401  (the ibl study's names, where the studies' users read them)
    GRID_METHOD,
    IBL_ENVIRONMENTS,
    IBL_EXACT_MODELS,
    IBL_EXACT_RTOL,
    IBL_LIT_FRACTION,
    IBL_SUN,
    IBL_VIEW_ROTATION,
    PIXEL_SUM_SUFFIX,
    _ibl_points,
    _ibl_work,
    _progressive,
    ibl_environment,
    ibl_front_pixels,
    ibl_models,
    ibl_pixel_errors,
    ibl_sphere,
    sun_gradient_image,
)


# ---------------------------------------------------------------------- driver
def _settings(quick: bool):
    # The quick settings keep every study's shape (the same methods, and costs spanning enough decades
    # for the laws the tests check) at a fraction of the work: the references, the dominant cost, are
    # smaller but still far more accurate than the cheapest method they judge.
    if quick:
        return {
            "samples": [16, 64, 256, 1024],
            "seeds": [0, 1],
            "repeat": 3,
            "integration_reference": 65536,
            "area_counts": [1, 4, 16, 64, 256],
            "area_size": 48,
            "area_reference": 4096,
            "levels": [0, 1, 2, 3],
            "tess_size": 96,
            "precision_size": 128,
            "ibl_size": 32,
            "ibl_pixels": 512,
            "ibl_env_height": 128,
            "ibl_irradiance_height": 16,
            "ibl_reference_spp": 512,
            "ibl_spp": [8, 32, 128],
            "ibl_exact_pixels": 0,
            "ibl_models": ibl_models(quick=True),
            "ibl_environments": dict(list(IBL_ENVIRONMENTS.items())[:2]),
        }
    return {
        "samples": [16, 64, 256, 1024, 4096, 16384],
        "seeds": [0, 1, 2, 3, 4],
        "repeat": 5,
        "integration_reference": 262144,
        "area_counts": [1, 4, 16, 64, 256, 1024, 4096],
        "area_size": 128,
        "area_reference": 16384,
        "levels": [0, 1, 2, 3, 4, 5],
        "tess_size": 256,
        "precision_size": 512,
        "ibl_size": 128,
        "ibl_pixels": 1024,
        "ibl_env_height": 256,
        "ibl_irradiance_height": 64,
        "ibl_reference_spp": 8192,
        "ibl_spp": [8, 32, 128, 512],
        "ibl_exact_pixels": 256,
        "ibl_models": ibl_models(),
        "ibl_environments": dict(IBL_ENVIRONMENTS),
    }


#: The settings (keys of the full or quick configuration) each study reads.
STUDY_SETTINGS = {
    "integration": ("samples", "seeds", "repeat", "integration_reference"),
    "area-light": ("area_counts", "area_size", "area_reference", "repeat"),
    "tessellation": ("levels", "tess_size", "repeat"),
    "precision": ("precision_size", "repeat"),
    "ibl": ("ibl_size", "ibl_pixels", "repeat", "ibl_env_height", "ibl_irradiance_height", "ibl_reference_spp",
            "ibl_spp", "ibl_exact_pixels", "ibl_models", "ibl_environments"),
}  # fmt: skip


def study_settings(name: str, quick: bool = False) -> dict:
    """The settings one study runs with, as plain JSON-ready values (models by label and ``repr``).

    Two runs of a study with equal settings (and the same engine source) measure the same thing: this
    is what a saved result is keyed by (:mod:`explorer.reports.cache`).

    Parameters
    ----------
    name : str
        A study of :data:`STUDY_NAMES`.
    quick : bool, optional
        The quick settings instead of the full ones.

    Returns
    -------
    dict
        Setting name -> value (numbers, strings, lists), in :data:`STUDY_SETTINGS` order.

    Raises
    ------
    ValueError
        For an unknown study name.

    Examples
    --------
    >>> study_settings("precision", quick=True)
    {'precision_size': 128, 'repeat': 3}
    >>> study_settings(["precision"])
    Traceback (most recent call last):
    ...
    ValueError: study must be one of integration, area-light, tessellation, precision, ibl; got ['precision']
    """
    quick = check_bool("quick", quick)
    if not isinstance(name, str) or name not in STUDY_SETTINGS:
        raise ValueError(f"study must be one of {', '.join(STUDY_NAMES)}; got {quote(name)}")
    cfg = _settings(quick)
    out = {}
    for key in STUDY_SETTINGS[name]:
        value = cfg[key]
        if key == "ibl_models":
            value = [[label, repr(model)] for label, model in value]
        elif isinstance(value, dict):
            value = [[k, v] for k, v in value.items()]
        out[key] = value
    return out


def run_studies(*, quick: bool = False, only=None, progress_factory=None) -> list[Study]:
    """Run the studies (all, or those named in ``only``) and return their points.

    ``progress_factory(total, label)`` may return an object with ``update()``
    (a progress bar); it is called once per study.

    Parameters
    ----------
    quick : bool, optional
        The quick settings (fewer samples, seeds, sizes and repeats) instead of the full ones.
    only : str or iterable of str, optional
        Study names from :data:`STUDY_NAMES`; ``None`` (default): all of them.
    progress_factory : callable or None, optional
        ``progress_factory(total, label)`` returning an object with ``update()``, called once per unit
        of work; ``None`` (default): no progress display.

    Returns
    -------
    list of Study
        The studies run, in the order of :data:`STUDY_NAMES`, each holding its measured points (:class:`Point`).

    Raises
    ------
    ValueError
        For an unknown study name (``ArgumentTypeError`` for arguments of the wrong type).
    """
    quick = check_bool("quick", quick)
    if progress_factory is not None and not callable(progress_factory):
        raise ArgumentTypeError(
            f"progress_factory must be None or a callable (total, label); got {type(progress_factory).__name__} "
            f"{quote(progress_factory)}"
        )
    cfg = _settings(quick)
    if only is None:
        names = STUDY_NAMES
    elif isinstance(only, str):
        names = (only,)
    elif hasattr(only, "__iter__") and not isinstance(only, bytes):
        names = tuple(only)
    else:
        raise ArgumentTypeError(f"only must be None or study names; got {type(only).__name__} {quote(only)}")
    for n in names:
        if not isinstance(n, str):
            raise ArgumentTypeError(f"only must hold study names ({', '.join(STUDY_NAMES)}); got {quote(n)}")
        if n not in STUDY_NAMES:
            raise ValueError(f"study must be one of {', '.join(STUDY_NAMES)}; got {quote(n)}")

    def bar(total, label):
        if progress_factory is None:
            return lambda: None
        p = progress_factory(total, label)
        return p.update

    studies = []
    if "integration" in names:
        tick = bar(_integration_work(cfg["samples"], cfg["seeds"]), "hemisphere integration")
        pts = _integration_points(cfg["samples"], cfg["seeds"], cfg["repeat"], tick, cfg["integration_reference"])
        studies.append(Study("integration", "Hemisphere integration methods", pts))
    if "area-light" in names:
        tick = bar(len(cfg["area_counts"]), "area light samples")
        pts = _area_points(cfg["area_counts"], cfg["area_size"], cfg["repeat"], tick, cfg["area_reference"])
        studies.append(Study("area-light", "Area light by sample count", pts))
    if "tessellation" in names:
        tick = bar(3 * len(cfg["levels"]), "tessellation")
        pts = _tessellation_points(cfg["levels"], cfg["tess_size"], cfg["repeat"], tick)
        studies.append(Study("tessellation", "Flat / Gouraud / Phong interpolation by tessellation", pts))
    if "precision" in names:
        tick = bar(2, "float32 vs float64")
        pts = _precision_points(cfg["precision_size"], max(cfg["repeat"], 3), tick)
        studies.append(Study("precision", "float32 vs float64 re-shading", pts))
    if "ibl" in names:
        tick = bar(_ibl_work(cfg), "image-based lighting")
        pts = _ibl_points(cfg, tick)
        studies.append(
            Study(
                "ibl",
                "Image-based lighting: SH9 and the split sum against exact and Monte-Carlo "
                "references (median relative error over the lit pixels)",
                pts,
            )
        )
    return studies


def summary(studies, thresholds=(1e-2, 1e-3)) -> list[dict]:
    """Per case: the cheapest (fastest) method and cost that reach each error threshold.

    Returns rows ``{"study", "case", "threshold", "method", "cost", "cost_unit",
    "error", "seconds"}``; ``method`` is ``None`` where nothing measured reached it.
    Each row also carries ``unconverged``: the chosen point's flag (its own
    relative error estimate above 2 %), so a method that reached the threshold
    without being able to tell is marked.

    Parameters
    ----------
    studies : iterable of Study
        As :func:`run_studies` returns them.
    thresholds : sequence of float, optional
        Relative errors > 0 to reach, a nonempty 1-D list (default 1 % and 0.1 %).

    Returns
    -------
    list of dict
        One row per study, case (in order of first appearance) and threshold, with the keys above.
    """
    allowed = "error thresholds, finite numbers > 0"
    thr_arr = real_array("thresholds", thresholds, allowed=allowed, dtype=np.float64)
    if thr_arr.ndim != 1 or thr_arr.size == 0 or np.any(thr_arr <= 0):
        raise ValueError(f"thresholds must be {allowed}, a nonempty 1-D list; got {quote(thresholds)}")
    thresholds = thr_arr.tolist()
    if isinstance(studies, Study) or not hasattr(studies, "__iter__"):
        raise ArgumentTypeError(f"studies must be a list of Study (from run_studies); got {quote(studies)}")
    studies = list(studies)
    if not all(isinstance(st, Study) for st in studies):
        raise ArgumentTypeError(f"studies must be a list of Study (from run_studies); got {quote(studies)}")
    rows = []
    for st in studies:
        cases = sorted({p.case for p in st.points}, key=[p.case for p in st.points].index)
        for case in cases:
            pts = [p for p in st.points if p.case == case]
            for thr in thresholds:
                ok = [p for p in pts if p.error <= thr]
                best = min(ok, key=lambda p: p.seconds) if ok else None
                rows.append(
                    {
                        "study": st.name,
                        "case": case,
                        "threshold": thr,
                        "method": best.method if best else None,
                        "cost": best.cost if best else None,
                        "cost_unit": best.cost_unit if best else pts[0].cost_unit,
                        "error": best.error if best else None,
                        "seconds": best.seconds if best else None,
                        "unconverged": best.unconverged if best else None,
                    }
                )
    return rows

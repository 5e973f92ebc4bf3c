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
  Monte Carlo with MIS at increasing samples per pixel against a Monte-Carlo reference, per model and
  roughness on a sphere under five environments (:data:`IBL_ENVIRONMENTS`).

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
from ..lights.environment import FunctionEnvironment, LatLongEnvironment, latlong_azimuth
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
#: The environments of the ``ibl`` study: label -> procedural sky (:mod:`lighting.lights.skies`), or
#: ``"sun-gradient"`` (:func:`sun_gradient_image`).  The quick settings take the first two.
IBL_ENVIRONMENTS = {"smooth sky": "glow", "small bright sun": "sunset", "studio": "studio", "daylight": "daylight",
                    "1.5° sun, gradient sky": "sun-gradient"}  # fmt: skip
#: The sun of ``"sun-gradient"``: its direction (toward the ``ibl`` sphere's lit side), angular diameter
#: (degrees) and radiance.
IBL_SUN = {"direction": (0.45, -0.55, 0.70), "diameter_deg": 1.5, "radiance": 3000.0}
#: The ``ibl`` study's sphere is seen from the side: camera ``x`` -> world ``x``, camera ``y`` (up in
#: the image) -> world ``z`` (the sky's zenith), toward the viewer -> world ``−y``.
IBL_VIEW_ROTATION = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
#: Pixels darker than this fraction of the image's 99th-percentile pixel are not "lit".
IBL_LIT_FRACTION = 0.02
_GOLD = (0.95, 0.64, 0.54)


def ibl_models(quick: bool = False) -> list:
    """The ``(label, model)`` pairs of the ``ibl`` study.

    Parameters
    ----------
    quick : bool, optional
        Three models (Lambert, Phong e=50, GGX α=0.2 with F = 1) instead of all sixteen.

    Returns
    -------
    list of tuple
        Lambert, Phong ``e`` = 50 and 500, normalized Blinn–Phong ``e`` = 200, and Cook–Torrance with
        the Beckmann and GGX distributions at ``α`` = 0.05, 0.2, 0.5, each with ``F = 1`` and with
        Schlick's Fresnel (a gold ``F_0``).
    """
    models = [("Lambert", Lambert(0.8)), ("Phong e=50", Phong(1.0, 50.0))]
    if quick:
        return models + [("GGX α=0.2, F=1", CookTorrance(1.0, 0.2, 1.0, ndf="ggx", fresnel="none"))]
    models += [("Phong e=500", Phong(1.0, 500.0)), ("Blinn-Phong e=200", BlinnPhong(1.0, 200.0, normalized=True))]
    for ndf, name in (("beckmann", "Beckmann"), ("ggx", "GGX")):
        for alpha in (0.05, 0.2, 0.5):
            models.append((f"{name} α={alpha:g}, F=1", CookTorrance(1.0, alpha, 1.0, ndf=ndf, fresnel="none")))
            models.append((f"{name} α={alpha:g}, Schlick", CookTorrance(1.0, alpha, _GOLD, ndf=ndf, fresnel="schlick")))
    return models


def ibl_environment(name: str, height: int = 256):
    """A procedural sky of :mod:`lighting.lights.skies` tabulated as a ``height × 2 height`` lat-long image.

    The image *is* the environment of the study: the reference, the prefiltered levels and the
    exact irradiance are all computed from the same pixels.

    Parameters
    ----------
    name : str
        A sky name (the values of :data:`IBL_ENVIRONMENTS`).
    height : int, optional
        Rows of the image.

    Returns
    -------
    LatLongEnvironment
    """
    from ..lights.skies import SKIES

    if name == "sun-gradient":
        return LatLongEnvironment(sun_gradient_image(height))
    return LatLongEnvironment.from_function(SKIES[name].function, height)


def sun_gradient_image(height: int = 256, *, supersample: int = 16) -> np.ndarray:
    """A sun disk over a gradient sky, as an ``height × 2 height`` lat-long image (:data:`IBL_SUN`).

    The sky is ``(0.05 + 0.3 max(cos θ, 0))`` times ``(0.8, 0.9, 1.0)``; the sun adds its radiance times the
    share of each pixel's solid angle the disk covers (``supersample²`` points per pixel near the disk), so
    the image holds the disk's power at any height, even where the disk is smaller than a pixel.

    Parameters
    ----------
    height : int, optional
        Rows of the image.
    supersample : int, optional
        Points per pixel side where the disk's coverage is measured.

    Returns
    -------
    ndarray, (height, 2 height, 3)
        Float64 radiance.
    """
    h, w = height, 2 * height
    sun = np.asarray(IBL_SUN["direction"], dtype=np.float64)
    sun = sun / np.linalg.norm(sun)
    cos_r = math.cos(math.radians(IBL_SUN["diameter_deg"] / 2))
    d = LatLongEnvironment.pixel_directions(h, w)
    img = (0.05 + 0.3 * np.maximum(d[..., 2], 0.0))[..., None] * np.array([0.8, 0.9, 1.0])
    # Pixels whose centre is within two pixels (π/h each way at most) of the disk: their coverage by
    # equal-solid-angle supersampling.
    near = np.argwhere(d @ sun >= math.cos(math.radians(IBL_SUN["diameter_deg"] / 2) + 2 * math.pi / h))
    k = (np.arange(supersample) + 0.5) / supersample
    for i, j in near:
        c0, c1 = math.cos(i * math.pi / h), math.cos((i + 1) * math.pi / h)
        z = c0 + (c1 - c0) * k  # equal solid angle steps in cos θ
        a = (j + k) * (2 * math.pi / w)
        phi = latlong_azimuth(a)
        r = np.sqrt(np.maximum(1 - z * z, 0.0))
        pts = np.stack(np.broadcast_arrays(r[:, None] * np.cos(phi), r[:, None] * np.sin(phi), z[:, None]), -1)
        img[i, j] += IBL_SUN["radiance"] * float(np.mean(pts @ sun >= cos_r))
    return img


def ibl_sphere(size: int, dtype=np.float64):
    """The unit sphere of the ``ibl`` study seen from the side: its pixels' normals and view vectors.

    Parameters
    ----------
    size : int
        Image width and height (:func:`lighting.render.sphere_camera`).
    dtype : numpy dtype, optional

    Returns
    -------
    coverage : ndarray of bool, (size, size)
        The pixels the sphere covers, row for row with the vectors.
    normals, views : ndarray, (N, 3)
        World-frame unit normals and directions toward the viewer (:data:`IBL_VIEW_ROTATION`).
    """
    from ..render.sphere import sphere_camera

    r = Renderer(AnalyticSphere(), sphere_camera(size), dtype=dtype)
    n = np.asarray(r.sample_normals("phong"))
    v = np.broadcast_to(r.sample_view("phong")[0], n.shape)
    rot = IBL_VIEW_ROTATION.astype(dtype)
    return r.gbuffer.coverage, np.ascontiguousarray(n @ rot.T), np.ascontiguousarray(v @ rot.T)


def ibl_pixel_errors(value, reference, reference_error=None):
    """Per-pixel relative errors over the lit pixels: ``max_c |value − ref| / max_c ref``.

    Parameters
    ----------
    value, reference : array_like, (N, 3)
        An estimate and its reference, per pixel.
    reference_error : array_like, (N, 3), optional
        The reference's standard error per pixel.

    Returns
    -------
    errors : ndarray, (M,)
        Relative errors of the ``M`` lit pixels (reference brighter than :data:`IBL_LIT_FRACTION`
        of its 99th percentile).
    lit : ndarray of bool, (N,)
    reference_errors : ndarray, (M,) or None
        ``max_c σ_ref / max_c ref`` of the lit pixels.
    """
    value = np.asarray(value, dtype=np.float64)
    reference = np.asarray(reference, dtype=np.float64)
    peak = np.max(reference, axis=-1)
    lit = peak > IBL_LIT_FRACTION * np.percentile(peak, 99)
    errors = np.max(np.abs(value[lit] - reference[lit]), axis=-1) / peak[lit]
    own = None
    if reference_error is not None:
        own = np.max(np.asarray(reference_error, dtype=np.float64)[lit], axis=-1) / peak[lit]
    return errors, lit, own


def _progressive(model, env, n, v, spp, seed):
    """Monte Carlo with MIS at ``spp`` samples per pixel, in 4 to 8 passes (more above 4096 spp)."""
    from ..integrate.ibl import ProgressiveRadiance

    p = ProgressiveRadiance(model, env, n, v, seed=seed)
    # Eight passes where the count allows (the spread of the passes is the error estimate), more for
    # large counts so that one pass stays within memory.
    passes = max(4, min(8, spp // 2), spp // 512)
    for _ in range(passes):
        p.add(max(2, 2 * (spp // (2 * passes))), chunk=min(n.shape[0], 4096))
    return p


def _ibl_points(cfg, progress):
    from ..integrate.dominant import DOMINANT_SAMPLES, dominant_environment, dominant_radiance
    from ..integrate.ibl import split_sum_radiance
    from ..integrate.prefilter import irradiance_map, prefilter_environment

    size, subset, repeat = cfg["ibl_size"], cfg["ibl_pixels"], cfg["repeat"]
    _, n_all, v_all = ibl_sphere(size)
    front = np.flatnonzero(np.sum(n_all * v_all, axis=-1) > 0)
    pick = front[np.unique(np.linspace(0, front.size - 1, min(subset, front.size)).astype(np.int64))]
    n, v = n_all[pick], v_all[pick]
    n32, v32 = n.astype(np.float32), v.astype(np.float32)
    where = f"{pick.size} pixels of a {size}² sphere"
    points = []
    for e_i, (env_label, sky_name) in enumerate(cfg["ibl_environments"].items()):
        env = ibl_environment(sky_name, cfg["ibl_env_height"])
        pre = prefilter_environment(env)
        dominant_environment(pre)  # the lights, the residual's levels and irradiance: once, out of the timings
        # (a) SH9 irradiance against the exact irradiance of the same pixels, at the irradiance map's pixels
        h = cfg["ibl_irradiance_height"]
        exact = irradiance_map(env, h).image
        dirs = LatLongEnvironment.pixel_directions(h, 2 * h)
        sh9 = pre.irradiance_sh(dirs)
        rel = np.max(np.abs(sh9 - exact), axis=-1) / np.max(exact, axis=-1)
        _, t = _median_time(lambda pre=pre: pre.irradiance_sh(n32), repeat)
        points.append(
            Point("ibl", f"SH9 irradiance · {env_label}", "SH9 irradiance", 9, "coefficients",
                  float(np.median(rel)), 0.0, t, f"exact irradiance of the {env.height}x{env.width} map at the "
                  f"{h}x{2 * h} pixel centres (times: {where}, float32)", error_p95=float(np.percentile(rel, 95)))
        )  # fmt: skip
        progress()
        # (b) the split sum and Monte Carlo at increasing spp against a Monte-Carlo reference
        for m_i, (label, model) in enumerate(cfg["ibl_models"]):
            seed = 1000 * e_i + 10 * m_i
            ref = _progressive(model, env, n, v, cfg["ibl_reference_spp"], seed)
            ref_value, ref_err = ref.value, ref.error
            ref_text = f"Monte Carlo with MIS at {ref.samples} spp in {ref.passes} passes ({where})"
            case = f"{label} · {env_label}"
            split_sum_radiance(model, pre, n32, v32)  # the albedo tables once, out of the timings
            fast, t = _median_time(lambda m=model, pre=pre: split_sum_radiance(m, pre, n32, v32), repeat)
            errs, lit, own_ref = ibl_pixel_errors(fast, ref_value, ref_err)
            points.append(
                Point("ibl", case, "split sum", 1, "lookup per lobe", float(np.median(errs)), 0.0, t, ref_text,
                      error_p95=float(np.percentile(errs, 95)), reference_error=float(np.median(own_ref)))
            )  # fmt: skip
            dominant_radiance(model, pre, n32, v32)  # the sample tables once, out of the timings
            fast, t = _median_time(lambda m=model, pre=pre: dominant_radiance(m, pre, n32, v32), repeat)
            errs, _, own_ref = ibl_pixel_errors(fast, ref_value, ref_err)
            points.append(
                Point("ibl", case, "dominant lights", DOMINANT_SAMPLES, "filtered samples per glossy lobe",
                      float(np.median(errs)), 0.0, t, ref_text,
                      error_p95=float(np.percentile(errs, 95)), reference_error=float(np.median(own_ref)))
            )  # fmt: skip
            if cfg["ibl_exact_pixels"] and label in IBL_EXACT_MODELS:
                points += _exact_points(case, model, env, pre, n, v, cfg["ibl_exact_pixels"])
            for spp in cfg["ibl_spp"]:
                mc = _progressive(model, env, n, v, spp, seed + 1 + spp)
                errs, _, own_ref = ibl_pixel_errors(mc.value, ref_value, ref_err)
                own = np.max(mc.error[lit], axis=-1) / np.max(ref_value[lit], axis=-1)
                both = np.sqrt(np.asarray(mc.error[lit], np.float64) ** 2 + ref_err[lit] ** 2)
                covered = np.all(np.abs(mc.value[lit] - ref_value[lit]) <= 2 * both, axis=-1)
                points.append(
                    Point("ibl", case, "Monte Carlo, MIS", mc.samples, "samples per pixel", float(np.median(errs)),
                          0.0, mc.seconds, ref_text, float(np.median(own)), float(np.mean(covered)),
                          error_p95=float(np.percentile(errs, 95)), reference_error=float(np.median(own_ref)))
                )  # fmt: skip
            progress()
    return points


#: The models the fast methods are also judged on against the pixel sum (the targets' four materials).
IBL_EXACT_MODELS = ("Lambert", "GGX α=0.05, F=1", "GGX α=0.2, F=1", "GGX α=0.5, F=1")
#: The pixel sum's tolerance there: its reported error is at most this fraction of each pixel's value.
IBL_EXACT_RTOL = 1e-4


def _exact_points(case, model, env, pre, n, v, count):
    """The split sum and the dominant lights against the pixel sum (:mod:`lighting.integrate.pixelsum`), whose own
    error is far below the Monte-Carlo reference's, on ``count`` of the study's pixels spread over the sphere."""
    from ..integrate.dominant import DOMINANT_SAMPLES, dominant_radiance
    from ..integrate.ibl import split_sum_radiance
    from ..integrate.pixelsum import environment_sum_radiance

    sub = np.unique(np.linspace(0, n.shape[0] - 1, min(count, n.shape[0])).astype(np.int64))
    text = (f"the pixel sum (the environment's cells by adaptive Gauss–Legendre, rtol {IBL_EXACT_RTOL:g}) on "
            f"{sub.size} of the {n.shape[0]} pixels")  # fmt: skip
    n, v = n[sub], v[sub]
    exact = environment_sum_radiance(model, env, n, v, rtol=IBL_EXACT_RTOL)
    points = []
    n32, v32 = n.astype(np.float32), v.astype(np.float32)
    for method, fn, cost, unit in (("split sum", split_sum_radiance, 1, "lookup per lobe"),
                                   ("dominant lights", dominant_radiance, DOMINANT_SAMPLES,
                                    "filtered samples per glossy lobe")):  # fmt: skip
        fast, t = _median_time(lambda fn=fn: fn(model, pre, n32, v32), 1)
        errs, _, own = ibl_pixel_errors(fast, exact.value, exact.error)
        points.append(Point("ibl", case, f"{method} · pixel sum", cost, unit, float(np.median(errs)), 0.0, t,
                            text, error_p95=float(np.percentile(errs, 95)),
                            reference_error=float(np.median(own))))  # fmt: skip
    return points


def _ibl_work(cfg):
    return len(cfg["ibl_environments"]) * (1 + len(cfg["ibl_models"]))


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

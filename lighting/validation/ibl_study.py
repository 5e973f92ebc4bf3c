"""The ``ibl`` study of :mod:`lighting.validation.accuracy`: its skies, sphere, models, error measure and points.

The split sum, the dominant lights and Monte Carlo at increasing samples per pixel are measured on a sphere
seen from the side under five environments (:data:`IBL_ENVIRONMENTS`), against a Monte-Carlo MIS reference on
every study pixel and, for the four materials of :data:`IBL_EXACT_MODELS`, against the pixel sum
(:mod:`lighting.integrate.pixelsum`) on part of them; :func:`lighting.validation.accuracy.run_studies` runs it.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..lights.environment import LatLongEnvironment, latlong_azimuth
from ..models.brdf import BlinnPhong, CookTorrance, Lambert, Phong
from ..render.renderer import AnalyticSphere, Renderer

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


def ibl_front_pixels(size: int, count: int, *, min_cos: float = 0.0):
    """``count`` pixels of :func:`ibl_sphere` spread evenly over those facing the viewer: ``(normals, views)``.

    Parameters
    ----------
    size : int
        The sphere's image size.
    count : int
        Pixels wanted (all of them where fewer face the viewer).
    min_cos : float, optional
        The pixels facing the viewer are those with ``n·v`` above this.

    Returns
    -------
    normals, views : ndarray, (count, 3)
        In scan order, float64.
    """
    _, n, v = ibl_sphere(size)
    front = np.flatnonzero(np.sum(n * v, axis=-1) > min_cos)
    pick = front[np.unique(np.linspace(0, front.size - 1, min(count, front.size)).astype(np.int64))]
    return n[pick], v[pick]


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
    from .accuracy import Point, _median_time

    size, subset, repeat = cfg["ibl_size"], cfg["ibl_pixels"], cfg["repeat"]
    n, v = ibl_front_pixels(size, subset)
    n32, v32 = n.astype(np.float32), v.astype(np.float32)
    where = f"{n.shape[0]} pixels of a {size}² sphere"
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
            for method, grid in (("dominant lights", False), (GRID_METHOD, True)):
                dominant_radiance(model, pre, n32, v32, normal_grid=grid)  # the sample tables once, untimed
                fast, t = _median_time(
                    lambda m=model, pre=pre, g=grid: dominant_radiance(m, pre, n32, v32, normal_grid=g), repeat
                )
                errs, _, own_ref = ibl_pixel_errors(fast, ref_value, ref_err)
                points.append(
                    Point("ibl", case, method, DOMINANT_SAMPLES, "filtered samples per glossy lobe",
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


#: The dominant-light method with its blurred terms shaded on the grid of normals (what a large image of one view
#: direction gets: :mod:`lighting.integrate._normalgrid`); ``"dominant lights"`` is the same shaded pixel by pixel.
GRID_METHOD = "dominant lights, normal grid"
#: The models the fast methods are also judged on against the pixel sum (the targets' four materials).
IBL_EXACT_MODELS = ("Lambert", "GGX α=0.05, F=1", "GGX α=0.2, F=1", "GGX α=0.5, F=1")
#: What the method of a point judged against the pixel sum ends with (``"dominant lights · pixel sum"``).
PIXEL_SUM_SUFFIX = " · pixel sum"
#: The pixel sum's tolerance there: its reported error is at most this fraction of each pixel's value.
IBL_EXACT_RTOL = 1e-4


def _exact_points(case, model, env, pre, n, v, count):
    """The split sum and the dominant lights against the pixel sum (:mod:`lighting.integrate.pixelsum`), whose own
    error is far below the Monte-Carlo reference's, on ``count`` of the study's pixels spread over the sphere."""
    from ..integrate.dominant import DOMINANT_SAMPLES, dominant_radiance
    from ..integrate.ibl import split_sum_radiance
    from ..integrate.pixelsum import environment_sum_radiance
    from .accuracy import Point, _median_time

    sub = np.unique(np.linspace(0, n.shape[0] - 1, min(count, n.shape[0])).astype(np.int64))
    text = (f"the pixel sum (the environment's cells by adaptive Gauss–Legendre, rtol {IBL_EXACT_RTOL:g}) on "
            f"{sub.size} of the {n.shape[0]} pixels")  # fmt: skip
    n, v = n[sub], v[sub]
    exact = environment_sum_radiance(model, env, n, v, rtol=IBL_EXACT_RTOL)
    points = []
    n32, v32 = n.astype(np.float32), v.astype(np.float32)
    per_pixel = functools.partial(dominant_radiance, normal_grid=False)
    on_grid = functools.partial(dominant_radiance, normal_grid=True)
    for method, fn, cost, unit in (
        ("split sum", split_sum_radiance, 1, "lookup per lobe"),
        ("dominant lights", per_pixel, DOMINANT_SAMPLES, "filtered samples per glossy lobe"),
        (GRID_METHOD, on_grid, DOMINANT_SAMPLES, "filtered samples per glossy lobe"),
    ):
        fast, t = _median_time(lambda fn=fn: fn(model, pre, n32, v32), 1)
        errs, _, own = ibl_pixel_errors(fast, exact.value, exact.error)
        points.append(Point("ibl", case, f"{method}{PIXEL_SUM_SUFFIX}", cost, unit, float(np.median(errs)), 0.0, t,
                            text, error_p95=float(np.percentile(errs, 95)),
                            reference_error=float(np.median(own))))  # fmt: skip
    return points


def _ibl_work(cfg):
    return len(cfg["ibl_environments"]) * (1 + len(cfg["ibl_models"]))

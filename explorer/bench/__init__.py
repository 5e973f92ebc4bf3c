"""The bench, in one place: what ``lighting-explorer bench`` measures (the command is :mod:`explorer.commands.bench`).

This module times the engine's image pipeline against VTK, in one run; :mod:`.window` times the desktop
window (``bench --app``), and :mod:`.costs` measures the costs behind the render time budget
(``python -m explorer.bench.costs``).

These numbers, each the median of repeated runs on the machine that runs the command:

* ``reshade_ms`` — lighting a cached 512×512 geometry buffer of a sphere with
  three lights (Blinn–Phong, Phong interpolation): what a slider move costs;
* ``raster_ms`` — rasterizing the ~5,000-triangle sphere into a geometry buffer;
* ``raster_shade_ms`` — a whole frame from nothing: rasterizing, interpolating
  the normals and shading;
* ``vtk_ms`` — PyVista/VTK rendering the same mesh and lights off-screen at
  512×512, render plus read-back of the pixels;

and the ratios of ours to VTK.  The measurements are interleaved: each round
runs every item once untimed and once timed, so all of them see the same
machine conditions.
``--json`` prints one machine-readable line.

``--ibl`` times image-based lighting instead (:func:`run_ibl`): re-shading a 512² sphere by SH9 and
the split sum in float32 once the environment is prefiltered, prefiltering a 512×256 map for 8
lobe widths, and the Monte-Carlo reference at 64 samples per pixel, each beside a reference
measured in the same run.
"""

from __future__ import annotations

import json
import statistics
import sys
import time

import numpy as np

from lighting import AmbientLight, BlinnPhong, DirectionalLight, Lambert, Material
from lighting.render.camera import Camera
from lighting.render.mesh import sphere_for_triangles
from lighting.render.raster import rasterize
from lighting.render.renderer import Renderer

SIZE = 512
LIGHT_DIRS = [(-1.0, 1.0, 1.5), (1.0, 0.3, 0.8), (0.0, -1.0, 0.6)]
LIGHT_COLOURS = [(1.0, 0.95, 0.9), (0.3, 0.35, 0.6), (0.25, 0.2, 0.15)]


def bench_scene(size=SIZE, triangles=5000):
    """The benchmark's scene: a tessellated sphere, a camera, Lambert + Blinn–Phong and four lights.

    Parameters
    ----------
    size : int, optional
        Image width and height in pixels.
    triangles : int, optional
        About how many triangles the sphere has.

    Returns
    -------
    tuple
        ``(mesh, camera, material, lights)``.
    """
    mesh = sphere_for_triangles(triangles)
    camera = Camera((0, 0, 6.0), (0, 0, 0), fov_y_deg=22.0, width=size, height=size)
    material = Material(Lambert((0.7, 0.25, 0.2)) + BlinnPhong(0.5, 40.0))
    lights = [AmbientLight(intensity=0.05)] + [
        DirectionalLight(d, color=c) for d, c in zip(LIGHT_DIRS, LIGHT_COLOURS, strict=True)
    ]
    return mesh, camera, material, lights


def _median_ms(fn, repeat: int) -> float:
    return _interleaved_ms({"x": fn}, repeat)["x"]


def _interleaved_ms(fns: dict, repeat: int) -> dict:
    """Median ms of each callable, timed in rounds that run every callable in turn.

    Interleaving puts every measurement under the same machine conditions: on
    a shared machine the speed drifts by 10–30 % over seconds, and timing one
    item after another would fold that drift into their ratios.  Within a round
    each callable runs once untimed and then once timed, so it is measured as
    in use (a slider's re-shades follow each other), not with the caches the
    previous item left.
    """
    times = {key: [] for key in fns}
    for _ in range(repeat):
        for key, fn in fns.items():
            fn()
            t0 = time.perf_counter()
            fn()
            times[key].append(time.perf_counter() - t0)
    return {key: 1e3 * statistics.median(t) for key, t in times.items()}


def engine_frames(size: int = SIZE) -> dict:
    """The engine's timed callables.

    Parameters
    ----------
    size : int, optional
        Image width and height in pixels.

    Returns
    -------
    dict
        ``{result key: callable}``: re-shading (float64, float32), rasterizing, and whole frames.
    """
    mesh, camera, material, lights = bench_scene(size)
    fns = {}
    for dt, key in ((np.float64, "reshade_ms"), (np.float32, "reshade_f32_ms")):
        r = Renderer(mesh, camera, dtype=dt)
        r.render(material, lights)
        k = [0]

        def reshade(r=r, k=k):
            # A slider move: the key light turns a little each frame.
            k[0] += 1
            a = 0.05 * k[0]
            moved = [lights[0], DirectionalLight((np.cos(a) - 1.5, 1.0, 1.5))] + lights[2:]
            r.render(material, moved)

        fns[key] = reshade
    fns["raster_ms"] = lambda: rasterize(mesh, camera, dtype=np.float32)
    fns["raster_shade_ms"] = lambda: Renderer(mesh, camera).render(material, lights)
    fns["raster_shade_f32_ms"] = lambda: Renderer(mesh, camera, dtype=np.float32).render(material, lights)
    return fns


def vtk_frame(size: int = SIZE):
    """One VTK render plus read-back of the same scene, and the clean-up.

    Parameters
    ----------
    size : int, optional
        Image width and height in pixels.

    Returns
    -------
    tuple or None
        ``(frame, close)``, or ``None`` without PyVista/VTK.
    """
    try:
        import pyvista as pv
    except ImportError:
        return None
    mesh, camera, material, lights = bench_scene(size)
    faces = np.hstack([np.full((mesh.n_triangles, 1), 3), mesh.faces]).ravel()
    poly = pv.PolyData(mesh.vertices, faces)
    poly.point_data["Normals"] = mesh.normals
    pl = pv.Plotter(off_screen=True, window_size=(size, size), lighting="none")
    pl.add_mesh(poly, color=(0.7, 0.25, 0.2), smooth_shading=True, specular=0.5, specular_power=40.0, ambient=0.05)
    for d, c in zip(LIGHT_DIRS, LIGHT_COLOURS, strict=True):
        pl.add_light(pv.Light(position=d, focal_point=(0, 0, 0), color=c, light_type="scene light", positional=False))
    pl.camera_position = [tuple(camera.eye), tuple(camera.target), tuple(camera.up)]
    pl.camera.view_angle = camera.fov_y_deg
    pl.show(auto_close=False)

    def frame():
        pl.render()
        pl.screenshot(return_img=True)

    return frame, pl.close


def run(repeat: int = 15, size: int | None = None) -> dict:
    """All measurements of one benchmark run (see the module docstring).

    Parameters
    ----------
    repeat : int, optional
        Timed runs per measurement (the median is reported).
    size : int, optional
        Image width and height (default :data:`SIZE`).

    Returns
    -------
    dict
        The medians in ms (``reshade_ms``, ``raster_ms``, ``raster_shade_ms``, ``vtk_ms`` ...), the
        ratios to VTK and the scene's size.
    """
    return _run(repeat, SIZE if size is None else size)


def _run(repeat: int, size: int) -> dict:
    fns = engine_frames(size)
    made = vtk_frame(size)
    if made is not None:
        fns["vtk_ms"] = made[0]
    try:
        result = {"triangles": bench_scene(size)[0].n_triangles, "size": size, **_interleaved_ms(fns, repeat)}
    finally:
        if made is not None:
            made[1]()
    vtk = result.setdefault("vtk_ms", None)
    if vtk:
        result["reshade_over_vtk"] = result["reshade_ms"] / vtk
        result["reshade_f32_over_vtk"] = result["reshade_f32_ms"] / vtk
        result["raster_shade_over_vtk"] = result["raster_shade_ms"] / vtk
        result["raster_shade_f32_over_vtk"] = result["raster_shade_f32_ms"] / vtk
    return result


#: The ``bench --ibl`` targets, ms.
IBL_TARGETS = {"ibl_reshade_ms": 50.0, "ibl_dominant_ms": 50.0, "ibl_dominant_studio_ms": 50.0,
               "ibl_dominant_sun_ms": 50.0, "ibl_dominant_narrow_ms": 50.0, "ibl_prefilter_ms": 300.0,
               "ibl_mc64_ms": 5000.0}  # fmt: skip


def ibl_frames(size: int = SIZE, env_height: int = 256, model=None) -> dict:
    """The timed callables of ``bench --ibl`` (a GGX + Lambert sphere under the ``daylight`` sky).

    Parameters
    ----------
    size : int, optional
        Sphere image width and height in pixels.
    env_height : int, optional
        Rows of the lat-long environment (``2 env_height`` columns).
    model : BRDF, optional
        Default Lambert + GGX (``α`` = 0.3, F = 1).

    Returns
    -------
    dict
        ``{result key: callable}``: ``ibl_reshade_ms`` (split sum, float32, prefiltered once),
        ``ibl_reshade_f64_ms`` (the same in float64), ``ibl_dominant_ms`` (the dominant-light method,
        float32, its lights and residual made once; on the grid of normals, as every pixel shares one view),
        ``ibl_dominant_studio_ms`` and ``ibl_dominant_sun_ms`` (the same under the studio's two soft boxes and under a
        1.5° sun over a gradient sky), ``ibl_dominant_pixels_ms`` (daylight, pixel by pixel: ``normal_grid=False``),
        ``ibl_dominant_narrow_ms`` (daylight, GGX ``α`` = 0.05: a narrow lobe, four times the samples per point, on
        a grid of two rows per ``σ`` with the round lobe read per pixel),
        ``ibl_dominant_setup_ms`` (making them: the lights, the residual's levels and irradiance map),
        ``ibl_prefilter_ms`` (8 levels),
        ``ibl_mc64_ms`` (:class:`~lighting.integrate.ibl.ProgressiveRadiance`, one 64-sample pass),
        and ``ibl_pixels`` (the sphere's pixel count, an int).
    """
    from lighting import CookTorrance
    from lighting.integrate.dominant import DominantEnvironment, dominant_radiance
    from lighting.integrate.ibl import ProgressiveRadiance, split_sum_radiance
    from lighting.integrate.prefilter import PREFILTER_SIGMAS, prefilter_environment
    from lighting.validation.accuracy import ibl_environment, ibl_sphere

    model = model or Lambert(0.3) + CookTorrance(1.0, 0.3, 1.0, ndf="ggx", fresnel="none")
    env = ibl_environment("daylight", env_height)
    _, n, v = ibl_sphere(size)
    n32, v32 = n.astype(np.float32), v.astype(np.float32)
    pre = prefilter_environment(env, sigmas=PREFILTER_SIGMAS)
    studio, sun = (prefilter_environment(ibl_environment(sky, env_height), sigmas=PREFILTER_SIGMAS)
                   for sky in ("studio", "sun-gradient"))  # fmt: skip
    narrow = Lambert(0.3) + CookTorrance(1.0, 0.05, 1.0, ndf="ggx", fresnel="none")
    split_sum_radiance(model, pre, n32, v32)  # albedo tables: once per model, not per frame
    for m, p in ((model, pre), (model, studio), (model, sun), (narrow, pre)):
        dominant_radiance(m, p, n32, v32)  # its lights, residual and sample tables: once per environment
    return {
        "ibl_reshade_ms": lambda: split_sum_radiance(model, pre, n32, v32),
        "ibl_reshade_f64_ms": lambda: split_sum_radiance(model, pre, n, v),
        "ibl_dominant_ms": lambda: dominant_radiance(model, pre, n32, v32),
        "ibl_dominant_studio_ms": lambda: dominant_radiance(model, studio, n32, v32),
        "ibl_dominant_sun_ms": lambda: dominant_radiance(model, sun, n32, v32),
        "ibl_dominant_pixels_ms": lambda: dominant_radiance(model, pre, n32, v32, normal_grid=False),
        "ibl_dominant_narrow_ms": lambda: dominant_radiance(narrow, pre, n32, v32),
        "ibl_dominant_setup_ms": lambda: DominantEnvironment(pre),
        "ibl_prefilter_ms": lambda: prefilter_environment(env, sigmas=PREFILTER_SIGMAS, reuse=False),
        "ibl_mc64_ms": lambda: ProgressiveRadiance(model, env, n, v, seed=0).add(64),
        "ibl_pixels": int(n.shape[0]),
    }


def run_ibl(repeat: int = 3, size: int | None = None) -> dict:
    """The ``bench --ibl`` measurements (medians in ms, interleaved), their targets and ratios.

    Parameters
    ----------
    repeat : int, optional
        Timed runs per measurement (the Monte-Carlo row takes seconds: keep it small).
    size : int, optional
        Sphere image size (default :data:`SIZE`); the environment is always 512×256.

    Returns
    -------
    dict
        ``ibl_*_ms`` medians, ``ibl_reshade_over_f64`` (float32 split sum ÷ float64 split sum),
        ``ibl_mc64_over_reshade`` (the reference ÷ the fast path), ``ibl_dominant_over_reshade`` (the
        dominant-light method ÷ the split sum), ``ibl_pixels_over_grid`` (pixel by pixel ÷ on the grid of normals),
        ``targets`` and ``size``, ``pixels``.
    """
    fns = ibl_frames(SIZE if size is None else size)
    pixels = fns.pop("ibl_pixels")
    r = {"size": SIZE if size is None else size, "pixels": pixels, **_interleaved_ms(fns, repeat)}
    r["ibl_reshade_over_f64"] = r["ibl_reshade_ms"] / r["ibl_reshade_f64_ms"]
    r["ibl_mc64_over_reshade"] = r["ibl_mc64_ms"] / r["ibl_reshade_ms"]
    r["ibl_dominant_over_reshade"] = r["ibl_dominant_ms"] / r["ibl_reshade_ms"]
    r["ibl_pixels_over_grid"] = r["ibl_dominant_pixels_ms"] / r["ibl_dominant_ms"]
    r["targets"] = dict(IBL_TARGETS)
    return r


def format_ibl(r: dict) -> str:
    """The table that ``lighting-explorer bench --ibl`` prints.

    Parameters
    ----------
    r : dict
        A result of :func:`run_ibl`.

    Returns
    -------
    str
        One row per measurement: median ms, its target, met or missed.
    """
    lines = [
        f"Image-based lighting: {r['size']}x{r['size']} sphere ({r['pixels']} pixels), Lambert + GGX α=0.3, "
        "daylight sky 512x256 (median ms)",
        "",
        f"{'what':52s} {'ms':>9s} {'target':>8s}  ",
    ]
    rows = (
        ("re-shade, SH9 + split sum, float32 (prefiltered)", "ibl_reshade_ms"),
        ("re-shade, SH9 + split sum, float64 (same run)", "ibl_reshade_f64_ms"),
        ("re-shade, dominant lights + filtered samples, float32", "ibl_dominant_ms"),
        ("  the same under the studio (two soft boxes)", "ibl_dominant_studio_ms"),
        ("  the same under a 1.5° sun over a gradient sky", "ibl_dominant_sun_ms"),
        ("  daylight, pixel by pixel (no grid of normals)", "ibl_dominant_pixels_ms"),
        ("  daylight, GGX α=0.05 (a narrow lobe: 64 samples)", "ibl_dominant_narrow_ms"),
        ("  its lights, residual levels and irradiance, once", "ibl_dominant_setup_ms"),
        ("prefilter 512x256, 8 lobe widths", "ibl_prefilter_ms"),
        ("Monte Carlo MIS reference, 64 spp", "ibl_mc64_ms"),
    )
    for label, key in rows:
        target = r["targets"].get(key)
        verdict = "" if target is None else ("met" if r[key] <= target else "MISSED")
        tgt = "" if target is None else f"<= {target:g}"
        lines.append(f"{label:52s} {r[key]:9.1f} {tgt:>8s}  {verdict}".rstrip())
    lines.append("")
    lines.append(f"float32 re-shade ÷ float64 re-shade: {r['ibl_reshade_over_f64']:.2f}")
    lines.append(f"Monte Carlo 64 spp ÷ float32 re-shade: {r['ibl_mc64_over_reshade']:.0f}x")
    lines.append(f"dominant lights ÷ split sum (float32 re-shades): {r['ibl_dominant_over_reshade']:.1f}x")
    lines.append(f"dominant lights pixel by pixel ÷ on the grid of normals: {r['ibl_pixels_over_grid']:.1f}x")
    return "\n".join(lines)


def format_report(r: dict) -> str:
    """The table that ``lighting-explorer bench`` prints.

    Parameters
    ----------
    r : dict
        A result of :func:`run`.

    Returns
    -------
    str
        One row per measurement: ms, the ratio to VTK, the target.
    """
    vtk = r.get("vtk_ms")
    lines = [
        f"Sphere of {r['triangles']} triangles, {r['size']}x{r['size']}, three lights, Blinn-Phong (median ms)",
        "",
        f"{'what':44s} {'ms':>8s} {'÷ VTK':>7s}  target",
    ]

    def row(label, key, target=""):
        ratio = f"{r[key] / vtk:7.2f}" if vtk else "      -"
        lines.append(f"{label:44s} {r[key]:8.2f} {ratio}  {target}")

    row("re-shade cached buffer (float64)", "reshade_ms", "<= 0.25")
    row("re-shade cached buffer (float32)", "reshade_f32_ms", "<= 0.25")
    row("rasterize only (geometry buffer)", "raster_ms")
    row("rasterize + shade (float64)", "raster_shade_ms", "<= 1")
    row("rasterize + shade (float32)", "raster_shade_f32_ms", "<= 1")
    no_vtk = "VTK: not installed (pip install 'lighting-explorer[app]')"
    lines.append(f"{'VTK off-screen render + read-back':44s} {vtk:8.2f}" if vtk else no_vtk)
    return "\n".join(lines)


#: Where ``bench --app`` measures the desktop window: Qt's platform and the 3D view's kind.
APP_RUNS = (
    ("offscreen", "images", ["--repeat"], {"QT_QPA_PLATFORM": "offscreen"}),
    ("X server", "images", ["--repeat"], {"QT_QPA_PLATFORM": "xcb"}),
    ("X server", "OpenGL widget", ["--opengl-3d", "--repeat"], {"QT_QPA_PLATFORM": "xcb"}),
)


def run_app(repeat: int = 15) -> list[dict]:
    """The desktop window's interactions (:func:`explorer.bench.window.benchmark_window`), each run in a process.

    On Qt's ``offscreen`` platform, and in a real X server (``DISPLAY``, else a private Xvfb through
    ``xvfb-run`` when it is installed) with the 3D lobe drawn as VTK images and as pyvistaqt's OpenGL widget.

    Parameters
    ----------
    repeat : int
        Samples per measurement.

    Returns
    -------
    list of dict
        One row per run: ``platform``, ``view3d`` and the medians (ms), or ``skipped`` with the reason.
    """
    import os
    import shutil
    import subprocess

    rows = []
    for platform, view3d, flags, env in APP_RUNS:
        cmd = [sys.executable, "-m", "explorer.bench.window", *flags, str(repeat)]
        if env["QT_QPA_PLATFORM"] == "xcb" and not os.environ.get("DISPLAY"):
            xvfb = shutil.which("xvfb-run")
            if xvfb is None:
                rows.append({"platform": platform, "view3d": view3d, "skipped": "no X server and no xvfb-run"})
                continue
            cmd = [xvfb, "--auto-servernum", "--server-args=-screen 0 1920x1200x24", *cmd]
        done = subprocess.run(cmd, env={**os.environ, **env}, capture_output=True, text=True, timeout=900)
        lines = [ln for ln in done.stdout.splitlines() if ln.startswith("{")]
        if done.returncode != 0 or not lines:
            reason = (done.stderr.strip().splitlines() or ["no output"])[-1]
            rows.append({"platform": platform, "view3d": view3d, "skipped": f"failed: {reason}"})
            continue
        rows.append({"platform": platform, "view3d": view3d, **json.loads(lines[-1])})
    return rows


def format_app(rows) -> str:
    """The table of ``lighting-explorer bench --app``: one column per run, one row per interaction."""
    keys = [("drag_ms", "light slider dragged → lit sphere repainted", 16.0),
            ("release_ms", "slider released → lobe and plots repainted", 100.0),
            ("model_switch_ms", "model switched → every view repainted", 150.0),
            ("lobe_redraw_ms", "3D lobe redrawn alone", None)]  # fmt: skip
    size = next((r["window"] for r in rows if "window" in r), None)
    head = f"The desktop window at {size[0]}x{size[1]} (median ms)" if size else "The desktop window (median ms)"
    lines = [head, ""]
    cols = [f"{r['platform']}, {r['view3d']}" for r in rows]
    lines.append(f"{'what':46s} " + " ".join(f"{c:>24s}" for c in cols) + "  target")
    for key, label, target in keys:
        cells = [f"{r[key]:24.1f}" if key in r else f"{'-':>24s}" for r in rows]
        lines.append(f"{label:46s} " + " ".join(cells) + (f"  <= {target:g}" if target else ""))
    for r in rows:
        if "skipped" in r:
            lines.append(f"{r['platform']}, {r['view3d']}: skipped ({r['skipped']})")
    return "\n".join(lines)


def time_plans(repeat: int = 15, size=None) -> list[dict]:
    """Per example scene: median ms of one frame, planned vs the nothing-skipped evaluation.

    Both re-use the scene's geometry buffers (rasterization is not timed); the
    planned frame also re-uses its cached samples, exactly as an interactive
    session does, while the full evaluation prepares every input afresh.

    Parameters
    ----------
    repeat : int, optional
        Timed runs per measurement (the median is reported).
    size : tuple of int, optional
        ``(width, height)`` to render every scene at instead of its own size.

    Returns
    -------
    list of dict
        Per scene: ``scene``, ``pixels``, ``planned_ms``, ``full_ms``, ``speedup``.
    """
    from lighting.scene import SceneRenderer, example_path, list_examples, load_scene

    rows = []
    for name in list_examples():
        scene = load_scene(example_path(name))
        if size:
            scene = scene.with_size(*size)
        planned = SceneRenderer(scene, plan=True)
        full = SceneRenderer(scene, plan="full")
        row = {"scene": name, "pixels": scene.camera.width * scene.camera.height}
        row["planned_ms"] = _median_ms(lambda planned=planned: planned.render(), repeat)
        row["full_ms"] = _median_ms(lambda full=full: full.render(), repeat)
        row["speedup"] = row["full_ms"] / row["planned_ms"]
        rows.append(row)
    return rows


def format_plans(rows) -> str:
    """The table that ``lighting-explorer bench --plan`` prints.

    Parameters
    ----------
    rows : list of dict
        A result of :func:`time_plans`.

    Returns
    -------
    str
        One row per example scene.
    """
    lines = [
        "One frame per example scene, geometry buffers cached (median ms)",
        "",
        f"{'scene':22s} {'pixels':>8s} {'planned':>9s} {'full':>9s} {'speed-up':>9s}",
    ]
    for r in rows:
        lines.append(
            f"{r['scene']:22s} {r['pixels']:8d} {r['planned_ms']:9.2f} {r['full_ms']:9.2f} {r['speedup']:8.1f}x"
        )
    return "\n".join(lines)

"""Timing of the explorer's slider handlers and frames, off-screen (``explorer.app.benchmark_handlers``)."""

from __future__ import annotations

import math
import statistics
import time

from .layout import DEFAULT_WINDOW_SIZE
from .window import ExplorerApp

__all__ = ["benchmark_handlers"]


def benchmark_handlers(repeat: int = 15, window_size=DEFAULT_WINDOW_SIZE) -> dict:
    """Median times (ms) of the slider handlers and of whole frames at ``window_size``, off-screen.

    A slider being dragged calls the *drag* handler (:meth:`ExplorerApp.on_slider` with
    ``live=True``): validate and store the value, re-shade the lit sphere and the coarse
    spheres from their cached geometry buffers (never re-rasterized), encode and upload
    them, move the light arrow; the other views wait for the release.  A *frame* adds
    VTK's render of the whole window (software OpenGL here), which is what the eye waits
    for.  Keys:

    * ``azimuth_ms``, ``elevation_ms`` — the drag handler of the light sliders;
    * ``azimuth_frame_ms``, ``light_frame_ms`` — the same plus rendering the window:
      what a drag of the azimuth or elevation slider costs per frame;
    * ``release_ms`` — the frame at the release of the elevation slider: the scan-line
      profile, the lobe and the plots brought up to date, and the window rendered;
    * ``elevation_full_ms``, ``elevation_full_frame_ms`` — one elevation change updating
      every view at once (a key, or :meth:`ExplorerApp.set_control`), without and with
      the render;
    * ``shininess_ms`` — the drag handler of a material slider;
    * ``tessellation_new_ms`` — a coarse sphere not seen before (rasterized), dragged;
    * ``tessellation_cached_ms`` — back to one already rasterized;
    * ``render_ms`` — VTK alone, redrawing the unchanged window.

    Parameters
    ----------
    repeat : int
        Runs per measurement (the median is reported).
    window_size : (int, int)
        Window width and height in pixels.

    Returns
    -------
    dict
        The keys above (milliseconds), plus ``window``, ``sphere_px`` and ``mesh_px``.
    """
    import pyvista as pv

    old = pv.OFF_SCREEN
    pv.OFF_SCREEN = True
    app = ExplorerApp(window_size=window_size, off_screen=True)
    try:
        out = {"window": list(app.window_size), "sphere_px": app.model.sphere_size, "mesh_px": app.model.mesh_size}

        def timed(action, n, frame=False, before=None):
            times = []
            for k in range(n):
                if before is not None:
                    before(k)
                t0 = time.perf_counter()
                action(k)
                if frame:
                    app.plotter.render()
                times.append(1e3 * (time.perf_counter() - t0))
            return statistics.median(times)

        def azimuth(k):
            app.on_slider("azimuth", 135.0 + 40.0 * math.sin(0.2 * (k + 1)), live=True)

        def elevation(k):
            app.on_slider("elevation", 45.0 + 20.0 * math.sin(0.3 * (k + 1)), live=True)

        def elevation_full(k):
            app.on_slider("elevation", 45.0 + 20.0 * math.sin(0.3 * (k + 1)))

        timed(elevation, 3, frame=True)
        out["azimuth_ms"] = timed(azimuth, repeat)
        out["elevation_ms"] = timed(elevation, repeat)
        out["azimuth_frame_ms"] = timed(azimuth, repeat, frame=True)
        out["light_frame_ms"] = timed(elevation, repeat, frame=True)
        out["release_ms"] = timed(lambda k: app.flush(render=False), repeat, frame=True, before=elevation)
        out["elevation_full_ms"] = timed(elevation_full, repeat)
        out["elevation_full_frame_ms"] = timed(elevation_full, repeat, frame=True)
        shininess = "param:shininess"  # a slider of the model's own controls
        out["shininess_ms"] = timed(lambda k: app.on_slider(shininess, 1.0 + 0.05 * (k % 20 + 1), live=True), repeat)
        app.flush(render=False)
        seq = [t for t in range(5, 41) if not app.model.is_rasterized(t, app.model.mesh_size)]
        n_new = min(repeat, len(seq), 8)  # within the renderer cache (12), so they stay rasterized
        out["tessellation_new_ms"] = timed(lambda k: app.on_slider("tessellation", seq[k], live=True), n_new)
        out["tessellation_cached_ms"] = timed(
            lambda k: app.on_slider("tessellation", seq[k % n_new], live=True), repeat
        )
        app.flush(render=False)
        out["render_ms"] = timed(lambda k: None, repeat, frame=True)
        return out
    finally:
        app.close()
        pv.OFF_SCREEN = old

"""The window's layout: panel grid, colours, view scales, and small geometry helpers of the panels."""

from __future__ import annotations

import os

import numpy as np

__all__ = ["DEFAULT_WINDOW_SIZE", "IDLE_MS", "PANEL_VIEWS"]

DEFAULT_WINDOW_SIZE = (1280, 768)
#: Window height for which the font sizes below are given; other sizes scale them (and the plots' dpi).
DESIGN_HEIGHT = 768
BACKGROUND = (0.105, 0.11, 0.125)
TEXT = (0.91, 0.925, 0.94)
MUTED = (0.55, 0.57, 0.6)
ACCENT = (1.0, 0.88, 0.4)
SCANLINE = (1.0, 0.42, 0.42)
HALF = 1.08  # half-width of the engine images in sphere units (lighting.render.sphere.sphere_camera's margin)
SPHERE_SCALE = 1.45  # half-height of the lit sphere panel's view, sphere units (room for the light arrow)
COARSE_SCALE = 1.16
LOBE_SCALE = 1.0
#: While a slider is dragged only the lit sphere and the coarse spheres follow; the profile, the lobe
#: and the plots follow on release, or once the slider has rested this long (milliseconds).
IDLE_MS = 150

# Panels: (row, column) of the subplot grid.
SPHERE, GOURAUD, PHONG, PROFILE = (0, 0), (0, 1), (0, 2), (0, 3)
LOBE, POLAR, ANGLES, CONTROLS_PANEL = (1, 0), (1, 1), (1, 2), (2, 0)
#: The views each panel shows.  During a drag VTK redraws only the panels whose views changed (and
#: the controls); the others keep last frame's pixels, which are still right.
PANEL_VIEWS = {
    SPHERE: frozenset({"sphere"}),
    GOURAUD: frozenset({"coarse", "profile"}),  # the red scan line follows the profile
    PHONG: frozenset({"coarse", "profile"}),
    PROFILE: frozenset({"profile"}),
    LOBE: frozenset({"lobe", "object"}),  # the 3D panel: the lobe, or the lit object
    POLAR: frozenset({"polar"}),
    ANGLES: frozenset({"theta_v", "theta_h", "theta_d", "halfdiff", "albedo"}),  # albedo: the albedo curves
}


def _font_file(name: str = "DejaVuSans.ttf") -> str | None:
    """A DejaVu font from Matplotlib's data: VTK's built-in fonts have no Greek letters (θ, Δ)."""
    try:
        import matplotlib

        path = os.path.join(matplotlib.get_data_path(), "fonts", "ttf", name)
    except ImportError:  # pragma: no cover - matplotlib is a dependency of the explorer
        return None
    return path if os.path.exists(path) else None


def _arrow_matrix(start, end) -> np.ndarray:
    """4×4 matrix taking the unit arrow (0,0,0)→(1,0,0) to ``start``→``end`` (uniform scale)."""
    start, end = np.asarray(start, float), np.asarray(end, float)
    d = end - start
    length = float(np.linalg.norm(d))
    if not length > 0:
        m = np.eye(4)
        m[:3, :3] *= 1e-9
        return m
    x = d / length
    helper = np.array([0.0, 0.0, 1.0]) if abs(x[2]) < 0.9 else np.array([0.0, 1.0, 0.0])
    y = np.cross(helper, x)
    y /= np.linalg.norm(y)
    z = np.cross(x, y)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2] = x * length, y * length, z * length
    m[:3, 3] = start
    return m

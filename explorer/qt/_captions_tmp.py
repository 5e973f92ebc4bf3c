"""Temporary caption texts until explorer.app.captions lands (then this module goes)."""
import math

from ..app.state import CHANNEL_LABELS, MODEL_LABELS


def window_title(s):
    return f"lighting-explorer — {MODEL_LABELS[s.model]}"


def channel_label(s):
    return CHANNEL_LABELS[s.channel]


def sphere_title(s, sv):
    return f"Lit sphere (engine): {MODEL_LABELS[s.model]}"


def sphere_caption(s, sv, model):
    where = "per pixel, exact sphere" if sv.mode == "phong" else f"{sv.mode}, {sv.geometry}"
    share = 100 * sv.clipped / max(int(sv.coverage.sum()), 1)
    clipped = f"{share:.0f}% of the sphere above 1: clipped (lower the exposure)\n" if sv.clipped else ""
    light = "ambient light only"
    if s.light != "ambient":
        light = f"{s.light}, elevation {s.elevation:.0f}°, azimuth {s.azimuth:.0f}°"
    return f"{clipped}{where} · arrow: the light\n{light}"


def coarse_caption(cv):
    return f"{cv.n_triangles} triangles, {len(cv.vertices)} vertices: engine colours interpolated"


def profile_title(s):
    return f"Scan line: intensity ({CHANNEL_LABELS[s.channel]})"


def profile_caption(pv):
    return f"Mach-band measure: Gouraud {pv.metric_gouraud:.2f}, Phong {pv.metric_phong:.2f}"


def lobe_title(s, lv):
    return f"3D lobe: {s.quantity_label()}"


def lobe_caption(s, lv):
    return f"θ_l = {math.degrees(s.theta_l):.0f}°, peak {lv.peak:.3g}"


def object_caption(s, ov, model):
    return f"{ov.triangles} triangles, {ov.method}"


def polar_title(s, pv):
    return f"Polar slice, θ_l = {math.degrees(s.theta_l):.0f}°, φ_l = {pv.phi_deg:.0f}°"


def polar_caption(s, pv, plot_captions):
    return s.quantity_label() + (" · " + plot_captions.get("scale", "") if plot_captions.get("scale") else "")


def albedo_caption(av):
    from ..app.drawing import albedo_caption as f

    return f(av)


def albedo_panel_title(s, plot_captions):
    return plot_captions.get("title", "")


def angles_title(s, tv):
    return f"{MODEL_LABELS[s.model]}: {s.quantity_label()} against θ_v, θ_h, θ_d"

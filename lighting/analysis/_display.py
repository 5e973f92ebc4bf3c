r"""How the analysis results show themselves: one short line of text, and a picture in a notebook.

Every result prints as one line naming its class, the model, its sample counts and its key numbers
(peak, range, albedo…), never its arrays.  In Jupyter it also shows as a picture (``_repr_png_``):

* a half-difference image as its own pixels, encoded by the engine (sRGB, :func:`lighting.render.image.png_bytes`:
  NumPy and the standard library only);
* a curve, slice, lobe, albedo curve or scan line as a small plot (``FIGSIZE`` at ``DPI``: 400 × 300
  pixels), drawn with Matplotlib, which is imported only when the picture is asked for.  Without
  Matplotlib the picture is ``None`` and the notebook shows the line of text.

So ``import lighting``, computing results and printing them never import Matplotlib.
"""

from __future__ import annotations

import io
import math
import textwrap

import numpy as np

#: Size (inches) and resolution of the plots: 400 × 300 pixels.
FIGSIZE = (4.0, 3.0)
DPI = 100
#: A result keeps its model's one-line repr up to this many characters; its own line shows the first ``MODEL_CHARS``.
MODEL_KEEP = 120
MODEL_CHARS = 60
#: A half-difference image is enlarged by a whole factor until its longer side reaches this many pixels.
IMAGE_MIN_SIDE = 256
#: A half-difference image shows this percentile of its values white (:func:`image_white`).
WHITE_PERCENTILE = 99.0
#: Pixels where the image has no value (a direction on or below the horizon): a muted blue, not any BRDF's grey.
NO_VALUE_RGB = (72, 88, 120)

_SYMBOLS = {"theta_h": "θ_h", "theta_d": "θ_d", "theta_v": "θ_v", "theta_l": "θ_l", "phi_d": "φ_d", "phi_h": "φ_h",
            "phi_l": "φ_l"}  # fmt: skip
_CHANNEL_COLOURS = ("#c62828", "#2e7d32", "#1565c0")
_LIGHT = "#e65100"
_MATH_SYMBOLS = {"theta_h": r"\theta_h", "theta_d": r"\theta_d", "theta_v": r"\theta_v", "theta_l": r"\theta_l",
                 "phi_d": r"\phi_d", "phi_h": r"\phi_h", "phi_l": r"\phi_l"}  # fmt: skip


# --------------------------------------------------------------------------- text
def num(x) -> str:
    """A number to four significant digits (``inf`` and ``nan`` as Python spells them)."""
    return f"{float(x):.4g}"


def deg(x) -> str:
    """An angle given in radians, in degrees to four significant digits."""
    return f"{math.degrees(float(x)):.4g}°"


def short(text: str, limit: int = MODEL_CHARS) -> str:
    """``text`` cut to ``limit`` characters, the cut marked by an ellipsis."""
    return text if len(text) <= limit else text[: limit - 1] + "…"


def model_label(brdf) -> str:
    """The model's short name: its one-line repr, e.g. ``Phong(ks=0.5, shininess=32)``, cut to ``MODEL_KEEP``."""
    return short(repr(brdf), MODEL_KEEP)


def quantity_label(cosine=None, log=False, channel=None) -> str:
    """What a result's values are: ``f_r``, ``f_r·(n·l)`` or ``f_r·(n·v)``, maybe ``log10(1 + …)`` and a channel."""
    q = {None: "f_r", "light": "f_r·(n·l)", "view": "f_r·(n·v)"}[cosine]
    if log:
        q = f"log10(1 + {q})"
    if channel is not None:
        q += f" [{channel}]"
    return q


def unit_label(cosine=None, log=False, channel=None) -> str:
    """The quantity with its unit, for a plot's axis: ``f_r (1/sr)``; ``log10(1 + f_r)`` has none."""
    q = quantity_label(cosine, log, channel)
    return q if log else q + " (1/sr)"


def peak(values) -> tuple[int, float]:
    """``(index, value)`` of the largest sample; an RGB sample counts by its largest channel."""
    v = np.asarray(values, dtype=np.float64)
    if v.ndim == 2:
        v = v.max(axis=-1)
    if v.size == 0:
        return 0, math.nan
    k = int(np.argmax(v))
    return k, float(v[k])


def _of(model: str) -> str:
    return f" of {short(model)}" if model else ""


def curve_repr(c) -> str:
    """One line for an :class:`~lighting.analysis.curves.AngleCurve`."""
    name = _SYMBOLS[c.variable]
    k, top = peak(c.values)
    fixed = ", ".join(f"{_SYMBOLS.get(key, key)}={deg(v)}" for key, v in c.params.items())
    q = quantity_label(c.cosine, c.log, c.channel)
    span = f"{deg(c.angles[0])} to {deg(c.angles[-1])}" if len(c.angles) else "no angles"
    valid = int(np.count_nonzero(c.valid))
    return (
        f"AngleCurve({q} against {name}{_of(c.model)}: {len(c.angles)} samples, {name} {span}, "
        f"{valid} above the horizon; {fixed}; max {num(top)} at {name}={deg(c.angles[k])})"
    )


def slice_repr(s) -> str:
    """One line for a :class:`~lighting.analysis.slices.PolarSlice`."""
    k, top = peak(s.values)
    q = quantity_label(s.cosine, s.log, s.channel)
    if s.lock:
        how = "view locked to the light"
    else:
        how = f"{s.fixed} fixed at θ={deg(s.theta_in)}, φ={deg(s.phi_in)}, {s.plane} plane"
    return (f"PolarSlice({q}{_of(s.model)}, {how}: {len(s.angles)} samples; "
            f"max {num(top)} at {deg(s.angles[k])}, mirror at {deg(s.mirror_angle)})")  # fmt: skip


def image_repr(im) -> str:
    """One line for a :class:`~lighting.analysis.halfdiff.HalfDiffImage`."""
    q = quantity_label(im.cosine, im.log, im.channel)
    shown = np.asarray(im.values, dtype=np.float64)[im.valid]
    lo, hi = (float(shown.min()), float(shown.max())) if shown.size else (math.nan, math.nan)
    nd, nh = im.valid.shape
    valid = int(np.count_nonzero(im.valid))
    return (
        f"HalfDiffImage({q}{_of(im.model)}: {nd}×{nh} (rows θ_d, columns θ_h), φ_d={deg(im.phi_d)}, "
        f"φ_h={deg(im.phi_h)}; {valid} above the horizon, range {num(lo)} to {num(hi)})"
    )


def _polar_text(d) -> str:
    d = np.asarray(d, dtype=np.float64)
    return f"θ={deg(math.atan2(math.hypot(d[0], d[1]), d[2]))}, φ={deg(math.atan2(d[1], d[0]))}"


def mesh_repr(m) -> str:
    """One line for a :class:`~lighting.analysis.meshes.LobeMesh`."""
    q = quantity_label(m.cosine, False, "luminance" if m.channel is None else m.channel)  # the radius is one number
    return (f"LobeMesh({q} lobe{_of(m.model)}, light at {_polar_text(m.light)}: {len(m.vertices)} vertices, "
            f"{len(m.faces)} faces ({m.rings} rings × {m.segments} segments); max {num(peak(m.values)[1])} toward "
            f"{_polar_text(m.peak)}, width {num(m.width)} rad)")  # fmt: skip


def _vector(d) -> str:
    return "(" + ", ".join(f"{float(x):.4g}" for x in np.asarray(d).reshape(-1)) + ")"


def lobe_peak_repr(p) -> str:
    """One line for a :class:`~lighting.analysis.lobes.LobePeak`."""
    return f"LobePeak(direction={_vector(p.direction)}, value={num(p.value)})"


def albedo_repr(a) -> str:
    """One line for a :class:`lighting.integrate.AlbedoCurve`: the largest and smallest albedo, the largest error."""
    rho = np.asarray(a.albedo, dtype=np.float64)
    if rho.size == 0:
        return f"AlbedoCurve({a.method}, no view angles)"
    top = rho.max(axis=-1)
    kmax, kmin = int(np.argmax(top)), int(np.argmin(top))
    theta = np.asarray(a.theta)
    bad = int(np.count_nonzero(a.unconverged))
    return (
        f"AlbedoCurve({a.method}, {a.samples} samples, {len(theta)} view angles {deg(theta[0])} to "
        f"{deg(theta[-1])}: ρ max {num(top[kmax])} at θ_v={deg(theta[kmax])}, min {num(top[kmin])} at "
        f"θ_v={deg(theta[kmin])}, error ≤ {num(np.max(a.error))}" + (f", {bad} unconverged)" if bad else ")")
    )


def profile_repr(p) -> str:
    """One line for a Mach-band :class:`~lighting.analysis.machband.Profile`."""
    x = np.asarray(p.x)
    if x.size == 0:
        return "Profile(no covered pixel on the row)"
    i = np.asarray(p.intensity, dtype=np.float64)
    d1 = float(np.max(np.abs(p.d1))) if np.size(p.d1) else 0.0
    d2 = float(np.max(np.abs(p.d2))) if np.size(p.d2) else 0.0
    return (
        f"Profile({x.size} pixels, columns {x[0]} to {x[-1]}: intensity {num(i.min())} to {num(i.max())}, "
        f"|ΔI| ≤ {num(d1)}, |Δ²I| ≤ {num(d2)})"
    )


def _verdict(flag: bool) -> str:
    return "pass" if flag else "FAIL"


def audit_row_repr(r) -> str:
    """One line for an :class:`~lighting.analysis.audit.AuditRow` (its note left out: ``format_table`` has it)."""
    return (
        f"AuditRow({short(r.label, 40)!r}, {short(r.params, 50)}: positive {_verdict(r.positive)} "
        f"(min f_r {num(r.min_value)}), reciprocal {_verdict(r.reciprocal)} (error {num(r.reciprocity)}), "
        f"energy {_verdict(r.energy)} (ρ max {num(r.albedo_max)} ± {num(r.albedo_error)} at "
        f"{num(r.theta_max_deg)}°))"
    )


def audit_table_repr(t) -> str:
    """One line for an :class:`~lighting.analysis.audit.AuditTable`: counts, then as many failing labels as fit."""
    failing = [r.label for r in t.rows if not r.plausible]
    head = f"AuditTable({len(t.rows)} models, {len(t.rows) - len(failing)} plausible"
    if not failing:
        return head + ")"
    names, room = [], 280 - len(head)
    for k, label in enumerate(failing):
        more = f", … {len(failing) - k} more"
        if len(", ".join([*names, label])) + len(more) > room:
            names.append(f"… {len(failing) - k} more")
            break
        names.append(label)
    return head + "; not plausible: " + ", ".join(names) + ")"


def fit_repr(f) -> str:
    """One line for a :class:`~lighting.analysis.fit.FitResult`: the fitted model and how well it fits."""
    state = "converged" if f.success else "not converged"
    return (
        f"FitResult({short(repr(f.model), 150)}: relative rms {num(f.relative_rms)}, rms {num(f.rms)} 1/sr, "
        f"{f.evaluations} evaluations, {state})"
    )


# --------------------------------------------------------------------------- pictures
def image_white(values, valid) -> float:
    """The value a half-difference image shows white: the 99th percentile of its valid values (RGB channels
    together), or their largest if that percentile is 0; 0 for an image without a positive value.

    A percentile, not the largest value, so that a blow-up at grazing angles (the slides' Phong BRDF's
    ``1/(n·l)``, Cook–Torrance's ``1/(4 (n·v)(n·l))``) does not leave the rest of the picture black.
    """
    v = np.maximum(np.asarray(values, dtype=np.float64)[valid], 0.0)
    if v.size == 0 or not v.max() > 0:
        return 0.0
    white = float(np.percentile(v, WHITE_PERCENTILE))
    return white if white > 0 else float(v.max())


def image_srgb8(values, valid) -> np.ndarray:
    """8-bit sRGB pixels of a value image, with its rows reversed (the first row of ``values`` at the bottom).

    Values are divided by :func:`image_white` and sRGB-encoded (:func:`lighting.render.image.encode_srgb8`,
    which clips at 1); negative values count as 0, one channel shows grey, and pixels where ``valid`` is
    False are ``NO_VALUE_RGB``.
    """
    from ..render.image import encode_srgb8

    v = np.asarray(values, dtype=np.float64)
    rgb = np.repeat(v[..., None], 3, axis=-1) if v.ndim == 2 else v
    rgb = np.where(valid[..., None], np.maximum(rgb, 0.0), 0.0)
    white = image_white(values, valid)
    if white > 0:
        rgb = rgb / white
    out, _ = encode_srgb8(rgb)
    out[~valid] = NO_VALUE_RGB
    return np.ascontiguousarray(out[::-1])


def image_scale(shape) -> int:
    """The whole factor a half-difference image is enlarged by in its picture (``IMAGE_MIN_SIDE``)."""
    return max(1, math.ceil(IMAGE_MIN_SIDE / max(shape)))


def image_png(rgb8) -> bytes:
    """PNG bytes of ``rgb8`` enlarged by :func:`image_scale` (each pixel a square block)."""
    from ..render.image import png_bytes

    k = image_scale(rgb8.shape[:2])
    big = np.repeat(np.repeat(rgb8, k, axis=0), k, axis=1)
    return png_bytes(np.ascontiguousarray(big))


def math_quantity(cosine=None, log=False, channel=None, *, unit=False) -> str:
    """The quantity in Matplotlib's mathtext, e.g. ``$f_r\\,(\\mathbf{n}\\cdot\\mathbf{l})$ (1/sr)``."""
    q = {None: "f_r", "light": r"f_r\,(\mathbf{n}\cdot\mathbf{l})", "view": r"f_r\,(\mathbf{n}\cdot\mathbf{v})"}[cosine]
    if log:
        q = rf"\log_{{10}}(1 + {q})"
    text = f"${q}$"
    if channel is not None:
        text += f" [{channel}]"
    return text + (" (1/sr)" if unit and not log else "")


def _fixed_text(params) -> str:
    return ", ".join(f"${_MATH_SYMBOLS.get(k, k)}$ = {math.degrees(v):.4g}°" for k, v in params.items())


def _figure(projection=None, rect=None):
    """A Matplotlib figure of ``FIGSIZE`` and one axes, drawn by Agg (pyplot's state untouched); ``(None, None)``
    without Matplotlib.  Without ``rect`` the layout is Matplotlib's constrained one."""
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
    except ImportError:
        return None, None
    fig = Figure(figsize=FIGSIZE, dpi=DPI, layout=None if rect else "constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_axes(rect, projection=projection) if rect else fig.add_subplot(projection=projection)
    return fig, ax


def _png(fig) -> bytes:
    import matplotlib

    buf = io.BytesIO()
    # A style that saves "tight" would change the size the picture promises.
    with matplotlib.rc_context({"savefig.bbox": "standard"}):
        fig.savefig(buf, format="png", dpi=DPI, facecolor="white")
    return buf.getvalue()


def _wrap(lines) -> str:
    return "\n".join(textwrap.fill(s, 70) for s in lines if s)


def _title(ax, *lines):
    ax.set_title(_wrap(lines), fontsize=7.5, loc="left")


def _fig_title(fig, *lines):
    fig.text(0.02, 0.98, _wrap(lines), fontsize=7.5, ha="left", va="top")


def _lines(ax, x, values):
    """Plot one line, or one per channel when an RGB quantity's channels differ."""
    v = np.asarray(values, dtype=np.float64)
    if v.ndim == 1 or (np.array_equal(v[:, 0], v[:, 1]) and np.array_equal(v[:, 0], v[:, 2])):
        ax.plot(x, v if v.ndim == 1 else v[:, 0], color="0.15", lw=1.4)
        return
    for c, name, colour in zip(range(3), "RGB", _CHANNEL_COLOURS, strict=True):
        ax.plot(x, v[:, c], color=colour, lw=1.3, label=name)
    ax.legend(fontsize=7, frameon=False, loc="upper right")


def curve_png(c):
    """The picture of an :class:`~lighting.analysis.curves.AngleCurve`: the values against the angle in degrees."""
    fig, ax = _figure()
    if fig is None:
        return None
    x = np.degrees(np.asarray(c.angles, dtype=np.float64))
    _lines(ax, x, c.values)
    name = f"${_MATH_SYMBOLS[c.variable]}$"
    if c.variable == "theta_v":
        t = math.degrees(c.params["theta_l"])
        ax.axvline(t, color="0.5", lw=0.8, ls="--")
        ax.axvline(-t, color=_LIGHT, lw=0.8, ls=":")
        ax.set_xlim(-90, 90)
        ax.set_xticks([-90, -60, -30, 0, 30, 60, 90])
        ax.text(t, 1.0, " mirror", transform=ax.get_xaxis_transform(), fontsize=7, color="0.4", va="top")
        ax.text(-t, 1.0, " light", transform=ax.get_xaxis_transform(), fontsize=7, color=_LIGHT, va="top")
    else:
        ax.set_xlim(0, 90)
        ax.set_xticks([0, 15, 30, 45, 60, 75, 90])
    ax.set_xlabel(f"{name} (degrees)")
    ax.set_ylabel(math_quantity(c.cosine, c.log, c.channel, unit=True))
    ax.set_ylim(bottom=0)
    ax.grid(True, color="0.9", lw=0.6)
    _title(ax, c.model, _fixed_text(c.params))
    return _png(fig)


def slice_png(s):
    """The picture of a :class:`~lighting.analysis.slices.PolarSlice`: a polar plot over the upper half-plane."""
    # The half-disc fills the width: its (square) axes reach below the picture, where nothing is drawn.
    fig, ax = _figure("polar", rect=(0.1, -0.1, 0.8, 0.8 * FIGSIZE[0] / FIGSIZE[1]))
    if fig is None:
        return None
    t = np.asarray(s.angles, dtype=np.float64)
    v = np.asarray(s.values, dtype=np.float64)
    _lines(ax, t, v)
    rmax = peak(v)[1]
    rmax = 1.1 * rmax if rmax > 0 and math.isfinite(rmax) else 1.0
    ax.set_theta_zero_location("N")
    ax.set_theta_direction(-1)
    ax.set_thetamin(-90)
    ax.set_thetamax(90)
    ax.set_ylim(0, rmax)
    ax.set_xticks(np.radians([-90, -60, -30, 0, 30, 60, 90]))
    ax.set_xticklabels(["−90°", "−60°", "−30°", "0°", "30°", "60°", "90°"], fontsize=7.5)
    from matplotlib.ticker import MaxNLocator

    ax.yaxis.set_major_locator(MaxNLocator(3))
    # A wedge draws its radial labels along a side edge: the right half of the baseline reads 0 → rmax.
    ax.tick_params(axis="y", labelsize=7, labelcolor="0.35", pad=1, labelleft=False, labelright=True, left=False,
                   right=True)  # fmt: skip
    ax.grid(True, color="0.88", lw=0.6)
    if not s.lock and s.plane == "incidence":
        ax.plot([s.incident_angle] * 2, [0, rmax], color=_LIGHT, lw=1.0, ls=":")
        ax.plot([s.mirror_angle] * 2, [0, rmax], color="0.5", lw=0.8, ls="--")

    fig.text(0.75, 0.025, math_quantity(s.cosine, s.log, s.channel, unit=True), fontsize=8, color="0.3",
             ha="center", va="bottom")  # fmt: skip
    swept = {"light": r"$\mathbf{v}$", "view": r"$\mathbf{l}$"}[s.fixed]
    if s.lock:
        how = "view locked to the light: $f_r(\\mathbf{d}, \\mathbf{d})$ for every direction $\\mathbf{d}$"
    else:
        how = f"{s.fixed} fixed at θ = {math.degrees(s.theta_in):.4g}°, {swept} swept across the {s.plane} plane"
        if s.plane == "incidence":
            how += f"; the {s.fixed} dotted, its mirror direction dashed"
    _fig_title(fig, s.model, how)
    return _png(fig)


def mesh_png(m):
    """The picture of a :class:`~lighting.analysis.meshes.LobeMesh`: the surface in 3D, coloured by value (viridis)."""
    fig, _ = _figure()
    if fig is None:
        return None
    import matplotlib
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    fig.clear()
    ax = fig.add_subplot(projection="3d")
    v = np.asarray(m.vertices, dtype=np.float64)
    values = np.asarray(m.values, dtype=np.float64)
    top = float(values.max()) if values.size and values.max() > 0 else 1.0
    colours = matplotlib.colormaps["viridis"](values[m.faces].mean(axis=1) / top)
    edges = colours.copy()
    edges[:, :3] *= 0.72  # a darker grid shows the surface's shape without lighting
    ax.add_collection3d(Poly3DCollection(v[m.faces], facecolors=colours, edgecolors=edges, linewidths=0.2))
    r = float(np.max(np.linalg.norm(v, axis=1))) if v.size else 0.0
    r = r if r > 0 else 1.0
    t = np.linspace(0, 2 * np.pi, 73)
    ax.plot(r * np.cos(t), r * np.sin(t), 0 * t, color="0.6", lw=0.8)
    ax.plot([0, 0], [0, 0], [0, 1.05 * r], color="0.2", lw=1.2)
    ax.text(0, 0, 1.12 * r, r"$\mathbf{n}$", fontsize=10, ha="center")
    ld = np.asarray(m.light, dtype=np.float64)
    ax.plot([0, ld[0] * r], [0, ld[1] * r], [0, ld[2] * r], color=_LIGHT, lw=1.6)
    ax.text(*(1.14 * r * ld), r"$\mathbf{l}$", color=_LIGHT, fontsize=10, ha="center")
    ax.set_xlim(-r, r)
    ax.set_ylim(-r, r)
    ax.set_zlim(0, r)
    ax.set_box_aspect((2, 2, 1), zoom=1.3)
    ax.view_init(elev=16, azim=-68)
    ax.set_axis_off()
    q = math_quantity(m.cosine, False, "luminance" if m.channel is None else m.channel)
    light = f"light at θ = {math.degrees(math.acos(min(max(ld[2], -1.0), 1.0))):.4g}°"
    _fig_title(fig, m.model, f"{light}; distance from the centre in each view direction: {q}, up to {num(top)} 1/sr")
    return _png(fig)


def albedo_png(a):
    """The picture of an :class:`lighting.integrate.AlbedoCurve`: ρ against the view angle, the line ρ = 1 marked."""
    fig, ax = _figure()
    if fig is None:
        return None
    x = np.degrees(np.asarray(a.theta, dtype=np.float64))
    rho = np.asarray(a.albedo, dtype=np.float64)
    _lines(ax, x, rho)
    err = np.asarray(a.error, dtype=np.float64).max(axis=-1)
    top = rho.max(axis=-1)
    band = bool(np.any(err > 1e-3 * np.maximum(np.abs(top), 1e-300)))  # a band thinner than the line is noise
    if band:
        ax.fill_between(x, top - 2 * err, top + 2 * err, color="0.6", alpha=0.35, lw=0)
    ax.axhline(1.0, color=_LIGHT, lw=0.8, ls="--")
    ax.text(0.01, 1.0, r" $\rho = 1$: energy is conserved below", transform=ax.get_yaxis_transform(), fontsize=7,
            color=_LIGHT, va="bottom")  # fmt: skip
    ax.set_xlim(0, 90)
    ax.set_xticks([0, 15, 30, 45, 60, 75, 90])
    ax.set_ylim(0, max(1.1, 1.05 * float(np.max(top)) if top.size else 1.1))
    ax.set_xlabel(r"view angle $\theta_v$ (degrees)")
    ax.set_ylabel(r"directional albedo $\rho(\theta_v)$")
    ax.grid(True, color="0.9", lw=0.6)
    _title(ax, f"directional albedo by {a.method}, {a.samples} samples" + (", 2σ band in grey" if band else ""))
    return _png(fig)


def profile_png(p):
    """The picture of a Mach-band :class:`~lighting.analysis.machband.Profile`: intensity and ``Δ²I`` along the row."""
    if np.size(p.x) == 0:
        return None
    fig, ax = _figure()
    if fig is None:
        return None
    x = np.asarray(p.x, dtype=np.float64)
    ax.plot(x, p.intensity, color="0.15", lw=1.3)
    ax.set_xlabel("pixel column")
    ax.set_ylabel(r"intensity $I$ (linear, 1 = white)")
    ax.grid(True, color="0.9", lw=0.6)
    if np.size(p.d2):
        twin = ax.twinx()
        twin.plot(x[1:-1], p.d2, color="#1565c0", lw=0.9, alpha=0.8)
        twin.set_ylabel(r"$\Delta^2 I$", color="#1565c0")
        twin.tick_params(axis="y", labelcolor="#1565c0")
    _title(
        ax, "one scan line: the intensity (black) and its second difference (blue), which jumps where the slope kinks"
    )
    return _png(fig)

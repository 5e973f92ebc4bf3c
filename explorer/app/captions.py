r"""Every text the explorer window shows, as plain functions of the controls and the views.

The window (any front end: the Qt window, the notebook) puts these strings into its labels; nothing here
imports Qt, VTK or Matplotlib, and nothing computes lighting: each function reads the
:class:`~explorer.app.state.AppState` and the view records of :class:`~explorer.app.views.ExplorerModel`
(``views``).  A plot's own words (its scale, its peak, the albedo panel's flags) come from the plot and are
passed in as ``plot_captions``.

* the window: :func:`window_title`, :data:`KEYS` (the key table, from which the window makes its actions and
  its help) and :func:`keys_help`;
* the lit sphere: :func:`sphere_title`, :func:`sphere_legend` (with the split's halves), :func:`sphere_caption`
  (clipping, an ideal mirror's note, the light, the exposure);
* the coarse spheres and the scan line: :func:`coarse_title`, :func:`coarse_caption`, :func:`phong_title`,
  :func:`phong_caption`, :func:`profile_title`, :func:`profile_caption`;
* the BRDF views: :func:`lobe_title`, :func:`lobe_caption`, :func:`polar_title`, :func:`polar_note`,
  :func:`polar_caption`, :func:`albedo_caption`, :func:`angles_title`, :func:`albedo_panel_title`;
* the lit object: :func:`object_title`, :func:`object_caption`.

The incident angle is the light's true polar angle at the facing point, ``θ_l`` in ``[0°, 180°]``
(:attr:`AppState.theta_l <explorer.app.state.AppState.theta_l>`), said to be below the horizon past 90°:
the views clamp the angle they plot at 90°, the captions do not.

Example
-------
>>> from explorer.app.state import AppState
>>> state = AppState(elevation=-36.0)
>>> incidence(state)
'θ_l = 126° (below the horizon)'
"""

from __future__ import annotations

import math
from typing import NamedTuple

from lighting.models import BRDFFlags

from .environment import ENVIRONMENT_LABELS
from .lights import lights_line
from .params import kd_label, model_label
from .state import CHANNEL_LABELS

__all__ = [
    "Key",
    "KEYS",
    "keys_help",
    "window_title",
    "channel_label",
    "incidence",
    "light_summary",
    "delta_note",
    "clipped_note",
    "exposure_note",
    "split_sides",
    "sphere_title",
    "sphere_legend",
    "sphere_caption",
    "coarse_title",
    "coarse_caption",
    "phong_title",
    "phong_caption",
    "profile_title",
    "profile_caption",
    "lobe_title",
    "lobe_caption",
    "polar_title",
    "polar_note",
    "polar_caption",
    "albedo_caption",
    "albedo_panel_title",
    "angles_title",
    "object_title",
    "object_caption",
    "kd_control_label",
]


# =============================================================================== the window
class Key(NamedTuple):
    """One row of the key table: the key (Qt's portable key-sequence text, e.g. ``"Shift+M"``) and what it does."""

    key: str
    description: str


#: The window's keys, in the help's order.  ``key`` is what ``QKeySequence(key)`` reads (letters are case-blind
#: there, so a capital is ``Shift+`` its letter); the window makes one action per row and its help from them.
KEYS: tuple[Key, ...] = (
    Key("H", "show / hide this help"),
    Key("S", "save a screenshot of the window (PNG in the current folder)"),
    Key("R", "reset every control to its default"),
    Key("M", "next reflectance model"),
    Key("Shift+M", "previous reflectance model"),
    Key("T", "next light type (directional, point, spot, ambient)"),
    Key("I", "next shading mode of the lit sphere (flat, Gouraud, Phong)"),
    Key("F", "classic I / physical radiance I/π"),
    Key("1", "ambient term on or off"),
    Key("2", "diffuse term on or off"),
    Key("3", "specular term on or off"),
    Key("C", "next plot channel (luminance Y, R, G, B)"),
    Key("L", "plots: log10(1 + x) on or off"),
    Key("N", "plots: × n·l on or off"),
    Key("E", "triangle edges on the coarse spheres on or off"),
    Key("P", "pin the current model to the Compare list"),
    Key("Shift+F", "fit the chosen analytic model to the current one (seconds)"),
    Key("A", "right panel: angle curves / albedo ρ(θ_v)"),
    Key("V", "split lit sphere: current | first shown entry, divided along the light"),
    Key("X", "next environment (none, the skies, the file)"),
    Key("O", "3D panel: BRDF lobe / lit object"),
    Key("K", "environment by the Monte-Carlo reference (refined while the view rests) / by the dominant lights"),
    Key("Up", "move the scan line up"),
    Key("Down", "move the scan line down"),
    Key("Left", "coarser coarse sphere"),
    Key("Right", "finer coarse sphere"),
    Key("Q", "quit"),
)


def keys_help() -> str:
    """The help text: every row of :data:`KEYS`, the key padded to one column, and the mouse.

    Returns
    -------
    str

    Examples
    --------
    >>> keys_help().splitlines()[0]
    'H         show / hide this help'
    """
    width = max(len(k.key) for k in KEYS) + 3
    rows = [f"{k.key:<{width}}{k.description}" for k in KEYS]
    return "\n".join(rows + ["", "Mouse: rotate the 3D lobe with the left button, zoom with the wheel."])


def window_title(state) -> str:
    """The window's title: the program and the current model (and the environment when one is chosen).

    Parameters
    ----------
    state : AppState

    Returns
    -------
    str

    Examples
    --------
    >>> from explorer.app.state import AppState
    >>> window_title(AppState())
    'lighting-explorer — Blinn-Phong'
    >>> window_title(AppState(model="ward", environment="band-limited"))
    'lighting-explorer — Ward, environment band-limited'
    """
    title = f"lighting-explorer — {model_label(state.model)}"
    if state.environment != "none":
        title += f", environment {ENVIRONMENT_LABELS[state.environment]}"
    return title


def channel_label(state) -> str:
    """The plotted channel's name (``"luminance Y"``, ``"red"``, …).

    >>> from explorer.app.state import AppState
    >>> channel_label(AppState(channel="g"))
    'green'
    """
    return CHANNEL_LABELS[state.channel]


def kd_control_label(state) -> str:
    """The label of the ``k_d`` control for the current model: what it sets (:func:`~explorer.app.params.kd_label`).

    >>> from explorer.app.state import AppState
    >>> kd_control_label(AppState())
    'k_d (diffuse albedo)'
    """
    return kd_label(state.model)


# =============================================================================== pieces
def _stops(x: float) -> str:
    """Stops with a sign and a true minus: ``"−2.3"``, ``"+1.0"``, ``"0"``."""
    x = round(float(x), 1)
    return "0" if x == 0 else f"{x:+.1f}".replace("-", "−")


def incidence(state) -> str:
    """The incident polar angle at the facing point, ``θ_l``, and whether the light is below the horizon.

    Parameters
    ----------
    state : AppState

    Returns
    -------
    str
        ``"θ_l = 45°"``, ``"θ_l = 90° (on the horizon)"`` or ``"θ_l = 126° (below the horizon)"``.

    Examples
    --------
    >>> from explorer.app.state import AppState
    >>> incidence(AppState()), incidence(AppState(elevation=0.0))
    ('θ_l = 45°', 'θ_l = 90° (on the horizon)')
    """
    theta = math.degrees(state.theta_l)
    text = f"θ_l = {theta:.0f}°"
    if theta > 90.0 + 1e-9:
        text += " (below the horizon)"
    elif theta > 90.0 - 1e-9:
        text += " (on the horizon)"
    return text


def light_summary(state) -> str:
    """The light and the equation's form and terms, two lines (the lit sphere's caption ends with it).

    Parameters
    ----------
    state : AppState

    Returns
    -------
    str

    Examples
    --------
    >>> from explorer.app.state import AppState
    >>> print(light_summary(AppState()))
    directional, elevation 45°, azimuth 135°
    classic I · ambient + diffuse + specular
    >>> print(light_summary(AppState(light="point", distance=3.0, environment="sunset", form="physical")))
    point, elevation 45°, azimuth 135°, distance 3.0 · environment sunset
    physical I/π · ambient + diffuse + specular
    """
    s = state
    light = lights_line(s)  # the key light and the scene's extra lights ("ambient light only" when neither)
    if s.environment != "none":
        light += f" · environment {ENVIRONMENT_LABELS[s.environment]}"
    terms = " + ".join(s.terms) or "no terms"
    form = "classic I" if s.form == "classic" else "physical I/π"
    return f"{light}\n{form} · {terms}"


def delta_note(state) -> str:
    """What an ideal mirror (a Dirac delta, ``BRDFFlags.DELTA``) shows under the explorer's lights; ``""`` otherwise.

    Parameters
    ----------
    state : AppState

    Returns
    -------
    str
        Two lines ending in a newline, or ``""``.

    Examples
    --------
    >>> from explorer.app.state import AppState
    >>> delta_note(AppState())
    ''
    """
    if not any(BRDFFlags.DELTA in p.flags for p in state.brdf().parts):
        return ""
    return ("ideal mirror (δ): a point or directional light shows only\n"
            "where R = v exactly (one point): black but for ambient and k_d\n")  # fmt: skip


def clipped_note(sv) -> str:
    """How much of the lit sphere the encoding clipped, with a newline; ``""`` when nothing clips.

    Parameters
    ----------
    sv : SphereView

    Returns
    -------
    str
    """
    if not sv.clipped:
        return ""
    share = 100 * sv.clipped / max(int(sv.coverage.sum()), 1)
    share = f"{share:.0f}%" if share >= 0.5 else "under 1%"
    return f"{share} of the sphere above 1: clipped (lower the exposure)\n"


def exposure_note(state, sv) -> str:
    """The display exposure when it is not 0 or was chosen for an environment; ``""`` otherwise.

    Under an environment the sphere view carries its automatic exposure
    (:attr:`~explorer.app.views.SphereView.auto_exposure`): the note says whether the control holds it.

    Parameters
    ----------
    state : AppState
    sv : SphereView

    Returns
    -------
    str
        E.g. ``"exposure −2.1 stops (automatic)"``.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> exposure_note(NS(exposure=-2.1), NS(auto_exposure=-2.1))
    'exposure −2.1 stops (automatic)'
    >>> exposure_note(NS(exposure=0.0), NS(auto_exposure=-2.1))
    'exposure 0 stops (automatic: −2.1)'
    >>> exposure_note(NS(exposure=0.0), NS(auto_exposure=None))
    ''
    """
    auto = getattr(sv, "auto_exposure", None)
    if auto is not None:
        if abs(state.exposure - auto) < 1e-9:
            return f"exposure {_stops(auto)} stops (automatic)"
        return f"exposure {_stops(state.exposure)} stops (automatic: {_stops(auto)})"
    return "" if state.exposure == 0 else f"exposure {_stops(state.exposure)} stops"


_SIDES = ("right", "upper right", "top", "upper left", "left", "lower left", "bottom", "lower right")


def split_sides(angle_deg: float) -> tuple[str, str]:
    """Where the split sphere's two halves are, in words: the current model's, then the entry's.

    The current model is on the counter-clockwise side of the divider
    (:func:`~explorer.app.split.split_mask`).

    Parameters
    ----------
    angle_deg : float
        The divider's direction (:attr:`~explorer.app.views.SphereView.split_angle`).

    Returns
    -------
    (str, str)

    Examples
    --------
    >>> split_sides(90.0), split_sides(135.0)
    (('left', 'right'), ('lower left', 'upper right'))
    """
    k = round((angle_deg + 90.0) / 45.0) % 8
    return _SIDES[k], _SIDES[(k + 4) % 8]


# =============================================================================== the lit sphere
def sphere_title(state, sv=None) -> str:
    """The lit sphere's title.

    >>> from explorer.app.state import AppState
    >>> sphere_title(AppState(model="cook-torrance"))
    'Lit sphere (engine): Cook-Torrance'
    """
    return f"Lit sphere (engine): {model_label(state.model)}"


def sphere_legend(state, sv) -> str:
    """How the sphere is shaded, and the split's halves when it is split.

    Parameters
    ----------
    state : AppState
    sv : SphereView

    Returns
    -------
    str
        E.g. ``"per pixel, exact sphere · arrow: the key light"``; split: ``"split along the light: lower left
        current · upper right ▸ <entry>"`` first.
    """
    where = "per pixel, exact sphere" if sv.mode == "phong" else f"{sv.mode}, {sv.geometry}"
    marks = (["arrow: the key light"] if state.light != "ambient" else []) + (
        ["squares: the scene's lights"] if state.scene_lights else [])
    legend = " · ".join([where, *marks])
    if sv.split:
        mine, other = split_sides(sv.split_angle)
        legend = f"split along the light: {mine} current · {other} ▸ {sv.split}\n" + legend
    return legend


def sphere_caption(state, sv, model=None, *, clipping: bool = True) -> str:
    """The lit sphere's caption: clipping, an ideal mirror's note, the light, the exposure, the reference.

    Parameters
    ----------
    state : AppState
    sv : SphereView
    model : ExplorerModel, optional
        For the progressive reference's line (:meth:`~explorer.app.environment.EnvironmentMixin.refine_caption`).
    clipping : bool
        Start with :func:`clipped_note` (a front end that shows it as a warning of its own passes False).

    Returns
    -------
    str
        Lines joined by newlines.
    """
    text = (clipped_note(sv) if clipping else "") + delta_note(state) + light_summary(state)
    exposure = exposure_note(state, sv)
    if exposure:
        text += "\n" + exposure
    refine = model.refine_caption() if model is not None and state.reference else ""
    return text + ("\n" + refine if refine else "")


# =============================================================================== coarse spheres, scan line
def coarse_title(state=None) -> str:
    """The Gouraud sphere's title."""
    return "Gouraud: lit at the vertices"


def coarse_caption(cv) -> str:
    """The Gouraud sphere's caption: its triangles and vertices.

    Parameters
    ----------
    cv : CoarseView

    Returns
    -------
    str
    """
    return (f"{cv.n_triangles} triangles, {len(cv.vertices)} vertices: engine colours\n"
            "interpolated across each triangle")  # fmt: skip


def phong_title(state=None) -> str:
    """The Phong-interpolated coarse sphere's title."""
    return "Phong interpolation: lit per pixel"


def phong_caption(state=None) -> str:
    """The Phong-interpolated coarse sphere's caption."""
    return "normals interpolated, engine lights each pixel\nred line: the scan line"


def profile_title(state) -> str:
    """The scan line's title, with the plotted channel.

    >>> from explorer.app.state import AppState
    >>> profile_title(AppState())
    'Scan line: intensity (luminance Y)'
    """
    return f"Scan line: intensity ({CHANNEL_LABELS[state.channel]})"


def profile_caption(pv) -> str:
    """The Mach-band metric of both interpolations (:func:`lighting.analysis.machband.edge_jump_metric`).

    Parameters
    ----------
    pv : ProfileView

    Returns
    -------
    str
    """
    return f"Mach-band metric (slope kinks): Gouraud {pv.metric_gouraud:.2f}, Phong {pv.metric_phong:.2f}"


# =============================================================================== BRDF views
def lobe_title(state, lv) -> str:
    """The 3D lobe's title: the lobe or, with the view lock, the retro-reflection lobe; and the quantity."""
    kind = "retro-reflection lobe f(d, d), view lock" if lv.lock else "3D lobe"
    return f"{kind}: {state.quantity_label()}"


def lobe_caption(state, lv) -> str:
    """The 3D lobe's caption: where the light is (its true ``θ_l``), the peak, an ideal mirror's spike.

    Parameters
    ----------
    state : AppState
    lv : LobeView

    Returns
    -------
    str
        Two lines (three with a δ spike); "nothing reflected" when the light is below the horizon
        and the view is not locked (the retro-reflection needs no light above it).
    """
    nothing = " · nothing reflected" if lv.below_horizon and not lv.lock else ""
    delta = f"\nδ spike: ideal mirror, R = {lv.spike:.3g}" if lv.spike > 0 else ""
    return (f"light l at {incidence(state)}, φ_l = {state.phi:.0f}° (yellow), mirror (red); t = +x\n"
            f"peak {lv.peak:.3g}, radius scaled to fit{nothing}{delta}")  # fmt: skip


def polar_title(state, pv) -> str:
    """The polar slice's title: the plane of incidence and the light's true ``θ_l``, or the retro-reflection.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> from explorer.app.state import AppState
    >>> polar_title(AppState(elevation=-36.0), NS(lock=False, phi_deg=180.0))
    'Polar slice, θ_l = 126° (below the horizon), φ_l = 180°'
    """
    if pv.lock:
        return f"Retro-reflection f(d, d) (view lock), φ = {pv.phi_deg:.0f}°"
    return f"Polar slice, {incidence(state)}, φ_l = {pv.phi_deg:.0f}°"


def polar_note(state, pv) -> str:
    """The polar slice's note on a light below the horizon, saying what the plot shows.

    Without the view lock nothing is reflected and the curves are 0.  With it, the plot is
    ``f(d, d)`` over the view (and light) direction ``d``, which the key light's place does not enter:
    drawn all the same.

    Parameters
    ----------
    state : AppState
    pv : PolarView

    Returns
    -------
    str
        ``""`` when the light is above the horizon.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> polar_note(None, NS(below_horizon=True, lock=False))
    'light below the horizon:\\nnothing reflected'
    >>> polar_note(None, NS(below_horizon=True, lock=True))
    'light below the horizon; the view lock\\ndraws f(d, d), which needs no light above it'
    """
    if not pv.below_horizon:
        return ""
    if pv.lock:
        return "light below the horizon; the view lock\ndraws f(d, d), which needs no light above it"
    return "light below the horizon:\nnothing reflected"


def polar_caption(state, pv, plot_captions=None) -> str:
    """What the polar slice plots: the quantity, the plot's scale, and the Compare list's colours.

    Parameters
    ----------
    state : AppState
    pv : PolarView
    plot_captions : dict, optional
        The plot's own words (``"scale"``).

    Returns
    -------
    str
    """
    scale = (plot_captions or {}).get("scale", "")
    text = state.quantity_label() + (f" · {scale}" if scale else "")
    if pv.overlays:
        text += " · colours: Compare list"
    return text


def albedo_caption(av) -> str:
    """The text of the albedo readout of an :class:`~explorer.app.views.AlbedoView`.

    >>> from explorer.app.views import AlbedoView
    >>> albedo_caption(AlbedoView(0.5, 0.8123, 2e-5, 2.5e-5, False, None, None, "quadrature", 4096))
    'albedo ρ(θ_v = 29°) = 0.8123 ± 2e-05'
    >>> albedo_caption(AlbedoView(0.5, 1.2, 0.05, 0.042, True, None, None, "quadrature", 4096))
    'albedo ρ(θ_v = 29°) = 1.2 ± 0.05  unconverged (4.2 % > 2 %)  above 1: not energy conserving'
    >>> albedo_caption(AlbedoView(0.5, 1.05, 0.05, 0.048, True, None, None, "quadrature", 4096))  # 1 within 2σ
    'albedo ρ(θ_v = 29°) = 1.05 ± 0.05  unconverged (4.8 % > 2 %)'
    >>> albedo_caption(AlbedoView(0.785, 1.365, 3e-8, 2e-8, False, None, None, "quadrature", 4096))
    'albedo ρ(θ_v = 45°) = 1.365 ± 3e-08  above 1: not energy conserving'

    Parameters
    ----------
    av : AlbedoView
        The albedo view.

    Returns
    -------
    str
        ``albedo ρ(θ_v = …°) = value ± error``, with "unconverged (…)" above 2 % relative error and
        "above 1: not energy conserving" (the plausibility audit's criterion,
        :mod:`lighting.analysis.audit`) when the value exceeds 1 by more than twice its error; a
        channel above 1 while the plotted value is not is named ("red above 1: …").
    """
    text = f"albedo ρ(θ_v = {math.degrees(av.theta_v):.0f}°) = {av.value:.4g} ± {av.error:.2g}"
    if av.unconverged:
        rel = f"{100 * av.relative_error:.2g} %" if math.isfinite(av.relative_error) else "no digit"
        text += f"  unconverged ({rel} > 2 %)"
    if av.above_one:
        text += "  above 1: not energy conserving"
    elif av.channels_above_one:
        names = " and ".join(CHANNEL_LABELS[c] for c in av.channels_above_one)
        text += f"  {names} above 1: not energy conserving"
    return text


def angles_title(state, tv) -> str:
    """The angle curves' title: the model, the quantity, and whose colours the other curves are.

    Parameters
    ----------
    state : AppState
    tv : CurveView
        The θ_v curve (its overlays say whether the Compare list is drawn).

    Returns
    -------
    str
    """
    white = " (white; colours: Compare list)" if tv.overlays else ""
    return f"{model_label(state.model)}{white}: {state.quantity_label()} against θ_v, θ_h, θ_d (Rusinkiewicz)"


def albedo_panel_title(state, plot_captions=None) -> str:
    """The albedo panel's title: the plot's own title and the plotted channel.

    Parameters
    ----------
    state : AppState
    plot_captions : dict, optional
        The plot's own words (``"title"``).

    Returns
    -------
    str
    """
    title = (plot_captions or {}).get("title", "") or "Albedo ρ(θ_v)"
    return f"{title}  [{CHANNEL_LABELS[state.channel]}]"


# =============================================================================== the lit object
def object_title(state, ov) -> str:
    """The lit object's title: its triangles."""
    return f"Lit object (engine): {ov.triangles} triangles, Phong normals"


def object_caption(state, ov, model=None) -> str:
    """How the object is lit: the environment (or none) and the method; the reference's progress with ``model``.

    Parameters
    ----------
    state : AppState
    ov : ObjectView
    model : ExplorerModel, optional
        For the reference's line.

    Returns
    -------
    str
    """
    if ov.method == "key light":
        env = ("no environment file given (--environment FILE)" if state.environment == "file"
               else "no environment (key + ambient light)")  # fmt: skip
    elif state.environment == "file":
        env = "environment file"
    else:
        env = f"sky {ENVIRONMENT_LABELS[state.environment]}"
    text = f"{env} · {ov.method}"
    refine = model.refine_caption() if model is not None else ""
    return text + ("\n" + refine if refine else "")

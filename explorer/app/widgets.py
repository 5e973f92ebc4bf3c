"""Sliders and check boxes: their specifications and the plumbing between VTK widgets and the state.

:class:`SliderSpec` maps a control to a slider (range, log scale, choices, title);
:data:`SLIDER_COLUMNS` is the control panel.  :class:`WidgetsMixin` (a part of
:class:`~explorer.app.window.ExplorerApp`) builds the widgets and keeps them in step with the state.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from lighting._numeric import check_range

from .layout import ACCENT, CONTROLS_PANEL, MUTED, TEXT
from .state import (
    ATTENUATIONS,
    CHANNEL_LABELS,
    CHANNELS,
    CONTROLS,
    FORMS,
    LIGHT_COLOURS,
    LIGHT_TYPES,
    MODEL_LABELS,
    MODELS,
    TERM_NAMES,
)

__all__ = ["SliderSpec", "SLIDER_COLUMNS", "SLIDERS", "CHECKBOXES", "WidgetsMixin"]


# =============================================================================== sliders
class SliderSpec:
    """One slider: which control, its range in slider units, and how to show the value.

    An integer control (``CONTROLS[name].kind == "int"``) spans its control's whole range unless
    told otherwise, and :meth:`from_slider` snaps the widget's float to the nearest integer.
    """

    def __init__(self, name, label, lo=None, hi=None, *, log=False, choices=None, fmt="{:.2f}", unit=""):
        self.name, self.label = name, label
        # A sequence is kept as it is: the model list follows the registry (a window built after a
        # model was registered offers it); anything else is frozen into a tuple.
        self.choices = None if choices is None else choices if isinstance(choices, Sequence) else tuple(choices)
        self.log = log
        control = CONTROLS.get(name)
        self.integer = control is not None and control.kind == "int"
        if self.choices is None and self.integer:
            lo = control.lo if lo is None else lo
            hi = control.hi if hi is None else hi
        self._range = None if self.choices is not None else (float(lo), float(hi))
        self.fmt, self.unit = fmt, unit

    @property
    def lo(self) -> float:
        """The slider's lowest position (0 for choices: their index)."""
        return 0.0 if self._range is None else self._range[0]

    @property
    def hi(self) -> float:
        """The slider's highest position (the last index for choices)."""
        return float(len(self.choices) - 1) if self._range is None else self._range[1]

    def to_slider(self, value) -> float:
        """The slider position that shows ``value``.

        Parameters
        ----------
        value
            A control value (a choice, or a number).

        Returns
        -------
        float
            The slider position (an index for choices, log10 for log sliders), within the range.
        """
        if self.choices is not None:
            return float(self.choices.index(value)) if value in self.choices else 0.0
        if self.log:
            return min(max(math.log10(max(float(value), 10.0**self.lo)), self.lo), self.hi)
        return min(max(float(value), self.lo), self.hi)

    def from_slider(self, x: float):
        """The control value at slider position ``x`` (a float, as VTK reports it; clamped to the range).

        Choices and integer controls snap to the nearest allowed value (ties upward): a float from
        a widget is a position, not a user's error.

        Parameters
        ----------
        x : float
            The slider position.

        Returns
        -------
        str, int or float
            The control value.
        """
        x = check_range(f"{self.name} slider position", x)
        x = min(max(x, self.lo), self.hi)
        if self.choices is not None:
            return self.choices[int(math.floor(x + 0.5))]
        if self.integer:
            return int(math.floor(x + 0.5))
        if self.log:
            return 10.0**x
        return x

    def title(self, value) -> str:
        """The slider's title showing ``value``.

        Parameters
        ----------
        value
            The control value.

        Returns
        -------
        str
            E.g. ``"k_d = 0.80"`` or ``"model: Blinn-Phong"``.
        """
        if self.choices is not None:
            shown = _CHOICE_LABELS.get(self.name, {}).get(value, value)
            return f"{self.label}: {shown}"
        if self.log:
            v = float(value)
            text = f"{v:.3g}" if v < 1e5 else f"{v:.0e}"
        else:
            text = self.fmt.format(value)
        return f"{self.label} = {text}{self.unit}"


_CHOICE_LABELS = {
    "model": MODEL_LABELS,
    "channel": CHANNEL_LABELS,
    "mode": {"flat": "flat (per face)", "gouraud": "Gouraud (per vertex)", "phong": "Phong (per pixel)"},
    "form": {"classic": "classic I", "physical": "physical I/π"},
}

#: The control panel: five columns of sliders (top to bottom).
SLIDER_COLUMNS = (
    (
        "Light",
        (
            SliderSpec("light", "light", choices=LIGHT_TYPES),
            SliderSpec("elevation", "elevation", -90, 90, fmt="{:.0f}", unit="°"),
            SliderSpec("azimuth", "azimuth", -180, 180, fmt="{:.0f}", unit="°"),
            SliderSpec("intensity", "intensity", 0, 4, fmt="{:.2f}"),
            SliderSpec("light_color", "light colour", choices=tuple(LIGHT_COLOURS) + ("custom",)),
        ),
    ),
    (
        "Ambient, point and spot",
        (
            SliderSpec("ambient", "ambient I_a", 0, 1, fmt="{:.2f}"),
            SliderSpec("distance", "point/spot distance", 1.5, 12, fmt="{:.1f}"),
            SliderSpec("attenuation", "falloff", choices=tuple(ATTENUATIONS)),
            SliderSpec("cutoff", "spot cutoff", 0, 90, fmt="{:.0f}", unit="°"),
            SliderSpec("spot_exponent", "spot exponent", 0, 128, fmt="{:.0f}"),
        ),
    ),
    (
        "Material",
        (
            SliderSpec("model", "model", choices=MODELS),
            SliderSpec("kd", "k_d", 0, 1),
            SliderSpec("ks", "k_s", 0, 1),
            SliderSpec("shininess", "shininess e", 0, 6, log=True),
            SliderSpec("roughness", "roughness α (Cook-Torrance)", -4, 0, log=True),
        ),
    ),
    (
        "Shading",
        (
            SliderSpec("f0", "F0 (Cook-Torrance)", 0, 1),
            SliderSpec("mode", "lit sphere", choices=("flat", "gouraud", "phong")),
            SliderSpec("form", "form", choices=FORMS),
            SliderSpec("tessellation", "coarse sphere bands", fmt="{:.0f}"),  # the control's range, 3 … 64
            SliderSpec("exposure", "exposure", -4, 4, fmt="{:+.1f}", unit=" stops"),
        ),
    ),
    ("Terms and plots", (SliderSpec("channel", "plot channel", choices=CHANNELS),)),
)
SLIDERS = {spec.name: spec for _, column in SLIDER_COLUMNS for spec in column}
#: Check boxes of the "Plots" column: (key, label).
CHECKBOXES = (
    ("ambient", "ambient term"),
    ("diffuse", "diffuse term"),
    ("specular", "specular term"),
    ("log", "log10(1 + x)"),
    ("times_cos", "× n·l"),
)


def _light_colour_name(rgb) -> str:
    for name, c in LIGHT_COLOURS.items():
        if np.allclose(c, rgb):
            return name
    return "custom"


class WidgetsMixin:
    """The control panel's widgets: built from :data:`SLIDER_COLUMNS` and :data:`CHECKBOXES`, kept in step."""

    def _build_controls(self):
        self._renderer(CONTROLS_PANEL)
        ncol = len(SLIDER_COLUMNS)
        width = 1.0 / ncol
        top, step = 0.8, 0.168
        style = self.pv.global_theme.slider_styles.modern
        for c, (header, specs) in enumerate(SLIDER_COLUMNS):
            x0 = c * width
            self._text(CONTROLS_PANEL, f"header{c}", header, x0 + 0.012, 0.97, size=10.5, color=ACCENT, bold=True)
            for r, spec in enumerate(specs):
                y = top - r * step
                self._add_slider(spec, (x0 + 0.018, y), (x0 + width - 0.02, y), style)
        self._text(CONTROLS_PANEL, "hint", "keys: h help · s screenshot · r reset", 1 - 0.006, 0.03, size=9,
                   color=MUTED, align="right", valign="bottom")  # fmt: skip
        # Check boxes under the channel slider, in the last column: terms left, plot options right.
        w, h = self.window_size
        vp_w = w
        vp_h = self._row_frac[2] * h
        box = max(10, round(13 * self.ui_scale))
        for k, (key, label) in enumerate(CHECKBOXES):
            sub, row = (0, k) if k < 3 else (1, k - 3)
            x_px = int(((ncol - 1) * width + 0.016 + sub * 0.52 * width) * vp_w)
            y_px = int((0.56 - row * 0.17) * vp_h)
            widget = self.plotter.add_checkbox_button_widget(
                self._checkbox_callback(key), value=self._checkbox_value(key), position=(x_px, y_px), size=box,
                border_size=2, color_on=ACCENT, color_off=(0.25, 0.26, 0.3), background_color=MUTED,
            )  # fmt: skip
            self.checkboxes[key] = widget
            self._text(CONTROLS_PANEL, f"check_{key}", label, (x_px + box + 6) / vp_w, (y_px + box / 2) / vp_h,
                       size=9.5, valign="center")  # fmt: skip

    def _add_slider(self, spec, a, b, style):
        value = self._state_value(spec.name)
        widget = self.plotter.add_slider_widget(
            self._slider_callback(spec.name), [spec.lo, spec.hi], value=spec.to_slider(value),
            title=spec.title(value), pointa=a, pointb=b, interaction_event="always", style="modern",
            title_height=0.05, title_color=TEXT, color=TEXT, slider_width=0.028, tube_width=0.006,
        )  # fmt: skip
        rep = widget.GetRepresentation()
        rep.ShowSliderLabelOff()
        rep.SetSliderLength(0.022)
        rep.SetEndCapLength(0.0)
        rep.GetTubeProperty().SetColor(0.4, 0.42, 0.47)
        rep.GetSliderProperty().SetColor(*ACCENT)
        rep.GetSelectedProperty().SetColor(1.0, 1.0, 1.0)
        tp = rep.GetTitleProperty()
        tp.SetBold(False)
        tp.SetShadow(False)
        if self.font:
            import vtk

            tp.SetFontFamily(vtk.VTK_FONT_FILE)
            tp.SetFontFile(self.font)
        if spec.choices is not None or spec.integer:  # the knob comes to rest on the value chosen
            widget.AddObserver("EndInteractionEvent", self._snap_callback(spec.name))
        widget.AddObserver("EndInteractionEvent", self._release_callback(spec.name))
        self.sliders[spec.name] = widget

    # ------------------------------------------------------------------ widget plumbing
    def _state_value(self, name):
        if name == "light_color":
            return _light_colour_name(self.state.light_color)
        return getattr(self.state, name)

    def _checkbox_value(self, key) -> bool:
        return key in self.state.terms if key in TERM_NAMES else bool(getattr(self.state, key))

    def _slider_callback(self, name):
        def callback(value):
            if not self._building:
                self.on_slider(name, value, live=True)

        return callback

    def _release_callback(self, name):
        def release(widget, event):
            # The widget renders after this event: bring the views the drag left behind up to date.
            if not self._building:
                self.flush(render=False)

        return release

    def _snap_callback(self, name):
        def snap(widget, event):
            spec = SLIDERS[name]
            widget.GetRepresentation().SetValue(spec.to_slider(self._state_value(name)))

        return snap

    def _checkbox_callback(self, key):
        def callback(flag):
            if self._building:
                return
            # The button widget renders after calling back.
            if key in TERM_NAMES:
                terms = set(self.state.terms)
                terms = terms | {key} if flag else terms - {key}
                self.set_control("terms", tuple(terms), render=False)
            else:
                self.set_control(key, bool(flag), render=False)

        return callback

    def _sync_widgets(self):
        """Make every slider and check box show the state (after keys, reset, or programmatic changes)."""
        for name, widget in self.sliders.items():
            spec = SLIDERS[name]
            value = self._state_value(name)
            rep = widget.GetRepresentation()
            target = spec.to_slider(value)
            current = rep.GetValue()
            same = spec.from_slider(current) == value if spec.choices is not None else math.isclose(
                spec.from_slider(current), float(value), rel_tol=1e-9, abs_tol=1e-9
            )  # fmt: skip
            if not same:
                rep.SetValue(target)
            rep.SetTitleText(spec.title(value))
        for key, widget in self.checkboxes.items():
            rep = widget.GetRepresentation()
            want = 1 if self._checkbox_value(key) else 0
            if rep.GetState() != want:
                rep.SetState(want)

"""The control panel: sliders, button groups and check boxes, and the plumbing between VTK widgets and the state.

:class:`SliderSpec` maps a number to a slider (range, log scale, title); :data:`PANEL` lays out the
fixed controls in columns; a choice among names (the model, the light type, its colour, the falloff,
the shading mode, the form, the plot channel) is a group of buttons of which one is on
(:data:`BUTTON_GROUPS`).  The model's own controls are generated from its parameter table
(:mod:`explorer.app.params`) and rebuilt when the model changes (:mod:`explorer.app.modelcontrols`).
:class:`WidgetsMixin` (a part of :class:`~explorer.app.window.ExplorerApp`) builds the widgets and
keeps them in step with the state.
"""

from __future__ import annotations

import math

import numpy as np

from lighting._numeric import check_range

from .comparepanel import ComparePanelMixin
from .layout import ACCENT, CONTROLS_PANEL, MUTED, TEXT
from .modelcontrols import ModelControlsMixin, ParamSliderSpec, button_width
from .state import (
    ATTENUATIONS,
    CHANNELS,
    CONTROLS,
    ENVIRONMENTS,
    FIT_MODELS,
    FORMS,
    LIGHT_COLOURS,
    LIGHT_TYPES,
    MODELS,
    VIEWS_3D,
)

__all__ = ["SliderSpec", "ParamSliderSpec", "PANEL", "SLIDERS", "BUTTON_GROUPS", "CHECKBOXES", "WidgetsMixin"]


# =============================================================================== sliders
class SliderSpec:
    """One slider: which control, its range in slider units, and how to show the value.

    An integer control (``CONTROLS[name].kind == "int"``) spans its control's whole range unless
    told otherwise, and :meth:`from_slider` snaps the widget's float to the nearest integer.
    """

    def __init__(self, name, label, lo=None, hi=None, *, log=False, fmt="{:.2f}", unit=""):
        self.name, self.label = name, label
        self.log = log
        control = CONTROLS.get(name)
        self.integer = control is not None and control.kind == "int"
        if self.integer:
            lo = control.lo if lo is None else lo
            hi = control.hi if hi is None else hi
        self.lo, self.hi = float(lo), float(hi)
        self.fmt, self.unit = fmt, unit

    def to_slider(self, value) -> float:
        """The slider position that shows ``value`` (log10 for log sliders), within the range.

        Parameters
        ----------
        value : float
            A control value.

        Returns
        -------
        float
            The slider position.
        """
        if self.log:
            return min(max(math.log10(max(float(value), 10.0**self.lo)), self.lo), self.hi)
        return min(max(float(value), self.lo), self.hi)

    def from_slider(self, x: float):
        """The control value at slider position ``x`` (a float, as VTK reports it; clamped to the range).

        Integer controls snap to the nearest integer (ties upward): a float from a widget is a
        position, not a user's error.

        Parameters
        ----------
        x : float
            The slider position.

        Returns
        -------
        int or float
            The control value.
        """
        x = check_range(f"{self.name} slider position", x)
        x = min(max(x, self.lo), self.hi)
        if self.integer:
            return int(math.floor(x + 0.5))
        if self.log:
            return 10.0**x
        return x

    def title(self, value) -> str:
        """The slider's title showing ``value``, e.g. ``"k_d = 0.80"``.

        Parameters
        ----------
        value : float
            The control value.

        Returns
        -------
        str
        """
        if self.log:
            v = float(value)
            text = f"{v:.3g}" if v < 1e5 else f"{v:.0e}"
        else:
            text = self.fmt.format(value)
        return f"{self.label} = {text}{self.unit}"


#: Button groups: control → (caption, options, labels).  One button of a group is on: the control's value.
BUTTON_GROUPS = {
    "model": ("", MODELS, None),
    "light": ("light", LIGHT_TYPES, None),
    "light_color": ("colour", tuple(LIGHT_COLOURS) + ("custom",), None),
    "attenuation": ("falloff", tuple(ATTENUATIONS), {"inverse-square": "1/r²", "linear": "1/r", "none": "none"}),
    "mode": ("lit sphere", ("flat", "gouraud", "phong"), {"flat": "flat", "gouraud": "Gouraud", "phong": "Phong"}),
    "form": ("form", FORMS, {"classic": "classic I", "physical": "physical I/π"}),
    "channel": ("plots", CHANNELS, {"luminance": "Y", "r": "R", "g": "G", "b": "B"}),
    "fit": ("fit", tuple(FIT_MODELS), None),
    "panel": ("right", ("angles", "albedo"), {"angles": "angles", "albedo": "albedo ρ"}),
    "environment": ("", ENVIRONMENTS, None),  # the engine's names, as explorer.app.environment.ENVIRONMENT_LABELS
    "view3d": ("3D", VIEWS_3D, None),
}

#: The fixed part of the control panel: columns (left edge, right edge, header, items).  An item is
#: ``("slider", SliderSpec)``, ``("buttons", control)`` or ``("checks", ((key, label), ...))``; the
#: model's own controls fill the column whose items are ``("model controls",)``, the comparison list's rows
#: the column whose last item is ``("compare list",)``.
PANEL = (
    (0.0, 0.11, "Model", (("buttons", "model"),)),
    (0.11, 0.26, "Light", (
        ("buttons", "light"),
        ("slider", SliderSpec("elevation", "elevation", -90, 90, fmt="{:.0f}", unit="°")),
        ("slider", SliderSpec("azimuth", "azimuth", -180, 180, fmt="{:.0f}", unit="°")),
        ("slider", SliderSpec("intensity", "intensity", 0, 4, fmt="{:.2f}")),
        ("buttons", "light_color"),
    )),
    (0.26, 0.375, "Ambient, point and spot", (
        ("slider", SliderSpec("ambient", "ambient I_a", 0, 1, fmt="{:.2f}")),
        ("slider", SliderSpec("distance", "point/spot distance", 1.5, 12, fmt="{:.1f}")),
        ("buttons", "attenuation"),
        ("slider", SliderSpec("cutoff", "spot cutoff", 0, 90, fmt="{:.0f}", unit="°")),
        ("slider", SliderSpec("spot_exponent", "spot exponent", 0, 128, fmt="{:.0f}")),
    )),
    (0.375, 0.485, "Environment", (
        ("buttons", "environment"),
        ("slider", SliderSpec("env_rotation", "rotation", -180, 180, fmt="{:.0f}", unit="°")),
        ("slider", SliderSpec("env_intensity", "intensity", 0, 4, fmt="{:.2f}")),
        ("buttons", "view3d"),
        ("checks", (("reference", "reference (MC)"),)),
    )),
    (0.485, 0.71, "Material", (("model controls",),)),
    (0.71, 0.87, "Shading and plots", (
        ("buttons", "mode"),
        ("buttons", "form"),
        ("slider", SliderSpec("tessellation", "coarse sphere bands", fmt="{:.0f}")),  # the control's range, 3 … 64
        ("slider", SliderSpec("exposure", "exposure", -4, 4, fmt="{:+.1f}", unit=" stops")),
        ("buttons", "channel"),
        ("slider", SliderSpec("phi", "BRDF views: light azimuth φ_l", -180, 180, fmt="{:.0f}", unit="°")),
        ("checks", (("lock", "view lock (retro)"), ("log", "log10(1+x)"), ("times_cos", "× n·l"))),
        ("checks", (("ambient", "ambient"), ("diffuse", "diffuse"), ("specular", "specular"))),
    )),
    (0.87, 1.0, "Compare", (
        ("actions", (("pin", "pin"), ("fit", "fit"))),
        ("checks", (("split", "split sphere"),)),
        ("buttons", "fit"),
        ("buttons", "panel"),
        ("compare list",),
    )),
)  # fmt: skip
#: The caption key of the Material column's header (its text names the model).
MATERIAL_HEADER = f"header{next(i for i, c in enumerate(PANEL) if c[3] == (('model controls',),))}"
#: The ``k_d`` slider heads the model's column: the explorer's diffuse albedo (or the model's own diffuse colour).
KD_SLIDER = SliderSpec("kd", "k_d (diffuse albedo)", 0, 1)
SLIDERS = {spec.name: spec for *_, items in PANEL for kind, *rest in items if kind == "slider" for spec in rest}
SLIDERS["kd"] = KD_SLIDER
#: Check boxes: key → label (the terms of the illumination equation and the plot options).
CHECKBOXES = {k: label for *_, items in PANEL for kind, *rest in items if kind == "checks" for k, label in rest[0]}

#: Heights in pixels at the design height: a slider's slot, a row of buttons, a button's box.
SLIDER_STEP, ROW_STEP, BOX = 31.0, 17.0, 11.0


def _light_colour_name(rgb) -> str:
    for name, c in LIGHT_COLOURS.items():
        if np.allclose(c, rgb):
            return name
    return "custom"


class WidgetsMixin(ModelControlsMixin, ComparePanelMixin):
    """The control panel's widgets: built from :data:`PANEL`, kept in step with the state."""

    def _build_controls(self):
        self._renderer(CONTROLS_PANEL)
        self.buttons: dict = {}  # control → {option: widget}
        self._param_widgets: list = []
        self._param_specs: dict = {}
        w, h = self.window_size
        self._panel_w, self._panel_h = w, self._row_frac[2] * h
        for c, (x0, x1, header, items) in enumerate(PANEL):
            self._text(CONTROLS_PANEL, f"header{c}", header, x0 + 0.008, 0.985, size=10.5, color=ACCENT, bold=True)
            y = 17.0 * self.ui_scale  # pixels below the panel's top
            for kind, *rest in items:
                if kind == "slider":
                    y = self._place_slider(rest[0], x0, x1, y)
                elif kind == "buttons":
                    y = self._place_buttons(rest[0], x0, x1, y)
                elif kind == "checks":
                    y = self._place_checks(rest[0], x0, x1, y)
                elif kind == "actions":
                    y = self._place_actions(rest[0], x0, x1, y)
                elif kind == "compare list":
                    self._compare_column = (x0, x1, y)
                    self._build_compare_rows()
                else:
                    self._model_column = (x0, x1, y)
                    self._build_model_controls()
        self._text(CONTROLS_PANEL, "hint", "keys: h help · s screenshot · r reset", 1 - 0.006, 0.012, size=8.5,
                   color=MUTED, align="right", valign="bottom")  # fmt: skip

    # ------------------------------------------------------------------ placing widgets
    def _px(self, x_frac) -> float:
        return x_frac * self._panel_w

    def _place_slider(self, spec, x0, x1, y, *, store=None, key=None):
        """A slider whose title sits at ``y`` pixels below the panel's top; returns the next free ``y``."""
        s = self.ui_scale
        bar = 1.0 - (y + 7.0 * s) / self._panel_h  # VTK draws the title under the bar
        widget = self._add_slider(spec, key or spec.name, (x0 + 0.012, bar), (x1 - 0.014, bar))
        (store if store is not None else self.sliders)[key or spec.name] = widget
        return y + SLIDER_STEP * s

    def _button(self, callback, on, x_px, y_px, color_on=ACCENT, color_off=(0.25, 0.26, 0.3)):
        box = max(8, round(BOX * self.ui_scale))
        return self.plotter.add_checkbox_button_widget(
            callback, value=on, position=(int(x_px), int(y_px)), size=box, border_size=2, color_on=color_on,
            color_off=color_off, background_color=MUTED,
        )  # fmt: skip

    def _flow(self, entries, x0, x1, y, caption="", prefix=""):
        """Lay out ``(key, label, make)`` entries left to right, wrapping; ``make(x_px, y_px)`` adds a button.

        Returns the widgets and the next free ``y``.
        """
        s = self.ui_scale
        left, right = self._px(x0 + 0.008), self._px(x1 - 0.006)
        x = left
        row_y = y
        texts = []
        if caption:
            texts.append((f"{prefix}cap", caption, x, row_y, MUTED))
            x += button_width(caption, s, box=False)
        widgets = {}
        for key, label, make in entries:
            width = button_width(label, s)
            if x + width > right and x > left + (button_width(caption, s, box=False) if caption else 0) + 1:
                row_y += ROW_STEP * s
                x = left + (button_width(caption, s, box=False) if caption else 0)
            y_px = self._panel_h - row_y - (BOX + 2.0) * s
            widgets[key] = make(x, y_px)
            if label:
                texts.append((f"{prefix}{key}", label, x + (BOX + 4) * s, row_y, TEXT))
            x += width
        actors = []
        for tkey, label, tx, ty, colour in texts:
            ty = 1.0 - (ty + (BOX / 2 + 1) * s) / self._panel_h
            actors.append(self._text(CONTROLS_PANEL, tkey, label, tx / self._panel_w, ty, size=8.5, color=colour,
                                     valign="center"))  # fmt: skip
        self._last_flow_texts = actors
        return widgets, row_y + ROW_STEP * s

    def _place_buttons(self, name, x0, x1, y):
        caption, options, labels = BUTTON_GROUPS[name]
        labels = labels or {}
        value = self._state_value(name)
        swatches = name == "light_color"
        entries = []
        for option in options:
            if name == "environment" and option == "file" and self.model.environment_file is None:
                continue  # the file choice is offered when --environment FILE gave one
            on_colour = ACCENT
            off_colour = (0.25, 0.26, 0.3)
            label = labels.get(option, self._option_label(name, option))
            if swatches and option != "custom":
                on_colour = tuple(0.15 + 0.85 * np.asarray(LIGHT_COLOURS[option]))
                off_colour = tuple(0.3 * np.asarray(on_colour))
                label = ""
            entries.append((option, label, self._radio_maker(name, option, value == option, on_colour, off_colour)))
        if swatches:
            caption = "colour"
        widgets, y = self._flow(entries, x0, x1, y, caption=caption, prefix=f"btn_{name}_")
        self.buttons[name] = widgets
        return y

    def _option_label(self, name, option):
        if name == "model":
            from .state import MODEL_LABELS

            return MODEL_LABELS[option]
        return option

    def _radio_maker(self, name, option, on, color_on, color_off):
        def make(x, y):
            return self._button(self._radio_callback(name, option), on, x, y, color_on, color_off)

        return make

    def _place_checks(self, checks, x0, x1, y):
        entries = []
        for key, label in checks:
            entries.append((key, label, self._check_maker(key)))
        widgets, y = self._flow(entries, x0, x1, y, prefix="check_")
        self.checkboxes.update(widgets)
        return y

    def _check_maker(self, key):
        def make(x, y):
            return self._button(self._checkbox_callback(key), self._checkbox_value(key), x, y)

        return make

    def _add_slider(self, spec, key, a, b):
        value = self._state_value(key)
        widget = self.plotter.add_slider_widget(
            self._slider_callback(key), [spec.lo, spec.hi], value=spec.to_slider(value),
            title=spec.title(value), pointa=a, pointb=b, interaction_event="always", style="modern",
            title_height=0.05 * 192.0 / max(self._panel_h / self.ui_scale, 1.0), title_color=TEXT, color=TEXT,
            slider_width=0.028, tube_width=0.006,
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
        if spec.integer:  # the knob comes to rest on the value chosen
            widget.AddObserver("EndInteractionEvent", self._snap_callback(key))
        widget.AddObserver("EndInteractionEvent", self._release_callback(key))
        return widget

    # ------------------------------------------------------------------ widget plumbing
    def slider_spec(self, name):
        """The :class:`SliderSpec` of a slider of the panel (``"param:NAME"`` for the model's own).

        Parameters
        ----------
        name : str
            A key of :attr:`sliders`.

        Returns
        -------
        SliderSpec
        """
        return self._param_specs[name] if name.startswith("param:") else SLIDERS[name]

    def _state_value(self, name):
        if name == "light_color":
            return _light_colour_name(self.state.light_color)
        if name.startswith("param:"):
            return self.state.param(name[6:])
        return getattr(self.state, name)

    def _checkbox_value(self, key) -> bool:
        if key.startswith("none:"):
            return self.state.param(key[5:]) is None
        if key.startswith("param:"):
            return bool(self.state.param(key[6:]))
        return key in self.state.terms if key in ("ambient", "diffuse", "specular") else bool(getattr(self.state, key))

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
            widget.GetRepresentation().SetValue(self.slider_spec(name).to_slider(self._state_value(name)))

        return snap

    def _refused(self, exc):
        """A click the model refuses (a combination its constructor does not allow): say so, show the state."""
        self._set_text("hint", f"not applied: {exc}"[:150])
        self.captions["hint"].GetTextProperty().SetColor(1.0, 0.42, 0.42)
        self._sync_widgets()

    def _radio_callback(self, name, option):
        def callback(flag):
            if self._building:
                return
            if not flag:  # the button that is on was clicked: it stays on (one of the group always is)
                self.buttons[name][option].GetRepresentation().SetState(1)
                return
            if name == "light_color":
                if option == "custom":
                    self._sync_widgets()
                    return
                self.set_control(name, LIGHT_COLOURS[option], render=False)
            elif name.startswith("param:"):
                try:
                    self.set_control("params", {name[6:]: option}, render=False)
                except ValueError as exc:
                    self._refused(exc)
            else:
                self.set_control(name, option, render=False)

        return callback

    def _checkbox_callback(self, key):
        def callback(flag):
            if self._building:
                return
            # The button widget renders after calling back.
            if key in ("ambient", "diffuse", "specular"):
                terms = set(self.state.terms)
                terms = terms | {key} if flag else terms - {key}
                self.set_control("terms", tuple(terms), render=False)
            elif key.startswith("none:"):
                name = key[5:]
                value = None if flag else self._param_specs[f"param:{name}"].linked_value(self.state)
                self.set_control("params", {name: value}, render=False)
            elif key.startswith("param:"):
                try:
                    self.set_control("params", {key[6:]: bool(flag)}, render=False)
                except ValueError as exc:
                    self._refused(exc)
            else:
                self.set_control(key, bool(flag), render=False)

        return callback

    def _sync_widgets(self):
        """Make every slider, button and check box show the state (after keys, reset, or programmatic changes)."""
        if self._params_model != self.state.model:
            self._build_model_controls()
        for name, widget in self.sliders.items():
            spec = self.slider_spec(name)
            value = self._state_value(name)
            rep = widget.GetRepresentation()
            target = spec.to_slider(value)
            if not math.isclose(rep.GetValue(), target, rel_tol=1e-9, abs_tol=1e-9):
                rep.SetValue(target)
            rep.SetTitleText(spec.title(value))
        for name, group in self.buttons.items():
            value = self._state_value(name)
            for option, widget in group.items():
                rep = widget.GetRepresentation()
                want = 1 if option == value else 0
                if rep.GetState() != want:
                    rep.SetState(want)
        for key, widget in self.checkboxes.items():
            rep = widget.GetRepresentation()
            want = 1 if self._checkbox_value(key) else 0
            if rep.GetState() != want:
                rep.SetState(want)
        self._set_text(MATERIAL_HEADER, f"Material: {self._model_title()}")
        self._sync_compare_rows()

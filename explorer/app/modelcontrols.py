"""The model's own controls in the control panel, generated from its parameter table and rebuilt on a model switch.

One control per row of :func:`~explorer.app.params.offered_parameters` (as BRDF Explorer builds its
sliders from a file's parameter block): a slider for a number or a grey colour (log10 of the value for
a ``log`` row), a check box for a flag, a row of buttons for a choice, and for a number whose default is
``None`` (``alpha_y``: "None = α_x") a check box that sets ``None`` back.  The ``k_d`` slider heads the
column: the explorer's diffuse albedo, or the model's own diffuse colour
(:func:`~explorer.app.params.diffuse_parameter`).
A mixin of :class:`~explorer.app.widgets.WidgetsMixin`.
"""

from __future__ import annotations

import math

import numpy as np

from .layout import CONTROLS_PANEL
from .params import none_label, offered_parameters, slider_range

__all__ = ["ParamSliderSpec", "button_width", "ModelControlsMixin"]

#: Greek and subscripted labels of the registered models' parameter names (others are shown as named).
_LABELS = {"alpha_x": "α_x", "alpha_y": "α_y", "sigma": "σ", "shininess": "shininess e", "roughness": "roughness α",
           "ks": "k_s", "f0": "F0", "rs": "R_s", "nu": "n_u", "nv": "n_v"}  # fmt: skip


def button_width(label: str, scale: float, box: bool = True) -> float:
    """Pixels a button and its label take in a row (DejaVu Sans at 8.5 pt is about 5.3 px a character).

    Parameters
    ----------
    label : str
        The button's text.
    scale : float
        The window's scale (1 at 1280 × 768).
    box : bool
        Whether a check box is drawn before the label.

    Returns
    -------
    float
        The width in pixels.
    """
    return (17.0 if box else 4.0) * scale + 4.7 * scale * len(label) + 8.0 * scale


class ParamSliderSpec:
    """A slider of one parameter row: its range (log10 for log rows), title and the value it stands for."""

    def __init__(self, p):
        self.p = p
        self.name = f"param:{p.name}"
        self.label = _LABELS.get(p.name, p.name.replace("_", " "))
        self.log = p.log
        self.integer = False
        self.lo, self.hi = slider_range(p)
        self.unit = f" {p.unit}" if p.unit else ""

    def _number(self, value) -> float | None:
        if value is None:
            return None
        return float(np.max(value))

    def linked_value(self, state) -> float:
        """A number for a ``None`` row when its lock is released: the value at the slider's middle.

        Parameters
        ----------
        state : AppState
            The explorer's state (unused: the slider's range decides).

        Returns
        -------
        float
            The value, within the row's ``[low, high]``.
        """
        return min(max(self.from_slider(0.5 * (self.lo + self.hi)), self.p.low), self.p.high)

    def to_slider(self, value) -> float:
        """The slider position that shows ``value`` (a ``None`` value: the middle; a colour: its largest channel).

        Parameters
        ----------
        value : float, tuple or None
            The parameter's value.

        Returns
        -------
        float
        """
        x = self._number(value)
        if x is None:
            return 0.5 * (self.lo + self.hi)
        if self.log:
            x = math.log10(max(x, 10.0**self.lo))
        return min(max(x, self.lo), self.hi)

    def from_slider(self, x: float) -> float:
        """The value at slider position ``x`` (clamped to the range; ``10**x`` for a log row).

        Parameters
        ----------
        x : float
            The position.

        Returns
        -------
        float
        """
        from lighting._numeric import check_range

        x = min(max(check_range(f"{self.name} slider position", x), self.lo), self.hi)
        value = 10.0**x if self.log else x
        if self.p.low_open and value <= self.p.low:
            value = math.nextafter(self.p.low, math.inf)
        return value

    def title(self, value) -> str:
        """``"σ = 0.30 rad"``; ``"α_y = α_x (None)"`` for a ``None`` value; a colour shows its channels.

        Parameters
        ----------
        value : float, tuple or None

        Returns
        -------
        str
        """
        if value is None:
            return f"{self.label}: {none_label(self.p)}"
        if isinstance(value, tuple):
            return f"{self.label} = (" + ", ".join(f"{v:.2f}" for v in value) + ")"
        v = float(value)
        text = (f"{v:.3g}" if v < 1e5 else f"{v:.0e}") if self.log else f"{v:.2f}"
        return f"{self.label} = {text}{self.unit}"


class ModelControlsMixin:
    """Builds (and rebuilds, on a model switch) the controls of the current model's parameters."""

    _params_model = None

    def _model_title(self) -> str:
        from .state import MODEL_LABELS

        return MODEL_LABELS[self.state.model] if self.state.model in MODEL_LABELS else self.state.model

    def _clear_model_controls(self):
        widgets = getattr(self.plotter, "widgets", self.plotter)  # PyVista >= 0.47 keeps them there
        for widget in self._param_widgets:
            widget.Off()
            for store in (widgets.slider_widgets, widgets.button_widgets):
                if widget in store:
                    store.remove(widget)
        ren = self._renderer(CONTROLS_PANEL)
        for key in [k for k in self.captions if k.startswith("pm_")]:
            ren.RemoveViewProp(self.captions.pop(key))
        for key in [k for k in self.sliders if k.startswith("param:")] + ["kd"]:
            self.sliders.pop(key, None)
        for key in [k for k in self.checkboxes if k.startswith(("param:", "none:"))]:
            self.checkboxes.pop(key)
        for key in [k for k in self.buttons if k.startswith("param:")]:
            self.buttons.pop(key)
        self._param_widgets = []
        self._param_specs = {}

    def _build_model_controls(self):
        """The k_d slider and one control per offered parameter, in two sub-columns of the model's column."""
        from .widgets import KD_SLIDER, SLIDER_STEP

        building, self._building = self._building, True
        self._clear_model_controls()
        x0, x1, y0 = self._model_column
        mid = 0.5 * (x0 + x1)
        cols = [[x0, mid, y0], [mid, x1, y0]]
        bottom = self._panel_h - 14.0 * self.ui_scale
        s = self.ui_scale

        def column(height):
            # The first sub-column with room for ``height`` pixels (the second takes the rest).
            return cols[0] if cols[0][2] + height <= bottom else cols[1]

        c = column(SLIDER_STEP * s)
        c[2] = self._place_slider(KD_SLIDER, c[0], c[1], c[2])
        for p in offered_parameters(self.state.model):
            key = f"param:{p.name}"
            if p.kind in ("float", "color"):
                spec = ParamSliderSpec(p)
                self._param_specs[key] = spec
                c = column(SLIDER_STEP * s)
                c[2] = self._place_slider(spec, c[0], c[1], c[2], key=key)
                if p.default is None:
                    meaning = none_label(p).lstrip("= ")
                    c[2] = self._param_checks([(f"none:{p.name}", f"{spec.label} = {meaning}")], c)
            elif p.kind == "bool":
                c = column(17.0 * s)
                c[2] = self._param_checks([(key, _LABELS.get(p.name, p.name))], c)
            else:
                c = column(34.0 * s)
                c[2] = self._param_buttons(p, c)
        self._param_widgets += [w for k, w in self.sliders.items() if k == "kd" or k.startswith("param:")]
        self._params_model = self.state.model
        from .widgets import MATERIAL_HEADER  # widgets builds on this module

        self._set_text(MATERIAL_HEADER, f"Material: {self._model_title()}")
        self._building = building

    def _param_checks(self, checks, c):
        entries = [(key, label, self._check_maker(key)) for key, label in checks]
        widgets, y = self._flow(entries, c[0], c[1], c[2], prefix=f"pm_{checks[0][0]}_")
        self.checkboxes.update(widgets)
        self._param_widgets += list(widgets.values())
        return y

    def _param_buttons(self, p, c):
        key = f"param:{p.name}"
        value = self.state.param(p.name)
        entries = [(o, o, self._radio_maker(key, o, o == value, *self._button_colours())) for o in p.choices]
        widgets, y = self._flow(entries, c[0], c[1], c[2], caption=_LABELS.get(p.name, p.name), prefix=f"pm_{key}_")
        self.buttons[key] = widgets
        self._param_widgets += list(widgets.values())
        return y

    @staticmethod
    def _button_colours():
        from .layout import ACCENT

        return ACCENT, (0.25, 0.26, 0.3)

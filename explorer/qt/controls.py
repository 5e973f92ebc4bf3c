"""The control panel: one editor per control and per parameter of the current model, generated from the tables.

The window's controls come from :data:`explorer.app.state.CONTROLS` (kind, range, log scale, help), the
model's own parameters from its table (:func:`explorer.app.params.offered_parameters`); nothing is placed
by hand.  :data:`SECTIONS` groups them (Light, Material, Shading, Plots, Environment, Compare); the
Material section ends with the current model's parameters, rebuilt when the model changes.  A number is
a slider (log10 of the value for a log row; integers snap) beside a spin box; a colour is a swatch and
three channels; a choice is a combo box; a flag is a check box.  A parameter whose default is ``None``
(``alpha_y``: "None: = α_x") has a check box under its slider that sets ``None``.

As in napari's Qt layer, the panel maps the state onto the widgets (:meth:`ControlPanel.sync`, signals
blocked) and the widgets' edits onto requests (:attr:`ControlPanel.change_requested`); the window applies
a request with ``AppState.update`` and, when the state refuses it, calls :meth:`~ControlPanel.sync` so the
widget shows the state's value again.  Rows that do not apply to the state are hidden (the falloff and
distance of a directional light, the cone of anything but a spot).
"""

from __future__ import annotations

import math

from PySide6 import QtCore, QtWidgets

from ..app.captions import kd_control_label
from ..app.environment import ENVIRONMENT_LABELS
from ..app.params import conductor_none_value, none_label, offered_parameters, slider_range
from ..app.state import CHANNEL_LABELS, CONTROLS, FIT_MODELS, MODEL_LABELS, AppState
from ._controls_editors import CheckEditor, ChoiceEditor, ColourEditor, NumberEditor, TermsEditor

__all__ = ["ControlPanel", "SECTIONS", "LABELS", "PARAM_LABELS", "PARAMS", "applies"]

#: Where the model's own parameters go in :data:`SECTIONS`.
PARAMS = "<parameters>"
#: The panel's sections and their controls, in order.
SECTIONS = (
    ("Light", ("light", "elevation", "azimuth", "intensity", "light_color", "distance", "attenuation", "cutoff",
               "spot_exponent", "ambient")),
    ("Material", ("model", "kd", "color", PARAMS)),
    ("Shading", ("mode", "form", "terms", "tessellation", "exposure", "scanline")),
    ("Plots", ("channel", "log", "times_cos", "phi", "lock", "panel", "view3d")),
    ("Environment", ("environment", "env_rotation", "env_intensity", "reference")),
    ("Compare", ("split", "fit")),
)  # fmt: skip

#: Each control's label (the old window's words).
LABELS = {
    "light": "key light", "elevation": "elevation", "azimuth": "azimuth", "intensity": "intensity",
    "light_color": "light colour", "distance": "point/spot distance", "attenuation": "falloff",
    "cutoff": "spot cutoff", "spot_exponent": "spot exponent", "ambient": "ambient I_a", "model": "model",
    "kd": "k_d (diffuse albedo)", "color": "surface colour", "mode": "lit sphere", "form": "form", "terms": "terms",
    "tessellation": "coarse sphere bands", "exposure": "exposure", "scanline": "scan line", "channel": "plots",
    "log": "log10(1+x)", "times_cos": "× n·l", "phi": "light azimuth φ_l", "lock": "view lock (retro)",
    "panel": "right panel", "view3d": "3D", "environment": "environment", "env_rotation": "rotation",
    "env_intensity": "intensity", "reference": "reference (MC)", "split": "split sphere", "fit": "fit",
}  # fmt: skip
#: Units shown after a control's number.
UNITS = {"elevation": "°", "azimuth": "°", "cutoff": "°", "phi": "°", "env_rotation": "°", "exposure": " stops"}
#: The labels of a choice control's options (others are shown as named).
OPTION_LABELS = {
    "model": MODEL_LABELS,
    "attenuation": {"inverse-square": "1/r²", "linear": "1/r", "none": "none"},
    "mode": {"flat": "flat", "gouraud": "Gouraud", "phong": "Phong"},
    "form": {"classic": "classic I", "physical": "physical I/π"},
    "channel": CHANNEL_LABELS,
    "panel": {"angles": "angles", "albedo": "albedo ρ"},
    "environment": ENVIRONMENT_LABELS,
    "fit": {name: entry[2] for name, entry in FIT_MODELS.items()},
}
#: Greek and subscripted labels of the registered models' parameter names (others are shown as named).
PARAM_LABELS = {"alpha_x": "α_x", "alpha_y": "α_y", "sigma": "σ", "shininess": "shininess e",
                "roughness": "roughness α", "ks": "k_s", "f0": "F0", "rs": "R_s", "nu": "n_u", "nv": "n_v"}  # fmt: skip

#: Rows shown only when the state needs them: control → the test on the state.
_APPLIES = {
    "distance": lambda s: s.light in ("point", "spot"),
    "attenuation": lambda s: s.light in ("point", "spot"),
    "cutoff": lambda s: s.light == "spot",
    "spot_exponent": lambda s: s.light == "spot",
    "env_rotation": lambda s: s.environment != "none",
    "env_intensity": lambda s: s.environment != "none",
    "reference": lambda s: s.environment != "none",
}
#: Sections a section_requested name may name besides the table's (the ambient row sits in Light).
_SECTION_OF = {name: title for title, names in SECTIONS for name in names}


def applies(name: str, state: AppState) -> bool:
    """Whether the control ``name`` applies to ``state`` (its row is shown).

    Parameters
    ----------
    name : str
        A control of :data:`~explorer.app.state.CONTROLS`.
    state : AppState

    Returns
    -------
    bool
        False for the point/spot rows of a directional light, the cone of a non-spot light and the
        environment's rows without an environment.
    """
    test = _APPLIES.get(name)
    return True if test is None else bool(test(state))


def param_label(p) -> str:
    """The label of a parameter row (``"α_y"``, ``"shininess e"``; others as named, ``_`` as spaces)."""
    return PARAM_LABELS.get(p.name, p.name.replace("_", " "))


def _tip(label: str, help_text: str, unit: str = "") -> str:
    return f"{label}{f' ({unit.strip()})' if unit.strip() else ''}: {help_text}" if help_text else label


class _Label(QtWidgets.QLabel):
    """A row's label: wraps at word boundaries within its column; its tooltip holds the whole text and the help."""

    def __init__(self, text, tip, width, parent=None):
        super().__init__(text, parent)
        self.setWordWrap(True)
        self.setFixedWidth(width)
        self.setToolTip(tip)
        self.setAlignment(QtCore.Qt.AlignmentFlag.AlignLeft | QtCore.Qt.AlignmentFlag.AlignVCenter)
        self.setSizePolicy(QtWidgets.QSizePolicy.Policy.Fixed, QtWidgets.QSizePolicy.Policy.Preferred)
        # The width is fixed, so the wrapped lines' height is known: the row keeps room for every line.
        self.setMinimumHeight(self.heightForWidth(width))


class _Row(QtWidgets.QWidget):
    """One control: its label in the label column (or none, for a check box) and its editor."""

    def __init__(self, label, editor, tip, label_width, parent=None):
        super().__init__(parent)
        row = QtWidgets.QHBoxLayout(self)
        row.setContentsMargins(0, 1, 0, 1)
        row.setSpacing(6)
        self.label = _Label(label, tip, label_width, self) if label is not None else None
        if self.label is not None:
            row.addWidget(self.label, 0)
        else:
            row.addSpacing(label_width + row.spacing())
        row.addWidget(editor, 1)
        self.editor = editor
        editor.setToolTip(editor.toolTip() or tip)


class _Section(QtWidgets.QWidget):
    """A titled, collapsible group of rows (the title is a button that folds the rows away)."""

    def __init__(self, title, parent=None):
        super().__init__(parent)
        self.title = title
        self.header = QtWidgets.QToolButton(self)
        self.header.setText(title)
        self.header.setCheckable(True)
        self.header.setChecked(True)
        self.header.setToolButtonStyle(QtCore.Qt.ToolButtonStyle.ToolButtonTextBesideIcon)
        self.header.setArrowType(QtCore.Qt.ArrowType.DownArrow)
        self.header.setAutoRaise(True)
        font = self.header.font()
        font.setBold(True)
        self.header.setFont(font)
        self.header.setSizePolicy(QtWidgets.QSizePolicy.Policy.Expanding, QtWidgets.QSizePolicy.Policy.Fixed)
        self.header.toggled.connect(self.set_open)
        self.body = QtWidgets.QWidget(self)
        self.rows = QtWidgets.QVBoxLayout(self.body)
        self.rows.setContentsMargins(8, 0, 0, 4)
        self.rows.setSpacing(2)
        box = QtWidgets.QVBoxLayout(self)
        box.setContentsMargins(0, 0, 0, 0)
        box.setSpacing(0)
        box.addWidget(self.header)
        box.addWidget(self.body)

    def set_open(self, on: bool) -> None:
        """Show or fold the section's rows."""
        blocked = self.header.blockSignals(True)
        self.header.setChecked(on)
        self.header.blockSignals(blocked)
        self.header.setArrowType(QtCore.Qt.ArrowType.DownArrow if on else QtCore.Qt.ArrowType.RightArrow)
        self.body.setVisible(on)


class ControlPanel(QtWidgets.QScrollArea):
    """Every control of the explorer and the current model's parameters, in sections (see the module).

    Parameters
    ----------
    state : AppState
        The state the widgets show first.
    parent : QWidget, optional

    Attributes
    ----------
    change_requested : Signal(object, bool)
        ``({name: value}, live)``: a control's or parameter's new value (a parameter whose name is also a
        control's, Oren–Nayar's ``form``, as ``{"params": {name: value}}``); ``live`` while a slider is
        dragged, False for its release and every other edit.
    sections : dict of str to QWidget
        The sections by title.
    """

    change_requested = QtCore.Signal(object, bool)

    def __init__(self, state: AppState, parent=None):
        super().__init__(parent)
        self.setWidgetResizable(True)
        self.setHorizontalScrollBarPolicy(QtCore.Qt.ScrollBarPolicy.ScrollBarAsNeeded)
        self.setFrameShape(QtWidgets.QFrame.Shape.NoFrame)
        inner = QtWidgets.QWidget(self)
        self._column = QtWidgets.QVBoxLayout(inner)
        self._column.setContentsMargins(6, 4, 6, 6)
        self._column.setSpacing(4)
        self._label_width = self._measure_label_width()
        self._editors: dict[str, QtWidgets.QWidget] = {}
        self._rows: dict[str, _Row] = {}
        self._param_editors: dict[str, QtWidgets.QWidget] = {}
        self._param_box: QtWidgets.QWidget | None = None
        self._params_model = None
        self.sections: dict[str, _Section] = {}
        for title, names in SECTIONS:
            section = _Section(title, inner)
            self.sections[title] = section
            self._column.addWidget(section)
            for name in names:
                if name == PARAMS:
                    self._param_host = QtWidgets.QVBoxLayout()
                    self._param_host.setContentsMargins(0, 0, 0, 0)
                    section.rows.addLayout(self._param_host)
                else:
                    row = self._control_row(name, section.body)
                    section.rows.addWidget(row)
                    self._rows[name] = row
        self._column.addStretch(1)
        self.setWidget(inner)
        self.sync(state)
        self._fit_width()

    # ------------------------------------------------------------------ public
    def widget(self, name: str | None = None) -> QtWidgets.QWidget:
        """The editor of a control, or of a parameter of the current model.

        Parameters
        ----------
        name : str, optional
            A control name (``"elevation"``), a parameter name (``"shininess"``), or ``"param:NAME"``
            for a parameter whose name is also a control's (Oren–Nayar's ``form``).  Without a name:
            the scrolled widget holding the sections (``QScrollArea.widget``).

        Returns
        -------
        QWidget
            A :class:`~explorer.qt._controls_editors.NumberEditor` (``.slider``, ``.spin``; a ``None``-able
            row also ``.none_box``), ``ColourEditor``, ``ChoiceEditor`` (a QComboBox), ``CheckEditor``
            (a QCheckBox) or ``TermsEditor`` (``.boxes``).
        """
        if name is None:
            return super().widget()
        if name.startswith("param:"):
            key = name[len("param:") :]
            if key in self._param_editors:
                return self._param_editors[key]
        elif name in self._editors:
            return self._editors[name]
        elif name in self._param_editors:
            return self._param_editors[name]
        have = ", ".join([*self._editors, *self._param_editors])
        raise KeyError(f"the control panel has no control {name!r}; it has {have}")

    def row_visible(self, name: str) -> bool:
        """Whether the row of a control is shown (not hidden as not applying)."""
        return not self._rows[name].isHidden()

    def show_section(self, title: str) -> None:
        """Unfold a section (by its title, or by the name of one of its controls) and scroll it into view.

        Parameters
        ----------
        title : str
            ``"Light"``, ``"Environment"``, ... or a control name (``"ambient"``).
        """
        title = _SECTION_OF.get(title, title)
        if title not in self.sections:
            raise ValueError(f"section must be one of {', '.join(self.sections)}; got {title!r}")
        section = self.sections[title]
        section.set_open(True)
        self.ensureWidgetVisible(section, 0, 0)
        # Bring the section's head to the top where there is room below it.
        bar = self.verticalScrollBar()
        bar.setValue(min(section.y(), bar.maximum()))

    def sync(self, state: AppState) -> None:
        """Show the state's values in every widget (no edit is reported); rebuild the parameter rows on a new model.

        Parameters
        ----------
        state : AppState
            The explorer's state.
        """
        if state.model != self._params_model:
            self._build_params(state.model)
            self._fit_width()
        for name, editor in self._editors.items():
            editor.set_value(getattr(state, name))
            self._rows[name].setHidden(not applies(name, state))
        kd_row = self._rows.get("kd")
        if kd_row is not None and kd_row.label is not None:
            # What the k_d slider sets depends on the model (a BRDF file's own diffuse: k_a alone).
            text = kd_control_label(state)
            if kd_row.label.text() != text:
                kd_row.label.setText(text)
                kd_row.label.setMinimumHeight(kd_row.label.heightForWidth(kd_row.label.width()))
        params = state.params
        for name, editor in self._param_editors.items():
            self._show_param(editor, params.get(name), params)

    # ------------------------------------------------------------------ building
    def _fit_width(self) -> None:
        """The panel's minimum width: every row whole beside the vertical scroll bar (no sideways scrolling)."""
        inner = super().widget()
        if inner is None:
            return
        bar = self.style().pixelMetric(QtWidgets.QStyle.PixelMetric.PM_ScrollBarExtent, None, self)
        self.setMinimumWidth(inner.minimumSizeHint().width() + bar + 2 * self.frameWidth())

    def _measure_label_width(self) -> int:
        """The label column: room for the longest word of any label, and at least 7 em."""
        fm = self.fontMetrics()
        words = [w for text in [*LABELS.values(), *PARAM_LABELS.values()] for w in text.split()]
        longest = max(fm.horizontalAdvance(w) for w in words)
        return max(longest + 4, 7 * fm.horizontalAdvance("m"))

    def _control_row(self, name, parent) -> _Row:
        spec = CONTROLS[name]
        label = LABELS.get(name, name.replace("_", " "))
        unit = UNITS.get(name, "")
        tip = _tip(label, spec.help, unit)
        if spec.kind in ("float", "int"):
            editor = NumberEditor(
                math.log10(spec.lo) if spec.log else spec.lo,
                math.log10(spec.hi) if spec.log else spec.hi,
                minimum=spec.lo,
                maximum=spec.hi,
                log=spec.log,
                integer=spec.kind == "int",
                unit=unit,
            )
        elif spec.kind == "choice":
            editor = ChoiceEditor(spec.choices, OPTION_LABELS.get(name), help=spec.help)
        elif spec.kind == "rgb":
            editor = ColourEditor(title=label)
        elif spec.kind == "bool":
            editor = CheckEditor(label)
            label = None
        elif spec.kind == "terms":
            editor = TermsEditor(spec.choices)
        else:  # a kind this panel does not know: say so rather than show nothing
            raise ValueError(f"control {name} has kind {spec.kind!r}; the panel shows float, int, choice, bool, "
                             f"rgb and terms")  # fmt: skip
        editor.setParent(parent)
        editor.edited.connect(lambda value, live, name=name: self.change_requested.emit({name: value}, live))
        self._editors[name] = editor
        return _Row(label, editor, tip, self._label_width, parent)

    def _build_params(self, model: str) -> None:
        """The rows of ``model``'s parameters, replacing the previous model's (deleted later, never in a handler)."""
        if self._param_box is not None:
            old = self._param_box
            old.hide()
            self._param_host.removeWidget(old)
            old.deleteLater()
        section = self.sections["Material"]
        box = QtWidgets.QWidget(section.body)
        rows = QtWidgets.QVBoxLayout(box)
        rows.setContentsMargins(0, 0, 0, 0)
        rows.setSpacing(2)
        self._param_editors = {}
        for p in offered_parameters(model):
            self._add_param_row(p, box, rows)
        self._param_host.addWidget(box)
        self._param_box = box
        self._params_model = model

    def _add_param_row(self, p, parent, rows) -> None:
        """A parameter's row added to ``rows`` (and under it, for a ``None`` default, the box that sets None)."""
        label = param_label(p)
        tip = _tip(label, p.description, p.unit)
        in_params = p.name in CONTROLS  # a parameter named like a control (Oren–Nayar's form) goes in params

        def request(value, live, name=p.name):
            self.change_requested.emit({"params": {name: value}} if in_params else {name: value}, live)

        if p.kind in ("float", "color"):
            lo, hi = slider_range(p)
            editor = NumberEditor(lo, hi, minimum=p.low, maximum=p.high, log=p.log,
                                  unit=f" {p.unit}" if p.unit else "")  # fmt: skip
            editor.edited.connect(request)
        elif p.kind == "bool":
            editor = CheckEditor(label)
            editor.edited.connect(request)
            label = None
        else:
            editor = ChoiceEditor(p.choices, help=p.description)
            editor.edited.connect(request)
        editor.setParent(parent)
        self._param_editors[p.name] = editor
        rows.addWidget(_Row(label, editor, tip, self._label_width, parent))
        if p.kind in ("float", "color") and p.default is None:
            self._add_none_box(editor, p, label, request, rows)

    def _add_none_box(self, editor: NumberEditor, p, label: str, request, rows) -> None:
        """Under the row of a ``None``-able parameter: the box that sets ``None`` ("α_y = α_x")."""
        meaning = none_label(p).lstrip("= ").strip()
        box = CheckEditor(f"{label} = {meaning}")
        box.setToolTip(f"{label} = {meaning}: {p.description}")
        line = QtWidgets.QWidget(rows.parentWidget())
        indent = QtWidgets.QHBoxLayout(line)
        indent.setContentsMargins(min(self._label_width // 2, 24), 0, 0, 1)
        indent.addWidget(box, 1)
        rows.addWidget(line)
        editor.none_box = box
        editor.none_meaning = meaning
        editor.param_name = p.name

        def toggled(on, _live=False, editor=editor):
            # Released: the value None stood for (the parameter it names, if it is one), so the look holds.
            request(None if on else self._released_value(editor), False)

        box.edited.connect(toggled)

    @staticmethod
    def _released_value(editor: NumberEditor) -> float | tuple:
        whole = getattr(editor, "linked_whole", None)  # a conductor's RGB index: released as it is
        if whole is not None:
            return whole
        value = getattr(editor, "linked_value", None)
        return float(value if value is not None else editor.from_position(editor.slider.value()))

    def _show_param(self, editor, value, params: dict) -> None:
        box = getattr(editor, "none_box", None)
        if box is None:
            if isinstance(editor, NumberEditor) and isinstance(value, tuple):
                editor.set_value(max(value))  # an RGB value from a scene file: the knob shows its largest channel
                editor.setToolTip(f"({', '.join(f'{c:.3g}' for c in value)}); the slider sets a grey value")
            else:
                editor.set_value(value)
            return
        box.set_value(value is None)
        editor.slider.setEnabled(value is not None)
        editor.spin.setEnabled(value is not None)
        if value is None:
            # Show what None stands for where that is another number of the table ("α_y = α_x").
            # Else the knob rests mid-way, and that value is the one a released box starts from.
            linked = conductor_none_value(editor.param_name, params)
            editor.linked_whole = conductor_none_value(editor.param_name, params, whole=True)
            if linked is None:
                linked = self._linked(editor.none_meaning, params)
            if linked is None:
                linked = editor.from_position((editor.slider.minimum() + editor.slider.maximum()) // 2)
            editor.linked_value = linked
            editor.set_value(linked)
        else:
            editor.linked_value = editor.linked_whole = None
            editor.set_value(max(value) if isinstance(value, tuple) else value)

    @staticmethod
    def _linked(meaning: str, params: dict):
        """The number a ``None`` row stands for: one its meaning starts with ("0 or the metal's"), or the value
        of the parameter it names ("α_x", "roughness"); None when it says neither."""
        first = meaning.split()[0] if meaning.split() else ""
        try:
            return float(first)
        except ValueError:
            pass
        for name, value in params.items():
            if meaning in (name, PARAM_LABELS.get(name)) and isinstance(value, (int, float)) and value is not True:
                return float(value)
        return None

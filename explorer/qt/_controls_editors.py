"""The editors the control panel and the lights panel are built from: a number, a colour, a choice, a flag.

Each editor shows one value and reports the user's edits as ``edited(value, live)``: ``live`` is True
while a slider's knob is dragged (the window then updates only the views that follow a drag) and False
for the last value of a drag, a typed number, a chosen item or a toggled box.  ``set_value`` shows a
value without reporting it (signals blocked): the panels call it when the state changed or refused.
Nothing here knows the explorer's controls; the panels map names and tables onto these editors.
"""

from __future__ import annotations

import math

from PySide6 import QtCore, QtGui, QtWidgets

__all__ = ["NumberEditor", "ColourEditor", "ChoiceEditor", "CheckEditor", "TermsEditor", "JumpSlider", "decimals_for"]

#: Slider positions of a float editor (an integer editor has one position per integer).
STEPS = 1000


def decimals_for(lo: float, hi: float, log: bool = False) -> int:
    """Decimals a spin box shows for values in ``[lo, hi]``: about four significant digits of the span.

    Parameters
    ----------
    lo, hi : float
        The values' range (for a log row: the values, not their log10).
    log : bool
        Whether the row spans decades: then the small end decides.

    Returns
    -------
    int
        Between 0 and 4 for a log row, 0 and 5 else.

    Examples
    --------
    >>> decimals_for(0.0, 1.0), decimals_for(-180.0, 180.0), decimals_for(0.001, 1.0, log=True)
    (3, 1, 4)
    """
    if log:
        small = max(lo, 1e-5)
        return int(min(max(3 - math.floor(math.log10(small)) - 2, 0), 4))
    span = hi - lo
    if not (math.isfinite(span) and span > 0):
        return 3
    return int(min(max(3 - math.floor(math.log10(span)), 0), 5))


class _JumpStyle(QtWidgets.QProxyStyle):
    """A left click on a slider's track puts the knob there (and the drag goes on from there).

    ``absolute`` is cleared for a press on the knob itself, which then only starts a drag: Qt's jump would
    centre the knob under the pointer, a step off for a press beside the knob's centre.
    """

    absolute = True

    def styleHint(self, hint, option=None, widget=None, returnData=None):  # noqa: N802 (Qt's name)
        if hint == QtWidgets.QStyle.StyleHint.SH_Slider_AbsoluteSetButtons:
            return QtCore.Qt.MouseButton.LeftButton.value if self.absolute else 0
        return super().styleHint(hint, option, widget, returnData)


class _WheelGuard:
    """A wheel turn over an editor without focus scrolls the panel instead of changing the value."""

    def wheelEvent(self, event):  # noqa: N802 (Qt's name)
        if self.hasFocus():
            super().wheelEvent(event)
        else:
            event.ignore()


class JumpSlider(_WheelGuard, QtWidgets.QSlider):
    """A horizontal slider whose track click jumps the knob, reporting ``moved(position, live)``.

    A press (on the knob or the track) starts a drag: every position until the release is reported
    live, and the release reports the position again as final.  Keys and the wheel (with focus) report
    final positions.
    """

    moved = QtCore.Signal(int, bool)

    def __init__(self, parent=None):
        super().__init__(QtCore.Qt.Orientation.Horizontal, parent)
        self._jump = _JumpStyle(QtWidgets.QApplication.style().name())
        self._jump.setParent(self)  # lives as long as the slider
        self.setStyle(self._jump)
        self._pressed = False
        self.setFocusPolicy(QtCore.Qt.FocusPolicy.StrongFocus)
        self.setMinimumWidth(60)
        self.valueChanged.connect(self._changed)

    def handle_rect(self) -> QtCore.QRect:
        """Where the knob is drawn, in the slider's coordinates."""
        opt = QtWidgets.QStyleOptionSlider()
        self.initStyleOption(opt)
        return self.style().subControlRect(QtWidgets.QStyle.ComplexControl.CC_Slider, opt,
                                           QtWidgets.QStyle.SubControl.SC_SliderHandle, self)  # fmt: skip

    def mousePressEvent(self, event):  # noqa: N802 (Qt's name)
        self._pressed = event.button() == QtCore.Qt.MouseButton.LeftButton
        self._jump.absolute = not self.handle_rect().contains(event.position().toPoint())
        try:
            super().mousePressEvent(event)
        finally:
            self._jump.absolute = True

    def mouseReleaseEvent(self, event):  # noqa: N802 (Qt's name)
        was = self._pressed
        super().mouseReleaseEvent(event)
        if was and event.button() == QtCore.Qt.MouseButton.LeftButton:
            self._pressed = False
            self.moved.emit(self.value(), False)

    def _changed(self, position: int):
        self.moved.emit(position, self._pressed or self.isSliderDown())


class _SpinBox(_WheelGuard, QtWidgets.QDoubleSpinBox):
    """A spin box as wide as the values it usually shows (Qt sizes it for its range's ends, 1e9 for no end)."""

    _width = None

    def fit_to(self, *values) -> None:
        """Size the box for ``values`` (with its suffix, sign and arrows) rather than for its whole range."""
        fm = self.fontMetrics()
        text = max((self.textFromValue(v) + self.suffix() for v in values), key=fm.horizontalAdvance)
        probe = QtWidgets.QDoubleSpinBox()
        probe.setRange(0.0, 0.0)
        probe.setDecimals(0)
        probe.setButtonSymbols(self.buttonSymbols())
        chrome = probe.sizeHint().width() - fm.horizontalAdvance("0")
        self._width = fm.horizontalAdvance(text) + chrome
        self.updateGeometry()

    def sizeHint(self):  # noqa: N802 (Qt's name)
        hint = super().sizeHint()
        if self._width is not None:
            hint.setWidth(self._width)
        return hint

    def minimumSizeHint(self):  # noqa: N802 (Qt's name)
        hint = super().minimumSizeHint()
        if self._width is not None:
            hint.setWidth(self._width)
        return hint


class _ComboBox(_WheelGuard, QtWidgets.QComboBox):
    pass


class NumberEditor(QtWidgets.QWidget):
    """A slider and a spin box showing one number; the slider moves log10 of the value for a log row.

    Parameters
    ----------
    lo, hi : float
        The slider's ends (log10 of the values for a log row).
    minimum, maximum : float
        The values the spin box accepts (the control's whole range; the state refuses what it must).
    log : bool
        The slider's position is log10 of the value.
    integer : bool
        Integer values: one slider position per integer, the spin box shows no decimals.
    decimals : int, optional
        The spin box's decimals (default :func:`decimals_for`).
    unit : str
        The spin box's suffix (``"°"``).

    Attributes
    ----------
    slider : JumpSlider
    spin : QDoubleSpinBox
    """

    edited = QtCore.Signal(object, bool)

    def __init__(self, lo, hi, *, minimum=None, maximum=None, log=False, integer=False, decimals=None, unit="",
                 parent=None):  # fmt: skip
        super().__init__(parent)
        self.lo, self.hi, self.log, self.integer = float(lo), float(hi), bool(log), bool(integer)
        minimum = (10.0**self.lo if log else self.lo) if minimum is None else float(minimum)
        maximum = (10.0**self.hi if log else self.hi) if maximum is None else float(maximum)
        self.slider = JumpSlider(self)
        if integer:
            self.slider.setRange(int(round(self.lo)), int(round(self.hi)))
        else:
            self.slider.setRange(0, STEPS)
            self.slider.setPageStep(STEPS // 20)
        self.spin = _SpinBox(self)
        self.spin.setFocusPolicy(QtCore.Qt.FocusPolicy.StrongFocus)
        self.spin.setKeyboardTracking(False)  # a typed number counts when entered, not at each digit
        self.spin.setDecimals(0 if integer else (decimals_for(minimum, maximum, log) if decimals is None else decimals))
        big = 1e9
        self.spin.setRange(max(minimum, -big), min(maximum, big))
        if log:
            self.spin.setStepType(QtWidgets.QAbstractSpinBox.StepType.AdaptiveDecimalStepType)
        else:
            self.spin.setSingleStep(1.0 if integer else _nice_step((self.hi - self.lo) / 100.0))
        if unit:
            self.spin.setSuffix(unit)
        self.spin.setAlignment(QtCore.Qt.AlignmentFlag.AlignRight)
        ends = (10.0**self.lo, 10.0**self.hi) if log else (self.lo, self.hi)
        self.spin.fit_to(*ends, -abs(ends[1]) if ends[0] < 0 else ends[1])
        row = QtWidgets.QHBoxLayout(self)
        row.setContentsMargins(0, 0, 0, 0)
        row.setSpacing(4)
        row.addWidget(self.slider, 1)
        row.addWidget(self.spin, 0)
        self._value = None
        self.slider.moved.connect(self._slid)
        self.spin.valueChanged.connect(self._typed)

    # ------------------------------------------------------------------ positions
    def to_position(self, value) -> int:
        """The slider position showing ``value`` (clamped to the slider's range)."""
        x = float(value)
        if self.log:
            x = math.log10(x) if x > 0 else self.lo
        x = min(max(x, self.lo), self.hi)
        if self.integer:
            return int(math.floor(x + 0.5))
        return int(round((x - self.lo) / (self.hi - self.lo) * STEPS)) if self.hi > self.lo else 0

    def from_position(self, position: int):
        """The value at a slider position (an int for an integer editor; ``10**x`` for a log one)."""
        if self.integer:
            return int(position)
        x = self.lo + (self.hi - self.lo) * position / STEPS
        if self.log:
            value = 10.0**x
            # The knob's ends are the range's ends exactly (10**log10(x) may miss by one ulp).
            if position == 0:
                value = 10.0**self.lo
            return float(f"{value:.4g}")
        return float(round(x, self.spin.decimals()))

    # ------------------------------------------------------------------ showing and reporting
    def value(self):
        """The value shown."""
        return self._value

    def set_value(self, value) -> None:
        """Show ``value`` on the knob and in the spin box without reporting it (None: leave the knob)."""
        self._value = value
        if value is None:
            return
        for w, v in ((self.slider, self.to_position(value)), (self.spin, float(value))):
            blocked = w.blockSignals(True)
            w.setValue(v)
            w.blockSignals(blocked)

    def _slid(self, position: int, live: bool):
        value = self.from_position(position)
        blocked = self.spin.blockSignals(True)
        self.spin.setValue(float(value))
        self.spin.blockSignals(blocked)
        self._value = value
        self.edited.emit(value, live)

    def _typed(self, value: float):
        value = int(round(value)) if self.integer else float(value)
        blocked = self.slider.blockSignals(True)
        self.slider.setValue(self.to_position(value))
        self.slider.blockSignals(blocked)
        self._value = value
        self.edited.emit(value, False)


def _nice_step(x: float) -> float:
    """1, 2 or 5 times a power of ten, at most ``x`` (a spin box's arrow step)."""
    if not x > 0:
        return 0.01
    p = 10.0 ** math.floor(math.log10(x))
    return next(m * p for m in (5.0, 2.0, 1.0) if m * p <= x)


class ColourEditor(QtWidgets.QWidget):
    """A colour: a swatch button opening a colour dialog, and the three channels as small spin boxes.

    Attributes
    ----------
    button : QToolButton
        The swatch (its tooltip names the value).
    spins : tuple of QDoubleSpinBox
        r, g, b in ``[0, 1]``.
    """

    edited = QtCore.Signal(object, bool)

    def __init__(self, parent=None, *, title="colour"):
        super().__init__(parent)
        self._title = title
        self.button = QtWidgets.QToolButton(self)
        self.button.setFixedSize(26, 22)
        self.button.clicked.connect(self._choose)
        self.spins = []
        row = QtWidgets.QHBoxLayout(self)
        row.setContentsMargins(0, 0, 0, 0)
        row.setSpacing(3)
        row.addWidget(self.button)
        for channel in "rgb":
            spin = _SpinBox(self)
            spin.setFocusPolicy(QtCore.Qt.FocusPolicy.StrongFocus)
            spin.setRange(0.0, 1.0)
            spin.setDecimals(2)
            spin.setSingleStep(0.05)
            spin.setKeyboardTracking(False)
            spin.setButtonSymbols(QtWidgets.QAbstractSpinBox.ButtonSymbols.NoButtons)
            spin.setToolTip(f"{title}: {channel} in [0, 1]")
            spin.fit_to(0.5)
            spin.valueChanged.connect(self._typed)
            row.addWidget(spin, 1)
            self.spins.append(spin)
        self.spins = tuple(self.spins)
        self._value = (1.0, 1.0, 1.0)

    def value(self) -> tuple:
        """The colour shown, ``(r, g, b)``."""
        return self._value

    def set_value(self, value) -> None:
        """Show ``value`` (one grey number or ``(r, g, b)``) without reporting it."""
        rgb = (float(value),) * 3 if isinstance(value, (int, float)) else tuple(float(c) for c in value)
        self._value = rgb
        for spin, c in zip(self.spins, rgb, strict=True):
            blocked = spin.blockSignals(True)
            spin.setValue(c)
            spin.blockSignals(blocked)
        self._paint()

    def _paint(self):
        r, g, b = (min(max(c, 0.0), 1.0) for c in self._value)
        colour = QtGui.QColor.fromRgbF(r, g, b)
        self.button.setStyleSheet(f"background-color: {colour.name()}; border: 1px solid #9aa1a9;")
        self.button.setToolTip(f"{self._title} = ({', '.join(f'{c:.2f}' for c in self._value)}): click to choose")

    def _typed(self, _=None):
        rgb = tuple(round(float(s.value()), 2) for s in self.spins)
        self._value = rgb
        self._paint()
        self.edited.emit(rgb, False)

    def _choose(self):
        r, g, b = (min(max(c, 0.0), 1.0) for c in self._value)
        colour = QtWidgets.QColorDialog.getColor(QtGui.QColor.fromRgbF(r, g, b), self, self._title)
        if colour.isValid():
            self.set_value((round(colour.redF(), 3), round(colour.greenF(), 3), round(colour.blueF(), 3)))
            self.edited.emit(self._value, False)


class ChoiceEditor(_ComboBox):
    """A combo box of options; each item shows its label and carries its value.

    The box may be narrower than its longest label (the list drops down whole); its tooltip names the
    item shown, so a cut text can be read whole.
    """

    edited = QtCore.Signal(object, bool)

    def __init__(self, options, labels=None, *, help="", parent=None):  # noqa: A002 (the table's name)
        super().__init__(parent)
        labels = labels or {}
        self._help = help
        self.setFocusPolicy(QtCore.Qt.FocusPolicy.StrongFocus)
        self.setSizeAdjustPolicy(QtWidgets.QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        self.setMinimumContentsLength(8)
        for option in options:
            self.addItem(str(labels.get(option, option)), option)
        self.currentIndexChanged.connect(self._chosen)
        self._tip()

    def value(self):
        """The value of the item shown."""
        return self.currentData()

    def set_value(self, value) -> None:
        """Show the item of ``value`` without reporting it (an unknown value leaves the box as it is)."""
        i = self.findData(value)
        if i >= 0:
            blocked = self.blockSignals(True)
            self.setCurrentIndex(i)
            self.blockSignals(blocked)
        self._tip()

    def _tip(self):
        self.setToolTip(f"{self.currentText()}: {self._help}" if self._help else self.currentText())

    def _chosen(self, _index):
        self._tip()
        self.edited.emit(self.currentData(), False)


class CheckEditor(QtWidgets.QCheckBox):
    """A check box reporting ``edited(bool, False)``."""

    edited = QtCore.Signal(object, bool)

    def __init__(self, text, parent=None):
        super().__init__(text, parent)
        self.toggled.connect(lambda on: self.edited.emit(bool(on), False))

    def value(self) -> bool:
        """Whether the box is checked."""
        return self.isChecked()

    def set_value(self, value) -> None:
        """Check or clear the box without reporting it."""
        blocked = self.blockSignals(True)
        self.setChecked(bool(value))
        self.blockSignals(blocked)


class TermsEditor(QtWidgets.QWidget):
    """One check box per term; reports the tuple of the checked terms, in the terms' order.

    Attributes
    ----------
    boxes : dict of str to QCheckBox
    """

    edited = QtCore.Signal(object, bool)

    def __init__(self, terms, parent=None):
        super().__init__(parent)
        self._terms = tuple(terms)
        flow = QtWidgets.QGridLayout(self)
        flow.setContentsMargins(0, 0, 0, 0)
        flow.setHorizontalSpacing(6)
        flow.setVerticalSpacing(2)
        self.boxes = {}
        for i, term in enumerate(self._terms):
            box = QtWidgets.QCheckBox(term, self)
            box.toggled.connect(self._toggled)
            flow.addWidget(box, i // 2, i % 2)
            self.boxes[term] = box

    def value(self) -> tuple:
        """The checked terms."""
        return tuple(t for t in self._terms if self.boxes[t].isChecked())

    def set_value(self, value) -> None:
        """Check the boxes of ``value``'s terms, clear the others, without reporting it."""
        for term, box in self.boxes.items():
            blocked = box.blockSignals(True)
            box.setChecked(term in value)
            box.blockSignals(blocked)

    def _toggled(self, _on):
        self.edited.emit(self.value(), False)

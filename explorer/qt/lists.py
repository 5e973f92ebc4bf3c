"""The lists beside the control panel: the scene's lights and the comparison list.

:class:`LightsPanel` lists what lights the sphere: the ambient light, the key light, the environment
(when one is on) and every extra light of the ``scene_lights`` control, each described by
:func:`explorer.app.lights.light_label`.  Extra lights are added (a menu of
:data:`~explorer.app.lights.EXTRA_LIGHT_TYPES`), removed, and edited with editors generated from
:data:`~explorer.app.lights.LIGHT_FIELDS`; every edit is a request ``{"scene_lights": new_tuple}``, as the
control panel's.  Selecting the ambient, key or environment row asks the window to show that section of
the control panel (:attr:`LightsPanel.section_requested`).

:class:`ComparePanel` shows :attr:`ExplorerModel.compare <explorer.app.views.ExplorerModel>`: one row per
entry (its colour, its whole label, shown, solo, remove) and the Pin and Fit buttons; every click is a
request (:attr:`ComparePanel.action_requested`) the window carries out before calling
:meth:`ComparePanel.sync`.  Rows are replaced with ``deleteLater``: the × clicked may be the row's own,
and a widget must outlive the handler of its own signal.
"""

from __future__ import annotations

import importlib
import math
from types import SimpleNamespace

from PySide6 import QtCore, QtGui, QtWidgets

from ._controls_editors import CheckEditor, ChoiceEditor, ColourEditor, NumberEditor

__all__ = ["LightsPanel", "ComparePanel", "Vec3Editor", "light_fields"]

MUTED = "#9aa1a9"
ERROR = "#ff8787"


def _lights_module():
    """:mod:`explorer.app.lights`, imported when a panel first needs it."""
    return importlib.import_module("explorer.app.lights")


def light_fields(kind: str) -> tuple:
    """The field descriptions of an extra light of type ``kind``, each as a namespace.

    :data:`~explorer.app.lights.LIGHT_FIELDS` rows are ``(name, kind, lo, hi, log, help)`` tuples (a
    ``choice`` row may add its choices) or objects with those attributes.

    Parameters
    ----------
    kind : str
        A type of :data:`~explorer.app.lights.EXTRA_LIGHT_TYPES`.

    Returns
    -------
    tuple of SimpleNamespace
        ``name``, ``kind``, ``lo``, ``hi``, ``log``, ``help``, ``choices``.
    """
    out = []
    for f in _lights_module().LIGHT_FIELDS.get(kind, ()):
        if hasattr(f, "name"):
            d = {a: getattr(f, a, None) for a in ("name", "kind", "lo", "hi", "log", "help")}
            d["choices"] = tuple(getattr(f, "choices", ()) or ())
        else:
            row = tuple(f) + (None,) * max(0, 7 - len(f))
            d = dict(zip(("name", "kind", "lo", "hi", "log", "help"), row[:6], strict=True))
            d["choices"] = tuple(row[6] or ())
        if d["kind"] == "choice" and not d["choices"] and isinstance(d["lo"], (tuple, list)):
            d["choices"] = tuple(d["lo"])
        d["log"] = bool(d["log"])
        d["help"] = d["help"] or ""
        out.append(SimpleNamespace(**d))
    return tuple(out)


class Vec3Editor(QtWidgets.QWidget):
    """Three numbers (x, y, z) in spin boxes; reports the triple, ``edited(tuple, False)``."""

    edited = QtCore.Signal(object, bool)

    def __init__(self, lo=None, hi=None, *, title="", parent=None):
        super().__init__(parent)
        lo = -100.0 if lo is None or not math.isfinite(lo) else float(lo)
        hi = 100.0 if hi is None or not math.isfinite(hi) else float(hi)
        row = QtWidgets.QHBoxLayout(self)
        row.setContentsMargins(0, 0, 0, 0)
        row.setSpacing(3)
        self.spins = []
        for axis in "xyz":
            spin = QtWidgets.QDoubleSpinBox(self)
            spin.setRange(lo, hi)
            # Four decimals, as the light tables keep them: an edit of one coordinate sends the others unchanged.
            spin.setDecimals(4)
            spin.setSingleStep(0.1)
            spin.setKeyboardTracking(False)
            spin.setButtonSymbols(QtWidgets.QAbstractSpinBox.ButtonSymbols.NoButtons)
            spin.setToolTip(f"{title}: {axis}")
            spin.valueChanged.connect(self._typed)
            row.addWidget(spin, 1)
            self.spins.append(spin)
        self.spins = tuple(self.spins)

    def value(self) -> tuple:
        """The triple shown."""
        return tuple(float(s.value()) for s in self.spins)

    def set_value(self, value) -> None:
        """Show ``value`` (three numbers) without reporting it."""
        for spin, v in zip(self.spins, value, strict=True):
            blocked = spin.blockSignals(True)
            spin.setValue(float(v))
            spin.blockSignals(blocked)

    def _typed(self, _=None):
        self.edited.emit(self.value(), False)


def _number_editor(f) -> NumberEditor:
    """A slider and spin box for a number field; whole-number ends (``samples`` 1 … 256) make an integer editor."""
    if isinstance(f.lo, int) and isinstance(f.hi, int) and not isinstance(f.lo, bool):
        return NumberEditor(f.lo, f.hi, integer=True)
    lo = 0.0 if f.lo is None else float(f.lo)
    hi = float(f.hi) if f.hi is not None and math.isfinite(f.hi) else (lo + 10.0 if not f.log else max(lo, 1.0) * 1e4)
    if f.log:
        low = lo if lo > 0 else hi * 1e-6
        return NumberEditor(math.log10(low), math.log10(hi), minimum=lo, maximum=f.hi if f.hi is not None else hi,
                            log=True)  # fmt: skip
    return NumberEditor(lo, hi, minimum=lo, maximum=f.hi if f.hi is not None else hi)


class LightsPanel(QtWidgets.QWidget):
    """The scene's lights: ambient, key, environment and the extra lights, which are added, removed and edited.

    Parameters
    ----------
    state : AppState
        The explorer's state (read: ``ambient``, ``light``, ``environment``, ``scene_lights``).
    parent : QWidget, optional

    Attributes
    ----------
    change_requested : Signal(object, bool)
        ``({"scene_lights": new_tuple}, live)``, as the control panel's requests.
    section_requested : Signal(str)
        The control panel's section to show, when the ambient (``"Light"``), key (``"Light"``) or
        environment (``"Environment"``) row is selected.
    """

    change_requested = QtCore.Signal(object, bool)
    section_requested = QtCore.Signal(str)

    def __init__(self, state, parent=None):
        super().__init__(parent)
        self._state = state
        self._rows: list[tuple] = []
        self._fields_for = None  # (index, type) of the light whose editors are shown
        self._field_editors: dict[str, QtWidgets.QWidget] = {}
        self._select_next = None
        self.list = QtWidgets.QListWidget(self)
        self.list.setWordWrap(True)
        self.list.setTextElideMode(QtCore.Qt.TextElideMode.ElideNone)
        self.list.setUniformItemSizes(False)
        self.list.setResizeMode(QtWidgets.QListView.ResizeMode.Adjust)
        self.list.setSelectionMode(QtWidgets.QAbstractItemView.SelectionMode.SingleSelection)
        self.list.currentRowChanged.connect(self._selected)
        self.add_button = QtWidgets.QToolButton(self)
        self.add_button.setText("Add light")
        self.add_button.setToolTip("add an extra light to the scene")
        self.add_button.setPopupMode(QtWidgets.QToolButton.ToolButtonPopupMode.InstantPopup)
        # Room for the menu's arrow after the text (Fusion draws it inside the button's text rectangle).
        self.add_button.setStyleSheet("QToolButton { padding-right: 14px; }")
        self.add_menu = QtWidgets.QMenu(self.add_button)
        self.add_button.setMenu(self.add_menu)
        self.remove_button = QtWidgets.QToolButton(self)
        self.remove_button.setText("Remove")
        self.remove_button.setToolTip("remove the selected extra light")
        self.remove_button.clicked.connect(self.remove_selected)
        buttons = QtWidgets.QHBoxLayout()
        buttons.addWidget(self.add_button)
        buttons.addWidget(self.remove_button)
        buttons.addStretch(1)
        self.fields = QtWidgets.QGroupBox("", self)
        self._fields_form = QtWidgets.QVBoxLayout(self.fields)
        self._fields_form.setContentsMargins(6, 6, 6, 6)
        self._fields_body = None
        self.fields.hide()
        self.message = QtWidgets.QLabel(self)
        self.message.setWordWrap(True)
        self.message.setStyleSheet(f"color: {ERROR};")
        self.message.hide()
        column = QtWidgets.QVBoxLayout(self)
        column.setContentsMargins(6, 6, 6, 6)
        column.addWidget(self.list, 1)
        column.addLayout(buttons)
        column.addWidget(self.message)
        column.addWidget(self.fields)
        self._menu_built = False
        self.sync(state)

    # ------------------------------------------------------------------ actions
    def add_light(self, kind: str) -> None:
        """Request a new extra light of type ``kind`` (:func:`~explorer.app.lights.new_light`), selected after."""
        lights = _lights_module()
        table = lights.new_light(kind, self._state)
        current = tuple(getattr(self._state, "scene_lights", ()) or ())
        self._select_next = ("extra", len(current))
        self.change_requested.emit({"scene_lights": current + (table,)}, False)

    def remove_selected(self) -> None:
        """Request the selected extra light's removal (nothing when another row is selected)."""
        row = self.list.currentRow()
        if not 0 <= row < len(self._rows) or self._rows[row][0] != "extra":
            return
        i = self._rows[row][1]
        current = tuple(getattr(self._state, "scene_lights", ()) or ())
        self._select_next = ("extra", i - 1) if i > 0 else None
        self.change_requested.emit({"scene_lights": current[:i] + current[i + 1 :]}, False)

    def set_field(self, index: int, name: str, value, live: bool = False) -> None:
        """Request one field of extra light ``index`` changed (:func:`~explorer.app.lights.with_field`).

        A value the light refuses is shown under the list, and the editors return to the state's values.
        """
        current = tuple(getattr(self._state, "scene_lights", ()) or ())
        try:
            new = _lights_module().with_field(current, index, name, value)
        except ValueError as exc:
            self._show_message(str(exc))
            self._show_fields(self._state)
            return
        self._show_message("")
        self.change_requested.emit({"scene_lights": new}, live)

    def _show_message(self, text: str) -> None:
        self.message.setText(text)
        self.message.setToolTip(text)
        self.message.setVisible(bool(text))

    # ------------------------------------------------------------------ showing the state
    def sync(self, state) -> None:
        """Show ``state``'s lights: the list's rows, and the selected extra light's fields.

        Parameters
        ----------
        state : AppState
        """
        self._state = state
        if not self._menu_built:
            self._build_menu()
        rows = self._wanted_rows(state)
        keep = self._select_next or (self._rows[self.list.currentRow()][:2]
                                     if 0 <= self.list.currentRow() < len(self._rows) else None)  # fmt: skip
        self._select_next = None
        blocked = self.list.blockSignals(True)
        if [r[:2] for r in rows] != [r[:2] for r in self._rows]:
            self.list.clear()
            for *_, text in rows:
                item = QtWidgets.QListWidgetItem(text)
                item.setToolTip(text)
                self.list.addItem(item)
        else:
            for i, (_, _, text) in enumerate(rows):
                item = self.list.item(i)
                if item.text() != text:
                    item.setText(text)
                    item.setToolTip(text)
        self._rows = rows
        index = next((i for i, r in enumerate(rows) if keep is not None and r[:2] == tuple(keep)), -1)
        self.list.setCurrentRow(index)
        self.list.blockSignals(blocked)
        self._update_buttons()
        self._show_fields(state)

    def _build_menu(self):
        try:
            kinds = _lights_module().EXTRA_LIGHT_TYPES
        except ImportError:
            kinds = ()
        for kind in kinds:
            action = self.add_menu.addAction(kind)
            action.triggered.connect(lambda _checked=False, kind=kind: self.add_light(kind))
        self.add_button.setEnabled(bool(kinds))
        self._menu_built = True

    def _wanted_rows(self, state) -> list:
        rows = [("ambient", None, f"ambient I_a = {state.ambient:g}")]
        key = "none (ambient only)" if state.light == "ambient" else state.light
        rows.append(("key", None, f"key: {key}"))
        if state.environment != "none":
            rows.append(("environment", None, f"environment: {state.environment}"))
        extra = tuple(getattr(state, "scene_lights", ()) or ())
        if extra:
            label = _lights_module().light_label
            rows += [("extra", i, label(table)) for i, table in enumerate(extra)]
        return rows

    def _update_buttons(self):
        row = self.list.currentRow()
        extra = 0 <= row < len(self._rows) and self._rows[row][0] == "extra"
        self.remove_button.setEnabled(extra)

    def _selected(self, row: int) -> None:
        self._update_buttons()
        self._show_fields(self._state)
        if 0 <= row < len(self._rows):
            kind = self._rows[row][0]
            if kind in ("ambient", "key"):
                self.section_requested.emit("Light")
            elif kind == "environment":
                self.section_requested.emit("Environment")

    def selected_light(self) -> int | None:
        """The index in ``scene_lights`` of the selected extra light, or None."""
        row = self.list.currentRow()
        if 0 <= row < len(self._rows) and self._rows[row][0] == "extra":
            return self._rows[row][1]
        return None

    def field_editor(self, name: str) -> QtWidgets.QWidget:
        """The editor of a field of the selected extra light (tests use it)."""
        return self._field_editors[name]

    def _show_fields(self, state) -> None:
        i = self.selected_light()
        extra = tuple(getattr(state, "scene_lights", ()) or ())
        if i is None or i >= len(extra):
            self._fields_for = None
            self.fields.hide()
            return
        table = extra[i]
        kind = table.get("type", "")
        if self._fields_for != (i, kind):
            self._build_fields(i, kind)
        field_value = _lights_module().field_value
        for name, editor in self._field_editors.items():
            editor.set_value(field_value(table, name))
        self.fields.setTitle(f"light {i + 1}: {kind}")
        self.fields.show()

    def _build_fields(self, index: int, kind: str) -> None:
        """The editors of one extra light's fields (the old ones deleted later: one may be in its own handler)."""
        if self._fields_body is not None:
            old = self._fields_body
            old.hide()
            self._fields_form.removeWidget(old)
            old.deleteLater()
        body = QtWidgets.QWidget(self.fields)
        grid = QtWidgets.QGridLayout(body)
        grid.setContentsMargins(0, 0, 0, 0)
        grid.setHorizontalSpacing(6)
        self._field_editors = {}
        for r, f in enumerate(light_fields(kind)):
            label = f.name.replace("_", " ")
            tip = f"{label}: {f.help}" if f.help else label
            if f.kind == "vec3":
                editor = Vec3Editor(f.lo, f.hi, title=label)
            elif f.kind == "color":
                editor = ColourEditor(title=label)
            elif f.kind == "number":
                editor = _number_editor(f)
            elif f.kind == "choice":
                editor = ChoiceEditor(f.choices, help=f.help)
            elif f.kind == "bool":
                editor = CheckEditor(label)
            else:
                raise ValueError(f"LIGHT_FIELDS[{kind!r}] field {f.name} has kind {f.kind!r}; the panel shows "
                                 f"vec3, color, number, choice and bool")  # fmt: skip
            editor.setParent(body)
            editor.setToolTip(editor.toolTip() or tip)
            editor.edited.connect(lambda value, live, name=f.name, i=index: self.set_field(i, name, value, live))
            if f.kind == "bool":
                grid.addWidget(editor, r, 0, 1, 2)
            else:
                text = QtWidgets.QLabel(label, body)
                text.setWordWrap(True)
                text.setToolTip(tip)
                grid.addWidget(text, r, 0)
                grid.addWidget(editor, r, 1)
            self._field_editors[f.name] = editor
        grid.setColumnStretch(1, 1)
        self._fields_form.addWidget(body)
        self._fields_body = body
        self._fields_for = (index, kind)


class _Swatch(QtWidgets.QWidget):
    """A small square in an entry's colour."""

    def __init__(self, colour: str, parent=None):
        super().__init__(parent)
        self.colour = QtGui.QColor(colour)
        self.setFixedSize(14, 14)

    def paintEvent(self, _event):  # noqa: N802 (Qt's name)
        painter = QtGui.QPainter(self)
        painter.fillRect(self.rect(), self.colour)
        painter.end()


class _EntryRow(QtWidgets.QWidget):
    """One entry: shown, swatch, its whole label (wrapped), solo, ×."""

    def __init__(self, entry, solo: bool, panel, parent=None):
        super().__init__(parent)
        self.key = entry.key
        self.shown = QtWidgets.QCheckBox(self)
        self.shown.setToolTip(f"show {entry.label} in the plots")
        self.swatch = _Swatch(entry.colour, self)
        self.label = QtWidgets.QLabel(entry.label, self)
        self.label.setTextFormat(QtCore.Qt.TextFormat.PlainText)
        self.label.setWordWrap(True)
        self.label.setToolTip(entry.label)
        # A new size policy drops the height-for-width that word wrap set: without it a wrapped label keeps one
        # line's height and its two lines are cut.
        policy = QtWidgets.QSizePolicy(QtWidgets.QSizePolicy.Policy.Ignored, QtWidgets.QSizePolicy.Policy.Preferred)
        policy.setHeightForWidth(True)
        self.label.setSizePolicy(policy)
        self.label.setStyleSheet(f"color: {QtGui.QColor(entry.colour).name()};")
        self.solo = QtWidgets.QCheckBox("solo", self)
        self.solo.setToolTip(f"show {entry.label} alone")
        self.remove = QtWidgets.QToolButton(self)
        self.remove.setText("×")
        self.remove.setToolTip(f"remove {entry.label} from the comparison")
        row = QtWidgets.QHBoxLayout(self)
        row.setContentsMargins(2, 1, 2, 1)
        row.setSpacing(5)
        row.addWidget(self.shown)
        row.addWidget(self.swatch)
        row.addWidget(self.label, 1)
        row.addWidget(self.solo)
        row.addWidget(self.remove)
        self.set_state(entry.visible, solo)
        key = entry.key
        self.shown.toggled.connect(lambda on: panel.action_requested.emit("visible", (key, bool(on))))
        self.solo.toggled.connect(lambda on: panel.action_requested.emit("solo", key if on else None))
        self.remove.clicked.connect(lambda: panel.action_requested.emit("remove", key))

    def set_state(self, visible: bool, solo: bool) -> None:
        for box, on in ((self.shown, visible), (self.solo, solo)):
            blocked = box.blockSignals(True)
            box.setChecked(on)
            box.blockSignals(blocked)


class ComparePanel(QtWidgets.QWidget):
    """The comparison list: one row per entry, and the Pin and Fit buttons.

    Parameters
    ----------
    compare : explorer.compare.BRDFList
        The list shown first.
    parent : QWidget, optional

    Attributes
    ----------
    action_requested : Signal(str, object)
        ``("pin", None)``, ``("fit", None)``, ``("remove", key)``, ``("visible", (key, bool))``,
        ``("solo", key or None)``; ``key`` is the entry's :attr:`~explorer.compare.Entry.key`.
    rows : list of QWidget
        The rows shown, in the list's order (each has ``key``, ``shown``, ``label``, ``solo``, ``remove``).
    """

    action_requested = QtCore.Signal(str, object)

    def __init__(self, compare, parent=None):
        super().__init__(parent)
        self.pin_button = QtWidgets.QPushButton("Pin current (p)", self)
        self.pin_button.setToolTip("add the current model, with its parameters, to the comparison")
        self.pin_button.clicked.connect(lambda: self.action_requested.emit("pin", None))
        self.fit_button = QtWidgets.QPushButton("Fit", self)
        self.fit_button.setToolTip("fit the fit control's analytic model to the current model and add it")
        self.fit_button.clicked.connect(lambda: self.action_requested.emit("fit", None))
        buttons = QtWidgets.QHBoxLayout()
        buttons.addWidget(self.pin_button)
        buttons.addWidget(self.fit_button)
        buttons.addStretch(1)
        self.hint = QtWidgets.QLabel("Nothing pinned: Pin current (p) adds the current model.", self)
        self.hint.setWordWrap(True)
        self.hint.setStyleSheet(f"color: {MUTED};")
        self._host = QtWidgets.QVBoxLayout()
        self._host.setContentsMargins(0, 0, 0, 0)
        self._body = None
        self._signature = None
        self.rows: list[_EntryRow] = []
        column = QtWidgets.QVBoxLayout(self)
        column.setContentsMargins(6, 6, 6, 6)
        column.addLayout(buttons)
        column.addWidget(self.hint)
        column.addLayout(self._host)
        column.addStretch(1)
        self.sync(compare)

    def sync(self, compare) -> None:
        """Show ``compare``'s entries: rows rebuilt when entries came or went, else their boxes updated.

        Parameters
        ----------
        compare : explorer.compare.BRDFList
        """
        entries = list(compare)
        signature = tuple((e.key, e.label, e.colour) for e in entries)
        if signature != self._signature:
            self._rebuild(entries, compare.solo)
            self._signature = signature
        for i, (row, e) in enumerate(zip(self.rows, entries, strict=True)):
            row.set_state(e.visible, compare.solo == i)
        self.hint.setVisible(not entries)
        full = len(entries) >= compare.max_entries
        self.pin_button.setEnabled(not full)
        self.fit_button.setEnabled(not full)
        reason = f"the comparison holds at most {compare.max_entries} BRDFs; remove one first" if full else ""
        self.pin_button.setToolTip(reason or "add the current model, with its parameters, to the comparison")

    def _rebuild(self, entries, solo) -> None:
        if self._body is not None:
            old = self._body
            old.hide()
            self._host.removeWidget(old)
            old.deleteLater()  # never now: the × clicked may be one of its rows
        body = QtWidgets.QWidget(self)
        rows = QtWidgets.QVBoxLayout(body)
        rows.setContentsMargins(0, 0, 0, 0)
        rows.setSpacing(2)
        self.rows = []
        for i, e in enumerate(entries):
            row = _EntryRow(e, solo == i, self, body)
            rows.addWidget(row)
            self.rows.append(row)
        self._host.addWidget(body)
        self._body = body

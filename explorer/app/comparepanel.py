"""The Compare column of the control panel: pin and fit, the split sphere, and one row per entry of the list.

Each entry of the comparison list (:attr:`ExplorerModel.compare <explorer.app.views.ExplorerModel>`)
is a row: a check box in the entry's colour (shown or hidden), its label in its colour (the legend of
every plot's coloured curves), a *solo* box and a *×* that removes it.  The rows are rebuilt when the
list changes.  The actions (:meth:`ComparePanelMixin.pin`, :meth:`~ComparePanelMixin.fit`,
:meth:`~ComparePanelMixin.remove_entry`, :meth:`~ComparePanelMixin.set_entry_visible`,
:meth:`~ComparePanelMixin.set_solo`, :meth:`~ComparePanelMixin.open_brdf`) are what the buttons and
keys call, and what the tests call.  A mixin of :class:`~explorer.app.widgets.WidgetsMixin`.
"""

from __future__ import annotations

from .layout import CONTROLS_PANEL, MUTED, SCANLINE, TEXT
from .modelcontrols import button_width

__all__ = ["ComparePanelMixin"]

#: Characters of an entry's label the row shows (the albedo plot's legend shows it whole).
LABEL_CHARS = 22


def _rgb(colour) -> tuple:
    from matplotlib.colors import to_rgb

    return tuple(float(c) for c in to_rgb(colour))


class ComparePanelMixin:
    """The comparison list's controls and actions (see the module)."""

    _compare_built = None

    # ------------------------------------------------------------------ status line
    def status(self, text: str, *, error: bool = False, render: bool = True):
        """Show ``text`` in the status line (the panel's bottom right corner); red for an error.

        Parameters
        ----------
        text : str
            The message (cut at 150 characters).
        error : bool
            Red instead of muted.
        render : bool
            Render the window now (the fit says "fitting…" before it starts).
        """
        self._set_text("hint", text[:150])
        self.captions["hint"].GetTextProperty().SetColor(*(SCANLINE if error else MUTED))
        if render:
            self._render()

    # ------------------------------------------------------------------ actions
    def _list_changed(self, render=True):
        views = self.refresh(render=False)
        self.last_views = views
        self._sync_compare_rows()
        if render:
            self._render()
        return views

    def pin(self, label: str | None = None, *, render=True):
        """Add the current model with its current parameters to the comparison list (button *pin*, key ``p``).

        Parameters
        ----------
        label : str, optional
            Default: the model and its numbers (:func:`~explorer.app.comparing.pin_label`).
        render : bool
            Render the window afterwards.

        Returns
        -------
        Entry or None
            The new entry (None when the list is full: the status line says so).
        """
        try:
            entry = self.model.pin(label)
        except ValueError as exc:
            self.status(f"not pinned: {exc}", error=True, render=render)
            return None
        self.status(f"pinned: {entry.label}", render=False)
        self._list_changed(render)
        return entry

    def fit(self, name: str | None = None, *, render=True):
        """Fit an analytic model to the current model and add it to the list (button *fit*, key ``F``).

        Takes a second or more: the status line says "fitting …" while it runs (a click or a key,
        never a drag), then the fit's relative rms residual.

        Parameters
        ----------
        name : str, optional
            A name of :data:`~explorer.app.comparing.FIT_MODELS`; default the ``fit`` control.
        render : bool
            Render the window afterwards.

        Returns
        -------
        (Entry, FitResult) or None
            None when the fit was refused (a full list, nothing to fit): the status line says why.
        """
        from .comparing import FIT_MODELS

        what = FIT_MODELS.get(name or self.state.fit, ("?", {}, name))[2]
        self.status(f"fitting {what} to {self._model_title()} … (a few seconds)", render=render)
        try:
            entry, result = self.model.fit(name)
        except ValueError as exc:
            self.status(f"no fit: {exc}", error=True, render=render)
            return None
        self.status(f"fitted {what}: relative rms {result.relative_rms:.3f} in {result.evaluations} evaluations",
                    render=False)  # fmt: skip
        self._list_changed(render)
        return entry, result

    def open_brdf(self, path, *, current: bool = False, render=True) -> str:
        """Open a BRDF file (``.brdf``, MERL ``.binary``): the current model, or an entry of the list.

        Parameters
        ----------
        path : str or os.PathLike
            The file.
        current : bool
            Make it the current model (its controls appear in the Material column).
        render : bool
            Render the window afterwards.

        Returns
        -------
        str
            The registered model's name.
        """
        name = self.model.open_brdf(path, current=current)
        self._rebuild_model_buttons()
        self.refresh(render=False)
        self._sync_widgets()
        if render:
            self._render()
        return name

    def remove_entry(self, index: int, *, render=True):
        """Take an entry out of the list (its row's *×*).

        Parameters
        ----------
        index : int
        render : bool
        """
        self.model.compare.remove(index)
        self._list_changed(render)

    def set_entry_visible(self, index: int, visible: bool = True, *, render=True):
        """Show or hide an entry (its row's coloured box).

        Parameters
        ----------
        index : int
        visible : bool
        render : bool
        """
        self.model.compare.set_visible(index, visible)
        self._list_changed(render)

    def set_solo(self, index, *, render=True):
        """Show this entry alone (``None``: back to the check boxes), as its row's *solo* box.

        Parameters
        ----------
        index : int or None
        render : bool
        """
        self.model.compare.set_solo(index)
        self._list_changed(render)

    # ------------------------------------------------------------------ widgets
    def _place_actions(self, actions, x0, x1, y):
        """Push buttons (the box lights while the action runs, then goes out)."""
        entries = [(key, label, self._action_maker(key)) for key, label in actions]
        widgets, y = self._flow(entries, x0, x1, y, prefix="act_")
        self.actions = widgets
        return y

    def _action_maker(self, key):
        def make(x, y):
            return self._button(self._action_callback(key), False, x, y)

        return make

    def _action_callback(self, key):
        def callback(flag):
            if self._building:
                return
            self.actions[key].GetRepresentation().SetState(0)
            if key == "pin":
                self.pin(render=False)
            elif key == "fit":
                self.fit(render=True)

        return callback

    def _rebuild_model_buttons(self):
        """The model buttons again (a file model was registered): the Model column's first item."""
        from .widgets import PANEL

        widgets = getattr(self.plotter, "widgets", self.plotter)
        for widget in self.buttons.pop("model", {}).values():
            widget.Off()
            if widget in widgets.button_widgets:
                widgets.button_widgets.remove(widget)
        ren = self._renderer(CONTROLS_PANEL)
        for key in [k for k in self.captions if k.startswith("btn_model_")]:
            ren.RemoveViewProp(self.captions.pop(key))
        x0, x1 = PANEL[0][0], PANEL[0][1]
        building, self._building = self._building, True
        self._place_buttons("model", x0, x1, 17.0 * self.ui_scale)
        self._building = building

    def _clear_compare_rows(self):
        widgets = getattr(self.plotter, "widgets", self.plotter)
        for widget in getattr(self, "_compare_widgets", []):
            widget.Off()
            if widget in widgets.button_widgets:
                widgets.button_widgets.remove(widget)
        ren = self._renderer(CONTROLS_PANEL)
        for key in [k for k in self.captions if k.startswith("cmp_")]:
            ren.RemoveViewProp(self.captions.pop(key))
        self._compare_widgets = []
        self.compare_boxes: dict = {}

    def _compare_signature(self):
        return tuple((e.key, e.label, e.colour) for e in self.model.compare)

    def _build_compare_rows(self):
        """One row per entry: [shown, in its colour] label … [solo] [×]; a hint when the list is empty."""
        from .widgets import BOX, ROW_STEP

        building, self._building = self._building, True
        self._clear_compare_rows()
        x0, x1, y = self._compare_column
        s = self.ui_scale
        left, right = self._px(x0 + 0.008), self._px(x1 - 0.006)
        entries = list(self.model.compare)
        if not entries:
            ty = 1.0 - (y + (BOX / 2 + 1) * s) / self._panel_h
            self._text(CONTROLS_PANEL, "cmp_empty", "white: the current model\np pins it here, F fits it",
                       left / self._panel_w, ty, size=8.5, color=MUTED, valign="top")  # fmt: skip
        bottom = self._panel_h - 14.0 * s
        solo_w, remove_w = button_width("solo", s), button_width("×", s)
        for i, e in enumerate(entries):
            if y + ROW_STEP * s > bottom:
                more = len(entries) - i
                ty = 1.0 - (y + (BOX / 2 + 1) * s) / self._panel_h
                self._text(CONTROLS_PANEL, "cmp_more", f"+{more} more", left / self._panel_w, ty, size=8.5,
                           color=MUTED, valign="center")  # fmt: skip
                break
            y_px = self._panel_h - y - (BOX + 2.0) * s
            rgb = _rgb(e.colour)
            dim = tuple(0.3 * c for c in rgb)
            show = self._button(self._entry_callback("show", i), e.visible, left, y_px, rgb, dim)
            solo = self._button(self._entry_callback("solo", i), self.model.compare.solo == i,
                                right - solo_w - remove_w, y_px)  # fmt: skip
            remove = self._button(self._entry_callback("remove", i), False, right - remove_w, y_px)
            self.compare_boxes[i] = {"show": show, "solo": solo, "remove": remove}
            self._compare_widgets += [show, solo, remove]
            room = max(4, int((right - solo_w - remove_w - left - (BOX + 8) * s) / (4.7 * s)))
            label = e.label if len(e.label) <= room else e.label[: room - 1] + "…"
            ty = 1.0 - (y + (BOX / 2 + 1) * s) / self._panel_h
            self._text(CONTROLS_PANEL, f"cmp_label{i}", label, (left + (BOX + 4) * s) / self._panel_w, ty, size=8.5,
                       color=rgb, valign="center")  # fmt: skip
            for key, text, x in (("solo", "solo", right - solo_w - remove_w), ("remove", "×", right - remove_w)):
                self._text(CONTROLS_PANEL, f"cmp_{key}{i}", text, (x + (BOX + 4) * s) / self._panel_w, ty, size=8.5,
                           color=TEXT, valign="center")  # fmt: skip
            y += ROW_STEP * s
        self._compare_built = self._compare_signature()
        self._building = building

    def _sync_compare_rows(self):
        """Rebuild the rows if the list changed; else make their boxes show the entries' state."""
        if not hasattr(self, "_compare_column"):
            return
        if self._compare_built != self._compare_signature():
            self._build_compare_rows()
            return
        for i, boxes in self.compare_boxes.items():
            e = self.model.compare[i]
            for key, want in (("show", e.visible), ("solo", self.model.compare.solo == i), ("remove", False)):
                rep = boxes[key].GetRepresentation()
                if rep.GetState() != int(want):
                    rep.SetState(int(want))

    def _entry_callback(self, kind, index):
        def callback(flag):
            if self._building:
                return
            if kind == "show":
                self.set_entry_visible(index, bool(flag), render=False)
            elif kind == "solo":
                self.set_solo(index if flag else None, render=False)
            else:
                self.remove_entry(index, render=False)

        return callback

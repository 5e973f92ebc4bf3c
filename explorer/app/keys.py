"""The window's keys and its help overlay (a mixin of :class:`~explorer.app.window.ExplorerApp`)."""

from __future__ import annotations

from .layout import ACCENT, TEXT, _font_file
from .state import CHANNELS, CONTROLS, ENVIRONMENTS, FORMS, LIGHT_TYPES, MODELS, TERM_NAMES

__all__ = ["HELP_TEXT", "KeysMixin"]

HELP_TEXT = """ lighting-explorer: keys and mouse

 Drag the sliders below the views; click the boxes to switch plot options.
 Every colour on screen is computed by the engine (VTK lighting is off).

   h           show / hide this help
   s           save a screenshot of the window (PNG in the current folder)
   r           reset every control to its default
   m  /  M     next / previous reflectance model
   t           next light type (directional, point, spot, ambient)
   i           next shading mode of the lit sphere (flat, Gouraud, Phong)
   f           classic  I  /  physical radiance  I/π
   1  2  3     ambient / diffuse / specular term on or off
   c           next plot channel (luminance Y, R, G, B)
   l           plots: log10(1 + x) on or off
   n           plots: × n·l on or off
   e           triangle edges on the coarse spheres on or off
   p           pin the current model to the Compare list
   F           fit the chosen analytic model to the current one (seconds)
   a           right panel: angle curves / albedo ρ(θ_v)
   v           split lit sphere: current | first shown entry
   x           next environment (none, the skies, the file)
   o           3D panel: BRDF lobe / lit object
   k           environment by the Monte-Carlo reference (keeps sampling
               while the view rests) / by the split sum
   Up / Down   move the scan line
   Left/Right  coarser / finer coarse sphere
   q           quit

 Mouse: rotate the 3D lobe with the left button, zoom with the wheel. """


class KeysMixin:
    """Key presses (:meth:`on_key`, bound by :meth:`_bind_keys`) and the help overlay (``h``)."""

    def _build_help(self):
        import vtk

        # A renderer on a second layer over the whole window (layers above 0 keep what is below).
        ren = vtk.vtkRenderer()
        ren.SetLayer(1)
        ren.SetViewport(0.0, 0.0, 1.0, 1.0)
        ren.InteractiveOff()
        ren.DrawOff()
        actor = vtk.vtkTextActor()
        actor.SetInput(HELP_TEXT)
        prop = actor.GetTextProperty()
        prop.SetFontSize(self._font_px(15))
        prop.SetColor(*TEXT)
        prop.SetLineSpacing(1.2)
        prop.SetBackgroundColor(0.05, 0.055, 0.065)
        prop.SetBackgroundOpacity(0.95)
        prop.SetFrame(True)
        prop.SetFrameColor(*ACCENT)
        prop.SetFrameWidth(2)
        mono = _font_file("DejaVuSansMono.ttf")
        if mono:
            prop.SetFontFamily(vtk.VTK_FONT_FILE)
            prop.SetFontFile(mono)
        prop.SetJustification(0)
        prop.SetVerticalJustification(1)
        actor.GetPositionCoordinate().SetCoordinateSystemToNormalizedViewport()
        actor.GetPositionCoordinate().SetValue(0.27, 0.56)
        ren.AddViewProp(actor)
        rw = self.plotter.ren_win
        rw.SetNumberOfLayers(max(2, rw.GetNumberOfLayers()))
        rw.AddRenderer(ren)
        self.help_renderer = ren

    @property
    def help_visible(self) -> bool:
        """Whether the help overlay is shown."""
        return bool(self.help_renderer.GetDraw())

    def toggle_help(self, show=None):
        """Show or hide the help overlay (the ``h`` key).

        Parameters
        ----------
        show : bool, optional
            Show (True) or hide (False); default: the other way round from now.

        Returns
        -------
        bool
            Whether the help is shown now.
        """
        show = not self.help_visible if show is None else bool(show)
        self.help_renderer.SetDraw(show)
        self._render()
        return show

    def on_key(self, key: str) -> set[str]:
        """What a key press does (see the help text); returns the views it changed.

        Parameters
        ----------
        key : str
            The key symbol (``"m"``, ``"Up"``, ...).

        Returns
        -------
        set of str
            The names of the views recomputed (empty for keys that change no control).
        """
        s = self.state
        cycle = {
            "m": ("model", MODELS, 1),
            "M": ("model", MODELS, -1),
            "t": ("light", LIGHT_TYPES, 1),
            "i": ("mode", ("flat", "gouraud", "phong"), 1),
            "c": ("channel", CHANNELS, 1),
            "f": ("form", FORMS, 1),
        }
        if key in cycle:
            name, options, step = cycle[key]
            value = options[(options.index(getattr(s, name)) + step) % len(options)]
            return self.set_control(name, value)
        if key in ("1", "2", "3"):
            term = TERM_NAMES[int(key) - 1]
            terms = set(s.terms) ^ {term}
            return self.set_control("terms", tuple(terms))
        if key == "l":
            return self.set_control("log", not s.log)
        if key == "a":
            return self.set_control("panel", "angles" if s.panel == "albedo" else "albedo")
        if key == "v":
            return self.set_control("split", not s.split)
        if key == "x":
            options = [e for e in ENVIRONMENTS if e != "file" or self.model.environment_file is not None]
            current = options.index(s.environment) if s.environment in options else -1
            return self.set_control("environment", options[(current + 1) % len(options)])
        if key == "o":
            return self.set_control("view3d", "lobe" if s.view3d == "object" else "object")
        if key == "k":
            return self.set_control("reference", not s.reference)
        if key == "p":
            return set() if self.pin() is None else self.last_views
        if key == "F":
            return set() if self.fit() is None else self.last_views
        if key == "n":
            return self.set_control("times_cos", not s.times_cos)
        if key in ("Up", "Down"):
            spec = CONTROLS["scanline"]
            step = -0.02 if key == "Up" else 0.02
            return self.set_control("scanline", min(max(s.scanline + step, spec.lo), spec.hi))
        if key in ("Left", "Right"):
            # One step within the control's own range (the slider's too): finer never makes it coarser.
            spec = CONTROLS["tessellation"]
            t = min(max(s.tessellation + (1 if key == "Right" else -1), int(spec.lo)), int(spec.hi))
            return self.set_control("tessellation", t)
        if key == "r":
            return self.reset()
        if key == "h":
            self.toggle_help()
            return set()
        if key == "e":
            self.show_edges = not self.show_edges
            self.gouraud_edges.SetVisibility(self.show_edges)
            self.phong_edges.SetVisibility(self.show_edges)
            self._render()
            return set()
        if key == "s":
            path = self._next_screenshot_path()
            try:
                self.screenshot(path)
            except ValueError as exc:  # a full disk or a read-only folder: say so, keep the window
                print(f"lighting-explorer: screenshot not saved: {exc}")
                return set()
            print(f"lighting-explorer: saved {path}")
            return set()
        return set()

    def _bind_keys(self):
        pl = self.plotter
        keys = ["m", "M", "t", "i", "c", "f", "1", "2", "3", "l", "n", "Up", "Down", "Left", "Right", "r", "h"]
        keys += ["e", "s", "p", "F", "a", "v", "x", "o", "k"]
        for key in keys:
            pl.clear_events_for_key(key, raise_on_missing=False)
            pl.add_key_event(key, self._key_callback(key))
        # VTK's interactor style acts on characters by itself ('w' wireframe, 's' surface, 'r' camera reset,
        # '3' stereo, 'e' exit, ...), which would fight our keys and could turn the image planes into
        # wireframes.  An observer on the style's CharEvent replaces that behaviour; only 'q' still quits.
        style = getattr(pl.iren, "style", None) if pl.iren is not None else None
        if style is not None:
            style.AddObserver("CharEvent", self._on_char)
        iren = self._interactor()
        if iren is not None:
            iren.AddObserver("TimerEvent", self._on_timer)

    @staticmethod
    def _on_char(style, event):
        iren = style.GetInteractor()
        if iren is not None and iren.GetKeySym() == "q":
            iren.ExitCallback()

    def _key_callback(self, key):
        def callback():
            self.on_key(key)  # renders when something changed

        return callback

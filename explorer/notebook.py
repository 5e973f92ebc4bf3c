r"""The explorer in a Jupyter notebook: :class:`NotebookExplorer`, ipywidgets on :class:`ExplorerModel`.

The desktop window (:class:`explorer.qt.window.ExplorerWindow`) is one front end on
:class:`~explorer.app.views.ExplorerModel`; this is another.  The same controls
(:class:`~explorer.app.state.AppState`) and the same views, computed by the engine:

* controls: the light (type, elevation, azimuth, intensity), the model (every registered model,
  BRDF files opened with :meth:`NotebookExplorer.open_brdf` included) with the sliders and buttons
  of its parameter table (:mod:`explorer.app.params`, as the window builds them), ``k_d``, the
  shading mode, the terms of the illumination equation, the scan line;
* views: the lit sphere, the coarse sphere lit per vertex (Gouraud) and per pixel (Phong
  interpolation) with the scan line drawn across both, the scan-line profile, the 3D lobe (a static
  Matplotlib image of :func:`lighting.analysis.lobe_mesh`), the polar slice, the angle curves and
  half/difference image, and the directional albedo.

A change recomputes only the views whose inputs changed (:meth:`ExplorerModel.update` knows which)
and redraws only those; :attr:`NotebookExplorer.timings` records the seconds of every change.
Sliders report on release (``continuous_update=False``): one engine update per move.

Needs ipywidgets and Matplotlib (``pip install lighting-explorer[notebook]``); never imports PyVista
or VTK, and needs no display (the plots are drawn by Matplotlib's Agg canvas into PNG images).

Example
-------
>>> ex = NotebookExplorer(sphere_size=64, mesh_size=64, lobe_resolution=8)  # doctest: +SKIP
>>> ex                       # in a notebook: the controls and the views       # doctest: +SKIP
>>> ex.set(model="phong", shininess=80, elevation=30)   # as moving the widgets  # doctest: +SKIP
"""

from __future__ import annotations

import math
import time

import numpy as np

from lighting.render.image import png_bytes

from .app.captions import albedo_caption
from .app.params import model_label, none_label, offered_parameters, slider_range
from .app.state import CHANNEL_LABELS, ENVIRONMENTS, LIGHT_TYPES, MODELS, TERM_NAMES, VIEWS_3D, AppState
from .app.views import VIEWS, ExplorerModel

__all__ = ["NotebookExplorer", "LobePicture", "png_of", "EXTRA_MESSAGE"]

#: The plots' and images' background (display RGB in [0, 1], as Matplotlib takes it): a dark grey.
BACKGROUND = (0.105, 0.11, 0.125)

#: What to install when ipywidgets or Matplotlib is missing.
EXTRA_MESSAGE = "the notebook explorer needs ipywidgets and Matplotlib: pip install 'lighting-explorer[notebook]'"
#: Colour of the scan line drawn across the coarse spheres (the window's light yellow).
SCANLINE_RGB = (255, 224, 102)
_BG8 = tuple(int(round(255 * c)) for c in BACKGROUND)


def _require():
    try:
        import ipywidgets
        import matplotlib  # noqa: F401
    except ImportError as exc:  # pragma: no cover - the [notebook] extra installs both
        raise ImportError(f"{EXTRA_MESSAGE} ({exc.name} is missing)") from None
    return ipywidgets


def png_of(rgb8) -> bytes:
    """PNG bytes of an 8-bit image ``(H, W, 3)`` or ``(H, W, 4)`` (alpha composited over the window's background).

    Written by the engine's :func:`lighting.render.image.png_bytes` at ``zlib``'s fastest level (a widget
    image is sent once).

    Parameters
    ----------
    rgb8 : numpy.ndarray of uint8
        The pixels, first row at the top; RGBA is straight (not premultiplied) alpha, as Matplotlib's
        Agg buffer.

    Returns
    -------
    bytes
        A PNG file (8-bit RGB).
    """
    a = np.asarray(rgb8)
    if a.shape[-1] == 4:
        alpha = a[..., 3:4]
        if np.all(alpha == 255):
            a = a[..., :3]
        else:
            w = alpha.astype(np.uint16)
            bg = np.array(_BG8, dtype=np.uint16)
            a = ((a[..., :3].astype(np.uint16) * w + bg * (255 - w) + 127) // 255).astype(np.uint8)
    return png_bytes(np.ascontiguousarray(a, dtype=np.uint8), level=1)


def _with_scanline(rgb8: np.ndarray, row: int) -> np.ndarray:
    out = np.array(rgb8, copy=True)
    out[row] = SCANLINE_RGB
    return out


class NotebookExplorer:
    """The explorer as ipywidgets: controls, and the views of an :class:`ExplorerModel` as images.

    Parameters
    ----------
    state : AppState, optional
        The controls to start from (default: the explorer's defaults).
    sphere_size : int
        Pixels of the lit sphere image.
    mesh_size : int
        Pixels of the Gouraud and Phong sphere images.
    lobe_resolution : int
        Rings of the lobe mesh.
    plot_dpi : float
        Resolution of the Matplotlib plots (100: the window's layout at 768 px high).

    Attributes
    ----------
    model : ExplorerModel
        The views' engine (``model.state`` the controls).
    widget : ipywidgets.VBox
        What the notebook shows (displaying the explorer displays it).
    controls : dict
        The control widgets by control name (parameters of the current model by their names).
    images : dict
        The view widgets (``ipywidgets.Image``) by name: ``sphere``, ``gouraud``, ``phong``, ``profile``,
        ``lobe`` (the lobe, or the lit object when ``view3d = "object"``), ``polar``, ``angles``.
    timings : list of (set of str, float)
        For every change: the views recomputed and the seconds from the change to the redrawn images.
    """

    def __init__(self, state=None, *, sphere_size=256, mesh_size=192, lobe_resolution=32, plot_dpi=80.0):
        self._w = _require()
        self.model = ExplorerModel(state if state is not None else AppState(), sphere_size=sphere_size,
                                   mesh_size=mesh_size, lobe_resolution=lobe_resolution,
                                   object_size=(300, 280))  # fmt: skip
        self.plot_dpi = float(plot_dpi)
        self.timings: list = []
        self.controls: dict = {}
        self.images: dict = {}
        self._busy = False
        self._plots = None
        self._face = None  # what the lobe image shows: "lobe" or "object"
        self._build()
        self._redraw(self.model.refresh())

    # ------------------------------------------------------------------ public
    @property
    def state(self) -> AppState:
        """The controls (:attr:`model`'s :class:`AppState`)."""
        return self.model.state

    def set(self, **values) -> set[str]:
        """Change controls and parameters as the widgets would, update the stale views; return their names.

        Parameters
        ----------
        **values
            Control or parameter name → value (validated: a bad value raises ``ValueError`` and
            changes nothing).

        Returns
        -------
        set of str
            The views recomputed.
        """
        t0 = time.perf_counter()
        model_before = self.state.model
        self.state.update(**values)
        if self.state.model != model_before:
            self._build_params()
        self._sync_widgets()
        return self._changed(t0)

    def open_brdf(self, path) -> str:
        """Open a BRDF file (``.brdf``, MERL ``.binary``) as the current model; it joins the model list.

        Parameters
        ----------
        path : str or os.PathLike
            The file.

        Returns
        -------
        str
            Its registered model name.
        """
        t0 = time.perf_counter()
        name = self.model.open_brdf(path)
        self._busy = True
        try:
            self.controls["model"].options = self._model_options()
            self.controls["model"].value = name
        finally:
            self._busy = False
        self._build_params()
        self._changed(t0)
        return name

    def refine(self, seconds: float = 2.0) -> int:
        """Refine the environment's Monte-Carlo reference for ``seconds`` (turning ``reference`` on), then redraw.

        A notebook has no idle timer: this is the window's "keeps sampling while the view rests", on request
        (the **refine** button).  Without an environment there is nothing to refine.

        Parameters
        ----------
        seconds : float
            Seconds of Monte-Carlo passes.

        Returns
        -------
        int
            Samples per pixel reached (0 without an environment).
        """
        if not self.state.reference:
            self.set(reference=True)
        t0 = time.perf_counter()
        views = set()
        while self.model.refining and time.perf_counter() - t0 < seconds:
            views |= self.model.refine(0.05)
        if views:
            self._redraw(views)
        ref = self.model.refinement
        self.status.value = f"<span style='color:#868e96'>{self.model.refine_caption() or 'no environment'}</span>"
        return 0 if ref is None else ref.samples

    def _repr_mimebundle_(self, **kwargs):
        return self.widget._repr_mimebundle_(**kwargs)

    def __repr__(self) -> str:
        s = self.state
        return (f"NotebookExplorer({model_label(s.model)}, light {s.light} at elevation {s.elevation:g}°, "
                f"azimuth {s.azimuth:g}°, {s.mode} shading)")  # fmt: skip

    # ------------------------------------------------------------------ building
    def _model_options(self):
        return [(model_label(m), m) for m in MODELS]

    def _build(self):
        w = self._w
        s = self.state
        lay = w.Layout(width="300px")
        style = {"description_width": "90px"}

        def slider(name, lo, hi, step, desc):
            kind = w.IntSlider if name == "tessellation" else w.FloatSlider
            ctl = kind(value=getattr(s, name), min=lo, max=hi, step=step, description=desc, continuous_update=False,
                       layout=lay, style=style)  # fmt: skip
            ctl.observe(lambda ch, n=name: self._on_control(n, ch["new"]), names="value")
            self.controls[name] = ctl
            return ctl

        light = w.Dropdown(options=list(LIGHT_TYPES), value=s.light, description="light", layout=lay, style=style)
        light.observe(lambda ch: self._on_control("light", ch["new"]), names="value")
        self.controls["light"] = light
        model = w.Dropdown(options=self._model_options(), value=s.model, description="model", layout=lay,
                           style=style)  # fmt: skip
        model.observe(self._on_model, names="value")
        self.controls["model"] = model
        mode = w.ToggleButtons(options=["flat", "gouraud", "phong"], value=s.mode, description="shading",
                               style={"button_width": "70px", "description_width": "60px"})  # fmt: skip
        mode.observe(lambda ch: self._on_control("mode", ch["new"]), names="value")
        self.controls["mode"] = mode
        terms = []
        for t in TERM_NAMES:
            cb = w.Checkbox(value=t in s.terms, description=t, indent=False, layout=w.Layout(width="90px"))
            cb.observe(lambda ch: self._on_terms(), names="value")
            self.controls[f"term_{t}"] = cb
            terms.append(cb)
        light_box = w.VBox([light, slider("elevation", -90, 90, 1, "elevation °"),
                            slider("azimuth", -180, 180, 1, "azimuth °"),
                            slider("intensity", 0, 10, 0.05, "intensity")])  # fmt: skip
        self._param_box = w.VBox([])
        material_box = w.VBox([model, slider("kd", 0, 1, 0.01, "k_d"), self._param_box])
        shading_box = w.VBox([mode, w.HBox(terms), slider("tessellation", 3, 64, 1, "bands"),
                              slider("scanline", 0.02, 0.98, 0.01, "scan line")])  # fmt: skip
        # The "file" environment needs a file: the notebook offers the skies (ExplorerModel.open_environment).
        env = w.Dropdown(options=[e for e in ENVIRONMENTS if e != "file"] if s.environment != "file"
                         else list(ENVIRONMENTS), value=s.environment, description="environment", layout=lay,
                         style=style)  # fmt: skip
        env.observe(lambda ch: self._on_control("environment", ch["new"]), names="value")
        self.controls["environment"] = env
        face = w.ToggleButtons(options=list(VIEWS_3D), value=s.view3d, description="3D panel",
                               style={"button_width": "70px", "description_width": "60px"})  # fmt: skip
        face.observe(lambda ch: self._on_control("view3d", ch["new"]), names="value")
        self.controls["view3d"] = face
        refine = w.Button(description="refine 2 s (reference)", layout=w.Layout(width="200px"))
        refine.on_click(lambda _: self.refine(2.0))
        env_box = w.VBox([env, slider("env_rotation", -180, 180, 1, "rotation °"),
                          slider("env_intensity", 0, 4, 0.05, "intensity"), face, refine])  # fmt: skip
        self._build_params()

        def image(name, width):
            img = w.Image(format="png", layout=w.Layout(width=f"{width}px"))
            self.images[name] = img
            return img

        def titled(text, widget):
            return w.VBox([w.HTML(f"<b>{text}</b>"), widget])

        self.titles = {}

        def captioned(name, widget):
            self.titles[name] = w.HTML()
            return w.VBox([self.titles[name], widget])

        self.status = w.HTML()
        self.albedo = w.HTML()
        ss, ms = self.model.sphere_size, self.model.mesh_size
        top = w.HBox([captioned("sphere", image("sphere", ss)),
                      captioned("gouraud", w.HBox([image("gouraud", ms), image("phong", ms)]))])  # fmt: skip
        middle = w.HBox([captioned("profile", image("profile", 420)), captioned("lobe", image("lobe", 300)),
                         captioned("polar", image("polar", 320))])  # fmt: skip
        bottom = captioned("angles", image("angles", 720))
        controls = w.HBox([titled("Light", light_box), titled("Material", material_box),
                           titled("Shading", shading_box), titled("Environment", env_box)])  # fmt: skip
        self.widget = w.VBox([controls, top, middle, self.albedo, bottom, self.status])

    def _build_params(self):
        """The current model's parameter widgets, from its table (as the window's model controls)."""
        w = self._w
        s = self.state
        rows = []
        for name in [k for k in self.controls if k.startswith("param:")]:
            del self.controls[name]
        lay = w.Layout(width="300px")
        style = {"description_width": "90px"}
        for p in offered_parameters(s.model):
            value = s.param(p.name)
            desc = p.name if not p.unit else f"{p.name} ({p.unit})"
            if p.kind in ("float", "color"):
                lo, hi = slider_range(p)
                shown = value if not isinstance(value, tuple) else float(np.mean(value))
                if p.log:
                    v = min(max(float(shown) if shown is not None else 10**hi, 10**lo), 10**hi)
                    ctl = w.FloatLogSlider(value=v, min=lo, max=hi, base=10, step=(hi - lo) / 200, description=desc,
                                           continuous_update=False, layout=lay, style=style)  # fmt: skip
                else:
                    v = min(max(float(shown) if shown is not None else lo, lo), hi)
                    ctl = w.FloatSlider(value=v, min=lo, max=hi, step=(hi - lo) / 200, description=desc,
                                        continuous_update=False, layout=lay, style=style)  # fmt: skip
                ctl.observe(lambda ch, n=p.name: self._on_param(n, ch["new"]), names="value")
                if p.default is None:  # "None: = α_x": a check box gives the None back
                    none = w.Checkbox(value=value is None, description=f"= {none_label(p)}", indent=False,
                                      layout=w.Layout(width="120px"))  # fmt: skip
                    none.observe(lambda ch, n=p.name, c=ctl: self._on_param(n, None if ch["new"] else c.value),
                                 names="value")  # fmt: skip
                    ctl.disabled = value is None
                    self.controls[f"param:{p.name}:none"] = none
                    rows.append(w.HBox([ctl, none]))
                else:
                    rows.append(ctl)
            elif p.kind == "bool":
                ctl = w.Checkbox(value=bool(value), description=desc, indent=False)
                ctl.observe(lambda ch, n=p.name: self._on_param(n, ch["new"]), names="value")
                rows.append(ctl)
            else:  # choice
                ctl = w.Dropdown(options=list(p.choices), value=value, description=desc, layout=lay, style=style)
                ctl.observe(lambda ch, n=p.name: self._on_param(n, ch["new"]), names="value")
                rows.append(ctl)
            self.controls[f"param:{p.name}"] = ctl
        self._param_box.children = tuple(rows)

    def _sync_widgets(self):
        """Widgets show the state (after :meth:`set`), without firing their handlers."""
        s = self.state
        self._busy = True
        try:
            for name, ctl in self.controls.items():
                if name.startswith("term_"):
                    ctl.value = name[5:] in s.terms
                elif name.startswith("param:"):
                    parts = name.split(":")
                    value = s.param(parts[1])
                    if len(parts) == 3:
                        ctl.value = value is None
                    elif value is not None and not isinstance(value, tuple):
                        ctl.value = value
                elif name in ("light", "model", "mode"):
                    ctl.value = getattr(s, name)
                else:
                    ctl.value = getattr(s, name)
        finally:
            self._busy = False

    # ------------------------------------------------------------------ events
    def _on_control(self, name, value):
        if self._busy:
            return
        t0 = time.perf_counter()
        try:
            self.state.update(**{name: value})
        except ValueError as exc:
            self.status.value = f"<span style='color:#c92a2a'>{exc}</span>"
            return
        self._changed(t0)

    def _on_param(self, name, value):
        if self._busy:
            return
        t0 = time.perf_counter()
        if f"param:{name}:none" in self.controls:  # a row whose None has a check box: the slider is off at None
            self.controls[f"param:{name}"].disabled = value is None
        try:
            self.state.set_param(name, value)
        except ValueError as exc:
            self.status.value = f"<span style='color:#c92a2a'>{exc}</span>"
            return
        self._changed(t0)

    def _on_model(self, change):
        if self._busy:
            return
        t0 = time.perf_counter()
        self.state.update(model=change["new"])
        self._build_params()
        self._changed(t0)

    def _on_terms(self):
        if self._busy:
            return
        t0 = time.perf_counter()
        self.state.update(terms=[t for t in TERM_NAMES if self.controls[f"term_{t}"].value])
        self._changed(t0)

    def _changed(self, t0) -> set[str]:
        views = self.model.update()
        self._redraw(views)
        dt = time.perf_counter() - t0
        self.timings.append((set(views), dt))
        self.status.value = (f"<span style='color:#868e96'>updated {len(views)} of {len(VIEWS)} views "
                             f"({', '.join(sorted(views)) or 'none'}) in {1000 * dt:.0f} ms</span>")  # fmt: skip
        return views

    # ------------------------------------------------------------------ drawing
    def _plotters(self):
        if self._plots is None:
            from .app.plots import AnglePlots, PolarPlot, ProfilePlot

            dpi = self.plot_dpi
            # Captions as HTML above the images: Matplotlib's text is the slow part of a redraw.
            self._plots = {
                "profile": ProfilePlot((420, 280), dpi=dpi, captions=False),
                "polar": PolarPlot((320, 280), dpi=dpi, captions=False),
                "angles": AnglePlots((720, 240), dpi=dpi, captions=False),
                "lobe": LobePicture((300, 280), dpi=dpi),
            }
            for plot in self._plots.values():  # the window's dark panel behind the plots' light lines
                plot.fig.patch.set_facecolor(BACKGROUND)
                plot.fig.patch.set_alpha(1.0)
        return self._plots

    def _caption(self, name, texts):
        self.titles[name].value = "<b>" + " · ".join(t for t in texts if t) + "</b>"

    def _redraw(self, views):
        m, s = self.model.views, self.state
        label = s.quantity_label()
        plots = self._plotters()
        if "sphere" in views:
            sv = m["sphere"]
            self.images["sphere"].value = png_of(sv.rgb8)
            clipped = f", {sv.clipped} pixels clipped" if sv.clipped else ""
            self._caption("sphere", [f"Lit sphere: {sv.mode} shading, {sv.geometry}{clipped}"])
        if views & {"coarse", "profile"}:
            c, row = m["coarse"], m["profile"].row
            self.images["gouraud"].value = png_of(_with_scanline(c.gouraud_rgb8, row))
            self.images["phong"].value = png_of(_with_scanline(c.phong_rgb8, row))
            self._caption("gouraud", [f"{c.n_triangles} triangles, lit per vertex (Gouraud, left) and per pixel "
                                      "(Phong, right); scan line in yellow"])  # fmt: skip
        if "profile" in views:
            plot = plots["profile"]
            plot.set_data(m["profile"], CHANNEL_LABELS[s.channel])
            self.images["profile"].value = png_of(plot.render())
            self._caption("profile", [plot.captions.get("title", "")])
        face = s.view3d
        if face == "object" and ("object" in views or self._face != face):
            ov = m["object"]
            self.images["lobe"].value = png_of(ov.rgb8)
            env = "no environment" if not self.model.environment_active else f"environment {s.environment}"
            self._caption("lobe", [f"Lit object: {ov.triangles} triangles, Phong normals", f"{env}, {ov.method}",
                                   self.model.refine_caption()])  # fmt: skip
        elif face == "lobe" and ("lobe" in views or self._face != face):
            plot = plots["lobe"]
            self.images["lobe"].value = png_of(plot.render(m["lobe"], label))
            self._caption("lobe", [plot.caption])
        self._face = face
        if "polar" in views:
            plot = plots["polar"]
            plot.set_data(m["polar"], channel=s.channel, label=label)
            self.images["polar"].value = png_of(plot.render())
            self._caption("polar", [plot.captions.get(k, "") for k in ("title", "scale", "note")])
        if views & {"theta_v", "theta_h", "theta_d", "halfdiff"}:
            plot = plots["angles"]
            plot.set_data(m["theta_v"], m["theta_h"], m["theta_d"], m["halfdiff"], channel=s.channel, label=label)
            self.images["angles"].value = png_of(plot.render())
            rest = [t for k, t in plot.captions.items() if k != "title"]
            self._caption("angles", [plot.captions.get("title", "")] + rest)
        if "albedo" in views:
            self.albedo.value = f"<b>{model_label(s.model)}</b>: {albedo_caption(m['albedo'])}"


class LobePicture:
    """Static pictures of :class:`~explorer.app.views.LobeView`: the lobe surface, the light and the mirror.

    Drawn with Matplotlib's 3D axes on an Agg canvas (no window, no VTK): the surface coloured by the
    plotted value (``inferno``, 0 … peak), the light direction in yellow, the mirror direction in red,
    an ideal mirror's δ spike in white, the horizon as a grey circle.  The figure is built once and
    only its data change between pictures.

    Parameters
    ----------
    size_px : (int, int)
        Width and height in pixels.
    dpi : float
        Matplotlib's dots per inch.
    """

    def __init__(self, size_px=(300, 280), dpi: float = 80.0):
        import matplotlib
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        from .app.plots import STYLE

        self._style = STYLE
        with matplotlib.rc_context(STYLE):
            self.fig = Figure(figsize=(size_px[0] / dpi, size_px[1] / dpi), dpi=dpi, facecolor=BACKGROUND)
            FigureCanvasAgg(self.fig)
            ax = self.fig.add_axes((0.0, 0.0, 1.0, 1.0), projection="3d")
        ax.set_facecolor(BACKGROUND)
        ring = np.linspace(0.0, 2.0 * math.pi, 73)
        ax.plot(np.cos(ring), np.sin(ring), 0.0 * ring, color="#868e96", lw=0.6)  # the horizon
        ax.set_xlim(-1, 1)
        ax.set_ylim(-1, 1)
        ax.set_zlim(0, 1.4)
        ax.set_box_aspect((2, 2, 1.4), zoom=1.35)
        ax.view_init(elev=18, azim=-70)
        ax.set_axis_off()
        self.ax = ax
        self._artists: list = []
        self.caption = ""

    def render(self, lobe, label: str = "f_r") -> np.ndarray:
        """Draw ``lobe`` and return the RGBA pixels; :attr:`caption` says what it shows.

        Parameters
        ----------
        lobe : LobeView
            The lobe (vertices scaled so the largest radius is 1).
        label : str
            The plotted quantity, for the caption.

        Returns
        -------
        numpy.ndarray of uint8, shape (H, W, 4)
            The figure's pixels (a copy).
        """
        import matplotlib
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        for artist in self._artists:
            artist.remove()
        self._artists = []
        ax = self.ax
        v, f = lobe.vertices, lobe.faces
        if len(f):
            top = lobe.peak if lobe.peak > 0 else 1.0
            face_values = lobe.values[f].mean(axis=1) / top
            colours = matplotlib.colormaps["inferno"](0.15 + 0.85 * np.clip(face_values, 0.0, 1.0))
            poly = Poly3DCollection(v[f], facecolors=colours, edgecolors="none", linewidths=0.0)
            ax.add_collection3d(poly)
            self._artists.append(poly)
        for d, colour in ((lobe.light, "#ffe066"), (lobe.mirror, "#ff6b6b")):
            self._artists += ax.plot([0.0, 1.1 * d[0]], [0.0, 1.1 * d[1]], [0.0, 1.1 * d[2]], color=colour, lw=1.6)
        if lobe.spike > 0 and lobe.spike_direction is not None:
            d = lobe.spike_direction * lobe.spike * lobe.scale
            self._artists += ax.plot([0.0, d[0]], [0.0, d[1]], [0.0, d[2]], color="white", lw=2.0)
        kind = "retro-reflection f(d, d)" if lobe.lock else "3D lobe"
        note = " · light below the horizon" if lobe.below_horizon and not lobe.lock else ""
        self.caption = f"{kind}: {label}, peak {lobe.peak:.3g}; light yellow, mirror red{note}"
        with matplotlib.rc_context(self._style):
            self.fig.canvas.draw()
        return np.asarray(self.fig.canvas.buffer_rgba()).copy()

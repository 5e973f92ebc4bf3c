"""The window's panels: image planes, meshes, charts and captions (a mixin of the explorer window).

Per-pixel images (lit sphere, Phong panel) are the engine's images encoded to 8-bit sRGB and drawn
as textures on planes facing an orthographic camera; the Gouraud panel is the coarse mesh with the
engine's vertex colours; the plots are Matplotlib figures embedded with ``pyvista.ChartMPL``.
"""

from __future__ import annotations

import numpy as np

from .layout import (
    ACCENT,
    ANGLES,
    COARSE_SCALE,
    GOURAUD,
    HALF,
    LOBE,
    LOBE_SCALE,
    MUTED,
    PHONG,
    POLAR,
    PROFILE,
    SCANLINE,
    SPHERE,
    SPHERE_SCALE,
    TEXT,
)

__all__ = ["PanelsMixin"]


class PanelsMixin:
    """Builders of the panels and the small helpers they share (captions, cameras, textures)."""

    def _renderer(self, panel):
        self.plotter.subplot(*panel)
        return self.plotter.renderer

    def _text(self, panel, key, text, x, y, *, size=11, color=TEXT, align="left", valign="top", bold=False):
        import vtk

        ren = self._renderer(panel)
        actor = vtk.vtkTextActor()
        actor.SetInput(text)
        prop = actor.GetTextProperty()
        prop.SetFontSize(self._font_px(size))
        prop.SetColor(*color)
        prop.SetBold(bold)
        if self.font:
            prop.SetFontFamily(vtk.VTK_FONT_FILE)
            prop.SetFontFile(self.font)
        prop.SetJustification({"left": 0, "center": 1, "right": 2}[align])
        prop.SetVerticalJustification({"bottom": 0, "center": 1, "top": 2}[valign])
        coord = actor.GetPositionCoordinate()
        coord.SetCoordinateSystemToNormalizedViewport()
        coord.SetValue(x, y)
        ren.AddViewProp(actor)
        self.captions[key] = actor
        return actor

    def _font_px(self, size) -> int:
        return max(7, round(size * self.ui_scale))

    def _set_text(self, key, text):
        actor = self.captions[key]
        if actor.GetInput() != text:
            actor.SetInput(text)

    def _ortho_camera(self, scale, centre=(0.0, 0.0)):
        cam = self.plotter.camera
        cam.SetParallelProjection(True)
        cam.SetPosition(centre[0], centre[1], 10.0)
        cam.SetFocalPoint(centre[0], centre[1], 0.0)
        cam.SetViewUp(0.0, 1.0, 0.0)
        cam.SetParallelScale(scale)
        cam.SetClippingRange(1.0, 30.0)

    def _image_plane(self, size, z=0.0):
        """A textured square ``[−HALF, HALF]²`` at depth ``z`` showing an RGBA image of ``size`` pixels."""
        pv = self.pv
        blank = np.zeros((size, size, 4), dtype=np.uint8)
        texture = pv.Texture(blank)
        texture.interpolate = True
        plane = pv.Plane(center=(0.0, 0.0, z), direction=(0.0, 0.0, 1.0), i_size=2 * HALF, j_size=2 * HALF)
        actor = self.plotter.add_mesh(plane, texture=texture, lighting=False, show_scalar_bar=False)
        # Drawn with the opaque geometry: an RGBA texture would make VTK composite the panel in a
        # translucent pass (several extra full-panel buffers, slow with software OpenGL).  The
        # transparent texels still blend with what was drawn before (see _build_sphere_panel).
        actor.ForceOpaqueOn()
        image = texture.to_image()
        pixels = image.point_data.active_scalars
        return {"texture": texture, "image": image, "pixels": pixels, "actor": actor, "size": size}

    @staticmethod
    def _upload(plane, rgb8, coverage):
        """Put an engine image (rows top-down) into a plane's texture; uncovered pixels are transparent."""
        h, w = coverage.shape
        rgba = np.asarray(plane["pixels"]).reshape(h, w, 4)[::-1]  # VTK images start at the bottom row
        rgba[..., :3] = rgb8
        if plane.get("alpha_of") is not coverage:  # a renderer's coverage stays the same array
            np.multiply(coverage, np.uint8(255), out=rgba[..., 3], casting="unsafe")
            plane["alpha_of"] = coverage
        plane["image"].Modified()
        plane["texture"].Modified()

    # ------------------------------------------------------------------ panels
    def _build_sphere_panel(self):
        pv = self.pv
        self._renderer(SPHERE)
        # The arrow first: the image plane (drawn in the same opaque pass, in order) then hides the
        # part of the arrow behind the sphere, while its transparent corners let the rest show.
        arrow = pv.Arrow(start=(0, 0, 0), direction=(1, 0, 0), tip_length=0.35, tip_radius=0.16, shaft_radius=0.06)
        self.light_arrow = self.plotter.add_mesh(arrow, color=ACCENT, lighting=False)
        bulb = pv.Sphere(radius=0.07, theta_resolution=24, phi_resolution=12)
        self.light_bulb = self.plotter.add_mesh(bulb, color=ACCENT, lighting=False)
        self.sphere_plane = self._image_plane(self.model.sphere_size)
        self._ortho_camera(SPHERE_SCALE)
        # The split sphere's dividing line (left: the current model, right: a comparison entry).
        self.split_line = self.plotter.add_mesh(pv.Line((0.0, -1.12, 0.5), (0.0, 1.12, 0.5)), color=MUTED,
                                                line_width=2.0, lighting=False)  # fmt: skip
        self.split_line.SetVisibility(False)
        self._text(SPHERE, "sphere_title", "", 0.025, 0.98, size=11.5, bold=True)
        self._text(SPHERE, "sphere_legend", "", 0.025, 0.91, size=9.5, color=MUTED)
        self._text(SPHERE, "sphere_info", "", 0.025, 0.02, size=9.5, color=MUTED, valign="bottom")

    def _build_coarse_panels(self):
        pv = self.pv
        c = self._coarse_poly(self.state.tessellation)
        self._renderer(GOURAUD)
        self.gouraud_poly = c
        self.gouraud_actor = self.plotter.add_mesh(
            c, scalars="rgb", rgb=True, lighting=False, show_scalar_bar=False, smooth_shading=False
        )
        # The edges sit a hair outside the surface so the depth test never hides them.
        self.edges_poly = self._edges_poly(c)
        self.gouraud_edges = self._add_edges()
        self.scan_g = pv.Line((-1.12, 0.0, 1.5), (1.12, 0.0, 1.5))
        self.plotter.add_mesh(self.scan_g, color=SCANLINE, line_width=2.0, lighting=False)
        self._ortho_camera(COARSE_SCALE)
        self._text(GOURAUD, "gouraud_title", "", 0.025, 0.98, size=11.5, bold=True)
        self._text(GOURAUD, "gouraud_info", "", 0.025, 0.02, size=9.5, color=MUTED, valign="bottom")

        self._renderer(PHONG)
        self.phong_plane = self._image_plane(self.model.mesh_size, z=-0.01)
        self.phong_edges = self._add_edges()
        self.scan_p = pv.Line((-1.12, 0.0, 1.5), (1.12, 0.0, 1.5))
        self.plotter.add_mesh(self.scan_p, color=SCANLINE, line_width=2.0, lighting=False)
        self._ortho_camera(COARSE_SCALE)
        self._text(PHONG, "phong_title", "Phong interpolation: lit per pixel", 0.025, 0.98, size=11.5, bold=True)
        self._text(PHONG, "phong_info", "normals interpolated, engine lights each pixel\nred line: the scan line",
                   0.025, 0.02, size=9.5, color=MUTED, valign="bottom")  # fmt: skip

    def _add_edges(self):
        # 35 % black over the surface.  Drawn in the opaque pass after the surface (blending still
        # on): the same colours as a translucent actor, without VTK's costly translucent pass; the
        # depth test hides the edges of the far side.
        actor = self.plotter.add_mesh(
            self.edges_poly, style="wireframe", color=(0.0, 0.0, 0.0), opacity=0.35, lighting=False, line_width=1.0,
            show_scalar_bar=False, scalars=None,
        )  # fmt: skip
        actor.ForceOpaqueOn()
        return actor

    def _edges_poly(self, poly):
        edges = self.pv.PolyData(np.asarray(poly.points) * 1.004, poly.faces)
        return edges

    def _coarse_poly(self, tessellation):
        pv = self.pv
        mesh = self.model.mesh(tessellation)
        faces = np.hstack([np.full((mesh.n_triangles, 1), 3), mesh.faces]).ravel()
        poly = pv.PolyData(np.asarray(mesh.vertices, dtype=np.float64), faces)
        poly.point_data["rgb"] = np.zeros((mesh.n_vertices, 3), dtype=np.uint8)
        poly.point_data.active_scalars_name = "rgb"
        return poly

    def _build_lobe_panel(self):
        pv = self.pv
        self._renderer(LOBE)
        disc = pv.Disc(center=(0.0, 0.0, -0.004), inner=0.0, outer=1.3, normal=(0.0, 0.0, 1.0), c_res=72)
        self.plotter.add_mesh(disc, color=(0.3, 0.31, 0.35), lighting=False)
        self.plotter.add_mesh(pv.Line((0, 0, 0), (0, 0, 1.25)), color=MUTED, line_width=2.0, lighting=False)
        base = pv.Arrow(start=(0, 0, 0), direction=(1, 0, 0), tip_length=0.16, tip_radius=0.045, shaft_radius=0.012)
        self.lobe_light = self.plotter.add_mesh(base.copy(), color=ACCENT, lighting=False)  # l: yellow everywhere
        self.lobe_mirror = self.plotter.add_mesh(base.copy(), color=(1.0, 0.42, 0.42), lighting=False)
        spike = pv.Arrow(start=(0, 0, 0), direction=(1, 0, 0), tip_length=0.12, tip_radius=0.05, shaft_radius=0.022)
        self.lobe_spike = self.plotter.add_mesh(spike, color=(1.0, 0.42, 0.42), lighting=False)  # a mirror's δ
        self.lobe_spike.SetVisibility(False)
        # The tangent t (+x), the azimuth origin of φ_l and of anisotropic lobes, drawn on the disc.
        self.plotter.add_mesh(pv.Line((0, 0, 0), (1.28, 0, 0)), color=MUTED, line_width=1.5, lighting=False)
        self.lobe_poly = pv.PolyData(np.zeros((3, 3)), np.array([3, 0, 1, 2]))
        self.lobe_poly.point_data["value"] = np.zeros(3)
        # Coloured by the plotted value through a perceptual colour map (what the value is: the caption).
        self.lobe_actor = self.plotter.add_mesh(
            self.lobe_poly, scalars="value", cmap="viridis", lighting=False, clim=(0.0, 1.0),
            scalar_bar_args={
                "title": " ", "vertical": True, "position_x": 0.82, "position_y": 0.14, "width": 0.04,
                "height": 0.6, "n_labels": 3, "fmt": "%.3g", "color": TEXT, "title_font_size": 11,
                "label_font_size": 10,
            },
        )  # fmt: skip
        cam = self.plotter.camera
        cam.SetParallelProjection(True)
        cam.SetPosition(0.0, -6.0, 2.4)
        cam.SetFocalPoint(0.0, 0.0, 0.62)
        cam.SetViewUp(0.0, 0.0, 1.0)
        cam.SetParallelScale(LOBE_SCALE)
        cam.SetClippingRange(0.5, 30.0)
        self._lobe_camera = (cam.GetPosition(), cam.GetFocalPoint(), cam.GetViewUp(), cam.GetParallelScale())
        self._text(LOBE, "lobe_title", "", 0.025, 0.98, size=11.5, bold=True)
        self._text(LOBE, "lobe_info", "", 0.025, 0.905, size=9.5, color=MUTED)

    def _build_charts(self):
        from .plots import AlbedoPlot, AnglePlots, PolarPlot, ProfilePlot

        pv = self.pv
        w, h = self.window_size
        dpi = 100 * self.ui_scale  # the same layout at every window size
        self.profile_plot = ProfilePlot(self._panel_px(PROFILE, 0.92), dpi=dpi, captions=False)
        self.polar_plot = PolarPlot(self._panel_px(POLAR, 0.92), dpi=dpi, captions=False)
        self.angle_plots = AnglePlots(self._panel_px(ANGLES, 0.92, cols=2), dpi=dpi, captions=False)
        # The albedo curves take the angle plots' place when the ``panel`` control says "albedo".
        self.albedo_plot = AlbedoPlot(self._panel_px(ANGLES, 0.92, cols=2), dpi=dpi, captions=False)
        self._panel_shown = None
        self.charts = {}
        for panel, plot, key in (
            (PROFILE, self.profile_plot, "profile"),
            (POLAR, self.polar_plot, "polar"),
            (ANGLES, self.angle_plots, "angles"),
        ):
            self._renderer(panel)
            chart = pv.ChartMPL(plot.fig, size=(1.0, 0.92), loc=(0.0, 0.0), redraw_on_render=False)
            chart.background_color = (0.0, 0.0, 0.0, 0.0)
            self.plotter.add_chart(chart)
            plot.on_image = self._chart_pusher(chart)
            self.charts[key] = chart
            if key == "angles":
                self.albedo_plot.on_image = plot.on_image  # one chart, fed by whichever figure is shown
            self._text(panel, f"{key}_title", "", 0.025 if panel != ANGLES else 0.012, 0.98, size=11.5, bold=True)
        self._text(PROFILE, "profile_metric", "", 0.025, 0.905, size=9.5, color=MUTED)
        self._text(POLAR, "polar_quantity", "", 0.025, 0.905, size=9.5, color=MUTED)
        self._text(POLAR, "polar_note", "", 0.5, 0.45, size=11, color=SCANLINE, align="center", valign="center")
        self._text(POLAR, "polar_albedo", "", 0.025, 0.845, size=9.5, color=MUTED)
        self._text(ANGLES, "angles_peak", "", 0.988, 0.015, size=9, color=MUTED, align="right", valign="bottom")

    def _panel_px(self, panel, height_frac=1.0, cols=1):
        w, h = self.window_size
        cw = sum(self._col_frac[panel[1] : panel[1] + cols]) * w
        return (max(int(cw), 50), max(int(self._row_frac[panel[0]] * h * height_frac), 50))

    def _chart_pusher(self, chart):
        """A callback putting a figure's RGBA buffer into ``chart`` (one VTK image, updated in place)."""
        pv = self.pv
        holder = {}

        def push(rgba):
            h, w = rgba.shape[:2]
            image = holder.get("image")
            if image is None or holder["shape"] != (h, w):
                image = pv.ImageData(dimensions=(w, h, 1))
                image.point_data["rgba"] = np.zeros((w * h, 4), dtype=np.uint8)
                image.point_data.active_scalars_name = "rgba"
                holder.update(image=image, shape=(h, w), pixels=image.point_data["rgba"])
                chart.SetImage(image)
            holder["pixels"][:] = rgba[::-1].reshape(-1, 4)
            image.Modified()
            # ChartMPL puts a copy of the figure into the chart at each full Matplotlib draw (its
            # draw_event callback): without this the chart would keep that copy and miss every blit.
            chart.SetImage(image)
            chart.Modified()

        return push

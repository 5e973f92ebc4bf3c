"""Showing the model's views in the panels (a mixin of the explorer window), and the albedo caption."""

from __future__ import annotations

import math

import numpy as np

from .captions import albedo_caption  # kept importable from here while the old window lives
from .layout import ACCENT, MUTED, SCANLINE, _arrow_matrix
from .state import CHANNEL_LABELS, MODEL_LABELS

__all__ = ["albedo_caption", "DrawingMixin"]


def _rgb(colour) -> tuple:
    from matplotlib.colors import to_rgb

    return tuple(float(c) for c in to_rgb(colour)) if colour else MUTED


class DrawingMixin:
    """Puts the views of :class:`~explorer.app.views.ExplorerModel` into the panels' actors and captions."""

    def _display(self, views):
        s = self.state
        m = self.model.views
        label = s.quantity_label()
        if "sphere" in views:
            sv = m["sphere"]
            self._upload(self.sphere_plane, sv.rgb8, sv.coverage)
            where = "per pixel, exact sphere" if sv.mode == "phong" else f"{sv.mode}, {sv.geometry}"
            self._set_text("sphere_title", f"Lit sphere (engine): {MODEL_LABELS[s.model]}")
            share = 100 * sv.clipped / max(int(sv.coverage.sum()), 1)
            share = f"{share:.0f}%" if share >= 0.5 else "under 1%"
            clipped = f"{share} of the sphere above 1: clipped (lower the exposure)\n" if sv.clipped else ""
            self._set_text("sphere_legend", f"{where} · arrow: the light")
            if sv.split:
                self._set_text("sphere_legend", f"split: left current · right ▸ {sv.split}\n"
                                                f"{where} · arrow: the light")  # fmt: skip
                self.split_line.prop.color = _rgb(sv.split_colour)
            self.split_line.SetVisibility(bool(sv.split))
            self._set_text("sphere_info", clipped + self._delta_note() + self._light_summary())
        if views & {"sphere", "lobe"} or not self._glyphs_placed:
            self._update_light_glyphs()
        if "coarse" in views:
            cv = m["coarse"]
            if cv.vertices.shape[0] != self.gouraud_poly.n_points or len(cv.faces) != self.gouraud_poly.n_cells:
                self._replace_coarse_mesh(s.tessellation)
            self.gouraud_poly.point_data["rgb"][:] = cv.vertex_rgb8
            self.gouraud_poly.Modified()
            self._upload(self.phong_plane, cv.phong_rgb8, cv.coverage)
            self._set_text("gouraud_title", "Gouraud: lit at the vertices")
            self._set_text(
                "gouraud_info",
                f"{cv.n_triangles} triangles, {len(cv.vertices)} vertices: engine colours\n"
                "interpolated across each triangle (VTK lighting off)",
            )
        if "profile" in views:
            pv_ = m["profile"]
            for line in (self.scan_g, self.scan_p):
                pts = line.points
                pts[:, 1] = pv_.y
                line.points = pts
            self.profile_plot.set_data(pv_, CHANNEL_LABELS[s.channel])
            self.profile_plot.render()
            self._set_text("profile_title", f"Scan line: intensity ({CHANNEL_LABELS[s.channel]})")
            self._set_text(
                "profile_metric",
                f"Mach-band metric (slope kinks): Gouraud {pv_.metric_gouraud:.2f}, Phong {pv_.metric_phong:.2f}",
            )
        if "lobe" in views:
            self._update_lobe(m["lobe"], label)
        if "polar" in views:
            self.polar_plot.set_data(m["polar"], channel=s.channel, label=label)
            self.polar_plot.render()
            pv_ = m["polar"]
            theta_in = math.degrees(pv_.theta_in)
            plane = f"θ_l = {theta_in:.0f}°, φ_l = {pv_.phi_deg:.0f}°"
            title = (
                f"Retro-reflection f(d, d) (view lock), φ = {pv_.phi_deg:.0f}°" if pv_.lock else f"Polar slice, {plane}"
            )
            self._set_text("polar_title", title)
            self._set_text("polar_note", "light below the horizon:\nnothing reflected" if m["polar"].below_horizon
                           else "")  # fmt: skip
            scale = self.polar_plot.captions.get("scale", "")
            quantity = f"{label} · {scale}" if scale else label
            if pv_.overlays:
                quantity += " · colours: Compare list"
            self._set_text("polar_quantity", quantity)
        if "albedo" in views:
            self._show_albedo(m["albedo"])
        switched = self._panel_shown != s.panel
        self._panel_shown = s.panel
        if s.panel == "albedo":
            if "albedo" in views or switched:
                self._show_albedo_curves(m["albedo"], switched)
        elif views & {"theta_v", "theta_h", "theta_d", "halfdiff"} or switched:
            self.angle_plots.set_data(
                m["theta_v"], m["theta_h"], m["theta_d"], m["halfdiff"], channel=s.channel, label=label
            )
            if switched:
                self.angle_plots.invalidate()
            self.angle_plots.render()
            white = " (white; colours: Compare list)" if m["theta_v"].overlays else ""
            self._set_text("angles_title", f"{MODEL_LABELS[s.model]}{white}: {label} against θ_v, θ_h, θ_d "
                                           "(Rusinkiewicz)")  # fmt: skip
            self._set_text("angles_peak", self.angle_plots.captions.get("peak", ""))
            self.captions["angles_peak"].GetTextProperty().SetColor(*MUTED)

    def _show_albedo_curves(self, av, switched=False):
        """The albedo panel: ρ(θ_v) of the current model and each shown entry, errors and flags."""
        self.albedo_plot.set_data(av.curves, channel=self.state.channel)
        if switched:
            self.albedo_plot.invalidate()
        self.albedo_plot.render()
        self._set_text("angles_title", f"{self.albedo_plot.captions.get('title', '')}  "
                                       f"[{CHANNEL_LABELS[self.state.channel]}]")  # fmt: skip
        flagged = any(bool(c.unconverged.any()) for c in av.curves)
        self._set_text("angles_peak", self.albedo_plot.captions.get("flags", ""))
        self.captions["angles_peak"].GetTextProperty().SetColor(*(SCANLINE if flagged else MUTED))

    def _show_albedo(self, av):
        """The albedo readout: ``ρ(θ_v) = value ± error``, flagged "unconverged" above 2 % relative error."""
        self._set_text("polar_albedo", albedo_caption(av))
        self.captions["polar_albedo"].GetTextProperty().SetColor(*(SCANLINE if av.unconverged else MUTED))

    def _delta_note(self) -> str:
        """What an ideal mirror (a Dirac delta, ``is_delta``) shows under the explorer's lights, said on screen."""
        if not any(getattr(p, "is_delta", False) for p in self.state.brdf().parts):
            return ""
        return ("ideal mirror (δ): a point or directional light shows only\n"
                "where R = v exactly (one point): black but for ambient and k_d\n")  # fmt: skip

    def _light_summary(self) -> str:
        s = self.state
        if s.light == "ambient":
            light = "ambient light only"
        else:
            light = f"{s.light}, elevation {s.elevation:.0f}°, azimuth {s.azimuth:.0f}°"
            if s.light in ("point", "spot"):
                light += f", distance {s.distance:.1f}"
        terms = " + ".join(s.terms) or "no terms"
        form = "classic I" if s.form == "classic" else "physical I/π"
        return f"{light}\n{form} · {terms}"

    def _update_light_glyphs(self):
        self._glyphs_placed = True
        s = self.state
        d = s.light_direction()
        # The light is yellow in every panel; a coloured light shows its colour (lightened to stay visible).
        colour = np.asarray(s.light_color, float)
        if np.allclose(colour, colour[0]):
            colour = np.asarray(ACCENT)
        else:
            colour = 0.35 + 0.65 * colour / colour.max()
        visible = s.light != "ambient"
        self.light_arrow.user_matrix = _arrow_matrix(1.34 * d, 1.03 * d)
        self.light_arrow.prop.color = tuple(colour)
        self.light_arrow.SetVisibility(visible)
        self.light_bulb.user_matrix = _arrow_matrix(1.34 * d, 2.34 * d)
        self.light_bulb.prop.color = tuple(colour)
        self.light_bulb.SetVisibility(visible and s.light in ("point", "spot"))
        lv = self.model.views.get("lobe")
        if lv is not None:
            self.lobe_light.user_matrix = _arrow_matrix(1.3 * lv.light, 0.03 * lv.light)
            self.lobe_mirror.user_matrix = _arrow_matrix(0.03 * lv.mirror, 1.3 * lv.mirror)
            # An ideal mirror's delta: a spike along the mirror direction, its height R in the lobe's scale.
            if lv.spike > 0:
                d = lv.spike_direction
                self.lobe_spike.user_matrix = _arrow_matrix(0.0 * d, max(lv.spike * lv.scale, 0.05) * d)
            self.lobe_spike.SetVisibility(lv.spike > 0)

    def _replace_coarse_mesh(self, tessellation):
        new = self._coarse_poly(tessellation)
        self.gouraud_poly.copy_from(new)
        self.gouraud_poly.point_data.active_scalars_name = "rgb"
        self.edges_poly.copy_from(self._edges_poly(new))

    def _update_lobe(self, lv, label):
        poly = self.lobe_poly
        n = len(lv.vertices)
        if poly.n_points != n or poly.n_cells != len(lv.faces):
            faces = np.hstack([np.full((len(lv.faces), 1), 3), lv.faces]).ravel()
            new = self.pv.PolyData(lv.vertices.copy(), faces)
            new.point_data["value"] = lv.values.copy()
            poly.copy_from(new)
            poly.point_data.active_scalars_name = "value"
        else:
            poly.points[:] = lv.vertices
            poly.point_data["value"][:] = lv.values
            poly.Modified()
        top = lv.peak if lv.peak > 0 else 1.0
        self.lobe_actor.mapper.scalar_range = (0.0, top)
        theta = math.degrees(math.atan2(math.hypot(lv.light[0], lv.light[1]), lv.light[2]))
        kind = "retro-reflection lobe f(d, d), view lock" if lv.lock else "3D lobe"
        self._set_text("lobe_title", f"{kind}: {label}")
        extra = " · light below the horizon" if lv.below_horizon and not lv.lock else ""
        delta = f"\nδ spike: ideal mirror, R = {lv.spike:.3g}" if lv.spike > 0 else ""
        self._set_text(
            "lobe_info",
            f"light l at θ_l = {theta:.0f}°, φ_l = {self.state.phi:.0f}° (yellow), mirror (red); t = +x\n"
            f"peak {lv.peak:.3g}, radius scaled to fit{extra}{delta}",
        )

"""The 3D panel's second face, the lit object, and the reference refined on the idle timer (a window mixin).

The 3D panel (:data:`~explorer.app.layout.LOBE`) shows the BRDF lobe or, with ``view3d = "object"``,
the engine's image of a mesh under the environment, drawn as a texture on a plane far from the lobe's
scene: switching turns the camera to it and hides the lobe's colour bar and captions.  With
``reference`` on, :meth:`ObjectPanelMixin.refine_tick` adds Monte-Carlo passes for
:data:`REFINE_BUDGET` seconds and shows the result; the window calls it from a one-shot timer every
:data:`REFINE_MS` while there is something to refine, so events are handled between ticks.
"""

from __future__ import annotations

import numpy as np

from .layout import LOBE, TEXT

__all__ = ["REFINE_MS", "REFINE_BUDGET", "OBJECT_FILL", "ObjectPanelMixin"]

#: Milliseconds between refinement ticks (events are handled in between).
REFINE_MS = 10
#: Seconds of Monte-Carlo work per tick.
REFINE_BUDGET = 0.04
#: Share of the 3D panel's height the object's image fills (from the bottom; the title sits above it).
OBJECT_FILL = 0.87
#: Where the object's image plane sits in the 3D panel's scene: far from the lobe, out of its camera's view.
_PLANE_CENTRE = (100.0, 0.0, 0.0)


class ObjectPanelMixin:
    """The lit object in the 3D panel and the progressive reference's ticks."""

    def _build_object_panel(self):
        pv = self.pv
        ren = self._renderer(LOBE)
        # What the lobe face shows on top of its scene besides its captions: the colour bar.
        import vtk

        props = ren.GetViewProps()
        props.InitTraversal()
        items = [props.GetNextProp() for _ in range(props.GetNumberOfItems())]
        self._lobe_2d = [p for p in items if isinstance(p, vtk.vtkScalarBarActor)]
        w, h = self.model.object_size
        blank = np.zeros((h, w, 4), dtype=np.uint8)
        texture = pv.Texture(blank)
        texture.interpolate = True
        aspect = w / h
        plane = pv.Plane(center=_PLANE_CENTRE, direction=(0.0, 0.0, 1.0), i_size=2.0 * aspect, j_size=2.0)
        actor = self.plotter.add_mesh(plane, texture=texture, lighting=False, show_scalar_bar=False)
        actor.ForceOpaqueOn()
        image = texture.to_image()
        self.object_plane = {"texture": texture, "image": image, "pixels": image.point_data.active_scalars,
                             "actor": actor, "size": w}  # fmt: skip
        self._text(LOBE, "object_title", "", 0.025, 0.98, size=11.5, bold=True)
        # Over the image: light text with a dark shadow reads on a bright sky too.
        self._text(LOBE, "object_info", "", 0.025, 0.02, size=9.5, color=TEXT, valign="bottom")
        self._text(LOBE, "object_refine", "", 0.025, 0.09, size=9.5, color=TEXT, valign="bottom")
        for key in ("object_info", "object_refine"):
            self.captions[key].GetTextProperty().SetShadow(True)
        self._object_shown = False
        self._saved_lobe_camera = None
        self._refine_timer = None

    def _show_3d_face(self):
        """Turn the 3D panel to the lobe or to the object, as ``view3d`` says."""
        want = self.state.view3d == "object"
        if want == self._object_shown:
            return
        self._object_shown = want
        self._renderer(LOBE)
        cam = self.plotter.camera
        for key in ("lobe_title", "lobe_info"):
            self.captions[key].SetVisibility(not want)
        for key in ("object_title", "object_info", "object_refine"):
            self.captions[key].SetVisibility(want)
        for actor in self._lobe_2d:
            actor.SetVisibility(not want)
        if want:
            self._saved_lobe_camera = (cam.GetPosition(), cam.GetFocalPoint(), cam.GetViewUp(),
                                       cam.GetParallelScale())  # fmt: skip
            x, y, z = _PLANE_CENTRE
            half = 1.0 / OBJECT_FILL  # the plane (height 2) at the bottom of the panel
            y += half - 1.0
            cam.SetParallelProjection(True)
            cam.SetPosition(x, y, z + 10.0)
            cam.SetFocalPoint(x, y, z)
            cam.SetViewUp(0.0, 1.0, 0.0)
            cam.SetParallelScale(half)
            cam.SetClippingRange(1.0, 30.0)
        else:
            pos, focal, up, scale = self._saved_lobe_camera or self._lobe_camera
            cam.SetPosition(*pos)
            cam.SetFocalPoint(*focal)
            cam.SetViewUp(*up)
            cam.SetParallelScale(scale)
            cam.SetClippingRange(0.5, 30.0)

    def _display_object(self, views):
        """Show the object view and the reference's caption (after an update or a refinement tick)."""
        self._show_3d_face()
        ov = self.model.views.get("object")
        if ov is None or "object" not in views or self.state.view3d != "object":
            self._set_text("object_refine", self.model.refine_caption() if self.state.view3d == "object" else "")
            return
        self._upload(self.object_plane, ov.rgb8, np.ones(ov.coverage.shape, dtype=bool))
        s = self.state
        names = {"none": "no environment (key + ambient light)", "file": "environment file"}
        if not self.model.environment_active:
            names["file"] = "no environment file given (--environment FILE)"
        env = names.get(s.environment, f"sky '{s.environment}'")
        self._set_text("object_title", f"Lit object (engine): {ov.triangles} triangles, Phong normals")
        self._set_text("object_info", f"{env} · {ov.method}")
        self._set_text("object_refine", self.model.refine_caption())

    # ------------------------------------------------------------------ the reference's ticks
    def refine_tick(self, *, render=True, budget=REFINE_BUDGET) -> set[str]:
        """One tick of the progressive reference: passes for ``budget`` seconds, then the images shown.

        Parameters
        ----------
        render : bool
            Render the window afterwards.
        budget : float
            Seconds of Monte-Carlo work.

        Returns
        -------
        set of str
            The views refined (empty when there is nothing to refine).
        """
        views = self.model.refine(budget)
        if not views:
            return views
        self._display(views)
        self._display_object(views)
        if render:
            self._render(all_panels=False)
        return views

    def _start_refine_timer(self):
        """Ask for the next tick :data:`REFINE_MS` from now while the reference has passes left (a window only)."""
        iren = self._interactor()
        if iren is None or not self._shown or not self.model.refining or self._refine_timer is not None:
            return
        self._refine_timer = iren.CreateOneShotTimer(REFINE_MS)

    def _on_refine_timer(self):
        self._refine_timer = None
        if self.model.pending:  # a drag is in progress: its views first
            return
        self.refine_tick(render=True)
        self._start_refine_timer()

"""The Matplotlib panels (scan-line profile, polar slice, angle curves, albedo curves) on Qt canvases.

The figures are the explorer's own (:mod:`explorer.app.plots`: each draws only what the model computed
and redraws its data by blitting over a saved background); here each sits on a ``FigureCanvasQTAgg``
that follows the panel's size.  After new data the figure updates its Agg buffer (a blit, or a full draw
when the axes changed) and the canvas repaints itself alone: no other panel is redrawn.
"""

from __future__ import annotations

import matplotlib
from matplotlib.backends.backend_qtagg import FigureCanvasQTAgg
from PySide6 import QtCore, QtWidgets

from ..app.plots import STYLE, BlitFigure

__all__ = ["PlotCanvas"]

#: Pixels per inch of the figures: their fonts are in points, so text keeps its size on screen.
PLOT_DPI = 96


class PlotCanvas(FigureCanvasQTAgg):
    """A Qt canvas showing one :class:`~explorer.app.plots.BlitFigure`, resized with its panel.

    Parameters
    ----------
    plot_type : type
        A :class:`~explorer.app.plots.BlitFigure` subclass (``ProfilePlot``, ``PolarPlot``, ...).
    captions : bool
        Whether the figure draws its own changing captions (the window shows them as labels when False).
    """

    def __init__(self, plot_type: type[BlitFigure], *, captions: bool = False, parent=None):
        self.plot = plot_type((400, 300), dpi=PLOT_DPI, captions=captions)
        self.plot.fig.patch.set_alpha(1.0)
        self.plot.fig.patch.set_facecolor("#1e2024")
        super().__init__(self.plot.fig)
        self.setParent(parent)
        #: Paint events handled so far (the bench waits for the next one).
        self.paints = 0
        self.setMinimumSize(96, 72)
        self.setSizePolicy(QtWidgets.QSizePolicy.Policy.Expanding, QtWidgets.QSizePolicy.Policy.Expanding)

    def sizeHint(self):  # noqa: N802 - Qt's name
        # Small and equal for every view, so that the splitters share the space by their stretch factors.
        return QtCore.QSize(200, 160)

    def show_data(self, *args, invalidate: bool = False, **kwargs) -> None:
        """``plot.set_data(*args, **kwargs)``, then the figure's buffer is updated and this canvas repainted."""
        self.plot.set_data(*args, **kwargs)
        if invalidate:
            self.plot.invalidate()
        self.redraw()

    def redraw(self) -> None:
        """Update the figure's Agg buffer (blit or full draw) and repaint this canvas."""
        if self.width() < 2 or self.height() < 2:
            return
        with matplotlib.rc_context(STYLE):
            self.plot.render()
        self.update()

    def paintEvent(self, event):  # noqa: N802 - Qt's name
        self.paints += 1
        super().paintEvent(event)

    def resizeEvent(self, event):  # noqa: N802 - Qt's name
        # Qt sets the figure's new size here and asks for a full draw: the axes keep their pixel margins.
        super().resizeEvent(event)
        self.plot.relayout()
        self.plot.invalidate()

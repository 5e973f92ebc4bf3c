"""The engine's images shown as images: a panel with a title, the picture (aspect kept) and a caption.

The picture is the engine's 8-bit sRGB image drawn pixel for pixel by ``QPainter`` (scaled with
smooth filtering to the panel), with no 3D library in between: what the panel shows is what
``lighting.render`` computed.  Overlays (the light's arrow, the triangle edges, the scan line, the split
sphere's divider) are drawn in the image's own coordinates by a callback, so they stay on the picture
when the panel is resized.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

__all__ = ["ImageCanvas", "ImagePanel", "WrapLabel", "qimage"]

BACKGROUND = "#1e2024"
MUTED = "#9aa1a9"
WARN = "#ff8787"


def qimage(rgb8: np.ndarray) -> QtGui.QImage:
    """A QImage holding a copy of an ``(H, W, 3)`` or ``(H, W, 4)`` uint8 array.

    Parameters
    ----------
    rgb8 : ndarray of uint8
        RGB or RGBA rows, top row first.

    Returns
    -------
    QImage
        Independent of the array (it owns its pixels).
    """
    a = np.ascontiguousarray(rgb8, dtype=np.uint8)
    h, w, c = a.shape
    fmt = QtGui.QImage.Format.Format_RGB888 if c == 3 else QtGui.QImage.Format.Format_RGBA8888
    return QtGui.QImage(a.data, w, h, a.strides[0], fmt).copy()


class ImageCanvas(QtWidgets.QWidget):
    """Draws one image scaled to fit (aspect kept, centred), and an overlay in image pixel coordinates.

    Attributes
    ----------
    overlay : callable or None
        ``overlay(painter, scale)``: called with the painter already mapped to image pixels (``scale``:
        screen pixels per image pixel, to keep line widths constant on screen).
    """

    #: Mouse press, move and release in image pixel coordinates (x, y) with the buttons held.
    mouse_dragged = QtCore.Signal(float, float, bool)
    #: The mouse wheel turned over the image, in notches (positive: away from the user).
    wheel_turned = QtCore.Signal(float)

    def __init__(self, parent=None, *, min_size=64):
        super().__init__(parent)
        self._image: QtGui.QImage | None = None
        self._shape = (1, 1)
        self.overlay: Callable | None = None
        #: Paint events handled so far (the bench waits for the next one).
        self.paints = 0
        self.setMinimumSize(min_size, min_size)
        self.setSizePolicy(QtWidgets.QSizePolicy.Policy.Expanding, QtWidgets.QSizePolicy.Policy.Expanding)
        self.setAttribute(QtCore.Qt.WidgetAttribute.WA_OpaquePaintEvent)

    def sizeHint(self):  # noqa: N802 - Qt's name
        # Small and equal for every view, so that the splitters share the space by their stretch factors.
        return QtCore.QSize(200, 160)

    def set_image(self, rgb8: np.ndarray) -> None:
        """Show ``rgb8`` (copied) and repaint this widget only."""
        self._image = qimage(rgb8)
        self._shape = rgb8.shape[:2]
        self.update()

    def image_rect(self) -> QtCore.QRectF:
        """Where the image is drawn in the widget (aspect kept, centred)."""
        h, w = self._shape
        s = min(self.width() / w, self.height() / h)
        dw, dh = w * s, h * s
        return QtCore.QRectF((self.width() - dw) / 2, (self.height() - dh) / 2, dw, dh)

    def to_image(self, pos: QtCore.QPointF) -> tuple[float, float]:
        """Widget position → image pixel coordinates (x right, y down)."""
        r = self.image_rect()
        h, w = self._shape
        return ((pos.x() - r.x()) * w / r.width(), (pos.y() - r.y()) * h / r.height())

    def paintEvent(self, event):  # noqa: N802 - Qt's name
        self.paints += 1
        p = QtGui.QPainter(self)
        p.fillRect(self.rect(), QtGui.QColor(BACKGROUND))
        if self._image is not None:
            r = self.image_rect()
            p.setRenderHint(QtGui.QPainter.RenderHint.SmoothPixmapTransform)
            p.drawImage(r, self._image)
            if self.overlay is not None:
                h, w = self._shape
                s = r.width() / w
                p.save()
                p.translate(r.x(), r.y())
                p.scale(s, s)
                p.setRenderHint(QtGui.QPainter.RenderHint.Antialiasing)
                self.overlay(p, s)
                p.restore()
        p.end()

    def mousePressEvent(self, event):  # noqa: N802
        x, y = self.to_image(event.position())
        self.mouse_dragged.emit(x, y, False)

    def mouseMoveEvent(self, event):  # noqa: N802
        if event.buttons() & QtCore.Qt.MouseButton.LeftButton:
            x, y = self.to_image(event.position())
            self.mouse_dragged.emit(x, y, False)

    def mouseReleaseEvent(self, event):  # noqa: N802
        x, y = self.to_image(event.position())
        self.mouse_dragged.emit(x, y, True)

    def wheelEvent(self, event):  # noqa: N802
        self.wheel_turned.emit(event.angleDelta().y() / 120.0)


class ImagePanel(QtWidgets.QFrame):
    """A view panel: a bold title, a body (an :class:`ImageCanvas` or any widget) and a caption below.

    Titles (two lines at most) and captions (three) wrap at words; what does not fit ends with "…" and
    the label's tooltip holds the whole text (:class:`WrapLabel`).

    Parameters
    ----------
    title : str
        The panel's title.
    body : QWidget, optional
        The view (default: a new :class:`ImageCanvas`, as :attr:`canvas`).
    warning_line : bool
        Keep a line for :meth:`set_warning` under the picture (empty when there is nothing to warn of).
    """

    def __init__(self, title: str = "", body: QtWidgets.QWidget | None = None, parent=None, *,
                 warning_line: bool = False):  # fmt: skip
        super().__init__(parent)
        self.setObjectName("viewPanel")
        self.title = _label(title, bold=True, max_lines=2)
        self.warning = _label("", max_lines=1)
        self.warning.setStyleSheet(f"color: {WARN};")
        self.warning.setVisible(warning_line)
        self.caption = _label("", muted=True, max_lines=3)
        #: Labels whose line count follows the panel's height: (label, lines when short, lines when tall).
        self.adaptive_labels = [(self.caption, 2, 6), (self.title, 1, 2)]
        self.canvas = body if body is not None else ImageCanvas()
        lay = QtWidgets.QVBoxLayout(self)
        lay.setContentsMargins(4, 4, 4, 4)
        lay.setSpacing(2)
        lay.addWidget(self.title)
        lay.addWidget(self.canvas, 1)
        lay.addWidget(self.warning)
        lay.addWidget(self.caption)

    def set_title(self, text: str) -> None:
        """Set the title (and its tooltip: the whole text)."""
        self.title.set_full_text(text)

    def set_warning(self, text: str) -> None:
        """A warning line above the caption (clipped highlights ...); its line stays when it is empty."""
        self.warning.set_full_text(text)

    def resizeEvent(self, event):  # noqa: N802 - Qt's name
        # A tall panel shows its whole caption; a short one keeps its room for the picture (the rest is in the
        # tooltip).  One line of caption for every 110 px of panel height, within each label's bounds.
        super().resizeEvent(event)
        for label, fewest, most in self.adaptive_labels:
            lines = max(fewest, min(most, self.height() // 110))
            if lines != label.max_lines:
                label.max_lines = lines
                label._refit()

    def set_caption(self, text: str, *, warn: bool = False) -> None:
        """Set the caption; ``warn`` shows it in the warning colour (an unconverged or clipped value)."""
        self.caption.set_full_text(text)
        if self.caption.property("warn") != bool(warn):  # a style sheet costs a re-polish: only on a change
            self.caption.setProperty("warn", bool(warn))
            self.caption.setStyleSheet(f"color: {WARN if warn else MUTED};")


class WrapLabel(QtWidgets.QLabel):
    """A label that wraps at word boundaries and shows at most ``max_lines`` lines.

    Text beyond the last line is cut at a word and ends with "…"; the tooltip always holds the whole
    text, and :meth:`full_text` returns it.  A panel's picture keeps its room in a small window.

    Parameters
    ----------
    text : str
        The text.
    max_lines : int
        Lines shown at most.
    """

    def __init__(self, text: str = "", *, max_lines: int = 3, parent=None):
        super().__init__(parent)
        self.max_lines = int(max_lines)
        self._full = ""
        self.setWordWrap(True)
        self.setTextFormat(QtCore.Qt.TextFormat.PlainText)
        self.setSizePolicy(QtWidgets.QSizePolicy.Policy.Ignored, QtWidgets.QSizePolicy.Policy.Minimum)
        self.set_full_text(text)

    def full_text(self) -> str:
        """The whole text (what the label shows may be cut to :attr:`max_lines`)."""
        return self._full

    def is_cut(self) -> bool:
        """Whether the label shows less than its whole text."""
        return self.text() != self._full

    def set_full_text(self, text: str) -> None:
        """Set the text (shown up to :attr:`max_lines` lines; whole in the tooltip)."""
        if text == self._full and self.text():
            return
        self._full = text
        self.setToolTip(text)
        self._refit()

    def _lines(self, text: str, width: int) -> int:
        fm = self.fontMetrics()
        rect = fm.boundingRect(QtCore.QRect(0, 0, width, 1 << 20), QtCore.Qt.TextFlag.TextWordWrap, text)
        return max(1, round(rect.height() / max(fm.lineSpacing(), 1)))

    def _reserve(self) -> None:
        # Always the height of max_lines lines, whatever the text: a caption that grows or shrinks by a line
        # must not resize the picture (and redraw a plot in full) beside it.
        height = self.max_lines * self.fontMetrics().lineSpacing() + self.contentsMargins().top() + \
            self.contentsMargins().bottom() + 2
        if self.minimumHeight() != height or self.maximumHeight() != height:
            self.setFixedHeight(height)

    def _refit(self) -> None:
        self._reserve()
        width = self.contentsRect().width()
        shown = self._full
        if width > 20 and self._lines(shown, width) > self.max_lines:
            words = self._full.split(" ")
            lo, hi = 0, len(words)  # the longest prefix of words that fits with the ellipsis
            while lo < hi:
                mid = (lo + hi + 1) // 2
                if self._lines(" ".join(words[:mid]) + " …", width) <= self.max_lines:
                    lo = mid
                else:
                    hi = mid - 1
            shown = " ".join(words[:lo]) + " …"
        if shown != self.text():
            super().setText(shown)

    def resizeEvent(self, event):  # noqa: N802 - Qt's name
        super().resizeEvent(event)
        self._refit()


def _label(text: str, *, bold: bool = False, muted: bool = False, max_lines: int = 3) -> WrapLabel:
    label = WrapLabel(text, max_lines=max_lines)
    style = "font-weight: 600;" if bold else ""
    if muted:
        style += f" color: {MUTED};"
    label.setStyleSheet(style)
    return label

"""What the tests of the explorer's Qt window share: the window itself, its pixels by panel, the widgets' events.

A test drives the window as its widgets do: a slider being dragged asks ``window.apply(changes, live=True)``,
its release ``live=False``; a combo box or a check box emits its editor's ``edited`` signal.  The views follow
once control returns to Qt's loop (:func:`flush` brings them up to date at once).
"""

from __future__ import annotations

import numpy as np
from PySide6 import QtCore, QtWidgets

from explorer.qt.images import BACKGROUND


def settle(passes: int = 8) -> None:
    """Let the layouts and the zero-delay timers run: each pass of the event loop settles one more level."""
    for _ in range(passes):
        QtWidgets.QApplication.processEvents()


def open_window(size=(1200, 720), **kwargs):
    """An :class:`~explorer.qt.window.ExplorerWindow` of ``size``, shown and laid out (close it after use)."""
    from explorer.qt.app import qt_application
    from explorer.qt.window import ExplorerWindow

    qt_application()
    window = ExplorerWindow(window_size=size, **kwargs)
    window.show()
    settle()
    return window


def flush(window) -> set[str]:
    """The views brought up to date now, as on a release or a key once the loop is idle."""
    settle(2)
    return window.flush()


def reset(window) -> None:
    """Every control back to its default, every view up to date, the Compare list empty."""
    window.model.compare.set_solo(None)
    while len(window.model.compare):
        window.model.compare.remove(0)
    window.compare_panel.sync(window.model.compare)
    window.reset()
    flush(window)
    settle()


def pixels(window, widget, image=None, margin: int = 3) -> np.ndarray:
    """The window's pixels where ``widget`` is, ``margin`` pixels in from its borders (``(h, w, 3)`` uint8)."""
    image = window.image() if image is None else image
    top_left = widget.mapTo(window, QtCore.QPoint(0, 0))
    x0, y0 = top_left.x() + margin, top_left.y() + margin
    return image[y0 : y0 + widget.height() - 2 * margin, x0 : x0 + widget.width() - 2 * margin]


def background_rgb() -> np.ndarray:
    """The views' background colour as 8-bit RGB."""
    text = BACKGROUND.lstrip("#")
    return np.array([int(text[k : k + 2], 16) for k in (0, 2, 4)], dtype=np.float64)


def shown_image(canvas) -> np.ndarray:
    """The image an image canvas holds (what it paints, scaled to fit), as ``(h, w, 3)`` uint8."""
    from PySide6 import QtGui

    img = canvas._image.convertToFormat(QtGui.QImage.Format.Format_RGB888)
    a = np.frombuffer(img.constBits(), dtype=np.uint8, count=img.sizeInBytes()).reshape(img.height(), -1)
    return a[:, : 3 * img.width()].reshape(img.height(), img.width(), 3).copy()  # the QImage goes on return


def drag(editor, positions) -> None:
    """Move a number editor's slider as a mouse drag does: held down, each position reported live."""
    slider = editor.slider
    slider.setSliderDown(True)
    for position in positions:
        slider.setValue(int(position))


def release(editor) -> None:
    """Let go of the slider: the position reported again, as final (what the mouse's release does)."""
    slider = editor.slider
    slider.setSliderDown(False)
    slider.moved.emit(slider.value(), False)


def choose(editor, value) -> None:
    """Pick ``value`` in a choice editor (a combo box) as a click on its item does."""
    index = editor.findData(value)
    assert index >= 0, value
    editor.setCurrentIndex(index)


def click_box(qtbot, box) -> None:
    """Click a check box on its indicator (a box may be wider than its text; only text and indicator react)."""
    opt = QtWidgets.QStyleOptionButton()
    box.initStyleOption(opt)
    rect = box.style().subElementRect(QtWidgets.QStyle.SubElement.SE_CheckBoxIndicator, opt, box)
    qtbot.mouseClick(box, QtCore.Qt.MouseButton.LeftButton, pos=rect.center())


def groove_and_handle(slider):
    """A slider's groove and handle rectangles, in its own coordinates (where a hand would press)."""
    opt = QtWidgets.QStyleOptionSlider()
    slider.initStyleOption(opt)
    style = slider.style()
    groove = style.subControlRect(QtWidgets.QStyle.ComplexControl.CC_Slider, opt,
                                  QtWidgets.QStyle.SubControl.SC_SliderGroove, slider)  # fmt: skip
    handle = style.subControlRect(QtWidgets.QStyle.ComplexControl.CC_Slider, opt,
                                  QtWidgets.QStyle.SubControl.SC_SliderHandle, slider)  # fmt: skip
    return groove, handle

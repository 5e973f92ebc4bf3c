"""The QApplication of the explorer, and Ctrl-C / SIGTERM closing the window cleanly.

Qt's event loop runs in C++, where Python's signal handlers cannot run: a SIGTERM would wait for the next
X event.  Here the signals wake the loop through a socket (``signal.set_wakeup_fd`` and a
``QSocketNotifier``), and the handler closes the windows, as the window's own Quit does.
"""

from __future__ import annotations

import os
import signal
import socket
import sys

from PySide6 import QtCore, QtWidgets

__all__ = ["qt_application", "install_signal_handlers", "run_window"]

#: The signals that close the windows: Ctrl-C in the terminal and a polite kill.
CLOSING_SIGNALS = (signal.SIGINT, signal.SIGTERM)


def qt_application(argv=None, *, off_screen: bool = False) -> QtWidgets.QApplication:
    """The running QApplication, or a new one (Fusion style, the explorer's dark palette).

    Parameters
    ----------
    argv : list of str, optional
        Qt's arguments (default: the program name alone: the explorer's own options are not Qt's).
    off_screen : bool
        A new application draws without a display (Qt's ``offscreen`` platform): screenshots, tests.

    Returns
    -------
    QApplication
    """
    app = QtWidgets.QApplication.instance()
    if app is None:
        if off_screen:
            os.environ["QT_QPA_PLATFORM"] = "offscreen"
        QtWidgets.QApplication.setHighDpiScaleFactorRoundingPolicy(
            QtCore.Qt.HighDpiScaleFactorRoundingPolicy.PassThrough
        )
        app = QtWidgets.QApplication(list(argv) if argv is not None else [sys.argv[0] if sys.argv else "lighting"])
        _quiet_platform_notes()
        app.setApplicationName("lighting-explorer")
        app.setStyle("Fusion")
        app.setPalette(_dark_palette())
    return app


#: What Qt's offscreen platform says about window-manager requests it has no use for (a window without a screen
#: cannot raise itself): true, and no news to the user of a headless screenshot.
_PLATFORM_NOTES = ("This plugin does not support propagateSizeHints()", "This plugin does not support raise()")


def _quiet_platform_notes() -> None:
    previous = None

    def handler(kind, context, message):
        if message in _PLATFORM_NOTES:
            return
        if previous is not None:
            previous(kind, context, message)
        else:
            print(message, file=sys.stderr)

    previous = QtCore.qInstallMessageHandler(handler)


def _dark_palette():
    from PySide6.QtGui import QColor, QPalette

    p = QPalette()
    roles = {
        QPalette.ColorRole.Window: "#25282d",
        QPalette.ColorRole.WindowText: "#e9ecef",
        QPalette.ColorRole.Base: "#1b1d21",
        QPalette.ColorRole.AlternateBase: "#2b2f35",
        QPalette.ColorRole.ToolTipBase: "#f8f9fa",
        QPalette.ColorRole.ToolTipText: "#212529",
        QPalette.ColorRole.Text: "#e9ecef",
        QPalette.ColorRole.Button: "#30343a",
        QPalette.ColorRole.ButtonText: "#e9ecef",
        QPalette.ColorRole.Highlight: "#4d8fd6",
        QPalette.ColorRole.HighlightedText: "#ffffff",
        QPalette.ColorRole.PlaceholderText: "#868e96",
    }
    for role, colour in roles.items():
        p.setColor(role, QColor(colour))
    p.setColor(QPalette.ColorGroup.Disabled, QPalette.ColorRole.Text, QColor("#6c737a"))
    p.setColor(QPalette.ColorGroup.Disabled, QPalette.ColorRole.WindowText, QColor("#6c737a"))
    p.setColor(QPalette.ColorGroup.Disabled, QPalette.ColorRole.ButtonText, QColor("#6c737a"))
    return p


class _SignalWaker(QtCore.QObject):
    """Wakes Qt's loop when a closing signal arrives and calls ``on_signal(signum)`` there."""

    def __init__(self, on_signal, parent=None):
        super().__init__(parent)
        self._read, self._write = socket.socketpair()
        self._read.setblocking(False)
        self._write.setblocking(False)
        self._notifier = QtCore.QSocketNotifier(self._read.fileno(), QtCore.QSocketNotifier.Type.Read, self)
        self._notifier.activated.connect(self._readable)
        self._on_signal = on_signal
        self._previous_fd = signal.set_wakeup_fd(self._write.fileno())
        self._previous = {s: signal.signal(s, self._handler) for s in CLOSING_SIGNALS}
        self.received: list[int] = []

    def _handler(self, signum, frame):
        # Runs in Python once the loop is woken (the wakeup fd did that); record and let Qt act.
        self.received.append(signum)

    def _readable(self):
        try:
            data = self._read.recv(64)
        except OSError:
            data = b""
        for signum in list(self.received) or [int(b) for b in data]:
            self._on_signal(signum)
        self.received.clear()

    def restore(self):
        """Put back the handlers and wakeup fd that were there before."""
        signal.set_wakeup_fd(self._previous_fd)
        for s, h in self._previous.items():
            signal.signal(s, h)
        self._notifier.setEnabled(False)
        self._read.close()
        self._write.close()


def install_signal_handlers(on_signal) -> _SignalWaker:
    """Ctrl-C and SIGTERM call ``on_signal(signum)`` inside Qt's loop, at once (no X event needed).

    Parameters
    ----------
    on_signal : callable
        Called with the signal number.

    Returns
    -------
    object
        Its ``restore()`` puts the previous handlers back.
    """
    return _SignalWaker(on_signal)


def run_window(window) -> int:
    """Show ``window`` and run Qt's loop until it closes; Ctrl-C and SIGTERM close it cleanly.

    Parameters
    ----------
    window : QMainWindow

    Returns
    -------
    int
        0 after a normal close, 128 + the signal's number after Ctrl-C or SIGTERM (as a shell reports it).
    """
    app = qt_application()
    got: list[int] = []

    def closing(signum):
        got.append(signum)
        window.close()
        app.quit()

    waker = install_signal_handlers(closing)
    try:
        window.show()
        app.exec()
    finally:
        waker.restore()
    if got:
        return 128 + got[0]
    return 0

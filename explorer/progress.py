"""A tiny dependency-free progress bar for long reports.

On a terminal it redraws one line on standard error:

    stability  [##########..........]  512/1024  50%  3.1 s  ETA 3.1 s

Anywhere else (a pipe, a log file, CI) it prints a plain line at every tenth of
the work instead, so logs stay readable.

Examples
--------
>>> import io
>>> out = io.StringIO()
>>> with Progress(4, "demo", stream=out) as bar:
...     for _ in range(4):
...         bar.update()
>>> last = out.getvalue().splitlines()[-1]
>>> last.startswith("demo: 4/4 (100%)"), last.endswith("done")
(True, True)
"""

from __future__ import annotations

import sys
import time

__all__ = ["Progress"]


def _seconds(t: float) -> str:
    if t < 60:
        return f"{t:.1f} s"
    m, s = divmod(int(round(t)), 60)
    return f"{m} min {s:02d} s"


class Progress:
    """Progress of ``total`` units of work, shown on ``stream`` (standard error by default).

    Parameters
    ----------
    total : int
        Units of work; ``update`` adds to the count done.
    label : str
        Shown before the bar.
    stream : file-like, optional
        Where to write (default ``sys.stderr``).  A bar is drawn only when the
        stream is a terminal (``isatty()``); otherwise plain lines are written.
    width : int
        Characters in the bar.

    Notes
    -----
    Use it as a context manager, or call :meth:`close` at the end.
    """

    def __init__(self, total: int, label: str = "", *, stream=None, width: int = 30):
        self.total = max(int(total), 0)
        self.label = label
        self.stream = stream if stream is not None else sys.stderr
        self.width = width
        self.done = 0
        self.start = time.perf_counter()
        isatty = getattr(self.stream, "isatty", None)
        self.tty = bool(isatty and isatty())
        self._last_decile = -1
        self._last_draw = 0.0
        self._closed = False
        self._width_last = 0

    # -- reporting -------------------------------------------------------------
    def update(self, n: int = 1) -> None:
        """Mark ``n`` more units done and redraw (at most 20 times a second on a terminal).

        Reaching ``total`` finishes the display (as :meth:`close` does), so a caller
        that only ever calls ``update`` still leaves a complete line behind.

        Parameters
        ----------
        n : int, optional
            Units of work just done.

        Returns
        -------
        None
        """
        if self._closed:
            return
        self.done = min(self.done + n, self.total) if self.total else self.done + n
        if self.total and self.done >= self.total:
            self.close()
            return
        now = time.perf_counter()
        if self.tty:
            if now - self._last_draw >= 0.05:
                self._last_draw = now
                self._draw(now)
        else:
            decile = (10 * self.done // self.total) if self.total else 10
            if decile > self._last_decile:
                self._last_decile = decile
                self.stream.write(self._line(now) + "\n")
                self.stream.flush()

    def close(self, outcome: str = "done") -> None:
        """Finish the line (a terminal bar) or write the final plain line, ending with ``outcome``.

        :meth:`abort` closes with ``"stopped"``: work cut short is never reported as done.

        Parameters
        ----------
        outcome : str, optional
            The last word of the line (nothing is added on a terminal for ``"done"``).

        Returns
        -------
        None
        """
        if self._closed:
            return
        self._closed = True
        now = time.perf_counter()
        if self.tty:
            self._draw(now)
            self.stream.write("" if outcome == "done" else f"  {outcome}")
            self.stream.write("\n")
        else:
            self.stream.write(self._line(now) + f"  {outcome}\n")
        self.stream.flush()

    def abort(self) -> None:
        """Close the display for work that did not finish (an error, Ctrl-C, ``SIGTERM``).

        Returns
        -------
        None
        """
        self.close("stopped")

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, exc_type, *exc) -> None:
        if exc_type is None:
            self.close()
        else:
            self.abort()

    # -- formatting ------------------------------------------------------------
    def _fraction(self) -> float:
        return self.done / self.total if self.total else 1.0

    def _eta(self, now: float) -> str:
        f = self._fraction()
        if f <= 0 or f >= 1:
            return ""
        return f"  ETA {_seconds((now - self.start) * (1 - f) / f)}"

    def _line(self, now: float) -> str:
        pct = int(100 * self._fraction())
        return f"{self.label}: {self.done}/{self.total} ({pct}%)  {_seconds(now - self.start)}"

    def _draw(self, now: float) -> None:
        f = self._fraction()
        fill = int(round(self.width * f))
        bar = "#" * fill + "." * (self.width - fill)
        text = (
            f"\r{self.label}  [{bar}]  {self.done}/{self.total}  {int(100 * f):3d}%"
            f"  {_seconds(now - self.start)}{self._eta(now)}"
        )
        self.stream.write(text.ljust(self._width_last))
        self._width_last = len(text)
        self.stream.flush()

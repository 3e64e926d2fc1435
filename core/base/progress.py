"""A one-line progress bar for sweeps on a terminal or in a log file."""

from __future__ import annotations

import math
import sys
import time

__all__ = ["ProgressBar", "progress_callback"]


class ProgressBar:
    """A one-line progress bar: ``progress(done, total)`` redraws it on ``stream`` (stderr).

    On a terminal the line is redrawn in place (at most ten times a second);
    otherwise (a log file) a line is written at every tenth of the work.

    Parameters
    ----------
    stream : file, optional
        Where to draw (default ``sys.stderr``).
    label : str
        What is counted.
    width : int
        Characters of the bar.
    """

    def __init__(self, stream=None, label: str = "runs", width: int = 30):
        self.stream = sys.stderr if stream is None else stream
        self.label, self.width = label, width
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self._t0 = time.perf_counter()
        self._last_draw = -math.inf
        self._last_tenth = -1

    def line(self, done: int, total: int) -> str:
        """The text of the bar."""
        frac = done / total if total else 1.0
        filled = int(round(frac * self.width))
        elapsed = time.perf_counter() - self._t0
        eta = elapsed / done * (total - done) if done else float("nan")
        eta_s = f"eta {eta:.0f} s" if done and done < total else ""
        return (f"[{'#' * filled}{'.' * (self.width - filled)}] {done}/{total} {self.label} "
                f"{100 * frac:3.0f}%  {elapsed:.1f} s {eta_s}").rstrip()

    def __call__(self, done: int, total: int) -> None:
        now = time.perf_counter()
        final = done >= total
        if self.tty:
            if final or now - self._last_draw >= 0.1:
                self.stream.write("\r" + self.line(done, total) + ("\n" if final else ""))
                self.stream.flush()
                self._last_draw = now
            return
        tenth = int(10 * done / total) if total else 10
        if tenth != self._last_tenth:
            self.stream.write(self.line(done, total) + "\n")
            self.stream.flush()
            self._last_tenth = tenth


def progress_callback(progress, label="runs"):
    """``progress`` as a function ``(done, total)``: None/False nothing, True a :class:`ProgressBar`, or the callable."""
    if progress is None or progress is False:
        return lambda done, total: None
    if progress is True:
        return ProgressBar(label=label)
    if callable(progress):
        return progress
    raise ValueError(f"progress must be None, True or a callable(done, total), got {progress!r:.60}")

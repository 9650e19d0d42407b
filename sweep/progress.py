"""Progress of a run on rank 0: tasks done / total, rate and ETA.

``bar``: one line redrawn in place with a bar (a terminal); ``lines``: a plain line at
longer intervals (a pipe or a batch log).  :func:`open_stream` chooses for ``auto``: under
``mpiexec`` the ranks' stderr is a pipe to the launcher even when it runs on a terminal,
so the bar then goes straight to the controlling terminal.
"""

from __future__ import annotations

import os
import sys
import time
from typing import TextIO

#: Values of ``run --progress``.
MODES = ("auto", "bar", "lines", "none")


def open_stream(mode: str) -> tuple[TextIO | None, bool]:
    """The stream and the style for a ``--progress`` mode.

    Returns
    -------
    stream : file or None
        stderr, the controlling terminal (``/dev/tty``), or None for ``none``.
    bar : bool
        Redraw a bar in place (else plain lines).
    """
    if mode == "none":
        return None, False
    if mode == "lines":
        return sys.stderr, False
    if sys.stderr.isatty():
        return sys.stderr, True
    if mode == "bar" or os.environ.get("PMI_RANK") is not None or os.environ.get("PMI_SIZE") is not None:
        try:
            return open("/dev/tty", "w"), True
        except OSError:
            pass
    return sys.stderr, mode == "bar"


def format_duration(seconds: float) -> str:
    """``"1h02m"``, ``"3m05s"`` or ``"12s"``."""
    s = int(round(seconds))
    if s >= 3600:
        return f"{s // 3600}h{s % 3600 // 60:02d}m"
    if s >= 60:
        return f"{s // 60}m{s % 60:02d}s"
    return f"{s}s"


class Progress:
    """Reports the tasks done by all ranks.

    Parameters
    ----------
    total : int
        Tasks of the job.
    already_done : int
        Tasks found on disk when the run started (``--resume``); the rate counts only
        the tasks of this run.
    stream : file
        Where to write.
    bar : bool, optional
        Redraw a bar in place; default: when ``stream`` is a terminal.
    """

    BAR_WIDTH = 30

    def __init__(self, total: int, already_done: int, stream: TextIO, bar: bool | None = None):
        self.total, self.already_done, self.stream = total, already_done, stream
        self.tty = stream.isatty() if bar is None else bar
        self.interval = 0.5 if self.tty else 10.0  # seconds between reports
        self.start = self.last = time.monotonic()

    def _line(self, done: int) -> str:
        elapsed = time.monotonic() - self.start
        n = self.already_done + done
        rate = done / elapsed if elapsed > 0 else 0.0
        eta = format_duration((self.total - n) / rate) if rate > 0 else "?"
        text = (f"{n} / {self.total} tasks ({100 * n / self.total:.0f}%), "
                f"{rate:.3g} tasks/s, elapsed {format_duration(elapsed)}, ETA {eta}")
        if not self.tty:
            return text
        filled = self.BAR_WIDTH * n // self.total
        return f"[{'#' * filled}{'.' * (self.BAR_WIDTH - filled)}] {text}"

    def _write(self, text: str) -> None:
        # A progress report is never worth a run: a terminal gone (a closed SSH session, a
        # hang-up) switches the reports off.
        if self.stream is None:
            return
        try:
            self.stream.write(text)
            self.stream.flush()
        except (OSError, ValueError):
            self.stream = None

    def update(self, done: int) -> None:
        """Report, if the interval has passed, that ``done`` tasks of this run are done."""
        now = time.monotonic()
        if now - self.last < self.interval:
            return
        self.last = now
        self._write(("\r" + self._line(done) + "\x1b[K") if self.tty else self._line(done) + "\n")

    def finish(self, done: int) -> None:
        """Final report: ``done`` tasks of this run are done."""
        self._write(("\r" + self._line(done) + "\x1b[K\n") if self.tty else self._line(done) + "\n")

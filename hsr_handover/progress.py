"""A progress bar on stderr, for simulated time and for trials alike."""

from __future__ import annotations

import sys


class ProgressBar:
    """Redrawn in place on a terminal; elsewhere (a CI log, a pipe) one line per tenth, so logs
    stay short. `show(fraction, label, finished)` draws `[####....] label`."""

    def __init__(self, width: int = 30):
        self._width = width
        self._interactive = sys.stderr.isatty()
        self._last_tenth = -1

    def show(self, fraction: float, label: str, finished: bool) -> None:
        fraction = 1.0 if finished else min(max(fraction, 0.0), 1.0)
        tenth = int(10 * fraction)
        if not self._interactive and tenth == self._last_tenth and not finished:
            return
        self._last_tenth = tenth
        filled = int(self._width * fraction)
        text = f"[{'#' * filled}{'.' * (self._width - filled)}] {label}"
        if self._interactive:
            print("\r" + text, end="\n" if finished else "", file=sys.stderr, flush=True)
        else:
            print(text, file=sys.stderr, flush=True)

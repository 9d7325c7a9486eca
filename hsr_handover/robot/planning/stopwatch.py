"""Wall time by stage, the one clock every plan keeps: the planning benchmark reports where the
time goes, and the handover cycle how long it planned."""

from __future__ import annotations

import contextlib
import time
from collections.abc import Iterable, Iterator


class Stopwatch:
    """Seconds spent in each named stage; a stage timed again adds to its total."""

    def __init__(self, stages: Iterable[str] = ()):
        self.seconds: dict[str, float] = dict.fromkeys(stages, 0.0)

    @contextlib.contextmanager
    def stage(self, name: str) -> Iterator[None]:
        """Time the block's wall time to the stage `name`."""
        started = time.perf_counter()
        try:
            yield
        finally:
            self.seconds[name] = self.seconds.get(name, 0.0) + time.perf_counter() - started

    def snapshot(self) -> dict[str, float]:
        """The stages' seconds so far, as a copy that later timing leaves alone."""
        return dict(self.seconds)

"""The motions the handover cycle plays one after another: the one under way, those queued
behind it, and where the robot stands once they end (or when told to stand still)."""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Iterable

import numpy as np

from hsr_handover.robot.planning.plan import Motion


@dataclasses.dataclass(frozen=True)
class Running:
    """The motion under way: the `motion` and when it started (`start`, s)."""

    motion: Motion
    start: float

    @property
    def name(self) -> str:
        return self.motion.name


class MotionQueue:
    """Plays motions in order. A copy shares the motions, which are never changed once
    made, and copies the queue."""

    def __init__(self):
        self.running: Running | None = None
        self._queue: list[Motion] = []
        self.started: list[Running] = []  # every motion started, in order
        self._hold: tuple[np.ndarray, np.ndarray] | None = None  # (q, 0) to stand still at

    def __deepcopy__(self, memo: dict) -> MotionQueue:
        clone = copy.copy(self)
        clone._queue = list(self._queue)
        clone.started = list(self.started)
        return clone

    @property
    def running_name(self) -> str | None:
        """The name of the motion under way, None when none is."""
        return None if self.running is None else self.running.name

    def play(self, motions: Iterable[Motion]) -> None:
        """Queue `motions` in place of those queued (the one under way plays on)."""
        self._queue = list(motions)

    def advance(self, time: float) -> str | None:
        """At `time` (s): ends the motion under way if it is over (standing where it ended)
        and starts the next queued one; the name of the one it started, None if none."""
        running = self.running
        if running is not None and time - running.start < running.motion.duration:
            return None
        if running is not None:
            end = running.motion.state(running.motion.duration)[0]
            self._hold, self.running = (end, np.zeros_like(end)), None
        if not self._queue:
            return None
        motion = self._queue.pop(0)
        self.running = Running(motion, time)
        self.started.append(self.running)
        return motion.name

    def played_so_far(self, name: str, time: float, samples: int = 16) -> list[np.ndarray]:
        """Configurations along the motion `name` under way, from its start to `time` (none
        when no motion of that name is under way)."""
        if self.running is None or self.running.name != name:
            return []
        return self._along(0.0, time - self.running.start, samples)

    def still_to_play(self, time: float, step_s: float) -> list[np.ndarray]:
        """Configurations along the motion under way from `time` to its end, `step_s` apart
        or closer (none when no motion is under way)."""
        if self.running is None:
            return []
        duration = self.running.motion.duration
        elapsed = min(time - self.running.start, duration)
        samples = max(2, int(np.ceil((duration - elapsed) / step_s)) + 1)
        return self._along(elapsed, duration, samples)

    def _along(self, start: float, end: float, samples: int) -> list[np.ndarray]:
        """`samples` configurations of the motion under way from `start` to `end` (s into it,
        `end` held to its duration)."""
        motion = self.running.motion
        end = min(end, motion.duration)
        return [motion.state(t)[0] for t in np.linspace(start, end, samples)]

    def stand_still(self, q: np.ndarray) -> None:
        """Drop every motion and stand at `q`."""
        self.running, self._queue = None, []
        self._hold = (q, np.zeros_like(q))

    def command(self, time: float) -> tuple[np.ndarray | None, np.ndarray | None]:
        """(positions, velocities) at `time`: the motion under way, else where to stand; None
        before there is either."""
        if self.running is not None:
            return self.running.motion.state(time - self.running.start)
        if self._hold is not None:
            return self._hold
        return None, None

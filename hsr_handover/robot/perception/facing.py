"""SteadyFacing: which way a person's torso faces, voted over frames.

A seated or standing person at a table turns the head, not the torso, so the direction seen
most often is the torso's. Single frames err: a chest plane fitted on an arm held in front of
it (`chest_plane`), or, presenting an object, on the robot's own arm.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np

FACING_BIN_DEG = 5.0  # SteadyFacing's heading bins
FACING_WINDOW_BINS = 3  # either side: a window of 35 degrees around the busiest bin


class SteadyFacing:
    """The horizontal direction seen most often: votes in FACING_BIN_DEG bins of heading, and
    the mean of the votes within FACING_WINDOW_BINS of the busiest window. A few frames read
    wrong (a chest fitted on the arm in front of it) are outvoted, not averaged in. Adding
    returns a new SteadyFacing (the tracker's copies share it)."""

    BINS = int(360 / FACING_BIN_DEG)

    def __init__(self, counts: np.ndarray | None = None, sums: np.ndarray | None = None):
        self._counts = np.zeros(self.BINS) if counts is None else counts
        self._sums = np.zeros((self.BINS, 2)) if sums is None else sums

    def add(self, direction: np.ndarray | None) -> SteadyFacing:
        """With one more vote; a direction not seen (None or NaN) adds none."""
        if direction is None or not np.isfinite(direction[:2]).all():
            return self
        heading = math.degrees(math.atan2(direction[1], direction[0]))
        index = int((heading + 180.0) // FACING_BIN_DEG) % self.BINS
        counts, sums = self._counts.copy(), self._sums.copy()
        counts[index] += 1
        sums[index] += np.asarray(direction[:2], dtype=float)
        return SteadyFacing(counts, sums)

    def direction(self) -> np.ndarray | None:
        """The unit vector (x, y, 0) of the busiest window's mean; None before any vote."""
        if not self._counts.any():
            return None
        offsets = range(-FACING_WINDOW_BINS, FACING_WINDOW_BINS + 1)
        windows = sum(np.roll(self._counts, -offset) for offset in offsets)
        peak = int(np.argmax(windows))
        total = sum(self._sums[(peak + offset) % self.BINS] for offset in offsets)
        length = float(np.linalg.norm(total))
        return np.array([*(total / length), 0.0]) if length > 1e-9 else None


def steady_facing(directions: Iterable[np.ndarray | None]) -> np.ndarray | None:
    """SteadyFacing's direction over `directions` (None where none was seen)."""
    facing = SteadyFacing()
    for direction in directions:
        facing = facing.add(direction)
    return facing.direction()

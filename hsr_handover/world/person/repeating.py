"""The person whose request the robot does not take up asks again (the world side of a repeat):
when the robot's hand has stayed where it was for `wait_s` after the pointing ended, the person
looks at and points at the object once more, as people repeat a request that drew no response.
Once per run.

The person is part of the world: it may see where the robot's hand truly is. Points here are
in the person frame (`hsr_handover.world.station.world.person_pose`).
"""

from __future__ import annotations

import copy
import math

import numpy as np

from hsr_handover.world.person.correcting import Change, starting_at

MOVED = 0.10
"""m the robot's hand must move sideways (horizontally) for the person to see a response: a
robot setting off for the object moves its base or reaches out; raising the torso to see over
the objects (`handover.watch_view`) moves the hand only up."""


class Repeater:
    """Watches the robot's hand from the request's end (`ended`, s); if it has not moved MOVED
    horizontally by `ended + wait_s`, the person makes the request again at once: `changes`
    (times from the request's start, as `behavior.posture_changes` gives them)."""

    def __init__(self, changes: list[Change], ended: float, wait_s: float):
        self._changes = list(changes)
        self._ended, self._wait_s = ended, wait_s
        self._start: np.ndarray | None = None  # where the hand was when the request ended
        self.answered = False  # the robot's hand moved: the request drew a response
        self.repeated_at: float | None = None

    def __deepcopy__(self, memo: dict) -> Repeater:
        """Drake copies the state at every update: the changes and the hand's start are never
        altered in place, so copies share them."""
        return copy.copy(self)

    def update(self, time: float, hand: np.ndarray) -> list[Change]:
        """The postures to move to (empty when nothing changes), on the robot's hand now."""
        if not self._changes or self.answered or self.repeated_at is not None:
            return []
        if time < self._ended:
            return []
        if self._start is None:
            self._start = np.array(hand, dtype=float)
        if math.dist(hand[:2], self._start[:2]) >= MOVED:
            self.answered = True
            return []
        if time < self._ended + self._wait_s:
            return []
        self.repeated_at = time
        return starting_at(time, self._changes)

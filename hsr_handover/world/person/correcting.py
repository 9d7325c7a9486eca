"""The person who sees the robot pick up the wrong object asks again (the world side of a
correction): when an object other than the one asked for rises off the table, the person, after
a reaction time, looks at and points at the one they want once more, as people repair a request
that was misunderstood (they do not wait for the wrong object to be brought). Once per run.

The person is part of the world: it may know which object is lifted. Points here are in the
person frame (`hsr_handover.world.station.world.person_pose`).
"""

from __future__ import annotations

import copy
from collections.abc import Sequence

import numpy as np

from hsr_handover.world.person.receiving import RAISED

Change = tuple[float, np.ndarray]  # (time, whole-body posture)


def starting_at(start: float, changes: Sequence[Change]) -> list[Change]:
    """`changes` (times from their own start) moved to begin at `start` (s)."""
    return [(start + at, posture) for at, posture in changes]


class Corrector:
    """Watches the objects for one other than `wanted` lifted RAISED off the table; then the
    person asks again: the request's posture `changes` (times from the request's start, as
    `behavior.posture_changes` gives them), `reaction_s` after the lift is seen. `wanted` ""
    (nothing asked for) never corrects."""

    def __init__(self, wanted: str, changes: Sequence[Change], reaction_s: float):
        self.wanted = wanted
        self._changes = list(changes)
        self._reaction_s = reaction_s
        self._first: dict[str, float] = {}  # each object's height when first seen
        self.corrected_at: float | None = None  # when the wrong object was seen lifted

    def __deepcopy__(self, memo: dict) -> Corrector:
        """Drake copies the state at every update: the changes are never altered, so copies
        share them."""
        clone = copy.copy(self)
        clone._first = dict(self._first)
        return clone

    def update(self, time: float, objects: dict[str, np.ndarray]) -> list[Change]:
        """The postures to move to (empty when nothing changes), on the objects' centres now."""
        if not self.wanted or not self._changes or self.corrected_at is not None:
            return []
        for name, point in objects.items():
            first = self._first.setdefault(name, float(point[2]))
            if name != self.wanted and point[2] >= first + RAISED:
                self.corrected_at = time
                return starting_at(time + self._reaction_s, self._changes)
        return []

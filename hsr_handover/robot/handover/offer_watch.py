"""Whether the object the robot carries looks held out to the person (paper 3.3: the receiver
acts too). People reach for an object that has come to rest in front of them; a carry that
stops to be planned again, or crawls, has, and a person who reached for one then met the
robot's fingers as the carry went on (a carry set off again as the person began to reach; one
crept 7 cm up into the closing hand). Held out within the person's reach, the carry has become
a presentation, and the robot treats it as one.

The palm counts as still when it moves slower than `still_speed` between decisions, read by
the joint sensors' forward kinematics, and the object as held out once it has stayed still for
`offered_s` after moving: as a carry sets off the object is still where it was lifted, which
is not a stop."""

from __future__ import annotations

import numpy as np

from hsr_handover.robot.handover.cycle_params import CycleParams


class OfferWatch:
    """Made afresh as each object is carried off; `held_out(time, palm)` at each decision of
    the carry."""

    def __init__(self, params: CycleParams):
        self._params = params
        self._palm: tuple[float, np.ndarray] | None = None  # the last decision's
        self._moved = False  # whether the palm has moved yet
        self._still_since: float | None = None  # since when it has stayed still, having moved

    def held_out(self, time: float, palm: np.ndarray) -> bool:
        """Whether the object at `palm` (m, world) looks held out at `time` (s)."""
        params = self._params
        last, self._palm = self._palm, (time, np.asarray(palm, dtype=float))
        if last is None or time <= last[0]:
            return False
        still = np.linalg.norm(palm - last[1]) <= params.still_speed * (time - last[0])
        self._moved = self._moved or not still
        if not (still and self._moved):
            self._still_since = None
            return False
        self._still_since = last[0] if self._still_since is None else self._still_since
        return time - self._still_since >= params.offered_s - 1e-9

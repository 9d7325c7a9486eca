"""Where to hold an object out at a person's waiting hand: at the aim if the object fits there,
else at the nearest point round it where it does, beside the perceived hand.

The perceived forearm's capsule runs on a hand's length past the wrist and is widened by the
skeleton's error, so an object brought along the forearm's line to the fingers is inside it and
no inverse kinematics is found (the robot would try every second until it gives up).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from hsr_handover.robot.perception.object_shapes import ObjectShape
from hsr_handover.robot.planning.inverse_kinematics import MIN_DISTANCE
from hsr_handover.robot.planning.perceived_scene import Capsule
from hsr_handover.robot.planning.planning_scene import HELD_SPREAD

OFFER_SEARCH = 0.24
"""m round the aim searched for a point where the object fits: enough for an aim on the forearm
capsule's axis (its radius with the margin 9.5 cm, a held cup's extent 11.7 cm, the IK's
2 cm)."""
OFFER_STEP = 0.02  # m between the points tried
OFFER_TRIES = 3  # points handed on to the inverse kinematics, nearest first
FINGERS_EXTENT = 0.07
"""m from the pads' centre that the fingers reach (their tips 5 cm past it, a finger's width
to either side of an object): the least room the hand needs, holding anything or nothing."""


def _lattice() -> np.ndarray:
    """Offsets within OFFER_SEARCH, nearest first; of equally near ones, the higher first (an
    object is held out over a hand, not under it)."""
    count = round(OFFER_SEARCH / OFFER_STEP)
    steps = OFFER_STEP * np.arange(-count, count + 1)
    offsets = np.stack(np.meshgrid(steps, steps, steps, indexing="ij"), -1).reshape(-1, 3)
    offsets = offsets[np.linalg.norm(offsets, axis=1) <= OFFER_SEARCH + 1e-9]
    order = np.lexsort((-offsets[:, 2], np.round(np.linalg.norm(offsets, axis=1), 6)))
    return offsets[order]


OFFER_OFFSETS = _lattice()
"""The offsets (m) tried round an aim, nearest first."""


def object_extent(shape: ObjectShape | None) -> float:
    """m from the pads' centre to the farthest point of the hand holding an object of `shape`
    (None: nothing, or unknown), as the planning scene widens the object."""
    if shape is None:
        return FINGERS_EXTENT
    held = np.hypot(shape.radius + HELD_SPREAD, shape.height / 2 + HELD_SPREAD)
    return float(max(held, FINGERS_EXTENT))


def offer_points(aim: np.ndarray, person: Sequence[Capsule], extent: float) -> list[np.ndarray]:
    """Up to OFFER_TRIES points within OFFER_SEARCH of `aim` (m, world), nearest first, where
    an object reaching `extent` (m) from its centre keeps MIN_DISTANCE from every capsule of
    the `person`: `aim` itself when it fits there."""
    points = np.asarray(aim, dtype=float) + OFFER_OFFSETS
    if not person:
        return [points[0]]
    clearances = np.min([capsule.distance(points) for capsule in person], axis=0)
    return list(points[clearances >= extent + MIN_DISTANCE][:OFFER_TRIES])

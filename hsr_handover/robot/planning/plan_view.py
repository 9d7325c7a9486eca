"""What the robot's plans show in the replay: the palm's planned path and, once the
way to the person is planned, the arm's effectivity map at the chosen base, the person's
reachable range, the mutual area among the arm's nodes (paper fig. 14) and the handover point.
All in the world frame (m)."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterable

import numpy as np

PATH_STEP_S = 0.1  # s between the palm's samples along a planned motion


def _no_points() -> np.ndarray:
    return np.zeros((0, 3))


@dataclasses.dataclass(frozen=True)
class PlanView:
    """`palm_path` (n, 3) of the latest plan; `arm_nodes` (m, 3) with the `mutual` mask (m,),
    `person_nodes` (k, 3) and the `handover_point` (None until the carry is planned)."""

    palm_path: np.ndarray = dataclasses.field(default_factory=_no_points)
    arm_nodes: np.ndarray = dataclasses.field(default_factory=_no_points)
    mutual: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(0, dtype=bool))
    person_nodes: np.ndarray = dataclasses.field(default_factory=_no_points)
    handover_point: np.ndarray | None = None

    def updated(self, newer: PlanView | None) -> PlanView:
        """This view after a `newer` plan's: its palm path, and its maps if it has them (a
        follow or a retreat keeps the handover's)."""
        if newer is None:
            return self
        if newer.handover_point is not None:
            return newer
        return dataclasses.replace(self, palm_path=newer.palm_path)


def palm_path(motions: Iterable[object], palm: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    """The pads' centre every PATH_STEP_S along `motions` (each with a `duration` and
    `state(time)` giving positions first), `palm(q)` placing it for positions q."""
    points = []
    for motion in motions:
        for time in np.append(np.arange(0.0, motion.duration, PATH_STEP_S), motion.duration):
            points.append(palm(motion.state(float(time))[0]))
    return np.array(points, dtype=float).reshape(-1, 3)

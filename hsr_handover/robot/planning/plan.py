"""What a planner answers: a `Plan` of named, timed `Motion`s, or why there is none. The one
vocabulary of planning, from the planner's functions to the handover cycle that plays the
motions (which reads it without Drake)."""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Protocol

import numpy as np

from hsr_handover.robot.planning.outcome import Outcome
from hsr_handover.robot.planning.plan_view import PlanView

if TYPE_CHECKING:
    from hsr_handover.robot.planning.handover_pose import HandoverPose


class Trajectory(Protocol):
    """Plant positions over `duration` s from rest: a toppra-timed path (`timing.TimedPath`) or
    a ruckig state-to-state move (`retarget.Retargeting`)."""

    duration: float

    def state(self, time: float) -> tuple[np.ndarray, np.ndarray]:
        """Positions and velocities at `time` s from the start (held at the ends)."""

    def sample(self, step: float) -> tuple[np.ndarray, np.ndarray]:
        """Times (n,) every `step` s from 0, the end included, and the positions (n, nq)."""

    def knot_times(self) -> np.ndarray:
        """Times (s, rising, 0 and the end included) at which the trajectory is given as it
        was timed: toppra's grid points, or ruckig's samples."""


@dataclasses.dataclass(frozen=True, kw_only=True)
class Motion:
    """One timed segment of a plan: its `name` ("move" to the pre-grasp, "approach", "lift",
    "carry", "follow", ...), the `trajectory` and the obstacles it may touch (`ignore`)."""

    name: str
    trajectory: Trajectory
    ignore: tuple[str, ...] = ()

    @property
    def duration(self) -> float:
        return self.trajectory.duration

    def state(self, time: float) -> tuple[np.ndarray, np.ndarray]:
        """Positions and velocities at `time` s from its start (held at its ends)."""
        return self.trajectory.state(time)

    def sample(self, step: float) -> tuple[np.ndarray, np.ndarray]:
        """Times (n,) every `step` s from its start, the end included, and the positions."""
        return self.trajectory.sample(step)

    def knots(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Times (n,) from its start at which it is given as it was timed, and the positions
        and velocities (n, nq) then: what a joint trajectory controller is sent."""
        times = self.trajectory.knot_times()
        states = [self.state(float(t)) for t in times]
        return times, np.array([q for q, _ in states]), np.array([v for _, v in states])


@dataclasses.dataclass(frozen=True, kw_only=True)
class Plan(Outcome):
    """`ok` with the `motions` in order, ending at the configuration `goal`, or not with the
    `reason`. The wall `seconds` of each stage (`Stopwatch`) and the IK solves tried; for a
    grasp, the object as it will be `held` (`planner.Held`, for later plans); for a handover,
    the `pose` chosen and the person's arm it hands to (`receiving`: "r" or "l"); what the
    replay shows of it (`view`). `retried` names what a retry or fallback found after the
    first tries failed ("carry: base first", "handover pose: map node 3"), none when they
    found it all."""

    target: str = ""
    motions: tuple[Motion, ...] = ()
    seconds: dict[str, float] = dataclasses.field(default_factory=dict)
    ik_solves: int = 0
    goal: np.ndarray | None = None
    held: object = None
    pose: HandoverPose | None = None
    receiving: str = ""
    view: PlanView | None = None
    retried: tuple[str, ...] = ()

    @property
    def duration(self) -> float:
        """s the motions take, end to end."""
        return sum(motion.duration for motion in self.motions)

    @property
    def plan_seconds(self) -> float:
        """The wall time (s) it took to plan, all stages."""
        return sum(self.seconds.values())

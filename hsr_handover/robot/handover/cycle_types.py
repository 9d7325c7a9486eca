"""What the perceiving-acting cycle (paper 3.3) works on and gives: its phases and failures,
the percepts it decides from, the planner it asks and the motions it gets back, and its
record. Plain Python: `cycle.HandoverCycle` is the machine that uses them."""

from __future__ import annotations

import dataclasses
import enum
import math
from typing import Protocol

import numpy as np

from hsr_handover.robot.planning.plan import Motion, Plan


class Phase(enum.Enum):
    WATCH = "watch"
    APPROACH = "approach"  # to the pre-grasp, then along the approach
    GRASP = "grasp"  # the gripper closing
    LIFT = "lift"
    CARRY = "carry"  # to the handover point
    PUT_BACK = "put_back"  # the person asked for another object: the one lifted goes back
    PRESENT = "present"  # waiting for the person's hand
    RELEASE = "release"  # the gripper opening
    RETREAT = "retreat"
    DONE = "done"
    FAILED = "failed"


TERMINAL_PHASES = frozenset({Phase.DONE, Phase.FAILED})
"""The phases a cycle ends in: nothing is done in them."""


class Failure(enum.Enum):
    """Why a cycle failed (HandoverSim's classes and ours)."""

    UNREACHABLE = "unreachable"
    GRASP_MISSED = "grasp missed"
    DROPPED = "dropped"
    PERSON_WITHDREW = "person withdrew"
    TIMEOUT = "timeout"


@dataclasses.dataclass(frozen=True)
class Percepts:
    """What the robot knows at `time` s: its measured positions `q` (planning plant order), the
    gripper's measured `opening` (m), the `target` recognised (None until one is), the target
    object's centre as the camera sees it now (`object_seen`, None when not in view), the
    receiving hand from the skeleton (`hand`, None when not seen), the palm's point by forward
    kinematics of `q` (`palm`), a point on the person's body seen now (`person`: the
    receiving shoulder, or else the neck or a shoulder; None when none is in view), how far
    the joint sensors put the palm from where it is commanded (`pull`, m: a person tugging at
    the object held), the force the hand and its load exert on the wrist's sensor
    (`wrist_force`, N, world; None without the sensor) and a point of the person's face seen
    now (`face`: the nose, an eye or an ear; None when none is), and another object the person
    asked for after the target (`correction`, None if none)."""

    time: float
    q: np.ndarray
    opening: float
    target: str | None = None
    object_seen: np.ndarray | None = None
    hand: np.ndarray | None = None
    palm: np.ndarray | None = None
    person: np.ndarray | None = None
    pull: float = 0.0
    wrist_force: np.ndarray | None = None
    face: np.ndarray | None = None
    correction: str | None = None


class CyclePlanner(Protocol):
    """The motions the cycle asks for, planned from what the robot perceives."""

    def grasp(self, label: str, q: np.ndarray) -> Plan:
        """To the pre-grasp and along the approach (gripper open), then the lift ("lift",
        gripper closed), as named motions."""

    def carry(self, q: np.ndarray, held: object) -> Plan:
        """From the lifted object to the handover point, holding the grasp's `held`."""

    def person_clearance(self, path: list[np.ndarray], held: object, within: float) -> float:
        """The least clearance (m) of the configurations `path`, holding `held`, to the person
        as perceived now (inf when none comes within `within`)."""

    def person_reaches(self, point: np.ndarray) -> bool:
        """Whether the person, as perceived now, may reach for `point` (m, world)."""

    def follow(self, q: np.ndarray, v: np.ndarray, aim: np.ndarray, held: object) -> Plan:
        """State to state, to hold the object out at `aim` (m, world: `CycleParams.offer` in
        front of the person's hand), or beside it where the person's perceived hand leaves no
        room there."""

    def retreat(self, q: np.ndarray, held: object, let_go: object = None) -> Plan:
        """Back to the ready posture, with the object `held` or (None) without; `let_go` is the
        object just let go of (or missed), still between the fingers, to back away from."""

    def put_back(
        self, q: np.ndarray, held: object, lifted: np.ndarray, came: list[np.ndarray]
    ) -> Plan:
        """Holding `held`, back to `lifted` (the configuration the grasp's lift ended in) along
        the way it `came` from there (configurations, possibly none), then down to where it
        was grasped."""

    def back_off(self, q: np.ndarray, let_go: object) -> Plan:
        """The hand straight back from the object just let go of (no motion when it is clear
        of it already)."""


@dataclasses.dataclass
class Fetch:
    """What the robot knows of the object it fetches now: the grasp's `held` (the object as
    the hand holds it, for later plans) and `lift` (played once the fingers hold it), the
    opening they closed on it (`width`, m), where the camera saw it stand (`start`, m, world),
    when the robot turned to the person with it lifted (`turned`, s), until when it looks
    for it before planning its grasp unseen (`seek_until`, s), when the carry under way was
    last checked against the person (`checked`, s), whether it was stopped short of them, to
    be planned again (`stopped`), the way it was carried before (`carried`: configurations,
    from the lift's end), whether the robot presented it where a carry had stopped or crawled
    within the person's reach (`held_out_early`) and whether it then carried it on to the
    handover point (`went_on`)."""

    held: object = None
    lift: Motion | None = None
    width: float = math.inf
    start: np.ndarray | None = None
    turned: float | None = None
    seek_until: float | None = None
    checked: float = -math.inf
    stopped: bool = False
    carried: tuple[np.ndarray, ...] = ()
    held_out_early: bool = False
    went_on: bool = False


@dataclasses.dataclass
class CycleRecord:
    """The cycle's record: `phase`, `failure` (None unless failed), `reason`, when each phase
    began (`phase_times`, s), planning wall time (`planning_s`), when the target was
    recognised (`recognised_time`) and which (`target`: the object fetched now), the arm lift
    (m) the robot watched from (`watch_lift`; the supervisor's, 0 for the ready posture), the
    person's arm it hands to (`receiving`, "r" or "l", once the carry is planned) and, once
    the person has asked for another object, the one first fetched (`first_target`) and when
    the correction was seen (`corrected_time`)."""

    phase: Phase = Phase.WATCH
    failure: Failure | None = None
    reason: str = ""
    target: str | None = None
    recognised_time: float = math.nan
    phase_times: dict[str, float] = dataclasses.field(default_factory=dict)
    planning_s: float = 0.0
    watch_lift: float = 0.0
    receiving: str = ""
    first_target: str | None = None
    corrected_time: float = math.nan

    @property
    def over(self) -> bool:
        return self.phase in TERMINAL_PHASES

    @property
    def outcome(self) -> str:
        """How the cycle ended: `done`; `failed, CLASS: reason`; `not recognised` (it watched
        to the end); or `timeout: PHASE when the run ended` (the cycle was not over)."""
        if self.failure is not None:  # decided, though the retreat may still be under way
            return f"failed, {self.failure.value}: {self.reason}"
        if self.phase is Phase.DONE:
            return "done"
        if self.phase is Phase.WATCH and self.target is None:
            return "not recognised"
        return f"timeout: {self.phase.value} when the run ended"

"""The person taking the object (the world side): once the robot holds an object out within
reach and still, the person reaches for it after a reaction time (turning toward where it is
now if it moves on, and reaching again if the hand stops out of grip), closes the hand on it
when the hand gets there and, a moment later, draws it in: the tug a robot feels and lets go
at (a person does not wait to be told the gripper has opened). The hand comes at the object
from the side the robot's fingers leave free, as people do: straight from the shoulder when it
can, else turned round the object, from below or from above.

The person is part of the world: it may know where the objects and the robot's fingers truly
are. Points here are in the person frame (`hsr_handover.world.station.world.person_pose`).
"""

from __future__ import annotations

import dataclasses
import enum
import math
from collections.abc import Sequence

import numpy as np
from scipy.spatial.distance import cdist

from hsr_handover.world.person.aiming import arm_move_points, arm_points
from hsr_handover.world.person.behavior import REACHES, Action, rest_posture, target_posture
from hsr_handover.world.person.body import (
    HAND_THICKNESS,
    HAND_WIDTH,
    BodyDimensions,
    arm_joint_indices,
)

STILL_SPEED = 0.05  # m/s: an object moving slower than this is being held out
STILL_S = 0.3  # s it must stay still (and in reach) to count as offered
RAISED = 0.03  # m above where it first stood: an object on the table is not offered
REACH_SHARE = 0.95  # of the arm's length (shoulder to the hand's middle) the person reaches to
REACH_SHORT = 0.17
"""m short of the object's centre, on the person's side, that the hand's middle reaches for: a
hand's half length (about 9.5 cm) plus 7.5 cm, so the box-shaped hand stops clear of the robot's
fingertips, which stand up to 5 cm past the object's centre when the gripper points at the
person (reaching for the centre, or for the object's near side, put the person's fingertips
against the robot's). The hand's hold is a soft weld (`systems/hand_grip.py`), not friction,
so it closes a little short of the object's surface."""
ARRIVED = 0.02
"""m from the point reached for at which the hand closes on the object: it closes where it
arrives (closing on the way, by its distance to the object, latched the object 5 cm off and
dragged it up out of the robot's fingers into them), or where it first touches the object on
the way, and stops there: a hand that strikes what it reaches for closes on it, as people's
do, rather than shoving it through the robot's fingers (which pushes a box out of them before
the hand closes)."""
MOVED = 0.03
"""m the object may move from where the reach was aimed before the person aims again (the robot
may still be bringing it closer as the hand sets off)."""
CORRECTION_S = 0.1
"""s from seeing the object move to the hand's path turning toward where it is now: people
correct a reach in flight about 100 ms after its object is displaced (Paulignan et al. 1991,
Exp. Brain Res. 83:502; Prablanc and Martin 1992). Aimed only where the object first stood
still, a hand met the finger pad of a robot that had brought the box 17 cm on, into its path."""
SETTLED = 0.002  # m a hand moves between two looks once it has stopped short of the point
SETTLE_AFTER_S = 0.3  # s into the reach before a hand at rest counts as stopped
GRIP_DISTANCE = REACH_SHORT + 0.05
"""m from the hand's middle to the object's centre beyond which a stopped hand does not close
(the object is not there)."""
TURNS_DEG = (0.0, 30.0, -30.0, 60.0, -60.0, 90.0, -90.0)
"""Degrees round the object, about the vertical, from straight between it and the shoulder."""
TILTS_DEG = (0.0, -30.0, 30.0)  # level with the line to the shoulder, then from below, above
PATH_SAMPLES = 8  # arm poses checked along the move to the object
CLEAR = math.hypot(HAND_WIDTH, HAND_THICKNESS) / 2 + 0.025
"""m from the forearm's and hand's axes to the robot's gripper (its capsules): the hand box's
half diagonal (4.3 cm) and 2.5 cm to spare. The arm follows its move a little off the straight
line in joint space that is checked, and the finger pads' box corners stand 0.4 cm outside
their capsules: with 1 cm to spare, a hand planned 6 cm off the axis brushes a finger on its
way in."""
TUG_S = 0.3  # s from closing the hand to the tug
TUG = 0.06
"""m the hand draws back first, the way it came (out of the gripper's free side): the tug a
robot feels and lets go at (drawing the object all the way in at once swung the hand into the
robot's fingers; straight toward the shoulder, past a finger on that side, it pushed the
fingers apart)."""
DRAW_IN_S = 1.0  # s from the tug to drawing the object in
DRAW_IN = 0.2
"""m from where the hand closed that it draws the object in, the same way: clear of the
robot's fingers (a fixed point in front of the chest was barely nearer than an object held out
close, and the hand went back into the fingers)."""


Capsule = tuple[np.ndarray, np.ndarray, float]  # two end points and a radius (m)


class Receiving(enum.Enum):
    WAITING = "waiting"
    REACHING = "reaching"
    HOLDING = "holding"
    TUGGING = "tugging"
    DRAWN_IN = "drawn in"


@dataclasses.dataclass(frozen=True)
class ReceivingParams:
    """How this person takes an object: `takes` (False: never reaches, the robot must time
    out), the reaction time `reaction_s` (s) from the offer to the reach (and from seeing
    another object lifted to asking again), the `arm` they prefer (the hand they hold out),
    whether they take with `either_hand` (the one whose shoulder is nearer the object held
    out; False: with `arm` only), whether the person asks again when the robot lifts an
    object other than the one asked for (`corrects`, `human.correcting`), and whether they
    ask again when the robot's hand has not moved for `repeat_after_s` after the pointing
    ended (`repeats`, `human.repeating`)."""

    takes: bool = True
    reaction_s: float = 0.5
    arm: str = "right"
    either_hand: bool = True
    corrects: bool = True
    repeats: bool = True
    repeat_after_s: float = 6.0


class Receiver:
    """Steps the person's side of the handover on true positions; `changes` are the postures
    it adds to the person's timeline, `grip` the object the hand holds ("" for none). The
    body not reaching keeps its rest posture at a table whose top is `table_top` (m, person
    frame; see `rest_posture`). A person who asked for an object (`wanted`) takes only that
    one; "" takes whatever is held out."""

    def __init__(
        self,
        body: BodyDimensions,
        params: ReceivingParams,
        table_top: float | None = None,
        wanted: str = "",
    ):
        self._body, self._params, self._wanted = body, params, wanted
        self.arm = params.arm  # the arm it reaches with, once it reaches
        self._rest = rest_posture(body, table_top)
        self.state = Receiving.WAITING
        self.grip = ""
        self._offered: tuple[str, float] | None = None  # (object, since when it is still)
        self._last: dict[str, tuple[float, np.ndarray]] = {}
        self._first: dict[str, np.ndarray] = {}
        self._gripped_at = np.inf
        self._reach_for: tuple[float, np.ndarray] | None = None  # (from when, hand's point)
        self._aimed_at = np.zeros(3)  # the object's centre when the reach was aimed
        self._moved_since = math.inf  # since when the object has stood MOVED from there
        self._away = np.zeros(3)  # the unit direction the hand came from, from the object
        self._closed_at = np.zeros(3)  # where the hand closed
        self._hand_before: np.ndarray | None = None
        self._short_since = math.inf  # since when the hand has stopped out of grip

    @property
    def _reach(self) -> float:
        return REACH_SHARE * (self._body.upper_arm + self._body.forearm + self._body.hand / 2)

    def update(
        self,
        time: float,
        objects: dict[str, np.ndarray],
        hand: np.ndarray,
        gripper: Sequence[Capsule] = (),
        posture: np.ndarray | None = None,
        touching: frozenset[str] = frozenset(),
    ) -> list[tuple[float, np.ndarray]]:
        """Advance at `time` on the objects' centres, the middle of the hand it reaches with
        (`arm`) and the robot's `gripper`, all in the person frame, the person's `posture`
        now (PERSON_JOINTS order; the rest posture if None) and the objects the hand
        `touching` now; returns the postures to move to, as (time, posture) pairs (empty
        when nothing changes)."""
        if not self._params.takes or self.state is Receiving.DRAWN_IN:
            return []
        if self.state is Receiving.WAITING:
            posture = self._rest if posture is None else posture
            return self._watch(time, objects, gripper, posture)
        if self.state is Receiving.REACHING:
            name = self._offered[0]
            return self._reaching(time, objects[name], hand, gripper, posture, name in touching)
        if self.state is Receiving.HOLDING and time - self._gripped_at >= TUG_S:
            self.state = Receiving.TUGGING
            return [(time, self._posture(time, self._closed_at + TUG * self._away))]
        if self.state is Receiving.TUGGING and time - self._gripped_at >= TUG_S + DRAW_IN_S:
            self.state = Receiving.DRAWN_IN
            return [(time, self._posture(time, self._closed_at + DRAW_IN * self._away))]
        return []

    def _reaching(
        self,
        time: float,
        target: np.ndarray,
        hand: np.ndarray,
        gripper: Sequence[Capsule],
        posture: np.ndarray | None,
        touched: bool,
    ) -> list[tuple[float, np.ndarray]]:
        """Close the hand on the object at `target` if it got there (a hand that `touched` it
        stops where it is); aim again, for where the object is now, CORRECTION_S after it moved
        from where the reach was aimed, or a reaction time after the hand stopped out of grip
        (people correct a reach whose object has moved: Prablanc and Martin 1992,
        J. Neurophysiol. 67:455)."""
        since, point = self._reach_for
        before, self._hand_before = self._hand_before, hand
        arrived = np.linalg.norm(hand - point) <= ARRIVED
        stopped = (
            before is not None
            and time >= since + SETTLE_AFTER_S
            and np.linalg.norm(hand - before) <= SETTLED
        )
        if (arrived or stopped or touched) and np.linalg.norm(hand - target) <= GRIP_DISTANCE:
            self.state, self.grip, self._gripped_at = Receiving.HOLDING, self._offered[0], time
            self._closed_at = hand
            return [(time, posture)] if touched and posture is not None else []
        posture = self._rest if posture is None else posture
        if np.linalg.norm(target - self._aimed_at) <= MOVED:
            self._moved_since = math.inf
        else:
            self._moved_since = min(self._moved_since, time)
            if time - self._moved_since >= CORRECTION_S - 1e-9:
                # A move seen within the reaction time turns the reach it has not yet begun.
                return self._reach_for_object(max(time, since), target, gripper, posture)
        if not stopped:
            self._short_since = math.inf
            return []
        self._short_since = min(self._short_since, time)
        if time - self._short_since < self._params.reaction_s:
            return []
        return self._reach_for_object(time, target, gripper, posture)

    def _arms(self) -> tuple[str, ...]:
        """The arms it may take with, the preferred first."""
        other = "left" if self._params.arm == "right" else "right"
        return (self._params.arm, other) if self._params.either_hand else (self._params.arm,)

    def _nearest_arm(self, point: np.ndarray) -> tuple[str, float]:
        """The arm whose shoulder is nearest `point` (person frame) and how far it is (m)."""
        reaches = [(arm, float(np.linalg.norm(point - self._body.shoulder(arm))))
                   for arm in self._arms()]  # fmt: skip
        return min(reaches, key=lambda reach: reach[1])

    def _watch(self, time: float, objects: dict[str, np.ndarray], gripper, posture) -> list:
        still = None
        for name, point in objects.items():
            before = self._last.get(name)
            self._last[name] = (time, point)
            first = self._first.setdefault(name, point)
            if before is None or time <= before[0] or point[2] < first[2] + RAISED:
                continue
            if self._wanted and name != self._wanted:
                continue  # not what the person asked for
            speed = np.linalg.norm(point - before[1]) / (time - before[0])
            if speed < STILL_SPEED and self._nearest_arm(point)[1] < self._reach:
                still = name
        if still is None:
            self._offered = None
            return []
        if self._offered is None or self._offered[0] != still:
            self._offered = (still, time)
        if time - self._offered[1] < STILL_S:
            return []
        self.state = Receiving.REACHING
        return self._reach_for_object(time + self._params.reaction_s, objects[still], gripper,
                                      posture)  # fmt: skip

    def _reach_for_object(
        self, start: float, centre: np.ndarray, gripper: Sequence[Capsule], posture: np.ndarray
    ) -> list[tuple[float, np.ndarray]]:
        """Reach from `start` (s) for the object at `centre` with the arm nearer it, from the
        arm's angles in `posture`."""
        self.arm = self._nearest_arm(centre)[0]
        arm = posture[arm_joint_indices(self.arm)]
        reach = reach_point(self._body, self.arm, centre, gripper, arm)
        self._reach_for, self._hand_before, self._short_since = (start, reach), None, math.inf
        self._aimed_at, self._moved_since = centre, math.inf
        self._away = (reach - centre) / np.linalg.norm(reach - centre)
        return [(start, self._posture(start, reach))]

    def _posture(self, time: float, point: np.ndarray) -> np.ndarray:
        action = Action(REACHES[0], time, None, np.asarray(point, dtype=float), self.arm)
        return target_posture(self._body, action, self._rest)


def reach_point(
    body: BodyDimensions,
    arm: str,
    centre: np.ndarray,
    gripper: Sequence[Capsule] = (),
    start: np.ndarray | None = None,
) -> np.ndarray:
    """Where the hand's middle goes to take the object at `centre` (person frame): REACH_SHORT
    short of it, from the first side (TILTS_DEG, then TURNS_DEG, from straight at the
    shoulder) whose move there from the arm's `start` angles (the rest posture's if None)
    keeps the forearm and hand CLEAR of the robot's `gripper` and ends within GRIP_DISTANCE of
    the object (an object held near the shoulder asks the elbow past its limit, and the arm
    stopped there may end too far to close on it); else the clearest that ends within it;
    else the clearest."""
    if start is None:
        start = rest_posture(body)[arm_joint_indices(arm)]
    shoulder = body.shoulder(arm)
    toward = (shoulder - centre) / np.linalg.norm(shoulder - centre)
    heading = math.atan2(toward[1], toward[0])
    level = math.asin(float(np.clip(toward[2], -1.0, 1.0)))
    tried: list[tuple[bool, float, int, np.ndarray]] = []  # (grips, clearance, -order, point)
    for tilt in np.radians(TILTS_DEG):
        for turn in np.radians(TURNS_DEG):
            elevation, bearing = level + tilt, heading + turn
            flat = math.cos(elevation)
            side = [flat * math.cos(bearing), flat * math.sin(bearing), math.sin(elevation)]
            point = centre + REACH_SHORT * np.array(side)
            goal = _arm_goal(body, arm, point)
            clearance = _move_clearance(body, arm, start, goal, gripper)
            ends = arm_points(body, arm, goal)["hand"]
            grips = bool(np.linalg.norm(ends - centre) <= GRIP_DISTANCE)
            if clearance >= CLEAR and grips:
                return point
            tried.append((grips, clearance, -len(tried), point))
    return max(tried, key=lambda each: each[:3])[3]


def _arm_goal(body: BodyDimensions, arm: str, point: np.ndarray) -> np.ndarray:
    """The arm's joint angles the actor moves to for the hand's middle at `point`: within the
    joint limits (`target_posture`), where the hand may end short of the point."""
    return target_posture(body, Action(REACHES[0], 0.0, None, point, arm))[arm_joint_indices(arm)]


def path_clearance(
    body: BodyDimensions,
    arm: str,
    start: np.ndarray,
    point: np.ndarray,
    gripper: Sequence[Capsule],
) -> float:
    """m from the forearm and hand (axes, elbow to fingertips) to the gripper's capsules over
    the arm's move from joint angles `start` to the hand's middle at `point` (a straight line
    in joint space, as the actor moves, to the goal it moves to: within the joint limits, where
    an elbow folded past its limit ends the move elsewhere, along another way)."""
    return _move_clearance(body, arm, start, _arm_goal(body, arm, point), gripper)


def _move_clearance(
    body: BodyDimensions,
    arm: str,
    start: np.ndarray,
    goal: np.ndarray,
    gripper: Sequence[Capsule],
) -> float:
    """`path_clearance` over the move from joint angles `start` to `goal`."""
    if not gripper:
        return math.inf
    limbs = []
    for joints in arm_move_points(body, arm, start, goal, PATH_SAMPLES):
        limbs.append(_samples(joints["elbow"], joints["wrist"]))
        limbs.append(_samples(joints["wrist"], joints["tips"]))
    limb = np.concatenate(limbs)
    return min(float(cdist(limb, _samples(a, b)).min()) - radius for a, b, radius in gripper)


def _samples(start: np.ndarray, end: np.ndarray, spacing: float = 0.01) -> np.ndarray:
    """Points along a segment, `spacing` m apart or closer."""
    count = max(2, int(np.ceil(np.linalg.norm(end - start) / spacing)) + 1)
    return np.linspace(start, end, count)

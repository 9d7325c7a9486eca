"""The person taking the object (issue 10, the world side): once the robot holds an object out
within reach and still, the person reaches for it after a reaction time, closes the hand on it
when the hand gets there and, a moment later, draws it in: the tug a robot feels and lets go at
(a person does not wait to be told the gripper has opened).

The person is part of the world: it may know where the objects and the robot's fingers truly
are. Points here are in the person frame (`hsr_handover.station.world.person_pose`).
"""

from __future__ import annotations

import dataclasses
import enum

import numpy as np

from hsr_handover.human.behavior import REACHES, Action, target_posture
from hsr_handover.human.body import BodyDimensions

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
GRIP_DISTANCE = REACH_SHORT + 0.005
"""m from the hand's middle to the object's centre at which the hand closes on it: where it
arrives (closing earlier, the hand went on 2 cm into the robot's fingers)."""
TUG_S = 0.3  # s from closing the hand to the tug
TUG = 0.06
"""m the hand draws straight back toward the shoulder first: the tug a robot feels and lets
go at (drawing the object all the way in at once swung the hand into the robot's fingers)."""
DRAW_IN_S = 1.0  # s from the tug to drawing the object in
HOLD_POINT = np.array([0.32, -0.12, -0.05])
"""Where the person brings the object, from the receiving shoulder (m, person frame): in front
of the chest, a little toward the receiving side."""


class Receiving(enum.Enum):
    WAITING = "waiting"
    REACHING = "reaching"
    HOLDING = "holding"
    TUGGING = "tugging"
    DRAWN_IN = "drawn in"


@dataclasses.dataclass(frozen=True)
class ReceivingParams:
    """How this person takes an object: `takes` (False: never reaches, the robot must time
    out), the reaction time `reaction_s` (s) from the offer to the reach, and the `arm`."""

    takes: bool = True
    reaction_s: float = 0.5
    arm: str = "right"


class Receiver:
    """Steps the person's side of the handover on true positions; `changes` are the postures
    it adds to the person's timeline, `grip` the object the hand holds ("" for none)."""

    def __init__(self, body: BodyDimensions, params: ReceivingParams):
        self._body, self._params = body, params
        self.state = Receiving.WAITING
        self.grip = ""
        self._offered: tuple[str, float] | None = None  # (object, since when it is still)
        self._last: dict[str, tuple[float, np.ndarray]] = {}
        self._first: dict[str, np.ndarray] = {}
        self._gripped_at = np.inf

    @property
    def _reach(self) -> float:
        return REACH_SHARE * (self._body.upper_arm + self._body.forearm + self._body.hand / 2)

    def update(
        self,
        time: float,
        objects: dict[str, np.ndarray],
        hand: np.ndarray,
    ) -> list[tuple[float, np.ndarray]]:
        """Advance at `time` on the objects' centres and the hand's middle (person frame);
        returns the postures to move to, as (time, posture) pairs (empty when nothing
        changes)."""
        if not self._params.takes or self.state is Receiving.DRAWN_IN:
            return []
        if self.state is Receiving.WAITING:
            return self._watch(time, objects)
        if self.state is Receiving.REACHING:
            target = self._offered[0]
            if np.linalg.norm(objects[target] - hand) <= GRIP_DISTANCE:
                self.state, self.grip, self._gripped_at = Receiving.HOLDING, target, time
            return []
        shoulder = self._body.shoulder(self._params.arm)
        if self.state is Receiving.HOLDING and time - self._gripped_at >= TUG_S:
            self.state = Receiving.TUGGING
            back = (shoulder - hand) / np.linalg.norm(shoulder - hand)
            return [(time, self._posture(time, hand + TUG * back))]
        if self.state is Receiving.TUGGING and time - self._gripped_at >= TUG_S + DRAW_IN_S:
            self.state = Receiving.DRAWN_IN
            return [(time, self._posture(time, shoulder + HOLD_POINT))]
        return []

    def _watch(self, time: float, objects: dict[str, np.ndarray]) -> list:
        shoulder = self._body.shoulder(self._params.arm)
        still = None
        for name, point in objects.items():
            before = self._last.get(name)
            self._last[name] = (time, point)
            first = self._first.setdefault(name, point)
            if before is None or time <= before[0] or point[2] < first[2] + RAISED:
                continue
            speed = np.linalg.norm(point - before[1]) / (time - before[0])
            if speed < STILL_SPEED and np.linalg.norm(point - shoulder) < self._reach:
                still = name
        if still is None:
            self._offered = None
            return []
        if self._offered is None or self._offered[0] != still:
            self._offered = (still, time)
        if time - self._offered[1] < STILL_S:
            return []
        self.state = Receiving.REACHING
        start = time + self._params.reaction_s
        toward = shoulder - objects[still]
        reach = objects[still] + REACH_SHORT * toward / np.linalg.norm(toward)
        return [(start, self._posture(start, reach))]

    def _posture(self, time: float, point: np.ndarray) -> np.ndarray:
        action = Action(REACHES[0], time, None, np.asarray(point, dtype=float), self._params.arm)
        return target_posture(self._body, action)

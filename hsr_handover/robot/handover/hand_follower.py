"""Following the person's hand while presenting (paper 3.3: the robot brings the object to
the receiver's hand). A hand held out beyond `follow_beyond` and still for `offer_first_s`, or
nearer but still for `nudge_s`, with the object held out, has the object brought `offer` in
front of it; a hand that comes for the object while the robot moves toward it stops the arm
where it is. Where the object is then held out, beside the hand if the forearm leaves no room
in front of it, is the planner's (`planning.follow`)."""

from __future__ import annotations

import collections
import dataclasses
import enum
import math

import numpy as np

from hsr_handover.robot.handover.cycle_params import CycleParams
from hsr_handover.robot.handover.cycle_types import Percepts

PART_WAY = (0.5, 0.25)
"""Shares of the way from the palm to the aim in front of the hand, tried in turn where the arm
cannot reach the aim itself, for a hand that has waited near the object: the person judges it
out of reach, and any way nearer the hand is nearer their reach (a box held out 8 mm past a
seated person's reach stayed there for 12 s while every try at the hand itself found no
inverse kinematics). Not for a hand held out farther than `follow_beyond`: the person may yet
reach for the object where it is, and one who did as it set off part way, the robot's arm
hiding the hand, met it with the forearm."""


HAND_READINGS = 3
"""Decisions whose receiving-wrist readings the hand is taken as the median of: the detector
swaps the arms for a few frames, and a wrist read 40 cm off, on the hand at rest, for one
decision had the robot stop a follow it had just begun (the hand seemed to come for the
object). A hand that does come is seen a decision later."""


class FollowStep(enum.Enum):
    """What to do about the person's hand at one decision."""

    STOP = "stop"  # the followed hand comes for the object: hold it where it is
    STAY = "stay"  # reaching, waiting for less than `nudge_s`, or followed just now
    FOLLOW = "follow"  # bring the object to the hand, if the arm is not moving


class HandFollower:
    """Decides when to bring the object to the person's hand, and where to aim it.

    Its memory: when the object was first held out (`since`, s: the first decision's time
    if not given), the hand's last readings, where it came to rest and since when, when it
    last set off toward the hand and where the hand was then."""

    def __init__(self, params: CycleParams, since: float | None = None):
        self._params = params
        self._since = since
        self._hand_rest: tuple[np.ndarray, float] | None = None  # (where, since when)
        self._followed_at = -math.inf  # when it last tried to follow the hand
        self._followed_hand: np.ndarray | None = None  # where the hand was, as it was followed
        self._readings: collections.deque = collections.deque(maxlen=HAND_READINGS)

    def step(self, p: Percepts, following: bool) -> FollowStep:
        """This decision's step, with the hand and the palm seen in `p` (neither None);
        `following`: whether the arm is now on its way to the hand."""
        p = self._read(p)
        self._since = p.time if self._since is None else self._since
        self._note_rest(p)
        if self._coming(p, following):
            return FollowStep.STOP
        distance = float(np.linalg.norm(p.hand - p.palm))
        held_out = distance > self._params.follow_beyond
        if not ((held_out and self._waited(p) >= self._params.offer_first_s)
                or self._waiting_short(p)):  # fmt: skip
            return FollowStep.STAY
        if p.time - self._followed_at > self._params.follow_every_s:
            return FollowStep.FOLLOW
        return FollowStep.STAY

    def aims(self, p: Percepts) -> list[np.ndarray]:
        """Where to hold the object out (m, world), in order: `offer` in front of the hand
        toward the palm, then, for a hand that waited near the object, PART_WAY there from the
        palm. Noted as a try to follow the hand, as it is now."""
        p = self._read(p)
        self._followed_at, self._followed_hand = p.time, p.hand
        toward = (p.palm - p.hand) / float(np.linalg.norm(p.hand - p.palm))
        aim = p.hand + self._params.offer * toward
        far = float(np.linalg.norm(p.hand - p.palm)) > self._params.follow_beyond
        shares = () if far else PART_WAY
        return [aim] + [p.palm + share * (aim - p.palm) for share in shares]

    def _read(self, p: Percepts) -> Percepts:
        """`p` with the hand the median of the last HAND_READINGS decisions' readings (this
        one's taken once)."""
        if not self._readings or self._readings[-1][0] != p.time:
            self._readings.append((p.time, p.hand))
        hand = np.median([reading for _, reading in self._readings], axis=0)
        return dataclasses.replace(p, hand=hand)

    def _note_rest(self, p: Percepts) -> None:
        """Where the hand has rested, and since when: a hand first seen on its way out rests
        only once it has stopped."""
        rest = self._hand_rest
        if rest is None or float(np.linalg.norm(p.hand - rest[0])) > self._params.hand_still:
            self._hand_rest = (p.hand, p.time)

    def _coming(self, p: Percepts, following: bool) -> bool:
        """Whether the hand the robot is following has come over `coming` toward the palm: the
        person reaches for the object, aimed where it was, and following on would bring the
        fingers into the hand (a standing person's hand that waited 53 cm off reached as the
        robot set off toward it, and met the fingers 22 cm on)."""
        followed = self._followed_hand
        if followed is None or not following:
            return False
        toward = (p.palm - followed) / float(np.linalg.norm(followed - p.palm))
        return float((p.hand - followed) @ toward) > self._params.coming

    def _waited(self, p: Percepts) -> float:
        """s the hand has stayed where it came to rest with the object held out."""
        return p.time - max(self._hand_rest[1], self._since)

    def _waiting_short(self, p: Percepts) -> bool:
        """Whether the hand has waited still for `nudge_s` without coming for an object held
        farther than `offer` from it."""
        waited = self._waited(p) > self._params.nudge_s
        held_off = self._params.offer + self._params.hand_still
        return waited and float(np.linalg.norm(p.hand - p.palm)) > held_off

"""Presenting the object and letting go (paper 3.3): hold it out, bring it to a hand held out
(`hand_follower`), let go once the person holds it (`take`), or give up and keep it. A part of
`cycle.HandoverCycle`, whose state its handlers read and change."""

from __future__ import annotations

import numpy as np

from hsr_handover.robot.handover.cycle_types import Failure, Percepts, Phase
from hsr_handover.robot.handover.hand_follower import FollowStep, HandFollower
from hsr_handover.robot.handover.take import Emptied, TakeDetector


class Presenting:
    """The handover cycle's present and release phases."""

    def _start_presenting(self, p: Percepts) -> None:
        self._enter(Phase.PRESENT, p.time)
        self._seen_at = p.time
        self._take = TakeDetector(p.wrist_force, self._fetch.width, self._params)
        self._follower = HandFollower(self._params, p.time)

    def _present(self, p: Percepts) -> None:
        """Hold the object out and let go once the person holds it (`take`), bringing it to a
        hand held out (`hand_follower`), or give up."""
        if any(point is not None for point in (p.person, p.face, p.hand)):
            self._seen_at = p.time
        felt = self._take.feel(p, self._person)
        if felt.held:
            if not self._moving(p.time):
                self._let_go(p)
                return
            self._hold_still(p)  # held on the way to the hand: feel again standing still
        if felt.taken:
            self._let_go(p)  # the person has it, drawn out of the fingers or through them
            return
        if p.opening < self._params.held_opening:
            self._empty_fingers(p)
            return
        if self._given_up(p) or self._going_on(p):
            return
        # A hand near the object is not yet holding it (a hand held out, a person who changes
        # their mind): the robot lets go only when it feels the object taken, above.
        if p.hand is not None and p.palm is not None:
            self._follow_hand(p)

    def _given_up(self, p: Percepts) -> bool:
        """Whether the robot gives up presenting: no hand came in `wait_s`, or the person has
        been out of sight for `lost_s` (it keeps the object)."""
        params = self._params
        if p.time - self._since > params.wait_s:
            reason = f"no hand came for the object in {params.wait_s:.0f} s; holding it"
            self._fail_and_retreat(p, Failure.TIMEOUT, reason, holding=True)
            return True
        if p.time - self._seen_at > params.lost_s:
            reason = f"the person was out of sight for {params.lost_s:.0f} s; holding the object"
            self._fail_and_retreat(p, Failure.PERSON_WITHDREW, reason, holding=True)
            return True
        return False

    def _going_on(self, p: Percepts) -> bool:
        """Whether the robot, having held the object out where a carry stopped or crawled
        (`cycle._offered`), carries it on to the handover point: `go_on_s` on, the hand is seen,
        and farther than `reach` from it. Tried once; with no way found it stays presenting."""
        fetch = self._fetch
        if not fetch.held_out_early or fetch.went_on or p.time - self._since < self._params.go_on_s:
            return False
        if p.hand is None or p.palm is None:
            return False  # a hand at the object is often hidden by the robot's own arm
        if np.linalg.norm(p.hand - p.palm) <= self._params.reach:
            return False
        if self._moving(p.time):
            return False
        fetch.went_on = True
        planned = self.planner.carry(p.q, fetch.held)
        self.record.planning_s += planned.plan_seconds
        if not planned.ok:
            return False
        self.view = self.view.updated(planned.view)
        self._set_off(planned, p)
        return True

    def _empty_fingers(self, p: Percepts) -> None:
        emptied = self._take.emptied(p, self._fetch.start)
        if emptied is Emptied.JUST_NOW:
            self._hold_still(p)
        elif emptied is Emptied.TAKEN:
            self._let_go(p)
        elif emptied is Emptied.DROPPED:
            self._dropped(p)
        elif emptied is Emptied.UNSEEN:
            # Withdrawn, the hand no longer hides it: seen up in the person's hand on the way
            # back (`cycle._retreat`), it was taken.
            self._looking_back = True
            self._dropped(p)

    def _follow_hand(self, p: Percepts) -> None:
        step = self._follower.step(p, following=self._motions.running_name == "follow")
        if step is FollowStep.STOP:
            self._hold_still(p)  # the person reaches for it: hold it where it is
        elif step is FollowStep.FOLLOW and not self._moving(p.time):
            self._follow(p)

    def _follow(self, p: Percepts) -> None:
        """Re-target state to state (ruckig) to hold the object out at the hand, or as near
        it as the arm reaches (`HandFollower.aims`)."""
        for aim in self._follower.aims(p):
            planned = self.planner.follow(p.q, np.zeros_like(p.q), aim, self._fetch.held)
            self.record.planning_s += planned.plan_seconds
            if planned.ok:
                self._motions.play(planned.motions)
                self.view = self.view.updated(planned.view)
                self._moving(p.time)
                return

    def _let_go(self, p: Percepts) -> None:
        self._gripper = min(self._params.open, p.opening + self._params.let_go)
        self._hold_still(p)
        self._enter(Phase.RELEASE, p.time)

    def _release(self, p: Percepts) -> None:
        settle_s = self._params.settle_s
        opened = p.opening >= self._gripper - self._params.held_opening
        if p.time - self._since < settle_s or not (opened or p.time - self._since > 3 * settle_s):
            return
        self._retreat_then(p, Phase.DONE, None, "", holding=False)

"""The perceiving-acting cycle as a plain state machine (paper 3.3): watch, recognise
the request, plan, approach, grasp, lift, carry to the handover point (checked on the way
against the person as seen now, and planned again from where it stops if they have moved into
it; presented where it is once it stops within their reach, `offer_watch`, and carried on if
no hand comes), wait for the person's hand, release when the person holds the object, retreat.
Failures end it with a reason.

It decides from percepts only (`Percepts`: the joint sensors, the gripper's measured opening,
the intent estimator's target, the object as the camera sees it, the person's hand from the
skeleton) by the thresholds of `CycleParams`, and asks a `CyclePlanner` for motions. Each
phase has one handler (`HandoverCycle._HANDLERS`): those up to the carry and the retreat here,
presenting and releasing in `presenting` (where `take.TakeDetector` feels the object taken and
`hand_follower.HandFollower` brings it to the person's hand), and putting back in `put_back`: a
person who asks for another object while the robot lifts or carries one (the intent
estimator's correction) has that object put back where it stood and the other fetched, once.
It knows nothing of Drake systems: the `HandoverSupervisor` steps it and follows the motion it
gives.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable
from typing import ClassVar

import numpy as np

from hsr_handover.robot.handover.cycle_params import CycleParams
from hsr_handover.robot.handover.cycle_types import (
    CyclePlanner,
    CycleRecord,
    Failure,
    Fetch,
    Percepts,
    Phase,
)
from hsr_handover.robot.handover.hand_follower import HandFollower
from hsr_handover.robot.handover.motion_queue import MotionQueue
from hsr_handover.robot.handover.offer_watch import OfferWatch
from hsr_handover.robot.handover.presenting import Presenting
from hsr_handover.robot.handover.put_back import PutBack, PuttingBack
from hsr_handover.robot.handover.take import TakeDetector
from hsr_handover.robot.planning.plan import Motion, Plan
from hsr_handover.robot.planning.plan_view import PlanView

AHEAD_STEP_S = 0.05
"""s between the configurations of a carry's rest checked against the person: the hand moves
at most a few centimetres in it, and the person's capsules are PERSON_MARGIN (5 cm) wider
than the skeleton."""


class HandoverCycle(PuttingBack, Presenting):
    """Steps the cycle on percepts; `command(time)` gives what the robot should do then.

    It asks `planner` for its motions: whoever steps it may give it a planner for newer
    percepts before each step. A copy (Drake copies a system's state with each context) shares
    the planner, the params and the motions, which are never changed once made, and copies the
    rest."""

    def __init__(
        self,
        planner: CyclePlanner,
        params: CycleParams = CycleParams(),  # noqa: B008 (frozen)
    ):
        self.planner = planner
        self._params = params
        self.record = CycleRecord()
        self.view = PlanView()  # what the plans so far show in the replay
        self._motions = MotionQueue()
        self._gripper = params.open
        self._fetch = Fetch()
        self._person: np.ndarray | None = None  # the point on the person last seen
        self._since = 0.0  # when the current phase began
        self._blocked: float | None = None  # when the plan now wanted first found no way
        self._retry_at = -math.inf  # when to try that plan again
        self._after_retreat: tuple[Phase, Failure | None, str] = (Phase.DONE, None, "")
        self._putting: PutBack | None = None  # putting an object back, once asked for another
        self._seen_at = 0.0  # when the person was last seen, presenting
        self._take = TakeDetector(None, math.inf, params)  # made afresh as it presents
        self._looking_back = False  # retreating from fingers emptied with the object unseen
        self._follower = HandFollower(params)  # made afresh as it presents
        self._offer_watch = OfferWatch(params)  # made afresh as it sets off with an object

    def __deepcopy__(self, memo: dict) -> HandoverCycle:
        clone = copy.copy(self)
        clone.record = copy.deepcopy(self.record, memo)
        clone._motions = copy.deepcopy(self._motions, memo)
        clone._fetch = copy.copy(self._fetch)
        clone._take = copy.copy(self._take)
        clone._follower = copy.copy(self._follower)
        clone._offer_watch = copy.copy(self._offer_watch)
        return clone

    # What to do now -------------------------------------------------------------------------

    def command(self, time: float) -> tuple[np.ndarray | None, np.ndarray | None, float]:
        """(positions, velocities, gripper opening) to command at `time`; positions None while
        there is nothing to follow (hold where it stands)."""
        q, v = self._motions.command(time)
        return q, v, self._gripper

    @property
    def started(self) -> tuple[tuple[float, Motion], ...]:
        """Every motion it has started, with when (s), in order."""
        return tuple((running.start, running.motion) for running in self._motions.started)

    @property
    def gripper(self) -> float:
        """The gripper opening (m) to command now."""
        return self._gripper

    def gaze(self) -> np.ndarray | None:
        """Where to look (m, world): the object until it is lifted, then the person; None
        while watching (the head is the watcher's), unless a grasp of the object asked for
        found no way: then the object, so the table before it comes into view (watching a
        standing person, the head is raised and the table's near edge, unseen, runs on toward
        the robot and keeps its base from the object)."""
        if self.record.phase is Phase.WATCH:
            return self._fetch.start if self._blocked is not None else None
        on_object = (Phase.APPROACH, Phase.GRASP, Phase.LIFT)
        if self.record.phase in on_object and self._fetch.turned is None:
            return self._fetch.start
        return self._person

    def seeing(self) -> str | None:
        """The object asked for, while the robot has not seen it since (watching a standing
        person's face, the table is below the camera's view): the head turns to where it was
        last seen, and the grasp is planned once the camera shows it, or after `seek_s`
        without (then the cycle goes on without the object's start to check the lift
        against)."""
        watching = self.record.phase is Phase.WATCH and self.record.target is not None
        return self.record.target if watching and self._fetch.start is None else None

    @classmethod
    def handled_phases(cls) -> frozenset[Phase]:
        """The phases the cycle acts in: all but those it ends in."""
        return frozenset(cls._HANDLERS)

    # Stepping ---------------------------------------------------------------------------------

    def wait_until(self, time: float) -> None:
        """Plan nothing before `time` (s): the robot is moving on a command that is not the
        cycle's (the supervisor's raise to where it watches from), and a plan starts at rest
        where it stands. A request recognised meanwhile is recorded when it is."""
        self._retry_at = max(self._retry_at, time)

    def step(self, p: Percepts) -> CycleRecord:
        """Advance on the latest percepts; returns the cycle's record."""
        self._person = p.person if p.person is not None else self._person
        handler = self._HANDLERS.get(self.record.phase)
        if handler is not None:
            handler(self, p)
        return self.record

    def _watch(self, p: Percepts) -> None:
        """Record the request once recognised, then plan the grasp (tried again while it finds
        no way), once the camera has seen the object or has looked for it for `seek_s`."""
        fetch = self._fetch
        if self.record.target is None:
            if p.target is None:
                return
            self.record.target, self.record.recognised_time = p.target, p.time
            fetch.start = p.object_seen
        if p.time < self._retry_at:
            return
        fetch.start = fetch.start if p.object_seen is None else p.object_seen
        if fetch.start is None:  # out of view: the head turns to it first (`seeing`)
            seek_until = p.time + self._params.seek_s
            fetch.seek_until = seek_until if fetch.seek_until is None else fetch.seek_until
            if p.time < fetch.seek_until:
                return
        planned = self._plan(self.planner.grasp(self.record.target, p.q), p)
        if planned is None:
            return
        *reach, lift = planned.motions
        fetch.lift, fetch.held = lift, planned.held
        self._gripper = self._params.open
        self._enter(Phase.APPROACH, p.time)
        self._motions.play(reach)

    def _approach(self, p: Percepts) -> None:
        if self._moving(p.time):
            return
        self._gripper = self._params.closed
        self._enter(Phase.GRASP, p.time)

    def _grasp(self, p: Percepts) -> None:
        if p.time - self._since < self._params.settle_s:
            return
        if p.opening < self._params.held_opening:
            self._fail_and_retreat(p, Failure.GRASP_MISSED, "the gripper closed on nothing")
            return
        self._fetch.width = p.opening
        self._enter(Phase.LIFT, p.time)
        self._motions.play([self._fetch.lift])

    def _lift(self, p: Percepts) -> None:
        if self._dropped(p) or self._moving(p.time):
            return
        if self._fetch.turned is None:
            start, seen = self._fetch.start, p.object_seen
            if start is not None and seen is not None and seen[2] - start[2] < self._params.rise:
                reason = f"the object rose {100 * (seen[2] - start[2]):.1f} cm with the hand"
                self._fail_and_retreat(p, Failure.GRASP_MISSED, reason)
                return
            self._fetch.turned = p.time  # the person in view again before planning the way there
        if self._corrected(p):
            return
        if p.time - self._fetch.turned < self._params.look_s or p.time < self._retry_at:
            return
        self._plan_carry(p)

    def _plan_carry(self, p: Percepts) -> None:
        """Plan the carry from where the robot stands and set off (tried again while it finds
        no way: `_plan`)."""
        planned = self._plan(self.planner.carry(p.q, self._fetch.held), p, holding=True)
        if planned is not None:
            if self.record.phase is Phase.LIFT:
                self._offer_watch = OfferWatch(self._params)
            self._set_off(planned, p)

    def _set_off(self, planned: Plan, p: Percepts) -> None:
        """Carry the object along the `planned` carry, from now."""
        self.record.receiving = planned.receiving
        self._fetch.stopped, self._fetch.checked = False, p.time
        self._enter(Phase.CARRY, p.time)
        self._motions.play(planned.motions)

    def _carry(self, p: Percepts) -> None:
        if p.opening < self._params.held_opening:
            # Taken on the way or dropped: presenting, the robot holds still and the camera
            # tells (a hand held out beside the carry's slow end can take the object).
            self._start_presenting(p)
            self._empty_fingers(p)
            return
        if self._corrected(p):
            return
        if self._offered(p):
            self._hold_still(p)
            self._start_presenting(p)
            self._fetch.held_out_early = True
            return
        if self._moving(p.time):
            self._check_way(p)
        elif not self._fetch.stopped:
            self._start_presenting(p)
        elif p.time >= self._retry_at:
            self._plan_carry(p)

    def _offered(self, p: Percepts) -> bool:
        """Whether the carry, stopped or crawling, holds the object out within the person's
        reach: the person may reach for it there, and going on would meet the hand. Once per
        object: a presentation no hand came to goes on to the handover point (`presenting`)."""
        if self._fetch.held_out_early or p.palm is None:
            return False
        return self._offer_watch.held_out(p.time, p.palm) and self.planner.person_reaches(p.palm)

    def _check_way(self, p: Percepts) -> None:
        """Every `recheck_s`, the carry still to go against the person as seen now: one that
        comes within `carry_clear` of them stops where it is, to be planned again. Where the
        robot already stands deeper than that, the way may come as deep, less
        `carry_clear_slack`: the robot cannot stand inside a person without touching them, so
        such a percept is its own hand or the object it holds, in front of the camera, taken
        for the person's (a keypoint lifted onto what is nearer at its pixel)."""
        fetch, params = self._fetch, self._params
        if p.time - fetch.checked < params.recheck_s:
            return
        fetch.checked = p.time
        here = self.planner.person_clearance([p.q], fetch.held, params.carry_clear)
        bound = min(params.carry_clear, here - params.carry_clear_slack)
        ahead = self._motions.still_to_play(p.time, AHEAD_STEP_S)
        clearance = self.planner.person_clearance(ahead, fetch.held, bound)
        if clearance >= bound:
            return
        fetch.carried += tuple(self._motions.played_so_far("carry", p.time))
        fetch.stopped = True
        self._hold_still(p)

    def _retreat(self, p: Percepts) -> None:
        if self._looking_back and self._take.seen_up(p, self._fetch.start):
            self._looking_back = False
            self._let_go(p)  # in the person's hand, which the robot's own had hidden
            return
        if self._moving(p.time):
            return
        phase, failure, reason = self._after_retreat
        self._finish(phase, failure, reason, p.time)

    # Helpers ----------------------------------------------------------------------------------

    def _plan(self, planned: Plan, p: Percepts, holding: bool = False) -> Plan | None:
        """The motions planned, or None: to be tried again after `retry_every_s`, or, once the
        plan has found no way for `patience_s`, failed as unreachable."""
        self.record.planning_s += planned.plan_seconds
        if planned.ok:
            self._blocked = None
            self.view = self.view.updated(planned.view)
            return planned
        self._blocked = p.time if self._blocked is None else self._blocked
        if p.time - self._blocked < self._params.patience_s:
            self._retry_at = p.time + self._params.retry_every_s
            return None
        reason = f"{planned.reason} (tried for {p.time - self._blocked:.0f} s)"
        self._fail_and_retreat(p, Failure.UNREACHABLE, reason, holding=holding)
        return None

    def _moving(self, time: float) -> bool:
        """Whether a motion is still under way at `time`; starts the next queued one when the
        last has ended (the lift with the gripper closed)."""
        if self._motions.advance(time) == "lift":
            self._gripper = self._params.closed
        return self._motions.running is not None

    def _hold_still(self, p: Percepts) -> None:
        """Drop any motion and stand where the joints are."""
        self._motions.stand_still(p.q)

    def _dropped(self, p: Percepts) -> bool:
        if p.opening >= self._params.held_opening:
            return False
        self._fail_and_retreat(p, Failure.DROPPED, "the gripper closed: the object slipped out")
        return True

    def _fail_and_retreat(
        self, p: Percepts, failure: Failure, reason: str, holding: bool = False
    ) -> None:
        if not holding:
            self._gripper = self._params.open
        self._retreat_then(p, Phase.FAILED, failure, reason, holding)

    def _retreat_then(
        self, p: Percepts, phase: Phase, failure: Failure | None, reason: str, holding: bool
    ) -> None:
        """Retreat to the ready posture, then end in `phase`; end there at once if no retreat
        can be planned (the robot then stands where it is)."""
        self._hold_still(p)
        self._after_retreat = (phase, failure, reason)
        # Known now, not only once folded: a run that ends mid-retreat still says why.
        self.record.failure, self.record.reason = failure, reason
        held, let_go = (self._fetch.held, None) if holding else (None, self._fetch.held)
        planned = self.planner.retreat(p.q, held, let_go)
        self.record.planning_s += planned.plan_seconds
        if not planned.ok:
            self._finish(phase, failure, reason, p.time)
            return
        self._enter(Phase.RETREAT, p.time)
        self._motions.play(planned.motions)
        self.view = self.view.updated(planned.view)

    def _finish(self, phase: Phase, failure: Failure | None, reason: str, time: float) -> None:
        self.record.failure, self.record.reason = failure, reason
        self._enter(phase, time)

    def _enter(self, phase: Phase, time: float) -> None:
        self.record.phase, self._since = phase, time
        self.record.phase_times.setdefault(phase.value, time)

    # Dispatch: built once, of plain functions, so that a copy steps itself -------------------

    _HANDLERS: ClassVar[dict[Phase, Callable[[HandoverCycle, Percepts], None]]] = {
        Phase.WATCH: _watch, Phase.APPROACH: _approach, Phase.GRASP: _grasp, Phase.LIFT: _lift,
        Phase.CARRY: _carry, Phase.PUT_BACK: PuttingBack._put_back,
        Phase.PRESENT: Presenting._present, Phase.RELEASE: Presenting._release,
        Phase.RETREAT: _retreat,
    }  # fmt: skip

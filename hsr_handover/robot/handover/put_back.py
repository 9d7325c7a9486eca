"""Putting an object back, within the perceiving-acting cycle (paper 3.3): the person asked
for another object while the robot lifted or carried this one. Standing still, the robot plans
the way back (`PLAN`), goes back over the object's place and lowers it there (`LOWER`), opens
the fingers (`OPEN`), backs the hand straight off it (`LEAVE`), and then fetches the object
asked for. The steps follow one another only as `PutBack.advanced` has them."""

from __future__ import annotations

import dataclasses
import enum
from collections.abc import Callable
from typing import ClassVar

import numpy as np

from hsr_handover.robot.handover.cycle_types import Fetch, Percepts, Phase


class PutBackStep(enum.Enum):
    PLAN = "plan"  # standing still, holding the object: to plan the way back
    LOWER = "lower"  # holding it, back over its place and down onto it
    OPEN = "open"  # the fingers opening on the object put down
    LEAVE = "leave"  # the hand backing straight off it

    @property
    def holding(self) -> bool:
        """Whether the object is still in the hand (fingers closing on nothing: dropped)."""
        return self in (PutBackStep.PLAN, PutBackStep.LOWER)


_NEXT = {
    PutBackStep.PLAN: PutBackStep.LOWER,
    PutBackStep.LOWER: PutBackStep.OPEN,
    PutBackStep.OPEN: PutBackStep.LEAVE,
}


@dataclasses.dataclass(frozen=True)
class PutBack:
    """A put-back under way: the object to fetch once it is done (`next_target`), the way the
    robot carried the object it puts back (`came`: configurations, none if it had not set off),
    its `step` and when that step began (`since`, s)."""

    next_target: str
    came: list[np.ndarray]
    since: float
    step: PutBackStep = PutBackStep.PLAN

    def advanced(self, time: float) -> PutBack:
        """The put-back at its next step, begun at `time` (s). After `LEAVE` (or an `OPEN`
        with no way straight off the object) there is none: the robot fetches the next
        object."""
        if self.step not in _NEXT:
            raise ValueError(f"no step after {self.step.value}: the robot fetches the next object")
        return dataclasses.replace(self, step=_NEXT[self.step], since=time)


class PuttingBack:
    """The handover cycle's put-back phase (a part of `cycle.HandoverCycle`, whose state its
    handlers read and change): heed a correction, then each `PutBackStep` in turn."""

    def _corrected(self, p: Percepts) -> bool:
        """Whether the person has asked for another object than the one lifted (heeded once
        per cycle): the robot stands still, puts the object back and then fetches that one."""
        asked = p.correction
        if asked is None or asked == self.record.target or self.record.first_target is not None:
            return False
        self.record.first_target, self.record.corrected_time = self.record.target, p.time
        came = [*self._fetch.carried, *self._motions.played_so_far("carry", p.time)]
        self._putting = PutBack(asked, came, p.time)
        self._hold_still(p)
        self._enter(Phase.PUT_BACK, p.time)
        return True

    def _put_back(self, p: Percepts) -> None:
        """Back over the object's place and down (`planner.put_back`), open, back off it and
        fetch the object the person asked for: each `PutBackStep` once the last one's motions
        are over."""
        holding = self._putting.step.holding
        if (holding and self._dropped(p)) or self._moving(p.time):
            return
        self._PUT_BACK_STEPS[self._putting.step](self, p)

    def _plan_way_back(self, p: Percepts) -> None:
        if p.time < self._retry_at:
            return
        lift = self._fetch.lift
        lifted = lift.state(lift.duration)[0]
        put_back = self.planner.put_back(p.q, self._fetch.held, lifted, self._putting.came)
        planned = self._plan(put_back, p, holding=True)
        if planned is not None:
            self._motions.play(planned.motions)
            self._putting = self._putting.advanced(p.time)

    def _put_down(self, p: Percepts) -> None:
        """Back on its place: the fingers open."""
        self._gripper = self._params.open
        self._putting = self._putting.advanced(p.time)

    def _leave_once_open(self, p: Percepts) -> None:
        """The object is back where it stood and let go of: the hand backs straight off it
        (the next grasp is planned from there, not from the arm stowed), or, with no way
        straight back, the robot retreats; then it fetches the next object."""
        if p.time - self._putting.since < self._params.settle_s:
            return
        planned = self.planner.back_off(p.q, self._fetch.held)
        self.record.planning_s += planned.plan_seconds
        if planned.ok:
            self._motions.play(planned.motions)
            self._putting = self._putting.advanced(p.time)
            return
        self._retreat_then(p, Phase.WATCH, None, "", holding=False)
        self._fetch_next()

    def _left(self, p: Percepts) -> None:
        self._fetch_next(p.time)

    def _fetch_next(self, watch_from: float | None = None) -> None:
        """Asked for the next object: watch (`_watch` plans its grasp), at once from
        `watch_from` (s), else once the retreat under way is over."""
        self.record.target, self._putting = self._putting.next_target, None
        self._fetch = Fetch()
        if watch_from is not None:
            self._enter(Phase.WATCH, watch_from)

    _PUT_BACK_STEPS: ClassVar[dict[PutBackStep, Callable[[PuttingBack, Percepts], None]]] = {
        PutBackStep.PLAN: _plan_way_back, PutBackStep.LOWER: _put_down,
        PutBackStep.OPEN: _leave_once_open, PutBackStep.LEAVE: _left,
    }  # fmt: skip

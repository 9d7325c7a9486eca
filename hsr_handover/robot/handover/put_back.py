"""Putting an object back, within the perceiving-acting cycle (paper 3.3): the person asked
for another object while the robot lifted or carried this one. Standing still, the robot plans
the way back (`PLAN`), goes back over the object's place and lowers it there (`LOWER`), opens
the fingers (`OPEN`), backs the hand straight off it (`LEAVE`), and then fetches the object
asked for. The steps follow one another only as `PutBack.advanced` has them."""

from __future__ import annotations

import dataclasses
import enum

import numpy as np


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

"""HumanActor: the scripted person as a Drake system."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from pydrake.systems.framework import BasicVector, Context, LeafSystem

from hsr_handover.human.behavior import PostureTimeline
from hsr_handover.human.body import PERSON_JOINTS


class HumanActor(LeafSystem):
    """Turns the person's behaviour timeline into desired joint states for the plant's PD.

    Output `person_desired_state`: [q; v] of the person's actuated joints, ordered as
    `joint_order` (the plant's actuator order for the person). A function of time only, so the
    system has no state and no inputs.
    """

    def __init__(self, timeline: PostureTimeline, joint_order: Sequence[str]):
        super().__init__()
        unknown = [name for name in joint_order if name not in PERSON_JOINTS]
        if unknown:
            raise ValueError(f"joint_order: expected names from PERSON_JOINTS, got {unknown}")
        self._timeline = timeline
        self._order = np.array([PERSON_JOINTS.index(name) for name in joint_order])
        self.DeclareVectorOutputPort(
            "person_desired_state",
            2 * len(self._order),
            self._calc_desired_state,
            prerequisites_of_calc={self.time_ticket()},
        )

    def _calc_desired_state(self, context: Context, output: BasicVector) -> None:
        q, v = self._timeline.evaluate(context.get_time())
        output.SetFromVector(np.concatenate([q[self._order], v[self._order]]))

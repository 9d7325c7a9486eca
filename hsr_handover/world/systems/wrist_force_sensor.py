"""WristForceSensor: the HSR's 6-axis force-torque sensor between the wrist and the hand.

The real HSR carries one there; the robot uses it to feel a person take what it holds out, as
people feel a handover by the load shifting (Chan et al. 2013). In the plant it is the reaction
at the fixed joint that mounts the hand on the wrist (`hsr.WRIST_SENSOR_JOINT`).
"""

from __future__ import annotations

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.multibody.math import SpatialForce
from pydrake.systems.framework import BasicVector, Context, LeafSystem


class WristForceSensor(LeafSystem):
    """Input `reaction_forces` (the plant's: on each joint's child body, at and in the joint's
    child frame); output `wrench` [torque; force] (N m, N) that the hand, with what it holds,
    exerts on the wrist, at and in the hand's mounting frame: the joint with index
    `joint_index`'s child frame."""

    def __init__(self, joint_index: int):
        super().__init__()
        self._joint = int(joint_index)
        self._reactions = self.DeclareAbstractInputPort(
            "reaction_forces", AbstractValue.Make([SpatialForce()])
        )
        self.DeclareVectorOutputPort("wrench", 6, self._calc_wrench)

    def _calc_wrench(self, context: Context, output: BasicVector) -> None:
        on_hand = self._reactions.Eval(context)[self._joint]
        # Equal and opposite: what the wrist feels is what it does to the hand, reversed.
        output.SetFromVector(-np.concatenate([on_hand.rotational(), on_hand.translational()]))

"""HumanActor on its own context: its output port carries the timeline in the plant's order."""

from __future__ import annotations

import numpy as np
import pytest
from pydrake.math import RigidTransform

from hsr_handover.human.behavior import Action, PostureTimeline, posture_changes
from hsr_handover.human.body import PERSON_JOINTS, BodyDimensions
from hsr_handover.human.receiving import Receiver, ReceivingParams
from hsr_handover.systems.human_actor import HumanActor, WorldBodies

BODY = BodyDimensions.from_height(1.80, seated=False)


def _timeline() -> PostureTimeline:
    actions = [Action("point_at", 0.5, 2.0, np.array([1.0, 0.2, 0.9]), "left")]
    return PostureTimeline(posture_changes(BODY, actions))


def test_output_is_the_timeline_permuted_into_joint_order():
    timeline = _timeline()
    order = list(reversed(PERSON_JOINTS))
    actor = HumanActor(timeline, order)
    context = actor.CreateDefaultContext()
    port = actor.GetOutputPort("person_desired_state")
    assert port.size() == 2 * len(PERSON_JOINTS)
    for time in (0.0, 0.7, 1.1, 2.3, 5.0):
        context.SetTime(time)
        q, v = timeline.evaluate(time)
        index = [PERSON_JOINTS.index(name) for name in order]
        np.testing.assert_allclose(port.Eval(context), np.concatenate([q[index], v[index]]))
    context.SetTime(1.0)
    assert np.abs(port.Eval(context)[len(order) :]).max() > 0.1  # moving mid-gesture


def test_unknown_joint_names_are_rejected():
    with pytest.raises(ValueError, match="joint_order"):
        HumanActor(_timeline(), ["r_elbow", "knee"])


def test_a_copied_state_has_its_own_receiver():
    """Drake copies the state at every update: the person's side of a handover in one copy
    must not leak into another (the timeline, never changed once made, is shared)."""
    world = WorldBodies(hand=0, hand_middle=0.09, objects={}, X_WP=RigidTransform())
    actor = HumanActor(_timeline(), PERSON_JOINTS, Receiver(BODY, ReceivingParams()), world)
    context = actor.CreateDefaultContext()
    copied = context.Clone()
    copied.get_mutable_abstract_state(0).get_mutable_value().receiver.grip = "cup"
    assert actor.GetOutputPort("grip").Eval(copied) == "cup"
    assert actor.GetOutputPort("grip").Eval(context) == ""

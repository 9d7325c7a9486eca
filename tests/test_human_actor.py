"""HumanActor on its own context: its output port carries the timeline in the plant's order."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.human.behavior import Action, PostureTimeline, posture_changes
from hsr_handover.human.body import PERSON_JOINTS, BodyDimensions
from hsr_handover.systems.human_actor import HumanActor

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

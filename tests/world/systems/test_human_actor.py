"""HumanActor on its own context: its output port carries the timeline in the plant's order."""

from __future__ import annotations

import numpy as np
import pytest
from pydrake.math import RigidTransform
from pydrake.systems.analysis import Simulator

from hsr_handover.world.person.behavior import Action, PostureTimeline, posture_changes
from hsr_handover.world.person.body import PERSON_JOINTS, BodyDimensions
from hsr_handover.world.person.correcting import Corrector
from hsr_handover.world.person.receiving import Receiver, ReceivingParams
from hsr_handover.world.person.repeating import Repeater
from hsr_handover.world.systems.human_actor import HumanActor, WorldBodies

BODY = BodyDimensions.from_height(1.80, seated=False)


HANDS = {"right": 0, "left": 0}  # both hands the one body here


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
    world = WorldBodies(
        hands={"right": 0, "left": 0}, hand_middle=0.09, objects={}, X_WP=RigidTransform()
    )
    actor = HumanActor(_timeline(), PERSON_JOINTS, Receiver(BODY, ReceivingParams()), world)
    context = actor.CreateDefaultContext()
    copied = context.Clone()
    actor.acting(copied).receiver.grip = "cup"
    assert actor.GetOutputPort("grip").Eval(copied) == "cup"
    assert actor.GetOutputPort("grip").Eval(context) == ""


def test_a_corrector_without_a_receiver_is_rejected():
    corrector = Corrector("cup", [], 0.5)
    with pytest.raises(ValueError, match="corrector"):
        HumanActor(_timeline(), PERSON_JOINTS, corrector=corrector)


def test_the_person_asks_again_when_the_robot_lifts_another_object():
    """On its own context, the plant's body poses fixed: the red cup rises off the table, and
    the actor's output goes over to the request made again, `reaction_s` later."""
    table = {"red": [0.8, -0.2, 0.75], "blue": [0.8, 0.2, 0.75]}
    again = PostureTimeline([(0.0, np.zeros(len(PERSON_JOINTS)))])  # only its first posture
    pointing = _timeline().evaluate(3.0)[0]
    corrector = Corrector("blue", [(0.0, pointing)], reaction_s=0.5)
    world = WorldBodies(hands=HANDS, hand_middle=0.09, objects={"red": 1, "blue": 2},
                        X_WP=RigidTransform())  # fmt: skip
    receiver = Receiver(BODY, ReceivingParams(), wanted="blue")
    actor = HumanActor(again, PERSON_JOINTS, receiver, world, corrector)
    context = actor.CreateDefaultContext()
    poses = actor.GetInputPort("body_poses")

    def place(red_height: float) -> None:
        red = np.add(table["red"], [0.0, 0.0, red_height])
        poses.FixValue(context, [RigidTransform(), RigidTransform(red),
                                 RigidTransform(table["blue"])])  # fmt: skip

    place(0.0)
    simulator = Simulator(actor, context)
    simulator.AdvanceTo(0.5)
    output = actor.GetOutputPort("person_desired_state")
    np.testing.assert_allclose(output.Eval(context)[: len(PERSON_JOINTS)], 0.0)
    place(0.1)  # the robot lifts the red cup
    simulator.AdvanceTo(3.0)
    np.testing.assert_allclose(output.Eval(context)[: len(PERSON_JOINTS)], pointing, atol=1e-6)
    state = actor.acting(context)
    assert state.corrector.corrected_at == pytest.approx(0.55, abs=0.051)


@pytest.mark.parametrize("moves", [False, True])
def test_the_person_asks_again_when_the_robots_hand_stays_still(moves: bool):
    """On its own context, the plant's body poses fixed: the robot's hand (body 3) stays where
    it is, and after the request's end and the wait the actor's output goes over to the
    request made again; with the hand set off in the meantime, it does not."""
    pointing = _timeline().evaluate(3.0)[0]
    capsule = ((3, np.zeros(3), np.array([0.0, 0.0, 0.05]), 0.01),)
    world = WorldBodies(hands=HANDS, hand_middle=0.09, objects={"red": 1, "blue": 2},
                        X_WP=RigidTransform(), gripper=capsule)  # fmt: skip
    still = PostureTimeline([(0.0, np.zeros(len(PERSON_JOINTS)))])
    repeater = Repeater([(0.0, pointing)], ended=1.0, wait_s=2.0)
    receiver = Receiver(BODY, ReceivingParams(), wanted="blue")
    actor = HumanActor(still, PERSON_JOINTS, receiver, world, repeater=repeater)
    context = actor.CreateDefaultContext()
    poses = actor.GetInputPort("body_poses")

    def place(hand_x: float) -> None:
        poses.FixValue(context, [RigidTransform(), RigidTransform([0.8, -0.2, 0.75]),
                                 RigidTransform([0.8, 0.2, 0.75]),
                                 RigidTransform([hand_x, 0.0, 0.7])])  # fmt: skip

    place(0.3)
    simulator = Simulator(actor, context)
    simulator.AdvanceTo(2.0)
    if moves:
        place(0.5)
    simulator.AdvanceTo(5.0)
    output = actor.GetOutputPort("person_desired_state").Eval(context)[: len(PERSON_JOINTS)]
    expected = np.zeros(len(PERSON_JOINTS)) if moves else pointing
    np.testing.assert_allclose(output, expected, atol=1e-6)
    state = actor.acting(context)
    assert (state.repeater.repeated_at is None) is moves
    assert state.repeater.answered is moves


def test_a_repeater_without_the_robots_gripper_is_rejected():
    world = WorldBodies(
        hands={"right": 0, "left": 0}, hand_middle=0.09, objects={}, X_WP=RigidTransform()
    )
    receiver = Receiver(BODY, ReceivingParams())
    with pytest.raises(ValueError, match="repeater"):
        HumanActor(_timeline(), PERSON_JOINTS, receiver, world, repeater=Repeater([], 1.0, 2.0))

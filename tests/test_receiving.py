"""The person's side of a handover: taking an offered object (algorithm) and the hand's grip
on it (HandGrip, on its own ports)."""

from __future__ import annotations

import numpy as np
import pytest
from pydrake.math import RigidTransform
from pydrake.multibody.math import SpatialVelocity
from pydrake.systems.analysis import Simulator

from hsr_handover.human.body import BodyDimensions
from hsr_handover.human.receiving import (
    DRAW_IN_S,
    GRIP_DISTANCE,
    STILL_S,
    TUG_S,
    Receiver,
    Receiving,
    ReceivingParams,
)
from hsr_handover.systems.hand_grip import GRIP_PERIOD, STIFFNESS, HandGrip

BODY = BodyDimensions.from_height(1.7, seated=True)
SHOULDER = BODY.shoulder("right")
ON_TABLE = SHOULDER + [0.9, 0.0, -0.3]  # out of reach, where it stood
OFFERED = SHOULDER + [0.4, 0.05, -0.05]  # held out within reach


def _offer(receiver: Receiver, start: float = 0.0, seconds: float = 1.0, step: float = 0.05):
    changes, time = [], start
    while time < start + seconds:
        changes += receiver.update(time, {"cup": OFFERED}, SHOULDER)
        time += step
    return changes


def test_an_object_held_out_still_within_reach_is_reached_for_after_the_reaction_time():
    receiver = Receiver(BODY, ReceivingParams(reaction_s=0.4))
    receiver.update(0.0, {"cup": ON_TABLE}, SHOULDER)  # where it first stood
    changes = _offer(receiver, start=0.05)
    assert receiver.state is Receiving.REACHING and len(changes) == 1
    start, posture = changes[0]
    assert start == pytest.approx(0.1 + STILL_S + 0.4, abs=0.06)
    assert posture.shape == (len(posture),) and np.all(np.isfinite(posture))


def test_an_object_resting_where_it_stood_is_not_offered_even_within_reach():
    receiver = Receiver(BODY, ReceivingParams())
    for k in range(40):
        assert receiver.update(0.05 * k, {"cup": OFFERED}, SHOULDER) == []
    assert receiver.state is Receiving.WAITING


def test_the_hand_closes_at_the_object_tugs_it_straight_back_then_draws_it_in():
    receiver = Receiver(BODY, ReceivingParams())
    receiver.update(0.0, {"cup": ON_TABLE}, SHOULDER)
    _offer(receiver, start=0.05)
    far = OFFERED + [GRIP_DISTANCE + 0.02, 0, 0]
    assert receiver.update(2.0, {"cup": OFFERED}, far) == [] and receiver.grip == ""
    near = OFFERED + [GRIP_DISTANCE - 0.02, 0, 0]
    receiver.update(2.05, {"cup": OFFERED}, near)
    assert receiver.state is Receiving.HOLDING and receiver.grip == "cup"
    assert receiver.update(2.05 + TUG_S / 2, {"cup": OFFERED}, near) == []
    (start, tug), *rest = receiver.update(2.06 + TUG_S, {"cup": OFFERED}, near)
    assert rest == [] and receiver.state is Receiving.TUGGING and receiver.grip == "cup"
    assert receiver.update(2.06 + TUG_S + DRAW_IN_S / 2, {"cup": OFFERED}, near) == []
    (_, drawn_in), *rest = receiver.update(2.06 + TUG_S + DRAW_IN_S, {"cup": OFFERED}, near)
    assert rest == [] and receiver.state is Receiving.DRAWN_IN and receiver.grip == "cup"
    # The tug is a small move of the arm; drawing the object in, a large one.
    rest_posture = receiver._posture(0.0, near)
    assert np.abs(tug - rest_posture).max() < np.abs(drawn_in - rest_posture).max()


def test_a_person_who_does_not_take_never_reaches():
    receiver = Receiver(BODY, ReceivingParams(takes=False))
    receiver.update(0.0, {"cup": ON_TABLE}, SHOULDER)
    assert _offer(receiver, start=0.05, seconds=3.0) == []
    assert receiver.state is Receiving.WAITING


@pytest.fixture
def grip():
    system = HandGrip(hand=1, objects={"cup": 2})
    context = system.CreateDefaultContext()
    poses = [RigidTransform(), RigidTransform([0.5, 0, 1.0]), RigidTransform([0.6, 0, 1.0])]
    system.GetInputPort("body_poses").FixValue(context, poses)
    system.GetInputPort("body_spatial_velocities").FixValue(context, [SpatialVelocity.Zero()] * 3)
    return system, context, poses


def _latch(system, context):
    """Run the grip's periodic check once."""
    Simulator(system, context).AdvanceTo(context.get_time() + GRIP_PERIOD)


def test_an_open_hand_pulls_nothing(grip):
    system, context, _ = grip
    system.GetInputPort("grip").FixValue(context, "")
    _latch(system, context)
    assert system.GetOutputPort("spatial_forces").Eval(context) == []


def test_a_closed_hand_holds_the_object_where_it_closed_on_it(grip):
    system, context, poses = grip
    system.GetInputPort("grip").FixValue(context, "cup")
    _latch(system, context)
    forces = system.GetOutputPort("spatial_forces").Eval(context)
    assert [int(f.body_index) for f in forces] == [2, 1]
    np.testing.assert_allclose(forces[0].F_Bq_W.translational(), 0.0, atol=1e-9)
    moved = [*poses[:2], RigidTransform([0.6, 0, 0.99])]  # it sags 1 cm in the hand
    system.GetInputPort("body_poses").FixValue(context, moved)
    on_object, on_hand = system.GetOutputPort("spatial_forces").Eval(context)
    np.testing.assert_allclose(on_object.F_Bq_W.translational(), [0, 0, STIFFNESS * 0.01])
    np.testing.assert_allclose(on_hand.F_Bq_W.translational(), [0, 0, -STIFFNESS * 0.01])
    system.GetInputPort("grip").FixValue(context, "")
    _latch(system, context)
    assert system.GetOutputPort("spatial_forces").Eval(context) == []

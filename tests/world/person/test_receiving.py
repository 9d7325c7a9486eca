"""The person's side of a handover: taking an offered object (algorithm) and the hand's grip
on it (HandGrip, on its own ports)."""

from __future__ import annotations

import numpy as np
import pytest
from pydrake.math import RigidTransform
from pydrake.multibody.math import SpatialVelocity
from pydrake.systems.analysis import Simulator
from scipy.spatial.distance import cdist

from hsr_handover.world.person.aiming import arm_move_points, arm_points, reaching_arm_angles
from hsr_handover.world.person.behavior import joint_limits, rest_posture
from hsr_handover.world.person.body import ARM_JOINT_SUFFIXES, BodyDimensions, arm_joint_indices
from hsr_handover.world.person.receiving import (
    ARRIVED,
    CLEAR,
    CORRECTION_S,
    DRAW_IN_S,
    GRIP_DISTANCE,
    MOVED,
    PATH_SAMPLES,
    REACH_SHORT,
    SETTLE_AFTER_S,
    STILL_S,
    TUG,
    TUG_S,
    Receiver,
    Receiving,
    ReceivingParams,
    path_clearance,
    reach_point,
)
from hsr_handover.world.systems.hand_grip import GRIP_FREQUENCY, GRIP_PERIOD, GrippedBody, HandGrip

BODY = BodyDimensions.from_height(1.7, seated=True)
SHOULDER = BODY.shoulder("right")
REST_ARM = rest_posture(BODY)[arm_joint_indices("right")]
REST_LEFT = rest_posture(BODY)[arm_joint_indices("left")]
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
    hand = arm_points(BODY, "right", posture[arm_joint_indices("right")])["hand"]
    np.testing.assert_allclose(hand, reach_point(BODY, "right", OFFERED), atol=0.01)


def test_at_a_high_table_the_other_arm_keeps_resting_over_it_while_the_hand_reaches():
    table_top = 0.85  # over the level forearms' hands
    raised = rest_posture(BODY, table_top)
    receiver = Receiver(BODY, ReceivingParams(reaction_s=0.4), table_top)
    receiver.update(0.0, {"cup": ON_TABLE}, SHOULDER)
    changes = _offer(receiver, start=0.05)
    left = arm_joint_indices("left")
    assert len(changes) == 1 and not np.allclose(raised[left], REST_LEFT)
    np.testing.assert_array_equal(changes[0][1][left], raised[left])


def test_an_object_resting_where_it_stood_is_not_offered_even_within_reach():
    receiver = Receiver(BODY, ReceivingParams())
    for k in range(40):
        assert receiver.update(0.05 * k, {"cup": OFFERED}, SHOULDER) == []
    assert receiver.state is Receiving.WAITING


def test_the_hand_closes_where_it_arrives_tugs_then_draws_it_in_the_way_it_came():
    receiver = Receiver(BODY, ReceivingParams(reaction_s=0.5))
    receiver.update(0.0, {"cup": ON_TABLE}, SHOULDER)
    _offer(receiver, start=0.05)  # the reach starts at about 0.9 s
    point = reach_point(BODY, "right", OFFERED)
    on_the_way = point + [-0.03, 0.0, -0.03]  # moving, nearer the object than it will be
    for k, time in enumerate((1.0, 1.05, 1.1)):
        receiver.update(time, {"cup": OFFERED}, on_the_way + [0.0, 0.0, 0.01 * k])
    assert receiver.grip == "" and receiver.state is Receiving.REACHING
    near = point + [ARRIVED / 2, 0.0, 0.0]
    receiver.update(2.05, {"cup": OFFERED}, near)
    assert receiver.state is Receiving.HOLDING and receiver.grip == "cup"
    assert receiver.update(2.05 + TUG_S / 2, {"cup": OFFERED}, near) == []
    (start, tug), *rest = receiver.update(2.06 + TUG_S, {"cup": OFFERED}, near)
    assert rest == [] and receiver.state is Receiving.TUGGING and receiver.grip == "cup"
    assert receiver.update(2.06 + TUG_S + DRAW_IN_S / 2, {"cup": OFFERED}, near) == []
    (_, drawn_in), *rest = receiver.update(2.06 + TUG_S + DRAW_IN_S, {"cup": OFFERED}, near)
    assert rest == [] and receiver.state is Receiving.DRAWN_IN and receiver.grip == "cup"
    away = (point - OFFERED) / np.linalg.norm(point - OFFERED)
    tugged, drawn = (arm_points(BODY, "right", posture[arm_joint_indices("right")])["hand"]
                     for posture in (tug, drawn_in))  # fmt: skip
    np.testing.assert_allclose(tugged, near + TUG * away, atol=0.01)
    # Drawn in the same way as far as the folding arm allows (DRAW_IN is nearer the shoulder).
    assert np.linalg.norm(drawn - OFFERED) > np.linalg.norm(tugged - OFFERED) + 0.05


def test_a_hand_that_stops_short_closes_once_stopped_if_the_object_is_within_grip():
    for stop, closes in ((GRIP_DISTANCE - 0.01, True), (GRIP_DISTANCE + 0.01, False)):
        receiver = Receiver(BODY, ReceivingParams(reaction_s=0.0))
        receiver.update(0.0, {"cup": ON_TABLE}, SHOULDER)
        _offer(receiver, start=0.05, seconds=0.4)  # until the reach starts, at about 0.4 s
        toward = (SHOULDER - OFFERED) / np.linalg.norm(SHOULDER - OFFERED)
        stopped = OFFERED + stop * toward
        receiver.update(0.5, {"cup": OFFERED}, stopped)
        receiver.update(0.55, {"cup": OFFERED}, stopped)  # still, but not long into the reach
        assert receiver.grip == ""
        receiver.update(0.45 + SETTLE_AFTER_S, {"cup": OFFERED}, stopped)
        receiver.update(0.5 + SETTLE_AFTER_S, {"cup": OFFERED}, stopped)
        assert (receiver.grip == "cup") is closes


def _stopped_short(reaction_s: float) -> tuple[Receiver, np.ndarray, float]:
    """A receiver whose reach for OFFERED started and whose hand then stopped out of grip:
    the receiver, the stopped hand and the time (s) from which it counts as stopped."""
    receiver = Receiver(BODY, ReceivingParams(reaction_s=reaction_s))
    receiver.update(0.0, {"cup": ON_TABLE}, SHOULDER)
    ((reach_start, _),) = _offer(receiver, start=0.05, seconds=0.4)
    toward = (SHOULDER - OFFERED) / np.linalg.norm(SHOULDER - OFFERED)
    stopped = OFFERED + (GRIP_DISTANCE + 0.03) * toward
    receiver.update(reach_start + 0.01, {"cup": OFFERED}, stopped)  # still from here on
    assert receiver.update(reach_start + SETTLE_AFTER_S - 0.01, {"cup": OFFERED}, stopped) == []
    return receiver, stopped, reach_start + SETTLE_AFTER_S + 0.01


def test_a_hand_stopped_out_of_grip_reaches_again_for_where_the_object_is_now():
    receiver, stopped, short_since = _stopped_short(reaction_s=0.4)
    moved = OFFERED + [0.0, MOVED - 0.005, 0.0]  # nudged on, too little to correct the reach
    for time in short_since + np.array([0.0, 0.2, 0.38]):  # within the reaction time
        assert receiver.update(time, {"cup": moved}, stopped) == []
    ((start, posture),) = receiver.update(short_since + 0.42, {"cup": moved}, stopped)
    assert start == pytest.approx(short_since + 0.42) and receiver.grip == ""
    hand = arm_points(BODY, "right", posture[arm_joint_indices("right")])["hand"]
    np.testing.assert_allclose(hand, reach_point(BODY, "right", moved), atol=0.01)
    assert receiver.update(start + 0.05, {"cup": moved}, stopped) == []  # on its way
    assert receiver.update(start + 0.5, {"cup": moved}, hand) == []  # there: it closes
    assert receiver.state is Receiving.HOLDING and receiver.grip == "cup"


def test_a_reach_whose_object_moves_on_turns_toward_where_it_is_a_moment_later():
    receiver = Receiver(BODY, ReceivingParams(reaction_s=0.4))
    receiver.update(0.0, {"cup": ON_TABLE}, SHOULDER)
    ((reach_start, _),) = _offer(receiver, start=0.05, seconds=0.4)
    carried = OFFERED + [-0.02, 0.05, 0.0]  # the robot brings it on
    # Seen moved before the hand set off: the corrected reach still starts after the reaction.
    assert receiver.update(reach_start - 0.3, {"cup": carried}, SHOULDER) == []
    ((start, posture),) = receiver.update(reach_start - 0.3 + CORRECTION_S, {"cup": carried},
                                          SHOULDER)  # fmt: skip
    assert start == pytest.approx(reach_start)
    hand = arm_points(BODY, "right", posture[arm_joint_indices("right")])["hand"]
    np.testing.assert_allclose(hand, reach_point(BODY, "right", carried), atol=0.01)
    # Moved on again in flight: the hand turns toward it CORRECTION_S later, not before.
    farther = carried + [-0.02, 0.05, 0.02]
    moving = (hand + SHOULDER) / 2
    assert receiver.update(reach_start + 0.1, {"cup": farther}, moving) == []
    assert receiver.update(reach_start + 0.1 + CORRECTION_S / 2, {"cup": farther}, moving) == []
    ((start, posture),) = receiver.update(reach_start + 0.1 + CORRECTION_S, {"cup": farther},
                                          moving)  # fmt: skip
    assert start == pytest.approx(reach_start + 0.1 + CORRECTION_S)
    hand = arm_points(BODY, "right", posture[arm_joint_indices("right")])["hand"]
    np.testing.assert_allclose(hand, reach_point(BODY, "right", farther), atol=0.01)
    # Held still where it was aimed at: no more corrections.
    assert receiver.update(start + 0.3, {"cup": farther}, moving + [0.01, 0, 0]) == []


def test_a_reach_stopped_out_of_grip_for_the_other_hand_is_made_with_it():
    receiver, stopped, short_since = _stopped_short(reaction_s=0.0)
    across = BODY.shoulder("left") + [0.4, -0.05, -0.05]
    ((_, posture),) = receiver.update(short_since, {"cup": across}, stopped)
    assert receiver.arm == "left"
    hand = arm_points(BODY, "left", posture[arm_joint_indices("left")])["hand"]
    np.testing.assert_allclose(hand, reach_point(BODY, "left", across), atol=0.01)


def test_with_no_fingers_in_the_way_the_hand_comes_straight_from_the_shoulder():
    point = reach_point(BODY, "right", OFFERED)
    toward = (SHOULDER - OFFERED) / np.linalg.norm(SHOULDER - OFFERED)
    np.testing.assert_allclose(point, OFFERED + REACH_SHORT * toward, atol=1e-9)


def test_a_gripper_where_the_straight_reach_would_pass_sends_the_hand_round_it():
    toward = (SHOULDER - OFFERED) / np.linalg.norm(SHOULDER - OFFERED)
    straight = OFFERED + REACH_SHORT * toward
    joints = arm_points(BODY, "right", reaching_arm_angles(straight - SHOULDER, BODY))
    finger = (joints["tips"] - [0, 0, 0.03], joints["tips"] + [0, 0, 0.03], 0.01)
    assert path_clearance(BODY, "right", REST_ARM, straight, [finger]) < CLEAR
    point = reach_point(BODY, "right", OFFERED, [finger])
    assert np.linalg.norm(point - OFFERED) == pytest.approx(REACH_SHORT)
    assert path_clearance(BODY, "right", REST_ARM, point, [finger]) >= CLEAR


def test_the_way_there_counts_not_only_the_end():
    # A gripper capsule that the hand's final pose clears but the move from rest sweeps through.
    toward = (SHOULDER - OFFERED) / np.linalg.norm(SHOULDER - OFFERED)
    straight = OFFERED + REACH_SHORT * toward
    goal = reaching_arm_angles(straight - SHOULDER, BODY)
    halfway = arm_points(BODY, "right", (REST_ARM + goal) / 2)["tips"]
    finger = (halfway - [0, 0, 0.02], halfway + [0, 0, 0.02], 0.01)
    end = arm_points(BODY, "right", goal)
    ends_clear = min(np.linalg.norm(end[k] - halfway) for k in ("elbow", "wrist", "tips"))
    assert ends_clear > CLEAR + 0.03
    assert path_clearance(BODY, "right", REST_ARM, straight, [finger]) < CLEAR


def test_an_object_held_beside_the_shoulder_is_reached_from_a_side_the_hand_gets_to():
    """Straight from the shoulder the elbow would fold past its limit, and the arm stopped
    there ends too far from the object to close on it: the hand comes from a side it reaches."""
    near = SHOULDER + [0.1, -0.1, 0.0]
    toward = (SHOULDER - near) / np.linalg.norm(SHOULDER - near)
    straight = near + REACH_SHORT * toward
    assert np.linalg.norm(_hand_at_limits(straight) - near) > GRIP_DISTANCE
    point = reach_point(BODY, "right", near)
    assert np.linalg.norm(_hand_at_limits(point) - near) <= GRIP_DISTANCE


def _hand_at_limits(point: np.ndarray) -> np.ndarray:
    """Where the right hand's middle ends, reaching for `point` within the joint limits."""
    angles = _within_limits(reaching_arm_angles(point - SHOULDER, BODY))
    return arm_points(BODY, "right", angles)["hand"]


def _within_limits(angles: np.ndarray) -> np.ndarray:
    """The right arm's joint `angles` clipped to the person's joint limits."""
    limits = np.array([joint_limits("r_" + suffix) for suffix in ARM_JOINT_SUFFIXES]).T
    return np.clip(angles, *limits)


def test_the_way_checked_is_the_way_the_arm_moves_within_its_joint_limits():
    # A point so near the shoulder that the elbow would fold past its limit: the arm moves to
    # the limit instead, along another way, and a finger on that way is in the way of the
    # reach, though the way the angles alone would take passes 4 cm clear of it.
    near = SHOULDER + [0.05, -0.05, -0.05]
    unlimited = reaching_arm_angles(near - SHOULDER, BODY)
    limited = _within_limits(unlimited)
    assert np.flatnonzero(limited != unlimited).tolist() == [3]  # the elbow alone
    way, unlimited_way = _swept_axes(limited), _swept_axes(unlimited)
    apart = cdist(way, unlimited_way).min(axis=1)
    on_way = way[np.argmax(apart)]
    finger = (on_way - [0, 0, 0.01], on_way + [0, 0, 0.01], 0.01)
    unlimited_clearance = cdist(unlimited_way, np.array(finger[:2])).min() - finger[2]
    assert path_clearance(BODY, "right", REST_ARM, near, [finger]) < 0.0
    assert unlimited_clearance > 0.04


def _swept_axes(goal: np.ndarray) -> np.ndarray:
    """Points along the forearm's and hand's axes over the move from rest to `goal`."""
    moves = arm_move_points(BODY, "right", REST_ARM, goal, PATH_SAMPLES)
    return np.concatenate([np.linspace(joints["elbow"], joints["tips"], 30) for joints in moves])


def test_a_person_who_does_not_take_never_reaches():
    receiver = Receiver(BODY, ReceivingParams(takes=False))
    receiver.update(0.0, {"cup": ON_TABLE}, SHOULDER)
    assert _offer(receiver, start=0.05, seconds=3.0) == []
    assert receiver.state is Receiving.WAITING


def test_an_object_held_out_nearer_the_left_shoulder_is_taken_with_the_left_hand():
    left = BODY.shoulder("left")
    held_left = left + [0.45, 0.15, -0.05]  # beyond the right hand's reach
    for either, arm in ((True, "left"), (False, None)):
        receiver = Receiver(BODY, ReceivingParams(reaction_s=0.0, either_hand=either))
        receiver.update(0.0, {"cup": held_left - [0.0, 0.0, 0.2]}, SHOULDER)
        changes = []
        for time in np.arange(0.05, 1.0, 0.05):
            changes += receiver.update(float(time), {"cup": held_left}, SHOULDER)
        if arm is None:  # the right hand alone does not reach it: never offered
            assert changes == [] and receiver.state is Receiving.WAITING
            continue
        (_, posture), *_ = changes
        assert receiver.arm == arm and receiver.state is Receiving.REACHING
        np.testing.assert_allclose(posture[arm_joint_indices("right")], REST_ARM)
        assert not np.allclose(posture[arm_joint_indices("left")], REST_LEFT)


CUP_MASS = 0.2  # kg


@pytest.fixture
def grip():
    cup = GrippedBody(2, CUP_MASS, np.diag([2e-4, 2e-4, 1e-4]))
    system = HandGrip(hands=(1, 3), objects={"cup": cup})  # hands 1 and 3, the cup 2
    context = system.CreateDefaultContext()
    poses = [RigidTransform(), RigidTransform([0.5, 0, 1.0]), RigidTransform([0.6, 0, 1.0]),
             RigidTransform([0.5, 0.4, 0.8])]  # fmt: skip
    system.GetInputPort("body_poses").FixValue(context, poses)
    system.GetInputPort("body_spatial_velocities").FixValue(context, [SpatialVelocity.Zero()] * 4)
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
    moved = [*poses[:2], RigidTransform([0.6, 0, 0.99]), poses[3]]  # it sags 1 cm in the hand
    system.GetInputPort("body_poses").FixValue(context, moved)
    on_object, on_hand = system.GetOutputPort("spatial_forces").Eval(context)
    pull = CUP_MASS * GRIP_FREQUENCY**2 * 0.01  # N: the spring scaled by the cup's mass
    np.testing.assert_allclose(on_object.F_Bq_W.translational(), [0, 0, pull])
    np.testing.assert_allclose(on_hand.F_Bq_W.translational(), [0, 0, -pull])
    system.GetInputPort("grip").FixValue(context, "")
    _latch(system, context)
    assert system.GetOutputPort("spatial_forces").Eval(context) == []


def test_the_hand_nearest_the_object_is_the_one_that_holds_it(grip):
    system, context, poses = grip
    nearer = [*poses[:3], RigidTransform([0.65, 0.05, 1.0])]  # the other hand at the cup
    system.GetInputPort("body_poses").FixValue(context, nearer)
    system.GetInputPort("grip").FixValue(context, "cup")
    _latch(system, context)
    forces = system.GetOutputPort("spatial_forces").Eval(context)
    assert [int(f.body_index) for f in forces] == [2, 3]


def test_a_hand_that_strikes_the_object_on_its_way_closes_on_it_and_stops_there():
    """Touching the object it reaches for, short of where it was going, the hand closes and
    holds where it is; touching another object, it goes on."""
    receiver = Receiver(BODY, ReceivingParams(reaction_s=0.0))
    receiver.update(0.0, {"cup": ON_TABLE, "box": ON_TABLE}, SHOULDER)
    for k in range(20):
        receiver.update(0.05 + 0.05 * k, {"cup": OFFERED, "box": ON_TABLE}, SHOULDER)
    assert receiver.state is Receiving.REACHING
    below = OFFERED - [0.0, 0.0, 0.12]  # coming up under it, far from the point it makes for
    posture = rest_posture(BODY)
    objects = {"cup": OFFERED, "box": ON_TABLE}
    moving = receiver.update(1.1, objects, below - [0, 0, 0.02], (), posture, frozenset({"box"}))
    assert moving == [] and receiver.grip == ""
    stop = receiver.update(1.15, objects, below, (), posture, frozenset({"cup"}))
    assert receiver.state is Receiving.HOLDING and receiver.grip == "cup"
    assert len(stop) == 1 and stop[0][0] == pytest.approx(1.15)
    np.testing.assert_array_equal(stop[0][1], posture)

"""A pointing person holds the hand clear of the objects (the world's person model)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from hsr_handover.experiments.handover.trials import make_trials
from hsr_handover.experiments.seating import sit_clear
from hsr_handover.robot.intent.rays import angle_deg
from hsr_handover.scenario import load_scenario
from hsr_handover.world.person.aiming import arm_points, pointing_arm_angles
from hsr_handover.world.person.behavior import (
    PostureTimeline,
    arm_joint_indices,
    posture_changes,
    rest_posture,
)
from hsr_handover.world.person.body import HAND_WIDTH, BodyDimensions
from hsr_handover.world.person.pointing_clearance import (
    MAX_RAISE,
    POINT_CLEAR,
    RAISE_STEP,
    Upright,
    clear_aim,
    hand_clearance,
    lowering_clearance,
)
from hsr_handover.world.station.world import object_uprights, person_actions
from tests.paths import SCENARIOS

BODY = BodyDimensions.from_height(1.81, seated=True)


def _unit(vector: np.ndarray) -> np.ndarray:
    return vector / np.linalg.norm(vector)


def _box_under_the_hand(side: str = "right") -> tuple[np.ndarray, Upright]:
    """An aim whose straight arm's fingertips end on the top edge of a 12 cm box."""
    shoulder = BODY.shoulder(side)
    aim = shoulder + np.array([0.6, 0.0, -0.45])
    tips = arm_points(BODY, side, pointing_arm_angles(aim - shoulder))["tips"]
    box = Upright(tips[:2] + [0.02, 0.0], 0.04, tips[2] - 0.12, tips[2] + 0.005)
    return aim, box


def _raised(aim: np.ndarray, shoulder: np.ndarray, angle: float) -> np.ndarray:
    """The unit direction from `shoulder` toward `aim`, raised by `angle` (rad)."""
    offset = aim - shoulder
    elevation = math.atan2(offset[2], np.hypot(*offset[:2])) + angle
    heading = math.atan2(offset[1], offset[0])
    return np.array([math.cos(elevation) * math.cos(heading),
                     math.cos(elevation) * math.sin(heading), math.sin(elevation)])  # fmt: skip


def test_an_arm_that_would_land_on_an_object_is_raised_just_clear_of_it():
    aim, box = _box_under_the_hand()
    shoulder = BODY.shoulder("right")
    assert hand_clearance(BODY, shoulder, _unit(aim - shoulder), [box]) == 0.0
    raised = clear_aim(BODY, "right", aim, [box])
    assert np.linalg.norm(raised - shoulder) == pytest.approx(np.linalg.norm(aim - shoulder))
    assert raised[2] > aim[2]
    assert raised[1] == pytest.approx(aim[1])  # the same heading, only higher
    assert hand_clearance(BODY, shoulder, _unit(raised - shoulder), [box]) >= POINT_CLEAR
    # The least raise that clears: a step less does not.
    steps = round(angle_deg(raised - shoulder, aim - shoulder) / math.degrees(RAISE_STEP))
    assert steps >= 1
    lower = _raised(aim, shoulder, (steps - 1) * RAISE_STEP)
    assert hand_clearance(BODY, shoulder, lower, [box]) < POINT_CLEAR


def test_an_arm_clear_of_everything_or_unable_to_clear_keeps_its_aim():
    aim, box = _box_under_the_hand()
    far = Upright(box.xy + [0.5, 0.0], box.radius, box.bottom, box.top)
    np.testing.assert_array_equal(clear_aim(BODY, "right", aim, [far]), aim)
    np.testing.assert_array_equal(clear_aim(BODY, "right", aim, []), aim)
    tower = Upright(box.xy, 0.3, 0.0, 3.0)  # no raise up to MAX_RAISE clears it
    np.testing.assert_array_equal(clear_aim(BODY, "right", aim, [tower]), aim)
    highest = _raised(aim, BODY.shoulder("right"), MAX_RAISE)
    assert hand_clearance(BODY, BODY.shoulder("right"), highest, [tower]) == 0.0


def test_the_person_points_over_a_cup_within_reach_and_straight_at_one_beyond():
    """Through the world's script: the point_left scenario's person, 1.81 m tall and exact,
    pointing at the red cup where it stands (0.95 m off) and pulled in to 0.65 m."""
    scenario = load_scenario(SCENARIOS / "point_left.yaml")
    scenario.person.height = 1.81
    scenario.person.imprecision.pointing_error_deg = 0.0
    body = BodyDimensions.from_height(1.81, seated=True)
    far = person_actions(scenario, body)[-1]
    np.testing.assert_allclose(far.arm_point, far.point, atol=1e-9)
    scenario.objects[0].position = [1.10, -0.22]
    near = person_actions(scenario, body)[-1]
    assert near.arm_point[2] > near.point[2]
    cup = Upright(near.point[:2], 0.035, near.point[2] - 0.05, near.point[2] + 0.05)
    shoulder = body.shoulder(near.arm)
    straight_at = _unit(near.point - shoulder)
    assert hand_clearance(body, shoulder, straight_at, [cup]) < POINT_CLEAR
    assert hand_clearance(body, shoulder, _unit(near.arm_point - shoulder), [cup]) >= POINT_CLEAR


def _least_hand_clearance(trial, withdraw: bool) -> float:
    """The least distance (m) from either hand's axis to any object, from the pointing's start
    to 3 s after its end, with the pointing hand withdrawn before lowering or not."""
    scenario = trial.scenario
    sit_clear(scenario)
    body = BodyDimensions.from_height(scenario.person.height, seated=True)
    actions = person_actions(scenario, body)
    index = next(i for i, action in enumerate(actions) if action.kind == "point_at")
    pointing = actions[index]
    assert pointing.withdraw  # held over an object, or lowered straight through one
    actions[index] = dataclasses.replace(pointing, withdraw=withdraw)
    uprights = object_uprights(scenario)
    timeline = PostureTimeline(posture_changes(body, actions, scenario.table.height))
    least = math.inf
    for time in np.arange(pointing.start, pointing.end + 3.0, 0.02):
        q, _ = timeline.evaluate(time)
        for side in ("right", "left"):
            hand = arm_points(body, side, q[arm_joint_indices(side)])
            axis = np.linspace(hand["wrist"], hand["tips"], 11)
            least = min(least, min(float(obj.distance(axis).min()) for obj in uprights))
    return least


def test_a_hand_held_over_an_object_is_withdrawn_before_the_arm_lowers():
    """The moved layout's trial 57 of seed 2: the raised arm cleared the yellow box, but
    lowered straight to rest it swept the hand through the box and knocked it over."""
    trial = make_trials(load_scenario(SCENARIOS / "layouts" / "moved_base_four.yaml"), 60, 0, 2)[57]
    assert _least_hand_clearance(trial, withdraw=True) >= HAND_WIDTH / 2 + 0.01
    assert _least_hand_clearance(trial, withdraw=False) < HAND_WIDTH / 2


def test_the_lowering_arm_is_checked_all_the_way_down_to_rest():
    """A small box where the hand passes midway down: clear of the pointing hand and of the
    hand at rest, but not of the way between."""
    shoulder = BODY.shoulder("right")
    aim = shoulder + np.array([0.65, 0.0, 0.0])
    start = pointing_arm_angles(aim - shoulder)
    rest = rest_posture(BODY)[arm_joint_indices("right")]
    midway = arm_points(BODY, "right", start + 0.5 * (rest - start))["hand"]
    in_the_way = Upright(midway[:2], 0.02, midway[2] - 0.03, midway[2] + 0.03)
    far = Upright(midway[:2] + [0.0, 0.8], 0.02, midway[2] - 0.03, midway[2] + 0.03)
    assert hand_clearance(BODY, shoulder, _unit(aim - shoulder), [in_the_way]) > POINT_CLEAR
    resting = arm_points(BODY, "right", rest)
    assert in_the_way.distance(np.linspace(resting["wrist"], resting["tips"], 11)).min() > 0.05
    assert lowering_clearance(BODY, "right", aim, rest, [in_the_way]) == 0.0
    assert lowering_clearance(BODY, "right", aim, rest, [far]) > 0.5
    assert lowering_clearance(BODY, "right", aim, rest, []) == math.inf


def test_a_hand_that_would_sweep_through_an_object_on_its_way_down_is_withdrawn():
    """On the staggered layout (trial 49 of seed 2) the arm points clear of the objects (not
    raised), but lowered straight to rest its hand's axis would pass 3 cm from a box: through
    its edge."""
    layout = load_scenario(SCENARIOS / "layouts" / "staggered_high_four.yaml")
    trial = make_trials(layout, 60, 0, 2)[49]
    scenario = trial.scenario
    sit_clear(scenario)
    body = BodyDimensions.from_height(scenario.person.height, seated=True)
    pointing = next(a for a in person_actions(scenario, body) if a.kind == "point_at")
    uprights = object_uprights(scenario)
    shoulder = body.shoulder(pointing.arm)
    aimed = _unit(pointing.arm_point - shoulder)
    assert hand_clearance(body, shoulder, aimed, uprights) >= POINT_CLEAR  # clear as pointed
    rest = rest_posture(body, scenario.table.height)[arm_joint_indices(pointing.arm)]
    lowering = lowering_clearance(body, pointing.arm, pointing.arm_point, rest, uprights)
    assert lowering < POINT_CLEAR  # but not on the straight way down
    assert _least_hand_clearance(trial, withdraw=True) >= HAND_WIDTH / 2 + 0.01
    assert _least_hand_clearance(trial, withdraw=False) < HAND_WIDTH / 2

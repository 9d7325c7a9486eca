"""The person's layer-1 model: aiming the arms and head, and the behaviour timeline."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.robot.intent.rays import angle_deg
from hsr_handover.world.person.aiming import arm_points, pointing_arm_angles, reaching_arm_angles
from hsr_handover.world.person.behavior import (
    MIN_MOVE_TIME,
    OVER_TABLE,
    PEAK_JOINT_SPEED,
    Action,
    PostureTimeline,
    aim_head,
    head_rotation,
    posture_changes,
    rest_posture,
    target_posture,
)
from hsr_handover.world.person.body import (
    HAND_THICKNESS,
    PERSON_JOINTS,
    BodyDimensions,
    arm_joint_indices,
)

BODY = BodyDimensions.from_height(1.70, seated=True)


def _targets_in_front(count: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.column_stack(
        [rng.uniform(0.3, 1.2, count), rng.uniform(-0.6, 0.6, count), rng.uniform(0.5, 1.3, count)]
    )


@pytest.mark.parametrize("side", ["right", "left"])
def test_pointing_arm_puts_elbow_and_wrist_on_the_shoulder_to_target_ray(side):
    for target in _targets_in_front(50, seed=1):
        to_target = target - BODY.shoulder(side)
        points = arm_points(BODY, side, pointing_arm_angles(to_target))
        for joint in ("elbow", "wrist"):
            assert angle_deg(points[joint] - BODY.shoulder(side), to_target) < 1e-4


def test_reaching_arm_puts_the_hand_on_reachable_targets():
    reached = 0
    for target in _targets_in_front(200, seed=2) * [0.6, 1.0, 1.0]:
        to_target = target - BODY.shoulder("right")
        hand = arm_points(BODY, "right", reaching_arm_angles(to_target, BODY))["hand"]
        distance = np.linalg.norm(to_target)
        if distance < BODY.upper_arm + BODY.forearm + BODY.hand / 2 - 1e-3:
            assert np.linalg.norm(hand - target) < 1e-3
            reached += 1
        else:  # out of reach: the arm points straight at it instead
            assert angle_deg(hand - BODY.shoulder("right"), to_target) < 1e-4
    assert reached > 50  # the sample really exercised the bent-elbow branch


def test_head_aims_the_line_of_sight_from_the_eyes_at_the_target():
    face = BODY.face_points()
    eyes = (face["r_eye"] + face["l_eye"]) / 2
    for target in _targets_in_front(30, seed=3):
        rotation = head_rotation(*aim_head(BODY, target))
        eye_position = BODY.neck_pivot() + rotation @ eyes
        assert angle_deg(rotation @ [1.0, 0, 0], target - eye_position) < 0.05


def test_pointing_posture_aims_arm_and_head_and_leaves_the_other_arm_at_rest():
    target = np.array([0.9, 0.3, 0.8])
    posture = target_posture(BODY, Action("point_at", 0.0, None, target, "right"))
    rest = rest_posture(BODY)
    left = [PERSON_JOINTS.index(n) for n in PERSON_JOINTS if n.startswith("l_")]
    np.testing.assert_allclose(posture[left], rest[left])
    right = [PERSON_JOINTS.index(n) for n in PERSON_JOINTS if n.startswith("r_")]
    wrist = arm_points(BODY, "right", posture[right])["wrist"]
    assert angle_deg(wrist - BODY.shoulder("right"), target - BODY.shoulder("right")) < 1e-4
    assert not np.allclose(posture[:2], rest[:2])


def _smooth_within_peak_speed(timeline: PostureTimeline, times: np.ndarray) -> None:
    q = np.array([timeline.evaluate(t)[0] for t in times])
    v = np.array([timeline.evaluate(t)[1] for t in times])
    assert np.abs(v).max() <= PEAK_JOINT_SPEED * 1.001
    # Positions continuous, velocities continuous and the positions' derivative.
    step = times[1] - times[0]
    assert np.abs(np.diff(q, axis=0)).max() <= PEAK_JOINT_SPEED * step * 1.01
    assert np.abs(np.diff(v, axis=0)).max() < 0.05
    np.testing.assert_allclose(np.gradient(q, times, axis=0)[1:-1], v[1:-1], atol=2e-3)


def test_timeline_is_smooth_respects_peak_speed_and_arrives():
    target = np.array([0.9, -0.3, 0.8])
    actions = [Action("point_at", 1.0, 5.0, target, "right")]
    changes = posture_changes(BODY, actions)
    # rest, lift the hand, stretch the arm, back to rest
    assert [time for time, _ in changes][::3] == [0.0, 5.0]
    assert 1.0 == changes[1][0] < changes[2][0] < 5.0
    timeline = PostureTimeline(changes)
    _smooth_within_peak_speed(timeline, np.arange(0.0, 8.0, 1e-3))
    np.testing.assert_allclose(timeline.evaluate(4.9)[0], changes[2][1], atol=1e-12)
    np.testing.assert_allclose(timeline.evaluate(7.9)[0], rest_posture(BODY), atol=1e-12)


def test_a_change_mid_move_carries_the_motion_on_smoothly():
    rest = rest_posture(BODY)
    changes = [(0.0, rest), (1.0, rest + 1.2), (1.4, rest)]
    _smooth_within_peak_speed(PostureTimeline(changes), np.arange(0.0, 5.0, 1e-3))


def test_a_change_at_peak_speed_is_planned_not_stretched_forever():
    """Stretching a move cannot slow the motion carried on from before. In trial 30 of the
    reference run the hand's lift was at its peak speed, 1.5000000000000002 rad/s, when the
    stretch began; the timeline stretched the new move without end and the experiment hung."""
    body = BodyDimensions.from_height(1.600845744351017, seated=True)
    cup = np.array([0.9508783233633863, 0.22237950277553184, 0.77])
    aim = np.array([0.9664845393347904, 0.23678015349343867, 0.892533445801095])
    actions = [
        Action("look_at", 0.9857820959567596, None, cup, "right", 0.7519602420708945),
        Action("point_at", 1.7701727388681727, 4.273849718068751, cup, "right",
               0.7519602420708945, aim),
    ]  # fmt: skip
    changes = posture_changes(body, actions)
    stretch = changes[3][0]
    carried = PostureTimeline(changes[:3]).evaluate(stretch)[1]
    assert np.abs(carried).max() >= PEAK_JOINT_SPEED  # a hair above it, in floating point
    _smooth_within_peak_speed(PostureTimeline(changes), np.arange(0.0, 7.0, 1e-3))


def test_the_hand_rises_from_rest_before_it_reaches_out_over_a_table():
    """Seated, the forearm rests at table height: a straight arm swung out from there sweeps
    the hand level into the table's edge (it caught on it in one trial in ten)."""
    target = BODY.shoulder("left") + np.array([0.9, 0.0, -0.25])  # a cup on the table
    pointing = Action("point_at", 0.5, 5.0, target, "left")
    timeline = PostureTimeline(posture_changes(BODY, [pointing]))
    left = [PERSON_JOINTS.index(n) for n in PERSON_JOINTS if n.startswith("l_")]
    hand = np.array([
        arm_points(BODY, "left", timeline.evaluate(t)[0][left])["hand"]
        for t in np.arange(0.0, 4.0, 1e-3)
    ])  # fmt: skip
    ahead = hand[:, 0] > hand[0, 0] + 0.05  # past where a table's edge in front would be
    assert ahead.any()
    assert hand[ahead, 2].min() >= hand[0, 2] + 0.03


def _hand_bottom(body: BodyDimensions, q: np.ndarray, arm: str) -> float:
    points = arm_points(body, arm, q[arm_joint_indices(arm)])
    return min(points["wrist"][2], points["tips"][2]) - HAND_THICKNESS / 2


def test_seated_hands_and_elbows_rest_over_a_table_higher_than_the_resting_forearms():
    """An elbow under the top with the hand over it jams the forearm against the table's edge
    from below as the arm swings up to point."""
    level = rest_posture(BODY)
    np.testing.assert_array_equal(rest_posture(BODY, 0.62), level)  # a low table changes nothing
    low = min(_hand_bottom(BODY, level, arm) for arm in ("right", "left"))
    top = low + 0.05
    high = rest_posture(BODY, top)
    for arm in ("right", "left"):
        joints = arm_joint_indices(arm)
        assert _hand_bottom(BODY, high, arm) >= top + OVER_TABLE
        assert arm_points(BODY, arm, level[joints])["elbow"][2] < top  # under it at rest ...
        assert arm_points(BODY, arm, high[joints])["elbow"][2] >= top + OVER_TABLE  # ... now over
        assert high[joints[0]] < level[joints[0]]  # the upper arm forward
    arm_joints = {"shoulder_pitch", "elbow"}
    unchanged = [i for i, name in enumerate(PERSON_JOINTS) if name[2:] not in arm_joints]
    np.testing.assert_array_equal(high[unchanged], level[unchanged])
    standing = BodyDimensions.from_height(1.70, seated=False)  # hands hang beside the body
    np.testing.assert_array_equal(rest_posture(standing, 0.5), rest_posture(standing))


def test_standing_hands_under_a_table_top_rest_over_it_instead():
    """Swung out from hanging under a high table's top, a short person's hand met its edge
    from below and stayed jammed there through the gesture."""
    standing = BodyDimensions.from_height(1.50, seated=False)
    hanging = rest_posture(standing)
    tips = min(_hand_bottom(standing, hanging, arm) for arm in ("right", "left"))
    assert tips < 0.85  # the hands hang below a 0.85 m top
    raised = rest_posture(standing, 0.85)
    for arm in ("right", "left"):
        assert _hand_bottom(standing, raised, arm) >= 0.85 + OVER_TABLE
    changes = posture_changes(standing, [], 0.85)
    np.testing.assert_array_equal(changes[0][1], raised)  # the script starts from there


def test_at_a_high_table_the_script_starts_returns_to_and_keeps_the_raised_rest():
    table_top = 0.80
    rest = rest_posture(BODY, table_top)
    pointing = Action("point_at", 0.5, 2.5, BODY.shoulder("right") + [0.8, -0.2, -0.2], "right")
    changes = posture_changes(BODY, [pointing], table_top)
    np.testing.assert_array_equal(changes[0][1], rest)
    np.testing.assert_array_equal(changes[-1][1], rest)  # back to rest at its end
    left = arm_joint_indices("left")
    for _, posture in changes:  # the other arm keeps resting over the table
        np.testing.assert_array_equal(posture[left], rest[left])


def test_timeline_interrupted_move_starts_where_the_body_is():
    far = np.array([0.5, -0.5, 1.3])
    actions = [Action("point_at", 1.0, None, far, "right"), Action("rest", 1.2)]
    timeline = PostureTimeline(posture_changes(BODY, actions))
    before, _ = timeline.evaluate(1.2 - 1e-9)
    after, _ = timeline.evaluate(1.2 + 1e-9)
    np.testing.assert_allclose(before, after, atol=1e-6)
    assert timeline.evaluate(1.2 + MIN_MOVE_TIME + 2.0)[0] == pytest.approx(rest_posture(BODY))


def test_an_interrupted_timeline_keeps_its_past_and_moves_on_from_where_the_body_is():
    body = BodyDimensions.from_height(1.7, seated=True)
    rest = rest_posture(body)
    raised = rest + 0.5
    timeline = PostureTimeline([(0.0, rest), (1.0, raised)])
    goal = rest - 0.3
    changed = timeline.interrupted(1.5, goal)
    for time in (0.5, 1.2, 1.49):
        np.testing.assert_allclose(changed.evaluate(time)[0], timeline.evaluate(time)[0])
    np.testing.assert_allclose(changed.evaluate(1.5)[1], timeline.evaluate(1.5)[1])  # moving on
    np.testing.assert_allclose(changed.evaluate(10.0)[0], goal)
    np.testing.assert_allclose(timeline.evaluate(10.0)[0], raised)  # the original is unchanged

"""Grasp candidates and the base's placement rule (layer 1, no solver)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hsr_handover.hsr import GRIPPER_MAX_OPENING
from hsr_handover.kinematics import hsr_arm
from hsr_handover.robot.perception.object_shapes import BOX, CYLINDER, ObjectShape
from hsr_handover.robot.planning.base_placement import base_pose, hand_posture
from hsr_handover.robot.planning.grasps import (
    LEAN_DEG,
    MIN_GRIP_HEIGHT,
    PREGRASP_STANDOFF,
    TOP_GRIP_DEPTH,
    grasp_candidates,
)

TABLE_TOP = 0.72


def _cup(x=0.8, y=0.2) -> ObjectShape:
    return ObjectShape("red", CYLINDER, np.array([x, y]), np.array([0.07, 0.07]), 0.0,
                       TABLE_TOP, 0.10)  # fmt: skip


def test_a_cup_is_taken_from_the_side_straight_ahead_first():
    grasps = grasp_candidates(_cup(), robot_xy=np.zeros(2))
    first = grasps[0]
    heading = np.array([0.8, 0.2, 0]) / np.hypot(0.8, 0.2)
    np.testing.assert_allclose(first.approach, heading)
    assert first.kind == "side" and first.closing @ first.approach == pytest.approx(0)
    assert first.closing[2] == 0  # the fingers close horizontally round the cup
    assert first.point[2] == pytest.approx(TABLE_TOP + MIN_GRIP_HEIGHT)  # 5 cm is too low
    assert 0.07 < first.opening <= GRIPPER_MAX_OPENING
    np.testing.assert_allclose(first.pregrasp_point, first.point - PREGRASP_STANDOFF * heading)
    turns = [math.acos(np.clip(g.approach @ heading, -1, 1)) for g in grasps]
    assert turns == sorted(turns, key=lambda t: round(t, 6))  # from the robot's side first


def test_a_box_is_taken_from_the_top_across_its_short_side_then_from_its_faces():
    box = ObjectShape("yellow", BOX, np.array([0.8, 0.0]), np.array([0.10, 0.06]), 0.3,
                      TABLE_TOP, 0.12)  # fmt: skip
    grasps = grasp_candidates(box, robot_xy=np.zeros(2))
    top = grasps[0]
    assert top.kind == "top" and top.approach[2] == -1
    short_axis = np.array([-math.sin(0.3), math.cos(0.3), 0])
    assert abs(top.closing @ short_axis) == pytest.approx(1)
    assert top.width == pytest.approx(0.06)
    # From the side, the fingers straddle whichever horizontal side they face across.
    sides = grasps[1:]
    assert {round(g.width, 3) for g in sides} == {0.06, 0.1}
    assert all(abs(g.approach @ g.closing) < 1e-9 for g in sides)


def test_a_box_is_last_taken_from_above_leaning_away_the_pads_square_on_its_faces():
    box = ObjectShape("yellow", BOX, np.array([0.8, 0.3]), np.array([0.10, 0.06]), 0.3,
                      TABLE_TOP, 0.12)  # fmt: skip
    grasps = grasp_candidates(box, robot_xy=np.zeros(2))
    leaning = [g for g in grasps if g.kind == "leaning"]
    assert grasps[-len(leaning) :] == leaning and len(leaning) == 2 * len(LEAN_DEG)
    lid = TABLE_TOP + 0.12
    heading = np.array([0.8, 0.3, 0]) / np.hypot(0.8, 0.3)
    tilts = []
    for grasp in leaning:
        assert grasp.closing[2] == 0 and abs(grasp.approach @ grasp.closing) < 1e-9
        assert grasp.approach[2] < 0 and grasp.approach @ heading > 0  # down, away from the robot
        tilts.append(round(math.degrees(math.acos(-grasp.approach[2])), 6))
        # The palm (PAD_OFFSET back along the approach) stays as high over the lid as in the
        # top grasp, and the hand waits higher over it than the top grasp's pre-grasp.
        palm = grasp.point - 0.05 * grasp.approach
        assert palm[2] == pytest.approx(lid - TOP_GRIP_DEPTH + 0.05)
        assert grasp.pregrasp_point[2] > lid - TOP_GRIP_DEPTH + PREGRASP_STANDOFF
    assert tilts == [*LEAN_DEG, *LEAN_DEG]
    assert [round(g.width, 3) for g in leaning] == [0.06] * 2 + [0.1] * 2  # short side first


def test_a_box_too_wide_for_the_gripper_offers_only_the_sides_that_fit():
    box = ObjectShape("big", BOX, np.array([0.8, 0.0]), np.array([0.3, 0.08]), 0.0,
                      TABLE_TOP, 0.1)  # fmt: skip
    grasps = grasp_candidates(box, robot_xy=np.zeros(2))
    assert all(g.width == pytest.approx(0.08) for g in grasps)
    assert all(abs(g.closing[1]) == pytest.approx(1) for g in grasps)


def test_the_base_stands_a_reach_behind_the_palm_facing_the_approach():
    palm = np.array([0.75, 0.2, 0.77])
    yaw = math.radians(20)
    xy = base_pose(palm, yaw, reach=0.5)
    # In the base's frame the palm is `reach` ahead in the arm's plane y = 0.078.
    c, s = math.cos(yaw), math.sin(yaw)
    local = np.array([[c, s], [-s, c]]) @ (palm[:2] - xy)
    np.testing.assert_allclose(local, [0.5, hsr_arm.ARM_FLEX_ORIGIN[1]])


@pytest.mark.parametrize("approach", [(1.0, 0, 0), (0, 0, -1.0)])
def test_the_hand_posture_points_the_palm_along_the_approach(approach):
    approach = np.array(approach)
    closing = np.array([0, 1.0, 0]) if approach[2] == 0 else np.array([1.0, 1.0, 0]) / 2**0.5
    arm = hand_posture(np.array([0.3, -1.4, 1.0, 0.5, 2.0]), approach, closing)
    position, rotation = hsr_arm.palm_pose(arm)
    np.testing.assert_allclose(rotation[:, 2], approach, atol=1e-9)
    assert abs(rotation[:, 1] @ closing) == pytest.approx(1)
    assert arm[0] == 0.3 and arm[1] == -1.4  # the map's lift and flex are kept

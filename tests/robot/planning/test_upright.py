"""A held object keeps its top up: its tilt is read from the hand as it holds it, inverse
kinematics picks the hand's turn that keeps a cup up where the closing axis's sign leaves it
free, a path whose samples tilt the object past its bound is not taken, and a carry that finds
no way to a handover pose on the map's turn of the arm is planned again to the same pose on the
turn the arm holds the object."""

from __future__ import annotations

import math

import numpy as np
import pytest
from pydrake.math import BsplineBasis
from pydrake.trajectories import BsplineTrajectory

from hsr_handover.hsr import GRIPPER_JOINT, PALM_FRAME
from hsr_handover.robot.perception.object_shapes import BOX, CYLINDER, ObjectShape
from hsr_handover.robot.perception.table_fit import TableEstimate
from hsr_handover.robot.planning import paths, planner
from hsr_handover.robot.planning.handover_pose import HandoverPose
from hsr_handover.robot.planning.inverse_kinematics import PalmGoal, solve_palm_ik
from hsr_handover.robot.planning.paths import PathSearch
from hsr_handover.robot.planning.perceived_scene import PerceivedScene
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.stopwatch import Stopwatch
from hsr_handover.robot.planning.timing import joint_limits
from hsr_handover.robot.planning.trajectory import PathResult
from hsr_handover.robot.planning.upright import (
    BOX_TILT,
    CUP_TILT,
    SLACK,
    keeps_upright,
    path_bound,
    tilt,
    upright_for,
)
from tests.robot.planning.conftest import cup_in_hand

TABLE_TOP = 0.72
CUP = ObjectShape("red", CYLINDER, np.array([0.8, 0.0]), np.array([0.07, 0.07]), 0.0,
                  TABLE_TOP, 0.10)  # fmt: skip


@pytest.fixture(scope="module")
def scene() -> PlanningScene:
    table = TableEstimate(TABLE_TOP, np.array([0.845, 0.0]), np.array([0.6, 1.0]), 0.0, 6000)
    return PlanningScene(PerceivedScene(table, (CUP,), ()))


@pytest.fixture(scope="module")
def level(scene) -> np.ndarray:
    """The arm held out forward and level over the floor, the hand's approach horizontal: a cup
    held so stands up, and a half turn of the wrist turns it over."""
    scene.set_positions({"base_x_joint": -0.6, "arm_lift_joint": 0.3, "arm_flex_joint": -1.57,
                         "wrist_flex_joint": 0.0})  # fmt: skip
    return scene.positions()


def _rolled(scene: PlanningScene, q: np.ndarray, roll: float) -> np.ndarray:
    q = q.copy()
    q[scene.index("wrist_roll_joint")] = roll
    return q


def test_tilt_is_read_from_the_hand_as_it_holds_the_object(scene, level):
    assert tilt(scene, _rolled(scene, level, 3.0)) == 0.0  # nothing held
    with scene.holding("red", level, cup_in_hand(scene, level)):
        assert scene.upright.most == CUP_TILT
        assert tilt(scene, level) == pytest.approx(0.0, abs=1e-6)
        assert math.degrees(tilt(scene, _rolled(scene, level, 0.5))) == pytest.approx(28.6, abs=0.5)
        assert math.degrees(tilt(scene, _rolled(scene, level, 3.0))) > 170.0
    assert scene.upright is None


def test_a_box_may_lie_on_its_side_and_a_cup_may_not():
    box = ObjectShape("blue", BOX, np.zeros(2), np.array([0.06, 0.06]), 0.0, TABLE_TOP, 0.12)
    assert upright_for(box, np.eye(3)).most == BOX_TILT > math.radians(90)
    assert upright_for(CUP, np.eye(3)).most == CUP_TILT < math.radians(30)
    assert upright_for(CUP, np.eye(3)).up_in_hand == pytest.approx([0.0, 0.0, 1.0])


def test_the_bound_of_a_path_is_its_ends_tilt_where_they_pass_it(scene, level):
    tipped = _rolled(scene, level, 1.0)  # 57 degrees
    with scene.holding("red", level, cup_in_hand(scene, level)):
        assert path_bound(scene, level, level) == CUP_TILT
        assert path_bound(scene, tipped, level) == pytest.approx(1.0 + SLACK, abs=1e-3)
        assert keeps_upright(scene, [level, _rolled(scene, level, 0.3), level])
        assert not keeps_upright(scene, [level, _rolled(scene, level, 0.5), level])
        assert keeps_upright(scene, [tipped, _rolled(scene, level, 0.5), level])


def _goal_at(scene: PlanningScene, q: np.ndarray) -> PalmGoal:
    plant, context = scene.plant, scene.plant_context
    plant.SetPositions(context, q)
    palm = plant.GetFrameByName(PALM_FRAME, scene.robot).CalcPoseInWorld(context)
    rotation = palm.rotation().matrix()
    point = palm.translation() + 0.03 * rotation[:, 2]
    return PalmGoal(point, rotation[:, 2], rotation[:, 1], 2 * q[scene.index(GRIPPER_JOINT)])


def test_inverse_kinematics_keeps_a_held_cup_up_where_the_closing_axis_allows_either_turn(
    scene, level
):
    goal = _goal_at(scene, level)
    flipped = _rolled(scene, level, 3.0)  # the hand's other turn, nearest this seed
    free = solve_palm_ik(scene, goal, flipped)
    assert free.ok
    with scene.holding("red", level, cup_in_hand(scene, level)):
        assert tilt(scene, free.q) > math.radians(150)  # what the free solve would hold out
        kept = solve_palm_ik(scene, goal, flipped)
        assert kept.ok, kept.reason
        assert tilt(scene, kept.q) <= CUP_TILT + 1e-3


def test_a_path_that_tilts_the_held_cup_between_its_ends_is_not_taken(scene, level, monkeypatch):
    goal = level.copy()
    goal[scene.index("base_y_joint")] += 0.1
    over = np.linspace(level, goal, 10).T
    over[scene.index("wrist_roll_joint"), 3:7] = 2.0  # the cup swung over on the way
    swung = BsplineTrajectory(BsplineBasis(4, 10), over)
    found = PathResult(ok=True, reason="ok", path=swung)
    monkeypatch.setattr(paths, "optimize_path", lambda *args, **kwargs: found)
    with scene.holding("red", level, cup_in_hand(scene, level)):
        path, reason, _ = paths._verified_path(scene, level, goal, over, ("red",), None)
    assert path is None
    assert "tilts the object held" in reason
    path, _, _ = paths._verified_path(scene, level, goal, over, (), None)
    assert path is not None  # holding nothing, the same path is clear


def _other_turn(scene: PlanningScene, q: np.ndarray) -> np.ndarray:
    """`q` with the arm rolled a half turn, the wrist bent the other way and rolled back: the
    hand where it was, the arm on its other turn."""
    q = q.copy()
    q[scene.index("arm_roll_joint")] += math.pi
    q[scene.index("wrist_flex_joint")] *= -1.0
    q[scene.index("wrist_roll_joint")] += math.pi
    return q


def test_a_handover_pose_is_found_again_on_the_turn_the_arm_holds_the_object(scene, level):
    q_pose = level.copy()
    q_pose[scene.index("wrist_flex_joint")] = -0.4
    q_now = _other_turn(scene, q_pose)
    q_now[scene.index("arm_lift_joint")] = 0.2  # holding it elsewhere, on the other turn
    q_held = planner._as_held(scene, q_pose, q_now, ())
    assert q_held is not None
    assert q_held[scene.index("arm_roll_joint")] == pytest.approx(math.pi, abs=0.5)
    goal, found = _goal_at(scene, q_pose), _goal_at(scene, q_held)
    assert np.linalg.norm(found.point - goal.point) < 0.01
    assert found.approach @ goal.approach > math.cos(math.radians(6))
    assert planner._as_held(scene, q_pose, q_pose, ()) is None  # the same turn: no new pose


def test_a_carry_that_fails_is_planned_again_to_the_pose_on_the_arms_turn(
    scene, level, monkeypatch
):
    pose_q = level.copy()
    pose_q[scene.index("base_y_joint")] += 0.1
    pose = HandoverPose(ok=True, reason="ok", ideal=np.zeros(3), point=np.zeros(3), q=pose_q)
    monkeypatch.setattr(planner, "plan_handover_pose", lambda *args: pose)
    turned = _other_turn(scene, pose_q)
    asked = []

    def as_held(scene, q_pose, q_now, ignore):
        asked.append(q_pose)
        return turned

    monkeypatch.setattr(planner, "_as_held", as_held)
    real, searched = planner.search_path, []

    def search(scene, q_from, q_to, *args, **kwargs):
        searched.append(q_to)
        if len(searched) == 1:
            return PathSearch(ok=False, reason="infeasible: no path (SNOPT kInfeasible)")
        return real(scene, q_from, q_to, *args, **kwargs)

    monkeypatch.setattr(planner, "search_path", search)
    plan = planner.plan_handover(scene, object(), object(), level, joint_limits(scene.plant))
    assert plan.ok, plan.reason
    np.testing.assert_allclose(asked[0], pose_q)
    np.testing.assert_allclose(searched[1], turned)
    np.testing.assert_allclose(plan.goal, turned)
    assert plan.retried == (f"handover pose: {planner.AS_HELD}",)


def test_a_pose_whose_straight_way_tips_the_cup_is_tried_after_the_arms_own_turn(scene, level):
    held = cup_in_hand(scene, level)
    with scene.holding("red", level, held):
        straight = _other_turn(scene, level)
        straight[scene.index("base_y_joint")] += 0.1
        first, _ = next(planner._carry_goals(scene, straight, level, ("red",), Stopwatch()))
        assert first[scene.index("arm_roll_joint")] == pytest.approx(0.0, abs=0.3)  # level's
        same = level.copy()
        same[scene.index("base_y_joint")] += 0.1
        first, found_by = next(planner._carry_goals(scene, same, level, ("red",), Stopwatch()))
        np.testing.assert_allclose(first, same)
        assert found_by == ""

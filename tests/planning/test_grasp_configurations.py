"""Inverse kinematics, paths and the handover pose against a perceived scene (issue 9, parts
3, 5-7): the bundled table with three cups 22 cm apart and a person seated across it."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from hsr_handover.effectivity.arm_map import load_or_build
from hsr_handover.effectivity.mutual_area import ABOVE_TABLE
from hsr_handover.effectivity.person_map import HumanArm, PersonEffectivity
from hsr_handover.hsr import BASE_JOINTS, PALM_FRAME
from hsr_handover.perception.object_shapes import CYLINDER, ObjectShape
from hsr_handover.perception.table_fit import TableEstimate
from hsr_handover.planning.grasp_configurations import UNREACHABLE, grasp_configurations
from hsr_handover.planning.grasps import PAD_OFFSET
from hsr_handover.planning.handover_pose import NO_MUTUAL_AREA, plan_handover_pose
from hsr_handover.planning.inverse_kinematics import MIN_DISTANCE, PalmGoal, solve_palm_ik
from hsr_handover.planning.perceived_scene import Capsule, PerceivedScene
from hsr_handover.planning.planning_scene import PlanningScene
from hsr_handover.planning.trajectory import COLLISION_BOUND, optimize_path

TABLE_TOP = 0.72
CUPS = {"red": -0.22, "green": 0.0, "blue": 0.22}


def _cup(label: str, y: float, x: float = 0.8) -> ObjectShape:
    return ObjectShape(label, CYLINDER, np.array([x, y]), np.array([0.07, 0.07]), 0.0,
                       TABLE_TOP, 0.10)  # fmt: skip


@pytest.fixture(scope="module")
def scene() -> PlanningScene:
    table = TableEstimate(TABLE_TOP, np.array([0.845, 0.0]), np.array([0.6, 1.0]), 0.0, 6000)
    person = (Capsule(np.array([1.75, 0, 0.55]), np.array([1.75, 0, 1.05]), 0.2),
              Capsule(np.array([1.75, 0, 1.1]), np.array([1.7, 0, 1.25]), 0.15))  # fmt: skip
    cups = tuple(_cup(label, y) for label, y in CUPS.items())
    return PlanningScene(PerceivedScene(table, cups, person))


@pytest.fixture(scope="module")
def arm_map():
    return load_or_build()[0]


def _pads(scene: PlanningScene, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    scene.plant.SetPositions(scene.plant_context, q)
    palm = scene.plant.GetFrameByName(PALM_FRAME).CalcPoseInWorld(scene.plant_context)
    return palm.multiply([0, 0, PAD_OFFSET]), palm.rotation().matrix()


@pytest.mark.parametrize("label", CUPS)
def test_each_cup_gets_a_grasp_clear_of_all_but_itself(scene, arm_map, label):
    q_now = scene.positions()
    result = grasp_configurations(scene, arm_map, label, q_now)
    assert result.ok, result.reason
    grasp = result.grasp
    pads, rotation = _pads(scene, result.q_grasp)
    assert np.all(np.abs(pads - grasp.point) <= 0.0051)
    assert rotation[:, 2] @ grasp.approach > np.cos(np.radians(5.1))
    assert scene.clearance(ignore=(label,))[0] >= MIN_DISTANCE - 1e-3
    # The coupled joints hold in the solution, as the plant's mimic joints would hold them.
    A, b = scene.couplings()
    np.testing.assert_allclose(A @ result.q_grasp, b, atol=1e-6)
    pads, _ = _pads(scene, result.q_pregrasp)
    assert np.all(np.abs(pads - grasp.pregrasp_point) <= 0.0051)
    assert scene.clearance()[0] >= MIN_DISTANCE - 1e-3  # the target too, before closing in
    base = result.q_grasp[[scene.index(joint) for joint in BASE_JOINTS[:2]]]
    assert np.linalg.norm(base - q_now[:2]) > 0.1  # the cups are out of reach from the start


def test_a_cup_above_any_reach_is_unreachable_not_an_error(scene, arm_map):
    # On a shelf 1.8 m up: the palm rises to 1.52 m at most; the base could drive anywhere.
    high = dataclasses.replace(_cup("high", 0.0, x=3.0), bottom=1.8)
    shelf = PlanningScene(PerceivedScene(None, (high,)))
    result = grasp_configurations(shelf, arm_map, "high", shelf.positions())
    assert not result.ok and result.reason.startswith(UNREACHABLE)
    assert result.ik_solves == 0  # the map said so before any solve
    missing = grasp_configurations(scene, arm_map, "purple", scene.positions())
    assert not missing.ok and "purple" in missing.reason


def test_inverse_kinematics_refuses_a_goal_inside_the_table(scene):
    goal = PalmGoal(np.array([0.8, 0.4, TABLE_TOP - 0.05]), np.array([1.0, 0, 0]),
                    np.array([0, 1.0, 0]), 0.1)  # fmt: skip
    result = solve_palm_ik(scene, goal, scene.positions())
    assert not result.ok and "no IK solution" in result.reason
    nan = solve_palm_ik(scene, dataclasses.replace(goal, point=np.full(3, np.nan)), result.q)
    assert not nan.ok and "non-finite" in nan.reason


def test_the_optimised_path_keeps_clear_at_its_samples_and_joins_its_ends(scene, arm_map):
    q_now = scene.positions()
    target = grasp_configurations(scene, arm_map, "green", q_now)
    result = optimize_path(scene, q_now, target.q_pregrasp)
    assert result.ok, result.reason
    path = result.path
    np.testing.assert_allclose(path.value(path.start_time()).ravel(), q_now, atol=1e-6)
    np.testing.assert_allclose(path.value(path.end_time()).ravel(), target.q_pregrasp, atol=1e-6)
    clearances = []
    for t in np.linspace(path.start_time(), path.end_time(), 100):
        scene.plant.SetPositions(scene.plant_context, path.value(t).ravel())
        clearances.append(scene.clearance()[0])
    assert min(clearances) > COLLISION_BOUND - 0.012  # may dip between the optimiser's samples


def test_the_handover_pose_meets_the_person_at_a_mutual_node(scene, arm_map):
    shoulder = np.array([1.75, 0.19, 1.03])
    frame = np.column_stack([[-1.0, 0, 0], [0, -1.0, 0], [0, 0, 1.0]])  # facing the robot
    person = PersonEffectivity(HumanArm("r", shoulder, frame, 0.30, 0.25, 0.09))
    pose = plan_handover_pose(scene, arm_map, person, scene.positions())
    assert pose.ok, pose.reason
    assert pose.mutual[np.flatnonzero(np.all(pose.robot_nodes == pose.point, axis=1))].all()
    assert person.reachable(pose.point[None])[0]
    assert pose.point[2] >= TABLE_TOP + ABOVE_TABLE
    pads, _ = _pads(scene, pose.q)
    assert np.all(np.abs(pads - pose.point) <= 0.0051)
    assert scene.clearance()[0] >= MIN_DISTANCE - 1e-3
    # The table is in front of the seated person: the robot comes round it to their side.
    base = pose.q[[scene.index(joint) for joint in BASE_JOINTS]]
    assert base[0] > 0.845 + 0.3 and abs(base[1]) > 0.3, base


def test_a_person_out_of_every_reach_has_no_mutual_area(scene, arm_map):
    frame = np.column_stack([[-1.0, 0, 0], [0, -1.0, 0], [0, 0, 1.0]])
    tiny = HumanArm("r", np.array([1.75, 0.19, 3.5]), frame, 0.1, 0.1, 0.05)  # 3.5 m up
    pose = plan_handover_pose(scene, arm_map, PersonEffectivity(tiny), scene.positions())
    assert not pose.ok and pose.reason.startswith(NO_MUTUAL_AREA)

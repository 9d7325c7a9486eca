"""Inverse kinematics, paths and the handover pose against a perceived scene: the bundled table
with three cups 22 cm apart and a person seated across it."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from hsr_handover.hsr import BASE_JOINTS, FINGER_PER_OPENING, GRIPPER_JOINT, PALM_FRAME
from hsr_handover.robot.effectivity import mutual_area
from hsr_handover.robot.effectivity.arm_map import load_or_build
from hsr_handover.robot.effectivity.mutual_area import ABOVE_TABLE
from hsr_handover.robot.effectivity.person_map import HumanArm, PersonEffectivity
from hsr_handover.robot.perception.object_shapes import BOX, CYLINDER, ObjectShape
from hsr_handover.robot.perception.table_fit import TableEstimate
from hsr_handover.robot.planning import base_placement, grasps, handover_pose, paths, planner
from hsr_handover.robot.planning import grasp_configurations as configurations
from hsr_handover.robot.planning.grasp_configurations import UNREACHABLE, grasp_configurations
from hsr_handover.robot.planning.grasps import GRIP_CLEARANCE, LIFT_HEIGHT, PAD_OFFSET
from hsr_handover.robot.planning.handover_pose import NO_MUTUAL_AREA, plan_handover_pose
from hsr_handover.robot.planning.inverse_kinematics import (
    MIN_DISTANCE,
    IkResult,
    PalmGoal,
    solve_palm_ik,
)
from hsr_handover.robot.planning.paths import find_path
from hsr_handover.robot.planning.perceived_scene import Capsule, PerceivedScene
from hsr_handover.robot.planning.planner import (
    BACK_OFF,
    LOWER,
    PUT_BACK,
    STAGES,
    plan_back_off,
    plan_grasp,
    plan_handover,
    plan_put_back,
)
from hsr_handover.robot.planning.planning_scene import TABLE_MARGIN, PlanningScene
from hsr_handover.robot.planning.timing import joint_limits
from hsr_handover.robot.planning.trajectory import (
    COLLISION_BOUND,
    ESCAPE_SLACK,
    STOWED,
    approached_target,
    optimize_path,
)
from hsr_handover.robot.planning.verification import (
    DIP_ALLOWANCE,
    path_clearances,
    timed_clearance,
)
from tests.robot.planning.conftest import slid_until

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


def _ready(scene: PlanningScene) -> np.ndarray:
    """The robot at the origin, every joint at 0 (the module's scene is shared by the tests)."""
    scene.set_positions({})
    return scene.positions()


def _pads(scene: PlanningScene, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    scene.plant.SetPositions(scene.plant_context, q)
    palm = scene.plant.GetFrameByName(PALM_FRAME).CalcPoseInWorld(scene.plant_context)
    return palm.multiply([0, 0, PAD_OFFSET]), palm.rotation().matrix()


@pytest.mark.parametrize("label", CUPS)
def test_each_cup_gets_a_grasp_clear_of_all_but_itself(scene, arm_map, label):
    q_now = _ready(scene)
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
    lifted, _ = _pads(scene, result.q_lifted)
    assert np.all(np.abs(lifted - grasp.lifted_point) <= 0.0051)
    np.testing.assert_allclose(result.q_lifted[:3], result.q_grasp[:3])  # the base stays
    # Standing off before closing in, the hand keeps clear of the target too.
    assert scene.clearance_at(result.q_pregrasp) >= MIN_DISTANCE - 1e-3
    base = result.q_grasp[[scene.index(joint) for joint in BASE_JOINTS[:2]]]
    assert np.linalg.norm(base - q_now[:2]) > 0.1  # the cups are out of reach from the start


def test_a_cup_above_any_reach_is_unreachable_not_an_error(scene, arm_map):
    # On a shelf 1.8 m up: the palm rises to 1.52 m at most; the base could drive anywhere.
    high = dataclasses.replace(_cup("high", 0.0, x=3.0), bottom=1.8)
    shelf = PlanningScene(PerceivedScene(None, (high,)))
    result = grasp_configurations(shelf, arm_map, "high", shelf.positions())
    assert not result.ok and result.reason.startswith(UNREACHABLE)
    assert result.ik_solves == 0  # the map said so before any solve
    missing = grasp_configurations(scene, arm_map, "purple", _ready(scene))
    assert not missing.ok and "purple" in missing.reason


def test_a_box_deep_in_a_high_table_is_taken_from_above_beside_the_table(arm_map, monkeypatch):
    """The staggered layout's purple box: 35 cm in from the near edge of a table 80 cm high
    and 8 cm from its side. From above, facing it from where the robot stands, no base pose
    clear of the table reaches it; turned round it, the base stands beside the table."""
    table = TableEstimate(0.80, np.array([0.88, -0.05]), np.array([0.55, 0.9]), 0.0, 6000)
    box = ObjectShape("purple", BOX, np.array([0.95, 0.32]), np.array([0.07, 0.05]), 0.0,
                      0.80, 0.10)  # fmt: skip
    deep = PlanningScene(PerceivedScene(table, (box,)))
    deep.set_positions({"base_x_joint": 0.0, "base_y_joint": -0.25, "base_yaw_joint": 0.25})
    q_now = deep.positions()
    from_above = lambda shape, robot_xy: [  # noqa: E731
        grasp for grasp in grasps.grasp_candidates(shape, robot_xy) if grasp.kind == "top"
    ]
    monkeypatch.setattr(configurations, "grasp_candidates", from_above)
    result = grasp_configurations(deep, arm_map, "purple", q_now)
    assert result.ok, result.reason
    base = result.q_grasp[[deep.index(joint) for joint in BASE_JOINTS[:2]]]
    assert base[1] > 0.4 + 0.2  # beside the table's side, not at its near edge
    monkeypatch.setattr(base_placement, "ROUND_TURNS_DEG", ())
    facing = grasp_configurations(deep, arm_map, "purple", q_now)
    assert not facing.ok and facing.reason.startswith(UNREACHABLE)
    assert facing.ik_solves == 0  # no base pose clear of the table to try


def test_a_box_in_the_middle_of_a_high_table_is_taken_leaning_over_it(arm_map, monkeypatch):
    """A generated layout's yellow box, 30 cm in from the near edge of a table 0.81 m high: from
    straight above the arm falls 4-6 cm short of it, and no side grasp has a base pose clear
    of the table; leaning over it, the hand reaches it from where the robot stands."""
    table = TableEstimate(0.806, np.array([0.94, 0.0]), np.array([0.59, 1.14]), 0.0, 5500)
    box = ObjectShape("yellow", BOX, np.array([0.946, -0.036]), np.array([0.04, 0.08]), -0.77,
                      0.806, 0.11)  # fmt: skip
    deep = PlanningScene(PerceivedScene(table, (box,)))
    deep.set_positions({"base_x_joint": 0.134, "base_y_joint": 0.099, "base_yaw_joint": -0.387})
    q_now = deep.positions()
    result = grasp_configurations(deep, arm_map, "yellow", q_now)
    assert result.ok, result.reason
    assert result.grasp.kind == "leaning"
    base = result.q_grasp[[deep.index(joint) for joint in BASE_JOINTS[:2]]]
    assert base[0] < 0.645 - 0.2  # before the table's near edge, not round it
    upright = lambda shape, robot_xy: [  # noqa: E731
        grasp for grasp in grasps.grasp_candidates(shape, robot_xy) if grasp.kind != "leaning"
    ]
    monkeypatch.setattr(configurations, "grasp_candidates", upright)
    assert not grasp_configurations(deep, arm_map, "yellow", q_now).ok


def test_an_object_under_the_persons_hand_is_unreachable_and_the_reason_says_whose_hand(arm_map):
    table = TableEstimate(0.72, np.array([0.9, 0.0]), np.array([0.6, 1.0]), 0.0, 5500)
    box = ObjectShape("yellow", BOX, np.array([0.85, 0.0]), np.array([0.05, 0.08]), 0.0,
                      0.72, 0.1)  # fmt: skip
    forearm = Capsule(np.array([1.3, 0.1, 0.9]), np.array([0.85, 0.0, 0.86]), 0.095,
                      "l_elbow-l_wrist")  # fmt: skip
    scene = PlanningScene(PerceivedScene(table, (box,), (forearm,)))
    result = grasp_configurations(scene, arm_map, "yellow", scene.positions())
    assert not result.ok and result.reason.startswith(UNREACHABLE)
    assert "the person's l_elbow-l_wrist is within 5 cm" in result.reason
    away = dataclasses.replace(forearm, start=forearm.start + 0.5, end=forearm.end + [0.5, 0, 0])
    clear = PlanningScene(PerceivedScene(table, (box,), (away,)))
    assert grasp_configurations(clear, arm_map, "yellow", clear.positions()).ok


def test_inverse_kinematics_refuses_a_goal_inside_the_table(scene):
    goal = PalmGoal(np.array([0.8, 0.4, TABLE_TOP - 0.05]), np.array([1.0, 0, 0]),
                    np.array([0, 1.0, 0]), 0.1)  # fmt: skip
    result = solve_palm_ik(scene, goal, _ready(scene))
    assert not result.ok and "no IK solution" in result.reason
    nan = solve_palm_ik(scene, dataclasses.replace(goal, point=np.full(3, np.nan)), result.q)
    assert not nan.ok and "non-finite" in nan.reason


def test_the_optimised_path_keeps_clear_at_its_samples_and_joins_its_ends(scene, arm_map):
    q_now = _ready(scene)
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


def test_a_path_that_dips_between_its_samples_is_optimised_again_at_more(monkeypatch):
    """Along the table's long side, from one end to the other: three collision samples let the
    base cut through the table between them; the planner's check finds it and doubles the
    samples until the path keeps clear throughout."""
    table = TableEstimate(TABLE_TOP, np.array([0.845, 0.0]), np.array([0.6, 1.0]), 0.0, 6000)
    scene = PlanningScene(PerceivedScene(table, (), ()))
    stowed = {joint: value for joint, value in STOWED.items() if joint != "torso_lift_joint"}
    scene.set_positions({"base_x_joint": 0.845, "base_y_joint": -0.85, **stowed})
    q_from = scene.positions()
    scene.set_positions({"base_x_joint": 0.845, "base_y_joint": 0.85, **stowed})
    q_to = scene.positions()
    dense = 96
    loose = optimize_path(scene, q_from, q_to, samples=7)
    assert loose.ok and path_clearances(scene, loose.path, (), dense).min() < -0.05
    monkeypatch.setattr(paths, "COLLISION_SAMPLES", 7)
    path, reason = find_path(scene, q_from, q_to, (), straight=False)
    assert path is not None, reason
    floor = COLLISION_BOUND - DIP_ALLOWANCE
    assert path_clearances(scene, path, (), dense).min() >= floor - 2e-3


def test_a_start_the_perceived_table_crowds_still_gets_a_path(scene, arm_map):
    """The base driven up to 6 mm from the table's edge (inside the 13 mm bound): the path
    gets away from it, no nearer than it began, and on to the pre-grasp."""
    q_now = slid_until(scene, _ready(scene), BASE_JOINTS[0], 0.006, (0.0, 0.4))
    start = scene.clearance_at(q_now)
    assert start < COLLISION_BOUND
    target = grasp_configurations(scene, arm_map, "green", q_now)
    result = optimize_path(scene, q_now, target.q_pregrasp)
    assert result.ok, result.reason
    path = result.path
    times = np.linspace(path.start_time(), path.end_time(), 100)
    clearances = [scene.clearance_at(path.value(t).ravel()) for t in times]
    assert min(clearances) > start - ESCAPE_SLACK - 0.012  # may dip between the samples


def test_the_handover_pose_meets_the_person_at_a_mutual_node(scene, arm_map):
    shoulder = np.array([1.75, 0.19, 1.03])
    frame = np.column_stack([[-1.0, 0, 0], [0, -1.0, 0], [0, 0, 1.0]])  # facing the robot
    person = PersonEffectivity(HumanArm("r", shoulder, frame, 0.30, 0.25, 0.09))
    pose = plan_handover_pose(scene, arm_map, person, _ready(scene))
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


def test_an_ik_failing_from_the_aims_placement_is_tried_from_the_points_own(
    scene, arm_map, monkeypatch
):
    """The mutual node nearest the aim can lie 10 cm from it; seeded for the aim, the solver
    may run out of iterations short of the node (as in the demo). The pose is then
    sought from a base placed for the node itself, before any aim turned to the side."""
    shoulder = np.array([1.75, 0.19, 1.03])
    frame = np.column_stack([[-1.0, 0, 0], [0, -1.0, 0], [0, 0, 1.0]])
    person = PersonEffectivity(HumanArm("r", shoulder, frame, 0.30, 0.25, 0.09))
    seeds, goals, real = [], [], handover_pose.solve_palm_ik

    def first_runs_out(scene, goal, seed, ignore=()):
        seeds.append(np.array(seed))
        goals.append(goal)
        if len(seeds) == 1:
            return IkResult(
                ok=False, q=np.array(seed), reason="no IK solution (SNOPT kIterationLimit)"
            )
        return real(scene, goal, seed, ignore=ignore)

    monkeypatch.setattr(handover_pose, "solve_palm_ik", first_runs_out)
    pose = plan_handover_pose(scene, arm_map, person, _ready(scene))
    assert pose.ok, pose.reason
    assert len(seeds) == 2 and not np.allclose(seeds[0], seeds[1])
    assert goals[1] is goals[0]  # the same node, the same approach
    np.testing.assert_allclose(pose.ideal, mutual_area.handover_aims(person.arm)[0])


def test_a_person_standing_behind_a_wide_table_is_handed_to_from_the_side(arm_map, monkeypatch):
    """The table's far edge 0.45 m in front of a standing person and 1.4 m wide: the robot
    cannot stand anywhere to reach the point straight ahead of them, so it aims at the point
    turned toward the receiving (right) arm's side, which it reaches from beside the table."""
    table = TableEstimate(0.76, np.array([0.845, 0.0]), np.array([0.6, 1.4]), 0.0, 6000)
    x = 0.845 + 0.3 + 0.45
    body = (Capsule(np.array([x + 0.05, 0, 0.2]), np.array([x + 0.05, 0, 1.45]), 0.2),)
    standing = PlanningScene(PerceivedScene(table, (), body))
    frame = np.column_stack([[-1.0, 0, 0], [0, -1.0, 0], [0, 0, 1.0]])
    person = PersonEffectivity(HumanArm("r", np.array([x, 0.19, 1.43]), frame, 0.33, 0.27, 0.09))
    pose = plan_handover_pose(standing, arm_map, person, _ready(standing))
    assert pose.ok, pose.reason
    assert pose.ideal[1] > person.arm.shoulder[1] + 0.1  # turned to the person's right (+y)
    assert person.reachable(pose.point[None])[0]
    monkeypatch.setattr(mutual_area, "SIDE_TURNS_DEG", (0.0,))
    straight = plan_handover_pose(standing, arm_map, person, _ready(standing))
    assert not straight.ok and straight.reason.startswith(NO_MUTUAL_AREA)


def test_a_person_out_of_every_reach_has_no_mutual_area(scene, arm_map):
    frame = np.column_stack([[-1.0, 0, 0], [0, -1.0, 0], [0, 0, 1.0]])
    tiny = HumanArm("r", np.array([1.75, 0.19, 3.5]), frame, 0.1, 0.1, 0.05)  # 3.5 m up
    pose = plan_handover_pose(scene, arm_map, PersonEffectivity(tiny), _ready(scene))
    assert not pose.ok and pose.reason.startswith(NO_MUTUAL_AREA)


def test_a_grasp_plan_is_timed_and_clear_every_10_ms(scene, arm_map):
    limits = joint_limits(scene.plant)
    plan = plan_grasp(scene, arm_map, "blue", _ready(scene), limits)
    assert plan.ok, plan.reason
    assert [motion.name for motion in plan.motions] == ["move", "approach", "lift"]
    assert [motion.ignore for motion in plan.motions] == [(), ("blue",), ("blue",)]
    assert set(plan.seconds) == set(STAGES) and plan.plan_seconds > 0
    assert 1.0 < plan.duration < 15.0
    for motion in plan.motions:
        assert timed_clearance(scene, motion) >= COLLISION_BOUND - 0.012
    # The approach may touch the cup only as its end does.
    _, approaching = plan.motions[1].sample(0.01)
    bound = approached_target(scene, approaching[-1], "blue").bound
    to_cup = [scene.clearances_at(q).get("blue", np.inf) for q in approaching]
    assert min(to_cup) >= bound - DIP_ALLOWANCE
    # The gripper opens as the robot sets off: the move is planned open from its start, as
    # wide as the grasp's opening, and no path moves the fingers on its own.
    finger = scene.index(GRIPPER_JOINT)
    _, moving = plan.motions[0].sample(0.01)
    opening = 0.07 + GRIP_CLEARANCE
    np.testing.assert_allclose(moving[:, finger], FINGER_PER_OPENING * opening, atol=1e-6)
    _, positions = plan.motions[2].sample(0.01)
    np.testing.assert_allclose(positions[-1], plan.goal, atol=1e-6)
    lifted, _ = _pads(scene, plan.goal)
    grasped, _ = _pads(scene, plan.motions[1].sample(0.01)[1][-1])
    np.testing.assert_allclose(lifted - grasped, [0, 0, LIFT_HEIGHT], atol=0.011)
    # Then, holding the cup, to the person: a carry round the table into the mutual area.
    shoulder = np.array([1.75, 0.19, 1.03])
    frame = np.column_stack([[-1.0, 0, 0], [0, -1.0, 0], [0, 0, 1.0]])
    person = PersonEffectivity(HumanArm("r", shoulder, frame, 0.30, 0.25, 0.09))
    handover = plan_handover(scene, arm_map, person, plan.goal, limits, plan.held)
    assert handover.ok, handover.reason
    (carry,) = handover.motions
    assert carry.name == "carry" and carry.ignore == ("blue",)
    assert plan.held.label == "blue"
    with scene.holding(plan.held.label, plan.held.q_grasp):  # the cup, too, keeps clear
        assert timed_clearance(scene, carry) >= COLLISION_BOUND - 0.012
    pose = handover.pose  # what the replay draws: the maps and the point handed over at
    assert pose.ok and pose.mutual.any() and len(pose.mutual) == len(pose.robot_nodes)
    nearest = np.linalg.norm(pose.robot_nodes[pose.mutual] - pose.point, axis=1).min()
    assert nearest < 1e-9  # the point is one of the mutual area's nodes


def test_an_unreachable_target_plans_nothing_and_says_why(scene, arm_map):
    plan = plan_grasp(scene, arm_map, "purple", _ready(scene), joint_limits(scene.plant))
    assert not plan.ok and plan.motions == () and "purple" in plan.reason


def test_a_posture_plan_ends_at_the_posture_clear_of_the_table(scene):
    """The watch view's move (`plan_posture`): the torso raised 0.25 m and the arm folded down
    from the ready posture, the robot's centre 0.55 m from the table's near edge."""
    scene.set_positions({"wrist_flex_joint": -1.57})
    q_now = scene.positions()
    scene.set_positions({"arm_lift_joint": 0.5, "arm_flex_joint": -2.62, "wrist_flex_joint": -1.57})
    goal = scene.positions()
    plan = planner.plan_posture(scene, q_now, goal, joint_limits(scene.plant))
    assert plan.ok, plan.reason
    (motion,) = plan.motions
    assert motion.name == planner.POSTURE and motion.ignore == ()
    _, positions = motion.sample(0.01)
    np.testing.assert_allclose(positions[0], q_now, atol=1e-6)
    np.testing.assert_allclose(positions[-1], goal, atol=1e-6)
    assert timed_clearance(scene, motion) >= COLLISION_BOUND - 0.012


def test_a_posture_inside_the_table_plans_nothing_and_says_why(scene):
    scene.set_positions({})
    q_now = scene.positions()
    scene.set_positions({"base_x_joint": 0.7, "arm_lift_joint": 0.2})
    inside = scene.positions()
    plan = planner.plan_posture(scene, q_now, inside, joint_limits(scene.plant))
    assert not plan.ok and plan.motions == () and plan.reason.startswith(planner.POSTURE)


def test_an_object_is_put_back_the_way_it_came_and_lowered_onto_its_place(scene, arm_map):
    """The person asked for another cup while this one was carried: from part way along the
    carry, back along it to where the lift ended, then the lift backwards."""
    limits = joint_limits(scene.plant)
    grasp = plan_grasp(scene, arm_map, "red", _ready(scene), limits)
    assert grasp.ok, grasp.reason
    shoulder = np.array([1.75, 0.19, 1.03])
    frame = np.column_stack([[-1.0, 0, 0], [0, -1.0, 0], [0, 0, 1.0]])
    person = PersonEffectivity(HumanArm("r", shoulder, frame, 0.30, 0.25, 0.09))
    handover = plan_handover(scene, arm_map, person, grasp.goal, limits, grasp.held)
    assert handover.ok, handover.reason
    _, carried = handover.motions[0].sample(0.05)
    came = list(carried[: len(carried) // 2])
    plan = plan_put_back(scene, came[-1], grasp.held, grasp.goal, limits, came)
    assert plan.ok, plan.reason
    assert [motion.name for motion in plan.motions] == [PUT_BACK, LOWER]
    back, lower = plan.motions
    with scene.holding(grasp.held.label, grasp.held.q_grasp):  # the cup keeps clear on the way
        assert timed_clearance(scene, back) >= COLLISION_BOUND - 0.012
    _, lowering = lower.sample(0.01)
    np.testing.assert_allclose(lowering[0], grasp.goal, atol=1e-6)
    np.testing.assert_allclose(lowering[-1], grasp.held.q_grasp, atol=1e-6)
    # Still where the lift ended: only the lift backwards.
    at_lift = plan_put_back(scene, grasp.goal, grasp.held, grasp.goal, limits)
    assert at_lift.ok and [motion.name for motion in at_lift.motions] == [LOWER]
    # Let go of, the hand backs straight off it, to plan the next grasp from there.
    off = plan_back_off(scene, grasp.held.q_grasp, limits, "red")
    assert off.ok and [motion.name for motion in off.motions] == [BACK_OFF], off.reason
    assert scene.clearances_at(off.goal)["red"] >= COLLISION_BOUND
    clear = plan_back_off(scene, off.goal, limits, "red")
    assert clear.ok and clear.motions == ()


def test_what_is_remembered_of_the_object_where_it_stood_does_not_stop_its_put_back(scene, arm_map):
    """The arm split the cup's blob in two as it closed in, and the smaller piece, `red#2`, is
    remembered where the cup stood: it is the cup, and putting the cup back there is no
    collision with it."""
    limits = joint_limits(scene.plant)
    grasp = plan_grasp(scene, arm_map, "red", _ready(scene), limits)
    assert grasp.ok, grasp.reason
    piece = ObjectShape("red#2", BOX, grasp.held.shape.center + [0.01, 0.0],
                        np.array([0.025, 0.03]), 0.0, TABLE_TOP, 0.10)  # fmt: skip
    remembered = PlanningScene(
        dataclasses.replace(scene.scene, objects=(*scene.scene.objects, piece))
    )
    assert remembered.seen_where_it_stood(grasp.held.shape) == ("red#2",)
    plan = plan_put_back(remembered, grasp.goal, grasp.held, grasp.goal, limits)
    assert plan.ok, plan.reason
    assert [motion.name for motion in plan.motions] == [LOWER]


def test_a_base_ruled_out_in_the_table_is_not_clear(scene):
    """`_in_table` rules a base out without a distance query only where the folded robot
    is nearer the table than BASE_CLEARANCE: over a grid of bases round the table, the
    query agrees wherever it rules one out, and it rules out bases inside the table and just
    beside it."""
    q_ready = _ready(scene)
    x, y = (scene.index(joint) for joint in BASE_JOINTS[:2])
    ruled_out = 0
    for bx in np.linspace(0.2, 1.5, 27):
        for by in np.linspace(-0.9, 0.9, 19):
            q = q_ready.copy()
            q[x], q[y] = bx, by
            if base_placement._in_table(scene, q, ()):
                ruled_out += 1
                folded = scene.clearance_at(base_placement._folded(scene, q))
                assert folded < base_placement.BASE_CLEARANCE
    assert ruled_out > 100
    # The base disc 2 cm from the table's near edge (its planning solid widened by
    # TABLE_MARGIN): well within BASE_CLEARANCE.
    table = scene.scene.table
    near_edge = table.center[0] - table.size[0] / 2 - TABLE_MARGIN
    q = q_ready.copy()
    q[x], q[y] = near_edge - base_placement.BASE_DISC_RADIUS - 0.02, table.center[1]
    assert base_placement._in_table(scene, q, ())
    assert not base_placement._in_table(scene, q, ("table",))

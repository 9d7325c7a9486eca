"""Where the robot stands and holds the object out for the person.

The person's effectivity gives the ideal handover point (effectivity.mutual_area's rule), and
after it the same point turned toward the receiving arm's side. For each aim in turn, the robot
faces the person from the front if it can stand there, else turned round the person by
HANDOVER_TURNS_DEG, up to their side (the table is usually in front of a seated person); at the
first base pose that keeps clear, the arm's effectivity map placed there meets the person's
range in the mutual area, the handover point is the mutual node nearest the aim, and inverse
kinematics, seeded by eq. 11 at the aim, confirms the hand reaches it.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from hsr_handover.hsr import ARM_JOINTS, BASE_JOINTS, GRIPPER_JOINT, TORSO_JOINT
from hsr_handover.robot.effectivity.arm_map import ArmEffectivity
from hsr_handover.robot.effectivity.mutual_area import handover_aims, handover_point
from hsr_handover.robot.effectivity.person_map import PersonEffectivity
from hsr_handover.robot.planning.base_placement import hand_posture, place_base, with_arm
from hsr_handover.robot.planning.grasps import PAD_OFFSET
from hsr_handover.robot.planning.inverse_kinematics import PalmGoal, solve_palm_ik
from hsr_handover.robot.planning.outcome import Outcome
from hsr_handover.robot.planning.planning_scene import PlanningScene

HANDOVER_TURNS_DEG = (0.0, 30.0, -30.0, 60.0, -60.0, 90.0, -90.0)
"""The robot faces the person from in front or from the side, never from behind (a person
does not see what comes from behind; the chair is there)."""
NO_MUTUAL_AREA = "no mutual area"
NEIGHBOUR_SEEDS = 3  # map nodes round the point whose arms seed a retry of a failed IK
RETRIED_POSES = 2  # failed poses retried from other seeds, in the order first tried


@dataclasses.dataclass(frozen=True, kw_only=True)
class HandoverPose(Outcome):
    """`ok` with the configuration `q` handing over at `point` (world, m), or not with the
    `reason`. `robot_nodes` (n, 3, world) is the arm's map at the chosen base and `mutual` the
    mask of those the person reaches too; `ideal` is the rule's point aimed at (the first aim
    when none worked)."""

    ideal: np.ndarray
    point: np.ndarray | None = None
    q: np.ndarray | None = None
    robot_nodes: np.ndarray | None = None
    mutual: np.ndarray | None = None
    found_by: str = ""  # the retry's seed that found it, "" for the first tries


def nodes_in_world(arm_map: ArmEffectivity, base: np.ndarray) -> np.ndarray:
    """The arm map's nodes (n, 3) for the base at (x, y, yaw)."""
    c, s = math.cos(base[2]), math.sin(base[2])
    rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    return arm_map.nodes @ rotation.T + np.array([base[0], base[1], 0.0])


def unseeded_handover_pose(
    scene: PlanningScene,
    person: PersonEffectivity,
    q_now: np.ndarray,
    ignore: tuple[str, ...] = (),
) -> HandoverPose:
    """The baseline without the arm's map: the hand at the rule's ideal point, the base a
    fixed reach from it, facing the person or turned round them, IK from the arm as it is."""
    opening = 2 * q_now[scene.index(GRIPPER_JOINT)]
    reason = f"{NO_MUTUAL_AREA}: no base pose clear of the scene reaches the person"
    aims = handover_aims(person.arm)
    for aim, (approach, closing) in _aims_and_approaches(aims, person):
        for placement in place_base(scene, None, aim, approach, closing, q_now, ignore):
            goal = PalmGoal(aim, approach, closing, opening)
            result = solve_palm_ik(scene, goal, placement.q, ignore=ignore)
            if result.ok:
                return HandoverPose(ok=True, reason="ok", ideal=aim, point=aim, q=result.q)
            reason = f"unreachable: {result.reason} at the handover point"
    return HandoverPose(ok=False, reason=reason, ideal=aims[0])


def _aims_and_approaches(aims: list[np.ndarray], person: PersonEffectivity):
    """Each aim with each approach, the aims in turn."""
    for aim in aims:
        for approach, closing in _approaches(person):
            yield aim, (approach, closing)


def _approaches(person: PersonEffectivity):
    """The hand's horizontal approach and closing axes, facing the person first."""
    facing = -person.arm.frame[:, 0] * np.array([1.0, 1.0, 0.0])
    facing /= max(np.linalg.norm(facing), 1e-9)
    for turn in np.radians(HANDOVER_TURNS_DEG):
        c, s = math.cos(turn), math.sin(turn)
        approach = np.array([c * facing[0] - s * facing[1], s * facing[0] + c * facing[1], 0.0])
        yield approach, np.array([-approach[1], approach[0], 0.0])


def plan_handover_pose(
    scene: PlanningScene,
    arm_map: ArmEffectivity,
    person: PersonEffectivity,
    q_now: np.ndarray,
    ignore: tuple[str, ...] = (),
) -> HandoverPose:
    """The robot's handover configuration from `q_now` (plant positions; the gripper as it
    holds the object), clear of all but `ignore` (the object held). Never raises: an
    unreachable person gives `ok` False and why."""
    table = None if scene.scene.table is None else scene.scene.table.height
    reason = f"{NO_MUTUAL_AREA}: no base pose clear of the scene reaches the person"
    aims = handover_aims(person.arm)
    failed = []  # (the pose it would have been, its goal and seed) where IK failed
    for aim, (approach, closing) in _aims_and_approaches(aims, person):
        for placement in place_base(scene, arm_map, aim, approach, closing, q_now, ignore, 1):
            base = placement.q[[scene.index(joint) for joint in BASE_JOINTS]]
            robot_nodes = nodes_in_world(arm_map, base)
            body = scene.scene.person
            point, mutual = handover_point(robot_nodes, person, table, body, aim)
            if point is None:
                reason = f"{NO_MUTUAL_AREA}: the areas do not meet where the robot can stand"
                continue
            opening = 2 * q_now[scene.index(GRIPPER_JOINT)]
            goal = PalmGoal(point, approach, closing, opening)
            result = _ik_at_point(scene, arm_map, goal, placement.q, q_now, ignore)
            pose = HandoverPose(ok=True, reason="ok", ideal=aim, point=point, q=result.q,
                                robot_nodes=robot_nodes, mutual=mutual)  # fmt: skip
            if result.ok:
                return pose
            reason = f"unreachable: {result.reason} at the handover point"
            failed.append((pose, goal, placement.q))
    return _retried(scene, arm_map, failed, q_now, ignore) or HandoverPose(
        ok=False, reason=reason, ideal=aims[0]
    )


def _retried(scene, arm_map, failed, q_now: np.ndarray, ignore) -> HandoverPose | None:
    """The first pose whose IK, failed from its first seeds, is found from other seeds
    (`other_seeds`: the map's nodes round the point, the arm as it holds the object now), in
    the order they were tried; None if none is."""
    for pose, goal, seed in failed[:RETRIED_POSES]:
        for name, q_seed in other_seeds(scene, arm_map, goal, seed, q_now):
            result = solve_palm_ik(scene, goal, q_seed, ignore=ignore)
            if result.ok:
                return dataclasses.replace(pose, q=result.q, found_by=name)
    return None


def other_seeds(
    scene: PlanningScene,
    arm_map: ArmEffectivity,
    goal: PalmGoal,
    seed: np.ndarray,
    q_now: np.ndarray,
) -> list[tuple[str, np.ndarray]]:
    """Seeds for a retry at `goal` with the base where `seed` has it: `map_seeds`, then the
    arm as it is at `q_now` (the previous plan's end)."""
    as_it_is = seed.copy()
    arm_at = [scene.index(joint) for joint in (*ARM_JOINTS, TORSO_JOINT)]
    as_it_is[arm_at] = q_now[arm_at]
    return [*map_seeds(scene, arm_map, goal, seed), ("arm as it is", as_it_is)]


def map_seeds(
    scene: PlanningScene, arm_map: ArmEffectivity, goal: PalmGoal, seed: np.ndarray
) -> list[tuple[str, np.ndarray]]:
    """`seed` with the arm at each of the NEIGHBOUR_SEEDS map nodes nearest the palm at `goal`
    (eq. 11 blends them; one alone can lie on the other side of a joint limit or an obstacle),
    the hand turned to the goal, the base where `seed` has it."""
    x, y, yaw = (scene.index(joint) for joint in BASE_JOINTS)
    c, s = math.cos(seed[yaw]), math.sin(seed[yaw])
    to_base = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
    palm = np.asarray(goal.point, float) - PAD_OFFSET * np.asarray(goal.approach, float)
    local = to_base @ (palm - np.array([seed[x], seed[y], 0.0]))
    nearest = np.argsort(np.linalg.norm(arm_map.nodes - local, axis=1))[:NEIGHBOUR_SEEDS]
    seeds = []
    for rank, node in enumerate(nearest):
        arm = hand_posture(arm_map.joints[node], to_base @ goal.approach, to_base @ goal.closing)
        seeds.append((f"map node {rank + 1}", with_arm(scene, seed, arm)))
    return seeds


def _ik_at_point(scene, arm_map, goal: PalmGoal, seed: np.ndarray, q_now: np.ndarray, ignore):
    """IK for the hand at `goal` from `seed` (placed for the aim); failing that, from a base
    placed for the goal's own point: the mutual node nearest the aim can lie 10 cm from it,
    and seeded for the aim the solver may run out of iterations short of it."""
    result = solve_palm_ik(scene, goal, seed, ignore=ignore)
    if result.ok:
        return result
    for placement in place_base(scene, arm_map, goal.point, goal.approach, goal.closing, q_now,
                                ignore, 1):  # fmt: skip
        retry = solve_palm_ik(scene, goal, placement.q, ignore=ignore)
        if retry.ok:
            return retry
    return result

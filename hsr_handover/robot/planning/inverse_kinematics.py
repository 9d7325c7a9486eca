"""Inverse kinematics of the whole HSR against the planning scene (Drake's InverseKinematics,
solved by SNOPT): the finger pads at a point, the hand along an approach, the fingers across a
closing axis, at least `min_distance` from every obstacle that is not ignored, the torso and
the right finger coupled by linear constraints, the head and the fingers held where they are,
the base free within a box around its seed, and an object held kept up (`upright`).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from pydrake.multibody.inverse_kinematics import InverseKinematics

from hsr_handover.hsr import BASE_JOINTS, GRIPPER_JOINT, HEAD_JOINTS, PALM_FRAME
from hsr_handover.robot.planning.grasps import PAD_OFFSET
from hsr_handover.robot.planning.outcome import Outcome
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.solving import solve, solved, verdict
from hsr_handover.robot.planning.upright import turned_up

MIN_DISTANCE = 0.02  # m from every obstacle at an IK solution
POINT_TOLERANCE = 0.005  # m, each axis, the pads' centre from its target
ANGLE_TOLERANCE = math.radians(5)  # the hand's approach and closing axes
BASE_SLACK = (0.15, 0.15, 0.3)  # m, m, rad the base may move from its seed
POSTURE_WEIGHT = 1.0  # of the squared distance to the seed: the nearest solution wins


@dataclasses.dataclass(frozen=True)
class PalmGoal:
    """Where the pads' centre goes (m, world), the hand's unit approach (palm z) and the unit
    closing axis (palm y, either sign), with the fingertips `opening` (m) apart."""

    point: np.ndarray
    approach: np.ndarray
    closing: np.ndarray
    opening: float


@dataclasses.dataclass(frozen=True, kw_only=True)
class IkResult(Outcome):
    """`ok` with the plant's positions `q`, or not with the `reason`."""

    q: np.ndarray


def palm_goal(scene: PlanningScene, q: np.ndarray) -> PalmGoal:
    """The hand as it is at `q` (plant positions), as a goal: its pads' centre, its axes and
    its opening."""
    plant, context = scene.plant, scene.plant_context
    plant.SetPositions(context, q)
    palm = plant.GetFrameByName(PALM_FRAME, scene.robot).CalcPoseInWorld(context)
    axes = palm.rotation().matrix()
    point = palm.translation() + PAD_OFFSET * axes[:, 2]
    return PalmGoal(point, axes[:, 2], axes[:, 1], 2 * q[scene.index(GRIPPER_JOINT)])


def solve_palm_ik(
    scene: PlanningScene,
    goal: PalmGoal,
    seed: np.ndarray,
    ignore: tuple[str, ...] = (),
    base_fixed: bool = False,
    min_distance: float = MIN_DISTANCE,
) -> IkResult:
    """The configuration nearest `seed` (plant positions) that puts the hand at `goal`, clear
    of everything but the obstacles named in `ignore`; the base stays at the seed's pose when
    `base_fixed`. Never raises for an unreachable goal: `ok` is False and `reason` says why."""
    seed = np.asarray(seed, dtype=float)
    if not (np.all(np.isfinite(seed)) and np.all(np.isfinite(goal.point))):
        return IkResult(ok=False, q=seed, reason="non-finite seed or goal")
    plant = scene.plant
    seed = turned_up(scene, np.clip(seed, plant.GetPositionLowerLimits(),
                                    plant.GetPositionUpperLimits()))  # fmt: skip
    with scene.ignoring(ignore):
        ik = _build(scene, goal, seed, base_fixed, min_distance)
        result = solve(ik.prog(), seed)
        usable = solved(ik.prog(), result)
    q = result.GetSolution(ik.q())
    if not usable:
        solver = f"{result.get_solver_id().name()} {result.get_solution_result().name}"
        failure = f"no IK solution ({solver})"
        return IkResult(ok=False, q=q, reason=f"{failure}, {verdict(failure)}")
    return IkResult(ok=True, q=q, reason="ok")


def _build(scene, goal: PalmGoal, seed, base_fixed: bool, min_distance: float):
    plant = scene.plant
    palm, world = plant.GetFrameByName(PALM_FRAME, scene.robot), plant.world_frame()
    ik = InverseKinematics(plant, scene.plant_context)
    point = np.asarray(goal.point, dtype=float)
    ik.AddPositionConstraint(palm, [0, 0, PAD_OFFSET], world, point - POINT_TOLERANCE,
                             point + POINT_TOLERANCE)  # fmt: skip
    ik.AddAngleBetweenVectorsConstraint(world, goal.approach, palm, [0, 0, 1], 0.0,
                                        ANGLE_TOLERANCE)  # fmt: skip
    # The fingers close along +-y: the palm's y is square to the approach-closing normal.
    normal = np.cross(goal.approach, goal.closing)
    ik.AddAngleBetweenVectorsConstraint(world, normal, palm, [0, 1, 0],
                                        math.pi / 2 - ANGLE_TOLERANCE,
                                        math.pi / 2 + ANGLE_TOLERANCE)  # fmt: skip
    if min_distance > -1:
        ik.AddMinimumDistanceLowerBoundConstraint(min_distance)
    if scene.upright is not None:  # an object held keeps its top up (`upright`)
        hand = scene.hand().body_frame()
        ik.AddAngleBetweenVectorsConstraint(world, [0.0, 0.0, 1.0], hand,
                                            scene.upright.up_in_hand, 0.0,
                                            scene.upright.most)  # fmt: skip
    prog, q = ik.prog(), ik.q()
    A, b = scene.couplings()
    prog.AddLinearEqualityConstraint(A, b, q)
    held = dict(zip(HEAD_JOINTS, seed[[scene.index(j) for j in HEAD_JOINTS]], strict=True))
    held[GRIPPER_JOINT] = goal.opening / 2
    for joint, value in held.items():
        i = scene.index(joint)
        prog.AddBoundingBoxConstraint(value, value, q[i])
    for joint, slack in zip(BASE_JOINTS, BASE_SLACK, strict=True):
        i = scene.index(joint)
        reach = 0.0 if base_fixed else slack
        prog.AddBoundingBoxConstraint(seed[i] - reach, seed[i] + reach, q[i])
    prog.AddQuadraticErrorCost(POSTURE_WEIGHT * np.eye(len(seed)), seed, q)
    return ik

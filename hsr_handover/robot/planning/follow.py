"""Following a person's hand with the object (paper 3.3: the robot brings the object to the
receiver's hand): a state-to-state move (ruckig) from wherever the arm is, to hold the object
out at an aim in front of the hand, or at the nearest point round it where the object fits
beside the perceived hand (`offer.offer_points`); where IK from the arm as it is fails, it
starts again from the arm's effectivity map's nodes round the point, and the base steps when
the arm alone cannot reach. The move is checked for clearance like any timed path, and for the
object held kept up (`upright`)."""

from __future__ import annotations

import dataclasses

import numpy as np

from hsr_handover.robot.effectivity.arm_map import ArmEffectivity
from hsr_handover.robot.planning.handover_pose import map_seeds
from hsr_handover.robot.planning.inverse_kinematics import IkResult, PalmGoal, solve_palm_ik
from hsr_handover.robot.planning.offer import object_extent, offer_points
from hsr_handover.robot.planning.plan import Motion, Plan
from hsr_handover.robot.planning.planner import STAGES, Held, holding
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.retarget import retarget
from hsr_handover.robot.planning.stopwatch import Stopwatch
from hsr_handover.robot.planning.timing import JointLimits
from hsr_handover.robot.planning.trajectory import COLLISION_BOUND
from hsr_handover.robot.planning.upright import SLACK, keeps_upright
from hsr_handover.robot.planning.verification import DIP_ALLOWANCE, timed_clearance

FOLLOW = "follow"  # a follow plan's target and motion
FOLLOW_CHECK_S = 0.05  # s between the clearance checks of a re-targeted motion


def plan_follow(
    scene: PlanningScene,
    goal: PalmGoal,
    q: np.ndarray,
    v: np.ndarray,
    held: Held | None,
    limits: JointLimits,
    arm_map: ArmEffectivity | None = None,
) -> Plan:
    """From `q` at velocities `v` (plant order), the hand to `goal`, holding `held` (None:
    nothing); where the object there would be inside the person's perceived capsules, to the
    nearest point round `goal.point` where it fits. IK is retried from `arm_map`'s nodes
    (None: not). One "follow" motion, or not ok with the reason of the last point tried."""
    ignore = () if held is None else (held.label,)
    extent = object_extent(None if held is None else held.shape)
    reason = "no point at the hand clear of the person"
    watch = Stopwatch(STAGES)
    with holding(scene, held, q):
        for point in offer_points(goal.point, scene.scene.person, extent):
            at_point = dataclasses.replace(goal, point=point)
            motion, reason = _move(scene, q, v, at_point, ignore, limits, watch, arm_map)
            if motion is not None:
                goal_q = motion.state(motion.duration)[0]
                return Plan(ok=True, reason="ok", target=FOLLOW, motions=(motion,),
                            seconds=watch.snapshot(), goal=goal_q)  # fmt: skip
    return Plan(ok=False, reason=reason, target=FOLLOW, seconds=watch.snapshot())


def _move(
    scene: PlanningScene,
    q: np.ndarray,
    v: np.ndarray,
    goal: PalmGoal,
    ignore: tuple[str, ...],
    limits: JointLimits,
    watch: Stopwatch,
    arm_map: ArmEffectivity | None,
) -> tuple[Motion | None, str]:
    """The motion that brings the hand to `goal` clear of the scene and "ok", or None and
    why not."""
    with watch.stage("ik"):
        found = _palm_ik(scene, goal, q, ignore, arm_map)
    if not found.ok:
        return None, found.reason
    with watch.stage("timing"):
        retargeted = retarget(q, v, np.zeros_like(q), found.q, limits)
    if not retargeted.ok:
        return None, retargeted.reason
    motion = Motion(name=FOLLOW, trajectory=retargeted, ignore=ignore)
    with watch.stage("optimisation"):
        clearance = timed_clearance(scene, motion, FOLLOW_CHECK_S)
    if clearance < COLLISION_BOUND - DIP_ALLOWANCE:
        return None, f"the way to the hand comes {clearance:.3f} m near"
    if not keeps_upright(scene, motion.sample(FOLLOW_CHECK_S)[1], SLACK):
        return None, "the way to the hand tilts the object held"
    return motion, "ok"


def _palm_ik(
    scene: PlanningScene,
    goal: PalmGoal,
    q: np.ndarray,
    ignore: tuple[str, ...],
    arm_map: ArmEffectivity | None,
) -> IkResult:
    """IK for the hand at `goal`: with the base where it stands at `q`, from the arm as it is,
    then from the map's nodes round the point (a hand moved a few cm can need the elbow on the
    other side of a joint limit); else with a step of the base (out of the arm's reach)."""
    found = solve_palm_ik(scene, goal, q, ignore=ignore, base_fixed=True)
    if found.ok:
        return found
    if arm_map is not None:
        for _, seed in map_seeds(scene, arm_map, goal, q):
            retried = solve_palm_ik(scene, goal, seed, ignore=ignore, base_fixed=True)
            if retried.ok:
                return retried
    return solve_palm_ik(scene, goal, q, ignore=ignore)

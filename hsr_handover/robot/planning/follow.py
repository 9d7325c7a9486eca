"""Following a person's hand with the object (paper 3.3: the robot brings the object to the
receiver's hand): a state-to-state move (ruckig) from wherever the arm is, to hold the object
out at an aim in front of the hand, or at the nearest point round it where the object fits
beside the perceived hand (`offer.offer_points`); the base steps when the arm alone cannot
reach. The move is checked for clearance like any timed path."""

from __future__ import annotations

import dataclasses

import numpy as np

from hsr_handover.robot.planning.inverse_kinematics import IkResult, PalmGoal, solve_palm_ik
from hsr_handover.robot.planning.offer import object_extent, offer_points
from hsr_handover.robot.planning.planner import DIP_ALLOWANCE, Held, holding
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.retarget import Retargeting, retarget
from hsr_handover.robot.planning.timing import JointLimits
from hsr_handover.robot.planning.trajectory import COLLISION_BOUND

FOLLOW_CHECK_S = 0.05  # s between the clearance checks of a re-targeted motion


@dataclasses.dataclass(frozen=True)
class FollowMove:
    """The `motion` to the hand and "ok", or None and the `reason` there is none."""

    motion: Retargeting | None
    reason: str


def plan_follow(
    scene: PlanningScene,
    goal: PalmGoal,
    q: np.ndarray,
    v: np.ndarray,
    held: Held | None,
    limits: JointLimits,
) -> FollowMove:
    """From `q` at velocities `v` (plant order), the hand to `goal`, holding `held` (None:
    nothing); where the object there would be inside the person's perceived capsules, to the
    nearest point round `goal.point` where it fits."""
    ignore = () if held is None else (held.label,)
    extent = object_extent(None if held is None else held.shape)
    reason = "no point at the hand clear of the person"
    with holding(scene, held, q):
        for point in offer_points(goal.point, scene.scene.person, extent):
            at_point = dataclasses.replace(goal, point=point)
            motion, reason = _move(scene, q, v, at_point, ignore, limits)
            if motion is not None:
                return FollowMove(motion, "ok")
    return FollowMove(None, reason)


def _move(
    scene: PlanningScene,
    q: np.ndarray,
    v: np.ndarray,
    goal: PalmGoal,
    ignore: tuple[str, ...],
    limits: JointLimits,
) -> tuple[Retargeting | None, str]:
    """The motion that brings the hand to `goal` clear of the scene and "ok", or None and
    why not."""
    found = _palm_ik(scene, goal, q, ignore)
    if not found.ok:
        return None, found.reason
    motion = retarget(q, v, np.zeros_like(q), found.q, limits)
    if not motion.ok:
        return None, motion.reason
    _, positions = motion.sample(FOLLOW_CHECK_S)
    clearance = min(scene.clearance_at(p, ignore) for p in positions)
    if clearance < COLLISION_BOUND - DIP_ALLOWANCE:
        return None, f"the way to the hand comes {clearance:.3f} m near"
    return motion, "ok"


def _palm_ik(
    scene: PlanningScene, goal: PalmGoal, q: np.ndarray, ignore: tuple[str, ...]
) -> IkResult:
    """IK for the hand at `goal`: with the base where it stands at `q`, else with a step of the
    base (out of the arm's reach)."""
    found = solve_palm_ik(scene, goal, q, ignore=ignore, base_fixed=True)
    return found if found.ok else solve_palm_ik(scene, goal, q, ignore=ignore)

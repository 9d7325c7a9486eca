"""The arm stowed over the base where the base stands, or backed up from there when the arm
has no room to stow: how a retreat ends and how the base drives a carry."""

from __future__ import annotations

import numpy as np

from hsr_handover.hsr import BASE_JOINTS
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.trajectory import COLLISION_BOUND, STOWED
from hsr_handover.robot.planning.upright import turned_up

STOW_BACK_UPS = (0.0, 0.15, 0.3)  # m the base may back up to stow the arm
STOWED_HOLDING = {"arm_lift_joint": 0.3, "torso_lift_joint": 0.15}
"""Stowed with an object in the hand, the arm raised 30 cm: at STOWED's height the object rests
on the base's front, which levered a cup out of the fingers 2 s after a retreat."""


def stowed_posture(scene: PlanningScene) -> dict[str, float]:
    """STOWED, raised as STOWED_HOLDING while the scene holds an object."""
    return STOWED | STOWED_HOLDING if scene.upright is not None else STOWED


def stowed(
    scene: PlanningScene,
    q_now: np.ndarray,
    ignore: tuple[str, ...],
    posture=STOWED,
    back_ups: tuple[float, ...] = STOW_BACK_UPS,
) -> np.ndarray:
    """`q_now` with the arm in `posture`, the base backed up by the first of `back_ups` (m)
    that clears the collision bound (the last if none does): a base that came up to the table
    to present an object has no room there to fold the arm. An object held stays up
    (`upright.turned_up`)."""
    x, y, yaw = (scene.index(joint) for joint in BASE_JOINTS)
    for back in back_ups:
        q_stowed = q_now.copy()
        for joint, value in posture.items():
            q_stowed[scene.index(joint)] = value
        q_stowed[[x, y]] -= back * np.array([np.cos(q_now[yaw]), np.sin(q_now[yaw])])
        q_stowed = turned_up(scene, q_stowed)
        if scene.clearance_at(q_stowed, ignore) >= COLLISION_BOUND:
            break
    return q_stowed

"""Closed-form joint angles that aim the person's head and arms at points.

Arm chain (from the torso): shoulder pitch about y, roll about x, yaw about the upper arm, elbow
about y, wrist about y; the hanging arm points along -z. So the upper arm's direction is
`Ry(pitch) Rx(roll) (0, 0, -1) = (-sin p cos r, sin r, -cos p cos r)`, and a bent elbow
(negative angle, flexion) swings the forearm toward the upper arm's local +x.
"""

from __future__ import annotations

import numpy as np

from hsr_handover.world.person.body import BodyDimensions

_EPS = 1e-9


def rot_x(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def rot_y(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rot_z(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def _unit(v: np.ndarray) -> np.ndarray:
    return v / max(np.linalg.norm(v), _EPS)


def head_angles(pivot_to_target: np.ndarray) -> np.ndarray:
    """Neck (yaw, pitch) that turn the face (+x) toward a direction; positive pitch looks down."""
    x, y, z = pivot_to_target
    return np.array([np.arctan2(y, x), np.arctan2(-z, np.hypot(x, y))])


def upper_arm_angles(direction: np.ndarray) -> tuple[float, float]:
    """Shoulder (pitch, roll) that point the upper arm along `direction`."""
    dx, dy, dz = _unit(np.asarray(direction, dtype=float))
    roll = float(np.arcsin(np.clip(dy, -1.0, 1.0)))
    pitch = float(np.arctan2(-dx, -dz))
    return pitch, roll


def pointing_arm_angles(shoulder_to_target: np.ndarray) -> np.ndarray:
    """Arm joints (pitch, roll, yaw, elbow, wrist) for a straight arm along the shoulder-to-target
    ray, as a person points (paper §3.2: a pointing arm is nearly straight)."""
    pitch, roll = upper_arm_angles(shoulder_to_target)
    return np.array([pitch, roll, 0.0, 0.0, 0.0])


def reaching_arm_angles(shoulder_to_target: np.ndarray, body: BodyDimensions) -> np.ndarray:
    """Arm joints that put the middle of the hand at the target, elbow hanging as low as it can.

    Two-link arm: upper arm, then forearm plus half the hand. Beyond reach the arm points
    straight at the target; too close and the elbow folds as far as the hand allows.
    """
    upper, lower = body.upper_arm, body.forearm + body.hand / 2
    target = np.asarray(shoulder_to_target, dtype=float)
    distance = float(np.clip(np.linalg.norm(target), abs(upper - lower) + 1e-3, None))
    if distance >= upper + lower:
        return pointing_arm_angles(target)
    axis = _unit(target)
    # Law of cosines for the angle between the upper arm and the shoulder-to-target line.
    cos_beta = (upper**2 + distance**2 - lower**2) / (2 * upper * distance)
    beta = float(np.arccos(np.clip(cos_beta, -1.0, 1.0)))
    down = np.array([0.0, 0.0, -1.0])
    swing = down - (down @ axis) * axis
    if np.linalg.norm(swing) < 1e-6:
        swing = np.array([-1.0, 0.0, 0.0]) - axis[0] * axis
    elbow = upper * (np.cos(beta) * axis + np.sin(beta) * _unit(swing))
    forearm = _unit(axis * distance - elbow)
    pitch, roll = upper_arm_angles(elbow)
    local = (rot_y(pitch) @ rot_x(roll)).T @ forearm
    cos_elbow = np.clip(-local[2], -1.0, 1.0)
    elbow_angle = -float(np.arccos(cos_elbow))
    yaw = float(np.arctan2(local[1], local[0])) if abs(elbow_angle) > 1e-6 else 0.0
    return np.array([pitch, roll, yaw, elbow_angle, 0.0])


def arm_points(body: BodyDimensions, side: str, angles: np.ndarray) -> dict[str, np.ndarray]:
    """Elbow, wrist and hand-centre positions in the person frame for arm joint angles (the
    forward kinematics that the aiming functions invert, with the wrist straight), and the
    fingertips' `tips` with the wrist as it is (used by tests and by the actor)."""
    pitch, roll, yaw, elbow, wrist_angle = angles
    hang = np.array([0.0, 0.0, -1.0])
    rot_upper = rot_y(pitch) @ rot_x(roll) @ rot_z(yaw)
    rot_fore = rot_upper @ rot_y(elbow)
    shoulder = body.shoulder(side)
    elbow_point = shoulder + body.upper_arm * rot_upper @ hang
    wrist = elbow_point + body.forearm * rot_fore @ hang
    tips = wrist + body.hand * rot_fore @ rot_y(wrist_angle) @ hang
    return {"elbow": elbow_point, "wrist": wrist, "hand": wrist + body.hand / 2 * rot_fore @ hang,
            "tips": tips}  # fmt: skip


def arm_move_points(
    body: BodyDimensions, side: str, start: np.ndarray, goal: np.ndarray, samples: int
) -> list[dict[str, np.ndarray]]:
    """`arm_points` at `samples` evenly spaced poses of the arm's move from joint angles
    `start` to `goal`: a straight line in joint space, as the actor moves."""
    start, goal = np.asarray(start, dtype=float), np.asarray(goal, dtype=float)
    return [arm_points(body, side, start + share * (goal - start))
            for share in np.linspace(0.0, 1.0, samples)]  # fmt: skip

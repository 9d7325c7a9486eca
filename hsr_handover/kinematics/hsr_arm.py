"""Forward kinematics of the HSR-B arm (docs/design.md §4.1) in the robot's base frame, vectorised.

The arm has five joints, in this order: arm_lift (prismatic +z), arm_flex (revolute about -y),
arm_roll (revolute +z), wrist_flex (revolute about -y), wrist_roll (revolute +z). The palm frame
sits at (0.012, 0, 0.1405) in the wrist_roll frame, yawed by pi. This module is the numpy
reference that the SDF model is checked against and that the arm's Growing Cell Structures
learn from; it knows nothing of Drake.
"""

from __future__ import annotations

import numpy as np

ARM_JOINT_NAMES = (
    "arm_lift_joint",
    "arm_flex_joint",
    "arm_roll_joint",
    "wrist_flex_joint",
    "wrist_roll_joint",
)
ARM_LOWER = np.array([0.0, -2.62, -2.09, -1.92, -1.92])
ARM_UPPER = np.array([0.69, 0.0, 3.84, 1.22, 3.67])

ARM_LIFT_ORIGIN = np.array([0.0, 0.0, 0.340])
ARM_FLEX_ORIGIN = np.array([0.141, 0.078, 0.0])
ARM_ROLL_ORIGIN = np.array([0.005, 0.0, 0.345])
PALM_IN_WRIST_ROLL = np.array([0.012, 0.0, 0.1405])


def _rot_y(angle: np.ndarray) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    o, z = np.ones_like(angle), np.zeros_like(angle)
    return np.stack(
        [np.stack([c, z, s], -1), np.stack([z, o, z], -1), np.stack([-s, z, c], -1)], -2
    )


def _rot_z(angle: np.ndarray) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    o, z = np.ones_like(angle), np.zeros_like(angle)
    return np.stack(
        [np.stack([c, -s, z], -1), np.stack([s, c, z], -1), np.stack([z, z, o], -1)], -2
    )


def palm_pose(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Palm position (..., 3) and rotation (..., 3, 3) in the base frame for joints q (..., 5).

    Joint axes along -y are rotations about +y by the negated angle.
    """
    q = np.asarray(q, dtype=float)
    if q.shape[-1] != 5:
        raise ValueError(f"q: expected shape (..., 5) arm joint values, got {q.shape}")
    lift, flex, roll, wrist_flex, wrist_roll = np.moveaxis(q, -1, 0)
    rot_flex = _rot_y(-flex)
    rot_wrist = rot_flex @ _rot_z(roll) @ _rot_y(-wrist_flex) @ _rot_z(wrist_roll)
    shoulder = ARM_LIFT_ORIGIN + ARM_FLEX_ORIGIN + np.stack([0 * lift, 0 * lift, lift], -1)
    wrist = shoulder + rot_flex @ ARM_ROLL_ORIGIN
    position = wrist + rot_wrist @ PALM_IN_WRIST_ROLL
    rotation = rot_wrist @ _rot_z(np.full_like(lift, np.pi))
    return position, rotation


def palm_position(q: np.ndarray) -> np.ndarray:
    """Palm position (..., 3) in the base frame for arm joints q (..., 5)."""
    return palm_pose(q)[0]


def sample_arm_joints(n: int, rng: np.random.Generator) -> np.ndarray:
    """n joint vectors drawn uniformly within the arm's joint limits, shape (n, 5)."""
    return rng.uniform(ARM_LOWER, ARM_UPPER, size=(n, 5))

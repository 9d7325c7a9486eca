"""An adult's body dimensions from their height, and where the keypoint frames sit.

Segment ratios are Winter's anthropometric table (Biomechanics and Motor Control of Human
Movement, 4th ed., fig. 4.1): shoulder 0.818 H, hip 0.530 H, knee 0.285 H, ankle 0.039 H, eyes
0.936 H, upper arm 0.186 H, forearm 0.146 H, hand 0.108 H, thigh 0.245 H. All positions are in
the person frame: origin on the floor below the hips' midpoint, x forward, y to the person's
left, z up.
"""

from __future__ import annotations

import dataclasses

import numpy as np

SEAT_HEIGHT = 0.45  # m: a dining chair's seat, the default (`PersonConfig.seat_height`)
HIP_ABOVE_SEAT = 0.09
HAND_WIDTH, HAND_THICKNESS = 0.08, 0.03  # m: the hand's box, across the palm and through it
UPPER_ARM_RADIUS, FOREARM_RADIUS = 0.045, 0.035  # m: the arm segments' capsules

# Person joints in the order the actor and the model use. Arms: shoulder pitch (about y),
# roll (about x), yaw (about the upper arm), elbow (about y), wrist (about y).
ARM_JOINT_SUFFIXES = ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow", "wrist")
HEAD_JOINTS = ("neck_yaw", "neck_pitch")
PERSON_JOINTS = (
    *HEAD_JOINTS,
    *(f"r_{suffix}" for suffix in ARM_JOINT_SUFFIXES),
    *(f"l_{suffix}" for suffix in ARM_JOINT_SUFFIXES),
)


def arm_joint_indices(side: str) -> list[int]:
    """The `side` ("left" or "right") arm's joints' indices in PERSON_JOINTS, shoulder to wrist."""
    prefix = "r_" if side == "right" else "l_"
    return [PERSON_JOINTS.index(prefix + suffix) for suffix in ARM_JOINT_SUFFIXES]


def side_sign(side: str) -> float:
    """+1 for the person's left, -1 for the right (y points to the person's left)."""
    if side not in ("left", "right"):
        raise ValueError(f"side: expected 'left' or 'right', got {side!r}")
    return 1.0 if side == "left" else -1.0


@dataclasses.dataclass(frozen=True)
class BodyDimensions:
    """Lengths (m) and rest positions of an adult of a given height, standing or seated."""

    height: float
    seated: bool
    hip_z: float
    shoulder_z: float
    shoulder_half_width: float
    hip_half_width: float
    neck_pivot_z: float
    eye_z: float
    upper_arm: float
    forearm: float
    hand: float
    thigh: float
    shank: float
    ankle_z: float
    head_radius: float

    @classmethod
    def from_height(
        cls, height: float, seated: bool, seat_height: float = SEAT_HEIGHT
    ) -> BodyDimensions:
        h = height
        trunk = (0.818 - 0.530) * h
        hip_z = seat_height + HIP_ABOVE_SEAT if seated else 0.530 * h
        return cls(
            height=h,
            seated=seated,
            hip_z=hip_z,
            shoulder_z=hip_z + trunk,
            shoulder_half_width=0.11 * h,
            hip_half_width=0.05 * h,
            neck_pivot_z=hip_z + (0.870 - 0.530) * h,
            eye_z=hip_z + (0.936 - 0.530) * h,
            upper_arm=0.186 * h,
            forearm=0.146 * h,
            hand=0.108 * h,
            thigh=0.245 * h,
            shank=0.246 * h,
            ankle_z=0.039 * h,
            head_radius=0.056 * h,
        )

    @property
    def seat_height(self) -> float:
        """m: the top of the seat a seated person sits on (the hips over it)."""
        return self.hip_z - HIP_ABOVE_SEAT

    def shoulder(self, side: str) -> np.ndarray:
        return np.array([0.0, side_sign(side) * self.shoulder_half_width, self.shoulder_z])

    def neck_pivot(self) -> np.ndarray:
        return np.array([0.0, 0.0, self.neck_pivot_z])

    def head_center(self) -> np.ndarray:
        return np.array([0.0, 0.0, self.eye_z])

    def face_points(self) -> dict[str, np.ndarray]:
        """Nose, eyes and ears relative to the neck pivot, with the head facing +x.

        The eyes sit on the head sphere, the nose tip a little ahead of it and below the eyes,
        as on a real face (so the nose-eyes plane of eq. 17 tilts upward by some degrees).
        """
        r, up = self.head_radius, self.eye_z - self.neck_pivot_z
        eye_y = 0.34 * r
        return {
            "nose": np.array([1.12 * r, 0.0, up - 0.42 * r]),
            "r_eye": np.array([np.sqrt(r * r - eye_y * eye_y), -eye_y, up]),
            "l_eye": np.array([np.sqrt(r * r - eye_y * eye_y), eye_y, up]),
            "r_ear": np.array([0.0, -r, up - 0.1 * r]),
            "l_ear": np.array([0.0, r, up - 0.1 * r]),
        }

    def leg_points(self, side: str) -> dict[str, np.ndarray]:
        """Hip, knee and ankle of one leg (rigid in this model: the person does not walk)."""
        y = side_sign(side) * self.hip_half_width
        hip = np.array([0.0, y, self.hip_z])
        if self.seated:
            knee = np.array([self.thigh, y, self.ankle_z + self.shank])
            ankle = np.array([self.thigh, y, self.ankle_z])
        else:
            knee = np.array([0.0, y, 0.285 * self.height])
            ankle = np.array([0.0, y, self.ankle_z])
        return {"hip": hip, "knee": knee, "ankle": ankle}

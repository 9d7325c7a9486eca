"""A synthetic seated person's COCO-18 keypoints, pointing and looking where a test asks, built
with the simulated person's own body model and aiming (exact: no sensor in between)."""

from __future__ import annotations

import math

import numpy as np

from hsr_handover.interface.coco18 import COCO18_KEYPOINTS
from hsr_handover.literature import STIEFELHAGEN_HEAD_FRACTION
from hsr_handover.world.person.aiming import arm_points, pointing_arm_angles, rot_z
from hsr_handover.world.person.behavior import aim_head, head_rotation
from hsr_handover.world.person.body import BodyDimensions

BODY = BodyDimensions.from_height(1.70, seated=True)
PERSON_AT, PERSON_YAW = np.array([1.75, 0.0, 0.0]), math.pi  # facing the robot (-x)
# Three cups 22 cm apart on a 0.72 m table, as in the point_* scenarios.
TRUE_FACE_TILT = 23.0
"""deg: the face tilt of these true keypoints (`IntentParams.face_tilt_deg` is the lifted
skeleton's 30): a correction's check of the eyes' pitch needs it, as the eyes read 10 degrees
low at 30."""
CUPS = [("red", np.array([0.80, -0.22, 0.77])), ("green", np.array([0.80, 0.0, 0.77])),
        ("blue", np.array([0.80, 0.22, 0.77]))]  # fmt: skip


def _to_world(points: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    return {name: PERSON_AT + rot_z(PERSON_YAW) @ p for name, p in points.items()}


def to_person(point: np.ndarray) -> np.ndarray:
    return rot_z(PERSON_YAW).T @ (point - PERSON_AT)


def keypoints(look_at=None, point_with=None, point_at=None, arm_angles=None):
    """World COCO-18 keypoints of the seated person: the head aimed at `look_at` (or level),
    the `point_with` arm straight at `point_at` (or given `arm_angles`), the other resting."""
    pivot = BODY.neck_pivot()
    rest = np.array([0.0, 0.2])  # the rest posture's head: level, a little down
    yaw_pitch = rest
    if look_at is not None:  # the head turns its share of the way; the eyes do the rest
        yaw_pitch = rest + STIEFELHAGEN_HEAD_FRACTION * (aim_head(BODY, to_person(look_at)) - rest)
    face = {k: pivot + head_rotation(*yaw_pitch) @ v for k, v in BODY.face_points().items()}
    points = {**face, "neck": pivot}
    for side in ("right", "left"):
        if side == point_with:
            to_target = to_person(point_at) - BODY.shoulder(side) if point_at is not None else 0
            angles = arm_angles if arm_angles is not None else pointing_arm_angles(to_target)
        else:
            angles = np.array([-0.25, 0.08 * (1 if side == "left" else -1), 0.0, -1.5, 0.0])
        arm = arm_points(BODY, side, angles)
        prefix = side[0]
        points |= {f"{prefix}_shoulder": BODY.shoulder(side), f"{prefix}_elbow": arm["elbow"],
                   f"{prefix}_wrist": arm["wrist"]}  # fmt: skip
        legs = BODY.leg_points(side)
        points |= {f"{prefix}_{joint}": legs[joint] for joint in ("hip", "knee", "ankle")}
    world = _to_world(points)
    return np.array([world[name] for name in COCO18_KEYPOINTS]), np.full(18, 0.9)

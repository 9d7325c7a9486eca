"""The person's rays from one lifted COCO-18 skeleton: the pointing arm's ray (eq. 16), the
face's (eq. 17), the torso's forward direction and where the eyes look; and how far a ray
passes beside or above an object."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.robot.intent.params import IntentParams
from hsr_handover.robot.intent.rays import (
    Ray,
    angle_deg,
    elbow_angle_deg,
    face_normal,
    tilt_down,
    unit_direction,
)
from hsr_handover.robot.perception.torso_depth import mirrored_shoulder

ARMS = {
    side: tuple(keypoint_index(f"{side[0]}_{joint}") for joint in ("shoulder", "elbow", "wrist"))
    for side in ("right", "left")
}
NOSE, R_EYE, L_EYE = (keypoint_index(name) for name in ("nose", "r_eye", "l_eye"))
NECK = keypoint_index("neck")
R_SHOULDER, L_SHOULDER = keypoint_index("r_shoulder"), keypoint_index("l_shoulder")
# Pairs (a point on the person's right, one on their left) across the torso, the widest
# first; for a pointing arm, its own shoulder is left out: lifted, it lands on the raised arm,
# a hand's width off. A seated person's hips are under the table, and one shoulder can go
# unseen for a whole gesture: then the neck and the other shoulder.
TORSO_PAIRS = {
    None: (
        (R_SHOULDER, L_SHOULDER),
        (keypoint_index("r_hip"), keypoint_index("l_hip")),
        (R_SHOULDER, NECK),
        (NECK, L_SHOULDER),
    ),
    "right": ((NECK, L_SHOULDER),),
    "left": ((R_SHOULDER, NECK),),
}
UP = np.array([0.0, 0.0, 1.0])


def seen(points: np.ndarray, confidence: np.ndarray, indices: Sequence[int]) -> bool:
    return all(confidence[i] > 0 and np.isfinite(points[i]).all() for i in indices)


def horizontal(vector: np.ndarray) -> np.ndarray | None:
    flat = np.array([vector[0], vector[1], 0.0])
    length = float(np.linalg.norm(flat))
    return flat / length if length > 1e-9 else None


def face_ray(
    points: np.ndarray,
    confidence: np.ndarray,
    params: IntentParams,
    forward: np.ndarray | None = None,
) -> Ray | None:
    """The face's ray from the eyes' midpoint. Along `forward`, the face's direction read from
    the head's shape (`perception.head_pose`), when it is given (finite) and
    `params.face_from_head_shape`: from the nose without the eyes, None without either.
    Otherwise eq. 17's normal turned down by the face's tilt: None without the nose and both
    eyes."""
    if params.face_from_head_shape and forward is not None and np.isfinite(forward).all():
        for origin in ((R_EYE, L_EYE), (NOSE,)):
            if seen(points, confidence, origin):
                return Ray(points[list(origin)].mean(axis=0), np.asarray(forward, dtype=float))
        return None
    if not seen(points, confidence, (NOSE, R_EYE, L_EYE)):
        return None
    normal = face_normal(points[NOSE], points[R_EYE], points[L_EYE])
    if normal is None:
        return None
    eyes = (points[R_EYE] + points[L_EYE]) / 2
    return Ray(eyes, tilt_down(normal, params.face_tilt_deg))


def torso_forward(
    points: np.ndarray, confidence: np.ndarray, pointing_arm: str | None = None
) -> np.ndarray | None:
    """The horizontal direction the torso faces, square to the shoulders (or else the hips, or
    else a shoulder and the neck); with a `pointing_arm`, square to the neck and the other
    shoulder."""
    for right, left in TORSO_PAIRS[pointing_arm]:
        if seen(points, confidence, (right, left)):
            forward = horizontal(np.cross(points[left] - points[right], UP))
            if forward is not None:
                return forward
    return None


def gaze_ray(face: Ray, forward: np.ndarray | None, params: IntentParams) -> Ray:
    """Where the eyes look: the face's horizontal turn from `forward` and its pitch from level,
    each times `head_gain` (the turn is the face's own heading when the torso is not seen)."""
    heading = horizontal(face.direction)
    if heading is None:
        return face
    yaw = math.atan2(heading[1], heading[0])
    if forward is not None:
        turn = math.atan2(np.cross(forward, heading)[2], float(forward @ heading))
        yaw = math.atan2(forward[1], forward[0]) + params.head_gain * turn
    pitch = params.head_gain * math.asin(float(np.clip(face.direction[2], -1.0, 1.0)))
    pitch = float(np.clip(pitch, -math.pi / 2, math.pi / 2))
    return Ray(face.origin, unit_direction(yaw, pitch))


def pitch_errors_deg(ray: Ray, points: np.ndarray) -> np.ndarray:
    """The ray's elevation minus the elevation from its origin to each point (deg)."""
    offsets = np.asarray(points, dtype=float).reshape(-1, 3) - ray.origin
    toward = np.degrees(np.arctan2(offsets[:, 2], np.hypot(offsets[:, 0], offsets[:, 1])))
    return math.degrees(math.asin(float(np.clip(ray.direction[2], -1.0, 1.0)))) - toward


def pitch_tolerance_deg(eyes: np.ndarray, center: np.ndarray, params: IntentParams) -> float:
    """How far (deg) the eyes at `eyes` may look above `center`: `gaze_pitch_tolerance_deg`,
    or `gaze_pitch_tolerance_share` of how far they look down to it when that is more."""
    offset = np.asarray(center, dtype=float) - eyes
    down = -math.degrees(math.atan2(offset[2], math.hypot(offset[0], offset[1])))
    return max(params.gaze_pitch_tolerance_deg, params.gaze_pitch_tolerance_share * down)


def bearing_tolerance_deg(
    eyes: np.ndarray, forward: np.ndarray | None, center: np.ndarray, params: IntentParams
) -> float:
    """How far (deg) the eyes' estimated bearing may miss `center`: `gaze_tolerance_deg`, or
    `gaze_tolerance_share` of how far the eyes turn from the torso's `forward` to look at it
    when that is more (the turn read from the face errs in proportion to it)."""
    toward = horizontal(np.asarray(center, dtype=float) - eyes)
    if forward is None or toward is None:
        return params.gaze_tolerance_deg
    return max(params.gaze_tolerance_deg, params.gaze_tolerance_share * angle_deg(toward, forward))


def bearing_errors_deg(ray: Ray, points: np.ndarray) -> np.ndarray:
    """Horizontal angle (deg) between the ray and the direction from its origin to each point."""
    heading = horizontal(ray.direction)
    errors = []
    for point in np.asarray(points, dtype=float).reshape(-1, 3):
        toward = horizontal(point - ray.origin)
        if heading is None or toward is None:
            errors.append(180.0)
            continue
        cosine = float(np.clip(heading @ toward, -1.0, 1.0))
        errors.append(math.degrees(math.acos(cosine)))
    return np.array(errors)


def shoulder_point(points: np.ndarray, confidence: np.ndarray, arm: str) -> np.ndarray | None:
    """The `arm`'s shoulder (m, world): as seen, or, hidden, the other shoulder mirrored through
    the neck (None without those). An arm pointed at the camera hides its own shoulder,
    for over a second of a held gesture."""
    shoulder = ARMS[arm][0]
    if seen(points, confidence, (shoulder,)):
        return points[shoulder]
    other = ARMS["left" if arm == "right" else "right"][0]
    if seen(points, confidence, (NECK, other)):
        return mirrored_shoulder(points[NECK], points[other])
    return None


def pointing_rays(
    points: np.ndarray, confidence: np.ndarray, params: IntentParams
) -> list[tuple[str, float, Ray]]:
    """(arm, elbow angle, ray) for each arm seen straight enough to point (eq. 16); a hidden
    shoulder is taken from the torso (`shoulder_point`)."""
    rays = []
    for arm, (_, elbow, wrist) in ARMS.items():
        shoulder = shoulder_point(points, confidence, arm)
        if shoulder is None or not seen(points, confidence, (elbow, wrist)):
            continue
        angle = elbow_angle_deg(shoulder, points[elbow], points[wrist])
        if not angle >= params.straight_arm_deg:
            continue
        origin = _ray_origin(points, confidence, params.pointing_ray, shoulder, elbow)
        ray = None if origin is None else Ray.through(origin, points[wrist])
        if ray is not None:
            rays.append((arm, angle, ray))
    return rays


def _ray_origin(
    points: np.ndarray, confidence: np.ndarray, kind: str, shoulder: np.ndarray, elbow: int
) -> np.ndarray | None:
    """Where the pointing ray of kind `kind` (POINTING_RAYS) starts; None without the eyes."""
    if kind == "shoulder_wrist":
        return shoulder
    if kind == "elbow_wrist":
        return points[elbow]
    if seen(points, confidence, (R_EYE, L_EYE)):
        return (points[R_EYE] + points[L_EYE]) / 2
    return None

"""The points of the person the handover cycle reads from the lifted skeleton (m, world): the
receiving wrist, a point on the body and a point of the face, each None when not seen now."""

from __future__ import annotations

import numpy as np

from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.robot.effectivity.person_map import RECEIVING_SIDES, HumanArm
from hsr_handover.robot.perception.skeleton import Skeleton

WRISTS = {side: keypoint_index(f"{side}_wrist") for side in RECEIVING_SIDES}
UPPER_BODY = tuple(keypoint_index(name) for name in ("neck", "r_shoulder", "l_shoulder"))
FACE = tuple(keypoint_index(name) for name in ("nose", "r_eye", "l_eye", "r_ear", "l_ear"))


def keypoint(skeleton: Skeleton | None, index: int) -> np.ndarray | None:
    """The keypoint `index` (m, world), None when not seen."""
    if skeleton is None or skeleton.confidence[index] <= 0:
        return None
    point = skeleton.points[index]
    return point if np.all(np.isfinite(point)) else None


def first_seen(skeleton: Skeleton | None, indices: tuple[int, ...]) -> np.ndarray | None:
    """The first of the keypoints `indices` seen now, None if none is."""
    seen = (keypoint(skeleton, index) for index in indices)
    return next((point for point in seen if point is not None), None)


def wrist(skeleton: Skeleton | None, side: str) -> np.ndarray | None:
    """The receiving wrist on `side` ("r" or "l"), None when not seen."""
    return keypoint(skeleton, WRISTS[side])


def face_point(skeleton: Skeleton | None) -> np.ndarray | None:
    """A point of the person's face seen now (the nose, an eye or an ear), None if none is."""
    return first_seen(skeleton, FACE)


def person_point(skeleton: Skeleton | None, arm: HumanArm | None) -> np.ndarray | None:
    """A point on the person seen now (the neck or a shoulder; None when none is): the
    receiving arm's shoulder, steady over recent frames (`receiving_arms`), or else the first
    of those seen (presenting to a standing person at their chest, the robot's arm hides one
    shoulder from its camera, and the arm's frame needs both)."""
    seen = first_seen(skeleton, UPPER_BODY)
    if seen is None:
        return None
    return seen if arm is None else arm.shoulder

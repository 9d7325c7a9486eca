"""A shoulder hidden behind its own arm takes its depth from the torso.

An arm pointing at the camera covers its shoulder: OpenPose still finds the shoulder's pixel,
but the depth there is the arm's: a right shoulder can read 24 cm in front of the neck (inside
`body_check`'s slack), then be dropped for a second when the re-lift finds only arm, and the
shoulder-wrist ray is lost. The neck lies halfway between the shoulders, in depth as across the
body, so a shoulder with no depth, or nearer the camera than the other shoulder's mirror image
through the neck by more than SHOULDER_DEPTH_TOLERANCE_M, is given that mirror depth along its
own pixel's ray. Its pixel is kept: only the depth was hidden.

The intent's own mirror for a shoulder OpenPose misses outright is
`robot.intent.person_rays.shoulder_point`.
"""

from __future__ import annotations

import numpy as np

from hsr_handover.interface.coco18 import keypoint_index

SHOULDER_DEPTH_TOLERANCE_M = 0.1
"""m the shoulders' depths may sum to less than twice the neck's: a torso turned from the
camera moves one shoulder nearer and the other farther by the same amount; an occluder moves
only one."""
_NECK = keypoint_index("neck")
_SHOULDERS = (keypoint_index("r_shoulder"), keypoint_index("l_shoulder"))


def mirrored_shoulder(neck, other_shoulder):
    """The shoulder opposite `other_shoulder` through the `neck` (points, or depths along the
    optical axis): OpenPose's neck lies halfway between the shoulders."""
    return 2.0 * neck - other_shoulder


def torso_shoulder_depths(depths: np.ndarray, detected: np.ndarray) -> np.ndarray:
    """(18,) the keypoints' depths along the optical axis (m; NaN: none), with a `detected`
    shoulder's depth replaced by the other's mirrored through the neck's when it has none or
    lies in front of that mirror by more than the tolerance (the nearer of the two)."""
    depths = np.array(depths, dtype=float)
    neck = depths[_NECK]
    for shoulder, other in (_SHOULDERS, _SHOULDERS[::-1]):
        mirrored = mirrored_shoulder(neck, depths[other])
        if not (detected[shoulder] and np.isfinite(mirrored) and mirrored > 0.0):
            continue
        own = depths[shoulder]
        in_front = own < mirrored - SHOULDER_DEPTH_TOLERANCE_M and own < depths[other]
        if not np.isfinite(own) or in_front:
            depths[shoulder] = mirrored
    return depths


def seen_shoulders(
    points: np.ndarray, confidence: np.ndarray
) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The lifted (right, left) shoulders of a COCO-18 skeleton (18 x 3, 18), one hidden (a
    seated person's behind the objects on a high table, or behind their own pointing arm)
    mirrored from the other through the neck; None for one neither way shows."""
    seen = [_keypoint(points, confidence, i) for i in (*_SHOULDERS, _NECK)]
    right, left, neck = seen
    if neck is not None and right is None and left is not None:
        right = mirrored_shoulder(neck, left)
    elif neck is not None and left is None and right is not None:
        left = mirrored_shoulder(neck, right)
    return right, left


def _keypoint(points: np.ndarray, confidence: np.ndarray, index: int) -> np.ndarray | None:
    point = points[index]
    return point if confidence[index] > 0 and np.isfinite(point).all() else None

"""OpenPose's COCO-18 body model: the keypoint order and the limbs between keypoints.

This is the robot's own knowledge of its pose detector's output (docs/design.md §3.3); the simulated
person marks the same keypoints with frames named "coco_<name>".
"""

from __future__ import annotations

COCO18_KEYPOINTS = (
    "nose", "neck", "r_shoulder", "r_elbow", "r_wrist", "l_shoulder", "l_elbow", "l_wrist",
    "r_hip", "r_knee", "r_ankle", "l_hip", "l_knee", "l_ankle", "r_eye", "l_eye", "r_ear", "l_ear",
)  # fmt: skip
NUM_KEYPOINTS = len(COCO18_KEYPOINTS)
FACE_KEYPOINTS = ("nose", "r_eye", "l_eye", "r_ear", "l_ear")

# OpenPose's COCO-18 limbs (keypoint index pairs), the bones drawn between keypoints.
COCO18_LIMBS = (
    (1, 2), (1, 5), (2, 3), (3, 4), (5, 6), (6, 7), (1, 8), (8, 9), (9, 10),
    (1, 11), (11, 12), (12, 13), (1, 0), (0, 14), (14, 16), (0, 15), (15, 17),
)  # fmt: skip


def keypoint_index(name: str) -> int:
    """Index of a COCO-18 keypoint by name (e.g. "r_wrist" -> 4)."""
    if name not in COCO18_KEYPOINTS:
        raise ValueError(f"keypoint: expected one of {COCO18_KEYPOINTS}, got {name!r}")
    return COCO18_KEYPOINTS.index(name)

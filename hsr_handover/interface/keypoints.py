"""The pose detector's output as the `skeleton_keypoints` port carries it: one person's COCO-18
keypoints as OpenPose reports them (paper 3.2), and why a frame holds none.

Convention: a keypoint's confidence is 0 exactly when it is missing.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from hsr_handover.interface.coco18 import NUM_KEYPOINTS

STATUS_OK = "ok"
NOT_IN_VIEW = "person not in view"
ALL_HIDDEN = "person hidden: no keypoint visible"
NO_DEPTH_IMAGE = "no depth image"


def freeze_keypoint_arrays(instance, widths: dict[str, int]) -> None:
    """Store `confidence` (18,) and each named (18, width) field of a frozen dataclass as
    read-only float arrays, checking that confident keypoints have finite values."""
    confidence = np.array(instance.confidence, dtype=float)
    if confidence.shape != (NUM_KEYPOINTS,) or not np.all((confidence >= 0) & (confidence <= 1)):
        raise ValueError(f"confidence: expected {NUM_KEYPOINTS} values in [0, 1], got {confidence}")
    confidence.flags.writeable = False
    object.__setattr__(instance, "confidence", confidence)
    for name, width in widths.items():
        array = np.array(getattr(instance, name), dtype=float)
        if array.shape != (NUM_KEYPOINTS, width):
            raise ValueError(f"{name}: expected shape {(NUM_KEYPOINTS, width)}, got {array.shape}")
        if not np.isfinite(array[confidence > 0]).all():
            raise ValueError(f"{name}: expected finite values wherever confidence > 0")
        array.flags.writeable = False
        object.__setattr__(instance, name, array)


def no_keypoints(width: int) -> np.ndarray:
    return np.full((NUM_KEYPOINTS, width), np.nan)


@dataclasses.dataclass(frozen=True)
class Detection:
    """One person's 2-D keypoints as OpenPose reports them (COCO-18 order).

    `pixels` (18, 2) as (u, v) in Drake's pixel convention, NaN where missing; `confidence`
    (18,) in [0, 1], 0 where missing; `status` "ok" or why the detection is empty.
    """

    pixels: np.ndarray
    confidence: np.ndarray
    status: str = STATUS_OK

    def __post_init__(self) -> None:
        freeze_keypoint_arrays(self, {"pixels": 2})

    @classmethod
    def missing(cls, status: str) -> Detection:
        """No keypoint detected, for the reason `status`."""
        return cls(no_keypoints(2), np.zeros(NUM_KEYPOINTS), status)

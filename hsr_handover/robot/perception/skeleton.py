"""The robot's side of the skeleton: the pose detector's 2-D keypoints, simulated or recorded,
lifted to 3-D with the depth image of the same capture (paper 3.2).

`lift_keypoints` turns 2-D keypoints into world points with the depth image. The point it gives
is the body SURFACE seen at the keypoint's pixel, not the joint centre: a few cm nearer the
camera (the limb's radius; up to about 13 cm at a shoulder whose arm points toward the camera).
Later stages use rays between keypoints (shoulder-elbow-wrist, the face plane), which such
offsets barely turn.

Convention: a keypoint of a `Skeleton` with confidence > 0 always has a finite 3-D point.
"""

from __future__ import annotations

import dataclasses
from typing import NamedTuple

import numpy as np

from hsr_handover.interface.coco18 import NUM_KEYPOINTS, keypoint_index
from hsr_handover.interface.keypoints import (
    NOT_IN_VIEW,
    STATUS_OK,
    Detection,
    freeze_keypoint_arrays,
    no_keypoints,
)
from hsr_handover.interface.pinhole import PinholeCamera, checked_depth, valid_depth
from hsr_handover.robot.perception.body_check import body_consistent
from hsr_handover.robot.perception.chest_plane import chest_forward
from hsr_handover.robot.perception.depth_window import window_depths
from hsr_handover.robot.perception.head_pose import face_forward
from hsr_handover.robot.perception.torso_depth import torso_shoulder_depths

NO_VALID_DEPTH = "no valid depth"
NONE_DETECTED = "no keypoints detected"

# The depth a keypoint is lifted with: a low percentile of the valid depths in a 5 x 5 window.
# A limb is a few pixels wide and stands in front of whatever is behind it, so a pixel that
# slips off its edge onto the table or the wall reads farther: the near quarter of the window is
# the limb, where a median would take the background once half the window has slipped off.
DEPTH_PERCENTILE = 25.0
# The depth a keypoint the body check dropped is lifted with again: its window's far quarter.
# A keypoint seen beside something nearer (a face beside the hand pointing past it, 60 cm in
# front) is lifted onto that by the near quarter; its own surface is the farther part of the
# window.
RELIFT_PERCENTILE = 75.0


@dataclasses.dataclass(frozen=True)
class Skeleton:
    """A person's COCO-18 keypoints in the image and in the world (paper 3.2).

    `pixels` (18, 2): detected pixels (u, v), NaN where not detected. `points` (18, 3): world
    points of the body surface seen at the pixels, NaN where not lifted. `confidence` (18,):
    in [0, 1], 0 = missing (not detected, or detected without depth to lift it; such a
    keypoint keeps its pixel). `status`: "ok" when any keypoint is present, else why none is.
    `torso_forward` (3,): the horizontal unit vector the chest faces in the world, from its
    plane in the depth image (`chest_plane`); NaN when the chest was not seen. `face_forward`
    (3,): the unit vector the face points along in the world, from the head's shape in the
    depth image (`head_pose`); NaN when the skull and the nose tip were not found.
    """

    pixels: np.ndarray
    points: np.ndarray
    confidence: np.ndarray
    status: str = STATUS_OK
    torso_forward: np.ndarray = dataclasses.field(default_factory=lambda: np.full(3, np.nan))
    face_forward: np.ndarray = dataclasses.field(default_factory=lambda: np.full(3, np.nan))

    def __post_init__(self) -> None:
        freeze_keypoint_arrays(self, {"pixels": 2, "points": 3})
        for name in ("torso_forward", "face_forward"):
            forward = np.array(getattr(self, name), dtype=float)
            if forward.shape != (3,):
                raise ValueError(f"{name}: expected 3 values, got shape {forward.shape}")
            forward.flags.writeable = False
            object.__setattr__(self, name, forward)

    @classmethod
    def missing(cls, status: str) -> Skeleton:
        """An empty skeleton that says why it is empty."""
        return cls(no_keypoints(2), no_keypoints(3), np.zeros(NUM_KEYPOINTS), status)

    @property
    def visible(self) -> np.ndarray:
        """(18,) bool: which keypoints are present (confidence > 0, with a 3-D point)."""
        return self.confidence > 0

    @property
    def is_empty(self) -> bool:
        return not self.visible.any()

    def keypoint(self, name: str) -> Keypoint:
        """One keypoint by COCO-18 name; check `confidence > 0` before using its point."""
        i = keypoint_index(name)
        return Keypoint(self.pixels[i], self.points[i], float(self.confidence[i]))

    def detection(self) -> Detection:
        """The 2-D part, as OpenPose would report it (keypoints without depth drop out)."""
        pixels = np.where(self.visible[:, None], self.pixels, np.nan)
        return Detection(pixels, self.confidence, self.status)


class Keypoint(NamedTuple):
    """One keypoint of a Skeleton: pixel (u, v), world point (m) and confidence."""

    pixel: np.ndarray
    point: np.ndarray
    confidence: float


def lift_keypoints(
    pixels: np.ndarray,
    confidence: np.ndarray,
    depth: np.ndarray,
    camera: PinholeCamera,
    X_WC: np.ndarray,
) -> Skeleton:
    """Lift 2-D keypoints (18, 2) with confidences (18,) to world points with the depth image
    (H, W) (m) of `camera` at pose `X_WC` (4 x 4), as the paper lifts OpenPose's keypoints
    with the Xtion's depth (3.2).

    Each point is the body surface at the keypoint's pixel (its window's near quarter). One
    lifted where no body could hold it with the others (`body_consistent`: onto something in
    front of it) is lifted again from its window's far quarter, and checked again with the
    others. A shoulder hidden behind its arm takes its depth from the torso
    (`torso_shoulder_depths`). A keypoint without valid depth, or still where no body could
    hold it, keeps its pixel but gets confidence 0 and no point. The torso's facing comes from
    the chest's plane below the detected shoulders (`chest_forward`), the face's from the
    head's shape round the detected face (`face_forward`).
    """
    depth = checked_depth(depth, camera)
    pixels = np.asarray(pixels, dtype=float)
    confidence = np.asarray(confidence, dtype=float)
    detected = (confidence > 0) & np.isfinite(pixels).all(axis=1)
    detected[detected] = camera.contains(pixels[detected])
    if not detected.any():
        return Skeleton.missing(NONE_DETECTED)
    pixels = np.where(detected[:, None], pixels, np.nan)
    surface_depth = np.full(NUM_KEYPOINTS, np.nan)
    surface_depth[detected] = window_depths(depth, pixels[detected], DEPTH_PERCENTILE)
    points = no_keypoints(3)
    lifted = np.isfinite(surface_depth)
    points[lifted] = camera.deproject(pixels[lifted], surface_depth[lifted], X_WC)
    kept = body_consistent(points, lifted)
    again = lifted & ~kept
    if again.any():
        surface_depth[again] = window_depths(depth, pixels[again], RELIFT_PERCENTILE)
        points[again] = camera.deproject(pixels[again], surface_depth[again], X_WC)
        kept = body_consistent(points, kept | again)  # the same windows: valid depths
    kept_depth = np.where(kept, surface_depth, np.nan)
    torso_depth = torso_shoulder_depths(kept_depth, detected)
    mended = np.isfinite(torso_depth) & (torso_depth != kept_depth)
    points[mended] = camera.deproject(pixels[mended], torso_depth[mended], X_WC)
    lifted = kept | mended
    points[~lifted] = np.nan
    status = STATUS_OK if lifted.any() else NO_VALID_DEPTH
    seen = np.where(detected, confidence, 0.0)
    chest = chest_forward(depth, pixels, seen, camera, X_WC)
    face = face_forward(depth, pixels, seen, camera, X_WC)
    return Skeleton(
        pixels, points, np.where(lifted, confidence, 0.0), status, _or_nan(chest), _or_nan(face)
    )


def _or_nan(direction: np.ndarray | None) -> np.ndarray:
    return np.full(3, np.nan) if direction is None else direction


def lift_detection(
    detection: Detection, depth: np.ndarray, camera: PinholeCamera, X_WC: np.ndarray
) -> Skeleton:
    """The robot's side of the skeleton: a detection lifted with the depth image of the same
    capture (`lift_keypoints`), or an empty skeleton that says why: "person not in view", "no
    valid depth" (the depth image holds no measurement at all, or none at the detected
    keypoints), or the detection's own status."""
    depth = checked_depth(depth, camera)
    if detection.status == NOT_IN_VIEW:
        return Skeleton.missing(NOT_IN_VIEW)
    if not valid_depth(depth).any():
        return Skeleton.missing(NO_VALID_DEPTH)
    if detection.status != STATUS_OK:
        return Skeleton.missing(detection.status)
    return lift_keypoints(detection.pixels, detection.confidence, depth, camera, X_WC)

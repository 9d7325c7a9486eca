"""A simulated OpenPose detector and the lifting of its 2-D keypoints to 3-D (paper 3.2).

The paper detects the person with OpenPose: 18 keypoints in the COCO order
(`COCO18_KEYPOINTS`), each a pixel with a confidence, lifted to 3-D with the RGB-D camera's
depth image. This module models that sensor on numpy arrays:

- `detect_keypoints` turns the person's true keypoints into what OpenPose reports: the
  projection plus pixel noise, face points dropped at random (OpenPose often misses them),
  nothing for keypoints out of view or hidden behind something (the far arm when the right
  hand points left), and a confidence that falls near the image border.
- `lift_keypoints` turns 2-D keypoints, simulated or recorded, into world points with the
  depth image. The point it gives is the body SURFACE seen at the keypoint's pixel, not the
  joint centre: a few cm nearer the camera (the limb's radius; up to about 13 cm at a
  shoulder whose arm points toward the camera). Later stages use rays between keypoints
  (shoulder-elbow-wrist, the face plane), which such offsets barely turn.

Convention: a keypoint's confidence is 0 exactly when it is missing; a keypoint of a
`Skeleton` with confidence > 0 always has a finite 3-D point.
"""

from __future__ import annotations

import dataclasses
from typing import NamedTuple

import numpy as np

from hsr_handover.perception.body_check import body_consistent
from hsr_handover.perception.chest_plane import chest_forward
from hsr_handover.perception.coco18 import (
    COCO18_KEYPOINTS,
    COCO18_LIMBS,
    FACE_KEYPOINTS,
    NUM_KEYPOINTS,
    keypoint_index,
)
from hsr_handover.perception.pinhole import PinholeCamera, valid_depth
from hsr_handover.perception.torso_depth import torso_shoulder_depths

_FACE_INDICES = np.array([COCO18_KEYPOINTS.index(name) for name in FACE_KEYPOINTS])


STATUS_OK = "ok"
NOT_IN_VIEW = "person not in view"
NO_VALID_DEPTH = "no valid depth"
ALL_HIDDEN = "person hidden: no keypoint visible"
NONE_DETECTED = "no keypoints detected"
NO_DEPTH_IMAGE = "no depth image"

# OpenPose-like confidences: high inside the image, lower where a keypoint's surroundings
# are cut off by the border (OpenPose scores a part by the image evidence around it).
INTERIOR_CONFIDENCE = 0.9
BORDER_CONFIDENCE = 0.6
BORDER_BAND_PX = 32.0

# The depth a keypoint is lifted with: a low percentile of the valid depths in a 5 x 5 window.
# A limb is a few pixels wide and stands in front of whatever is behind it, so a pixel that
# slips off its edge onto the table or the wall reads farther: the near quarter of the window is
# the limb, where a median would take the background once half the window has slipped off.
DEPTH_PERCENTILE = 25.0
# The depth a keypoint the body check dropped is lifted with again: its window's far quarter.
# A keypoint seen beside something nearer (a face beside the hand pointing past it, 60 cm in
# front: the intent reference's trial 46) is lifted onto that by the near quarter; its own
# surface is the farther part of the window.
RELIFT_PERCENTILE = 75.0
# Half-size of the depth window a keypoint is lifted from: the window survives a pixel
# that slips off a limb's edge onto the background or a depth hole.
DEPTH_WINDOW_HALF = 2


def _freeze_keypoint_arrays(instance, widths: dict[str, int]) -> None:
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


def _no_keypoints(width: int) -> np.ndarray:
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
        _freeze_keypoint_arrays(self, {"pixels": 2})

    @classmethod
    def missing(cls, status: str) -> Detection:
        """No keypoint detected, for the reason `status`."""
        return cls(_no_keypoints(2), np.zeros(NUM_KEYPOINTS), status)


@dataclasses.dataclass(frozen=True)
class Skeleton:
    """A person's COCO-18 keypoints in the image and in the world (paper 3.2).

    `pixels` (18, 2): detected pixels (u, v), NaN where not detected. `points` (18, 3): world
    points of the body surface seen at the pixels, NaN where not lifted. `confidence` (18,):
    in [0, 1], 0 = missing (not detected, or detected without depth to lift it; such a
    keypoint keeps its pixel). `status`: "ok" when any keypoint is present, else why none is.
    `torso_forward` (3,): the horizontal unit vector the chest faces in the world, from its
    plane in the depth image (`chest_plane`); NaN when the chest was not seen.
    """

    pixels: np.ndarray
    points: np.ndarray
    confidence: np.ndarray
    status: str = STATUS_OK
    torso_forward: np.ndarray = dataclasses.field(default_factory=lambda: np.full(3, np.nan))

    def __post_init__(self) -> None:
        _freeze_keypoint_arrays(self, {"pixels": 2, "points": 3})
        forward = np.array(self.torso_forward, dtype=float)
        if forward.shape != (3,):
            raise ValueError(f"torso_forward: expected 3 values, got shape {forward.shape}")
        forward.flags.writeable = False
        object.__setattr__(self, "torso_forward", forward)

    @classmethod
    def missing(cls, status: str) -> Skeleton:
        """An empty skeleton that says why it is empty."""
        return cls(_no_keypoints(2), _no_keypoints(3), np.zeros(NUM_KEYPOINTS), status)

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


@dataclasses.dataclass(frozen=True)
class SkeletonNoise:
    """How the simulated detector errs.

    `pixel_sigma`: Gaussian pixel noise (px, per axis). `face_drop_probability`: chance that
    each face keypoint (nose, eyes, ears) goes missing, independently (OpenPose misses face
    points often, paper 3.2). `occlusion_margin` (m): a keypoint is hidden when the depth
    image shows a surface nearer than the keypoint by more than this, unless that surface is
    the person's own body around the keypoint: within `own_body_radius` (m) of a bone meeting
    at it (limbs are 3.5-7 cm thick, the trunk's front is 11 cm from its midline, and an arm
    raised toward the camera covers its own shoulder and elbow without hiding them).
    """

    pixel_sigma: float = 2.0
    face_drop_probability: float = 0.1
    occlusion_margin: float = 0.05
    own_body_radius: float = 0.12

    def __post_init__(self) -> None:
        if not self.pixel_sigma >= 0:
            raise ValueError(f"pixel_sigma: expected >= 0, got {self.pixel_sigma}")
        if not 0 <= self.face_drop_probability <= 1:
            raise ValueError(
                f"face_drop_probability: expected in [0, 1], got {self.face_drop_probability}"
            )
        if not (self.occlusion_margin >= 0 and self.own_body_radius >= 0):
            raise ValueError(
                "occlusion_margin, own_body_radius: expected >= 0, got "
                f"{self.occlusion_margin}, {self.own_body_radius}"
            )


def checked_depth(depth: np.ndarray, camera: PinholeCamera) -> np.ndarray:
    """The depth image (H, W) as an array, after checking it is the camera's size."""
    depth = np.asarray(depth)
    if depth.shape != (camera.height, camera.width):
        raise ValueError(
            f"depth: expected a {camera.height} x {camera.width} image, got shape {depth.shape}"
        )
    return depth


def _pixel_indices(pixels: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Column and row of the pixel nearest each (u, v); callers pass in-image pixels."""
    return np.rint(pixels[:, 0]).astype(int), np.rint(pixels[:, 1]).astype(int)


def border_confidence(pixels: np.ndarray, camera: PinholeCamera) -> np.ndarray:
    """Confidence of in-image detections: INTERIOR_CONFIDENCE, falling linearly to
    BORDER_CONFIDENCE at the border over BORDER_BAND_PX."""
    to_border = np.minimum.reduce(
        [
            pixels[:, 0] + 0.5,
            camera.width - 0.5 - pixels[:, 0],
            pixels[:, 1] + 0.5,
            camera.height - 0.5 - pixels[:, 1],
        ]
    )
    fraction = np.clip(to_border / BORDER_BAND_PX, 0.0, 1.0)
    return BORDER_CONFIDENCE + (INTERIOR_CONFIDENCE - BORDER_CONFIDENCE) * fraction


def hidden_keypoints(
    keypoints_W: np.ndarray,
    camera: PinholeCamera,
    X_WC: np.ndarray,
    depth: np.ndarray,
    noise: SkeletonNoise,
) -> np.ndarray:
    """(18,) bool: in-view keypoints that something else hides (see `SkeletonNoise`).

    A depth of 0 (too near to measure) hides; NaN and +inf (nothing in range) do not.
    """
    seen_depth, keypoint_depth, pixels = camera.depth_seen(depth, keypoints_W, X_WC)
    with np.errstate(invalid="ignore"):
        nearer = seen_depth < keypoint_depth - noise.occlusion_margin
    hidden = np.zeros(NUM_KEYPOINTS, dtype=bool)
    for i in np.flatnonzero(nearer):
        # Something too near the lens to measure (depth 0) hides whatever is behind it.
        hidden[i] = seen_depth[i] <= 0 or _foreign_surface(
            camera.deproject(pixels[i], seen_depth[i], X_WC)[0], i, keypoints_W, noise
        )
    return hidden


HAND_LENGTH = 0.2  # m: an adult hand, wrist to fingertips
_WRIST_ELBOW = {keypoint_index(f"{s}_wrist"): keypoint_index(f"{s}_elbow") for s in "rl"}


def _foreign_surface(
    surface: np.ndarray, index: int, keypoints_W: np.ndarray, noise: SkeletonNoise
) -> bool:
    """Whether a surface point is farther than `own_body_radius` from every bone that meets
    at keypoint `index`, so it belongs to something else."""
    bones = np.array([limb for limb in COCO18_LIMBS if index in limb])
    starts, ends = keypoints_W[bones[:, 0]], keypoints_W[bones[:, 1]]
    for wrist, elbow in _WRIST_ELBOW.items():
        if index in (wrist, elbow):
            # COCO-18 has no hand: the hand continues the forearm past the wrist, and a hand
            # held towards the camera does not hide its own wrist or elbow.
            forearm = keypoints_W[wrist] - keypoints_W[elbow]
            hand_end = keypoints_W[wrist] + HAND_LENGTH * forearm / max(
                np.linalg.norm(forearm), 1e-9
            )
            starts, ends = np.vstack([starts, keypoints_W[wrist]]), np.vstack([ends, hand_end])
    along = ends - starts
    t = np.clip(((surface - starts) * along).sum(axis=1) / (along * along).sum(axis=1), 0, 1)
    distance = np.linalg.norm(starts + t[:, None] * along - surface, axis=1)
    return bool(distance.min() > noise.own_body_radius)


def detect_keypoints(
    keypoints_W: np.ndarray,
    camera: PinholeCamera,
    X_WC: np.ndarray,
    depth: np.ndarray,
    noise: SkeletonNoise,
    rng: np.random.Generator,
) -> Detection:
    """What a pose detector reports for a person whose true COCO-18 keypoints (18, 3) are
    `keypoints_W`, seen by `camera` at pose `X_WC` (4 x 4) with depth image `depth` (H, W) (m).

    The random draws have fixed sizes, so a generator seeded the same way gives the same
    noise whichever keypoints are visible.
    """
    keypoints_W = np.asarray(keypoints_W, dtype=float).reshape(NUM_KEYPOINTS, 3)
    depth = checked_depth(depth, camera)
    pixel_noise = noise.pixel_sigma * rng.standard_normal((NUM_KEYPOINTS, 2))
    face_dropped = rng.random(len(_FACE_INDICES)) < noise.face_drop_probability
    true_pixels, _, in_view = camera.project_in_view(keypoints_W, X_WC)
    if not in_view.any():
        return Detection.missing(NOT_IN_VIEW)
    pixels = true_pixels + pixel_noise
    detected = in_view & camera.contains(pixels)
    detected &= ~hidden_keypoints(keypoints_W, camera, X_WC, depth, noise)
    detected[_FACE_INDICES[face_dropped]] = False
    if not detected.any():
        return Detection.missing(ALL_HIDDEN)
    confidence = np.where(detected, border_confidence(pixels, camera), 0.0)
    return Detection(np.where(detected[:, None], pixels, np.nan), confidence)


def window_depths(
    depth: np.ndarray, pixels: np.ndarray, percentile: float = DEPTH_PERCENTILE
) -> np.ndarray:
    """The `percentile` of the valid depths in the 5 x 5 window around each in-image pixel
    (N, 2); NaN where the window holds no valid depth."""
    u, v = _pixel_indices(pixels)
    result = np.full(len(pixels), np.nan)
    h = DEPTH_WINDOW_HALF
    for i, (col, row) in enumerate(zip(u, v, strict=True)):
        window = depth[max(row - h, 0) : row + h + 1, max(col - h, 0) : col + h + 1]
        values = window[valid_depth(window)]
        if values.size:
            result[i] = np.percentile(values, percentile)
    return result


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
    the chest's plane below the detected shoulders (`chest_forward`).
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
    surface_depth[detected] = window_depths(depth, pixels[detected])
    points = _no_keypoints(3)
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
    facing = chest_forward(depth, pixels, np.where(detected, confidence, 0.0), camera, X_WC)
    forward = np.full(3, np.nan) if facing is None else facing
    return Skeleton(pixels, points, np.where(lifted, confidence, 0.0), status, forward)


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

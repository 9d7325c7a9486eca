"""A simulated OpenPose detector and the lifting of its 2-D keypoints to 3-D (paper 3.2).

The paper detects the person with OpenPose: 18 keypoints in the COCO order
(`COCO18_KEYPOINTS`), each a pixel with a confidence, lifted to 3-D with the RGB-D camera's
depth image. This module models that sensor on numpy arrays:

- `detect_keypoints` turns the person's true keypoints into what OpenPose reports: the
  projection erring as a `DetectorModel` says (a persistent bias and frame jitter, misses in
  runs, swapped arms, a wrist on an object: `perception.detector_model`), nothing for
  keypoints out of view or hidden behind something (the far arm when the right hand points
  left), and a confidence that falls near the image border.
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
    COCO18_LIMBS,
    NUM_KEYPOINTS,
    keypoint_index,
)
from hsr_handover.perception.detector_model import (
    ARM_KEYPOINTS,
    KEYPOINT_SHARE,
    WRISTS,
    DetectorModel,
    DetectorState,
    advance,
)
from hsr_handover.perception.pinhole import PinholeCamera, valid_depth
from hsr_handover.perception.torso_depth import torso_shoulder_depths

STATUS_OK = "ok"
NOT_IN_VIEW = "person not in view"
NO_VALID_DEPTH = "no valid depth"
ALL_HIDDEN = "person hidden: no keypoint visible"
NONE_DETECTED = "no keypoints detected"
NO_DEPTH_IMAGE = "no depth image"

# A spurious keypoint's confidence, as a share of a true one's: OpenPose's part maps peak lower on
# an object taken for a hand.
SPURIOUS_CONFIDENCE = (0.2, 0.5)
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
    noise: DetectorModel,
) -> np.ndarray:
    """(18,) bool: in-view keypoints that something else hides (see `DetectorModel`'s
    `occlusion_margin` and `own_body_radius`).

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
    surface: np.ndarray, index: int, keypoints_W: np.ndarray, noise: DetectorModel
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
    model: DetectorModel,
    rng: np.random.Generator,
    state: DetectorState | None = None,
) -> Detection:
    """What a pose detector reports for a person whose true COCO-18 keypoints (18, 3) are
    `keypoints_W`, seen by `camera` at pose `X_WC` (4 x 4) with depth image `depth` (H, W) (m),
    erring as `model` says with the persistent errors of `state` (`detector_model.advance`;
    None: a first frame's, drawn from `rng`).

    The random draws have fixed sizes, so a generator seeded the same way gives the same
    noise whichever keypoints are visible.
    """
    keypoints_W = np.asarray(keypoints_W, dtype=float).reshape(NUM_KEYPOINTS, 3)
    depth = checked_depth(depth, camera)
    jitter_sd = model.joint_error_m * np.sqrt(1.0 - model.bias_share) * KEYPOINT_SHARE[:, None]
    jitter_m = jitter_sd * rng.standard_normal((NUM_KEYPOINTS, 2))
    jitter_px = model.pixel_sigma * rng.standard_normal((NUM_KEYPOINTS, 2))
    share = rng.random(NUM_KEYPOINTS)  # where each confidence falls in its range
    if state is None:
        state = advance(DetectorState.start(), keypoints_W, np.zeros((0, 3)), 0.0, model, rng)
    true_pixels, keypoint_depth, in_view = camera.project_in_view(keypoints_W, X_WC)
    if not in_view.any():
        return Detection.missing(NOT_IN_VIEW)
    at_depth = np.where(in_view, keypoint_depth, 1.0)[:, None]
    metres_to_px = np.array([camera.fx, camera.fy]) / at_depth
    pixels = true_pixels + (state.bias + jitter_m) * metres_to_px + jitter_px
    detected = in_view & camera.contains(pixels)
    detected &= ~hidden_keypoints(keypoints_W, camera, X_WC, depth, model)
    detected &= ~state.missing
    confidence = border_confidence(pixels, camera) * (1.0 - model.confidence_spread * share)
    for k, wrist in enumerate(WRISTS):
        if np.isfinite(state.spurious[k]).all():  # on the object instead
            on_object, _, seen = camera.project_in_view(state.spurious[k][None], X_WC)
            if seen[0]:
                pixels[wrist] = on_object[0] + jitter_px[wrist]
                detected[wrist] = camera.contains(pixels[wrist : wrist + 1])[0]
                low, high = SPURIOUS_CONFIDENCE
                confidence[wrist] *= low + (high - low) * share[wrist]
    if state.swapped:
        right, left = ARM_KEYPOINTS["r"], ARM_KEYPOINTS["l"]
        for array in (pixels, detected, confidence):
            array[right + left] = array[left + right]
    if not detected.any():
        return Detection.missing(ALL_HIDDEN)
    confidence = np.where(detected, confidence, 0.0)
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

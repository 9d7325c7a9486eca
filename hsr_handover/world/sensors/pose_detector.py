"""The simulated OpenPose: what a pose detector reports for a person whose true keypoints the
world knows (paper 3.2).

`detect_keypoints` turns the person's true COCO-18 keypoints into OpenPose's 2-D report: the
projection erring as a `DetectorModel` says (a persistent bias and frame jitter, misses in runs,
swapped arms, a wrist on an object: `world.sensors.detector_model`), nothing for keypoints out
of view or hidden behind something (the far arm when the right hand points left), and a
confidence that falls near the image border.
"""

from __future__ import annotations

import numpy as np

from hsr_handover.interface.coco18 import COCO18_LIMBS, NUM_KEYPOINTS, keypoint_index
from hsr_handover.interface.keypoints import ALL_HIDDEN, NOT_IN_VIEW, Detection
from hsr_handover.interface.pinhole import PinholeCamera, checked_depth
from hsr_handover.world.sensors.detector_model import (
    ARM_KEYPOINTS,
    KEYPOINT_SHARE,
    WRISTS,
    DetectorModel,
    DetectorState,
    advance,
)

# A spurious keypoint's confidence, as a share of a true one's: OpenPose's part maps peak lower on
# an object taken for a hand.
SPURIOUS_CONFIDENCE = (0.2, 0.5)
# OpenPose-like confidences: high inside the image, lower where a keypoint's surroundings
# are cut off by the border (OpenPose scores a part by the image evidence around it).
INTERIOR_CONFIDENCE = 0.9
BORDER_CONFIDENCE = 0.6
BORDER_BAND_PX = 32.0


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

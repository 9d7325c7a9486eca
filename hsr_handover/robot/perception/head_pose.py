"""Which way the face points, from the head's shape in the depth image.

Eq. 17's face normal turns with the lifted eyes' depths: one degree of heading is 1.1 mm of
depth between eyes 6 cm apart, and each eye is lifted from where its pixel lands on the face,
a few millimetres off (the realistic detector's eyes err 5 mm in the image). On recorded
gestures its heading errs 3.3 deg from frame to frame (sd by the median absolute deviation)
and 2.4 deg over a gesture (root mean square of per-trial medians); the gaze turns that by
`head_gain` (1.45).

The head's shape does not depend on the keypoints' few millimetres. The skull is round and the
nose stands out of it, so the direction from the skull's centre to the tip of the nose is the
face's, less the nose's drop below it (head pose from the nose tip in a range image:
Breitenstein et al. 2008, CVPR; Fanelli et al. 2011, DAGM). The keypoints only say where to
look:

1. **The skull**: the sphere through four of the depth points within `HEAD_WINDOW_M` of the
   face's keypoints that holds the most of them (RANSAC over fixed draws), leaving out the
   face itself (within `FACE_CLEAR_M` of the nose's and eyes' pixels) and the neck (more than
   `NECK_BELOW_M` below the lowest of them); then refitted (algebraic least squares) to the
   points within a shrinking tolerance of it, so that a hand beside the face, the shoulders
   and the background drop out.
2. **The nose tip**: of the points within `NOSE_GATE_M` of the nose's pixel that stand more than
   `NOSE_OUT_M` out of the skull, those within `APEX_CAP_M` of the farthest; their directions
   from the skull's centre, weighted by how far out they stand. The tip of a round nose lies
   on the line from the skull's centre through the nose's centre, whichever side the camera
   sees it from (the centre of the nose points seen lies toward the camera: 0.19 of the head's
   turn from it).
3. **Checks**: a tip standing out less than `MIN_NOSE_OUT_M` is the nose seen edge on or not
   at all, and one turned more than `MAX_TURN_FROM_CAMERA_DEG` from the camera cannot be seen:
   either gives no direction, and the recogniser falls back on eq. 17.

The face's forward direction is the tip's direction raised by `NOSE_DROP_DEG` in its vertical
plane (the nose tip lies below the eyes and ahead of them: 4 cm below and 11 cm ahead of the
head's centre on the simulated head and, in proportion, on a person's).

On 12 recorded generated-layout gestures (1462 frames, realistic detector) the heading from the
nose tip errs 0.5 deg from frame to frame and 0.55 deg over a gesture (against 3.3 and 2.4 for
eq. 17), its elevation +0.4 deg (median; -0.1 to +1.0, 5th-95th percentile); 88 % of the frames
give a direction. Its error is the depth image's: with 5 mm of noise on every depth pixel, 2.5
and 1.0 deg.
"""

from __future__ import annotations

import math

import numpy as np

from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.interface.pinhole import PinholeCamera, valid_depth
from hsr_handover.robot.perception.depth_window import window_depths

HEAD_WINDOW_M = 0.17  # radius round the face's keypoints that holds the whole head
DEPTH_BAND_M = 0.2  # of the face's depth: nearer or farther is not the head
FACE_CLEAR_M = 0.045  # round the nose's and eyes' pixels: the face, left out of the skull
NECK_BELOW_M = 0.02  # below the lowest face keypoint: the chin, then the neck
SKULL_TOLERANCES_M = (0.01, 0.005, 0.003)  # the refits' inlier bands, shrinking
SPHERE_DRAWS = 128  # RANSAC's four-point draws
MIN_SKULL_POINTS = 15
SKULL_RADIUS_M = (0.06, 0.14)  # a fit outside this is not a head
NOSE_GATE_M = 0.03  # round the nose's pixel: its own error and the nose's size
NOSE_OUT_M = 0.011  # out of the skull: beyond the eyes' and cheeks' relief
NOSE_OUT_MAX_M = 0.06  # farther out is a hand or an arm in front of the face
APEX_CAP_M = 0.004  # the tip: the nose points within this of the farthest
MIN_NOSE_OUT_M = 0.025  # a tip standing out less is the nose seen edge on, or not seen
MAX_TURN_FROM_CAMERA_DEG = 70.0
NOSE_DROP_DEG = 20.6  # the nose tip's direction below the face's forward direction

NOSE = keypoint_index("nose")
_FACE = tuple(keypoint_index(name) for name in ("nose", "r_eye", "l_eye"))
# RANSAC's draws, fixed: uniform in [0, 1), scaled to however many points a head has.
_DRAWS = np.random.default_rng(0).random((SPHERE_DRAWS, 4))


def face_forward(
    depth: np.ndarray,
    pixels: np.ndarray,
    confidence: np.ndarray,
    camera: PinholeCamera,
    X_WC: np.ndarray,
) -> np.ndarray | None:
    """The unit vector (world) the face points along, from the depth image (H, W, m) round
    the detected COCO-18 `pixels` (18, 2) with their `confidence` (18,); None without the
    nose's keypoint, or without a skull and a nose tip that pass the checks."""
    found = _head_points(depth, pixels, confidence, camera, X_WC)
    if found is None:
        return None
    points, skull_side, near_nose = found
    skull = _skull(points[skull_side])
    if skull is None:
        return None
    center, radius = skull
    tip = _nose_tip(points[near_nose], center, radius)
    if tip is None:
        return None
    to_camera = np.asarray(X_WC, dtype=float)[:3, 3] - center
    if tip @ to_camera < math.cos(math.radians(MAX_TURN_FROM_CAMERA_DEG)) * np.linalg.norm(
        to_camera
    ):
        return None
    return _raised(tip, NOSE_DROP_DEG)


def _head_points(depth, pixels, confidence, camera, X_WC):
    """(world points round the face, which of them may be skull, which may be nose), or None."""
    pixels, confidence = np.asarray(pixels, dtype=float), np.asarray(confidence, dtype=float)
    face = [i for i in _FACE if confidence[i] > 0 and np.isfinite(pixels[i]).all()]
    if NOSE not in face:
        return None
    middle = pixels[face].mean(axis=0)
    face_depth = float(window_depths(depth, pixels[NOSE][None], 50.0)[0])
    if not np.isfinite(face_depth):
        return None
    per_metre = camera.fx / face_depth  # pixels per metre at the face
    reach = HEAD_WINDOW_M * per_metre
    rows, cols = np.mgrid[
        max(int(middle[1] - reach), 0) : min(int(middle[1] + reach) + 1, depth.shape[0]),
        max(int(middle[0] - reach), 0) : min(int(middle[0] + reach) + 1, depth.shape[1]),
    ]
    values = depth[rows, cols]
    inside = valid_depth(values) & (np.hypot(cols - middle[0], rows - middle[1]) <= reach)
    inside &= np.abs(values - face_depth) < DEPTH_BAND_M
    u, v, values = cols[inside], rows[inside], values[inside]
    if u.size < MIN_SKULL_POINTS:
        return None
    points = camera.deproject(np.column_stack([u, v]).astype(float), values, X_WC)
    skull_side = v < max(pixels[i][1] for i in face) + NECK_BELOW_M * per_metre
    for i in face:
        skull_side &= np.hypot(u - pixels[i][0], v - pixels[i][1]) > FACE_CLEAR_M * per_metre
    near_nose = np.hypot(u - pixels[NOSE][0], v - pixels[NOSE][1]) <= NOSE_GATE_M * per_metre
    return points, skull_side, near_nose


def _skull(points: np.ndarray) -> tuple[np.ndarray, float] | None:
    """The sphere (centre, radius) the skull's points lie on: the one through four of them
    that holds the most within `SKULL_TOLERANCES_M[-1]` (RANSAC over fixed draws, so that a
    hand beside the face does not pull the first fit), refitted to the points within each of
    `SKULL_TOLERANCES_M` of it. None when too few stay on it or its radius is not a head's."""
    if len(points) < MIN_SKULL_POINTS:
        return None
    found = _likeliest_sphere(points)
    if found is None:
        return None
    center, radius = found
    for tolerance in SKULL_TOLERANCES_M:
        on = np.abs(np.linalg.norm(points - center, axis=1) - radius) < tolerance
        if on.sum() < MIN_SKULL_POINTS:
            return None
        center, radius = _sphere(points[on])
    return (center, radius) if SKULL_RADIUS_M[0] <= radius <= SKULL_RADIUS_M[1] else None


def _likeliest_sphere(points: np.ndarray) -> tuple[np.ndarray, float] | None:
    """Of the spheres through four drawn points with a head's radius, the one that holds the
    most points within `SKULL_TOLERANCES_M[-1]`; None when no draw gives one."""
    draws = points[(_DRAWS * len(points)).astype(int)]  # (draws, 4, 3)
    design = np.concatenate([2.0 * draws, np.ones((*draws.shape[:2], 1))], axis=2)
    usable = np.abs(np.linalg.det(design)) > 1e-12
    if not usable.any():
        return None
    solution = np.linalg.solve(design[usable], (draws[usable] ** 2).sum(axis=2)[..., None])[..., 0]
    centers = solution[:, :3]
    radii = np.sqrt(np.maximum(solution[:, 3] + (centers**2).sum(axis=1), 0.0))
    head_sized = (radii >= SKULL_RADIUS_M[0]) & (radii <= SKULL_RADIUS_M[1])
    if not head_sized.any():
        return None
    centers, radii = centers[head_sized], radii[head_sized]
    distances = np.linalg.norm(points[:, None, :] - centers[None], axis=2)  # (N, spheres)
    held = (np.abs(distances - radii) < SKULL_TOLERANCES_M[-1]).sum(axis=0)
    best = int(np.argmax(held))
    return centers[best], float(radii[best])


def _sphere(points: np.ndarray) -> tuple[np.ndarray, float]:
    """The least-squares sphere through `points` (N, 3), algebraic (Kasa): |p|^2 = 2 p.c + k."""
    design = np.column_stack([2.0 * points, np.ones(len(points))])
    solution, *_ = np.linalg.lstsq(design, (points**2).sum(axis=1), rcond=None)
    center = solution[:3]
    return center, math.sqrt(max(float(solution[3] + center @ center), 0.0))


def _nose_tip(points: np.ndarray, center: np.ndarray, radius: float) -> np.ndarray | None:
    """The unit direction from the skull's centre to the nose tip among `points` (those near
    the nose's pixel); None when no tip stands out `MIN_NOSE_OUT_M`."""
    offsets = points - center
    distances = np.linalg.norm(offsets, axis=1)
    out = distances - radius
    nose = (out > NOSE_OUT_M) & (out < NOSE_OUT_MAX_M)
    if not nose.any() or out[nose].max() < MIN_NOSE_OUT_M:
        return None
    tip = nose & (out >= out[nose].max() - APEX_CAP_M)
    weights = out[tip] - (out[nose].max() - APEX_CAP_M) + 1e-4
    direction = (offsets[tip] / distances[tip, None] * weights[:, None]).sum(axis=0)
    return direction / np.linalg.norm(direction)


def _raised(direction: np.ndarray, degrees: float) -> np.ndarray:
    """`direction` turned up by `degrees` in its vertical plane."""
    heading = math.atan2(direction[1], direction[0])
    elevation = math.atan2(direction[2], math.hypot(direction[0], direction[1]))
    elevation = min(elevation + math.radians(degrees), math.pi / 2)
    level = math.cos(elevation)
    return np.array([level * math.cos(heading), level * math.sin(heading), math.sin(elevation)])

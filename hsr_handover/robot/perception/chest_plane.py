"""Which way the torso faces, from the plane of the chest in the depth image.

The shoulders' lifted points do not tell it. Their pixels lie at the body's outline, and the
depth there is whatever surface is nearest the camera: for a person turned from the camera,
the far shoulder reads the front of the chest. On the handover reference's intent trials (seed
7, 60 requests) the line between the lifted shoulders turned only a fifth as far as the person:
its error was -0.81 x the person's turn from the camera (correlation -0.95), 6 degrees at the
median and up to 13. The estimated gaze inherits (head_gain - 1) of that error, and it read a
neighbour where the arm was right.

The chest below the shoulders is a surface the camera sees face on: the plane fitted to its
depth points turns with the person. The patch is a parallelogram hanging from the shoulders'
pixels, the middle CHEST_ACROSS of their width across and CHEST_DOWN shoulder widths down, so
that neither the arms beside the trunk nor the neck above it enter. The plane is the one that
holds most of the patch's points within PLANE_TOLERANCE_M (RANSAC over fixed draws, so a frame
always gives the same answer): a forearm or an object in front of part of the chest, or the
background beside it, is left out. (A surface within a few cm in front of the chest and
covering much of the patch can still tilt it: a plane through both may hold the most.) A
patch with too few points on one plane gives no direction.
"""

from __future__ import annotations

import numpy as np

from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.interface.pinhole import PinholeCamera, valid_depth

CHEST_ACROSS = 0.6  # of the shoulders' width, centred between them
CHEST_DOWN = (0.1, 0.5)  # shoulder widths below the shoulder line: the patch's top and bottom
CHEST_GRID = (15, 10)  # samples across and down the patch
MIN_CHEST_POINTS = 40  # of the 150 samples, on the chest's plane
PLANE_TOLERANCE_M = 0.01  # a point this near the plane lies on it (clothes, depth noise)
PLANE_DRAWS = 64  # RANSAC's three-point draws
MIN_SHOULDER_WIDTH_PX = 6.0  # narrower, the shoulders span too few pixels for a patch
MIN_NORMAL_HORIZONTAL = 0.5  # of the plane's unit normal: a chest is upright
MAX_TURN_FROM_CAMERA_DEG = 60.0  # a chest the camera sees enough of to fit is turned toward it

_SHOULDERS = (keypoint_index("r_shoulder"), keypoint_index("l_shoulder"))
# The patch's samples as (across, down) offsets: across in shoulders' widths from their middle,
# down in shoulder widths below their line.
_ACROSS, _DOWN = (
    grid.ravel()
    for grid in np.meshgrid(
        np.linspace(-CHEST_ACROSS / 2, CHEST_ACROSS / 2, CHEST_GRID[0]),
        np.linspace(*CHEST_DOWN, CHEST_GRID[1]),
    )
)
# RANSAC's draws, fixed: uniform in [0, 1), scaled to however many points a patch has.
_DRAWS = np.random.default_rng(0).random((PLANE_DRAWS, 3))


def chest_forward(
    depth: np.ndarray,
    pixels: np.ndarray,
    confidence: np.ndarray,
    camera: PinholeCamera,
    X_WC: np.ndarray,
) -> np.ndarray | None:
    """The horizontal unit vector (world) the chest faces, from the depth image (H, W, m) and
    the detected COCO-18 `pixels` (18, 2) with their `confidence` (18,); None without both
    shoulders, or without a patch of chest plane enough to fit."""
    patch = _chest_pixels(pixels, confidence)
    if patch is None:
        return None
    u, v = patch
    inside = (u >= 0) & (u < depth.shape[1]) & (v >= 0) & (v < depth.shape[0])
    u, v = u[inside], v[inside]
    depths = depth[v, u]
    seen = valid_depth(depths)
    if seen.sum() < MIN_CHEST_POINTS:
        return None
    patch_pixels = np.column_stack([u[seen], v[seen]]).astype(float)
    chest = _plane_points(camera.deproject(patch_pixels, depths[seen], X_WC))
    return None if chest is None else _facing(chest, np.asarray(X_WC)[:3, 3])


def _chest_pixels(pixels: np.ndarray, confidence: np.ndarray):
    """(columns, rows) of the patch's samples, or None without both shoulders."""
    right, left = (np.asarray(pixels, dtype=float)[i] for i in _SHOULDERS)
    if not all(confidence[i] > 0 for i in _SHOULDERS) or not np.isfinite([right, left]).all():
        return None
    across = left - right
    width = float(np.linalg.norm(across))
    if width < MIN_SHOULDER_WIDTH_PX:
        return None
    down = np.array([-across[1], across[0]]) / width
    down = down if down[1] > 0 else -down  # image rows grow downward
    samples = (right + left) / 2 + np.outer(_ACROSS, across) + np.outer(_DOWN * width, down)
    return np.rint(samples[:, 0]).astype(int), np.rint(samples[:, 1]).astype(int)


def _plane_points(points: np.ndarray) -> np.ndarray | None:
    """The points (N, 3) on the plane through three of them that holds the most within
    PLANE_TOLERANCE_M; None when that plane holds fewer than MIN_CHEST_POINTS."""
    draws = (_DRAWS * len(points)).astype(int)
    first, second, third = (points[draws[:, k]] for k in range(3))
    normals = np.cross(second - first, third - first)
    lengths = np.linalg.norm(normals, axis=1)
    usable = lengths > 1e-9
    if not usable.any():
        return None
    normals = normals[usable] / lengths[usable, None]
    offsets = np.einsum("dk,dk->d", normals, first[usable])
    on_plane = np.abs(points @ normals.T - offsets) < PLANE_TOLERANCE_M  # (N, draws)
    best = on_plane[:, int(np.argmax(on_plane.sum(axis=0)))]
    return points[best] if best.sum() >= MIN_CHEST_POINTS else None


def _facing(points: np.ndarray, camera_position: np.ndarray) -> np.ndarray | None:
    """The horizontal normal of the plane fitted to `points`, toward the camera (the chest the
    camera sees faces it); None for a plane too tilted, or turned too far from the camera, to
    be a chest's (an arm hanging in front of the chest fits a plane edge on)."""
    center = points.mean(axis=0)
    offsets = points - center
    _, axes = np.linalg.eigh(offsets.T @ offsets)  # ascending: the first axis is the normal
    to_camera = camera_position - center
    normal = axes[:, 0] if axes[:, 0] @ to_camera > 0 else -axes[:, 0]
    horizontal = np.array([normal[0], normal[1], 0.0])
    length = float(np.linalg.norm(horizontal))
    toward = np.array([to_camera[0], to_camera[1], 0.0])
    toward /= max(float(np.linalg.norm(toward)), 1e-9)
    if length < MIN_NORMAL_HORIZONTAL:
        return None
    facing = horizontal / length
    if facing @ toward < np.cos(np.radians(MAX_TURN_FROM_CAMERA_DEG)):
        return None
    return facing

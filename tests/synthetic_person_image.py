"""A synthetic person facing a synthetic camera, for the skeleton's tests: the true COCO-18
keypoints and a depth image of the body's surface around them. Numpy only."""

from __future__ import annotations

import numpy as np

from hsr_handover.interface.pinhole import PinholeCamera

CAMERA = PinholeCamera.from_fov_x(320, 240, 1.05)
X_WC = np.eye(4)
SURFACE_OFFSET = 0.02
BODY_RADIUS_PX = 12

# A person facing the camera 2 m away (camera frame: x right, y down, z forward); the ankles
# fall below the image.
KEYPOINTS = np.array([
    [0.0, -0.55, 1.88], [0.0, -0.40, 2.0], [-0.20, -0.40, 2.0], [-0.26, -0.12, 1.95],
    [-0.24, 0.14, 1.85], [0.20, -0.40, 2.0], [0.26, -0.12, 2.0], [0.27, 0.15, 2.0],
    [-0.10, 0.10, 2.0], [-0.10, 0.35, 1.7], [-0.10, 0.90, 1.7], [0.10, 0.10, 2.0],
    [0.10, 0.35, 1.7], [0.10, 0.90, 1.7], [-0.035, -0.58, 1.90], [0.035, -0.58, 1.90],
    [-0.08, -0.56, 1.97], [0.08, -0.56, 1.97],
])  # fmt: skip


def synthetic_depth(offset: float = SURFACE_OFFSET) -> np.ndarray:
    """Body surface `offset` in front of the nearest keypoint (in the image) within
    BODY_RADIUS_PX of it, and the background out of range."""
    pixels, z = CAMERA.project(KEYPOINTS, X_WC)
    v, u = np.indices((CAMERA.height, CAMERA.width))
    distance = np.hypot(u[..., None] - pixels[:, 0], v[..., None] - pixels[:, 1])
    surface = (z - offset)[distance.argmin(axis=2)]
    return np.where(distance.min(axis=2) <= BODY_RADIUS_PX, surface, np.inf).astype(np.float32)

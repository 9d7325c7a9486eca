"""Pinhole camera geometry on numpy arrays: project world points to pixels and lift pixels with
their depth back to world points.

Conventions follow Drake's cameras: the camera frame C has z forward (the optical axis), x right
and y down in the image; pixel (u, v) has u along image columns and v along rows, the centre
of the pixel in column i and row j is at (i, j), and the principal point of a W x H image is
((W - 1) / 2, (H - 1) / 2), as in Drake's CameraInfo. `X_WC` is a 4 x 4 homogeneous pose of C in
the world W.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np


@dataclasses.dataclass(frozen=True)
class PinholeCamera:
    """Intrinsics of an ideal pinhole camera (no distortion), in pixels."""

    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float

    @classmethod
    def from_fov_x(cls, width: int, height: int, fov_x: float) -> PinholeCamera:
        """Square pixels and a centred principal point, from the horizontal field of view."""
        focal = width / (2.0 * math.tan(fov_x / 2.0))
        return cls(width, height, focal, focal, (width - 1) / 2.0, (height - 1) / 2.0)

    def scaled(self, width: int, height: int) -> PinholeCamera:
        """The same camera seen through an image resized to width x height (e.g. 200 x 200)."""
        sx, sy = width / self.width, height / self.height
        # Pixel centres sit at integers, so scale about the image's corner at (-0.5, -0.5).
        cx, cy = (self.cx + 0.5) * sx - 0.5, (self.cy + 0.5) * sy - 0.5
        return PinholeCamera(width, height, self.fx * sx, self.fy * sy, cx, cy)

    def project(self, points_W: np.ndarray, X_WC: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pixels (N, 2) as (u, v) and depths along the optical axis (N,) of world points (N, 3).

        Points behind the camera get depth <= 0; their pixels are meaningless.
        """
        points_C = to_frame(np.linalg.inv(X_WC), points_W)
        depth = points_C[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            u = self.fx * points_C[:, 0] / depth + self.cx
            v = self.fy * points_C[:, 1] / depth + self.cy
        return np.stack([u, v], axis=1), depth

    def deproject(self, pixels: np.ndarray, depth: np.ndarray, X_WC: np.ndarray) -> np.ndarray:
        """World points (N, 3) of pixels (N, 2) (u, v) with depths (N,) along the optical axis."""
        pixels = np.asarray(pixels, dtype=float).reshape(-1, 2)
        depth = np.asarray(depth, dtype=float).reshape(-1)
        x = (pixels[:, 0] - self.cx) * depth / self.fx
        y = (pixels[:, 1] - self.cy) * depth / self.fy
        return to_frame(X_WC, np.stack([x, y, depth], axis=1))

    def deproject_image(self, depth_image: np.ndarray, X_WC: np.ndarray) -> np.ndarray:
        """World points (H * W, 3) of every pixel of a depth image (H, W), row-major; pixels
        without a finite positive depth give NaN rows, so indices still match the image."""
        height, width = depth_image.shape
        v, u = np.indices((height, width), dtype=float)
        pixels = np.stack([u.ravel(), v.ravel()], axis=1)
        depth = depth_image.astype(float).ravel()
        valid = valid_depth(depth)
        points = self.deproject(pixels, np.where(valid, depth, np.nan), X_WC)
        points[~valid] = np.nan
        return points

    def project_in_view(
        self, points_W: np.ndarray, X_WC: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """`project`, and whether each point is in view (in front of the camera, in the image)."""
        pixels, depth = self.project(points_W, X_WC)
        return pixels, depth, (depth > 0) & self.contains(pixels)

    def depth_seen(
        self, depth_image: np.ndarray, points_W: np.ndarray, X_WC: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """What a depth image (H, W) taken from `X_WC` shows along each world point's (N, 3)
        line of sight: the image's value at the point's nearest pixel (NaN out of view), the
        point's own depth along the optical axis, and the point's pixel (N, 2)."""
        pixels, point_depth, in_view = self.project_in_view(points_W, X_WC)
        u, v = np.rint(np.where(in_view[:, None], pixels, 0.0)).astype(int).T
        seen = np.where(in_view, depth_image[v, u], np.nan)
        return seen, point_depth, pixels

    def contains(self, pixels: np.ndarray) -> np.ndarray:
        """Whether each pixel (N, 2) lies inside the image (its nearest pixel centre exists)."""
        u, v = pixels[:, 0], pixels[:, 1]
        return (u > -0.5) & (u < self.width - 0.5) & (v > -0.5) & (v < self.height - 0.5)


def valid_depth(depth: np.ndarray) -> np.ndarray:
    """Where a depth image (m) holds a measurement: finite and positive (Drake renders +inf
    beyond range and 0 too near; real sensors add NaN)."""
    return np.isfinite(depth) & (depth > 0)


def to_frame(X_AB: np.ndarray, points_B: np.ndarray) -> np.ndarray:
    """Points (N, 3) expressed in B, re-expressed in A, for a 4 x 4 pose X_AB."""
    points_B = np.asarray(points_B, dtype=float).reshape(-1, 3)
    return points_B @ X_AB[:3, :3].T + X_AB[:3, 3]


def checked_depth(depth: np.ndarray, camera: PinholeCamera) -> np.ndarray:
    """The depth image (H, W) as an array, after checking it is the camera's size."""
    depth = np.asarray(depth)
    if depth.shape != (camera.height, camera.width):
        raise ValueError(
            f"depth: expected a {camera.height} x {camera.width} image, got shape {depth.shape}"
        )
    return depth

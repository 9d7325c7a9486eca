"""A depth image with the camera that took it: how far past a point in the world the camera
sees, which tells whether the point is hidden, empty or unknown."""

from __future__ import annotations

import dataclasses

import numpy as np

from hsr_handover.interface.pinhole import PinholeCamera, valid_depth


@dataclasses.dataclass(frozen=True, eq=False)
class DepthView:
    """A depth image `depth` (H, W; m along the optical axis) taken by `camera` at `X_WC`
    (4 x 4 pose of the camera in the world)."""

    camera: PinholeCamera
    X_WC: np.ndarray
    depth: np.ndarray

    def depth_past(self, points_W: np.ndarray) -> np.ndarray:
        """How far (m, along the optical axis) behind each world point (N, 3) the camera sees a
        surface on the point's line of sight: negative where something nearer hides the
        point, +inf where nothing is in range behind it, NaN where the point is out of view
        or its pixel holds no measurement (NaN, or 0: too near to measure)."""
        seen, point_depth, _ = self.camera.depth_seen(self.depth, points_W, self.X_WC)
        measured = valid_depth(seen) | np.isposinf(seen)
        return np.where(measured, seen - point_depth, np.nan)

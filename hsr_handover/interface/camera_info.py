"""The head camera's intrinsics as the `camera_info` port carries them: Drake's CameraInfo."""

from __future__ import annotations

from pydrake.systems.sensors import CameraInfo

from hsr_handover.interface.pinhole import PinholeCamera


def to_camera_info(camera: PinholeCamera) -> CameraInfo:
    """The same intrinsics as Drake's CameraInfo, for renderers and point-cloud systems."""
    return CameraInfo(camera.width, camera.height, camera.fx, camera.fy, camera.cx, camera.cy)

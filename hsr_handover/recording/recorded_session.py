"""What the robot's perception reads from any recording, a session folder (`rgbd_session`) or a
ROS bag (`ros_bag_session`): so the same offline pipeline (`SessionPlayer`, `offline_intent`)
runs on either."""

from __future__ import annotations

from typing import Protocol

from hsr_handover.interface.keypoints import Detection
from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.recording.rgbd_session import SessionFrame


class RecordedSession(Protocol):
    """A recording's `camera`, its frames' `stamps` (s, rising), the pose detector's `keypoints`
    of each frame, the robot's `settings` it was recorded with ({}: the defaults) and where
    they came from (`settings_source`, for messages), and the frames left out, each with why
    (`skipped`); `frame(k)` loads frame k."""

    camera: PinholeCamera
    stamps: tuple[float, ...]
    keypoints: tuple[Detection, ...]
    settings: dict
    skipped: tuple[str, ...]

    @property
    def settings_source(self) -> str: ...

    def frame(self, k: int) -> SessionFrame: ...

"""SessionRecorder: writes what the robot's sensors give, frame by frame, as an RGB-D session
folder (`recording.rgbd_session`): colour, depth, the camera's pose and the skeleton."""

from __future__ import annotations

from pathlib import Path

from pydrake.systems.framework import Context

from hsr_handover.recording.capture_recorder import CaptureRecorder
from hsr_handover.recording.rgbd_session import SessionFrame, write_frame


class SessionRecorder(CaptureRecorder):
    """The camera's inputs (`CaptureRecorder`). Every `period` s (the camera's) it writes the
    frame captured then into `directory` (begun with `start_session`), frame k being the
    capture at k x `period`."""

    def __init__(self, directory: Path, period: float):
        super().__init__(period)
        self._directory = Path(directory)

    def write_capture(self, context: Context, frame: SessionFrame) -> None:
        write_frame(self._directory, round(frame.stamp / self._period), frame)

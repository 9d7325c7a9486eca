"""SessionPlayer: a recording (`recorded_session`: a session folder or a ROS bag) played back
on the ports the station's sensors would feed the robot, so its perception runs on a recording
as it runs live."""

from __future__ import annotations

import bisect

from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.systems.framework import Context, LeafSystem
from pydrake.systems.sensors import ImageDepth32F, ImageRgba8U

from hsr_handover.interface import (
    CAMERA_COLOR_IMAGE,
    CAMERA_DEPTH_IMAGE,
    CAMERA_IMAGE_TIME,
    CAMERA_POSE,
    SKELETON_KEYPOINTS,
)
from hsr_handover.interface.keypoints import Detection
from hsr_handover.recording.recorded_session import RecordedSession
from hsr_handover.recording.rgbd_session import SessionFrame

BEFORE_FIRST = "before the recording's first frame"


class SessionPlayer(LeafSystem):
    """Outputs `camera_color_image` (ImageRgba8U), `camera_depth_image` (ImageDepth32F, m),
    `camera_pose` (RigidTransform), `camera_image_time` (s) and `skeleton_keypoints`: frame k of
    `session` from its stamp until the next one's (the last frame holds to the end), with the
    stamps shifted by `-start` s so a recording may begin at any time."""

    def __init__(self, session: RecordedSession, start: float = 0.0):
        super().__init__()
        self._session, self._start = session, float(start)
        self._loaded: tuple[int, SessionFrame] | None = None
        width, height = session.camera.width, session.camera.height
        outputs = {
            CAMERA_COLOR_IMAGE: (ImageRgba8U(width, height), self._color),
            CAMERA_DEPTH_IMAGE: (ImageDepth32F(width, height), self._depth),
            CAMERA_POSE: (RigidTransform(), self._pose),
            CAMERA_IMAGE_TIME: (float("nan"), self._time),
            SKELETON_KEYPOINTS: (Detection.missing(BEFORE_FIRST), self._keypoints),
        }
        for name, (model, calc) in outputs.items():
            self.DeclareAbstractOutputPort(
                name, lambda model=model: AbstractValue.Make(model), calc,
                prerequisites_of_calc={self.time_ticket()},
            )  # fmt: skip

    def _index(self, context: Context) -> int:
        """The frame in force at the context's time; -1 before the first."""
        # The allowance keeps frame k at its own stamp despite rounding in the time.
        time = context.get_time() + self._start + 1e-9
        return bisect.bisect_right(self._session.stamps, time) - 1

    def _frame(self, context: Context) -> SessionFrame | None:
        index = self._index(context)
        if index < 0:
            return None
        if self._loaded is None or self._loaded[0] != index:
            self._loaded = (index, self._session.frame(index))  # a cache: frames load on demand
        return self._loaded[1]

    def _color(self, context: Context, output: AbstractValue) -> None:
        frame = self._frame(context)
        if frame is not None:
            image = output.get_mutable_value()
            image.mutable_data[:] = frame.color

    def _depth(self, context: Context, output: AbstractValue) -> None:
        frame = self._frame(context)
        if frame is not None:
            image = output.get_mutable_value()
            image.mutable_data[:, :, 0] = frame.depth

    def _pose(self, context: Context, output: AbstractValue) -> None:
        frame = self._frame(context)
        output.set_value(RigidTransform() if frame is None else RigidTransform(frame.X_WC))

    def _time(self, context: Context, output: AbstractValue) -> None:
        frame = self._frame(context)
        output.set_value(float("nan") if frame is None else frame.stamp - self._start)

    def _keypoints(self, context: Context, output: AbstractValue) -> None:
        index = self._index(context)
        inside = index >= 0
        output.set_value(
            self._session.keypoints[index] if inside else Detection.missing(BEFORE_FIRST)
        )

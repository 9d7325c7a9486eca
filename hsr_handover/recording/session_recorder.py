"""SessionRecorder: writes what the robot's sensors give, frame by frame, as an RGB-D session
folder (`perception.rgbd_session`): colour, depth, the camera's pose and the skeleton."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.systems.framework import Context, LeafSystem
from pydrake.systems.sensors import ImageDepth32F, ImageRgba8U

from hsr_handover.interface.keypoints import Detection
from hsr_handover.recording.rgbd_session import SessionFrame, write_frame


class SessionRecorder(LeafSystem):
    """Inputs named as the station's sensors: `camera_color_image`, `camera_depth_image`,
    `camera_pose`, `camera_image_time` and `skeleton_keypoints`. Every `period` s (the camera's)
    it writes the frame captured then into `directory` (begun with `start_session`), frame
    k being the capture at k x `period`."""

    def __init__(self, directory: Path, period: float):
        super().__init__()
        self._directory, self._period = Path(directory), float(period)
        self._color = self.DeclareAbstractInputPort(
            "camera_color_image", AbstractValue.Make(ImageRgba8U())
        )
        self._depth = self.DeclareAbstractInputPort(
            "camera_depth_image", AbstractValue.Make(ImageDepth32F())
        )
        self._pose = self.DeclareAbstractInputPort(
            "camera_pose", AbstractValue.Make(RigidTransform())
        )
        self._time = self.DeclareAbstractInputPort("camera_image_time", AbstractValue.Make(0.0))
        self._keypoints = self.DeclareAbstractInputPort(
            "skeleton_keypoints", AbstractValue.Make(Detection.missing(""))
        )
        # Publish events come after the updates at the same instant: the capture is in.
        self.DeclarePeriodicPublishEvent(self._period, 0.0, self._write)

    def _write(self, context: Context) -> None:
        stamp = float(self._time.Eval(context))
        if not math.isfinite(stamp):
            return
        frame = SessionFrame(
            stamp,
            np.array(self._color.Eval(context).data, copy=True),
            np.array(self._depth.Eval(context).data[:, :, 0], copy=True),
            self._pose.Eval(context).GetAsMatrix4(),
            self._keypoints.Eval(context),
        )
        write_frame(self._directory, round(stamp / self._period), frame)

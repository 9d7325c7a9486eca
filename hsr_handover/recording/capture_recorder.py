"""CaptureRecorder: the part every recorder shares, a system that reads the head camera's
capture on the ports the station's sensors give it, once per camera period."""

from __future__ import annotations

import math

import numpy as np
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
from hsr_handover.recording.rgbd_session import SessionFrame


class CaptureRecorder(LeafSystem):
    """Inputs named as the station's sensors: `camera_color_image`, `camera_depth_image`,
    `camera_pose`, `camera_image_time` and `skeleton_keypoints`. Every `period` s (the
    camera's) it hands the capture held then to `write_capture`, which a recorder defines."""

    def __init__(self, period: float):
        super().__init__()
        self._period = float(period)
        self._color = self.DeclareAbstractInputPort(
            CAMERA_COLOR_IMAGE, AbstractValue.Make(ImageRgba8U())
        )
        self._depth = self.DeclareAbstractInputPort(
            CAMERA_DEPTH_IMAGE, AbstractValue.Make(ImageDepth32F())
        )
        self._pose = self.DeclareAbstractInputPort(
            CAMERA_POSE, AbstractValue.Make(RigidTransform())
        )
        self._time = self.DeclareAbstractInputPort(CAMERA_IMAGE_TIME, AbstractValue.Make(0.0))
        self._keypoints = self.DeclareAbstractInputPort(
            SKELETON_KEYPOINTS, AbstractValue.Make(Detection.missing(""))
        )
        # Publish events come after the updates at the same instant: the capture is in.
        self.DeclarePeriodicPublishEvent(self._period, 0.0, self._publish)

    def _publish(self, context: Context) -> None:
        stamp = float(self._time.Eval(context))
        if not math.isfinite(stamp):  # nothing captured yet
            return
        frame = SessionFrame(
            stamp,
            np.array(self._color.Eval(context).data, copy=True),
            np.array(self._depth.Eval(context).data[:, :, 0], copy=True),
            self._pose.Eval(context).GetAsMatrix4(),
            self._keypoints.Eval(context),
        )
        self.write_capture(context, frame)

    def write_capture(self, context: Context, frame: SessionFrame) -> None:
        """Write `frame`, the capture held at the context's time."""
        raise NotImplementedError

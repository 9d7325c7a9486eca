"""RosBagRecorder: writes what the robot's sensors give, frame by frame, into a ROS bag
(`ros_bag_writer`): the head camera's images, intrinsics and pose, the skeleton, and the joints
as the encoders and the base's odometry read them; and, when the robot's planned motions are
connected, each one as the HSR's trajectory controllers take it, stamped when it started."""

from __future__ import annotations

import math

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.systems.framework import Context, LeafSystem
from pydrake.systems.sensors import ImageDepth32F, ImageRgba8U

from hsr_handover.hsr import BASE_JOINTS
from hsr_handover.interface import (
    CAMERA_COLOR_IMAGE,
    CAMERA_DEPTH_IMAGE,
    CAMERA_IMAGE_TIME,
    CAMERA_POSE,
    COMMANDED_TRAJECTORIES,
    HSR_STATE_MEASURED,
    SKELETON_KEYPOINTS,
)
from hsr_handover.interface.joint_trajectory import JointTrajectory
from hsr_handover.interface.keypoints import Detection
from hsr_handover.recording.rgbd_session import SessionFrame
from hsr_handover.recording.ros_bag_writer import RosBagWriter
from hsr_handover.recording.ros_topics import hsr_joint_name


class RosBagRecorder(LeafSystem):
    """Inputs named as the station's sensors: `camera_color_image`, `camera_depth_image`,
    `camera_pose`, `camera_image_time`, `skeleton_keypoints` and `hsr_state_measured` ([q; v]
    of `joints`, the model's names), and optionally `commanded_trajectories` (the robot's).
    Every `period` s (the camera's) it writes the capture and the joint state at the capture's
    time into `writer`, and the motions started since. Whoever made the writer closes it."""

    def __init__(self, writer: RosBagWriter, period: float, joints: tuple[str, ...]):
        super().__init__()
        missing = [name for name in BASE_JOINTS if name not in joints]
        if missing:
            raise ValueError(f"joints: expected the base's {', '.join(missing)}")
        self._writer, self._period = writer, float(period)
        self._base = [joints.index(name) for name in BASE_JOINTS]
        self._names = tuple(hsr_joint_name(name) for name in joints)
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
        self._state = self.DeclareVectorInputPort(HSR_STATE_MEASURED, 2 * len(joints))
        self._commanded = self.DeclareAbstractInputPort(
            COMMANDED_TRAJECTORIES, AbstractValue.Make(())
        )
        self._motions_written = 0  # a sink's own count: the bag is outside any context
        # Publish events come after the updates at the same instant: the capture is in.
        self.DeclarePeriodicPublishEvent(self._period, 0.0, self._write)

    def _write(self, context: Context) -> None:
        stamp = float(self._time.Eval(context))
        if not math.isfinite(stamp):
            return
        state = np.asarray(self._state.Eval(context), dtype=float)
        count = len(self._names)
        frame = SessionFrame(
            stamp,
            np.array(self._color.Eval(context).data, copy=True),
            np.array(self._depth.Eval(context).data[:, :, 0], copy=True),
            self._pose.Eval(context).GetAsMatrix4(),
            self._keypoints.Eval(context),
        )
        if self._writer.write_frame(frame, state[self._base]):
            self._writer.write_joint_state(stamp, self._names, state[:count], state[count:])
        if self._commanded.HasValue(context):
            self._write_motions(self._commanded.Eval(context))

    def _write_motions(self, trajectories: tuple[JointTrajectory, ...]) -> None:
        """The motions not yet written, each controller's part at the motion's start."""
        for trajectory in trajectories[self._motions_written :]:
            start, times = trajectory.start, trajectory.times
            for topic, names, positions, velocities in trajectory.for_controllers():
                self._writer.add_joint_trajectory(topic, start, names, times, positions, velocities)
        self._motions_written = len(trajectories)

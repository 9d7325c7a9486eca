"""RosBagRecorder: writes what the robot's sensors give, frame by frame, into a ROS bag
(`ros_bag_writer`): the head camera's images, intrinsics and pose, the skeleton, and the joints
as the encoders and the base's odometry read them; and, when the robot's planned motions are
connected, each one as the HSR's trajectory controllers take it, stamped when it started."""

from __future__ import annotations

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.systems.framework import Context

from hsr_handover.hsr import BASE_JOINTS
from hsr_handover.interface import COMMANDED_TRAJECTORIES, HSR_STATE_MEASURED
from hsr_handover.interface.joint_trajectory import JointTrajectory
from hsr_handover.recording.capture_recorder import CaptureRecorder
from hsr_handover.recording.rgbd_session import SessionFrame
from hsr_handover.recording.ros_bag_writer import RosBagWriter
from hsr_handover.recording.ros_topics import hsr_joint_name


class RosBagRecorder(CaptureRecorder):
    """The camera's inputs (`CaptureRecorder`), `hsr_state_measured` ([q; v] of `joints`, the
    model's names), and optionally `commanded_trajectories` (the robot's). Every `period` s
    (the camera's) it writes the capture and the joint state at the capture's time into
    `writer`, and the motions started since. Whoever made the writer closes it."""

    def __init__(self, writer: RosBagWriter, period: float, joints: tuple[str, ...]):
        super().__init__(period)
        missing = [name for name in BASE_JOINTS if name not in joints]
        if missing:
            raise ValueError(f"joints: expected the base's {', '.join(missing)}")
        self._writer = writer
        self._base = [joints.index(name) for name in BASE_JOINTS]
        self._names = tuple(hsr_joint_name(name) for name in joints)
        self._state = self.DeclareVectorInputPort(HSR_STATE_MEASURED, 2 * len(joints))
        self._commanded = self.DeclareAbstractInputPort(
            COMMANDED_TRAJECTORIES, AbstractValue.Make(())
        )
        self._motions_written = 0  # a sink's own count: the bag is outside any context

    def write_capture(self, context: Context, frame: SessionFrame) -> None:
        state = np.asarray(self._state.Eval(context), dtype=float)
        count = len(self._names)
        if self._writer.write_frame(frame, state[self._base]):
            self._writer.write_joint_state(frame.stamp, self._names, state[:count], state[count:])
        if self._commanded.HasValue(context):
            self._write_motions(self._commanded.Eval(context))

    def _write_motions(self, trajectories: tuple[JointTrajectory, ...]) -> None:
        """The motions not yet written, each controller's part at the motion's start."""
        for trajectory in trajectories[self._motions_written :]:
            start, times = trajectory.start, trajectory.times
            for topic, names, positions, velocities in trajectory.for_controllers():
                self._writer.add_joint_trajectory(topic, start, names, times, positions, velocities)
        self._motions_written = len(trajectories)

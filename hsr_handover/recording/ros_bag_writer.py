"""A session written as a ROS bag, with the topics and message types a Toyota HSR publishes
(`ros_topics`), so Foxglove, rviz, `ros2 bag info` and `hsr-handover intent` read it: a ROS 2
bag folder in MCAP, or a ROS 1 `.bag` file.

A bag is written under a hidden name beside its path (`.NAME.partial/NAME`) and moved to its
path only when `close` has written its index (ROS 1) or metadata.yaml (ROS 2); `abort`, or a
failure while writing, removes it. So a bag at the path is always complete, and a run that
fails leaves nothing there.
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import yaml
from rosbags.interfaces import (
    Qos,
    QosDurability,
    QosHistory,
    QosLiveliness,
    QosReliability,
    QosTime,
)
from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Ros2Writer

from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.recording import ros_messages as msgs
from hsr_handover.recording.rgbd_session import SessionFrame
from hsr_handover.recording.ros_topics import (
    BASE_FRAME,
    CAMERA_FRAME,
    CAMERA_INFO_TOPIC,
    CAMERA_LINK_FRAME,
    COLOR_TOPIC,
    DEPTH_TOPIC,
    JOINT_STATES_TOPIC,
    ODOM_FRAME,
    SETTINGS_TOPIC,
    SKELETON_TOPIC,
    TF_STATIC_TOPIC,
    TF_TOPIC,
)

ROS2_BAG_VERSION = 9  # metadata.yaml version, the newest rosbags writes (rosbag2 of Jazzy on)
_ZERO = QosTime(0, 0)
LATCHED_QOS = Qos(QosHistory.KEEP_LAST, 1, QosReliability.RELIABLE,
                  QosDurability.TRANSIENT_LOCAL, _ZERO, _ZERO, QosLiveliness.AUTOMATIC, _ZERO,
                  False)  # fmt: skip
"""/tf_static's and the settings' QoS in ROS 2: latched, as tf2's static broadcaster offers."""
LATCHED = {TF_STATIC_TOPIC, SETTINGS_TOPIC}


def partial_path(path: Path) -> Path:
    """Where the bag for `path` is written until it is complete."""
    return path.parent / f".{path.name}.partial" / path.name


class RosBagWriter:
    """Writes a session to `path` as a ROS bag (`version` "ros1" or "ros2"), each message at
    its header's stamp; `close` completes it, `abort` removes it."""

    def __init__(self, path: Path, version: str, camera: PinholeCamera):
        self.path, self.version, self.camera = Path(path), version, camera
        self._types = msgs.ros_types(version)
        self._working = partial_path(self.path)
        if self._working.parent.exists():
            shutil.rmtree(self._working.parent)
        self._working.parent.mkdir(parents=True)
        if version == msgs.ROS1:
            self._writer = Ros1Writer(self._working)
        else:
            self._writer = Ros2Writer(self._working, version=ROS2_BAG_VERSION,
                                      storage_plugin=StoragePlugin.MCAP)  # fmt: skip
        self._writer.open()
        self._connections: dict[str, tuple[object, str]] = {}
        self._seq: dict[str, int] = {}
        self._mount_written = False
        self._last_frame = -float("inf")

    def _connection(self, topic: str, msgtype: str):
        if topic not in self._connections:
            options = {"typestore": self._types.typestore}
            if self.version == msgs.ROS1:
                options["latching"] = 1 if topic in LATCHED else None
            elif topic in LATCHED:
                options["offered_qos_profiles"] = [LATCHED_QOS]
            connection = self._writer.add_connection(topic, msgtype, **options)
            self._connections[topic] = (connection, msgtype)
        connection, declared = self._connections[topic]
        if declared != msgtype:
            raise ValueError(f"{topic}: expected {declared} messages, got {msgtype}")
        return connection

    def _next_seq(self, topic: str) -> int:
        self._seq[topic] = self._seq.get(topic, -1) + 1
        return self._seq[topic]

    def write(self, topic: str, msgtype: str, stamp: float, message) -> None:
        """Write one message, logged at `stamp` (s)."""
        connection = self._connection(topic, msgtype)
        data = self._types.serialize(message, msgtype)
        self._writer.write(connection, msgs.to_nanoseconds(stamp), data)

    def write_settings(self, stamp: float, settings: dict) -> None:
        """The robot's perception settings (a session.yaml's sections), once."""
        text = yaml.safe_dump(settings, sort_keys=False)
        self.write(SETTINGS_TOPIC, msgs.STRING, stamp, msgs.string_message(self._types, text))

    def _write_static_camera_mount(self, stamp: float) -> None:
        """/tf_static: the camera's optical frame on its body frame (a rotation, REP 103)."""
        X = np.eye(4)
        X[:3, :3] = msgs.X_LINK_OPTICAL
        transform = msgs.transform_stamped(self._types, stamp, CAMERA_LINK_FRAME, CAMERA_FRAME, X)
        message = msgs.tf_message(self._types, [transform])
        self.write(TF_STATIC_TOPIC, msgs.TF_MESSAGE, stamp, message)

    def write_frame(self, frame: SessionFrame, base_xy_yaw: Sequence[float]) -> bool:
        """One capture: colour, depth, camera_info, the skeleton and /tf (odom -> base_footprint
        from the base's odometry `base_xy_yaw`, base_footprint -> the camera's body frame from
        the camera's pose `frame.X_WC` in odom), all stamped `frame.stamp`; the first frame
        also puts the camera's mount on /tf_static. A capture already written (a stamp not after
        the last frame's) is not written again: frames rise in time. Whether it was written."""
        types, stamp = self._types, frame.stamp
        if stamp <= self._last_frame:
            return False
        self._last_frame = stamp
        if not self._mount_written:
            self._write_static_camera_mount(stamp)
            self._mount_written = True
        for topic, msgtype, build in (
            (COLOR_TOPIC, msgs.IMAGE, lambda s: msgs.color_message(types, stamp, CAMERA_FRAME,
                                                                   frame.color, s)),
            (DEPTH_TOPIC, msgs.IMAGE, lambda s: msgs.depth_message(types, stamp, CAMERA_FRAME,
                                                                   frame.depth, s)),
            (CAMERA_INFO_TOPIC, msgs.CAMERA_INFO,
             lambda s: msgs.camera_info_message(types, stamp, CAMERA_FRAME, self.camera, s)),
            (SKELETON_TOPIC, msgs.POLYGON_STAMPED,
             lambda s: msgs.skeleton_message(types, stamp, CAMERA_FRAME, _people(frame), s)),
        ):  # fmt: skip
            self.write(topic, msgtype, stamp, build(self._next_seq(topic)))
        X_OB = msgs.base_pose(*base_xy_yaw)
        X_link_optical = np.eye(4)
        X_link_optical[:3, :3] = msgs.X_LINK_OPTICAL
        X_BL = np.linalg.inv(X_OB) @ frame.X_WC @ np.linalg.inv(X_link_optical)
        transforms = [
            msgs.transform_stamped(types, stamp, ODOM_FRAME, BASE_FRAME, X_OB),
            msgs.transform_stamped(types, stamp, BASE_FRAME, CAMERA_LINK_FRAME, X_BL),
        ]
        self.write(TF_TOPIC, msgs.TF_MESSAGE, stamp, msgs.tf_message(types, transforms))
        return True

    def write_joint_state(self, stamp: float, names: Sequence[str], positions: np.ndarray,
                          velocities: np.ndarray) -> None:  # fmt: skip
        """/hsrb/joint_states: the joints by the HSR's names, as the encoders read them."""
        message = msgs.joint_state_message(self._types, stamp, names, positions, velocities,
                                           self._next_seq(JOINT_STATES_TOPIC))  # fmt: skip
        self.write(JOINT_STATES_TOPIC, msgs.JOINT_STATE, stamp, message)

    def add_joint_trajectory(self, topic: str, stamp: float, joint_names: Sequence[str],
                             times_from_start: Sequence[float], positions: np.ndarray,
                             velocities: np.ndarray) -> None:  # fmt: skip
        """A trajectory_msgs/JointTrajectory on `topic` (the HSR's controllers listen on
        `ros_topics.ARM_TRAJECTORY_TOPIC` and `BASE_TRAJECTORY_TOPIC`):
        `positions` and `velocities` one row per time from the start (s), one column per joint,
        sent at `stamp` (s). Raises ValueError when the sizes disagree or the times do not
        rise."""
        times = np.asarray(times_from_start, dtype=float)
        shape = (len(times), len(joint_names))
        for name, values in (("positions", positions), ("velocities", velocities)):
            if np.shape(values) != shape:
                raise ValueError(
                    f"{name}: expected {shape[0]} x {shape[1]}, got {np.shape(values)}"
                )
        if len(times) == 0 or times[0] < 0 or np.any(np.diff(times) <= 0):
            raise ValueError("times_from_start: expected times from 0 on, rising")
        message = msgs.joint_trajectory_message(self._types, stamp, joint_names, times,
                                                positions, velocities)  # fmt: skip
        self.write(topic, msgs.JOINT_TRAJECTORY, stamp, message)

    def close(self) -> None:
        """Complete the bag and move it to its path."""
        self._writer.close()
        if self.path.is_dir():  # the empty directory a ROS 2 bag was asked to fill
            self.path.rmdir()
        os.replace(self._working, self.path)
        self._working.parent.rmdir()

    def abort(self) -> None:
        """Stop writing and remove what was written."""
        try:
            self._writer.close()
        except Exception:  # the bag is being thrown away; what failed is reported elsewhere
            pass
        shutil.rmtree(self._working.parent, ignore_errors=True)


def _people(frame: SessionFrame) -> list[np.ndarray]:
    """The frame's person as OpenPose would list them: none when no keypoint is seen."""
    keypoints = frame.keypoints
    if not np.any(keypoints.confidence > 0):
        return []
    return [np.column_stack([keypoints.pixels, keypoints.confidence])]

"""Small ROS 1 and ROS 2 bags built in the tests with `rosbags`' own writers: a head camera's
colour (rgb8, bgr8 or compressed PNG), depth (16UC1 mm or 32FC1 m), camera_info, TF and
skeletons, each stream's stamps chosen by the test."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import cv2
import numpy as np
from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Ros2Writer
from scipy.spatial.transform import Rotation

from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.recording import ros_messages as msgs
from hsr_handover.recording.ros_topics import (
    CAMERA_FRAME,
    CAMERA_INFO_TOPIC,
    COLOR_TOPIC,
    COMPRESSED_SUFFIX,
    DEPTH_TOPIC,
    SKELETON_TOPIC,
    TF_STATIC_TOPIC,
    TF_TOPIC,
)

CAMERA = PinholeCamera(32, 24, 30.0, 31.0, 15.5, 11.5)
FORMATS = ("ros1", "ros2-sqlite3", "ros2-mcap")
PERIOD = 0.1


def colour(k: int) -> np.ndarray:
    """Frame k's colour, RGB uint8."""
    return np.random.default_rng(k).integers(0, 256, (CAMERA.height, CAMERA.width, 3), np.uint8)


def depth_mm(k: int) -> np.ndarray:
    """Frame k's depth in whole millimetres, with a few pixels without a reading (0)."""
    depth = np.random.default_rng(100 + k).integers(400, 4000, (CAMERA.height, CAMERA.width))
    depth[0, :3] = 0
    return depth.astype(np.uint16)


def pose(seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    X = np.eye(4)
    X[:3, :3] = Rotation.from_rotvec(rng.normal(scale=0.5, size=3)).as_matrix()
    X[:3, 3] = rng.normal(size=3)
    return X


def person(k: int) -> np.ndarray:
    """Frame k's person, COCO-18 (u, v, confidence), a few pixels' drift per frame."""
    rng = np.random.default_rng(7)
    table = np.column_stack([rng.uniform(5, 25, 18) + 0.2 * k, rng.uniform(5, 18, 18),
                             rng.uniform(0.3, 1.0, 18)])  # fmt: skip
    table[3] = 0  # not found
    return table


@dataclasses.dataclass
class BagSpec:
    """What a test bag holds: the stamps of each stream (None: no such topic), the encodings."""

    color_stamps: list[float] | None = dataclasses.field(
        default_factory=lambda: [0.0, 0.1, 0.2, 0.3]
    )
    depth_stamps: list[float] | None = None  # None: the colour's
    color_encoding: str = "rgb8"  # rgb8, bgr8, png (CompressedImage), or anything to refuse
    depth_encoding: str = "16UC1"  # 16UC1 (mm) or 32FC1 (m)
    tf_stamps: list[float] | None = None  # None: the colour's
    skeleton_stamps: list[float] | None = None  # None: the colour's
    static_mount: bool = True
    odom: bool = True
    camera_info: bool = True


X_OB = [pose(1), pose(2)]  # odom -> base_footprint at the first and last TF stamp
X_BL = pose(3)  # base_footprint -> head_rgbd_sensor_link (a moving head, held here)
X_LC = np.eye(4)
X_LC[:3, :3] = msgs.X_LINK_OPTICAL


def base_at(share: float) -> np.ndarray:
    """odom -> base_footprint between the two poses (share 0 to 1, as TF interpolates)."""
    from scipy.spatial.transform import Slerp

    rotations = Rotation.from_matrix(np.stack([X_OB[0][:3, :3], X_OB[1][:3, :3]]))
    X = np.eye(4)
    X[:3, :3] = Slerp([0, 1], rotations)([share]).as_matrix()[0]
    X[:3, 3] = (1 - share) * X_OB[0][:3, 3] + share * X_OB[1][:3, 3]
    return X


def expected_X_WC(stamp: float, tf_stamps: list[float]) -> np.ndarray:
    share = (stamp - tf_stamps[0]) / (tf_stamps[-1] - tf_stamps[0])
    return base_at(share) @ X_BL @ X_LC


def _color_message(types, stamp: float, k: int, encoding: str):
    rgb = colour(k)
    header = msgs.header(types, stamp, CAMERA_FRAME)
    if encoding == "png":
        data = cv2.imencode(".png", cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR))[1].reshape(-1)
        return msgs.COMPRESSED_IMAGE, types.types[msgs.COMPRESSED_IMAGE](
            header=header, format="rgb8; png compressed bgr8", data=data
        )
    pixels = cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR) if encoding == "bgr8" else rgb
    return msgs.IMAGE, types.types[msgs.IMAGE](
        header=header, height=CAMERA.height, width=CAMERA.width, encoding=encoding,
        is_bigendian=0, step=CAMERA.width * 3, data=pixels.reshape(-1),
    )  # fmt: skip


def _depth_message(types, stamp: float, k: int, encoding: str):
    millimetres = depth_mm(k)
    if encoding == "32FC1":
        metres = millimetres.astype(np.float32) / np.float32(1000.0)
        metres[millimetres == 0] = np.nan
        data, step = metres.astype("<f4").tobytes(), CAMERA.width * 4
    else:
        data, step = millimetres.astype("<u2").tobytes(), CAMERA.width * 2
    return types.types[msgs.IMAGE](
        header=msgs.header(types, stamp, CAMERA_FRAME), height=CAMERA.height, width=CAMERA.width,
        encoding=encoding, is_bigendian=0, step=step, data=np.frombuffer(data, np.uint8),
    )  # fmt: skip


def build_bag(folder: Path, kind: str, spec: BagSpec, name: str = "session") -> Path:
    """Write a bag of `kind` (FORMATS) into `folder` as `spec` says; its path."""
    version = "ros1" if kind == "ros1" else "ros2"
    types = msgs.ros_types(version)
    path = folder / (f"{name}.bag" if version == "ros1" else name)
    if version == "ros1":
        writer = Ros1Writer(path)
    else:
        plugin = StoragePlugin.MCAP if kind.endswith("mcap") else StoragePlugin.SQLITE3
        writer = Ros2Writer(path, version=9, storage_plugin=plugin)
    writer.open()
    connections = {}

    def write(topic: str, msgtype: str, stamp: float, message) -> None:
        if topic not in connections:
            connections[topic] = writer.add_connection(topic, msgtype, typestore=types.typestore)
        writer.write(
            connections[topic], msgs.to_nanoseconds(stamp), types.serialize(message, msgtype)
        )

    color_stamps = spec.color_stamps or []
    depth_stamps = color_stamps if spec.depth_stamps is None else spec.depth_stamps
    tf_stamps = color_stamps if spec.tf_stamps is None else spec.tf_stamps
    skeleton_stamps = color_stamps if spec.skeleton_stamps is None else spec.skeleton_stamps
    if spec.static_mount:
        mount = msgs.transform_stamped(types, 0.0, "head_rgbd_sensor_link", CAMERA_FRAME, X_LC)
        write(TF_STATIC_TOPIC, msgs.TF_MESSAGE, 0.0, msgs.tf_message(types, [mount]))
    fixed = "odom" if spec.odom else "map"
    for stamp in tf_stamps:
        share = (stamp - tf_stamps[0]) / (tf_stamps[-1] - tf_stamps[0]) if len(tf_stamps) > 1 else 0
        transforms = [
            msgs.transform_stamped(types, stamp, fixed, "base_footprint", base_at(share)),
            msgs.transform_stamped(types, stamp, "base_footprint", "head_rgbd_sensor_link", X_BL),
        ]
        write(TF_TOPIC, msgs.TF_MESSAGE, stamp, msgs.tf_message(types, transforms))
    if spec.color_stamps is not None:
        topic = COLOR_TOPIC + (COMPRESSED_SUFFIX if spec.color_encoding == "png" else "")
        for k, stamp in enumerate(color_stamps):
            msgtype, message = _color_message(types, stamp, k, spec.color_encoding)
            write(topic, msgtype, stamp, message)
            if spec.camera_info:
                info = msgs.camera_info_message(types, stamp, CAMERA_FRAME, CAMERA)
                write(CAMERA_INFO_TOPIC, msgs.CAMERA_INFO, stamp, info)
    if spec.depth_stamps != []:
        for k, stamp in enumerate(depth_stamps):
            write(
                DEPTH_TOPIC, msgs.IMAGE, stamp, _depth_message(types, stamp, k, spec.depth_encoding)
            )
    for k, stamp in enumerate(skeleton_stamps):
        message = msgs.skeleton_message(types, stamp, CAMERA_FRAME, [person(k)])
        write(SKELETON_TOPIC, msgs.POLYGON_STAMPED, stamp, message)
    writer.close()
    return path

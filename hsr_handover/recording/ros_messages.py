"""ROS messages built from numpy arrays and read back into them, for ROS 1 (Noetic) and ROS 2
(Humble) bags alike, with `rosbags`' type stores: images, depth, camera intrinsics, transforms,
joint states and trajectories, skeletons and text.

Images follow sensor_msgs/Image's encodings: colour rgb8, bgr8, rgba8 or bgra8, or a
sensor_msgs/CompressedImage (PNG or JPEG); depth 16UC1 (or mono16) in millimetres or 32FC1 in
metres, 0 or NaN where there is no reading. A message another encoding is refused with
`UnsupportedEncoding`, naming it.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import cv2
import numpy as np
from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from scipy.spatial.transform import Rotation

from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.recording.rgbd_session import depth_to_millimetres

ROS1, ROS2 = "ros1", "ros2"
IMAGE = "sensor_msgs/msg/Image"
COMPRESSED_IMAGE = "sensor_msgs/msg/CompressedImage"
CAMERA_INFO = "sensor_msgs/msg/CameraInfo"
JOINT_STATE = "sensor_msgs/msg/JointState"
TF_MESSAGE = "tf2_msgs/msg/TFMessage"
POLYGON_STAMPED = "geometry_msgs/msg/PolygonStamped"
STRING = "std_msgs/msg/String"
JOINT_TRAJECTORY = "trajectory_msgs/msg/JointTrajectory"
COLOR_ENCODINGS = {"rgb8": (3, cv2.COLOR_RGB2RGBA), "bgr8": (3, cv2.COLOR_BGR2RGBA),
                   "rgba8": (4, None), "bgra8": (4, cv2.COLOR_BGRA2RGBA)}  # fmt: skip
DEPTH_ENCODINGS = {"16UC1": np.uint16, "mono16": np.uint16, "32FC1": np.float32}
MILLIMETRES = 1000.0  # per metre
_TF_MESSAGE_DEFINITION = "geometry_msgs/TransformStamped[] transforms"
X_LINK_OPTICAL = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
"""The rotation from a camera's body frame (x forward, y left, z up) to its optical frame
(z forward, x right, y down): columns are the optical axes in the body frame (REP 103)."""


class UnsupportedEncoding(ValueError):
    """An image whose encoding or format is not one read here: "<what>: expected ..., got ..."."""


@dataclasses.dataclass(frozen=True)
class RosTypes:
    """One ROS version's message classes (`types`) and serialisation (`serialize` and
    `deserialize` from and to bytes, as its bags store them)."""

    version: str
    typestore: object

    @property
    def types(self) -> dict:
        return self.typestore.types

    def serialize(self, message, msgtype: str) -> bytes:
        if self.version == ROS1:
            return bytes(self.typestore.serialize_ros1(message, msgtype))
        return bytes(self.typestore.serialize_cdr(message, msgtype))


def ros_types(version: str) -> RosTypes:
    """The type store of ROS 1 Noetic (with tf2_msgs/TFMessage, which rosbags' Noetic store
    lacks) or ROS 2 Humble."""
    if version == ROS1:
        typestore = get_typestore(Stores.ROS1_NOETIC)
        typestore.register(get_types_from_msg(_TF_MESSAGE_DEFINITION, TF_MESSAGE))
    else:
        typestore = get_typestore(Stores.ROS2_HUMBLE)
    return RosTypes(version, typestore)


# Time -----------------------------------------------------------------------------------------


def to_nanoseconds(seconds: float) -> int:
    return int(round(seconds * 1e9))


def stamp_seconds(stamp) -> float:
    """A builtin_interfaces Time or Duration (sec, nanosec) in seconds."""
    return stamp.sec + stamp.nanosec * 1e-9


def _time(types: RosTypes, seconds: float, kind: str = "Time"):
    sec, nanosec = divmod(to_nanoseconds(seconds), 1_000_000_000)
    return types.types[f"builtin_interfaces/msg/{kind}"](sec=sec, nanosec=nanosec)


def header(types: RosTypes, stamp: float, frame_id: str, seq: int = 0):
    """A std_msgs/Header (ROS 1's with its sequence number)."""
    cls = types.types["std_msgs/msg/Header"]
    if types.version == ROS1:
        return cls(seq=seq, stamp=_time(types, stamp), frame_id=frame_id)
    return cls(stamp=_time(types, stamp), frame_id=frame_id)


# Images ---------------------------------------------------------------------------------------


def color_message(types: RosTypes, stamp: float, frame_id: str, rgba: np.ndarray, seq: int = 0):
    """An RGBA image as sensor_msgs/Image rgb8 (the alpha dropped)."""
    rgb = np.ascontiguousarray(rgba[:, :, :3], dtype=np.uint8)
    height, width = rgb.shape[:2]
    return types.types[IMAGE](header=header(types, stamp, frame_id, seq), height=height,
                              width=width, encoding="rgb8", is_bigendian=0, step=width * 3,
                              data=rgb.reshape(-1))  # fmt: skip


def depth_message(types: RosTypes, stamp: float, frame_id: str, depth: np.ndarray, seq: int = 0):
    """Depth in metres as sensor_msgs/Image 16UC1 millimetres (0 where there is no reading),
    as the HSR's Xtion gives its registered depth."""
    millimetres = depth_to_millimetres(depth)
    height, width = millimetres.shape
    data = np.frombuffer(millimetres.astype("<u2").tobytes(), dtype=np.uint8)
    return types.types[IMAGE](header=header(types, stamp, frame_id, seq), height=height,
                              width=width, encoding="16UC1", is_bigendian=0, step=width * 2,
                              data=data)  # fmt: skip


def _rows(message, channels_bytes: int) -> np.ndarray:
    """The image's bytes as (height, width * channels_bytes), the rows' padding cut off."""
    data = np.asarray(message.data, dtype=np.uint8)
    height, width, step = int(message.height), int(message.width), int(message.step)
    if step < width * channels_bytes or data.size < height * step:
        raise UnsupportedEncoding(
            f"expected {height} rows of {step} bytes holding {width} pixels, got {data.size} bytes"
        )
    return data[: height * step].reshape(height, step)[:, : width * channels_bytes]


def color_rgba(message, msgtype: str) -> np.ndarray:
    """An RGBA uint8 image from a colour sensor_msgs/Image or CompressedImage."""
    if msgtype == COMPRESSED_IMAGE:
        image = cv2.imdecode(np.asarray(message.data, dtype=np.uint8), cv2.IMREAD_COLOR)
        if image is None or "depth" in message.format.lower():
            raise UnsupportedEncoding(
                f"expected a PNG or JPEG colour image, got format {message.format!r}"
            )
        return cv2.cvtColor(image, cv2.COLOR_BGR2RGBA)
    if msgtype != IMAGE:
        raise UnsupportedEncoding(f"expected {IMAGE} or {COMPRESSED_IMAGE}, got {msgtype}")
    if message.encoding not in COLOR_ENCODINGS:
        raise UnsupportedEncoding(
            f"expected encoding {', '.join(COLOR_ENCODINGS)}, got {message.encoding!r}"
        )
    channels, conversion = COLOR_ENCODINGS[message.encoding]
    pixels = _rows(message, channels).reshape(int(message.height), int(message.width), channels)
    return np.ascontiguousarray(pixels) if conversion is None else cv2.cvtColor(pixels, conversion)


def depth_metres(message, msgtype: str) -> np.ndarray:
    """Depth in float32 metres from a sensor_msgs/Image 16UC1 (mm) or 32FC1 (m); 0 where there is
    no reading (0 or NaN in the message)."""
    if msgtype != IMAGE or message.encoding not in DEPTH_ENCODINGS:
        got = message.encoding if msgtype == IMAGE else msgtype
        raise UnsupportedEncoding(
            f"expected {IMAGE} {', '.join(DEPTH_ENCODINGS)} depth, got {got!r}"
        )
    dtype = np.dtype(DEPTH_ENCODINGS[message.encoding])
    dtype = dtype.newbyteorder(">" if message.is_bigendian else "<")
    rows = _rows(message, dtype.itemsize)
    values = np.ascontiguousarray(rows).view(dtype).astype(np.float32)
    if DEPTH_ENCODINGS[message.encoding] is np.uint16:
        values /= np.float32(MILLIMETRES)
    values[~np.isfinite(values) | (values < 0)] = 0.0
    return values.reshape(int(message.height), int(message.width))


# Camera info ----------------------------------------------------------------------------------


def _field(message, name: str):
    """A CameraInfo matrix by its ROS 2 name (ROS 1 spells them in capitals)."""
    return (
        getattr(message, name, None) if hasattr(message, name) else getattr(message, name.upper())
    )


def camera_info_message(types: RosTypes, stamp: float, frame_id: str, camera: PinholeCamera,
                        seq: int = 0):  # fmt: skip
    """The intrinsics as sensor_msgs/CameraInfo: K and P from the pinhole, D zeros (plumb_bob),
    R the identity."""
    K = [camera.fx, 0.0, camera.cx, 0.0, camera.fy, camera.cy, 0.0, 0.0, 1.0]
    P = [camera.fx, 0.0, camera.cx, 0.0, 0.0, camera.fy, camera.cy, 0.0, 0.0, 0.0, 1.0, 0.0]
    matrices = {"d": np.zeros(5), "k": np.array(K), "r": np.eye(3).reshape(-1), "p": np.array(P)}
    if types.version == ROS1:
        matrices = {name.upper(): value for name, value in matrices.items()}
    roi = types.types["sensor_msgs/msg/RegionOfInterest"](
        x_offset=0, y_offset=0, height=0, width=0, do_rectify=False
    )
    return types.types[CAMERA_INFO](header=header(types, stamp, frame_id, seq),
                                    height=camera.height, width=camera.width,
                                    distortion_model="plumb_bob", binning_x=0, binning_y=0,
                                    roi=roi, **matrices)  # fmt: skip


def camera_from_info(message) -> PinholeCamera:
    """The intrinsics of the rectified images a CameraInfo describes: P's fx, fy, cx, cy (as
    image_geometry reads them for rectified images), or K's when P is unset, which then asks for
    zero distortion. Raises ValueError saying what is missing."""
    width, height = int(message.width), int(message.height)
    if width <= 0 or height <= 0:
        raise ValueError(f"width, height: expected positive sizes, got {width} x {height}")
    P = np.asarray(_field(message, "p"), dtype=float)
    if P.size == 12 and P[0] > 0 and P[5] > 0:
        return PinholeCamera(width, height, P[0], P[5], P[2], P[6])
    K = np.asarray(_field(message, "k"), dtype=float)
    D = np.asarray(_field(message, "d"), dtype=float)
    if K.size != 9 or not (K[0] > 0 and K[4] > 0):
        raise ValueError("K, P: expected the intrinsics (fx, fy > 0) in one of them")
    if np.any(D != 0):
        raise ValueError("D: expected zeros with P unset (rectified images)")
    return PinholeCamera(width, height, K[0], K[4], K[2], K[5])


# Transforms -----------------------------------------------------------------------------------


def transform_stamped(types: RosTypes, stamp: float, parent: str, child: str, X: np.ndarray):
    """A geometry_msgs/TransformStamped: `child`'s 4 x 4 pose `X` in `parent`."""
    T = types.types
    x, y, z, w = Rotation.from_matrix(X[:3, :3]).as_quat()
    transform = T["geometry_msgs/msg/Transform"](
        translation=T["geometry_msgs/msg/Vector3"](x=float(X[0, 3]), y=float(X[1, 3]),
                                                   z=float(X[2, 3])),
        rotation=T["geometry_msgs/msg/Quaternion"](x=x, y=y, z=z, w=w),
    )  # fmt: skip
    return T["geometry_msgs/msg/TransformStamped"](
        header=header(types, stamp, parent), child_frame_id=child, transform=transform
    )


def tf_message(types: RosTypes, transforms: Sequence) -> object:
    return types.types[TF_MESSAGE](transforms=list(transforms))


def transform_matrix(transform) -> np.ndarray:
    """A geometry_msgs/Transform as a 4 x 4 pose."""
    q, t = transform.rotation, transform.translation
    X = np.eye(4)
    X[:3, :3] = Rotation.from_quat([q.x, q.y, q.z, q.w]).as_matrix()
    X[:3, 3] = [t.x, t.y, t.z]
    return X


def base_pose(x: float, y: float, yaw: float) -> np.ndarray:
    """The 4 x 4 pose of a base standing on the floor at (x, y), turned by `yaw`."""
    X = np.eye(4)
    c, s = math.cos(yaw), math.sin(yaw)
    X[:2, :2] = [[c, -s], [s, c]]
    X[:2, 3] = [x, y]
    return X


# Joints, skeletons, text ----------------------------------------------------------------------


def joint_state_message(types: RosTypes, stamp: float, names: Sequence[str],
                        positions: np.ndarray, velocities: np.ndarray, seq: int = 0):  # fmt: skip
    return types.types[JOINT_STATE](header=header(types, stamp, "", seq), name=list(names),
                                    position=np.asarray(positions, dtype=float),
                                    velocity=np.asarray(velocities, dtype=float),
                                    effort=np.zeros(0))  # fmt: skip


def joint_trajectory_message(types: RosTypes, stamp: float, joint_names: Sequence[str],
                             times_from_start: Sequence[float], positions: np.ndarray,
                             velocities: np.ndarray):  # fmt: skip
    """trajectory_msgs/JointTrajectory: one point per time from the start (s), each with the
    joints' positions and velocities (rows: points, columns: `joint_names`)."""
    # Each point's row is serialised from its own memory: a column-sliced array's rows are not.
    positions = np.ascontiguousarray(positions, dtype=float).reshape(len(times_from_start), -1)
    velocities = np.ascontiguousarray(velocities, dtype=float).reshape(positions.shape)
    point = types.types["trajectory_msgs/msg/JointTrajectoryPoint"]
    points = [
        point(positions=p, velocities=v, accelerations=np.zeros(0), effort=np.zeros(0),
              time_from_start=_time(types, float(t), "Duration"))
        for t, p, v in zip(times_from_start, positions, velocities, strict=True)
    ]  # fmt: skip
    return types.types[JOINT_TRAJECTORY](
        header=header(types, stamp, ""), joint_names=list(joint_names), points=points
    )


def skeleton_message(types: RosTypes, stamp: float, frame_id: str, people: Sequence[np.ndarray],
                     seq: int = 0):  # fmt: skip
    """geometry_msgs/PolygonStamped: each person's (K, 3) keypoints (u px, v px, confidence) in
    OpenPose's order, one person after another; a missing keypoint is (0, 0, 0) as OpenPose
    writes it."""
    point = types.types["geometry_msgs/msg/Point32"]
    points = [
        point(x=float(u), y=float(v), z=float(c)) if c > 0 and np.isfinite(u + v)
        else point(x=0.0, y=0.0, z=0.0)
        for table in people for u, v, c in np.asarray(table, dtype=float)
    ]  # fmt: skip
    polygon = types.types["geometry_msgs/msg/Polygon"](points=points)
    return types.types[POLYGON_STAMPED](header=header(types, stamp, frame_id, seq), polygon=polygon)


def skeleton_points(message) -> np.ndarray:
    """A skeleton message's points as an (N, 3) table of u, v, confidence."""
    return np.array([[p.x, p.y, p.z] for p in message.polygon.points], dtype=float).reshape(-1, 3)


def string_message(types: RosTypes, text: str):
    return types.types[STRING](data=text)

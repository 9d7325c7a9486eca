"""A recorded RGB-D session on disk, frame by frame, in the formats robotics people use: what the
head camera saw and what the pose detector found, so the robot's perception and intent can run
on it offline, and a session recorded on a real robot can be read the same way.

    DIR/camera_info.yaml        intrinsics, as ROS's sensor_msgs/CameraInfo (K, D, R, P)
    DIR/session.yaml            optional: the settings the robot perceived with (`perception`,
                                `intent`, `seed`, as in a scenario); defaults without it
    DIR/color/NNNNNNNNNNNN.png  8-bit colour
    DIR/depth/NNNNNNNNNNNN.png  16-bit depth in millimetres, 0 where there is no reading
    DIR/pose/NNNNNNNNNNNN.yaml  `stamp` (s) and the camera's pose in the world: `position`
                                [x, y, z] (m) and `orientation` [x, y, z, w] (geometry_msgs/Pose),
                                of the optical frame (z forward, x right, y down)
    DIR/openpose/NNNNNNNNNNNN_keypoints.json   the skeleton as OpenPose writes it

NNNNNNNNNNNN is the frame's index in 12 digits, as OpenPose numbers frames; a frame is the
index found in `pose/`, and each of the others must hold it too. Depth beyond the sensor's
range, missing keypoints and frames with nobody in them are written as RGB-D cameras and
OpenPose write them: zeros.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import cv2
import numpy as np
import yaml
from scipy.spatial.transform import Rotation

from hsr_handover.interface.keypoints import Detection
from hsr_handover.interface.openpose_json import read_openpose_recording, write_openpose_json
from hsr_handover.interface.pinhole import PinholeCamera, valid_depth

CAMERA_INFO = "camera_info.yaml"
SESSION = "session.yaml"
SESSION_SECTIONS = {"simulation": ("seed",), "camera": ("rate_hz",), "perception": None,
                    "intent": None}  # fmt: skip
"""What a session.yaml may set: the robot's own settings (None: any key of the section). A
session is read as it was recorded, never the world it was recorded in."""
PERCEPTION_NOT_IN_SESSION = ("enabled", "attention", "skeleton_recording", "detector")
"""Perception settings a session leaves out: the world's sensor model, or not the robot's to
replay (a skeleton recording would also name a file outside the session)."""
MILLIMETRES = 1000.0  # per metre
DEPTH_LIMIT_M = 65.535  # the deepest a 16-bit millimetre image holds


def _name(index: int) -> str:
    return f"{index:012d}"


@dataclasses.dataclass(frozen=True)
class SessionFrame:
    """One frame as perception reads it: `color` (H, W, 4) uint8 RGBA, `depth` (H, W) float32
    metres (0 where there is no reading), `X_WC` the camera's 4 x 4 pose, `stamp` (s) and the
    pose detector's `keypoints`."""

    stamp: float
    color: np.ndarray
    depth: np.ndarray
    X_WC: np.ndarray
    keypoints: Detection


# Writing ------------------------------------------------------------------------------------


def camera_info_dict(camera: PinholeCamera, name: str = "head_rgbd_sensor") -> dict:
    """The intrinsics as ROS's CameraInfo YAML (camera_calibration_parsers' layout)."""
    K = [camera.fx, 0.0, camera.cx, 0.0, camera.fy, camera.cy, 0.0, 0.0, 1.0]
    P = [camera.fx, 0.0, camera.cx, 0.0, 0.0, camera.fy, camera.cy, 0.0, 0.0, 0.0, 1.0, 0.0]

    def matrix(rows: int, cols: int, data: list[float]) -> dict:
        return {"rows": rows, "cols": cols, "data": [float(x) for x in data]}

    return {
        "image_width": camera.width,
        "image_height": camera.height,
        "camera_name": name,
        "camera_matrix": matrix(3, 3, K),
        "distortion_model": "plumb_bob",
        "distortion_coefficients": matrix(1, 5, [0.0] * 5),
        "rectification_matrix": matrix(3, 3, [1, 0, 0, 0, 1, 0, 0, 0, 1]),
        "projection_matrix": matrix(3, 4, P),
    }


def start_session(directory: Path, camera: PinholeCamera, settings: dict | None = None) -> None:
    """Make the session's folders and write its intrinsics (and `settings`, when given)."""
    for folder in ("color", "depth", "pose", "openpose"):
        (directory / folder).mkdir(parents=True, exist_ok=True)
    (directory / CAMERA_INFO).write_text(yaml.safe_dump(camera_info_dict(camera)))
    if settings is not None:
        (directory / SESSION).write_text(yaml.safe_dump(settings, sort_keys=False))


def write_frame(directory: Path, index: int, frame: SessionFrame) -> None:
    """Write frame `index` of a session begun with `start_session`."""
    name = _name(index)
    bgr = cv2.cvtColor(np.ascontiguousarray(frame.color[:, :, :3]), cv2.COLOR_RGB2BGR)
    cv2.imwrite(str(directory / "color" / f"{name}.png"), bgr)
    cv2.imwrite(str(directory / "depth" / f"{name}.png"), depth_to_millimetres(frame.depth))
    rotation = Rotation.from_matrix(frame.X_WC[:3, :3])
    pose = {
        "stamp": float(frame.stamp),
        "position": [float(x) for x in frame.X_WC[:3, 3]],
        "orientation": [float(x) for x in rotation.as_quat()],  # x, y, z, w
    }
    (directory / "pose" / f"{name}.yaml").write_text(yaml.safe_dump(pose))
    people = [frame.keypoints] if np.any(frame.keypoints.confidence > 0) else []
    write_openpose_json(directory / "openpose" / f"{name}_keypoints.json", people)


def depth_to_millimetres(depth: np.ndarray) -> np.ndarray:
    """Metres to 16-bit millimetres, rounded; 0 where there is no reading or it is too deep."""
    millimetres = np.zeros(depth.shape, dtype=np.uint16)
    valid = valid_depth(depth) & (depth <= DEPTH_LIMIT_M)
    millimetres[valid] = np.rint(depth[valid] * MILLIMETRES).astype(np.uint16)
    return millimetres


# Reading ------------------------------------------------------------------------------------


class SessionError(ValueError):
    """A folder that is not a session as recorded here: "<path>: expected ..."."""


@dataclasses.dataclass(frozen=True)
class RgbdSession:
    """A session folder read: its `camera`, its frames' `stamps` (s, rising) and `indices`, the
    `settings` it was recorded with ({} when it has none), the pose detector's keypoints of
    each frame and the frames left out, each with why (`skipped`: an image missing or cut
    short); `frame(k)` loads frame k's images and pose."""

    directory: Path
    camera: PinholeCamera
    indices: tuple[int, ...]
    stamps: tuple[float, ...]
    poses: tuple[np.ndarray, ...]
    keypoints: tuple[Detection, ...]
    settings: dict
    skipped: tuple[str, ...] = ()

    @property
    def settings_source(self) -> str:
        """Where the settings are read from, for messages."""
        return str(self.directory / SESSION)

    def frame(self, k: int) -> SessionFrame:
        name = _name(self.indices[k])
        folder = self.directory
        color = _read_image(_inside(folder, folder / "color" / f"{name}.png"), cv2.IMREAD_COLOR)
        depth_path = _inside(folder, folder / "depth" / f"{name}.png")
        depth = _read_image(depth_path, cv2.IMREAD_ANYDEPTH)
        if depth.dtype != np.uint16 or depth.shape != color.shape[:2]:
            size = f"{color.shape[1]} x {color.shape[0]}"
            where = self.directory / "depth" / f"{name}.png"
            raise SessionError(f"{where}: expected 16-bit depth of the colour image's size {size}")
        rgba = cv2.cvtColor(color, cv2.COLOR_BGR2RGBA)
        metres = depth.astype(np.float32) / np.float32(MILLIMETRES)
        return SessionFrame(self.stamps[k], rgba, metres, self.poses[k], self.keypoints[k])


def _inside(directory: Path, path: Path) -> Path:
    """`path`, after checking that it lies inside the session's folder (a symbolic link that
    leads out of it is refused: a recording is read, never what it points at elsewhere)."""
    if not path.resolve().is_relative_to(directory.resolve()):
        raise SessionError(f"{path}: expected a file inside the session folder {directory}")
    return path


PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
PNG_END = b"\x00\x00\x00\x00IEND\xaeB`\x82"  # the IEND chunk every whole PNG ends with


def _read_image(path: Path, flags: int) -> np.ndarray:
    """The PNG at `path`; one cut short is refused before it is decoded (libpng would print
    its own error on the way)."""
    data = path.read_bytes() if path.is_file() else b""
    if not data.startswith(PNG_SIGNATURE):
        raise SessionError(f"{path}: expected a PNG image")
    if not data.endswith(PNG_END):
        raise SessionError(f"{path}: expected a whole PNG image; it is cut short")
    image = cv2.imdecode(np.frombuffer(data, dtype=np.uint8), flags)
    if image is None:
        raise SessionError(f"{path}: expected a PNG image")
    return image


def _load_yaml(path: Path) -> dict:
    try:
        data = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError) as error:
        raise SessionError(f"{path}: expected YAML: {error}".splitlines()[0]) from None
    if not isinstance(data, dict):
        raise SessionError(f"{path}: expected a YAML mapping")
    return data


def _numbers(path: Path, data: dict, key: str, count: int) -> np.ndarray:
    values = data.get(key)
    if isinstance(values, dict):  # a CameraInfo matrix: {rows, cols, data}
        values = values.get("data")
    array = np.asarray(values, dtype=float) if isinstance(values, list) else np.empty(0)
    if array.shape != (count,) or not np.all(np.isfinite(array)):
        raise SessionError(f"{path}: {key}: expected {count} finite numbers")
    return array


def read_camera_info(path: Path) -> PinholeCamera:
    """A CameraInfo YAML's intrinsics. Distortion must be zero: perception assumes a pinhole
    (rectify real images first, as ROS's image_proc does)."""
    data = _load_yaml(path)
    width, height = data.get("image_width"), data.get("image_height")
    if not all(isinstance(n, int) and n > 0 for n in (width, height)):
        raise SessionError(f"{path}: image_width, image_height: expected positive integers")
    K = _numbers(path, data, "camera_matrix", 9)
    if "distortion_coefficients" in data:
        distortion = data["distortion_coefficients"]
        values = distortion.get("data", []) if isinstance(distortion, dict) else distortion
        if any(value != 0 for value in values or []):
            raise SessionError(
                f"{path}: distortion_coefficients: expected zeros (rectified images)"
            )
    return PinholeCamera(width, height, K[0], K[4], K[2], K[5])


def _read_pose(path: Path) -> tuple[float, np.ndarray]:
    data = _load_yaml(path)
    stamp = _numbers(path, {"stamp": [data.get("stamp")]}, "stamp", 1)[0]
    position = _numbers(path, data, "position", 3)
    quaternion = _numbers(path, data, "orientation", 4)
    if not abs(np.linalg.norm(quaternion) - 1.0) < 1e-3:
        raise SessionError(f"{path}: orientation: expected a unit quaternion [x, y, z, w]")
    X_WC = np.eye(4)
    X_WC[:3, :3] = Rotation.from_quat(quaternion).as_matrix()
    X_WC[:3, 3] = position
    return float(stamp), X_WC


def read_session(directory: Path) -> RgbdSession:
    """Read a session folder's intrinsics, poses, settings and keypoints (images load per
    frame). Raises SessionError naming the file and what was expected."""
    directory = Path(directory)
    if not (directory / CAMERA_INFO).is_file():
        raise SessionError(f"{directory}: expected a recorded session ({CAMERA_INFO} not found)")
    camera = read_camera_info(_inside(directory, directory / CAMERA_INFO))
    pose_files = [_inside(directory, path) for path in sorted((directory / "pose").glob("*.yaml"))]
    indices = tuple(int(path.stem) for path in pose_files if path.stem.isdigit())
    if not indices:
        raise SessionError(f"{directory / 'pose'}: expected one NNNNNNNNNNNN.yaml per frame")
    indices, pose_files, skipped = _whole_frames(directory, indices, pose_files)
    stamps, poses = zip(*(_read_pose(path) for path in pose_files), strict=True)
    if np.any(np.diff(stamps) <= 0):
        raise SessionError(f"{directory / 'pose'}: stamp: expected times rising frame by frame")
    keypoint_files = [directory / "openpose" / f"{_name(i)}_keypoints.json" for i in indices]
    missing = [path for path in keypoint_files if not path.is_file()]
    if missing:
        raise SessionError(f"{missing[0]}: expected the frame's OpenPose keypoints")
    for path in keypoint_files:
        _inside(directory, path)
    recording = read_openpose_recording(keypoint_files, image_size=(camera.width, camera.height))
    settings = _read_settings(directory / SESSION) if (directory / SESSION).is_file() else {}
    return RgbdSession(directory, camera, indices, tuple(stamps), tuple(poses),
                       tuple(recording.detections), settings, skipped)  # fmt: skip


def _whole_frames(directory: Path, indices: tuple[int, ...], pose_files: list[Path]):
    """The frames whose colour and depth images are there and whole PNGs (signature and end
    read, not decoded), their pose files, and each frame left out with why."""
    kept, files, skipped = [], [], []
    for index, pose in zip(indices, pose_files, strict=True):
        images = [directory / kind / f"{_name(index)}.png" for kind in ("color", "depth")]
        problem = next(filter(None, (_png_problem(_inside(directory, p)) for p in images)), "")
        if problem:
            skipped.append(f"frame {index}: {problem}")
        else:
            kept.append(index)
            files.append(pose)
    if not kept:
        raise SessionError(f"{directory}: expected a frame with whole images; {skipped[0]}")
    return tuple(kept), files, tuple(skipped)


def _png_problem(path: Path) -> str:
    """Why `path` is no whole PNG image ("" when it is one), from its first and last bytes."""
    if not path.is_file():
        return f"{path.name} in {path.parent.name}/ is missing"
    with path.open("rb") as stream:
        head = stream.read(len(PNG_SIGNATURE))
        stream.seek(max(0, path.stat().st_size - len(PNG_END)))
        tail = stream.read()
    if head != PNG_SIGNATURE:
        return f"{path.parent.name}/{path.name} is not a PNG image"
    if tail != PNG_END:
        return f"{path.parent.name}/{path.name} is cut short"
    return ""


def _read_settings(path: Path) -> dict:
    """session.yaml, holding only what SESSION_SECTIONS allows (SessionError naming the key)."""
    settings = _load_yaml(_inside(path.parent, path))
    check_settings(settings, str(path))
    return settings


def check_settings(settings: dict, where: str) -> None:
    """Raise SessionError "<where>: <key>: expected ..." unless `settings` holds only the robot's
    own settings (SESSION_SECTIONS, without PERCEPTION_NOT_IN_SESSION)."""
    for section, values in settings.items():
        if section not in SESSION_SECTIONS:
            allowed = ", ".join(SESSION_SECTIONS)
            raise SessionError(
                f"{where}: {section}: expected only the robot's settings ({allowed})"
            )
        keys = SESSION_SECTIONS[section]
        if not isinstance(values, dict):
            raise SessionError(f"{where}: {section}: expected a mapping")
        refused = [key for key in values if (keys is not None and key not in keys)
                   or (section == "perception" and key in PERCEPTION_NOT_IN_SESSION)]  # fmt: skip
        if refused:
            why = "it is the world's, or names a file outside the session"
            raise SessionError(f"{where}: {section}.{refused[0]}: expected none here ({why})")

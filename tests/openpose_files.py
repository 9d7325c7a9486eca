"""Small OpenPose output files written by the tests themselves, in each of OpenPose's formats:
a drawn person facing the camera as a COCO-18, BODY_25 or BODY_25B keypoint table, and frames
holding such people as OpenPose lays them out (face, hands and 3-D fields filled in)."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from hsr_handover.interface.coco18 import COCO18_KEYPOINTS

# A person facing the camera, in shoulder widths from the neck (u right, v down in the image);
# their right side on the image's left. The neck lies midway between the shoulders, as in
# OpenPose's training data.
_SHAPE = {
    "nose": (0.0, -0.55), "neck": (0.0, 0.0), "r_shoulder": (-0.5, 0.0),
    "r_elbow": (-0.6, 0.7), "r_wrist": (-0.65, 1.3), "l_shoulder": (0.5, 0.0),
    "l_elbow": (0.6, 0.7), "l_wrist": (0.65, 1.3), "r_hip": (-0.25, 1.5), "r_knee": (-0.25, 2.5),
    "r_ankle": (-0.25, 3.4), "l_hip": (0.25, 1.5), "l_knee": (0.25, 2.5), "l_ankle": (0.25, 3.4),
    "r_eye": (-0.1, -0.65), "l_eye": (0.1, -0.65), "r_ear": (-0.2, -0.6), "l_ear": (0.2, -0.6),
    "mid_hip": (0.0, 1.5), "upper_neck": (0.0, -0.2), "head_top": (0.0, -0.95),
    "l_big_toe": (0.35, 3.55), "l_small_toe": (0.4, 3.5), "l_heel": (0.2, 3.45),
    "r_big_toe": (-0.35, 3.55), "r_small_toe": (-0.4, 3.5), "r_heel": (-0.2, 3.45),
}  # fmt: skip
BODY25_ORDER = (
    "nose", "neck", "r_shoulder", "r_elbow", "r_wrist", "l_shoulder", "l_elbow", "l_wrist",
    "mid_hip", "r_hip", "r_knee", "r_ankle", "l_hip", "l_knee", "l_ankle", "r_eye", "l_eye",
    "r_ear", "l_ear", "l_big_toe", "l_small_toe", "l_heel", "r_big_toe", "r_small_toe", "r_heel",
)  # fmt: skip
BODY25B_ORDER = (
    "nose", "l_eye", "r_eye", "l_ear", "r_ear", "l_shoulder", "r_shoulder", "l_elbow", "r_elbow",
    "l_wrist", "r_wrist", "l_hip", "r_hip", "l_knee", "r_knee", "l_ankle", "r_ankle",
    "upper_neck", "head_top", "l_big_toe", "l_small_toe", "l_heel", "r_big_toe", "r_small_toe",
    "r_heel",
)  # fmt: skip
MPI_ORDER = (
    "head_top", "neck", "r_shoulder", "r_elbow", "r_wrist", "l_shoulder", "l_elbow", "l_wrist",
    "r_hip", "r_knee", "r_ankle", "l_hip", "l_knee", "l_ankle", "mid_hip",
)  # fmt: skip


def person_table(
    order: Sequence[str] = COCO18_KEYPOINTS,
    neck_px: tuple[float, float] = (320.0, 150.0),
    shoulder_px: float = 80.0,
    confidence: float = 0.8,
    missing: Sequence[str] = (),
    facing_away: bool = False,
) -> np.ndarray:
    """The drawn person's (K, 3) table of x, y, confidence in the keypoint `order`, with
    (0, 0, 0) for the `missing` keypoints. Facing away, their right side is on the image's
    right."""
    table = np.zeros((len(order), 3))
    mirror = -1.0 if facing_away else 1.0
    for row, name in enumerate(order):
        if name not in missing:
            du, dv = _SHAPE[name]
            table[row] = [neck_px[0] + mirror * du * shoulder_px, neck_px[1] + dv * shoulder_px,
                          confidence]  # fmt: skip
    return table


def person_dict(table: np.ndarray, key: str = "pose_keypoints_2d", extras: bool = True) -> dict:
    """One person as OpenPose writes them, with face (70), hands (21 each) and 3-D fields filled
    in (OpenPose's --face --hand --3d) when `extras`."""
    person = {"person_id": [-1], key: [float(value) for value in table.ravel()]}
    if extras:
        rng = np.random.default_rng(0)
        person["face_keypoints_2d"] = rng.uniform(0, 400, 70 * 3).tolist()
        person["hand_left_keypoints_2d"] = rng.uniform(0, 400, 21 * 3).tolist()
        person["hand_right_keypoints_2d"] = rng.uniform(0, 400, 21 * 3).tolist()
        person["pose_keypoints_3d"] = rng.uniform(-1, 1, len(table) * 4).tolist()
        person["face_keypoints_3d"] = []
    return person


def write_frame(
    path: Path,
    tables: Sequence[np.ndarray],
    key: str = "pose_keypoints_2d",
    version: float = 1.3,
    extras: bool = True,
) -> Path:
    """A frame file holding people with these keypoint tables."""
    frame = {"version": version, "people": [person_dict(t, key, extras) for t in tables]}
    path.write_text(json.dumps(frame))
    return path


def openpose_name(index: int, video: str = "video") -> str:
    """The name OpenPose gives frame `index` of a video: <name>_<12 digits>_keypoints.json."""
    return f"{video}_{index:012d}_keypoints.json"

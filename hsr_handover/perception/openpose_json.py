"""OpenPose's JSON output (`--write_json`), so recorded detections replay through the same
pipeline as simulated ones (paper 3.2 uses OpenPose's COCO-18 body keypoints).

OpenPose writes one file per image frame: {"version": 1.3, "people": [{"person_id": [-1],
"pose_keypoints_2d": [x0, y0, c0, x1, y1, c1, ...], ...}]}, with 18 keypoints for the COCO
model and (0, 0, 0) for a keypoint it did not find. Here a missing keypoint has NaN pixels
and confidence 0 in memory, and is (0, 0, 0) on disk.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Sequence
from pathlib import Path
from typing import IO, Protocol

import numpy as np

from hsr_handover.perception.coco18 import NUM_KEYPOINTS
from hsr_handover.perception.skeleton import Detection

OPENPOSE_VERSION = 1.3
_VALUES_PER_PERSON = 3 * NUM_KEYPOINTS
# OpenPose writes these for every person; only the body keypoints are filled in here.
_UNUSED_FIELDS = (
    "face_keypoints_2d", "hand_left_keypoints_2d", "hand_right_keypoints_2d",
    "pose_keypoints_3d", "face_keypoints_3d", "hand_left_keypoints_3d", "hand_right_keypoints_3d",
)  # fmt: skip
NO_PERSON = "no person in the frame"


class Keypoints2D(Protocol):
    """Anything with COCO-18 `pixels` (18, 2) and `confidence` (18,): a Detection or Skeleton."""

    pixels: np.ndarray
    confidence: np.ndarray


def _person_dict(person: Keypoints2D) -> dict:
    values = []
    for (u, v), confidence in zip(person.pixels, person.confidence, strict=True):
        values += [float(u), float(v), float(confidence)] if confidence > 0 else [0.0, 0.0, 0.0]
    return {"person_id": [-1], "pose_keypoints_2d": values, **{key: [] for key in _UNUSED_FIELDS}}


def to_openpose_dict(people: Sequence[Keypoints2D]) -> dict:
    """One OpenPose frame holding each person's COCO-18 keypoints."""
    return {"version": OPENPOSE_VERSION, "people": [_person_dict(p) for p in people]}


def write_openpose_json(
    destination: str | os.PathLike | IO[str], people: Sequence[Keypoints2D]
) -> None:
    """Write one frame's people as OpenPose JSON to a path or a text stream."""
    frame = to_openpose_dict(people)
    if hasattr(destination, "write"):
        json.dump(frame, destination)
    else:
        Path(destination).write_text(json.dumps(frame))


def _is_number(value) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)


def _person_detection(person, key: str, fail) -> Detection:
    values = person.get("pose_keypoints_2d") if isinstance(person, dict) else None
    if not isinstance(values, list):
        fail(f"{key}.pose_keypoints_2d", "expected a list of numbers")
    if len(values) != _VALUES_PER_PERSON:
        fail(
            f"{key}.pose_keypoints_2d",
            f"expected {_VALUES_PER_PERSON} numbers ({NUM_KEYPOINTS} keypoints x 3), "
            f"got {len(values)}",
        )
    if not all(_is_number(value) for value in values):
        fail(f"{key}.pose_keypoints_2d", "expected finite numbers only")
    table = np.array(values, dtype=float).reshape(NUM_KEYPOINTS, 3)
    confidence = table[:, 2]
    if not np.all((confidence >= 0) & (confidence <= 1)):
        fail(f"{key}.pose_keypoints_2d", "expected every third number (confidence) in [0, 1]")
    pixels = np.where(confidence[:, None] > 0, table[:, :2], np.nan)
    return Detection(pixels, confidence)


def _source_name(source) -> str:
    return str(getattr(source, "name", "<stream>")) if hasattr(source, "read") else str(source)


def read_openpose_json(source: str | os.PathLike | IO[str]) -> list[Detection]:
    """The people of one OpenPose JSON frame (a path or a text stream), COCO-18 body model.

    Raises ValueError naming the file and the field when the file is not such a frame.
    """
    name = _source_name(source)

    def fail(key: str, expected: str):
        raise ValueError(f"{name}: {key}: {expected}")

    try:
        text = source.read() if hasattr(source, "read") else Path(source).read_text()
        frame = json.loads(text)
    except (json.JSONDecodeError, UnicodeDecodeError) as error:
        raise ValueError(f"{name}: expected OpenPose JSON, could not parse it: {error}") from None
    people = frame.get("people") if isinstance(frame, dict) else None
    if not isinstance(people, list):
        fail("people", "expected a list of people")
    return [_person_detection(person, f"people[{i}]", fail) for i, person in enumerate(people)]


def read_openpose_frames(sources: Sequence[str | os.PathLike]) -> list[Detection]:
    """The first person of each of a sequence of OpenPose frames (one file per image, as
    OpenPose writes them); a frame without people gives an empty detection."""
    frames = []
    for source in sources:
        people = read_openpose_json(source)
        frames.append(people[0] if people else Detection.missing(NO_PERSON))
    return frames

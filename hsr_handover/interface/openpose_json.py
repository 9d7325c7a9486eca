"""OpenPose's JSON output (`--write_json`), read and written, so recorded detections replay
through the same pipeline as simulated ones (paper 3.2 uses OpenPose's body keypoints).

OpenPose writes one file per image frame: {"version": 1.3, "people": [{"person_id": [-1],
"pose_keypoints_2d": [x0, y0, c0, x1, y1, c1, ...], ...}]}, with (0, 0, 0) for a keypoint it did
not find. Here a missing keypoint has NaN pixels and confidence 0 in memory, and is (0, 0, 0) on
disk; everything read is COCO-18 in pixels (`openpose_format` says which files are read and how).

- `write_openpose_json`: one frame's people, COCO-18, as OpenPose writes them.
- `read_openpose_json`: every person of one file (or text stream); any problem is an error.
- `read_openpose_recording`: a file, a folder of per-frame files (in OpenPose's frame order) or
  a list of files, with the person of interest followed through it (`person_tracking`); a
  frame that cannot be read is skipped, counted and says why, and the recording goes on.
- `read_openpose_frames`: the tracked person of each of a list of files.

Errors are ValueErrors "<file>: <key>: expected ...".
"""

from __future__ import annotations

import dataclasses
import json
import logging
import os
import re
from collections.abc import Sequence
from pathlib import Path
from typing import IO, Protocol

import numpy as np

from hsr_handover.interface.keypoints import Detection
from hsr_handover.interface.openpose_format import (
    DEFAULT_KEYPOINT_SCALE,
    DEFAULT_MODEL,
    NOT_JSON,
    NOT_OPENPOSE,
    OTHER_MODEL,
    PIXELS,
    UNREADABLE,
    OpenPoseFormatError,
    RawFrame,
    check_choices,
    check_not_normalised,
    decide_model,
    frame_in_pixels,
    parse_frame,
    to_detection,
)
from hsr_handover.interface.person_tracking import NO_PERSON, PersonTracker

LOG = logging.getLogger(__name__)  # a file read in doubt: one line, the reading goes on

__all__ = [
    "NO_PERSON", "OPENPOSE_VERSION", "SKIPPED", "Keypoints2D", "OpenPoseRecording", "SkippedFrame",
    "natural_sort_key", "openpose_frame_files", "read_openpose_frames", "read_openpose_json",
    "read_openpose_recording", "to_openpose_dict", "write_openpose_json",
]  # fmt: skip

OPENPOSE_VERSION = 1.3
# OpenPose writes these for every person; only the body keypoints are filled in here.
_UNUSED_FIELDS = (
    "face_keypoints_2d", "hand_left_keypoints_2d", "hand_right_keypoints_2d",
    "pose_keypoints_3d", "face_keypoints_3d", "hand_left_keypoints_3d", "hand_right_keypoints_3d",
)  # fmt: skip
SKIPPED = "frame skipped"
"""The status of a frame that could not be read: "frame skipped: <why>"."""


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


def _source_name(source) -> str:
    return str(getattr(source, "name", "<stream>")) if hasattr(source, "read") else str(source)


def _read_frame(source, keypoint_scale: str) -> RawFrame:
    """Parse one frame from a path or a text stream (OpenPoseFormatError when it cannot be)."""
    name = _source_name(source)
    try:
        text = source.read() if hasattr(source, "read") else Path(source).read_text()
    except UnicodeDecodeError as error:
        raise OpenPoseFormatError(
            name, "", f"expected UTF-8 JSON text: {error}", NOT_JSON
        ) from None
    except OSError as error:
        raise OpenPoseFormatError(
            name, "", f"expected a readable file: {error}", UNREADABLE
        ) from None
    return parse_frame(text, name, keypoint_scale)


def _detections(frame: RawFrame, model: str) -> tuple[Detection, ...]:
    return tuple(to_detection(table, model) for table in frame.people)


def read_openpose_json(
    source: str | os.PathLike | IO[str],
    *,
    model: str = DEFAULT_MODEL,
    keypoint_scale: str = DEFAULT_KEYPOINT_SCALE,
    image_size: tuple[int, int] | None = None,
) -> list[Detection]:
    """Every person of one OpenPose JSON frame (a path or a text stream), as COCO-18 pixels.

    `model`: "auto" (told by the file: COCO-18 or BODY_25), "COCO" or "BODY_25" (OpenPose's
    --model_pose names). `keypoint_scale`: "pixels" (OpenPose's default), "unit" ([0, 1],
    --keypoint_scale 3) or "signed_unit" ([-1, 1], 4), converted with `image_size` (width,
    height in pixels). Raises ValueError naming the file and the key when the file is not such
    a frame, holds another model, or looks normalised while read as pixels.
    """
    check_choices(model, keypoint_scale, image_size)
    frame = _read_frame(source, keypoint_scale)
    if keypoint_scale == PIXELS:
        check_not_normalised([frame], frame.source)
    frame = frame_in_pixels(frame, keypoint_scale, image_size)
    decision = decide_model([frame], model)
    if decision.note:
        LOG.warning(decision.note)
    return list(_detections(frame, decision.model))


@dataclasses.dataclass(frozen=True)
class SkippedFrame:
    """A frame that could not be read: its file, why in a word (`kind`, for counting) and the
    whole one-line `reason`."""

    file: str
    kind: str
    reason: str


@dataclasses.dataclass(frozen=True)
class OpenPoseRecording:
    """A sequence of OpenPose frames, read.

    `source`: the file or folder given (or the first file of a list). `model`: the files'
    model ("COCO" or "BODY_25"; "unknown" when nobody is seen and none was declared).
    `files`: each frame's file, in order. `people`: each frame's people as COCO-18 pixel
    detections (none for a skipped frame). `detections`: the person of interest in each frame,
    or an empty detection whose status says why not (NO_PERSON, the tracker's "tracked person
    not in the frame", or "frame skipped: <kind>"). `skipped`: the frames that could not be
    read, in frame order. `model_note`: why the model read is in doubt, if it is.
    """

    source: str
    model: str
    keypoint_scale: str
    files: tuple[str, ...]
    people: tuple[tuple[Detection, ...], ...]
    detections: tuple[Detection, ...]
    skipped: tuple[SkippedFrame, ...]
    model_note: str = ""


def natural_sort_key(name: str) -> tuple:
    """Sort key that orders the digit runs of a name by value: img2 before img10."""
    parts = re.split(r"(\d+)", name)
    # re.split with a group alternates text and digits, so like compares with like.
    return tuple(int(part) if index % 2 else part.lower() for index, part in enumerate(parts))


def openpose_frame_files(folder: str | os.PathLike) -> list[Path]:
    """A folder's per-frame OpenPose files in frame order: `*_keypoints.json` (OpenPose's
    `<name>_<12-digit frame>_keypoints.json`, or `<image name>_keypoints.json` for a folder of
    images), else every `*.json`; natural order by name, hidden files left out."""
    files = [
        path
        for path in Path(folder).iterdir()
        if path.is_file() and path.suffix.lower() == ".json" and not path.name.startswith(".")
    ]
    keypoint_files = [path for path in files if path.name.lower().endswith("_keypoints.json")]
    return sorted(keypoint_files or files, key=lambda path: natural_sort_key(path.name))


def _frame_sources(
    source: str | os.PathLike | Sequence[str | os.PathLike],
) -> tuple[list[Path], str, bool]:
    """The files of a recording, what to call it in messages, and whether it is one file
    given on its own (then any problem is an error rather than a skipped frame)."""
    if isinstance(source, str | os.PathLike):
        path = Path(source)
        if path.is_dir():
            files = openpose_frame_files(path)
            if not files:
                expected = "expected OpenPose JSON frames (*_keypoints.json or *.json), found none"
                raise OpenPoseFormatError(str(path), "", expected, NOT_OPENPOSE)
            return files, str(path), False
        if not path.is_file():
            expected = "expected an OpenPose JSON file or a folder of them, found neither"
            raise OpenPoseFormatError(str(path), "", expected, UNREADABLE)
        return [path], str(path), True
    files = [Path(item) for item in source]
    if not files:
        raise ValueError("frames: expected at least one OpenPose JSON file, got none")
    return files, str(files[0]), False


def _read_frames(
    files: Sequence[Path], keypoint_scale: str, single: bool
) -> tuple[list[RawFrame | None], list[SkippedFrame]]:
    """Each file's frame, or None where it is skipped (a lone file raises instead)."""
    frames, skipped = [], []
    for path in files:
        try:
            frames.append(_read_frame(path, keypoint_scale))
        except OpenPoseFormatError as error:
            if single:
                raise
            frames.append(None)
            skipped.append(SkippedFrame(str(path), error.kind, str(error)))
    return frames, skipped


def _skip_other_counts(frames: list[RawFrame | None], skipped: list[SkippedFrame]) -> None:
    """Skip the frames whose people have another keypoint count than the first frame with
    people: one recording holds one model."""
    first = next((frame for frame in frames if frame is not None and frame.people), None)
    for index, frame in enumerate(frames):
        if frame is None or first is None or frame.keypoint_count in (None, first.keypoint_count):
            continue
        reason = (
            f"{frame.source}: people[0].{frame.key}: expected {first.keypoint_count} keypoints "
            f"like {Path(first.source).name}, got {frame.keypoint_count}"
        )
        frames[index] = None
        skipped.append(SkippedFrame(frame.source, OTHER_MODEL, reason))


def read_openpose_recording(
    source: str | os.PathLike | Sequence[str | os.PathLike],
    *,
    model: str = DEFAULT_MODEL,
    keypoint_scale: str = DEFAULT_KEYPOINT_SCALE,
    image_size: tuple[int, int] | None = None,
    near_px: tuple[float, float] | None = None,
) -> OpenPoseRecording:
    """Read a recording: one OpenPose JSON file, a folder of per-frame files (natural order by
    name, `openpose_frame_files`) or a list of files (in the order given), and follow the
    person of interest through it (`person_tracking.PersonTracker`, nearest `near_px` if
    given). `model`, `keypoint_scale` and `image_size` as for `read_openpose_json`, decided for
    the whole recording.

    In a folder or a list, a frame that cannot be read (empty, not JSON, not OpenPose, malformed
    keypoints, another keypoint count) is skipped and listed with its reason; a lone file that
    cannot be read is an error. Raises ValueError naming the file or folder when there is
    nothing to read, every frame is broken, or the recording holds a model not read here or
    normalised coordinates read as pixels.
    """
    check_choices(model, keypoint_scale, image_size)
    files, where, single = _frame_sources(source)
    frames, skipped = _read_frames(files, keypoint_scale, single)
    if all(frame is None for frame in frames):
        expected = (
            f"expected OpenPose JSON frames, none of the {len(files)} could be read (first: "
            f"{skipped[0].reason})"
        )
        raise OpenPoseFormatError(where, "", expected, skipped[0].kind)
    _skip_other_counts(frames, skipped)
    good = [frame for frame in frames if frame is not None]
    if keypoint_scale == PIXELS:
        check_not_normalised(good, where)
    pixel_frames = [
        None if frame is None else frame_in_pixels(frame, keypoint_scale, image_size)
        for frame in frames
    ]
    decision = decide_model([frame for frame in pixel_frames if frame is not None], model)
    if decision.note:
        LOG.warning(decision.note)
    model = decision.model
    people = tuple(() if frame is None else _detections(frame, model) for frame in pixel_frames)
    reasons = {item.file: item.kind for item in skipped}
    tracker = PersonTracker(near_px)
    detections = tuple(
        Detection.missing(f"{SKIPPED}: {reasons[str(path)]}")
        if frame is None
        else tracker.update(frame_people)
        for path, frame, frame_people in zip(files, frames, people, strict=True)
    )
    order = {str(path): index for index, path in enumerate(files)}
    skipped.sort(key=lambda item: order[item.file])  # in frame order, whatever skipped them
    names = tuple(str(path) for path in files)
    return OpenPoseRecording(
        where, model, keypoint_scale, names, people, detections, tuple(skipped), decision.note
    )


def read_openpose_frames(
    sources: Sequence[str | os.PathLike],
    *,
    model: str = DEFAULT_MODEL,
    keypoint_scale: str = DEFAULT_KEYPOINT_SCALE,
    image_size: tuple[int, int] | None = None,
    near_px: tuple[float, float] | None = None,
) -> list[Detection]:
    """The person of interest in each of a sequence of OpenPose frames (one file per image, as
    OpenPose writes them, in the order given), followed from frame to frame
    (`read_openpose_recording`); a frame without them gives an empty detection saying why."""
    recording = read_openpose_recording(
        list(sources), model=model, keypoint_scale=keypoint_scale, image_size=image_size,
        near_px=near_px,
    )  # fmt: skip
    return list(recording.detections)

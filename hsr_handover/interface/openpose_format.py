"""OpenPose's per-frame JSON as OpenPose writes it (numpy only): the body models, the keys of
its versions, its confidences and its coordinate scales, turned into COCO-18 pixels.

A frame (`--write_json`) is {"version": 1.3, "people": [{"person_id": [-1],
"pose_keypoints_2d": [x0, y0, c0, x1, y1, c1, ...], "face_keypoints_2d": [...], ...}]}; version
1.0 names the body keypoints `pose_keypoints`. A keypoint OpenPose did not find is (0, 0, 0).
Only the body keypoints are read: face, hand and 3-D fields are ignored whatever they hold.

- **Models** (`--model_pose`): COCO (18 keypoints, the project's order) and BODY_25 (OpenPose's
  default: COCO's keypoints plus MidHip at index 8 and six foot points, with the hips and the
  face moved) are read, BODY_25 remapped to COCO-18 by keypoint name. The model is told by the
  count of keypoints; BODY_25B, also 25 keypoints but in another order, is told from BODY_25 by
  the whole file's or sequence's geometry, and only on strong evidence (`decide_model`): a
  doubtful file is read as BODY_25, OpenPose's default, with a note. Other models are refused,
  named when known.
- **Confidences** are heat-map peaks and go slightly above 1 (1.006 is common): up to
  MAX_CONFIDENCE they are clamped to 1; above, or negative, the file is refused.
- **Scales** (`--keypoint_scale`): pixels (0, the default), [0, 1] (3) or [-1, 1] (4) of the
  image, converted to pixels with the image size. Reading as pixels a recording whose every
  keypoint lies within [-1, 1] is refused: no person is under 2 pixels wide.

Errors are `OpenPoseFormatError` (a ValueError): "<file>: <key>: expected ...".
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Sequence

import numpy as np

from hsr_handover.interface.coco18 import COCO18_KEYPOINTS
from hsr_handover.interface.keypoints import Detection

AUTO = "auto"
COCO = "COCO"
BODY_25 = "BODY_25"
MODEL_CHOICES = (AUTO, COCO, BODY_25)
"""What a caller may declare as the model (`--model_pose` names); "auto" tells it by the file."""
MODEL_KEYPOINTS = {COCO: 18, BODY_25: 25}
UNKNOWN = "unknown"
"""The model of a recording in which nobody is seen, when none is declared."""

PIXELS, UNIT, SIGNED_UNIT = "pixels", "unit", "signed_unit"
KEYPOINT_SCALES = (PIXELS, UNIT, SIGNED_UNIT)
"""Coordinate scales: pixels (OpenPose's --keypoint_scale 0), [0, 1] (3) and [-1, 1] (4)."""
_SCALE_RANGES = {UNIT: (0.0, 1.0), SIGNED_UNIT: (-1.0, 1.0)}
# A keypoint may sit a little outside the image after OpenPose's resizing; more than 2 % of the
# image outside means the scale declared is not the file's.
_SCALE_SLACK = 0.02

DEFAULT_MODEL = AUTO
DEFAULT_KEYPOINT_SCALE = PIXELS

# Heat-map peaks overshoot 1 by a few per cent at most (a real BODY_25 file has 1.006). 1.5 is
# far beyond any overshoot, and still catches a file whose numbers are not (x, y, confidence)
# triples, where a pixel coordinate of 2 or more would land in a confidence's place.
MAX_CONFIDENCE = 1.5

# OpenPose's BODY_25 order (doc/02_output.md, POSE_BODY_25_BODY_PARTS), in coco18's naming.
BODY25_KEYPOINTS = (
    "nose", "neck", "r_shoulder", "r_elbow", "r_wrist", "l_shoulder", "l_elbow", "l_wrist",
    "mid_hip", "r_hip", "r_knee", "r_ankle", "l_hip", "l_knee", "l_ankle", "r_eye", "l_eye",
    "r_ear", "l_ear", "l_big_toe", "l_small_toe", "l_heel", "r_big_toe", "r_small_toe", "r_heel",
)  # fmt: skip
BODY25_TO_COCO18 = np.array([BODY25_KEYPOINTS.index(name) for name in COCO18_KEYPOINTS])
"""Row k of a COCO-18 table is row BODY25_TO_COCO18[k] of a BODY_25 table (matched by name)."""

# Points BODY_25 places midway between two others (index, one end, other end): the neck between
# the shoulders and MidHip between the hips. OpenPose trained both on those midpoints (COCO has
# neither; its neck and mid-hip are made as midpoints), so what it detects sits close to them. In
# BODY_25B the same indices hold the eyes, a shoulder, an elbow, a wrist and a hip: the left eye
# is not midway between the right eye and the left shoulder, nor the right elbow between the
# left wrist and the right hip.
BODY25_MIDPOINTS = ((1, 2, 5), (8, 9, 12))
# A detected midpoint lies within a quarter of its segment's length of the true midpoint: the
# detector's few pixels of noise on segments tens of pixels long. A person seen side on, or half
# out of the image, can read far off, so the midpoints alone only ever make a file doubtful.
MIDPOINT_TOLERANCE = 0.25
# The decisive test: index 15 is BODY_25's right eye, a few cm from the nose (index 0), and
# BODY_25B's left ankle, a body's height from it; index 1 is BODY_25's neck, a head's height
# below the nose, and BODY_25B's left eye beside it. So |0-15| / |0-1| is about 0.2 in BODY_25
# and tens in BODY_25B, whatever way the person turns; a table over HEAD_SPAN_RATIO is BODY_25B's.
HEAD_SPAN_RATIO = 2.0
STRONG_EVIDENCE = 2  # people (over the file or the sequence) whose nose-eye-neck says BODY_25B

UNSUPPORTED_MODELS = {
    15: "MPI", 19: "BODY_19", 23: "BODY_23", 59: "BODY_59", 65: "BODY_65", 135: "BODY_135",
}  # fmt: skip
"""OpenPose's other body models by their keypoint count (poseParameters.cpp)."""
_UNSUPPORTED_NAMES = {*UNSUPPORTED_MODELS.values(), "MPI_4_layers", "BODY_25B"}

KEYS = ("pose_keypoints_2d", "pose_keypoints")
"""The body keypoints' key: since OpenPose 1.2, and in version 1.0 files."""

# Why a frame could not be read, as counted in a recording's summary.
UNREADABLE = "unreadable file"
EMPTY_FILE = "empty file"
NOT_JSON = "unparseable JSON"
NOT_OPENPOSE = "not OpenPose output"
BAD_KEYPOINTS = "malformed keypoints"
OTHER_MODEL = "keypoint count differs from the recording's"


class OpenPoseFormatError(ValueError):
    """A file that is not the OpenPose output expected: "<file>: <key>: expected ..."; `kind`
    says why in a word, for counting skipped frames."""

    def __init__(self, source: str, key: str, expected: str, kind: str = BAD_KEYPOINTS):
        super().__init__(f"{source}: {key}: {expected}" if key else f"{source}: {expected}")
        self.source, self.key, self.expected, self.kind = source, key, expected, kind


@dataclasses.dataclass(frozen=True)
class RawFrame:
    """One frame's people as the file gives them: `people` holds a (K, 3) table of x, y and
    confidence (clamped to [0, 1]) per person, in the file's model and scale; `key` is the
    keypoints' key the file uses."""

    source: str
    key: str
    people: tuple[np.ndarray, ...]

    @property
    def keypoint_count(self) -> int | None:
        """Keypoints per person (the model's count), None for a frame without people."""
        return len(self.people[0]) if self.people else None


def check_choices(model: str, keypoint_scale: str, image_size) -> None:
    """Raise ValueError naming the argument when the model, the scale or the image size a
    caller declares is not one this reader takes."""
    if model not in MODEL_CHOICES:
        note = f": OpenPose's {model} model is not supported" if model in _UNSUPPORTED_NAMES else ""
        raise ValueError(f"model: expected one of {', '.join(MODEL_CHOICES)}, got {model!r}{note}")
    if keypoint_scale not in KEYPOINT_SCALES:
        raise ValueError(
            f"keypoint_scale: expected one of {', '.join(KEYPOINT_SCALES)}, got {keypoint_scale!r}"
        )
    if keypoint_scale != PIXELS:
        size = np.asarray(image_size if image_size is not None else [], dtype=float)
        if size.shape != (2,) or not np.all(size >= 2) or not np.isfinite(size).all():
            raise ValueError(
                f"image_size: expected (width, height) in pixels, at least 2 each, to convert "
                f"keypoint_scale {keypoint_scale!r} to pixels, got {image_size!r}"
            )


def _is_number(value) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)


def parse_frame(text: str, source: str, keypoint_scale: str = PIXELS) -> RawFrame:
    """One OpenPose JSON frame's people (see RawFrame); raises OpenPoseFormatError."""
    if not text.strip():
        raise OpenPoseFormatError(
            source, "", "expected OpenPose JSON, the file is empty", EMPTY_FILE
        )
    try:
        frame = json.loads(text)
    except RecursionError:
        expected = "expected OpenPose JSON, got arrays or objects nested too deeply to read"
        raise OpenPoseFormatError(source, "", expected, NOT_JSON) from None
    except ValueError as error:  # malformed, or a number too long for Python to convert
        reason = str(error).split(";")[0]  # without Python's advice to its programmers
        expected = f"expected OpenPose JSON, could not parse it: {reason}"
        raise OpenPoseFormatError(source, "", expected, NOT_JSON) from None
    people = frame.get("people") if isinstance(frame, dict) else None
    if not isinstance(people, list):
        expected = "expected a list of people (OpenPose's --write_json output)"
        raise OpenPoseFormatError(source, "people", expected, NOT_OPENPOSE)
    tables, key = [], KEYS[0]
    for index, person in enumerate(people):
        key, table = _person_table(person, f"people[{index}]", source, keypoint_scale)
        if tables and len(table) != len(tables[0]):
            expected = f"expected {len(tables[0])} keypoints like people[0], got {len(table)}"
            raise OpenPoseFormatError(source, f"people[{index}].{key}", expected)
        tables.append(table)
    return RawFrame(source, key, tuple(tables))


def _person_table(
    person, person_key: str, source: str, keypoint_scale: str
) -> tuple[str, np.ndarray]:
    """The keypoints' key and (K, 3) table of one person, checked and confidences clamped."""
    key = next((k for k in KEYS if isinstance(person, dict) and k in person), KEYS[0])
    values = person.get(key) if isinstance(person, dict) else None
    where = f"{person_key}.{key}"

    def fail(expected: str):
        raise OpenPoseFormatError(source, where, expected)

    if not isinstance(values, list):
        fail("expected a list of numbers (pose_keypoints in version 1.0 files)")
    if not values:
        fail("expected 54 numbers (18 keypoints x 3) or BODY_25's 75, got none")
    if len(values) % 3:
        fail(
            f"expected 54 numbers (18 keypoints x 3), got {len(values)}: not whole x, y, "
            "confidence triples (BODY_25 files have 75)"
        )
    if not all(_is_number(value) for value in values):
        fail("expected finite numbers only")
    table = np.array(values, dtype=float).reshape(-1, 3)
    confidence = table[:, 2]
    if not np.all((confidence >= 0) & (confidence <= MAX_CONFIDENCE)):
        index = int(np.argmax((confidence < 0) | (confidence > MAX_CONFIDENCE)))
        fail(
            f"expected every third number (confidence) in [0, {MAX_CONFIDENCE:g}], got "
            f"{confidence[index]:g} at keypoint {index}"
        )
    table[:, 2] = np.minimum(confidence, 1.0)  # heat-map peaks overshoot 1 a little
    _check_scale_range(table, keypoint_scale, fail)
    return key, table


def _check_scale_range(table: np.ndarray, keypoint_scale: str, fail) -> None:
    """Found keypoints of a declared normalised scale lie within its range."""
    if keypoint_scale == PIXELS:
        return
    low, high = _SCALE_RANGES[keypoint_scale]
    slack = _SCALE_SLACK * (high - low)
    found = table[table[:, 2] > 0, :2]
    outside = (found < low - slack) | (found > high + slack)
    if outside.any():
        value = found[outside][0]
        fail(
            f"expected coordinates in [{low:g}, {high:g}] for keypoint_scale {keypoint_scale!r}, "
            f"got {value:g}"
        )


def check_not_normalised(frames: Sequence[RawFrame], where: str) -> None:
    """Raise OpenPoseFormatError when frames read as pixels hold keypoints, every one of them
    within [-1, 1]: OpenPose's normalised output, which the caller must declare."""
    found = [table[table[:, 2] > 0, :2] for frame in frames for table in frame.people]
    found = np.concatenate(found) if found else np.empty((0, 2))
    if len(found) and np.all(np.abs(found) <= 1.0):
        key = next((frame.key for frame in frames if frame.people), KEYS[0])
        raise OpenPoseFormatError(
            where,
            key,
            "expected pixel coordinates, but every keypoint lies within [-1, 1]: normalised "
            "output (OpenPose's --keypoint_scale 3 or 4); declare keypoint_scale unit ([0, 1]) "
            "or signed_unit ([-1, 1]) and the image size",
        )


def to_pixels(table: np.ndarray, keypoint_scale: str, image_size) -> np.ndarray:
    """A (K, 3) table with its coordinates in pixels, as OpenPose scales them back: [0, 1]
    spans pixel 0 to width - 1 (keypointScaler.cpp), [-1, 1] the same from -1."""
    if keypoint_scale == PIXELS:
        return table
    span = np.asarray(image_size, dtype=float) - 1.0
    low, high = _SCALE_RANGES[keypoint_scale]
    pixels = table.copy()
    pixels[:, :2] = (table[:, :2] - low) / (high - low) * span
    return pixels


def unsupported_model(count: int) -> str:
    """What OpenPose model gives `count` keypoints, for a message."""
    name = UNSUPPORTED_MODELS.get(count)
    return f"OpenPose's {name} model" if name else "no OpenPose model this reader knows"


def midpoint_offsets(table: np.ndarray) -> list[float]:
    """For each of BODY25_MIDPOINTS whose three keypoints are all found in this 25-keypoint
    table: the middle point's distance from the midpoint of the two ends, over the ends'
    distance."""
    offsets = []
    for middle, end_a, end_b in BODY25_MIDPOINTS:
        if not np.all(table[[middle, end_a, end_b], 2] > 0):
            continue
        a, b = table[end_a, :2], table[end_b, :2]
        length = float(np.linalg.norm(a - b))
        if length > 0:
            offsets.append(float(np.linalg.norm(table[middle, :2] - (a + b) / 2)) / length)
    return offsets


def head_span_ratio(table: np.ndarray) -> float | None:
    """|keypoint 0 - keypoint 15| / |keypoint 0 - keypoint 1| of a 25-keypoint table (see
    HEAD_SPAN_RATIO); None unless all three were found."""
    if not np.all(table[[0, 1, 15], 2] > 0):
        return None
    reach = float(np.linalg.norm(table[1, :2] - table[0, :2]))
    return float(np.linalg.norm(table[15, :2] - table[0, :2])) / reach if reach > 0 else None


@dataclasses.dataclass(frozen=True)
class ModelDecision:
    """The model frames are read as, and a one-line note when the file only looks doubtful
    (read as BODY_25, OpenPose's default, all the same)."""

    model: str
    note: str = ""


def _body25_or_b(tables: Sequence[np.ndarray], source: str, where: str) -> ModelDecision:
    """BODY_25 unless at least STRONG_EVIDENCE people, and most of those measured, have a
    head span only BODY_25B gives. Fewer such people, or (with no head span measured) necks and
    mid-hips off midway, make a note, not a refusal."""
    ratios = [r for r in map(head_span_ratio, tables) if r is not None]
    wide = sum(r > HEAD_SPAN_RATIO for r in ratios)
    far = f"in {wide} of {len(ratios)} people keypoint 15 lies far from the nose (BODY_25's eye, "
    if wide >= STRONG_EVIDENCE and wide > len(ratios) / 2:
        raise OpenPoseFormatError(
            source, where,
            f"expected COCO or BODY_25, got BODY_25B: {far}BODY_25B's ankle); not supported "
            "(declare model BODY_25 if it is BODY_25)",
        )  # fmt: skip
    offsets = [offset for table in tables for offset in midpoint_offsets(table)]
    doubt = ""
    if wide:
        doubt = f"{far}BODY_25B's ankle)"
    elif not ratios and offsets and float(np.median(offsets)) > MIDPOINT_TOLERANCE:
        median = float(np.median(offsets))
        doubt = f"its necks and mid-hips lie off midway (median {median:.2f} of a segment)"
    if not doubt:
        return ModelDecision(BODY_25)
    return ModelDecision(BODY_25, f"{source}: read as BODY_25 (OpenPose's default), though "
                                  f"{doubt}; declare the model if it is another")  # fmt: skip


def decide_model(frames: Sequence[RawFrame], declared: str) -> ModelDecision:
    """The model of frames (in pixels) whose people all have the same keypoint count: the
    declared one (checked against the count), or told by the count and, for 25, by the whole
    file's or sequence's geometry (`_body25_or_b`). Raises OpenPoseFormatError naming the first
    file with people and the model it holds. With no person in any frame, the declared model,
    or UNKNOWN (there is nothing to remap)."""
    first = next((frame for frame in frames if frame.people), None)
    if first is None:
        return ModelDecision(UNKNOWN if declared == AUTO else declared)
    count, where = first.keypoint_count, f"people[0].{first.key}"
    if declared != AUTO:
        if count != MODEL_KEYPOINTS[declared]:
            expected = f"expected {MODEL_KEYPOINTS[declared]} keypoints for model {declared}"
            raise OpenPoseFormatError(first.source, where, f"{expected}, got {count}")
        return ModelDecision(declared)
    if count == MODEL_KEYPOINTS[COCO]:
        return ModelDecision(COCO)
    if count != MODEL_KEYPOINTS[BODY_25]:
        raise OpenPoseFormatError(
            first.source,
            where,
            f"expected COCO's 18 or BODY_25's 25 keypoints, got {count} "
            f"({unsupported_model(count)}), not supported",
        )
    return _body25_or_b([table for frame in frames for table in frame.people], first.source, where)


def to_detection(table: np.ndarray, model: str) -> Detection:
    """One person's (K, 3) pixel table of `model` as a COCO-18 Detection: NaN pixels and
    confidence 0 where a keypoint was not found."""
    if model == BODY_25:
        table = table[BODY25_TO_COCO18]
    confidence = table[:, 2]
    pixels = np.where(confidence[:, None] > 0, table[:, :2], np.nan)
    return Detection(pixels, confidence)


def frame_in_pixels(frame: RawFrame, keypoint_scale: str, image_size) -> RawFrame:
    """The frame with every person's coordinates in pixels (`to_pixels`)."""
    if keypoint_scale == PIXELS:
        return frame
    people = tuple(to_pixels(table, keypoint_scale, image_size) for table in frame.people)
    return dataclasses.replace(frame, people=people)

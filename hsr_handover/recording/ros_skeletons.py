"""The pose detector's skeletons of a bag's colour images: from a topic of
geometry_msgs/PolygonStamped (`ros_topics.SKELETON_TOPIC`: each person's keypoints one after
another, x = u px, y = v px, z = confidence, in OpenPose's COCO-18 or BODY_25 order), or from
an OpenPose JSON folder whose k-th frame belongs to the bag's k-th colour image. Either way the
model is decided and one person followed through the frames as for OpenPose's files
(`openpose_format.decide_model`, `person_tracking.PersonTracker`)."""

from __future__ import annotations

import logging
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from hsr_handover.interface.keypoints import Detection
from hsr_handover.interface.openpose_format import (
    AUTO,
    MAX_CONFIDENCE,
    MODEL_KEYPOINTS,
    RawFrame,
    decide_model,
    to_detection,
)
from hsr_handover.interface.openpose_json import (
    openpose_frame_files,
    read_openpose_recording,
)
from hsr_handover.interface.person_tracking import PersonTracker

LOG = logging.getLogger(__name__)
NO_SKELETON = "no skeleton message within the tolerance of the image"


def keypoints_per_person(counts: Sequence[int], topic: str) -> int:
    """Keypoints per person on a skeleton topic: BODY_25's 25 or COCO's 18, whichever divides
    every message's point count (25 when both do: OpenPose's default). Raises ValueError."""
    counts = [count for count in counts if count]
    fitting = [k for k in (MODEL_KEYPOINTS["BODY_25"], MODEL_KEYPOINTS["COCO"])
               if all(count % k == 0 for count in counts)]  # fmt: skip
    if not fitting:
        bad = next(c for c in counts if c % 18 and c % 25)
        raise ValueError(
            f"{topic}: expected each message's points to be people of 18 (COCO) or 25 (BODY_25) "
            f"keypoints, got {bad} points"
        )
    return fitting[0]


def detections_from_points(tables: Sequence[np.ndarray], topic: str) -> list[Detection]:
    """The followed person of each skeleton message, from its (N, 3) points table."""
    size = keypoints_per_person([len(table) for table in tables], topic)
    frames = []
    for index, table in enumerate(tables):
        if len(table) and not np.all((table[:, 2] >= 0) & (table[:, 2] <= MAX_CONFIDENCE)):
            raise ValueError(
                f"{topic}: message {index}: expected confidences (z) in [0, {MAX_CONFIDENCE:g}]"
            )
        table = (
            np.column_stack([table[:, :2], np.minimum(table[:, 2], 1.0)]) if len(table) else table
        )
        people = tuple(table[start : start + size] for start in range(0, len(table), size))
        frames.append(RawFrame(f"{topic} message {index}", "points", people))
    decision = decide_model(frames, AUTO)
    if decision.note:
        LOG.warning(decision.note)
    tracker = PersonTracker()
    return [
        tracker.update([to_detection(person, decision.model) for person in frame.people])
        for frame in frames
    ]


def detections_from_openpose(
    folder: Path, images: int, image_size: tuple[int, int]
) -> list[Detection]:
    """The followed person in each frame of an OpenPose JSON folder, frame k for the bag's k-th
    colour image. Raises ValueError when the folder's frames and the images differ in number."""
    files = openpose_frame_files(folder) if Path(folder).is_dir() else []
    if len(files) != images:
        raise ValueError(
            f"{folder}: expected {images} OpenPose frames, one per colour image, found {len(files)}"
        )
    return list(read_openpose_recording(files, image_size=image_size).detections)

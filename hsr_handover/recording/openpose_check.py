"""A summary of an OpenPose recording, for `hsr-handover openpose check`: what model and scale
it holds, how many frames and people, which frames could not be read and why, and how far the
tracked person's keypoints move from frame to frame (a jump much larger than usual means the
tracker or OpenPose confused two people)."""

from __future__ import annotations

import collections
import dataclasses
import math
import os
from collections.abc import Sequence

import numpy as np

from hsr_handover.interface.keypoints import STATUS_OK
from hsr_handover.interface.openpose_format import DEFAULT_KEYPOINT_SCALE, DEFAULT_MODEL
from hsr_handover.interface.openpose_json import OpenPoseRecording, read_openpose_recording
from hsr_handover.interface.person_tracking import mean_keypoint_distance

SKIPPED_EXAMPLES = 5
"""How many skipped frames a summary names."""


@dataclasses.dataclass(frozen=True)
class OpenPoseSummary:
    """What `summarise_recording` finds (JSON-ready through `to_dict`; None where undefined).

    `model_note`: why the model read is in doubt ("" when it is not). `people_per_frame`: min,
    median and max over the frames read. `skipped_reasons`: skipped
    frames counted by why; `skipped_examples`: the first few, {file, reason}. `tracked_frames`:
    frames in which the tracked person is seen. `jump_px`: their mean keypoint displacement
    between consecutive frames in which they are seen (`pairs` of frames): median and p95.
    """

    path: str
    model: str
    model_note: str
    keypoint_scale: str
    frames: int
    people_per_frame: dict[str, int | float | None]
    skipped: int
    skipped_reasons: dict[str, int]
    skipped_examples: list[dict[str, str]]
    tracked_frames: int
    jump_px: dict[str, float | int | None]

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)


def _statistic(values: Sequence[float], function) -> float | None:
    return float(function(values)) if len(values) else None


def frame_jumps_px(recording: OpenPoseRecording) -> list[float]:
    """The tracked person's mean keypoint displacement (px) between each pair of consecutive
    frames in which they are seen."""
    jumps = []
    for before, after in zip(recording.detections, recording.detections[1:], strict=False):
        if before.status == STATUS_OK and after.status == STATUS_OK:
            distance = mean_keypoint_distance(before, after)
            if math.isfinite(distance):
                jumps.append(distance)
    return jumps


def summarise_recording(recording: OpenPoseRecording) -> OpenPoseSummary:
    """The summary of a recording that has been read."""
    skipped_files = {item.file for item in recording.skipped}
    counts = [
        len(people)
        for file, people in zip(recording.files, recording.people, strict=True)
        if file not in skipped_files
    ]
    jumps = frame_jumps_px(recording)
    return OpenPoseSummary(
        path=recording.source,
        model=recording.model,
        model_note=recording.model_note,
        keypoint_scale=recording.keypoint_scale,
        frames=len(recording.files),
        people_per_frame={
            "min": min(counts, default=None),
            "median": _statistic(counts, np.median),
            "max": max(counts, default=None),
        },
        skipped=len(recording.skipped),
        skipped_reasons=dict(collections.Counter(item.kind for item in recording.skipped)),
        skipped_examples=[
            {"file": item.file, "reason": item.reason}
            for item in recording.skipped[:SKIPPED_EXAMPLES]
        ],
        tracked_frames=sum(d.status == STATUS_OK for d in recording.detections),
        jump_px={
            "median": _statistic(jumps, np.median),
            "p95": _statistic(jumps, lambda values: np.percentile(values, 95)),
            "pairs": len(jumps),
        },
    )


def check_openpose(
    path: str | os.PathLike,
    *,
    model: str = DEFAULT_MODEL,
    keypoint_scale: str = DEFAULT_KEYPOINT_SCALE,
    image_size: tuple[int, int] | None = None,
    near_px: tuple[float, float] | None = None,
) -> OpenPoseSummary:
    """Read an OpenPose file or folder of per-frame files (`read_openpose_recording`, whose
    ValueErrors it raises) and summarise it."""
    recording = read_openpose_recording(
        path, model=model, keypoint_scale=keypoint_scale, image_size=image_size, near_px=near_px
    )
    return summarise_recording(recording)


def _number(value: float | None, unit: str = "") -> str:
    return "n/a" if value is None else f"{value:.3g}{unit}"


def summary_lines(summary: OpenPoseSummary) -> list[str]:
    """A short human summary of one recording."""
    people = summary.people_per_frame
    lines = [
        f"{summary.path}: {summary.model}, {summary.keypoint_scale}, {summary.frames} "
        f"frame{'' if summary.frames == 1 else 's'}",
        f"  people per frame: min {_number(people['min'])}, median {_number(people['median'])}, "
        f"max {_number(people['max'])}",
    ]
    if summary.model_note:
        lines.append(f"  model: {summary.model_note}")
    if summary.skipped:
        reasons = ", ".join(f"{count} {kind}" for kind, count in summary.skipped_reasons.items())
        first = summary.skipped_examples[0]["reason"]
        lines.append(f"  skipped: {summary.skipped} ({reasons}); first: {first}")
    else:
        lines.append("  skipped: none")
    jump = summary.jump_px
    lines.append(
        f"  tracked person: seen in {summary.tracked_frames} frames; jump between frames "
        f"median {_number(jump['median'], ' px')}, p95 {_number(jump['p95'], ' px')} "
        f"({jump['pairs']} pairs)"
    )
    return lines

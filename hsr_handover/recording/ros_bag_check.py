"""A summary of a ROS bag for `hsr-handover bag check`: its format and length, each topic the
robot's perception reads (type, messages, rate, encodings), the frames paired and the gaps,
the TF chain to the camera, the skeletons, and whether `intent` can read it and if not why."""

from __future__ import annotations

from pathlib import Path

from hsr_handover.recording.ros_bag import RosBag
from hsr_handover.recording.ros_bag_survey import UNPAIRED_NAMED, BagSurvey, survey_bag
from hsr_handover.recording.ros_topics import HSR_TOPICS, BagTopics


def check_bag(path: Path, topics: BagTopics = HSR_TOPICS, tolerance: float | None = None,
              openpose: Path | None = None) -> BagSurvey:  # fmt: skip
    """Survey a bag (`ros_bag_survey.survey_bag`); BagError only when it is not one."""
    with RosBag(path) as bag:
        return survey_bag(bag, topics, tolerance, openpose)


def _stamps(stamps: list[float]) -> str:
    named = ", ".join(f"{stamp:.3f}" for stamp in stamps[:UNPAIRED_NAMED])
    more = f", ... ({len(stamps)} in all)" if len(stamps) > UNPAIRED_NAMED else ""
    return f"{len(stamps)}" + (f" (at {named} s{more})" if stamps else "")


def _line(label: str, text: str) -> str:
    return f"  {label + ':':14s}{text}"


def summary_lines(survey: BagSurvey) -> list[str]:
    """A short human summary of one bag."""
    lines = [f"{survey.path}: {survey.format}, {survey.duration_s:.2f} s, "
             f"{survey.message_count} messages"]  # fmt: skip
    for role, stream in survey.streams.items():
        if stream.msgtype is None:
            what = "not in the bag" + ("" if stream.needed else " (not needed)")
        else:
            rate = f", {stream.rate_hz:.1f} Hz" if stream.rate_hz else ""
            encodings = f", {' '.join(stream.encodings)}" if stream.encodings else ""
            what = f"{stream.msgtype}, {stream.messages} messages{rate}{encodings}"
        lines.append(_line(role, f"{stream.topic}: {what}"))
    if survey.tolerance_s:
        lines.append(_line("paired", (
            f"{survey.paired} colour-depth frames within {survey.tolerance_s * 1e3:.1f} ms; "
            f"unpaired colour {_stamps(survey.unpaired_color)}, depth "
            f"{_stamps(survey.unpaired_depth)}"
        )))  # fmt: skip
    if survey.tf_chain is not None:
        lines.append(_line("camera pose", f"{' -> '.join(survey.tf_chain)}; without a pose "
                           f"within the tolerance: {_stamps(survey.without_pose)}"))  # fmt: skip
    elif survey.base_frame:
        lines.append(_line("camera pose", f"no TF chain from {survey.base_frame}"))
    if survey.base_frame_note:
        lines.append(_line("note", survey.base_frame_note))
    if survey.skeleton_source:
        lines.append(_line("skeletons", f"{survey.skeleton_source}, for "
                           f"{survey.skeleton_frames} colour images"))  # fmt: skip
    if survey.settings:
        lines.append(_line("settings", f"the robot's, recorded ({', '.join(survey.settings)})"))
    if survey.problems:
        lines.append(_line("intent", f"cannot read it: {survey.problems[0]}"))
        lines.extend(_line("", f"also: {problem}") for problem in survey.problems[1:])
    else:
        lines.append(_line("intent", f"reads {len(survey.frames)} frames"))
    return lines

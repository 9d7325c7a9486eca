"""The pose detector's place filled by a recording: OpenPose's output read from files
(`perception.skeleton_recording` in a scenario) and played back at its frame rate, on the same
`skeleton_keypoints` port as the simulated detector, so the robot's side is unchanged."""

from __future__ import annotations

import logging
from pathlib import Path

from pydrake.systems.framework import DiagramBuilder, OutputPort

from hsr_handover.interface.openpose_format import OpenPoseFormatError
from hsr_handover.interface.openpose_json import OpenPoseRecording, read_openpose_recording
from hsr_handover.scenario import Scenario, ScenarioError, resolve_recording_path
from hsr_handover.world.systems.skeleton_sensor import RecordedSkeletonSource

KEY = "perception.skeleton_recording"
_logger = logging.getLogger(__name__)


def read_scenario_recording(scenario: Scenario) -> OpenPoseRecording:
    """The scenario's recording, read for its camera's image size. Raises ScenarioError naming
    the key when the files are not OpenPose output this reader takes."""
    config = scenario.perception.skeleton_recording
    path = resolve_recording_path(config.path, scenario.source)
    if path is None:  # the scenario's checks rule this out for a loaded scenario
        raise ScenarioError(scenario.source, f"{KEY}.path", "expected an existing file or folder")
    camera = scenario.camera
    try:
        return read_openpose_recording(
            path, model=config.model, keypoint_scale=config.keypoint_scale,
            image_size=(camera.width, camera.height), near_px=tuple(config.near_px) or None,
        )  # fmt: skip
    except OpenPoseFormatError as error:
        # The file's name, not its whole path, so that the one-line error keeps its point.
        where = Path(error.source).name + (f": {error.key}" if error.key else "")
        raise ScenarioError(scenario.source, f"{KEY}.path", f"{where}: {error.expected}") from None
    except ValueError as error:
        raise ScenarioError(scenario.source, KEY, str(error)) from None


def add_recorded_skeleton(builder: DiagramBuilder, scenario: Scenario) -> OutputPort:
    """Add the scenario's recording as a RecordedSkeletonSource named "skeleton_recording" and
    return its `keypoints` output. Frames that could not be read are skipped (their detection
    says so) and reported in one warning."""
    recording = read_scenario_recording(scenario)
    if recording.skipped:
        first = recording.skipped[0]
        _logger.warning(
            "%s: %s: skipped %d of %d frames (first: %s)", scenario.source, KEY,
            len(recording.skipped), len(recording.files), first.reason,
        )  # fmt: skip
    rate = scenario.perception.skeleton_recording.frame_rate_hz
    source = builder.AddNamedSystem(
        "skeleton_recording", RecordedSkeletonSource(recording.detections, rate)
    )
    return source.GetOutputPort("keypoints")

"""`perception.skeleton_recording` in a scenario: the station's `skeleton_keypoints` plays a
recording of OpenPose's output in place of the simulated detector; a bad key is a one-line
ScenarioError naming it."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover import interface
from hsr_handover.cli import main
from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.scenario import ScenarioError, load_scenario
from hsr_handover.simulation import build_simulation
from hsr_handover.world.station.recorded_skeleton import read_scenario_recording
from tests.openpose_files import BODY25_ORDER, BODY25B_ORDER, openpose_name, person_table
from tests.openpose_files import write_frame as write_openpose_frame

NECK = keypoint_index("neck")
KEY = "perception.skeleton_recording"


def _record(folder, order=BODY25_ORDER, frames: int = 3):
    """Frame k: the person of interest with the neck at u = 300 + 10 k, and a smaller person
    listed first in odd frames."""
    folder.mkdir()
    for k in range(frames):
        ours = person_table(order, neck_px=(300.0 + 10 * k, 150.0), shoulder_px=90.0)
        other = person_table(order, neck_px=(80.0, 160.0), shoulder_px=40.0)
        write_openpose_frame(folder / openpose_name(k), [other, ours] if k % 2 else [ours, other])
    return folder


def _with_recording(**settings):
    def mutate(data):
        data["camera"] = {"width": 320, "height": 240, "render_label": False}
        data["perception"] = {"enabled": True, "skeleton_recording": settings}

    return mutate


def test_a_scenario_with_a_recording_builds_a_station_that_plays_it(tmp_path, write_scenario):
    """The station's skeleton output is the recording, and the robot reads it on the same port
    (no simulation needed: the recording plays by the clock)."""
    _record(tmp_path / "session")
    scenario = load_scenario(write_scenario(_with_recording(path="session", frame_rate_hz=10.0)))
    recording = scenario.perception.skeleton_recording
    assert (recording.model, recording.keypoint_scale, recording.near_px) == ("auto", "pixels", [])
    simulation = build_simulation(scenario)
    station = simulation.station.diagram
    system_names = {system.get_name() for system in station.GetSystems()}
    assert "skeleton_recording" in system_names and "pose_detector" not in system_names
    root = simulation.diagram.CreateDefaultContext()
    played = station.GetOutputPort(interface.SKELETON_KEYPOINTS)
    robot_input = simulation.robot.diagram.GetInputPort(interface.SKELETON_KEYPOINTS)
    necks = []
    for time in (0.0, 0.05, 0.1, 0.25):
        root.SetTime(time)
        detection = played.Eval(simulation.station_context(root))
        seen_by_robot = robot_input.Eval(simulation.robot_context(root))
        np.testing.assert_array_equal(seen_by_robot.pixels, detection.pixels)
        necks.append(detection.pixels[NECK, 0])
    assert necks == [300.0, 300.0, 310.0, 320.0]  # frame k from k / 10 s, the same person
    root.SetTime(0.3)
    assert played.Eval(simulation.station_context(root)).status == "recording ended"


def test_normalised_recordings_are_converted_with_the_cameras_size(tmp_path, write_scenario):
    folder = tmp_path / "unit"
    folder.mkdir()
    table = person_table(neck_px=(160.0, 60.0), shoulder_px=40.0)
    table[:, :2] /= [319.0, 239.0]  # --keypoint_scale 3 on 320 x 240 images
    write_openpose_frame(folder / openpose_name(0), [table])

    def mutate(data):
        data["camera"] = {"width": 320, "height": 240}
        data["perception"] = {"skeleton_recording": {"path": str(folder), "keypoint_scale": "unit"}}

    (detection,) = read_scenario_recording(load_scenario(write_scenario(mutate))).detections
    np.testing.assert_allclose(detection.pixels[NECK], [160.0, 60.0])


@pytest.mark.parametrize(
    ("settings", "key_path", "expected"),
    [
        ({"frame_rate_hz": 30.0}, f"{KEY}.path", "expected an existing OpenPose JSON file or"),
        ({"path": "absent"}, f"{KEY}.path", "expected an existing OpenPose JSON file or folder"),
        (
            {"path": "session", "model": "BODY_25B"},
            f"{KEY}.model",
            "expected one of ['auto', 'COCO', 'BODY_25'], got 'BODY_25B'",
        ),
        (
            {"path": "session", "keypoint_scale": "normalised"},
            f"{KEY}.keypoint_scale",
            "expected one of ['pixels', 'unit', 'signed_unit']",
        ),
        ({"path": "session", "frame_rate_hz": 0}, f"{KEY}.frame_rate_hz", "expected a number in"),
        ({"path": "session", "near_px": [1.0]}, f"{KEY}.near_px", "expected [u, v]"),
        ({"path": "session", "fps": 30}, f"{KEY}.fps", "unknown key; expected one of: path"),
    ],
)
def test_a_bad_recording_key_is_a_scenario_error_naming_it(
    tmp_path, write_scenario, settings, key_path, expected
):
    _record(tmp_path / "session", frames=1)
    path = write_scenario(_with_recording(**settings))
    with pytest.raises(ScenarioError) as raised:
        load_scenario(path)
    assert raised.value.key_path == key_path
    assert raised.value.expected.startswith(expected), raised.value.expected


def test_a_recording_of_an_unsupported_model_fails_validation_in_one_line(
    tmp_path, write_scenario, capsys
):
    _record(tmp_path / "session", order=BODY25B_ORDER, frames=2)
    path = write_scenario(_with_recording(path="session"))
    scenario = load_scenario(path)  # the files are read when the station is built
    with pytest.raises(ScenarioError) as raised:
        read_scenario_recording(scenario)
    assert raised.value.key_path == f"{KEY}.path"
    assert raised.value.expected.startswith(
        f"{openpose_name(0)}: people[0].pose_keypoints_2d: expected COCO or BODY_25, got BODY_25B"
    )
    assert main(["validate", str(path)]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and len(captured.err.splitlines()) == 1
    assert captured.err.startswith(f"error: {path}: {KEY}.path: {openpose_name(0)}: people[0]")

"""Recorded RGB-D sessions: the folder layout written and read back, the player and recorder on
their own ports, and errors naming the file at fault."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.systems.analysis import Simulator
from pydrake.systems.sensors import ImageDepth32F, ImageRgba8U

from hsr_handover import interface
from hsr_handover.interface.coco18 import NUM_KEYPOINTS
from hsr_handover.interface.keypoints import Detection
from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.recording.rgbd_session import (
    CAMERA_INFO,
    SessionError,
    SessionFrame,
    depth_to_millimetres,
    read_session,
    start_session,
    write_frame,
)
from hsr_handover.recording.session_player import BEFORE_FIRST, SessionPlayer
from hsr_handover.recording.session_recorder import SessionRecorder

CAMERA = PinholeCamera(32, 24, 30.0, 31.0, 15.5, 11.0)
PERIOD = 0.1


def _frame(k: int) -> SessionFrame:
    rng = np.random.default_rng(k)
    color = rng.integers(0, 256, (CAMERA.height, CAMERA.width, 4), dtype=np.uint8)
    color[:, :, 3] = 255
    depth = rng.uniform(0.5, 3.0, (CAMERA.height, CAMERA.width)).astype(np.float32)
    depth[0, :3] = [np.inf, 0.0, np.nan]  # beyond range, too near, no reading
    X_WC = RigidTransform(RollPitchYaw(0.1 * k, -0.2, 0.3), [1.0, 2.0 + k, 1.2]).GetAsMatrix4()
    pixels = rng.uniform(0, 20, (NUM_KEYPOINTS, 2))
    confidence = rng.uniform(0.2, 1.0, NUM_KEYPOINTS)
    confidence[3] = 0.0  # a keypoint the detector missed
    pixels[3] = np.nan
    keypoints = Detection(pixels, confidence) if k != 1 else Detection.missing("nobody")
    return SessionFrame(k * PERIOD, color, depth, X_WC, keypoints)


@pytest.fixture
def session(tmp_path):
    directory = tmp_path / "session"
    start_session(directory, CAMERA, {"camera": {"rate_hz": 1 / PERIOD}})
    for k in range(3):
        write_frame(directory, k, _frame(k))
    return directory


def test_depth_is_written_in_whole_millimetres_with_zero_where_there_is_no_reading():
    depth = np.array([[1.2344, 1.2346, np.inf, 0.0, np.nan, 70.0]], dtype=np.float32)
    millimetres = depth_to_millimetres(depth)
    assert millimetres.dtype == np.uint16
    np.testing.assert_array_equal(millimetres, [[1234, 1235, 0, 0, 0, 0]])


def test_a_session_reads_back_as_it_was_written(session):
    read = read_session(session)
    assert read.camera == CAMERA and read.indices == (0, 1, 2)
    np.testing.assert_allclose(read.stamps, [0.0, 0.1, 0.2])
    assert read.settings == {"camera": {"rate_hz": 1 / PERIOD}}
    for k in range(3):
        written, frame = _frame(k), read.frame(k)
        np.testing.assert_array_equal(frame.color, written.color)
        expected = np.where(np.isfinite(written.depth), np.round(written.depth * 1000) / 1000, 0)
        np.testing.assert_allclose(frame.depth, expected, atol=1e-6)
        np.testing.assert_allclose(frame.X_WC, written.X_WC, atol=1e-12)
    np.testing.assert_allclose(read.keypoints[0].pixels, _frame(0).keypoints.pixels)
    np.testing.assert_allclose(read.keypoints[0].confidence, _frame(0).keypoints.confidence)
    assert not np.any(read.keypoints[1].confidence > 0)  # nobody in frame 1


def test_camera_info_is_ros_camera_info(session):
    info = yaml.safe_load((session / CAMERA_INFO).read_text())
    assert (info["image_width"], info["image_height"]) == (32, 24)
    assert info["camera_matrix"]["data"] == [30.0, 0.0, 15.5, 0.0, 31.0, 11.0, 0.0, 0.0, 1.0]
    assert info["distortion_model"] == "plumb_bob"
    assert len(info["projection_matrix"]["data"]) == 12


@pytest.mark.parametrize(
    ("spoil", "expected"),
    [
        (lambda d: (d / CAMERA_INFO).unlink(), "camera_info.yaml not found"),
        (lambda d: (d / "pose" / "000000000002.yaml").write_text("stamp: 0.05\n"
         "position: [0, 0, 0]\norientation: [0, 0, 0, 1]\n"), "expected times rising"),
        (lambda d: (d / "openpose" / "000000000001_keypoints.json").unlink(),
         "expected the frame's OpenPose keypoints"),
        (lambda d: (d / "pose" / "000000000000.yaml").write_text("stamp: 0\n"),
         "position: expected 3 finite numbers"),
    ],
)  # fmt: skip
def test_a_broken_session_is_refused_naming_the_file(session, spoil, expected):
    spoil(session)
    with pytest.raises(SessionError, match=expected):
        read_session(session)


def _settings(text: str):
    return lambda d: (d / "session.yaml").write_text(text)


def _link_out(d: Path, inside: str) -> None:
    """Replace a file of the session with a symbolic link to a copy outside the folder."""
    outside = d.parent / "elsewhere"
    outside.write_bytes((d / inside).read_bytes())
    (d / inside).unlink()
    (d / inside).symlink_to(outside)


@pytest.mark.parametrize(
    ("spoil", "expected"),
    [
        (_settings("robot:\n  model: ../../elsewhere/x.sdf\n"),
         r"session.yaml: robot: expected only the robot's settings"),
        (_settings("perception:\n  skeleton_recording:\n    path: /etc/passwd\n"),
         r"session.yaml: perception.skeleton_recording: expected none here"),
        (_settings("simulation:\n  duration: 5\n"), r"simulation.duration: expected none here"),
        (lambda d: _link_out(d, "pose/000000000001.yaml"),
         r"pose/000000000001.yaml: expected a file inside the session folder"),
        (lambda d: _link_out(d, "openpose/000000000002_keypoints.json"),
         r"000000000002_keypoints.json: expected a file inside the session folder"),
    ],
)  # fmt: skip
def test_a_session_is_read_only_from_inside_its_folder(session, spoil, expected):
    """Nothing a session names leads out of it: its settings are the robot's own (no model
    file, no recording elsewhere), and no frame is a link to a file outside the folder."""
    spoil(session)
    with pytest.raises(SessionError, match=expected):
        read_session(session)


def test_a_frames_image_linked_out_of_the_session_is_refused(session):
    _link_out(session, "color/000000000001.png")
    with pytest.raises(SessionError, match="expected a file inside the session folder"):
        read_session(session)


def test_a_frame_whose_image_is_cut_short_or_missing_is_skipped_and_said_why(session, capfd):
    """A frame's image cut short (a copy interrupted) or missing leaves that frame out, named
    with why; libpng is never given it, so its own error lines never reach the user."""
    image = session / "depth" / "000000000002.png"
    image.write_bytes(image.read_bytes()[:200])
    (session / "color" / "000000000000.png").unlink()
    read = read_session(session)
    assert read.skipped == ("frame 0: 000000000000.png in color/ is missing",
                            "frame 2: depth/000000000002.png is cut short")  # fmt: skip
    assert read.stamps == pytest.approx([PERIOD]) and read.indices == (1,)
    assert read.frame(0).stamp == pytest.approx(PERIOD)
    assert capfd.readouterr().err == ""


def test_an_image_spoilt_after_the_session_was_read_is_refused_when_loaded(session):
    read = read_session(session)
    image = session / "color" / "000000000001.png"
    image.write_bytes(image.read_bytes()[:200])
    with pytest.raises(SessionError, match="expected a whole PNG image; it is cut short"):
        read.frame(1)


def test_a_session_with_no_whole_frame_is_refused(session):
    for image in (session / "color").glob("*.png"):
        image.write_bytes(b"not a png")
    with pytest.raises(SessionError, match="expected a frame with whole images; frame 0: "):
        read_session(session)


def test_a_distorted_camera_is_refused(session):
    info = yaml.safe_load((session / CAMERA_INFO).read_text())
    info["distortion_coefficients"]["data"] = [0.1, 0, 0, 0, 0]
    (session / CAMERA_INFO).write_text(yaml.safe_dump(info))
    with pytest.raises(SessionError, match=r"camera_info.yaml: distortion_coefficients"):
        read_session(session)


def test_the_player_holds_each_frame_from_its_stamp_until_the_next(session):
    player = SessionPlayer(read_session(session), start=0.0)
    context = player.CreateDefaultContext()
    for time, k in ((0.0, 0), (0.05, 0), (0.1, 1), (0.19, 1), (0.2, 2), (5.0, 2)):
        context.SetTime(time)
        frame = _frame(k)
        assert player.GetOutputPort(interface.CAMERA_IMAGE_TIME).Eval(context) == pytest.approx(
            k * PERIOD
        )
        color = player.GetOutputPort(interface.CAMERA_COLOR_IMAGE).Eval(context)
        np.testing.assert_array_equal(color.data, frame.color)
        pose = player.GetOutputPort(interface.CAMERA_POSE).Eval(context)
        np.testing.assert_allclose(pose.GetAsMatrix4(), frame.X_WC, atol=1e-12)
    late = SessionPlayer(read_session(session), start=-1.0)  # its first frame comes at 1 s
    context = late.CreateDefaultContext()
    assert math.isnan(late.GetOutputPort(interface.CAMERA_IMAGE_TIME).Eval(context))
    keypoints = late.GetOutputPort(interface.SKELETON_KEYPOINTS).Eval(context)
    assert keypoints.status == BEFORE_FIRST


def test_the_recorder_writes_the_frame_captured_at_each_period(tmp_path):
    directory = tmp_path / "recorded"
    start_session(directory, CAMERA)
    recorder = SessionRecorder(directory, PERIOD)
    context = recorder.CreateDefaultContext()
    frame = _frame(2)
    color, depth = ImageRgba8U(CAMERA.width, CAMERA.height), ImageDepth32F(32, 24)
    color.mutable_data[:] = frame.color
    depth.mutable_data[:, :, 0] = frame.depth
    inputs = {
        interface.CAMERA_COLOR_IMAGE: color, interface.CAMERA_DEPTH_IMAGE: depth,
        interface.CAMERA_POSE: RigidTransform(frame.X_WC), interface.CAMERA_IMAGE_TIME: 0.2,
        interface.SKELETON_KEYPOINTS: frame.keypoints,
    }  # fmt: skip
    for name, value in inputs.items():
        recorder.GetInputPort(name).FixValue(context, value)
    Simulator(recorder, context).AdvanceTo(0.25)
    assert sorted(p.name for p in (directory / "pose").iterdir()) == ["000000000002.yaml"]
    read = read_session(directory)
    np.testing.assert_array_equal(read.frame(0).color, frame.color)
    assert read.stamps == (0.2,)

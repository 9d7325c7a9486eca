"""ROS bags read as sessions: ROS 1, ROS 2 sqlite3 and MCAP bags built here with rosbags'
writers, their frames paired by stamp, depth and colour in each encoding giving the same
images, the camera's pose composed from TF, and every bad bag refused with one line and exit
status 2 before anything is written."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hsr_handover.cli import main
from hsr_handover.recording.ros_bag_session import read_bag_session
from hsr_handover.recording.ros_pairing import pair_stamps
from hsr_handover.recording.ros_skeletons import NO_SKELETON
from tests.recording.ros_bag_builder import (
    CAMERA,
    FORMATS,
    BagSpec,
    build_bag,
    colour,
    depth_mm,
    expected_X_WC,
    person,
)


@pytest.mark.parametrize("kind", FORMATS)
def test_a_bag_reads_as_the_session_it_holds(tmp_path, kind):
    path = build_bag(tmp_path, kind, BagSpec())
    with read_bag_session(path) as session:
        assert session.camera == CAMERA
        assert session.stamps == pytest.approx([0.0, 0.1, 0.2, 0.3], abs=1e-9)
        assert session.settings == {}
        for k, stamp in enumerate(session.stamps):
            frame = session.frame(k)
            assert np.array_equal(frame.color[:, :, :3], colour(k))
            assert np.all(frame.color[:, :, 3] == 255)
            np.testing.assert_allclose(frame.depth, depth_mm(k) / 1000.0, atol=1e-6)
            assert frame.depth.dtype == np.float32 and frame.depth[0, 0] == 0
            np.testing.assert_allclose(frame.X_WC, expected_X_WC(stamp, session.stamps), atol=1e-12)
            seen = person(k)[:, 2] > 0
            np.testing.assert_allclose(frame.keypoints.pixels[seen], person(k)[seen, :2], atol=1e-4)
            assert np.isnan(frame.keypoints.pixels[3]).all()


@pytest.mark.parametrize("encoding", ["bgr8", "png"])
def test_colour_in_bgr8_or_compressed_gives_the_same_rgb_as_rgb8(tmp_path, encoding):
    path = build_bag(tmp_path, "ros2-mcap", BagSpec(color_encoding=encoding))
    with read_bag_session(path) as session:
        for k in range(len(session.stamps)):
            assert np.array_equal(session.frame(k).color[:, :, :3], colour(k))


@pytest.mark.parametrize("kind", ["ros1", "ros2-sqlite3"])
def test_depth_in_32fc1_metres_gives_the_same_metres_as_16uc1_millimetres(tmp_path, kind):
    millimetres = build_bag(tmp_path, kind, BagSpec(depth_encoding="16UC1"), "mm")
    metres = build_bag(tmp_path, kind, BagSpec(depth_encoding="32FC1"), "m")
    with read_bag_session(millimetres) as a, read_bag_session(metres) as b:
        for k in range(len(a.stamps)):
            depth_a, depth_b = a.frame(k).depth, b.frame(k).depth
            np.testing.assert_allclose(depth_a, depth_b, atol=1e-6)
            assert depth_b[0, 0] == 0  # NaN read as no reading


def test_frames_pair_by_nearest_stamp_within_the_tolerance_and_gaps_are_named(tmp_path, capsys):
    colour_stamps = [0.0, 0.1, 0.2, 0.3, 0.4]
    # depth 10 ms late, none near 0.2 s, one stray between frames
    depth_stamps = [0.01, 0.11, 0.26, 0.31, 0.41]
    spec = BagSpec(color_stamps=colour_stamps, depth_stamps=depth_stamps)
    path = build_bag(tmp_path, "ros2-mcap", spec)
    with read_bag_session(path) as session:
        assert session.stamps == pytest.approx([0.0, 0.1, 0.3, 0.4])
    summary = tmp_path / "check.json"
    assert main(["bag", "check", str(path), "--json", str(summary)]) == 0
    out = capsys.readouterr().out
    assert "paired:       4 colour-depth frames within 50.0 ms" in out
    assert "unpaired colour 1 (at 0.200 s), depth 1 (at 0.260 s)" in out
    written = json.loads(summary.read_text())
    assert written["paired"] == 4 and written["usable"] is True
    assert written["unpaired_color"] == pytest.approx([0.2])
    assert written["unpaired_depth"] == pytest.approx([0.26])
    assert written["streams"]["depth"]["encodings"] == ["16UC1"]
    assert written["format"] == "ROS 2 (MCAP)"


def test_a_tighter_tolerance_pairs_fewer_frames(tmp_path):
    spec = BagSpec(depth_stamps=[0.0, 0.104, 0.2, 0.3])
    path = build_bag(tmp_path, "ros1", spec)
    with read_bag_session(path, tolerance=0.003) as session:
        assert session.stamps == pytest.approx([0.0, 0.2, 0.3])


def test_pairing_keeps_the_nearer_of_two_claims():
    pairing = pair_stamps([0.0, 0.04, 0.1], [0.03, 0.1], 0.05)
    assert pairing.pairs == ((1, 0), (2, 1))
    assert pairing.unpaired_first == (0,) and pairing.unpaired_second == ()


def test_the_camera_pose_is_interpolated_between_tf_samples(tmp_path):
    spec = BagSpec(color_stamps=[0.0, 0.05, 0.1], tf_stamps=[0.0, 0.1])
    path = build_bag(tmp_path, "ros2-sqlite3", spec)
    with read_bag_session(path) as session:
        middle = session.frame(1).X_WC
        np.testing.assert_allclose(middle, expected_X_WC(0.05, [0.0, 0.1]), atol=1e-12)
        assert not np.allclose(middle, session.frame(0).X_WC)


def test_frames_without_a_pose_within_the_tolerance_are_dropped(tmp_path, capsys):
    spec = BagSpec(color_stamps=[0.0, 0.1, 0.2, 0.3], tf_stamps=[0.0, 0.1])
    path = build_bag(tmp_path, "ros1", spec)
    with read_bag_session(path) as session:
        assert session.stamps == pytest.approx([0.0, 0.1])
    assert main(["bag", "check", str(path)]) == 0
    assert "without a pose within the tolerance: 2 (at 0.200, 0.300 s)" in capsys.readouterr().out


def test_without_odom_the_pose_is_in_base_footprint_and_the_summary_says_so(tmp_path, capsys):
    path = build_bag(tmp_path, "ros2-mcap", BagSpec(odom=False))
    with read_bag_session(path) as session:
        X_BC = session.frame(0).X_WC
    with read_bag_session(path, topics=_topics(base_frame="map")) as session:
        X_MC = session.frame(0).X_WC
    np.testing.assert_allclose(X_MC, expected_X_WC(0.0, [0.0, 0.3]), atol=1e-12)
    assert not np.allclose(X_BC, X_MC)
    assert main(["bag", "check", str(path)]) == 0
    assert "note:         no odom frame in TF: poses in base_footprint" in capsys.readouterr().out


def _topics(**changes):
    import dataclasses

    from hsr_handover.recording.ros_topics import HSR_TOPICS

    return dataclasses.replace(HSR_TOPICS, **changes)


def test_skeleton_messages_pair_with_images_by_stamp(tmp_path):
    spec = BagSpec(skeleton_stamps=[0.0, 0.1, 0.3])
    path = build_bag(tmp_path, "ros1", spec)
    with read_bag_session(path) as session:
        statuses = [detection.status for detection in session.keypoints]
    assert statuses == ["ok", "ok", NO_SKELETON, "ok"]


def test_skeletons_from_an_openpose_folder_belong_to_the_images_in_order(tmp_path):
    from hsr_handover.interface.openpose_format import to_detection
    from hsr_handover.interface.openpose_json import write_openpose_json

    path = build_bag(tmp_path, "ros2-mcap", BagSpec(skeleton_stamps=[]))
    folder = tmp_path / "openpose"
    folder.mkdir()
    for k in range(4):
        people = [to_detection(person(k), "COCO")] if k != 2 else []
        write_openpose_json(folder / f"video_{k:012d}_keypoints.json", people)
    with read_bag_session(path, openpose=folder) as session:
        assert [d.status for d in session.keypoints][2] != "ok"
        seen = person(3)[:, 2] > 0
        np.testing.assert_allclose(
            session.keypoints[3].pixels[seen], person(3)[seen, :2], atol=1e-3
        )


def _refused(capsys, argv: list[str]) -> str:
    code = main(argv)
    captured = capsys.readouterr()
    assert code == 2 and captured.out == "", captured
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), captured.err
    return lines[0]


BAD_BAGS = {
    "no depth topic": (BagSpec(depth_stamps=[]),
                       "/hsrb/head_rgbd_sensor/depth_registered/image_rect_raw: expected "
                       "sensor_msgs/msg/Image, the topic is not in the bag"),
    "no camera_info": (BagSpec(camera_info=False),
                       "/hsrb/head_rgbd_sensor/rgb/camera_info: expected "
                       "sensor_msgs/msg/CameraInfo"),
    "unpaired depth": (BagSpec(depth_stamps=[1.0, 1.1, 1.2, 1.3]),
                       "expected colour and depth images stamped within 50.0 ms of each other, "
                       "found no such pair"),
    "unsupported colour": (BagSpec(color_encoding="8UC3"),
                           "image_rect_color: expected encoding rgb8, bgr8, rgba8, bgra8, "
                           "got '8UC3'"),
    "no TF chain": (BagSpec(static_mount=False),
                    "/tf: expected a chain of transforms from odom to head_rgbd_sensor_rgb_frame"),
    "no skeletons": (BagSpec(skeleton_stamps=[]),
                     "/openpose/pose_keypoints: expected geometry_msgs/msg/PolygonStamped, the "
                     "topic is not in the bag"),
}  # fmt: skip


@pytest.mark.parametrize("case", BAD_BAGS)
@pytest.mark.parametrize("command", [["intent"], ["bag", "check"]])
def test_a_bag_intent_cannot_read_is_refused_with_one_line(tmp_path, capsys, case, command):
    spec, expected = BAD_BAGS[case]
    path = build_bag(tmp_path, "ros2-mcap" if len(case) % 2 else "ros1", spec)
    output = tmp_path / "out.json"
    if command == ["intent"]:
        line = _refused(capsys, ["intent", str(path), "--json", str(output)])
        assert line.startswith(f"error: {path}: ") and expected in line, line
        assert not output.exists()
    else:  # the check summarises what it can, and names why intent cannot read it
        assert main(["bag", "check", str(path), "--json", str(output)]) == 0
        out = capsys.readouterr().out
        assert "intent:       cannot read it: " in out and expected in out, out
        assert json.loads(output.read_text())["usable"] is False


@pytest.mark.parametrize("command", [["intent"], ["bag", "check"]])
def test_a_file_or_folder_that_is_not_a_bag_is_refused_with_one_line(tmp_path, capsys, command):
    fake = tmp_path / "fake.bag"
    fake.write_text("not a bag\n")
    line = _refused(capsys, [*command, str(fake)])
    assert line.startswith(f"error: {fake}: expected a readable ROS 1 bag: "), line
    folder = tmp_path / "fake2"
    folder.mkdir()
    (folder / "metadata.yaml").write_text("rosbag2_bagfile_information: 3\n")
    line = _refused(capsys, [*command, str(folder)])
    assert line.startswith(f"error: {folder}: expected a readable ROS 2 (?) bag: "), line
    other = tmp_path / "notes.txt"
    other.write_text("x")
    line = _refused(capsys, [*command, str(other)])
    assert "expected" in line and str(other) in line


def test_bag_options_are_refused_for_a_session_folder(tmp_path, capsys):
    (tmp_path / "camera_info.yaml").write_text("{}")
    line = _refused(capsys, ["intent", str(tmp_path), "--tolerance", "0.01"])
    assert line == f"error: --tolerance: expected a bag, {tmp_path} is a folder"
    line = _refused(capsys, ["intent", str(tmp_path), "--tolerance", "-1"])
    assert line == "error: --tolerance: expected a positive number of seconds, got -1.0"


def test_a_bag_whose_messages_cannot_be_read_is_refused_with_one_line(tmp_path, capsys):
    """A ROS 1 bag that opens but whose chunk is overwritten half way: rosbags fails while
    reading its messages, which is the bag's fault (exit 2), not an internal error."""
    path = build_bag(tmp_path, "ros1", BagSpec())
    data = bytearray(path.read_bytes())
    middle = len(data) // 2
    data[middle : middle + 64] = b"\xff" * 64
    path.write_bytes(bytes(data))
    output = tmp_path / "out.json"
    line = _refused(capsys, ["intent", str(path), "--json", str(output)])
    assert line.startswith(f"error: {path}: ") and "expected readable messages" in line, line
    assert not output.exists()

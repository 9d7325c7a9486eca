"""A simulated session recorded as a ROS bag (`run --record-format ros2` or `ros1`) and replayed
offline through `intent`: the same target at the same time as the robot recognised online,
as for the folder layout (`test_offline_intent.py`)."""

from __future__ import annotations

import json

import pytest

from hsr_handover.cli import main
from tests.recording.online_offline import assert_offline_as_online, record_point_left


@pytest.fixture(scope="module", params=["ros2", "ros1"])
def recorded_bag(request, tmp_path_factory):
    """point_left.yaml recorded as a bag: the run's printout and the bag."""
    folder = tmp_path_factory.mktemp(f"bag_{request.param}")
    bag = folder / ("session.bag" if request.param == "ros1" else "session")
    printed = record_point_left(folder, bag, "--record-format", request.param)
    return folder, bag, printed


def test_a_bag_replayed_offline_recognises_what_the_robot_did_online_and_when(recorded_bag, capsys):
    """One test per bag (the run is the cost), so each run is made once however tests are
    spread over workers."""
    folder, bag, printed = recorded_bag
    assert_offline_as_online(bag, printed, folder, capsys)
    # and every topic the HSR publishes is there, as bag check finds it
    summary = folder / "check.json"
    assert main(["bag", "check", str(bag), "--json", str(summary)]) == 0
    written = json.loads(summary.read_text())
    assert written["usable"] and written["paired"] == 105 and written["frames"] == 105
    assert written["format"] == ("ROS 1" if bag.suffix == ".bag" else "ROS 2 (MCAP)")
    streams = written["streams"]
    assert streams["color"]["encodings"] == ["rgb8"]
    assert streams["depth"]["encodings"] == ["16UC1"]
    assert all(streams[role]["messages"] == 105 for role in ("color", "depth", "joint_states"))
    assert written["tf_chain"] == ["odom", "base_footprint", "head_rgbd_sensor_link",
                                   "head_rgbd_sensor_rgb_frame"]  # fmt: skip
    assert not list(folder.glob(".*.partial"))

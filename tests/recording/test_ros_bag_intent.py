"""A simulated session recorded as a ROS bag (`run --record-format ros2` or `ros1`) and replayed
offline through `intent`: the same target at the same time as the robot recognised online,
as for the folder layout (`test_offline_intent.py`)."""

from __future__ import annotations

import contextlib
import io
import json
import re

import pytest
import yaml

from hsr_handover.cli import main
from tests.paths import SCENARIOS


@pytest.fixture(scope="module", params=["ros2", "ros1"])
def recorded_bag(request, tmp_path_factory):
    """point_left.yaml at 320 x 240, 3.5 s, recorded as a bag: the run's printout and the bag."""
    folder = tmp_path_factory.mktemp(f"bag_{request.param}")
    scenario = yaml.safe_load((SCENARIOS / "point_left.yaml").read_text())
    scenario["camera"] = {"width": 320, "height": 240, "render_label": False}
    scenario["perception"] = {"enabled": True}
    scenario["simulation"]["duration"] = 3.5
    path = folder / "point_left.yaml"
    path.write_text(yaml.safe_dump(scenario))
    bag = folder / ("session.bag" if request.param == "ros1" else "session")
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        code = main(["run", str(path), "--record", str(bag), "--record-format", request.param,
                     "--html", str(folder / "r.html")])  # fmt: skip
    assert code == 0
    return folder, bag, printed.getvalue()


def _line(output: str, label: str) -> str:
    return next(line for line in output.splitlines() if line.startswith(label))


def test_a_bag_replayed_offline_recognises_what_the_robot_did_online_and_when(recorded_bag, capsys):
    """One test per bag (the run is the cost), so each run is made once however tests are
    spread over workers."""
    folder, bag, printed = recorded_bag
    online = _line(printed, "intent:")
    matched = re.fullmatch(r"intent:      red \(recognised at (\d\.\d\d) s\)", online)
    assert matched is not None, online
    summary = folder / "intent.json"
    assert main(["intent", str(bag), "--json", str(summary)]) == 0
    out = capsys.readouterr().out
    assert _line(out, "intent:") == online
    assert _line(out, "frames:") == "frames:      105 at 30 Hz"
    written = json.loads(summary.read_text())
    frame = written["frame"]
    assert written["target"] == "red"
    assert written["recognised_time"] == pytest.approx(frame / 30, abs=1e-6)
    assert f"{frame / 30:.2f}" == matched.group(1)
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

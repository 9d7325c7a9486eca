"""The bag writer and its recorder on their own ports: a capture written as the HSR's topics
and read back as the session it was, trajectories for the HSR's controllers, a bag that only
appears at its path once complete, and --record's checks before anything runs."""

from __future__ import annotations

import numpy as np
import pytest
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.systems.analysis import Simulator
from pydrake.systems.sensors import ImageDepth32F, ImageRgba8U

from hsr_handover import interface
from hsr_handover.cli import main
from hsr_handover.hsr import COMMANDED_JOINTS
from hsr_handover.interface.joint_trajectory import MODEL_JOINTS, JointTrajectory
from hsr_handover.interface.keypoints import Detection
from hsr_handover.recording.ros_bag import RosBag
from hsr_handover.recording.ros_bag_recorder import RosBagRecorder
from hsr_handover.recording.ros_bag_session import read_bag_session
from hsr_handover.recording.ros_bag_writer import RosBagWriter, partial_path
from hsr_handover.recording.ros_messages import stamp_seconds
from hsr_handover.recording.ros_topics import (
    ARM_TRAJECTORY_TOPIC,
    BASE_TRAJECTORY_TOPIC,
    JOINT_STATES_TOPIC,
)
from tests.paths import SCENARIOS
from tests.recording.ros_bag_builder import CAMERA, person

PERIOD = 0.1


def _bag_path(tmp_path, version: str):
    return tmp_path / ("run.bag" if version == "ros1" else "run")


def _fix_inputs(recorder: RosBagRecorder, context, stamp: float, state: np.ndarray) -> dict:
    rng = np.random.default_rng(int(stamp * 10))
    color = ImageRgba8U(CAMERA.width, CAMERA.height)
    color.mutable_data[:] = rng.integers(0, 256, color.data.shape, dtype=np.uint8)
    color.mutable_data[:, :, 3] = 255
    depth = ImageDepth32F(CAMERA.width, CAMERA.height)
    depth.mutable_data[:] = np.rint(rng.uniform(0.5, 3.0, depth.data.shape) * 1000) / 1000
    depth.mutable_data[0, 0] = np.inf  # beyond the sensor's range: no reading
    X_WC = RigidTransform(RollPitchYaw(-1.7, 0.1, 0.4), [0.3, -0.2, 1.2])
    table = person(0)
    keypoints = Detection(np.where(table[:, 2:] > 0, table[:, :2], np.nan), table[:, 2])
    values = {
        interface.CAMERA_COLOR_IMAGE: color, interface.CAMERA_DEPTH_IMAGE: depth,
        interface.CAMERA_POSE: X_WC, interface.CAMERA_IMAGE_TIME: stamp,
        interface.SKELETON_KEYPOINTS: keypoints, interface.HSR_STATE_MEASURED: state,
    }  # fmt: skip
    for name, value in values.items():
        recorder.GetInputPort(name).FixValue(context, value)
    return values


@pytest.mark.parametrize("version", ["ros1", "ros2"])
def test_the_recorder_writes_each_capture_once_as_the_hsr_topics(tmp_path, version):
    path = _bag_path(tmp_path, version)
    writer = RosBagWriter(path, version, CAMERA)
    recorder = RosBagRecorder(writer, PERIOD, COMMANDED_JOINTS)
    simulator = Simulator(recorder)
    context = simulator.get_mutable_context()
    state = np.arange(2 * len(COMMANDED_JOINTS), dtype=float) / 10
    written = []
    # At 0.1 s the camera still holds the capture of 0 s: it is not written again.
    for time, stamp in ((0.0, 0.0), (0.1, 0.0), (0.2, 0.2)):
        written.append(_fix_inputs(recorder, context, stamp, state))
        simulator.AdvanceTo(time)
    assert not path.exists()  # not until it is complete
    writer.close()
    assert path.exists() and not partial_path(path).parent.exists()
    with read_bag_session(path) as session:
        assert session.stamps == pytest.approx([0.0, 0.2])
        frame = session.frame(1)
        values = written[2]
        assert np.array_equal(frame.color, values[interface.CAMERA_COLOR_IMAGE].data)
        expected_depth = values[interface.CAMERA_DEPTH_IMAGE].data[:, :, 0].copy()
        expected_depth[0, 0] = 0
        np.testing.assert_allclose(frame.depth, expected_depth, atol=1e-6)
        np.testing.assert_allclose(
            frame.X_WC, values[interface.CAMERA_POSE].GetAsMatrix4(), atol=1e-12
        )
        seen = person(0)[:, 2] > 0
        np.testing.assert_allclose(frame.keypoints.pixels[seen], person(0)[seen, :2], atol=1e-4)
    with RosBag(path) as bag:
        states = list(bag.messages(JOINT_STATES_TOPIC))
    assert len(states) == 2
    assert states[0].name[:4] == ["odom_x", "odom_y", "odom_t", "arm_lift_joint"]
    assert "head_pan_joint" in states[0].name
    count = len(COMMANDED_JOINTS)
    np.testing.assert_allclose(states[1].position, state[:count])
    np.testing.assert_allclose(states[1].velocity, state[count:])


@pytest.mark.parametrize("version", ["ros1", "ros2"])
def test_a_joint_trajectory_is_written_for_the_hsr_controller(tmp_path, version):
    path = _bag_path(tmp_path, version)
    writer = RosBagWriter(path, version, CAMERA)
    joints = ["arm_lift_joint", "arm_flex_joint"]
    positions = np.array([[0.0, 0.0], [0.1, -0.2], [0.2, -0.5]])
    velocities = np.array([[0.0, 0.0], [0.15, -0.3], [0.0, 0.0]])
    writer.add_joint_trajectory(ARM_TRAJECTORY_TOPIC, 2.5, joints, [0.0, 0.8, 1.75],
                                positions, velocities)  # fmt: skip
    with pytest.raises(ValueError, match="positions: expected 3 x 2"):
        writer.add_joint_trajectory(ARM_TRAJECTORY_TOPIC, 3.0, joints, [0.0, 0.8, 1.75],
                                    positions[:, :1], velocities)  # fmt: skip
    with pytest.raises(ValueError, match="times_from_start: expected times from 0 on, rising"):
        writer.add_joint_trajectory(ARM_TRAJECTORY_TOPIC, 3.0, joints, [0.0, 0.8, 0.8],
                                    positions, velocities)  # fmt: skip
    writer.close()
    with RosBag(path) as bag:
        assert bag.topics()[ARM_TRAJECTORY_TOPIC] == ("trajectory_msgs/msg/JointTrajectory", 1)
        (message,) = bag.messages(ARM_TRAJECTORY_TOPIC)
    assert stamp_seconds(message.header.stamp) == pytest.approx(2.5)
    assert list(message.joint_names) == joints
    times = [stamp_seconds(point.time_from_start) for point in message.points]
    assert times == pytest.approx([0.0, 0.8, 1.75])
    np.testing.assert_allclose([point.positions for point in message.points], positions)
    np.testing.assert_allclose([point.velocities for point in message.points], velocities)


def test_the_recorder_writes_each_motion_the_robot_starts_once_per_controller(tmp_path):
    """The robot's commanded motions: each on the controllers of the joints it moves (the arm
    and the omni base here), stamped when it started, never written twice."""
    path = _bag_path(tmp_path, "ros2")
    writer = RosBagWriter(path, "ros2", CAMERA)
    recorder = RosBagRecorder(writer, PERIOD, COMMANDED_JOINTS)
    simulator = Simulator(recorder)
    context = simulator.get_mutable_context()
    times = np.array([0.0, 0.5, 1.0])
    end = np.zeros(len(MODEL_JOINTS))
    end[[MODEL_JOINTS.index("base_x_joint"), MODEL_JOINTS.index("arm_lift_joint")]] = 0.3, 0.2
    carry = JointTrajectory("carry", 0.05, times, np.outer(times, end), np.tile(end, (3, 1)))
    recorder.GetInputPort(interface.COMMANDED_TRAJECTORIES).FixValue(context, (carry,))
    for time in (0.0, 0.1, 0.2):
        _fix_inputs(recorder, context, time, np.zeros(2 * len(COMMANDED_JOINTS)))
        simulator.AdvanceTo(time)
    writer.close()
    with RosBag(path) as bag:
        (arm,) = bag.messages(ARM_TRAJECTORY_TOPIC)
        (base,) = bag.messages(BASE_TRAJECTORY_TOPIC)
    assert stamp_seconds(arm.header.stamp) == pytest.approx(0.05)
    assert list(base.joint_names) == ["odom_x", "odom_y", "odom_t"]
    np.testing.assert_allclose(base.points[-1].positions, [0.3, 0.0, 0.0])
    assert arm.joint_names[0] == "arm_lift_joint" and arm.points[-1].positions[0] == 0.2


def test_an_aborted_bag_leaves_nothing_behind(tmp_path):
    path = tmp_path / "run"
    writer = RosBagWriter(path, "ros2", CAMERA)
    writer.write_settings(0.0, {"simulation": {"seed": 0}})
    writer.abort()
    assert list(tmp_path.iterdir()) == []


def _refused(capsys, argv: list[str]) -> str:
    code = main(argv)
    captured = capsys.readouterr()
    assert code == 2 and captured.out == "", captured
    return captured.err.strip()


def test_record_paths_are_checked_before_anything_runs(tmp_path, capsys):
    scenario, replay = str(SCENARIOS / "point_left.yaml"), str(tmp_path / "never.html")
    run = ["run", scenario, "--html", replay, "--record"]
    assert _refused(capsys, [*run, str(tmp_path / "x"), "--record-format", "ros1"]) == (
        f"error: --record: expected a path ending in .bag for ros1, got {str(tmp_path / 'x')!r}"
    )
    existing = tmp_path / "old.bag"
    existing.write_text("")
    assert _refused(capsys, [*run, str(existing), "--record-format", "ros1"]) == (
        f"error: --record: expected a new .bag file, {str(existing)!r} exists"
    )
    full = tmp_path / "full"
    (full / "a").mkdir(parents=True)
    assert _refused(capsys, [*run, str(full), "--record-format", "ros2"]) == (
        f"error: --record: expected a new or empty directory, {str(full)!r} is not"
    )
    assert not (tmp_path / "never.html").exists()

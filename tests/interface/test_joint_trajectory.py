"""JointTrajectory: a planned motion split over the HSR's trajectory controllers."""

from __future__ import annotations

import json

import numpy as np

from hsr_handover.hsr import COMMANDED_JOINTS, HEAD_JOINTS
from hsr_handover.interface.joint_trajectory import (
    ARM_CONTROLLER,
    BASE_CONTROLLER,
    MODEL_JOINTS,
    JointTrajectory,
)


def _trajectory(moved: dict[str, float]) -> JointTrajectory:
    """A 1 s motion from 0 moving the named joints by the given amounts, at 3 times."""
    times = np.array([0.0, 0.5, 1.0])
    end = np.array([moved.get(joint, 0.0) for joint in MODEL_JOINTS])
    positions = np.outer(times, end)
    return JointTrajectory("carry", 12.5, times, positions, np.tile(end, (3, 1)))


def test_the_model_joints_are_the_commanded_ones_but_the_heads():
    assert MODEL_JOINTS == tuple(j for j in COMMANDED_JOINTS if j not in HEAD_JOINTS)


def test_each_controller_gets_its_joints_by_the_hsrs_names_and_only_if_they_move():
    commands = _trajectory({"arm_lift_joint": 0.2, "base_yaw_joint": 0.5}).for_controllers()
    by_topic = {topic: (names, positions) for topic, names, positions, _ in commands}
    assert set(by_topic) == {ARM_CONTROLLER, BASE_CONTROLLER}
    names, positions = by_topic[BASE_CONTROLLER]
    assert names == ("odom_x", "odom_y", "odom_t")
    np.testing.assert_allclose(positions[-1], [0.0, 0.0, 0.5])
    names, positions = by_topic[ARM_CONTROLLER]
    assert names[0] == "arm_lift_joint" and len(names) == 5
    np.testing.assert_allclose(positions[:, 0], [0.0, 0.1, 0.2])
    arm_only = _trajectory({"wrist_flex_joint": -0.3}).for_controllers()
    assert [topic for topic, *_ in arm_only] == [ARM_CONTROLLER]
    assert _trajectory({}).for_controllers() == []


def test_as_json_is_plain_json_with_times_positions_and_velocities():
    written = json.loads(json.dumps(_trajectory({"arm_flex_joint": -1.0}).as_json()))
    assert written["name"] == "carry" and written["start_s"] == 12.5
    (arm,) = written["controllers"]
    assert arm["topic"] == ARM_CONTROLLER and arm["time_from_start_s"] == [0.0, 0.5, 1.0]
    assert np.shape(arm["positions"]) == (3, 5) and np.shape(arm["velocities"]) == (3, 5)
    assert arm["positions"][-1][arm["joint_names"].index("arm_flex_joint")] == -1.0

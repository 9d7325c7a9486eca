"""The robot's start configuration, from the scenario's robot section."""

from __future__ import annotations

from hsr_handover.hsr import BASE_JOINTS, GRIPPER_MIMIC_JOINT, TORSO_JOINT
from hsr_handover.scenario.schema import Scenario, ScenarioError


def robot_start_positions(scenario: Scenario) -> dict[str, float]:
    """The robot's start configuration by actuated joint name: base pose plus the posture."""
    for name in scenario.robot.joints:
        if name in BASE_JOINTS:
            expected = "the base pose under robot.base_pose, not as a joint"
        elif name in (TORSO_JOINT, GRIPPER_MIMIC_JOINT):
            expected = "an actuated joint; this one follows its partner by mimic"
        else:
            continue
        raise ScenarioError(scenario.source, f"robot.joints.{name}", f"expected {expected}")
    x, y, yaw = scenario.robot.base_pose
    return {**dict(zip(BASE_JOINTS, (x, y, yaw), strict=True)), **scenario.robot.joints}

"""Build the robot: what runs on the HSR, as a Diagram of its own (DESIGN §2).

Its inputs are named after the station's sensor outputs and its outputs after the station's
command inputs (`hsr_handover.interface`), so the two connect by name. Today it perceives
(when `perception.enabled`) and holds its ready posture; intent, effectivity, planning and the
handover supervisor go here.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from pydrake.systems.framework import Diagram, DiagramBuilder
from pydrake.systems.primitives import ConstantVectorSource

from hsr_handover import interface
from hsr_handover.hsr import COMMANDED_JOINTS, FINGER_PER_OPENING, GRIPPER_JOINT
from hsr_handover.robot.perception import PERCEPTION_OUTPUTS, add_perception
from hsr_handover.scenario import Scenario, robot_start_positions


@dataclasses.dataclass
class Robot:
    """The built robot: `diagram`, and the names of its perception outputs (empty when
    perception is off)."""

    diagram: Diagram
    perception_outputs: tuple[str, ...]


def ready_command(scenario: Scenario) -> tuple[np.ndarray, float]:
    """The ready posture as commands: [q_d; v_d] of COMMANDED_JOINTS and the gripper opening."""
    start = robot_start_positions(scenario)
    q = np.array([start.get(name, 0.0) for name in COMMANDED_JOINTS])
    return np.concatenate([q, np.zeros_like(q)]), start.get(GRIPPER_JOINT, 0.0) / FINGER_PER_OPENING


def build_robot(scenario: Scenario) -> Robot:
    """The robot's diagram from the scenario's robot, camera and perception settings."""
    builder = DiagramBuilder()
    state, opening = ready_command(scenario)
    posture = builder.AddNamedSystem("ready_posture", ConstantVectorSource(state))
    gripper = builder.AddNamedSystem("ready_gripper", ConstantVectorSource([opening]))
    builder.ExportOutput(posture.get_output_port(), interface.HSR_DESIRED_STATE)
    builder.ExportOutput(gripper.get_output_port(), interface.GRIPPER_DESIRED_OPENING)
    outputs: tuple[str, ...] = ()
    if scenario.perception.enabled:
        add_perception(builder, scenario)
        outputs = PERCEPTION_OUTPUTS
    diagram = builder.Build()
    diagram.set_name("robot")
    return Robot(diagram, outputs)

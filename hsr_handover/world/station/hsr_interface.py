"""The HSR's command inputs and joint sensors on the station's boundary, as linear maps.

The plant's PD controllers take [q_d; v_d] over every actuator, the gripper's finger among
them; the robot commands `COMMANDED_JOINTS` and a fingertip opening instead, and reads the same
joints back. Both directions are constant selection matrices, Drake's MatrixGain (in, over
the commands stacked by a Multiplexer, with `RequiredInputs` naming a command left
unconnected). The wrist's force-torque sensor reads the plant's reaction at the hand's mount.
"""

from __future__ import annotations

import numpy as np
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import ModelInstanceIndex
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import MatrixGain, Multiplexer

from hsr_handover.hsr import (
    COMMANDED_JOINTS,
    FINGER_PER_OPENING,
    GRIPPER_JOINT,
    WRIST_SENSOR_JOINT,
    actuated_joint_names,
)
from hsr_handover.interface import (
    GRIPPER_DESIRED_OPENING,
    GRIPPER_OPENING_MEASURED,
    HSR_DESIRED_STATE,
    HSR_STATE_MEASURED,
    HSR_WRIST_WRENCH_MEASURED,
)
from hsr_handover.systems.required_inputs import RequiredInputs
from hsr_handover.world.systems.wrist_force_sensor import WristForceSensor


def command_matrix(plant: MultibodyPlant, robot: ModelInstanceIndex) -> np.ndarray:
    """D with plant desired state = D @ [q_d; v_d of COMMANDED_JOINTS; opening]."""
    actuated = actuated_joint_names(plant, robot)
    n, m = len(COMMANDED_JOINTS), len(actuated)
    D = np.zeros((2 * m, 2 * n + 1))
    for row, name in enumerate(actuated):
        if name == GRIPPER_JOINT:
            D[row, 2 * n] = FINGER_PER_OPENING
            continue
        column = COMMANDED_JOINTS.index(name)
        D[row, column] = D[m + row, n + column] = 1.0
    return D


def _instance_rows(plant: MultibodyPlant, robot: ModelInstanceIndex, name: str) -> tuple[int, int]:
    """Rows of a joint's position and velocity in the instance's state output [q; v]."""
    joint = plant.GetJointByName(name, robot)
    positions = plant.GetPositionsFromArray(robot, np.arange(plant.num_positions()))
    velocities = plant.GetVelocitiesFromArray(robot, np.arange(plant.num_velocities()))
    q_row = int(np.flatnonzero(positions == joint.position_start())[0])
    v_row = int(np.flatnonzero(velocities == joint.velocity_start())[0])
    return q_row, len(positions) + v_row


def measurement_matrices(
    plant: MultibodyPlant, robot: ModelInstanceIndex
) -> tuple[np.ndarray, np.ndarray]:
    """(S, G): [q; v of COMMANDED_JOINTS] = S @ x and [opening] = G @ x, for the instance
    state x."""
    n, size = len(COMMANDED_JOINTS), plant.num_multibody_states(robot)
    S = np.zeros((2 * n, size))
    for index, name in enumerate(COMMANDED_JOINTS):
        q_row, v_row = _instance_rows(plant, robot, name)
        S[index, q_row] = S[n + index, v_row] = 1.0
    G = np.zeros((1, size))
    G[0, _instance_rows(plant, robot, GRIPPER_JOINT)[0]] = 1.0 / FINGER_PER_OPENING
    return S, G


def add_hsr_interface(
    builder: DiagramBuilder, plant: MultibodyPlant, robot: ModelInstanceIndex
) -> None:
    """Export the HSR's command inputs and its joint and wrist sensors' outputs (names in
    `interface`).

    The command inputs have no default: a simulation with either left unconnected fails at its
    first step, naming the port, rather than holding some posture nobody asked for.
    """
    n = len(COMMANDED_JOINTS)
    inputs = ((HSR_DESIRED_STATE, 2 * n), (GRIPPER_DESIRED_OPENING, 1))
    stacked = builder.AddNamedSystem("hsr_commands", Multiplexer([size for _, size in inputs]))
    commands = builder.AddNamedSystem("hsr_command_map", MatrixGain(command_matrix(plant, robot)))
    required = builder.AddNamedSystem("hsr_commands_required", RequiredInputs(inputs))
    builder.Connect(stacked.get_output_port(), commands.get_input_port())
    builder.Connect(commands.get_output_port(), plant.get_desired_state_input_port(robot))
    for index, (name, _) in enumerate(inputs):
        builder.ExportInput(stacked.get_input_port(index), name)
        builder.ConnectInput(name, required.GetInputPort(name))
    joints, opening = measurement_matrices(plant, robot)
    for name, matrix in ((HSR_STATE_MEASURED, joints), (GRIPPER_OPENING_MEASURED, opening)):
        sensor = builder.AddNamedSystem(name, MatrixGain(matrix))
        builder.Connect(plant.get_state_output_port(robot), sensor.get_input_port())
        builder.ExportOutput(sensor.get_output_port(), name)
    joint = plant.GetJointByName(WRIST_SENSOR_JOINT, robot).index()
    wrist = builder.AddNamedSystem(HSR_WRIST_WRENCH_MEASURED, WristForceSensor(int(joint)))
    builder.Connect(plant.get_reaction_forces_output_port(), wrist.get_input_port())
    builder.ExportOutput(wrist.get_output_port(), HSR_WRIST_WRENCH_MEASURED)

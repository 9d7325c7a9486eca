"""Build the robot: what runs on the HSR, as a Diagram of its own (docs/design.md §2).

Its inputs are named after the station's sensor outputs and its outputs after the station's
command inputs (`hsr_handover.interface`), so the two connect by name. It perceives (when
`perception.enabled`), turning its head to find and frame the person (`GazeController`, with
`perception.active_gaze`), and holds its ready posture (with the gaze, raising its torso
where the objects would hide a pointing arm: `WatchingPosture`), or (when `handover.enabled`)
runs the perceiving-acting cycle: the HandoverSupervisor commands the HSR from its percepts.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from pydrake.systems.framework import Diagram, DiagramBuilder, LeafSystem
from pydrake.systems.primitives import ConstantVectorSource

from hsr_handover import interface
from hsr_handover.hsr import (
    COMMANDED_JOINTS,
    FINGER_PER_OPENING,
    GRIPPER_JOINT,
    HEAD_JOINTS,
    head_limits,
)
from hsr_handover.robot.effectivity.arm_map import load_or_build
from hsr_handover.robot.perception.active_gaze import FieldOfView
from hsr_handover.robot.perception_wiring import PERCEPTION_OUTPUTS, SensorInputs, add_perception
from hsr_handover.robot.systems.gaze_controller import GazeController
from hsr_handover.robot.systems.handover_supervisor import HandoverSupervisor
from hsr_handover.robot.systems.watching import WATCHING
from hsr_handover.robot.systems.watching_posture import WatchingPosture
from hsr_handover.scenario import Scenario, robot_start_positions

HANDOVER_OUTPUTS = ("cycle", "plan_view", WATCHING, interface.COMMANDED_TRAJECTORIES)
"""The supervisor's outputs the robot gives beside its commands, with handover on."""
GAZE_OUTPUTS = ("gaze",)  # the GazeController's, exported with perception.active_gaze
WATCH_OUTPUTS = ("watch_lift",)  # the watch-only robot's WatchingPosture's, with active gaze
WATCH_ONLY = ("point_cloud_gng", "intent_estimator")
"""The perception systems whose work serves only the watch for a request (`systems.watching`)."""


@dataclasses.dataclass
class Robot:
    """The built robot: `diagram`, and the names of its perception and handover outputs (empty
    when they are off)."""

    diagram: Diagram
    perception_outputs: tuple[str, ...]


def ready_command(scenario: Scenario) -> tuple[np.ndarray, float]:
    """The ready posture as commands: [q_d; v_d] of COMMANDED_JOINTS and the gripper opening."""
    start = robot_start_positions(scenario)
    q = np.array([start.get(name, 0.0) for name in COMMANDED_JOINTS])
    return np.concatenate([q, np.zeros_like(q)]), start.get(GRIPPER_JOINT, 0.0) / FINGER_PER_OPENING


def _feed_supervisor(
    builder: DiagramBuilder, inputs: SensorInputs, supervisor: HandoverSupervisor
) -> None:
    """The supervisor reads the joint and wrist sensors (exported inputs, shared with
    perception when it reads them) and the perception systems' outputs."""
    for sensor in (
        interface.HSR_STATE_MEASURED,
        interface.GRIPPER_OPENING_MEASURED,
        interface.HSR_WRIST_WRENCH_MEASURED,
    ):
        inputs.feed(sensor, supervisor.GetInputPort(sensor))
    for port, system, output in (
        ("intent", "intent_estimator", "intent"),
        ("perceived_scene", "perceived_scene_estimator", "scene"),
        ("skeleton", "skeleton_lifter", "skeleton"),
        ("detections", "object_detector", "detections"),
    ):
        source = builder.GetSubsystemByName(system).GetOutputPort(output)
        builder.Connect(source, supervisor.GetInputPort(port))
    # What serves only the watch rests while the robot acts.
    for system in WATCH_ONLY:
        watching = builder.GetSubsystemByName(system).GetInputPort(WATCHING)
        builder.Connect(supervisor.GetOutputPort(WATCHING), watching)


def _add_gaze(builder: DiagramBuilder, inputs: SensorInputs, scenario: Scenario) -> LeafSystem:
    """The GazeController, fed the lifted skeleton, the detections and what attention selects,
    the camera's pose and the joint sensors; it starts from the start posture's head."""
    start = robot_start_positions(scenario)
    view = FieldOfView.of(scenario.camera.pinhole())
    head = tuple(start.get(joint, 0.0) for joint in HEAD_JOINTS)
    gaze = builder.AddNamedSystem("gaze_controller", GazeController(view, head_limits(), head))
    for name, system, output in (("skeleton", "skeleton_lifter", "skeleton"),
                                 ("detections", "object_detector", "detections")):  # fmt: skip
        builder.Connect(builder.GetSubsystemByName(system).GetOutputPort(output),
                        gaze.GetInputPort(name))  # fmt: skip
    attention = builder.GetSubsystemByName("attention_focus").GetOutputPort("attention")
    builder.Connect(attention, gaze.GetInputPort("attention"))
    inputs.feed(interface.CAMERA_POSE, gaze.GetInputPort("camera_pose"))
    inputs.feed(interface.HSR_STATE_MEASURED, gaze.GetInputPort(interface.HSR_STATE_MEASURED))
    (name,) = GAZE_OUTPUTS
    builder.ExportOutput(gaze.GetOutputPort(name), name)
    return gaze


def _add_watching_posture(
    builder: DiagramBuilder, inputs: SensorInputs, gaze: LeafSystem, state: np.ndarray
) -> LeafSystem:
    """The watch-only robot's posture: `state`, the head the gaze's, the torso raised where
    the objects would hide a pointing arm."""
    posture = builder.AddNamedSystem("ready_posture", WatchingPosture(state))
    builder.Connect(gaze.GetOutputPort("head_command"), posture.GetInputPort("head_command"))
    for name, system, output in (("skeleton", "skeleton_lifter", "skeleton"),
                                 ("scene", "perceived_scene_estimator", "scene")):  # fmt: skip
        builder.Connect(builder.GetSubsystemByName(system).GetOutputPort(output),
                        posture.GetInputPort(name))  # fmt: skip
    inputs.feed(interface.HSR_STATE_MEASURED, posture.GetInputPort(interface.HSR_STATE_MEASURED))
    (name,) = WATCH_OUTPUTS
    builder.ExportOutput(posture.GetOutputPort(name), name)
    return posture


def build_robot(scenario: Scenario) -> Robot:
    """The robot's diagram from the scenario's robot, camera and perception settings."""
    builder = DiagramBuilder()
    state, opening = ready_command(scenario)
    outputs: tuple[str, ...] = ()
    gaze = None
    if scenario.perception.enabled:
        inputs = add_perception(builder, scenario)
        outputs = PERCEPTION_OUTPUTS
        if scenario.perception.active_gaze:
            gaze = _add_gaze(builder, inputs, scenario)
            outputs += GAZE_OUTPUTS
    if scenario.handover.enabled:
        supervisor = builder.AddNamedSystem(
            "handover_supervisor",
            # The intent's params were checked with the perception's.
            HandoverSupervisor(load_or_build()[0], state, opening, scenario.intent.params()),
        )
        _feed_supervisor(builder, inputs, supervisor)
        if gaze is not None:
            builder.Connect(gaze.GetOutputPort("head_command"),
                            supervisor.GetInputPort("head_command"))  # fmt: skip
        commands = (supervisor.GetOutputPort(interface.HSR_DESIRED_STATE),
                    supervisor.GetOutputPort(interface.GRIPPER_DESIRED_OPENING))  # fmt: skip
        for name in HANDOVER_OUTPUTS:
            builder.ExportOutput(supervisor.GetOutputPort(name), name)
        outputs += HANDOVER_OUTPUTS
    else:
        if gaze is not None:
            posture = _add_watching_posture(builder, inputs, gaze, state)
            outputs += WATCH_OUTPUTS
        else:
            posture = builder.AddNamedSystem("ready_posture", ConstantVectorSource(state))
        gripper = builder.AddNamedSystem("ready_gripper", ConstantVectorSource([opening]))
        commands = (posture.get_output_port(0), gripper.get_output_port())  # desired state first
    builder.ExportOutput(commands[0], interface.HSR_DESIRED_STATE)
    builder.ExportOutput(commands[1], interface.GRIPPER_DESIRED_OPENING)
    diagram = builder.Build()
    diagram.set_name("robot")
    return Robot(diagram, outputs)

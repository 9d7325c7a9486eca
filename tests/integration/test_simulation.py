"""The station and the robot side by side: joined by name, and the robot reads no ground truth."""

from __future__ import annotations

import numpy as np
import pytest
from pydrake.systems.framework import (
    Diagram,
    DiagramBuilder,
    InputPortIndex,
    LeafSystem,
    OutputPortIndex,
    System,
)
from pydrake.systems.primitives import ConstantVectorSource

from hsr_handover import interface
from hsr_handover.hsr import COMMANDED_JOINTS
from hsr_handover.robot.builder import (
    GAZE_OUTPUTS,
    WATCH_ONLY,
    WATCH_OUTPUTS,
    build_robot,
    ready_command,
)
from hsr_handover.robot.perception_wiring import PERCEPTION_OUTPUTS
from hsr_handover.robot.systems.watching import WATCHING
from hsr_handover.scenario import load_scenario
from hsr_handover.simulation import build_simulation, connect_robot
from hsr_handover.world.station import build_station
from tests.paths import SCENARIOS


class _Reader(LeafSystem):
    """A leaf with one vector input, standing in for a robot system."""

    def __init__(self, size: int = 1):
        super().__init__()
        self.DeclareVectorInputPort("anything", size)


@pytest.fixture(scope="module")
def perceiving():
    scenario = load_scenario(SCENARIOS / "attention_shift.yaml")
    assert scenario.perception.enabled
    return build_simulation(scenario)


def _sources(diagram: Diagram) -> dict[tuple[int, int], tuple[System, int]]:
    """Each connected input (system id, port index) of `diagram`'s own subsystems, mapped to
    the output that feeds it."""
    return {
        (destination.GetSystemPathname(), int(port)): (source, int(output))
        for (destination, port), (source, output) in diagram.connection_map().items()
    }


def _upstream_names(root: Diagram, system: System, port: int) -> list[str]:
    """The names of every output and input port on the way from a leaf system's input up
    through exported diagram inputs to the output that feeds it, with the leaf source's."""
    names, parent = [], _parent_of(root, system)
    while parent is not None:
        source = _sources(parent).get((system.GetSystemPathname(), port))
        if source is not None:
            return names + _downstream_output_names(*source)
        exported = _exported_input(parent, system, port)
        if exported is None:
            return names  # fixed or unconnected: reads nothing
        names.append(parent.get_input_port(exported).get_name())
        system, port, parent = parent, exported, _parent_of(root, parent)
    return names


def _downstream_output_names(system: System, port: int) -> list[str]:
    """An output port's name and, inside a diagram, the names down to the leaf output."""
    names = [system.get_output_port(port).get_name()]
    while isinstance(system, Diagram):
        locator = system.get_output_port_locator(OutputPortIndex(port))
        system, port = locator[0], int(locator[1])
        names.append(system.get_output_port(port).get_name())
    return names


def _exported_input(diagram: Diagram, system: System, port: int) -> int | None:
    for index in range(diagram.num_input_ports()):
        for inner, inner_port in diagram.GetInputPortLocators(InputPortIndex(index)):
            if inner.GetSystemPathname() == system.GetSystemPathname() and int(inner_port) == port:
                return index
    return None


def _parent_of(root: Diagram, system: System) -> Diagram | None:
    for candidate in _diagrams(root):
        if any(s.GetSystemPathname() == system.GetSystemPathname() for s in candidate.GetSystems()):
            return candidate
    return None


def _diagrams(diagram: Diagram) -> list[Diagram]:
    inner = [s for s in diagram.GetSystems() if isinstance(s, Diagram)]
    return [diagram, *(d for child in inner for d in _diagrams(child))]


def _leaves(diagram: Diagram) -> list[System]:
    leaves = []
    for system in diagram.GetSystems():
        leaves += _leaves(system) if isinstance(system, Diagram) else [system]
    return leaves


def test_no_robot_system_reads_a_truth_port(perceiving):
    root, robot = perceiving.diagram, perceiving.robot.diagram
    read = {}
    for leaf in _leaves(robot):
        for port in range(leaf.num_input_ports()):
            names = _upstream_names(root, leaf, port)
            read[f"{leaf.get_name()}.{leaf.get_input_port(port).get_name()}"] = names
    assert len(read) >= 15  # the walk saw the perception systems' inputs
    truth = {key: names for key, names in read.items()
             if any(name.startswith(interface.TRUTH_PREFIX) for name in names)}  # fmt: skip
    assert truth == {}
    seen = {name for names in read.values() for name in names}
    assert {"camera_depth_image", "skeleton_keypoints", "camera_image_time"} <= seen


def test_the_walk_would_see_a_robot_reading_truth(perceiving):
    """The check above is real: wire a probe inside a robot-like diagram to a truth output."""
    scenario = perceiving.station.scenario
    builder = DiagramBuilder()
    station = builder.AddSystem(build_station(scenario).diagram)
    truth = station.GetOutputPort(interface.TRUTH_PERSON_STATE)
    inner = DiagramBuilder()
    reader = inner.AddNamedSystem("reader", _Reader(truth.size()))
    inner.ExportInput(reader.get_input_port(), "person")
    cheat = builder.AddSystem(inner.Build())
    builder.Connect(truth, cheat.get_input_port())
    root = builder.Build()
    leaf = cheat.GetSubsystemByName("reader")
    assert interface.TRUTH_PERSON_STATE in _upstream_names(root, leaf, 0)


def test_connect_robot_refuses_a_truth_input():
    scenario = load_scenario(SCENARIOS / "point_left.yaml")
    robot_builder = DiagramBuilder()
    source = robot_builder.AddSystem(ConstantVectorSource([0.0]))
    robot_builder.ExportOutput(source.get_output_port(), interface.HSR_DESIRED_STATE)
    reader = robot_builder.AddSystem(_Reader())
    robot_builder.ExportInput(reader.get_input_port(), interface.TRUTH_BODY_POSES)
    robot = robot_builder.Build()
    builder = DiagramBuilder()
    station = builder.AddSystem(build_station(scenario).diagram)
    builder.AddSystem(robot)
    with pytest.raises(ValueError, match="truth_body_poses.*may not read truth"):
        connect_robot(builder, station, robot)


def test_robot_diagram_reads_sensors_and_commands_its_ready_posture():
    scenario = load_scenario(SCENARIOS / "attention_shift.yaml")
    robot = build_robot(scenario)
    diagram = robot.diagram
    inputs = {diagram.get_input_port(i).get_name() for i in range(diagram.num_input_ports())}
    outputs = {diagram.get_output_port(i).get_name() for i in range(diagram.num_output_ports())}
    assert inputs <= set(interface.SENSORS) and "skeleton_keypoints" in inputs
    expected = set(interface.COMMANDS) | set(PERCEPTION_OUTPUTS) | set(GAZE_OUTPUTS)
    assert outputs == expected | set(WATCH_OUTPUTS)  # the watch-only robot with active gaze
    context = diagram.CreateDefaultContext()
    state = diagram.GetOutputPort(interface.HSR_DESIRED_STATE).Eval(context)
    expected, opening = ready_command(scenario)
    np.testing.assert_array_equal(state, expected)
    n = len(COMMANDED_JOINTS)
    tilt = COMMANDED_JOINTS.index("head_tilt_joint")
    assert state[tilt] == scenario.robot.joints.get("head_tilt_joint", 0.0)
    assert not state[n:].any()
    assert diagram.GetOutputPort(interface.GRIPPER_DESIRED_OPENING).Eval(context)[0] == opening


def test_robot_without_perception_only_commands():
    scenario = load_scenario(SCENARIOS / "point_left.yaml")
    scenario.perception.enabled = False
    diagram = build_robot(scenario).diagram
    assert diagram.num_input_ports() == 0 and diagram.num_output_ports() == 2


@pytest.mark.parametrize("handover", [True, False])
def test_the_watch_only_perception_rests_by_the_supervisors_watching_output(handover):
    scenario = load_scenario(SCENARIOS / "demo.yaml")
    scenario.handover.enabled = handover
    diagram = build_robot(scenario).diagram
    sources = _sources(diagram)
    for name in WATCH_ONLY:
        system = diagram.GetSubsystemByName(name)
        port = system.GetInputPort(WATCHING).get_index()
        source = sources.get((system.GetSystemPathname(), int(port)))
        if not handover:
            assert source is None  # unconnected: it always works
            continue
        feeder, output = source
        assert feeder.get_name() == "handover_supervisor"
        assert feeder.get_output_port(output).get_name() == WATCHING

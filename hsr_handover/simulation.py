"""The station and the robot side by side, joined by ports: build the whole Diagram and run it.

    station (the world)  --sensor outputs-->  robot  --commands-->  station

`connect_robot` joins every robot input to the station output of the same name and every
command the robot gives to the station input of the same name; it refuses a robot input named
`truth_*`.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
from pydrake.common import RandomGenerator
from pydrake.geometry import Meshcat
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import Context, Diagram, DiagramBuilder, EventStatus

from hsr_handover import interface
from hsr_handover.error_text import first_line
from hsr_handover.hsr import COMMANDED_JOINTS, GRIPPER_KEY
from hsr_handover.interface.joint_trajectory import JointTrajectory
from hsr_handover.recording.rgbd_session import PERCEPTION_NOT_IN_SESSION, start_session
from hsr_handover.recording.ros_bag_recorder import RosBagRecorder
from hsr_handover.recording.ros_bag_writer import RosBagWriter
from hsr_handover.recording.ros_messages import ROS1, ROS2
from hsr_handover.recording.session_recorder import SessionRecorder
from hsr_handover.replay.cycle_visualizer import CycleVisualizer
from hsr_handover.replay.graph_visualizer import add_graph_visualizer
from hsr_handover.replay.meshcat_replay import (
    frame_view,
    make_local_meshcat,
    start_recording,
    write_replay,
)
from hsr_handover.robot.builder import Robot, build_robot
from hsr_handover.robot.handover.cycle_types import CycleRecord
from hsr_handover.robot.intent import IntentState
from hsr_handover.robot.systems.watching import WATCHING
from hsr_handover.scenario import Scenario
from hsr_handover.systems.port_types import check_abstract_connections
from hsr_handover.world.station import Station, build_station, check_initial_clearance

ProgressCallback = Callable[[float, float], None]
CYCLE = "cycle"  # the robot's output of its handover cycle
AFTER_CYCLE_S = 2.0  # s a run goes on once the handover cycle has ended
CHUNK_S = 0.1
"""s simulated between checks for the cycle's end and progress reports: a run stops within
this of AFTER_CYCLE_S (100 chunks of a 48 s trial overshot it by up to 0.48 s)."""
FOLDER = "folder"
RECORD_FORMATS = (FOLDER, ROS2, ROS1)
"""How `record` is written: a session folder (`rgbd_session`), a ROS 2 MCAP bag folder or a
ROS 1 .bag file (`ros_bag_writer`)."""


@dataclasses.dataclass
class Simulation:
    """The whole Diagram with the station and the robot inside it."""

    diagram: Diagram
    station: Station
    robot: Robot
    bag: RosBagWriter | None = None  # the bag being recorded, closed when the run ends

    def station_context(self, root: Context) -> Context:
        return self.station.diagram.GetMyContextFromRoot(root)

    def robot_context(self, root: Context) -> Context:
        return self.robot.diagram.GetMyContextFromRoot(root)

    def measured_positions(self, root: Context) -> dict[str, float]:
        """Where the robot's joint sensors say it is: the commanded joints by name and
        "gripper", the fingertips' opening (m). Sensor outputs, not truth."""
        station, context = self.station.diagram, self.station_context(root)
        state = station.GetOutputPort(interface.HSR_STATE_MEASURED).Eval(context)
        opening = station.GetOutputPort(interface.GRIPPER_OPENING_MEASURED).Eval(context)
        joints = dict(zip(COMMANDED_JOINTS, state[: len(COMMANDED_JOINTS)], strict=True))
        return {**joints, GRIPPER_KEY: float(opening[0])}


def connect_robot(builder: DiagramBuilder, station: Diagram, robot: Diagram) -> None:
    """Connect `robot`'s inputs to `station`'s outputs and the robot's commands to the
    station's command inputs, by name (both already added to `builder`)."""
    for index in range(robot.num_input_ports()):
        port = robot.get_input_port(index)
        if port.get_name().startswith(interface.TRUTH_PREFIX):
            raise ValueError(f"robot input {port.get_name()!r}: the robot may not read truth")
        builder.Connect(station.GetOutputPort(port.get_name()), port)
    for name in interface.COMMANDS:
        builder.Connect(robot.GetOutputPort(name), station.GetInputPort(name))


def add_station_and_robot(
    builder: DiagramBuilder, scenario: Scenario, meshcat: Meshcat | None = None
) -> tuple[Station, Robot]:
    """Add the station and the robot for `scenario` to `builder`, connected; with `meshcat`,
    the world and the robot's scene map are drawn there. For diagrams that add more (a test's
    probe, an experiment's logger); `build_simulation` is the usual entry."""
    station = build_station(scenario, meshcat)
    robot = build_robot(scenario)
    builder.AddSystem(station.diagram)
    builder.AddSystem(robot.diagram)
    connect_robot(builder, station.diagram, robot.diagram)
    if meshcat is not None and "gng_graph" in robot.perception_outputs:
        output = robot.diagram.GetOutputPort
        watching = output(WATCHING) if WATCHING in robot.perception_outputs else None
        add_graph_visualizer(builder, output("gng_graph"), meshcat, watching)
    if meshcat is not None and "plan_view" in robot.perception_outputs:
        _add_cycle_visualizer(builder, robot.diagram, meshcat)
    return station, robot


def _add_cycle_visualizer(builder: DiagramBuilder, robot: Diagram, meshcat: Meshcat) -> None:
    """What the robot thinks over the run (rays, target, plans, maps), in the replay: each of
    the visualiser's inputs from the robot's output of its name."""
    visualizer = builder.AddNamedSystem("cycle_visualizer", CycleVisualizer(meshcat))
    for port in map(visualizer.get_input_port, range(visualizer.num_input_ports())):
        builder.Connect(robot.GetOutputPort(port.get_name()), port)


def build_simulation(
    scenario: Scenario,
    meshcat: Meshcat | None = None,
    record: Path | None = None,
    record_format: str = FOLDER,
) -> Simulation:
    """The station and the robot for `scenario`, connected, as one Diagram; with `record`, the
    robot's sensors are written there frame by frame, as an RGB-D session folder or a ROS bag
    (`record_format`, one of RECORD_FORMATS; a bag is complete once `Simulation.bag` is
    closed)."""
    builder = DiagramBuilder()
    station, robot = add_station_and_robot(builder, scenario, meshcat)
    bag = None
    if record is not None and record_format == FOLDER:
        _add_session_recorder(builder, station.diagram, scenario, record)
    elif record is not None:
        bag = _add_bag_recorder(builder, station.diagram, robot.diagram, scenario, record,
                                record_format)  # fmt: skip
    try:
        diagram = builder.Build()
        diagram.set_name("hsr_handover")
        check_abstract_connections(diagram)
    except BaseException:
        if bag is not None:
            bag.abort()
        raise
    return Simulation(diagram, station, robot, bag)


def session_settings(scenario: Scenario) -> dict:
    """What a recorded session keeps of the scenario it was recorded in: the robot's perception
    and intent settings and the seed, as a scenario file's sections
    (`offline_intent.perceive` reads them)."""
    perception = dataclasses.asdict(scenario.perception)
    for key in PERCEPTION_NOT_IN_SESSION:
        perception.pop(key)
    return {
        "simulation": {"seed": scenario.simulation.seed},
        "camera": {"rate_hz": scenario.camera.rate_hz},
        "perception": perception,
        "intent": dataclasses.asdict(scenario.intent),
    }


def _add_session_recorder(
    builder: DiagramBuilder, station: Diagram, scenario: Scenario, directory: Path
) -> None:
    """Record the camera's frames and the pose detector's skeletons (`rgbd_session`), with the
    settings the robot perceives with, for `offline_intent.perceive`."""
    start_session(directory, scenario.camera.pinhole(), session_settings(scenario))
    recorder = builder.AddNamedSystem(
        "session_recorder", SessionRecorder(directory, 1.0 / scenario.camera.rate_hz)
    )
    for index in range(recorder.num_input_ports()):
        port = recorder.get_input_port(index)
        builder.Connect(station.GetOutputPort(port.get_name()), port)


def _add_bag_recorder(
    builder: DiagramBuilder,
    station: Diagram,
    robot: Diagram,
    scenario: Scenario,
    path: Path,
    version: str,
) -> RosBagWriter:
    """Record the robot's sensors into a ROS bag (`ros_bag_writer`) with the settings the robot
    perceives with, and its planned motions when it plans any; the writer, for the run to
    close."""
    if version not in (ROS1, ROS2):
        raise ValueError(
            f"record_format: expected one of {', '.join(RECORD_FORMATS)}, got {version!r}"
        )
    writer = RosBagWriter(path, version, scenario.camera.pinhole())
    writer.write_settings(0.0, session_settings(scenario))
    recorder = builder.AddNamedSystem(
        "ros_bag_recorder",
        RosBagRecorder(writer, 1.0 / scenario.camera.rate_hz, COMMANDED_JOINTS),
    )
    for index in range(recorder.num_input_ports()):
        port = recorder.get_input_port(index)
        if port.get_name() != interface.COMMANDED_TRAJECTORIES:
            builder.Connect(station.GetOutputPort(port.get_name()), port)
        elif robot.HasOutputPort(port.get_name()):
            builder.Connect(robot.GetOutputPort(port.get_name()), port)
    return writer


@dataclasses.dataclass
class RunReport:
    """What a run measured: simulated and wall-clock seconds, their ratio, the replay file;
    and the simulation with its final context, for scoring against ground truth."""

    sim_time: float
    wall_time: float
    replay: Path | None
    simulation: Simulation
    context: Context
    cycle: CycleRecord | None = None  # the robot's handover cycle as it ended (handover runs)
    intent: IntentState | None = None  # what the robot recognised (runs with perception)
    person_holds: str = ""  # what the person's hand holds at the end (truth, for the report)
    person_repeated: float = math.nan  # when the person asked again for want of a response (s)
    commanded: tuple[JointTrajectory, ...] = ()  # the robot's planned motions, as it started them

    @property
    def real_time_factor(self) -> float:
        return self.sim_time / self.wall_time if self.wall_time > 0 else float("inf")


def prepare_simulation(
    scenario: Scenario,
    with_meshcat: bool,
    record: Path | None = None,
    record_format: str = FOLDER,
) -> tuple[Simulation, Meshcat | None]:
    """Build the simulation and check the world's start; returns it with its Meshcat (or
    None). With `record`, the robot's sensors are recorded there (`build_simulation`)."""
    meshcat = make_local_meshcat() if with_meshcat else None
    simulation = build_simulation(scenario, meshcat, record, record_format)
    try:
        check_initial_clearance(simulation.station)
    except BaseException:
        if simulation.bag is not None:
            simulation.bag.abort()
        raise
    return simulation, meshcat


def _scene_points(scenario: Scenario) -> np.ndarray:
    """The robot, the table and the person: the replay opens framed on their bounding box."""
    robot_xy, table, person = list(scenario.robot.base_pose[:2]), scenario.table, scenario.person
    half = float(np.hypot(*table.size)) / 2  # the table's circumscribed circle: any yaw
    cx, cy = table.center
    return np.array([
        [*robot_xy, 0.0], [*robot_xy, 1.35],  # the HSR up to its head, arm raised
        [cx - half, cy - half, 0.0], [cx + half, cy + half, table.height],
        [*person.position, 0.0], [*person.position, person.height],
    ])  # fmt: skip


def start_replay(meshcat: Meshcat, scenario: Scenario) -> None:
    """Frame the robot, the table and the person, and start recording the replay."""
    frame_view(meshcat, _scene_points(scenario), side=scenario.robot.base_pose[:2])
    start_recording(meshcat, scenario.simulation.replay_fps)


def run_scenario(
    scenario: Scenario,
    replay: Path | None = None,
    progress: ProgressCallback | None = None,
    monitor_factory: Callable[[Simulation], Callable[[Context], EventStatus]] | None = None,
    record: Path | None = None,
    after_cycle_s: float = AFTER_CYCLE_S,
    record_format: str = FOLDER,
) -> RunReport:
    """Simulate `scenario.simulation.duration` seconds, or until `after_cycle_s` after the
    handover cycle ended; write the replay HTML when asked. `monitor_factory(simulation)`
    gives a function the simulator calls after every step (an experiment's recorder); with
    `record`, the robot's sensors are written there as an RGB-D session folder or a ROS bag
    (`record_format`). A bag is completed when the run ends, and removed if it fails."""
    simulation, meshcat = prepare_simulation(scenario, replay is not None, record, record_format)
    try:
        report = _simulate(scenario, simulation, meshcat, replay, progress, monitor_factory,
                           after_cycle_s)  # fmt: skip
    except SimulationFailed:
        if simulation.bag is not None:  # what was recorded up to the failure is whole
            simulation.bag.close()
        raise
    except BaseException:
        if simulation.bag is not None:
            simulation.bag.abort()
        raise
    if simulation.bag is not None:
        simulation.bag.close()
    return report


def _simulate(
    scenario: Scenario,
    simulation: Simulation,
    meshcat: Meshcat | None,
    replay: Path | None,
    progress: ProgressCallback | None,
    monitor_factory: Callable[[Simulation], Callable[[Context], EventStatus]] | None,
    after_cycle_s: float,
) -> RunReport:
    """Run a prepared simulation (`run_scenario`)."""
    simulator = Simulator(simulation.diagram)
    if monitor_factory is not None:
        simulator.set_monitor(monitor_factory(simulation))
    simulation.diagram.SetRandomContext(
        simulator.get_mutable_context(), RandomGenerator(scenario.simulation.seed)
    )
    if meshcat is not None:
        start_replay(meshcat, scenario)
    duration = scenario.simulation.duration
    # Counted in whole chunks so the last lands on the duration itself, not a rounding error
    # short of it.
    steps = max(1, math.ceil(duration / CHUNK_S))
    start = time.perf_counter()
    simulator.Initialize()
    now, failure = 0.0, None
    for step in range(1, steps + 1):
        now = duration if step == steps else duration * step / steps
        try:
            simulator.AdvanceTo(now)
        except RuntimeError as error:  # the plant's solver gave up (NaN, no factorisation)
            now, failure = simulator.get_context().get_time(), first_line(error)
            break
        if progress is not None:
            progress(now, duration)
        if _cycle_ended(simulation, simulator.get_context(), after_cycle_s):
            break
    wall = time.perf_counter() - start
    written = write_replay(meshcat, replay) if meshcat is not None else None
    root = simulator.get_context()
    commanded = _robot_output(simulation, root, interface.COMMANDED_TRAJECTORIES) or ()
    report = RunReport(now, wall, written, simulation, root, _cycle(simulation, root),
                       _robot_output(simulation, root, "intent"), *_person(simulation, root),
                       commanded=commanded)  # fmt: skip
    if failure is not None:
        raise SimulationFailed(report, failure)
    return report


class SimulationFailed(RuntimeError):
    """The simulation could not go on (the plant's solver failed at `report.sim_time`): the
    `report` of the run up to then, its replay written, and the solver's `reason`."""

    def __init__(self, report: RunReport, reason: str):
        super().__init__(f"at {report.sim_time:.2f} s: {reason}")
        self.report, self.reason = report, reason


def _robot_output(simulation: Simulation, root: Context, name: str) -> object | None:
    """The robot's output `name` in the `root` context, None when the robot has none."""
    robot = simulation.robot.diagram
    if not robot.HasOutputPort(name):
        return None
    return robot.GetOutputPort(name).Eval(simulation.robot_context(root))


def _cycle(simulation: Simulation, root: Context) -> CycleRecord | None:
    return _robot_output(simulation, root, CYCLE)


def _cycle_ended(simulation: Simulation, root: Context, after_s: float) -> bool:
    """Whether the handover cycle ended `after_s` or more ago (nothing more happens)."""
    cycle = _cycle(simulation, root)
    if cycle is None or not cycle.over:
        return False
    return root.get_time() >= cycle.phase_times[cycle.phase.value] + after_s


def _person(simulation: Simulation, root: Context) -> tuple[str, float]:
    """What the person holds at the end, and when they asked again for want of a response."""
    station = simulation.station.diagram
    context = station.GetMyContextFromRoot(root)
    grip = station.GetOutputPort(interface.TRUTH_PERSON_GRIP).Eval(context)
    return grip, float(station.GetOutputPort(interface.TRUTH_PERSON_REPEATED_AT).Eval(context)[0])

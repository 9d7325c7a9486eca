"""Let the robot watch a scenario for a while with perception on, then read its percepts: the
start of every experiment that plans from what the robot perceives."""

from __future__ import annotations

import dataclasses

from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import Context

from hsr_handover.hsr import COMMANDED_JOINTS
from hsr_handover.scenario import Scenario
from hsr_handover.simulation import Simulation, build_simulation

LOOK_AROUND_PANS = (0.7, -0.7)  # rad of head pan: the table's ends, each side in turn
LOOK_DWELL_S = 0.9  # s at each: the pan's move (1 rad/s) and a few table fits (5 Hz)


@dataclasses.dataclass
class Watched:
    """The simulation after watching, its `simulator` (keeps the contexts alive) and `root`
    context; `percept(name)` evaluates one of the robot's perception outputs."""

    simulation: Simulation
    simulator: Simulator
    root: Context

    def percept(self, name: str):
        robot = self.simulation.robot.diagram
        return robot.GetOutputPort(name).Eval(self.simulation.robot_context(self.root))

    def measured_positions(self) -> dict[str, float]:
        return self.simulation.measured_positions(self.root)


def watch(scenario: Scenario, seconds: float, look_around: bool = False) -> Watched:
    """Simulate `scenario` for `seconds` with perception on, whatever the file says. With
    `look_around`, the head first pans to each of LOOK_AROUND_PANS for LOOK_DWELL_S (so the
    table's ends come into view), then back, before the remaining time."""
    perception = dataclasses.replace(scenario.perception, enabled=True)
    scenario = dataclasses.replace(scenario, perception=perception)
    simulation = build_simulation(scenario)
    simulator = Simulator(simulation.diagram)
    if look_around:
        _look_around(simulation, simulator)
    simulator.AdvanceTo(max(seconds, simulator.get_context().get_time()))
    return Watched(simulation, simulator, simulator.get_context())


def _look_around(simulation: Simulation, simulator: Simulator) -> None:
    """A stand-in for the supervisor's look round (issue 10): the ready posture's head pan
    stepped through LOOK_AROUND_PANS, then back to where it was."""
    posture = simulation.robot.diagram.GetSubsystemByName("ready_posture")
    context = posture.GetMyMutableContextFromRoot(simulator.get_mutable_context())
    command = posture.get_mutable_source_value(context)
    pan = COMMANDED_JOINTS.index("head_pan_joint")
    start = command.get_value()[pan]
    for angle in (*LOOK_AROUND_PANS, start):
        value = command.get_value().copy()
        value[pan] = angle
        command.set_value(value)
        simulator.AdvanceTo(simulator.get_context().get_time() + LOOK_DWELL_S)

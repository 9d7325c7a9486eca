"""Let the robot watch a scenario for a while with perception on, then read its percepts: the
start of every experiment that plans from what the robot perceives."""

from __future__ import annotations

import dataclasses

from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import Context

from hsr_handover.scenario import Scenario
from hsr_handover.simulation import Simulation, build_simulation


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


def watch(scenario: Scenario, seconds: float) -> Watched:
    """Simulate `scenario` for `seconds` with perception on, whatever the file says."""
    perception = dataclasses.replace(scenario.perception, enabled=True)
    scenario = dataclasses.replace(scenario, perception=perception)
    simulation = build_simulation(scenario)
    simulator = Simulator(simulation.diagram)
    simulator.AdvanceTo(seconds)
    return Watched(simulation, simulator, simulator.get_context())

"""Run a scenario: build the station, simulate it, and record a replay."""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable
from pathlib import Path

from pydrake.common import RandomGenerator
from pydrake.geometry import Meshcat
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import Context, EventStatus

from hsr_handover.replay import make_local_meshcat, start_recording, write_replay
from hsr_handover.scenario import Scenario
from hsr_handover.station import Station, build_station, check_initial_clearance

ProgressCallback = Callable[[float, float], None]


@dataclasses.dataclass
class RunReport:
    """What a run measured: simulated and wall-clock seconds, their ratio, the replay file;
    and the station with the final context, for scoring against ground truth."""

    sim_time: float
    wall_time: float
    replay: Path | None
    station: Station
    context: Context

    @property
    def real_time_factor(self) -> float:
        return self.sim_time / self.wall_time if self.wall_time > 0 else float("inf")


def prepare_station(scenario: Scenario, with_meshcat: bool) -> tuple[Station, Meshcat | None]:
    """Build and check the station; returns it with its Meshcat (or None)."""
    meshcat = make_local_meshcat() if with_meshcat else None
    station = build_station(scenario, meshcat)
    check_initial_clearance(station)
    return station, meshcat


def run_scenario(
    scenario: Scenario,
    replay: Path | None = None,
    progress: ProgressCallback | None = None,
    monitor_factory: Callable[[Station], Callable[[Context], EventStatus]] | None = None,
) -> RunReport:
    """Simulate `scenario.simulation.duration` seconds; write the replay HTML when asked.
    `monitor_factory(station)` gives a function the simulator calls after every step (an
    experiment's recorder)."""
    station, meshcat = prepare_station(scenario, with_meshcat=replay is not None)
    simulator = Simulator(station.diagram)
    if monitor_factory is not None:
        simulator.set_monitor(monitor_factory(station))
    station.diagram.SetRandomContext(
        simulator.get_mutable_context(), RandomGenerator(scenario.simulation.seed)
    )
    if meshcat is not None:
        start_recording(meshcat, scenario.simulation.replay_fps)
    duration = scenario.simulation.duration
    step = max(duration / 100.0, 0.02)
    start = time.perf_counter()
    simulator.Initialize()
    now = 0.0
    while now < duration - 1e-12:
        now = min(now + step, duration)
        simulator.AdvanceTo(now)
        if progress is not None:
            progress(now, duration)
    wall = time.perf_counter() - start
    written = write_replay(meshcat, replay) if meshcat is not None else None
    return RunReport(now, wall, written, station, simulator.get_context())

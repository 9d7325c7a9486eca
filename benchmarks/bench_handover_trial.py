"""Handover trial speed: wall time and real-time factor of whole handover trials (the reference
experiment's, scored as the experiment scores them), in three configurations run side by side
in the same process, one trial at a time:

- `every frame` (the baseline): the reference scenario with every perception system working
  on every camera frame (the robot builder's WATCH_ONLY emptied, so the scene map and the
  intent estimator never rest and every frame is rendered) and 2 ms plant steps;
- `2 ms step`: the scenario with 2 ms plant steps;
- `reference`: the scenario as it is (`scenarios/handover_reference.yaml`: the 3 ms default
  plant step, the camera at 30 Hz; the scene map and the intent estimator rest while the
  robot acts, and frames nobody reads are not rendered). 4 ms steps with the camera at 15 Hz
  run 1.7x faster over the 64-trial run, but a grasp slips at 4 ms and a request goes
  unrecognised at 15 Hz.

Each trial's outcome is printed beside its time: a configuration that changes the handover
shows.

    python benchmarks/bench_handover_trial.py [--trials 0 1 7 42] [--scenario FILE]

Run it on a quiet machine: it takes half a minute to a minute a trial and configuration.
"""

from __future__ import annotations

import argparse
import copy
import dataclasses
import statistics
import time
from pathlib import Path
from unittest import mock

from hsr_handover.experiments.handover.trial import run_handover_trial
from hsr_handover.experiments.handover.trials import make_trials
from hsr_handover.robot import builder as robot_builder
from hsr_handover.scenario import Scenario, load_scenario

REFERENCE = Path(__file__).resolve().parents[1] / "scenarios" / "handover_reference.yaml"
TWO_MS = {"time_step": 0.002}
"""The finer plant step (the default is 3 ms)."""


@dataclasses.dataclass(frozen=True)
class Configuration:
    settings: dict[str, float]
    every_frame: bool = False  # perception works on every frame, resting never


def _settings(scenario: Scenario) -> dict[str, float]:
    return {
        "time_step": scenario.simulation.time_step,
        "rate_hz": scenario.camera.rate_hz,
        "signals_per_frame": scenario.perception.signals_per_frame,
    }


def _with(scenario: Scenario, settings: dict[str, float]) -> Scenario:
    scenario = copy.deepcopy(scenario)
    scenario.simulation.time_step = settings["time_step"]
    scenario.camera.rate_hz = settings["rate_hz"]
    scenario.perception.signals_per_frame = int(settings["signals_per_frame"])
    return scenario


def _run(base: Scenario, index: int, configuration: Configuration) -> tuple[float, dict]:
    """One trial (index `index` of the 60-trial experiment, seed 0) in `configuration`."""
    trial = make_trials(base, max(60, index + 1), 0, 0)[index]
    trial = dataclasses.replace(trial, scenario=_with(trial.scenario, configuration.settings))
    resting = () if configuration.every_frame else robot_builder.WATCH_ONLY
    with mock.patch.object(robot_builder, "WATCH_ONLY", resting):
        start = time.perf_counter()
        row = run_handover_trial(trial)
        return time.perf_counter() - start, row


def _line(name: str, index: int, wall: float, row: dict) -> str:
    outcome = "handed over" if row["handed_over"] else row["failure"] or "refused"
    return (
        f"  {name:11s} trial {index:2d}: wall {wall:6.1f} s  simulated {row['sim_s']:5.1f} s  "
        f"real-time factor {row['sim_s'] / wall:4.2f}  {outcome}, released at "
        f"{row['released_s']:.2f} s"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, nargs="+", default=[0, 1, 7, 42])
    parser.add_argument("--scenario", type=Path, default=REFERENCE)
    args = parser.parse_args()
    base = load_scenario(args.scenario)
    configurations = {
        "every frame": Configuration(_settings(base) | TWO_MS, every_frame=True),
        "2 ms step": Configuration(_settings(base) | TWO_MS),
        "reference": Configuration(_settings(base)),
    }
    factors: dict[str, list[float]] = {name: [] for name in configurations}
    walls: dict[str, list[float]] = {name: [] for name in configurations}
    print(f"{args.scenario.name}, trials {args.trials} of the 60-trial experiment (seed 0)")
    for name, configuration in configurations.items():
        print(f"{name}: {configuration}")
    _run(base, args.trials[0], configurations["reference"])  # warm-up: caches, compiled code
    for index in args.trials:
        for name, configuration in configurations.items():
            wall, row = _run(base, index, configuration)
            factors[name].append(row["sim_s"] / wall)
            walls[name].append(wall)
            print(_line(name, index, wall, row), flush=True)
    for name in configurations:
        print(
            f"{name:11s} median wall {statistics.median(walls[name]):6.1f} s a trial, "
            f"real-time factor {statistics.median(factors[name]):4.2f}"
        )
    baseline = statistics.median(factors["every frame"])
    for name in ("2 ms step", "reference"):
        ratio = statistics.median(factors[name]) / baseline
        print(f"speed-up in real-time factor, {name} / every frame (baseline): {ratio:.2f}x")


if __name__ == "__main__":
    main()

"""Handover trial speed: wall time and real-time factor of whole handover trials (the reference
experiment's, scored as the experiment scores them) at the settings of the scenario (the
baseline: `scenarios/handover_reference.yaml`, 2 ms plant steps, camera at 30 Hz) against a
faster candidate (4 ms steps, 15 Hz, twice the GNG signals a frame so the map learns as much a
second), in the same run. Each trial's outcome is printed beside its time: a faster setting
that breaks the handover shows (session 10: the candidate ran 1.7x faster over the 64-trial
run, but a grasp slipped at 4 ms and a request went unrecognised at 15 Hz).

    python benchmarks/bench_handover_trial.py [--trials 0 1 7 42] [--scenario FILE]

Run it on a quiet machine: it takes one to two minutes a trial and setting.
"""

from __future__ import annotations

import argparse
import copy
import dataclasses
import statistics
import time
from pathlib import Path

from hsr_handover.experiments.handover import run_handover_trial
from hsr_handover.experiments.handover_trials import make_trials
from hsr_handover.scenario import Scenario, load_scenario

REFERENCE = Path(__file__).resolve().parents[1] / "scenarios" / "handover_reference.yaml"
CANDIDATE = {"time_step": 0.004, "rate_hz": 15.0, "signals_per_frame": 10000}
"""Faster settings to weigh against the scenario's."""


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


def _run(base: Scenario, index: int, settings: dict[str, float]) -> tuple[float, dict]:
    """One trial (index `index` of the 60-trial experiment, seed 0) with `settings`."""
    trial = make_trials(base, max(60, index + 1), 0, 0)[index]
    trial = dataclasses.replace(trial, scenario=_with(trial.scenario, settings))
    start = time.perf_counter()
    row = run_handover_trial(trial)
    return time.perf_counter() - start, row


def _line(name: str, index: int, wall: float, row: dict) -> str:
    outcome = "handed over" if row["handed_over"] else row["failure"] or "refused"
    return (
        f"  {name:9s} trial {index:2d}: wall {wall:6.1f} s  simulated {row['sim_s']:5.1f} s  "
        f"real-time factor {row['sim_s'] / wall:4.2f}  {outcome}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, nargs="+", default=[0, 1, 7, 42])
    parser.add_argument("--scenario", type=Path, default=REFERENCE)
    args = parser.parse_args()
    base = load_scenario(args.scenario)
    configurations = {"baseline": _settings(base), "candidate": CANDIDATE}
    factors: dict[str, list[float]] = {name: [] for name in configurations}
    walls: dict[str, list[float]] = {name: [] for name in configurations}
    print(f"{args.scenario.name}, trials {args.trials} of the 60-trial experiment (seed 0)")
    for name, settings in configurations.items():
        print(f"{name}: {settings}")
    for index in args.trials:
        for name, settings in configurations.items():
            wall, row = _run(base, index, settings)
            factors[name].append(row["sim_s"] / wall)
            walls[name].append(wall)
            print(_line(name, index, wall, row), flush=True)
    for name in configurations:
        print(
            f"{name:9s} median wall {statistics.median(walls[name]):6.1f} s a trial, "
            f"real-time factor {statistics.median(factors[name]):4.2f}"
        )
    ratio = statistics.median(factors["candidate"]) / statistics.median(factors["baseline"])
    print(f"speed-up in real-time factor, candidate / baseline: {ratio:.2f}x")


if __name__ == "__main__":
    main()

"""Perception speed: per-stage medians for one head-camera frame (the GNG learns from 200 x 200)
and the real-time factor of attention_shift.yaml with perception on, against the same scene with
perception off (the baseline), in the same run.

    python benchmarks/bench_perception.py [--repeats 20] [--duration 3]
"""

from __future__ import annotations

import argparse
import copy
import statistics
import time
from collections.abc import Callable
from pathlib import Path

from pydrake.systems.analysis import Simulator

from hsr_handover.perception.cloud_map import Workspace, learn_frame
from hsr_handover.scenario import load_scenario
from hsr_handover.station import build_station

SCENARIO = Path(__file__).resolve().parents[1] / "scenarios" / "attention_shift.yaml"
TARGET_MS = 15.0


def _median_ms(action: Callable[[], object], repeats: int) -> float:
    action()  # warm-up: numba kernels, caches
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        action()
        times.append(time.perf_counter() - start)
    return statistics.median(times) * 1e3


def _port_eval(system, inputs: dict, output: str) -> Callable[[], object]:
    """Evaluate a system's output on its own context, inputs fixed anew so nothing is cached."""
    context = system.CreateDefaultContext()

    def evaluate():
        for name, value in inputs.items():
            system.GetInputPort(name).FixValue(context, value)
        return system.GetOutputPort(output).Eval(context)

    return evaluate


def _stage_times(repeats: int) -> dict[str, float]:
    scenario = load_scenario(SCENARIO)
    station = build_station(scenario)
    simulator = Simulator(station.diagram)
    simulator.AdvanceTo(5.0)  # attending to the hand, the person reaching: a full map
    diagram, context = station.diagram, simulator.get_context()

    def subsystem(name):
        system = diagram.GetSubsystemByName(name)
        return system, system.GetMyContextFromRoot(context)

    def input_values(name):
        system, own = subsystem(name)
        return {
            system.get_input_port(i).get_name(): system.get_input_port(i).Eval(own)
            for i in range(system.num_input_ports())
            if system.get_input_port(i).HasValue(own)
        }

    gng_system, gng_context = subsystem("point_cloud_gng")
    learner = gng_context.get_abstract_state(0).get_value()
    points = diagram.GetOutputPort("point_cloud").Eval(context).xyzs().T.copy()
    regions = diagram.GetOutputPort("attention").Eval(context)
    box = scenario.perception.workspace
    workspace = Workspace(tuple(box[:3]), tuple(box[3:]))

    def learn():
        learn_frame(
            copy.deepcopy(learner),
            points,
            workspace,
            regions,
            scenario.perception.signals_per_frame,
            scenario.perception.attention_gain,
        )

    copy_only = _median_ms(lambda: copy.deepcopy(learner), repeats)
    stages = {
        "cloud: downsample 640x480 -> 200x200": _median_ms(
            _port_eval(subsystem("depth_downsampler")[0], input_values("depth_downsampler"),
                       "depth_image"), repeats),
        "cloud: depth -> world point cloud": _median_ms(
            _port_eval(subsystem("depth_to_point_cloud")[0], input_values("depth_to_point_cloud"),
                       "point_cloud"), repeats),
        "GNG update (5000 signals + labels)": _median_ms(learn, repeats) - copy_only,
        "object detection (640x480)": _median_ms(
            _port_eval(subsystem("object_detector")[0], input_values("object_detector"),
                       "detections"), repeats),
        "skeleton sensor (640x480 depth)": _median_ms(
            _port_eval(subsystem("skeleton_sensor")[0], input_values("skeleton_sensor"),
                       "skeleton"), repeats),
    }  # fmt: skip
    return stages


def _wall_time(duration: float, perception: bool) -> float:
    scenario = load_scenario(SCENARIO)
    scenario.perception.enabled = perception
    simulator = Simulator(build_station(scenario).diagram)
    simulator.Initialize()
    start = time.perf_counter()
    simulator.AdvanceTo(duration)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=20, help="calls per stage")
    parser.add_argument("--runs", type=int, default=3, help="simulation runs per configuration")
    parser.add_argument("--duration", type=float, default=3.0, help="simulated seconds per run")
    args = parser.parse_args()

    stages = _stage_times(args.repeats)
    print(f"one frame, median of {args.repeats} calls (rendering excluded):")
    for name, milliseconds in stages.items():
        print(f"  {name:40s} {milliseconds:6.2f} ms")
    total = sum(stages.values())
    verdict = "met" if total <= TARGET_MS else "not met"
    print(f"  {'total':40s} {total:6.2f} ms   (target <= {TARGET_MS:g} ms: {verdict})")

    _wall_time(0.2, True)  # warm-up
    on = statistics.median(_wall_time(args.duration, True) for _ in range(args.runs))
    off = statistics.median(_wall_time(args.duration, False) for _ in range(args.runs))
    print(f"attention_shift.yaml, {args.duration:g} s simulated, median of {args.runs} runs:")
    print(f"  perception on:  wall {on:6.2f} s, real-time factor {args.duration / on:5.2f}")
    print(
        f"  baseline, perception off (camera still 30 Hz): wall {off:6.2f} s, "
        f"real-time factor {args.duration / off:5.2f}"
    )
    print(
        f"  perception's share of wall time: {(on - off) / on:.0%} "
        f"({(on - off) / (args.duration * 30) * 1e3:.1f} ms per camera frame)"
    )


if __name__ == "__main__":
    main()

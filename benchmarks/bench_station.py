"""Station speed: wall time and real-time factor of the demo scenario with the head camera at
30 Hz, against the same scene with the camera slowed to one frame (the physics-and-actor
baseline), in the same run. Also the cost of one camera frame, by image type.

    python benchmarks/bench_station.py [--repeats 3] [--duration 4]
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np
from pydrake.systems.analysis import Simulator

from hsr_handover.hsr import CAMERA_FRAME, COMMANDED_JOINTS
from hsr_handover.scenario import load_scenario
from hsr_handover.simulation import build_simulation
from hsr_handover.world.station import build_station

DEMO = Path(__file__).resolve().parents[1] / "scenarios" / "demo.yaml"


def _time_run(duration: float, camera_rate: float, render_label: bool = True) -> float:
    scenario = load_scenario(DEMO)
    scenario.camera.rate_hz = camera_rate
    scenario.camera.render_label = render_label
    simulator = Simulator(build_simulation(scenario).diagram)
    simulator.Initialize()
    start = time.perf_counter()
    simulator.AdvanceTo(duration)
    return time.perf_counter() - start


def _time_render(repeats: int = 12) -> dict[str, float]:
    """Median milliseconds to render one head-camera image of each kind at the demo's start."""
    station = build_station(load_scenario(DEMO))
    camera = station.diagram.GetSubsystemByName("head_camera")
    context = station.diagram.CreateDefaultContext()
    # The station's commands have no defaults; nothing steps here, so any value will do.
    station.diagram.GetInputPort("hsr_desired_state").FixValue(
        context, np.zeros(2 * len(COMMANDED_JOINTS))
    )
    station.diagram.GetInputPort("gripper_desired_opening").FixValue(context, [0.0])
    station.diagram.ExecuteInitializationEvents(context)  # the first capture poses the scene
    scene = station.diagram.GetSubsystemByName("camera_scene_graph")
    query = scene.get_query_output_port().Eval(scene.GetMyContextFromRoot(context))
    frame = station.plant.GetFrameByName(CAMERA_FRAME, station.robot)
    X_WC = frame.CalcPoseInWorld(station.plant.GetMyContextFromRoot(context))
    world = station.scene_graph.model_inspector().world_frame_id()
    color, depth = camera.color_camera, camera.depth_camera
    renders = {
        "color": lambda: query.RenderColorImage(color, world, X_WC),
        "depth": lambda: query.RenderDepthImage(depth, world, X_WC),
        "label": lambda: query.RenderLabelImage(color, world, X_WC),
    }
    medians = {}
    for kind, render in renders.items():
        render()
        times = []
        for _ in range(repeats):
            start = time.perf_counter()
            render()
            times.append(time.perf_counter() - start)
        medians[kind] = statistics.median(times) * 1e3
    return medians


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--duration", type=float, default=4.0, help="simulated seconds per run")
    args = parser.parse_args()

    _time_run(0.2, 30.0)  # warm-up: first render context, caches
    with_camera = [_time_run(args.duration, 30.0) for _ in range(args.repeats)]
    no_label = [_time_run(args.duration, 30.0, False) for _ in range(args.repeats)]
    baseline = [_time_run(args.duration, 1e-3) for _ in range(args.repeats)]
    wall, base = statistics.median(with_camera), statistics.median(baseline)
    wall_no_label = statistics.median(no_label)
    frames = args.duration * 30.0
    print(f"demo.yaml, {args.duration:g} s simulated, median of {args.repeats} runs")
    print(
        f"  camera 30 Hz (640x480 colour+depth+label): wall {wall:6.2f} s  "
        f"real-time factor {args.duration / wall:5.2f}"
    )
    print(
        f"  camera 30 Hz, label image off:              wall {wall_no_label:6.2f} s  "
        f"real-time factor {args.duration / wall_no_label:5.2f}"
    )
    print(
        f"  baseline, camera off (physics + actor):     wall {base:6.2f} s  "
        f"real-time factor {args.duration / base:5.2f}"
    )
    print(
        f"  ratio camera/baseline wall time: {wall / base:.2f}x; "
        f"camera cost per frame: {(wall - base) / frames * 1e3:.1f} ms"
    )
    for kind, milliseconds in _time_render().items():
        print(f"  render one {kind:5s} image: {milliseconds:6.1f} ms (median)")
    print(
        f"  target: real-time factor >= 1 with the camera at 30 Hz "
        f"({'met' if args.duration / wall >= 1 else 'not met'})"
    )


if __name__ == "__main__":
    main()

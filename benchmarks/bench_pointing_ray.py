"""How far the robot's lifted pointing arm is from the person's true one, with the realistic pose
detector and, as the baseline in the same run, the ideal one: over intent requests (generated
layouts by default), each frame after the pointing onset, the lifted shoulder, elbow and wrist
of the pointing arm against the true keypoints, split into depth (along the camera's line of
sight) and lateral error, and the shoulder-to-wrist ray's angle from the true one. Prints the
medians over trials. Scoring only: the truth is read from the world's pose detector.

    python benchmarks/bench_pointing_ray.py [--requests 8] [--seed 1] [--workers 2]
        [--scenario scenarios/intent_reference.yaml] [--layouts generated|scenario]
"""

from __future__ import annotations

import argparse
import copy
import dataclasses
import math
from pathlib import Path

import numpy as np
from pydrake.systems.framework import EventStatus

from hsr_handover.experiments.intent_trials import make_trials
from hsr_handover.experiments.trials import TrialProgress, run_trials
from hsr_handover.perception.coco18 import keypoint_index
from hsr_handover.scenario import load_scenario
from hsr_handover.simulation import run_scenario
from hsr_handover.systems.frame_timing import PROCESSING_DELAY_S

SCENARIO = Path(__file__).resolve().parents[1] / "scenarios" / "intent_reference.yaml"
JOINTS = ("shoulder", "elbow", "wrist")


@dataclasses.dataclass(frozen=True)
class Probe:
    detector: str
    arm: str
    onset: float
    scenario: object


def _frames(probe: Probe) -> list:
    """(true keypoints, lifted points, confidences, camera position) of each frame after onset."""
    frames = []

    def factory(simulation):
        detector = simulation.station.diagram.GetSubsystemByName("pose_detector")
        last = [math.nan]

        def monitor(root):
            context = detector.GetMyContextFromRoot(root)
            truth, time = detector.captured(context)
            lifted_by = time + 2 * PROCESSING_DELAY_S
            if time != last[0] and root.get_time() >= lifted_by and time >= probe.onset:
                last[0] = time
                robot = simulation.robot.diagram
                skeleton = robot.GetOutputPort("skeleton").Eval(simulation.robot_context(root))
                camera = detector.GetInputPort("camera_pose").Eval(context).translation()
                frames.append((truth.copy(), skeleton.points, skeleton.confidence, camera))
            return EventStatus.Succeeded()

        return monitor

    run_scenario(probe.scenario, None, monitor_factory=factory)
    return frames


def measure(probe: Probe) -> dict:
    """Per trial: each joint's median depth and lateral error (m) and the ray's median angle."""
    frames = _frames(probe)
    side = probe.arm[0]
    index = {joint: keypoint_index(f"{side}_{joint}") for joint in JOINTS}
    result = {}
    for joint, i in index.items():
        depth, lateral = [], []
        for truth, points, confidence, camera in frames:
            if confidence[i] > 0:
                sight = (truth[i] - camera) / np.linalg.norm(truth[i] - camera)
                error = points[i] - truth[i]
                depth.append(error @ sight)
                lateral.append(np.linalg.norm(error - (error @ sight) * sight))
        result[f"{joint}_depth"] = float(np.median(depth)) if depth else math.nan
        result[f"{joint}_lateral"] = float(np.median(lateral)) if lateral else math.nan
    angles = []
    s, w = index["shoulder"], index["wrist"]
    for truth, points, confidence, _ in frames:
        if confidence[s] > 0 and confidence[w] > 0:
            true_ray, seen_ray = truth[w] - truth[s], points[w] - points[s]
            cosine = true_ray @ seen_ray / np.linalg.norm(true_ray) / np.linalg.norm(seen_ray)
            angles.append(math.degrees(math.acos(np.clip(cosine, -1.0, 1.0))))
    result["ray_deg"] = float(np.median(angles)) if angles else math.nan
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", type=Path, default=SCENARIO)
    parser.add_argument("--requests", type=int, default=8)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--workers", type=int)
    parser.add_argument("--layouts", choices=("scenario", "generated"), default="generated")
    args = parser.parse_args()
    if not 1 <= args.requests <= 1000:
        parser.error(f"--requests: expected an integer in [1, 1000], got {args.requests}")
    base = load_scenario(args.scenario)
    probes = []
    for detector in ("realistic", "ideal"):
        scenario = copy.deepcopy(base)
        scenario.perception.detector.preset = detector
        for trial in make_trials(scenario, args.requests, 0, args.seed, layouts=args.layouts):
            probes.append(Probe(detector, trial.arm, trial.pointing_onset, trial.scenario))
    outcomes = run_trials(measure, probes, args.workers, progress=TrialProgress())
    print(f"{'detector':10s} {'trials':>6s}  " + "  ".join(
        f"{joint} depth / lateral (cm)" for joint in JOINTS) + "  ray (deg)")  # fmt: skip
    for detector in ("realistic", "ideal"):
        rows = [o.result for p, o in zip(probes, outcomes, strict=True)
                if p.detector == detector and o.ok]  # fmt: skip
        cells = []
        for joint in JOINTS:
            depth = 100 * np.nanmedian([row[f"{joint}_depth"] for row in rows])
            lateral = 100 * np.nanmedian([row[f"{joint}_lateral"] for row in rows])
            cells.append(f"{depth:+17.1f} / {lateral:4.1f}")
        ray = np.nanmedian([row["ray_deg"] for row in rows])
        print(f"{detector:10s} {len(rows):6d}  " + "  ".join(cells) + f"  {ray:9.1f}")
    failed = [o.error for o in outcomes if not o.ok]
    if failed:
        print(f"{len(failed)} trials failed: {failed}")


if __name__ == "__main__":
    main()

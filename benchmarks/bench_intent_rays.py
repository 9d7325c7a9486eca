"""Where the intent recogniser's rays err, and whose error it is: the person's or the detector's.

Over intent requests (generated layouts by default), the realistic pose detector and, as the
baseline in the same run, the ideal one:

- the lifted pointing arm against the person's true one, each frame after the pointing onset:
  the shoulder, elbow and wrist in depth (along the camera's line of sight) and across, and the
  shoulder-to-wrist ray's angle from the true one, whole, in bearing (about the vertical: what
  tells objects in a row apart) and in elevation (medians over trials of per-trial medians);
- the bearing from the pointing ray and from the estimated gaze to the object asked for, each
  frame the true arm is held straight, computed by the recogniser's own functions twice: on the
  person's true keypoints (the person's own imprecision: the arm's pointing error, the head's
  share of the gaze against the recogniser's model of it) and on the lifted skeleton (adding
  the detector and the lifting). Printed as the size (root mean square over trials of the
  per-trial medians, degrees: a bias counts) of each, of the detector's part (lifted minus
  true), and of the gaze's two parts: the face's heading and the torso's facing voted over
  the frames (`SteadyFacing`). The face's heading is read from the head's shape in the depth
  image (`head_pose`, the recogniser's default) and, as the baseline in the same run, from
  eq. 17 on the lifted keypoints. The gaze's error is head_gain x the face's minus
  (head_gain - 1) x the torso's. And how far the gaze passes above the target's centre
  (mean and sd over trials): what the recogniser's pitch tests read.

Scoring only: the truth is read from the world's pose detector.

    python benchmarks/bench_intent_rays.py [--requests 8] [--seed 1] [--workers 2]
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

from hsr_handover.experiments.intent.trials import make_trials
from hsr_handover.experiments.trials import TrialProgress, run_trials
from hsr_handover.interface.coco18 import NUM_KEYPOINTS, keypoint_index
from hsr_handover.robot.intent import IntentParams
from hsr_handover.robot.intent.person_rays import (
    ARMS,
    face_ray,
    gaze_ray,
    pitch_errors_deg,
    torso_forward,
)
from hsr_handover.robot.intent.rays import Ray, angle_deg, elbow_angle_deg, heading_elevation
from hsr_handover.robot.perception.active_gaze import wrap
from hsr_handover.robot.perception.facing import SteadyFacing
from hsr_handover.scenario import load_scenario
from hsr_handover.scenario.checks import object_center
from hsr_handover.simulation import run_scenario
from hsr_handover.systems.frame_timing import PROCESSING_DELAY_S

SCENARIO = Path(__file__).resolve().parents[1] / "scenarios" / "intent_reference.yaml"
JOINTS = ("shoulder", "elbow", "wrist")
# The face's direction from the head's shape (the recogniser's default) and, as the baseline
# in the same run, from eq. 17 on the lifted keypoints.
FACE_SOURCES = {"": True, "_eq17": False}
BEARINGS = ("pointing_true", "pointing_lifted", "gaze_true", "torso", "gaze_pitch_true",
            *(f"{name}{source}" for source in FACE_SOURCES
              for name in ("gaze_lifted", "face", "gaze_pitch_lifted")))  # fmt: skip
DETECTORS = ("realistic", "ideal")
HELD_STRAIGHT_DEG = 165.0  # the true elbow's angle while the gesture is held


@dataclasses.dataclass(frozen=True)
class Probe:
    detector: str
    arm: str
    onset: float
    scenario: object
    target: tuple[float, float, float]  # the centre of the object asked for (m, world)


def _frames(probe: Probe) -> list:
    """(true keypoints, lifted points, confidences, camera position, the chest's facing, the
    face's from the head's shape) of each frame after onset."""
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
                frames.append((truth.copy(), skeleton.points, skeleton.confidence, camera,
                               skeleton.torso_forward, skeleton.face_forward))  # fmt: skip
            return EventStatus.Succeeded()

        return monitor

    run_scenario(probe.scenario, None, monitor_factory=factory)
    return frames


def measure(probe: Probe) -> dict:
    """One trial's figures: `_arm_errors` and `_bearing_errors`."""
    frames = _frames(probe)
    return {**_arm_errors(frames, probe), **_bearing_errors(frames, probe)}


def _arm_errors(frames: list, probe: Probe) -> dict:
    """Each joint's median depth and lateral error (m) and the ray's median angles (deg)."""
    side = probe.arm[0]
    index = {joint: keypoint_index(f"{side}_{joint}") for joint in JOINTS}
    result = {}
    for joint, i in index.items():
        depth, lateral = [], []
        for truth, points, confidence, camera, *_ in frames:
            if confidence[i] > 0:
                sight = (truth[i] - camera) / np.linalg.norm(truth[i] - camera)
                error = points[i] - truth[i]
                depth.append(error @ sight)
                lateral.append(np.linalg.norm(error - (error @ sight) * sight))
        result[f"{joint}_depth"], result[f"{joint}_lateral"] = _median(depth), _median(lateral)
    angles, bearings, elevations = [], [], []
    s, w = index["shoulder"], index["wrist"]
    for truth, points, confidence, *_ in frames:
        if confidence[s] > 0 and confidence[w] > 0:
            true_ray, seen_ray = truth[w] - truth[s], points[w] - points[s]
            angles.append(angle_deg(true_ray, seen_ray))
            _, (true_elevation, seen_elevation) = heading_elevation(np.array([true_ray, seen_ray]))
            bearings.append(abs(_turn_deg(true_ray, seen_ray)))
            elevations.append(math.degrees(seen_elevation - true_elevation))
    for name, values in (("ray_deg", angles), ("bearing_deg", bearings),
                         ("elevation_deg", elevations)):  # fmt: skip
        result[name] = _median(values)
    return result


def _bearing_errors(frames: list, probe: Probe) -> dict:
    """Median signed bearings (deg) to the target over the frames whose true arm is straight:
    the pointing ray and the gaze on the true keypoints and on the lifted ones, and the lifted
    face's heading and the voted torso facing against the true ones."""
    params = IntentParams()
    shoulder, elbow, wrist = ARMS[probe.arm]
    everything = np.ones(NUM_KEYPOINTS)
    chest, shoulders = SteadyFacing(), SteadyFacing()  # as IntentTracker votes them
    values = {name: [] for name in BEARINGS}
    for truth, points, confidence, _, chest_forward, face_forward in frames:
        chest = chest.add(chest_forward)
        if elbow_angle_deg(truth[shoulder], truth[elbow], truth[wrist]) < HELD_STRAIGHT_DEG:
            shoulders = shoulders.add(torso_forward(points, confidence))
            continue
        true_face = face_ray(truth, everything, params)
        true_forward = torso_forward(truth, everything, probe.arm)
        if true_face is None or true_forward is None:
            continue
        values["pointing_true"].append(_bearing(Ray.through(truth[shoulder], truth[wrist]), probe))
        true_gaze = gaze_ray(true_face, true_forward, params)
        values["gaze_true"].append(_bearing(true_gaze, probe))
        values["gaze_pitch_true"].append(_above(true_gaze, probe))
        if confidence[shoulder] > 0 and confidence[wrist] > 0:
            pointing = Ray.through(points[shoulder], points[wrist])
            values["pointing_lifted"].append(_bearing(pointing, probe))
        forward = chest.direction()
        forward = shoulders.direction() if forward is None else forward
        if forward is not None:
            values["torso"].append(_turn_deg(true_forward, forward))
        for source, from_shape in FACE_SOURCES.items():
            face = face_ray(points, confidence, params, face_forward if from_shape else None)
            if face is None:
                continue
            gaze = gaze_ray(face, forward, params)
            values[f"gaze_lifted{source}"].append(_bearing(gaze, probe))
            values[f"gaze_pitch_lifted{source}"].append(_above(gaze, probe))
            values[f"face{source}"].append(_turn_deg(true_face.direction, face.direction))
    return {name: _median(found) for name, found in values.items()}


def _bearing(ray: Ray | None, probe: Probe) -> float:
    """How far (deg, signed, about world z) the ray heads from the direction to the target;
    NaN without a ray."""
    if ray is None:
        return math.nan
    target = np.array([*probe.target[:2], ray.origin[2]])
    return _turn_deg(target - ray.origin, ray.direction)


def _above(ray: Ray, probe: Probe) -> float:
    """How far (deg) the ray passes above the target's centre, seen from its origin."""
    return float(pitch_errors_deg(ray, np.array([probe.target]))[0])


def _turn_deg(reference: np.ndarray, direction: np.ndarray) -> float:
    """The signed turn (deg, counter-clockwise about world z) from `reference` to `direction`."""
    (first, second), _ = heading_elevation(np.array([reference, direction]))
    return math.degrees(wrap(second - first))


def _median(values: list) -> float:
    """The median of the values that are numbers; NaN without any."""
    finite = [value for value in values if math.isfinite(value)]
    return float(np.median(finite)) if finite else math.nan


def _print_arms(rows: dict[str, list[dict]]) -> None:
    print(f"{'detector':10s} {'trials':>6s}  " + "  ".join(
        f"{joint} depth / lateral (cm)" for joint in JOINTS)
        + "  ray / bearing / elevation (deg)")  # fmt: skip
    for detector, found in rows.items():
        cells = []
        for joint in JOINTS:
            depth = 100 * np.nanmedian([row[f"{joint}_depth"] for row in found])
            lateral = 100 * np.nanmedian([row[f"{joint}_lateral"] for row in found])
            cells.append(f"{depth:+17.1f} / {lateral:4.1f}")
        ray, bearing, elevation = (
            np.nanmedian([row[name] for row in found])
            for name in ("ray_deg", "bearing_deg", "elevation_deg")
        )
        print(f"{detector:10s} {len(found):6d}  " + "  ".join(cells)
              + f"  {ray:5.1f} / {bearing:4.1f} / {elevation:+5.1f}")  # fmt: skip


def _print_bearings(rows: dict[str, list[dict]]) -> None:
    """The size over trials (root mean square, deg: a bias counts) of the bearing errors to
    the target: the person's, the lifted skeleton's and their difference, for the pointing ray
    and the gaze; and how far the gaze passes above the target (mean ± sd over trials)."""
    print("\nbearing to the target, rms over trials (deg)"
          "    pointing: person / lifted / detector     gaze: person / lifted / detector"
          "  (face / torso)  gaze above: person / lifted / detector, mean ± sd")  # fmt: skip
    for detector, found in rows.items():
        column = {name: np.array([row[name] for row in found]) for name in BEARINGS}
        for source in FACE_SOURCES:
            label = detector + (", eq. 17" if source else "")
            cells = []
            for ray, suffix in (("pointing", ""), ("gaze", source)):
                person, lifted = column[f"{ray}_true"], column[f"{ray}_lifted{suffix}"]
                sizes = (_rms(values) for values in (person, lifted, lifted - person))
                cells.append(" / ".join(f"{size:4.1f}" for size in sizes))
            parts = f"({_rms(column['face' + source]):4.1f} / {_rms(column['torso']):4.1f})"
            person, lifted = column["gaze_pitch_true"], column[f"gaze_pitch_lifted{source}"]
            parts += "  pitch " + " / ".join(
                _mean_sd(values) for values in (person, lifted, lifted - person)
            )
            print(f"{label:19s} {len(found):6d} trials {'':19s}{cells[0]:18s}"
                  f"  {'':17s}{cells[1]:18s}  {parts}")  # fmt: skip


def _mean_sd(values: np.ndarray) -> str:
    finite = values[np.isfinite(values)]
    return f"{finite.mean():+4.1f} ± {finite.std():3.1f}" if len(finite) else "nan"


def _rms(values: np.ndarray) -> float:
    finite = values[np.isfinite(values)]
    return float(np.sqrt(np.mean(np.square(finite)))) if len(finite) else math.nan


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
    for detector in DETECTORS:
        scenario = copy.deepcopy(base)
        scenario.perception.detector.preset = detector
        for trial in make_trials(scenario, args.requests, 0, args.seed, layouts=args.layouts):
            asked = next(obj for obj in trial.scenario.objects if obj.name == trial.target)
            target = tuple(object_center(trial.scenario, asked))
            probes.append(Probe(detector, trial.arm, trial.pointing_onset, trial.scenario,
                                target))  # fmt: skip
    outcomes = run_trials(measure, probes, args.workers, progress=TrialProgress())
    rows = {
        detector: [o.result for p, o in zip(probes, outcomes, strict=True)
                   if p.detector == detector and o.ok]
        for detector in DETECTORS
    }  # fmt: skip
    _print_arms(rows)
    _print_bearings(rows)
    failed = [o.error for o in outcomes if not o.ok]
    if failed:
        print(f"{len(failed)} trials failed: {failed}")


if __name__ == "__main__":
    main()

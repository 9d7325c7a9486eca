"""The intent experiment (paper 4.2): the person asks for one object by looking and pointing, and
the robot must name it; on distractor trials the person does not ask, and the robot must not.

Each trial is a copy of the user's scenario with the person varied (`person.variation`), made
imprecise (`person.imprecision`), and given a new behaviour script; targets cycle evenly over
the objects. Trials are self-contained specs (`IntentTrial`), run by the shared trial runner in
worker processes or on Ray, so the same seed gives the same table whatever the workers.

Scoring uses the simulator's truth only to know what was asked (the script) and where the
objects are (to class them left, centre or right from the person's nominal seat); the robot
recognised its target from its own percepts.
"""

from __future__ import annotations

import copy
import dataclasses
import math
import time
from collections.abc import Sequence

import numpy as np
from pydrake.systems.framework import Context, EventStatus

from hsr_handover.experiments.trials import Progress, TrialOutcome, run_trials
from hsr_handover.human.body import BodyDimensions
from hsr_handover.intent import IntentParams, IntentState, IntentTracker
from hsr_handover.scenario import ActionConfig, Scenario, object_center
from hsr_handover.simulation import Simulation, run_scenario
from hsr_handover.station import person_pose
from hsr_handover.systems.frame_timing import PROCESSING_DELAY_S

DISTRACTORS = ("gesture", "arm_on_table", "scratch_head", "look_only")
"""Trials with no request: talking with the hands, a straight arm resting toward the table,
a hand raised to scratch the head, looking at an object while the hands rest."""
POSITIONS = ("left", "centre", "right")
PAPER_BY_POSITION = {"left": 0.783, "centre": 0.85, "right": 0.933}
"""The paper's intent recognition over 60 real trials, by the object's side as the person sees
it (4.2)."""
CENTRE_HALF_WIDTH = 0.1
"""m: an object this near the person's midline (sideways) is in the centre."""
SETTLE_S = 1.0
"""s of simulation after the last scripted action ends, for a late recognition to land."""


@dataclasses.dataclass(frozen=True)
class IntentTrial:
    """One trial, self-contained: its index, kind ("request" or one of DISTRACTORS), the object
    asked for ("" on a distractor trial), the arm used, when the pointing starts, and the whole
    scenario to run (its seed included)."""

    index: int
    kind: str
    target: str
    arm: str
    pointing_onset: float
    scenario: Scenario
    record_percepts: bool = False


def object_positions(scenario: Scenario) -> dict[str, str]:
    """Each object's side as the seated person sees it: "left", "centre" or "right"."""
    to_person = person_pose(scenario).inverse()
    sides = {}
    for obj in scenario.objects:
        lateral = (to_person @ object_center(scenario, obj))[1]  # +y: the person's left
        if abs(lateral) < CENTRE_HALF_WIDTH:
            sides[obj.name] = "centre"
        else:
            sides[obj.name] = "left" if lateral > 0 else "right"
    return sides


def make_trials(base: Scenario, trials: int, distractors: int, seed: int) -> list[IntentTrial]:
    """`trials` requests with targets cycling over the objects, then `distractors` trials with no
    request, each with its own seed and person drawn from `seed`."""
    rng = np.random.default_rng(seed)
    names = [obj.name for obj in base.objects]
    kinds = [("request", names[i % len(names)]) for i in range(trials)]
    kinds += [(DISTRACTORS[i % len(DISTRACTORS)], "") for i in range(distractors)]
    return [_make_trial(base, index, kind, target, rng) for index, (kind, target) in
            enumerate(kinds)]  # fmt: skip


def _uniform(rng: np.random.Generator, span: Sequence[float]) -> float:
    return float(rng.uniform(span[0], span[1]))


def _make_trial(base: Scenario, index: int, kind: str, target: str, rng) -> IntentTrial:
    scenario = copy.deepcopy(base)
    variation = scenario.person.variation
    scenario.simulation.seed = int(rng.integers(0, 2**32 - 1))
    person = scenario.person
    person.height = float(np.clip(rng.normal(person.height, variation.height_sd), 1.45, 2.0))
    person.position = [float(v) for v in rng.normal(person.position, variation.position_sd)]
    person.yaw = float(person.yaw + math.radians(rng.normal(0.0, variation.yaw_sd_deg)))
    arm = "left" if rng.random() < variation.left_arm_probability else "right"
    onset = _uniform(rng, variation.onset_s)
    lead = _uniform(rng, variation.look_lead_s)
    duration = _uniform(rng, variation.point_duration_s)
    look_target = str(rng.choice([obj.name for obj in scenario.objects]))
    person.behavior = _script(scenario, kind, target or look_target, arm, onset, lead, duration)
    scenario.simulation.duration = onset + lead + duration + SETTLE_S
    scenario.perception.enabled = True
    scenario.perception.attention = []
    scenario.camera.render_label = False  # ground truth nobody scores here
    return IntentTrial(index, kind, target, arm, onset + lead, scenario)


def _script(
    scenario: Scenario, kind: str, target: str, arm: str, onset: float, lead: float, duration: float
) -> list[ActionConfig]:
    """The person's behaviour for one trial: look at `target` from `onset`, point at it `lead`
    later for `duration` (a request), or one of the DISTRACTORS for as long."""
    look = ActionConfig("look_at", onset, target=target)
    if kind == "request":
        point = ActionConfig("point_at", onset + lead, duration, target=target, arm=arm)
        return [look, point]
    if kind == "look_only":
        return [ActionConfig("look_at", onset, lead + duration, target=target)]
    if kind == "gesture":
        return [ActionConfig("gesture", onset, lead + duration, arm=arm)]
    where = _table_rest_point if kind == "arm_on_table" else _head_side
    reach = where(scenario, arm)
    return [ActionConfig("touch", onset, lead + duration, point=list(reach), arm=arm)]


def _table_rest_point(scenario: Scenario, arm: str) -> np.ndarray:
    """On the table top, 5 cm inside its edge, nearest the arm's shoulder: where an arm laid
    straight on the table rests."""
    body = _body(scenario)
    shoulder = person_pose(scenario) @ body.shoulder(arm)
    table = scenario.table
    c, s = math.cos(table.yaw), math.sin(table.yaw)
    local = np.array([[c, s], [-s, c]]) @ (shoulder[:2] - np.asarray(table.center))
    half = np.asarray(table.size) / 2 - 0.05
    inside = np.clip(local, -half, half)
    xy = np.asarray(table.center) + np.array([[c, -s], [s, c]]) @ inside
    return np.array([*xy, table.height + 0.03])


def _head_side(scenario: Scenario, arm: str) -> np.ndarray:
    """Beside the head on the arm's side: where a hand goes to scratch it."""
    body = _body(scenario)
    sign = 1.0 if arm == "left" else -1.0
    beside = body.head_center() + np.array([0.0, sign * (body.head_radius + 0.04), 0.0])
    return person_pose(scenario) @ beside


def _body(scenario: Scenario) -> BodyDimensions:
    return BodyDimensions.from_height(scenario.person.height, scenario.person.posture == "seated")


@dataclasses.dataclass(frozen=True)
class PerceivedFrame:
    """What the intent estimator was given for one camera frame: the capture time, the lifted
    skeleton's points (18 x 3) and confidences, and the confirmed (label, centre) candidates."""

    time: float
    points: np.ndarray
    confidence: np.ndarray
    candidates: tuple[tuple[str, np.ndarray], ...]


class PerceptRecorder:
    """A simulator monitor that keeps the intent estimator's inputs of every camera frame, so
    other thresholds can be tried offline on the same percepts (`replay_intent`)."""

    def __init__(self, simulation: Simulation):
        self._simulation, self._last = simulation, math.nan
        self.frames: list[PerceivedFrame] = []

    def __call__(self, context: Context) -> EventStatus:
        robot = self._simulation.robot.diagram
        robot_context = self._simulation.robot_context(context)
        station = self._simulation.station.diagram
        image_time = station.GetOutputPort("camera_image_time").Eval(
            self._simulation.station_context(context)
        )
        # Once the estimator has judged the new frame (see frame_timing), as it saw it.
        if image_time != self._last and context.get_time() >= image_time + 2 * PROCESSING_DELAY_S:
            self._last = image_time
            skeleton = robot.GetOutputPort("skeleton").Eval(robot_context)
            detections = robot.GetOutputPort("detections").Eval(robot_context).detections
            support = robot.GetOutputPort("detection_support").Eval(robot_context)
            confirmed = {s.label for s in support if s.confirmed}
            candidates = tuple((d.label, d.center) for d in detections if d.label in confirmed)
            self.frames.append(
                PerceivedFrame(image_time, skeleton.points, skeleton.confidence, candidates)
            )
        return EventStatus.Succeeded()


def replay_intent(frames: Sequence[PerceivedFrame], params: IntentParams) -> IntentState:
    """The intent recogniser run offline over recorded frames: its state after the last."""
    tracker = IntentTracker(params)
    for frame in frames:
        tracker.update(frame.time, frame.points, frame.confidence, frame.candidates)
    return tracker.state_


def run_intent_trial(trial: IntentTrial) -> dict:
    """Simulate one trial; what the robot recognised, when, and how long it took (with
    `record_percepts`, also the frames the recogniser was given, under "percepts")."""
    start = time.perf_counter()
    recorders: list[PerceptRecorder] = []

    def recorder(simulation: Simulation) -> PerceptRecorder:
        recorders.append(PerceptRecorder(simulation))
        return recorders[-1]

    monitor = recorder if trial.record_percepts else None
    report = run_scenario(trial.scenario, monitor_factory=monitor)
    robot = report.simulation.robot.diagram
    intent = robot.GetOutputPort("intent").Eval(report.simulation.robot_context(report.context))
    by_color = {obj.color: obj.name for obj in trial.scenario.objects}
    recognised = by_color.get(intent.target, intent.target) if intent.target else ""
    latency = intent.recognised_time - trial.pointing_onset if recognised else math.nan
    person = trial.scenario.person
    return {
        "index": trial.index, "kind": trial.kind, "target": trial.target, "arm": trial.arm,
        "recognised": recognised, "recognised_time_s": intent.recognised_time,
        "latency_s": latency, "confidence": intent.confidence,
        "seed": trial.scenario.simulation.seed, "person_height_m": person.height,
        "person_x_m": person.position[0], "person_y_m": person.position[1],
        "person_yaw_rad": person.yaw, "sim_s": report.sim_time,
        "wall_s": time.perf_counter() - start,
        **({"percepts": recorders[0].frames} if recorders else {}),
    }  # fmt: skip


@dataclasses.dataclass
class IntentExperiment:
    """The trials as run, their outcomes, and the settings that made them."""

    trials: list[IntentTrial]
    outcomes: list[TrialOutcome]
    base: Scenario
    seed: int
    wall_s: float

    def rows(self) -> list[dict]:
        """One row per trial: the trial's own result, or what it was and why it failed."""
        rows = []
        for trial, outcome in zip(self.trials, self.outcomes, strict=True):
            if outcome.ok:
                rows.append({**outcome.result, "error": ""})
            else:
                what = {"kind": trial.kind, "target": trial.target, "arm": trial.arm}
                rows.append(
                    {"index": trial.index, **what, "recognised": "", "error": outcome.error}
                )
        return rows


def run_intent_experiment(
    base: Scenario,
    trials: int = 60,
    distractors: int = 0,
    seed: int = 0,
    workers: int | None = None,
    ray_address: str | None = None,
    progress: Progress | None = None,
) -> IntentExperiment:
    """Make and run the trials; `summarise` turns the result into the paper's table."""
    start = time.perf_counter()
    specs = make_trials(base, trials, distractors, seed)
    outcomes = run_trials(run_intent_trial, specs, workers, ray_address, progress)
    return IntentExperiment(specs, outcomes, base, seed, time.perf_counter() - start)


def _rate(hits: int, count: int) -> float:
    return hits / count if count else math.nan


def summarise(experiment: IntentExperiment) -> dict:
    """The JSON summary: success overall, by position and by object beside the paper's figures,
    a confusion matrix, the false-trigger rate, latency from pointing onset, failures, and the
    person model and settings the trials ran with."""
    rows = experiment.rows()
    requests = [row for row in rows if row["kind"] == "request"]
    distractors = [row for row in rows if row["kind"] != "request"]
    sides = object_positions(experiment.base)
    names = [obj.name for obj in experiment.base.objects]
    success = [row["recognised"] == row["target"] for row in requests]
    by_object = {
        name: _rate(sum(s for r, s in zip(requests, success, strict=True) if r["target"] == name),
                    sum(r["target"] == name for r in requests))
        for name in names
    }  # fmt: skip
    by_position = {}
    for side in POSITIONS:
        picked = [s for r, s in zip(requests, success, strict=True) if sides[r["target"]] == side]
        by_position[side] = _rate(sum(picked), len(picked))
    confusion = {name: dict.fromkeys([*names, "none"], 0) for name in names}
    for row in requests:
        confusion[row["target"]][row["recognised"] or "none"] += 1
    latencies = [r["latency_s"] for r, s in zip(requests, success, strict=True) if s]
    failures = [{"index": row["index"], "error": row["error"]} for row in rows if row["error"]]
    return {
        "trials": len(requests),
        "distractor_trials": len(distractors),
        "success_rate": _rate(sum(success), len(requests)),
        "by_position": by_position,
        "paper_by_position": PAPER_BY_POSITION,
        "object_positions": sides,
        "by_object": by_object,
        "confusion": confusion,
        "false_trigger_rate": _rate(
            sum(bool(r["recognised"]) for r in distractors), len(distractors)
        ),  # fmt: skip
        "latency_s": {
            "median": float(np.median(latencies)) if latencies else math.nan,
            "p95": float(np.percentile(latencies, 95)) if latencies else math.nan,
        },
        "failed_trials": len(failures),
        "failures": failures,
        "person_model": {
            "imprecision": dataclasses.asdict(experiment.base.person.imprecision),
            "variation": dataclasses.asdict(experiment.base.person.variation),
        },
        "intent_params": dataclasses.asdict(experiment.base.intent),
        "seed": experiment.seed,
        "wall_s": experiment.wall_s,
    }

"""The intent experiment (paper 4.2): the person asks for one object by looking and pointing, and
the robot must name it; on distractor trials the person does not ask, and the robot must not.

The trials (`intent_trials`) run on the shared trial runner in worker processes or on Ray.
Scoring uses the simulator's truth only to know what was asked (the script) and where the
objects are (to class them left, centre or right from the person's nominal seat); the robot
recognised its target from its own percepts.
"""

from __future__ import annotations

import dataclasses
import math
import time
from pathlib import Path

import numpy as np

from hsr_handover.experiments.arm_aim import with_arm_aims
from hsr_handover.experiments.experiment import (
    TrialExperiment,
    name_replay,
    rate,
    replay_while_running,
)
from hsr_handover.experiments.intent.percepts import PerceptRecorder
from hsr_handover.experiments.intent.trials import IntentTrial, make_trials, object_positions
from hsr_handover.experiments.layouts import write_trial_scenario
from hsr_handover.experiments.seating import sit_clear
from hsr_handover.experiments.trial_classes import by_class
from hsr_handover.experiments.trials import Progress
from hsr_handover.literature import BREUER_POINTING_ERROR_DEG, BREUER_TARGETS_FOUND
from hsr_handover.scenario import Scenario
from hsr_handover.simulation import Simulation, run_scenario

POSITIONS = ("left", "centre", "right")
PAPER_BY_POSITION = {"left": 0.783, "centre": 0.85, "right": 0.933}
"""The paper's intent recognition in real trials, by the object's side as the person sees it
(4.2)."""
PAPER_TRIALS_BY_POSITION = 60
"""Real trials behind each of the paper's rates: they are whole sixtieths (47, 51 and 56 of
60)."""


def run_intent_trial(trial: IntentTrial) -> dict:
    """Simulate one trial; what the robot recognised, when, and how long it took (with
    `record_percepts`, also the frames the recogniser was given, under "percepts")."""
    start = time.perf_counter()
    recorders: list[PerceptRecorder] = []

    def recorder(simulation: Simulation) -> PerceptRecorder:
        recorders.append(PerceptRecorder(simulation))
        return recorders[-1]

    monitor = recorder if trial.record_percepts else None
    replay = replay_while_running(trial.replay_dir, trial.index)
    moved_back = sit_clear(trial.scenario)
    write_trial_scenario(trial.scenario_dir, trial.index, trial.scenario)
    report = run_scenario(trial.scenario, replay, monitor_factory=monitor)
    robot = report.simulation.robot.diagram
    robot_context = report.simulation.robot_context(report.context)
    intent = robot.GetOutputPort("intent").Eval(robot_context)
    # The watch-only robot with active gaze raises its torso where objects hide the arm.
    lifted = robot.HasOutputPort("watch_lift")
    watch_lift = float(robot.GetOutputPort("watch_lift").Eval(robot_context)[0]) if lifted else 0.0
    by_color = {obj.color: obj.name for obj in trial.scenario.objects}
    recognised = by_color.get(intent.target, intent.target) if intent.target else ""
    name_replay(report.replay, trial.index, _outcome(trial, recognised))
    latency = intent.recognised_time - trial.pointing_onset if recognised else math.nan
    person = trial.scenario.person
    return {
        "index": trial.index, "kind": trial.kind, "target": trial.target, "arm": trial.arm,
        "recognised": recognised, "recognised_time_s": intent.recognised_time,
        "latency_s": latency, "confidence": intent.confidence,
        "seed": trial.scenario.simulation.seed, "person_height_m": person.height,
        "person_x_m": person.position[0], "person_y_m": person.position[1],
        "person_yaw_rad": person.yaw, "person_moved_back_m": moved_back,
        "watch_lift_m": watch_lift, "sim_s": report.sim_time,
        "wall_s": time.perf_counter() - start,
        **({"percepts": recorders[0].frames} if recorders else {}),
    }  # fmt: skip


def _outcome(trial: IntentTrial, recognised: str) -> str:
    """A trial's outcome in a word or two, for its replay's name."""
    if trial.kind != "request":
        return f"{trial.kind} triggered" if recognised else f"{trial.kind} ignored"
    if not recognised:
        return "not recognised"
    return "recognised" if recognised == trial.target else "wrong object"


class IntentExperiment(TrialExperiment):
    """The intent trials as run, their outcomes, and the settings that made them."""

    def crashed_row(self, trial: IntentTrial) -> dict:
        return {"kind": trial.kind, "target": trial.target, "arm": trial.arm, "recognised": ""}

    def described(self, trial: IntentTrial) -> dict:
        """The target's side as the person sees it, besides the layout (`TrialExperiment`)."""
        return {"position": trial.position, **super().described(trial)}

    def rows(self) -> list[dict]:
        return with_arm_aims(super().rows(), [trial.scenario for trial in self.trials])


def run_intent_experiment(
    base: Scenario,
    trials: int = 60,
    distractors: int = 0,
    seed: int = 0,
    workers: int | None = None,
    ray_address: str | None = None,
    progress: Progress | None = None,
    html_dir: Path | None = None,
    layouts: str = "scenario",
    scenario_dir: Path | None = None,
) -> IntentExperiment:
    """Make and run the trials; `summarise` turns the result into the paper's table. With
    `html_dir`, a replay of each trial is written there, named by trial and outcome; with
    `layouts` "generated", each trial has a layout of its own (`layouts.generate_layout`), and
    with `scenario_dir` each trial's scenario is written there as it ran."""
    counts = (trials, distractors)
    return IntentExperiment.run(make_trials, run_intent_trial, base, counts, seed, workers,
                                ray_address, progress, html_dir, layouts,
                                scenario_dir)  # fmt: skip


def _arm_alone(requests: list[dict], success: list[bool]) -> dict:
    """How often the arm alone pointed nearest the target, its mean error, and of the requests
    whose arm pointed nearer another object (`misaimed`), how many were read right anyway."""
    misaimed = [
        s for r, s in zip(requests, success, strict=True) if r["arm_nearest"] != r["target"]
    ]
    errors = [r["arm_error_deg"] for r in requests]
    return {
        "nearest_target_rate": rate(len(requests) - len(misaimed), len(requests)),
        "error_deg_mean": float(np.mean(errors)) if errors else math.nan,
        "misaimed": len(misaimed),
        "misaimed_recognised": sum(misaimed),
        "breuer": {"targets_found": BREUER_TARGETS_FOUND,
                   "error_deg_mean": BREUER_POINTING_ERROR_DEG},
    }  # fmt: skip


def _cue_limit(requests: list[dict], success: list[bool]) -> dict:
    """How often the person's arm and face together most likely asked for the target (the most
    a recogniser reading both exactly could read right: `arm_aim.most_likely_asked`), by class
    too, and of the requests whose arm and face asked for another object (`astray`), how many
    were read right anyway."""
    asked = lambda row: row["cues_most_likely"] == row["target"]  # noqa: E731
    astray = [s for r, s in zip(requests, success, strict=True) if not asked(r)]
    return {
        "success_rate": rate(len(requests) - len(astray), len(requests)),
        "by_class": by_class(requests, asked),
        "astray": len(astray),
        "astray_recognised": sum(astray),
    }


def summarise(experiment: IntentExperiment) -> dict:
    """The JSON summary: success overall, by position and by object beside the paper's figures,
    a confusion matrix, the false-trigger rate, latency from pointing onset, failures, how
    often the person's arm alone pointed nearest the target (`arm_alone`, beside Breuer et
    al.'s figures; `misaimed_recognised`: of the requests whose arm pointed nearer another
    object, those the robot still read right), the most a recogniser of the arm and the face
    could read right (`cue_limit`), and the person model and settings the trials
    ran with. A failed request counts as not recognised; a failed distractor trial is left out
    of the false-trigger rate, which it would otherwise lower (both are listed under
    `failures`)."""
    rows = experiment.rows()
    requests = [row for row in rows if row["kind"] == "request"]
    distractors = [row for row in rows if row["kind"] != "request"]
    distractors_run = [row for row in distractors if not row["error"]]
    sides = object_positions(experiment.base)
    names = [obj.name for obj in experiment.base.objects]
    names += sorted({row["target"] for row in requests} - set(names))  # generated layouts'
    success = [row["recognised"] == row["target"] for row in requests]
    by_object = {
        name: rate(sum(s for r, s in zip(requests, success, strict=True) if r["target"] == name),
                    sum(r["target"] == name for r in requests))
        for name in names
    }  # fmt: skip
    by_position = {}
    for side in POSITIONS:
        picked = [s for r, s in zip(requests, success, strict=True) if r["position"] == side]
        by_position[side] = rate(sum(picked), len(picked))
    confusion = {name: dict.fromkeys([*names, "none"], 0) for name in names}
    for row in requests:
        recognised = row["recognised"] or "none"
        confusion[row["target"]][recognised] = confusion[row["target"]].get(recognised, 0) + 1
    latencies = [r["latency_s"] for r, s in zip(requests, success, strict=True) if s]
    failures = [{"index": row["index"], "error": row["error"]} for row in rows if row["error"]]
    return {
        "trials": len(requests),
        "distractor_trials": len(distractors),
        "distractor_trials_run": len(distractors_run),  # false_trigger_rate's denominator
        "success_rate": rate(sum(success), len(requests)),
        "by_position": by_position,
        "paper_by_position": PAPER_BY_POSITION,
        "paper_trials_by_position": PAPER_TRIALS_BY_POSITION,
        "object_positions": sides,
        "by_object": by_object,
        "confusion": confusion,
        "false_trigger_rate": rate(
            sum(bool(r["recognised"]) for r in distractors_run), len(distractors_run)
        ),  # fmt: skip
        "latency_s": {
            "median": float(np.median(latencies)) if latencies else math.nan,
            "p95": float(np.percentile(latencies, 95)) if latencies else math.nan,
        },
        "by_class": by_class(requests, lambda row: row["recognised"] == row["target"]),
        "false_triggers_by_class": by_class(distractors_run, lambda row: bool(row["recognised"])),
        "requests_by_position": {
            side: sum(r["position"] == side for r in requests) for side in POSITIONS
        },
        "watched_raised": sum(row.get("watch_lift_m", 0.0) > 0 for row in rows),
        "failed_trials": len(failures),
        "failures": failures,
        "arm_alone": _arm_alone(requests, success),
        "cue_limit": _cue_limit(requests, success),
        "person_model": {
            "imprecision": dataclasses.asdict(experiment.base.person.imprecision),
            "variation": dataclasses.asdict(experiment.base.person.variation),
        },
        "intent_params": dataclasses.asdict(experiment.base.intent),
        "layouts": experiment.layouts,
        "active_gaze": experiment.base.perception.active_gaze,
        "seed": experiment.seed,
        "wall_s": experiment.wall_s,
    }

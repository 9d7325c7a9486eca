"""The handover experiment (paper 4.3): the person asks for one object by looking and pointing;
the robot must recognise it, fetch it and hand it over where both can reach, and the person
takes it. On refusal trials the person never reaches, and the robot must give up gracefully:
time out holding the object, touching nothing.

The trials (`handover_trials`) run on the shared trial runner in worker processes or on Ray.
Each is scored against the world's truth (`handover_scoring`) the way HandoverSim counts: a
handover succeeds when the person holds the object asked for and the robot has released it,
within the time limit, with no contact with the person and no drop; plus our own failure
classes. The robot itself decided from its percepts only.
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
from hsr_handover.experiments.handover.scoring import (
    DROPPED,
    SPILL_TILT_DEG,
    HandoverScorer,
    TrialScore,
)
from hsr_handover.experiments.handover.trials import TIME_LIMIT_S, HandoverTrial, make_trials
from hsr_handover.experiments.layouts import write_trial_scenario
from hsr_handover.experiments.seating import sit_clear
from hsr_handover.experiments.trial_classes import by_class
from hsr_handover.experiments.trials import Progress
from hsr_handover.robot.handover.cycle_types import CycleRecord, Phase
from hsr_handover.scenario import Scenario
from hsr_handover.simulation import Simulation, run_scenario

PAPER = {"retrieval_rate": 0.866, "handover_rate": 0.90, "trials": 60}
"""The paper's real trials (4.3: 20 for each of three objects): the object asked for
retrieved, and handed over."""
FAILURES = (
    "not recognised", "wrong object", "unreachable", "grasp missed", "dropped", "table contact",
    "person contact", "person withdrew", "timeout", "kept presenting", "trial crashed",
)  # fmt: skip
"""A failed trial's class: the first thing that went wrong. HandoverSim counts contact with
the person, drop and timeout; the rest are ours."""
TRIAL_AFTER_CYCLE_S = 0.5
"""s a trial runs on once the robot's cycle is over (the demo's run shows 2 s more): the
handover was decided before the retreat, and an object put back has settled by then."""
SUCCESS_HOLD_S = 0.1
"""s the person must have held the object, released, for the handover to be complete
(HandoverSim's success threshold): its episode ends there, so what happens after is not a
failure of the handover (`person_contacts` still counts it)."""


def run_handover_trial(trial: HandoverTrial) -> dict:
    """Simulate one trial and score it: a row of the experiment's table."""
    start = time.perf_counter()
    scorers: list[HandoverScorer] = []

    def scorer(simulation: Simulation) -> HandoverScorer:
        scorers.append(HandoverScorer(simulation, trial.target, trial.scenario.table.height))
        return scorers[-1]

    replay = replay_while_running(trial.replay_dir, trial.index)
    moved_back = sit_clear(trial.scenario)
    write_trial_scenario(trial.scenario_dir, trial.index, trial.scenario)
    report = run_scenario(
        trial.scenario, replay, monitor_factory=scorer, after_cycle_s=TRIAL_AFTER_CYCLE_S
    )
    names = {obj.color: obj.name for obj in trial.scenario.objects}
    row = judge(trial, report.cycle or CycleRecord(), scorers[0].score, report.person_holds, names,
                report.person_repeated)  # fmt: skip
    outcome = "handed over" if row["handed_over"] else row["failure"] or "refused, kept"
    name_replay(report.replay, trial.index, outcome)
    person = trial.scenario.person
    return {
        **row, "seed": trial.scenario.simulation.seed, "person_height_m": person.height,
        "person_x_m": person.position[0], "person_y_m": person.position[1],
        "person_yaw_rad": person.yaw, "person_moved_back_m": moved_back,
        "sim_s": report.sim_time,
        "wall_s": time.perf_counter() - start,
    }  # fmt: skip


def judge(
    trial: HandoverTrial,
    cycle: CycleRecord,
    score: TrialScore,
    holds: str,
    names: dict[str, str],
    repeated: float = math.nan,
) -> dict:
    """One trial's outcome from the robot's record (`cycle`), the truth (`score`), what the
    person holds at the end and when they asked again for want of a response (`repeated`,
    s; NaN if they did not); `names` maps the robot's labels (colours) to object names."""
    recognised = _name(names, cycle.target)
    corrected = cycle.first_target is not None
    # An object lifted first and then put back at the person's correction is no failure.
    retrieved = trial.target in score.lifted and (
        corrected or not _wrong_first(trial.target, score)
    )
    released = Phase.RELEASE.value in cycle.phase_times
    release_time = cycle.phase_times.get(Phase.RELEASE.value, math.nan)
    complete = max(score.gripped, release_time) + SUCCESS_HOLD_S  # nan until both happened
    failure = _first_failure(trial, cycle, score, recognised, complete)
    handed_over = trial.takes and not failure and released and holds == trial.target
    if trial.takes and not failure and not handed_over:
        failure = "timeout"  # the cycle was not over, or over with the object elsewhere
    graceful = _graceful(trial, cycle, score)
    if not trial.takes and not failure and not graceful:
        failure = "kept presenting"  # a refusal the robot did not give up on
    return {
        "index": trial.index, "target": trial.target, "arm": trial.arm, "takes": trial.takes,
        "reaction_s": trial.reaction_s, "held_out": bool(trial.hold_out),
        "recognised": recognised,
        "first_recognised": _name(names, cycle.first_target) or recognised,
        "corrected": corrected, "corrected_s": cycle.corrected_time - trial.pointing_onset,
        "repeated": not math.isnan(repeated), "repeated_s": repeated - trial.pointing_onset,
        "outcome": cycle.outcome,
        "robot_failure": cycle.failure.value if cycle.failure else "", "reason": cycle.reason,
        "retrieved": retrieved, "handed_over": handed_over, "person_holds": holds,
        "graceful": graceful, "failure": failure,
        "table_contact": not math.isnan(score.table_contact),
        "person_contact": not math.isnan(score.person_contact),
        "knocked": ",".join(sorted(set(score.knocked) - set(score.lifted))),
        "set_down_m": max((abs(float(v)) for v in score.set_down.values()), default=math.nan),
        "person_knocked": ",".join(sorted(score.person_knocked)),
        "table_contact_s": score.table_contact, "person_contact_s": score.person_contact,
        "dropped_s": score.dropped, "gripped_s": score.gripped, "released_s": release_time,
        "clearance_table_m": score.clearance_table, "clearance_person_m": score.clearance_person,
        "table_height_error_m": score.table_height_error,
        "held_tilt_deg": score.held_tilt,
        "spilled": _is_cup(trial) and score.held_tilt > SPILL_TILT_DEG,
        "recognition_s": cycle.recognised_time - trial.pointing_onset,
        "planning_s": cycle.planning_s, "execution_s": release_time - cycle.recognised_time,
        "watch_lift_m": cycle.watch_lift, "handed_to": cycle.receiving,
        "error": "",
    }  # fmt: skip


def _name(names: dict[str, str], label: str | None) -> str:
    """The object's name for the robot's `label` ("" for None)."""
    return names.get(label, label) if label else ""


def _is_cup(trial: HandoverTrial) -> bool:
    """Whether the object asked for is a cup (it may hold a drink)."""
    return any(obj.name == trial.target and obj.shape == "cup" for obj in trial.scenario.objects)


def _wrong_first(target: str, score: TrialScore) -> bool:
    """Whether another object was picked up before the target (or instead of it)."""
    when = score.lifted.get(target, math.inf)
    return any(name != target and at < when for name, at in score.lifted.items())


def _first_failure(
    trial: HandoverTrial, cycle: CycleRecord, score: TrialScore, recognised: str, complete: float
) -> str:
    """The earliest thing that went wrong before the handover was `complete` (s; NaN if it
    never was), or ""; a refusal trial's robot timing out, which is what it should do, is not
    a failure."""
    if not recognised:
        return "not recognised"
    events = [(cycle.recognised_time, "wrong object")] if recognised != trial.target else []
    events += [(at, name) for at, name in ((score.dropped, "dropped"),
               (score.table_contact, "table contact"), (score.person_contact, "person contact"))
               if not math.isnan(at)]  # fmt: skip
    if cycle.failure is not None:  # it failed on entering its retreat
        at = cycle.phase_times.get(Phase.RETREAT.value, cycle.phase_times.get(Phase.FAILED.value))
        events.append((at, cycle.failure.value))
    if not trial.takes:
        events = [event for event in events if event[1] not in ("timeout", "person withdrew")]
    events = [event for event in events if not event[0] >= complete]
    return min(events)[1] if events else ""


def _graceful(trial: HandoverTrial, cycle: CycleRecord, score: TrialScore) -> bool:
    """A refusal handled as it should be: the robot gave up waiting and kept the object, with
    no drop and no contact."""
    if trial.takes:
        return False
    untouched = all(math.isnan(at) for at in (score.dropped, score.table_contact,
                                               score.person_contact))  # fmt: skip
    return cycle.failure is not None and cycle.failure.value == "timeout" and untouched


class HandoverExperiment(TrialExperiment):
    """The handover trials as run, their outcomes, and the settings that made them."""

    def crashed_row(self, trial: HandoverTrial) -> dict:
        return {"target": trial.target, "arm": trial.arm, "takes": trial.takes,
                "retrieved": False, "handed_over": False, "graceful": False,
                "failure": "trial crashed"}  # fmt: skip

    def rows(self) -> list[dict]:
        return with_arm_aims(super().rows(), [trial.scenario for trial in self.trials])


def run_handover_experiment(
    base: Scenario,
    trials: int = 60,
    refusals: int = 0,
    seed: int = 0,
    workers: int | None = None,
    ray_address: str | None = None,
    progress: Progress | None = None,
    html_dir: Path | None = None,
    layouts: str = "scenario",
    scenario_dir: Path | None = None,
) -> HandoverExperiment:
    """Make and run the trials; `summarise` turns the result into the table. With `html_dir`,
    a replay of each trial is written there, named by trial and outcome; with `layouts`
    "generated", each trial has a layout of its own (`layouts.generate_layout`), and with
    `scenario_dir` each trial's scenario is written there as it ran."""
    counts = (trials, refusals)
    return HandoverExperiment.run(make_trials, run_handover_trial, base, counts, seed, workers,
                                  ray_address, progress, html_dir, layouts,
                                  scenario_dir)  # fmt: skip


def _median(values: list[float]) -> float:
    return _of_finite(np.median, values)


def _most(values: list[float]) -> float:
    return _of_finite(max, values)


def _of_finite(statistic, values: list[float]) -> float:
    """`statistic` of the finite `values` (NaN marks a trial without the figure); NaN if none."""
    finite = [v for v in values if math.isfinite(v)]
    return float(statistic(finite)) if finite else math.nan


def summarise(experiment: HandoverExperiment) -> dict:
    """The JSON summary: retrieval and handover rates beside the paper's, how often the object
    first fetched was the one asked for, in how many trials the person corrected the robot
    (which put the first object back and fetched the other) and in how many they asked again
    for want of a response, failures per class, contacts, objects knocked and objects lifted
    by mistake that did not end standing where they stood (`objects_misplaced`), the medians
    of recognition, planning and execution time over successful trials, the least clearance,
    the most the perceived table top was off the true one's height in any trial, the cups that
    tilted past spilling while carried and the most any object asked for tilted, in how many
    trials the robot watched from a raised torso, refusals handled, and the settings the trials
    ran with."""
    rows = experiment.rows()
    requests = [row for row in rows if row["takes"]]
    refusals = [row for row in rows if not row["takes"]]
    succeeded = [row for row in requests if row["handed_over"]]
    failures = dict.fromkeys(FAILURES, 0)
    for row in rows:
        if row["failure"]:
            failures[row["failure"]] += 1
    ran = [row for row in rows if not row["error"]]
    return {
        "trials": len(requests),
        "retrieval_rate": rate(sum(row["retrieved"] for row in requests), len(requests)),
        "handover_rate": rate(len(succeeded), len(requests)),
        "first_choice_rate": rate(
            sum(row.get("first_recognised") == row["target"] for row in requests), len(requests)
        ),  # fmt: skip
        "corrected": sum(bool(row.get("corrected")) for row in requests),
        "repeated": sum(bool(row.get("repeated")) for row in requests),
        "paper": PAPER,
        "failures": failures,
        "table_contacts": sum(row["table_contact"] for row in ran),
        "person_contacts": sum(row["person_contact"] for row in ran),
        "objects_knocked": sum(bool(row["knocked"]) for row in ran),
        "objects_misplaced": sum(bool(row.get("set_down_m", math.nan) > DROPPED) for row in ran),
        "person_knocked": sum(bool(row["person_knocked"]) for row in ran),
        "cups_spilled": sum(bool(row.get("spilled")) for row in ran),
        "most_held_tilt_deg": _most([row.get("held_tilt_deg", math.nan) for row in ran]),
        "times_s": {
            key: _median([row[f"{key}_s"] for row in succeeded])
            for key in ("recognition", "planning", "execution")
        },
        "min_clearance_m": min(
            (min(row["clearance_table_m"], row["clearance_person_m"]) for row in ran),
            default=math.nan,
        ),
        "table_height_error_m": _most([row.get("table_height_error_m", math.nan) for row in ran]),
        "watched_raised": sum(row["watch_lift_m"] > 0 for row in ran),
        "handed_to_left": sum(row.get("handed_to") == "l" for row in ran),
        "by_class": by_class(requests, lambda row: row["handed_over"]),
        "refusal_trials": len(refusals),
        "graceful_refusal_rate": rate(sum(row["graceful"] for row in refusals), len(refusals)),
        "time_limit_s": TIME_LIMIT_S,
        "crashed": [{"index": row["index"], "error": row["error"]} for row in rows if row["error"]],
        "person_model": {
            "imprecision": dataclasses.asdict(experiment.base.person.imprecision),
            "variation": dataclasses.asdict(experiment.base.person.variation),
            "receiving": dataclasses.asdict(experiment.base.person.receiving),
        },
        "layouts": experiment.layouts,
        "active_gaze": experiment.base.perception.active_gaze,
        "seed": experiment.seed,
        "wall_s": experiment.wall_s,
    }

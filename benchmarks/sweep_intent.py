"""Where the intent recogniser's defaults come from: simulate intent trials once, keeping what the
recogniser was given each frame (the lifted skeleton and the confirmed detections), then replay
the recogniser offline over a grid of thresholds and pointing rays on those same percepts.
Prints success, false triggers and latency for every setting, the defaults' row marked, so a
default is the measured best, not a guess.

    python benchmarks/sweep_intent.py [--trials 30] [--distractors 10] [--seed 5] [--workers 2]
        [--scenario scenarios/intent_reference.yaml] [--layouts scenario|generated]
        [--save percepts.pkl | --load percepts.pkl]
"""

from __future__ import annotations

import argparse
import dataclasses
import itertools
import pickle
import time
from pathlib import Path

import numpy as np

from hsr_handover.experiments.intent.percepts import replay_intent
from hsr_handover.experiments.intent.trial import run_intent_trial
from hsr_handover.experiments.intent.trials import make_trials
from hsr_handover.experiments.trials import TrialProgress, run_trials
from hsr_handover.robot.intent import IntentParams
from hsr_handover.scenario import load_scenario

SCENARIO = Path(__file__).resolve().parents[1] / "scenarios" / "intent_reference.yaml"
GRID = {
    "pointing_ray": ("shoulder_wrist", "elbow_wrist"),
    "d_min": (0.3, 0.4),
    "gaze_tolerance_deg": (8.0, 12.0),
    "gaze_weight": (0.4, 1.0),
    "t_max": (0.3, 0.5),
    "steady_deg_s": (30.0, 1000.0),
    "smoothing_s": (0.6, 1.0),
    "bent_gap_s": (0.0, 0.3),
    "gaze_pitch_tolerance_deg": (8.0, 90.0),
}


def record(args: argparse.Namespace):
    base = load_scenario(args.scenario)
    trials = [
        dataclasses.replace(trial, record_percepts=True)
        for trial in make_trials(base, args.trials, args.distractors, args.seed, args.layouts)
    ]
    start = time.perf_counter()
    outcomes = run_trials(run_intent_trial, trials, args.workers, progress=TrialProgress())
    print(f"simulated {len(trials)} trials in {time.perf_counter() - start:.0f} s")
    return base, trials, outcomes


def score(base, trials, outcomes, params: IntentParams) -> dict:
    """Success over requests, false triggers over distractors, latency from pointing onset."""
    hits, requests, triggers, distractors, latencies = 0, 0, 0, 0, []
    for trial, outcome in zip(trials, outcomes, strict=True):
        if not outcome.ok:
            continue
        names = {obj.color: obj.name for obj in trial.scenario.objects}
        state = replay_intent(outcome.result["percepts"], params)
        recognised = names.get(state.target, "") if state.target else ""
        if trial.kind == "request":
            requests += 1
            if recognised == trial.target:
                hits += 1
                latencies.append(state.recognised_time - trial.pointing_onset)
        else:
            distractors += 1
            triggers += bool(recognised)
    return {
        "success": hits / max(requests, 1), "false": triggers / max(distractors, 1),
        "latency": float(np.median(latencies)) if latencies else float("nan"),
    }  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", type=Path, default=SCENARIO)
    parser.add_argument("--trials", type=int, default=30)
    parser.add_argument("--distractors", type=int, default=10)
    parser.add_argument("--seed", type=int, default=5)
    parser.add_argument("--workers", type=int)
    parser.add_argument("--layouts", choices=("scenario", "generated"), default="scenario")
    parser.add_argument("--save", type=Path, help="keep the recorded percepts here")
    parser.add_argument("--load", type=Path, help="sweep percepts recorded before")
    args = parser.parse_args()
    if args.load:
        base, trials, outcomes = pickle.loads(args.load.read_bytes())
    else:
        base, trials, outcomes = record(args)
        if args.save:
            args.save.write_bytes(pickle.dumps((base, trials, outcomes)))
    failed = [outcome.error for outcome in outcomes if not outcome.ok]
    print(f"{len(trials)} trials, {len(failed)} failed {failed}")
    defaults = IntentParams()
    print(f"{'setting':90s} success  false  latency")
    for values in itertools.product(*GRID.values()):
        setting = dict(zip(GRID, values, strict=True))
        params = dataclasses.replace(defaults, **setting)
        result = score(base, trials, outcomes, params)
        mark = " <- defaults" if params == defaults else ""
        print(f"{str(setting):90s} {result['success']:6.1%} {result['false']:6.1%} "
              f"{result['latency']:6.2f} s{mark}")  # fmt: skip


if __name__ == "__main__":
    main()

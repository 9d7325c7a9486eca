"""Active perception on layouts nobody chose: the intent and handover experiments on generated
layouts (`--layouts generated`), the robot turning its head to find the person
(`perception.active_gaze`), beside the same trials with the head held still at the HSR's
default posture (the baseline), in one run. Prints each experiment's success (and false
triggers), its breakdown by class and its wall time; `--json` keeps the four summaries.

    python benchmarks/bench_active_perception.py [--requests 120] [--distractors 40]
        [--handovers 60] [--baseline-share 1.0] [--seed 1] [--workers 2] [--json OUT.json]
        [--only active|baseline]

`--baseline-share` runs that share of each count with the head still (a fraction saves time:
the baseline's shortfall shows on fewer trials).
"""

from __future__ import annotations

import argparse
import copy
import json
import time
from pathlib import Path

from hsr_handover.experiments.handover import trial as handover
from hsr_handover.experiments.intent import trial as intent
from hsr_handover.experiments.reporting import json_safe
from hsr_handover.experiments.trial_classes import class_lines
from hsr_handover.experiments.trials import TrialProgress
from hsr_handover.scenario import load_scenario

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"
INTENT = SCENARIOS / "intent_reference.yaml"
HANDOVER = SCENARIOS / "handover_reference.yaml"
TARGETS = "targets: intent >= 97 % with <= 2 % false triggers; handover >= 95 %, no contact"


def _scenario(path: Path, active: bool):
    scenario = copy.deepcopy(load_scenario(path))
    scenario.perception.active_gaze = active
    return scenario


def _intent(args, active: bool, share: float) -> dict:
    requests, distractors = round(args.requests * share), round(args.distractors * share)
    experiment = intent.run_intent_experiment(
        _scenario(INTENT, active), requests, distractors, args.seed, args.workers,
        progress=TrialProgress(), layouts="generated",
    )  # fmt: skip
    return intent.summarise(experiment)


def _handover(args, active: bool, share: float) -> dict:
    experiment = handover.run_handover_experiment(
        _scenario(HANDOVER, active), round(args.handovers * share), 0, args.seed, args.workers,
        progress=TrialProgress(), layouts="generated",
    )  # fmt: skip
    return handover.summarise(experiment)


def _percent(value: float) -> str:
    return f"{100 * value:5.1f} %"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--requests", type=int, default=120)
    parser.add_argument("--distractors", type=int, default=40)
    parser.add_argument("--handovers", type=int, default=60)
    parser.add_argument("--baseline-share", type=float, default=1.0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--workers", type=int)
    parser.add_argument("--json", type=Path)
    parser.add_argument(
        "--only", choices=("active", "baseline"), help="run one side alone (default: both)"
    )
    args = parser.parse_args()
    runs = {}
    for name, run, active, share in (
        ("intent, active gaze", _intent, True, 1.0),
        ("intent, head still (baseline)", _intent, False, args.baseline_share),
        ("handover, active gaze", _handover, True, 1.0),
        ("handover, head still (baseline)", _handover, False, args.baseline_share),
    ):
        skipped = args.only is not None and (args.only == "active") != active
        if skipped or round(share * (args.requests if run is _intent else args.handovers)) == 0:
            continue
        start = time.perf_counter()
        print(name)
        runs[name] = run(args, active, share)
        runs[name]["bench_wall_s"] = time.perf_counter() - start
    print(f"\ngenerated layouts, seed {args.seed}; {TARGETS}")
    print(f"{'experiment':34s} {'trials':>7s} {'success':>8s} {'false':>8s} {'wall':>8s}")
    for name, summary in runs.items():
        is_intent = "success_rate" in summary
        success = summary["success_rate"] if is_intent else summary["handover_rate"]
        false = _percent(summary["false_trigger_rate"]) if is_intent else "     -"
        print(f"{name:34s} {summary['trials']:7d} {_percent(success):>8s} {false:>8s} "
              f"{summary['bench_wall_s']:7.0f}s")  # fmt: skip
    for name, summary in runs.items():
        print()
        print("\n".join(class_lines(name, summary["by_class"])))
        if "handover_rate" in summary:
            print(f"  contacts: table {summary['table_contacts']}, person "
                  f"{summary['person_contacts']}; failures {summary['failures']}")  # fmt: skip
    if args.json is not None:
        args.json.write_text(json.dumps(json_safe(runs), indent=2))


if __name__ == "__main__":
    main()

"""How the intent recogniser holds up as the pose detector and the person err more: the intent
experiment across detector noise (ideal, realistic, 1.5x and 2x realistic; see
`hsr_handover.world.sensors.detector_model`) and the person's pointing error (5, 7.3, 11 and 15 deg
mean; Breuer et al. measured 7.3), every setting on the same trials (the same layouts, people
and scripts, drawn from one seed), all trials in one parallel pool. Prints success by position
and false triggers for each setting beside the paper's figures, and writes JSON, CSV and a plot.

    python benchmarks/sweep_detector.py [--trials 16] [--distractors 6] [--seed 1] [--workers 2]
        [--ray-address ADDR] [--scenario scenarios/intent_reference.yaml]
        [--layouts generated|scenario]
        [--detectors ideal,realistic,1.5,2] [--pointing 5,7.3,11,15]
        [--json sweep.json] [--csv sweep.csv] [--plot sweep.png]
"""

from __future__ import annotations

import argparse
import copy
import json
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from scipy.stats import binomtest  # noqa: E402

from hsr_handover.experiments.intent.trial import (  # noqa: E402
    PAPER_BY_POSITION,
    POSITIONS,
    IntentExperiment,
    run_intent_trial,
    summarise,
)
from hsr_handover.experiments.intent.trials import make_trials  # noqa: E402
from hsr_handover.experiments.reporting import write_json, write_rows  # noqa: E402
from hsr_handover.experiments.trials import TrialProgress, run_trials  # noqa: E402
from hsr_handover.literature import BREUER_POINTING_ERROR_DEG  # noqa: E402
from hsr_handover.scenario import Scenario, load_scenario  # noqa: E402

SCENARIO = Path(__file__).resolve().parents[1] / "scenarios" / "intent_reference.yaml"
PAPER_SUCCESS = sum(PAPER_BY_POSITION.values()) / len(PAPER_BY_POSITION)
COLUMNS = ("detector", "pointing_error_deg", "requests", "success", "success_low",
           "success_high", *POSITIONS, "distractors", "distractors_run", "false_triggers",
           "false_low", "false_high", "latency_median_s", "failed")  # fmt: skip


def interval(rate: float, count: int) -> tuple[float, float]:
    """The 95 % Wilson interval of a rate over `count` trials ((0, 1) without any)."""
    if count == 0:
        return 0.0, 1.0
    ci = binomtest(round(rate * count), count).proportion_ci(0.95, method="wilson")
    return float(ci.low), float(ci.high)


def with_intervals(row: dict) -> dict:
    """The row with the 95 % Wilson intervals of its success and false-trigger rates (over the
    distractors that ran; a row saved without that count: over all its distractors)."""
    distractors = row.get("distractors_run", row["distractors"])
    row["success_low"], row["success_high"] = interval(row["success"], row["requests"])
    row["false_low"], row["false_high"] = interval(row["false_triggers"], distractors)
    return row


def detector_setting(name: str) -> tuple[str, float]:
    """(preset, scale) of a detector level: "ideal", "realistic" or a multiple of realistic."""
    if name in ("ideal", "realistic"):
        return name, 1.0
    try:
        scale = float(name)
    except ValueError:
        scale = -1.0
    if not 0 <= scale <= 10:
        raise ValueError(f"expected ideal, realistic or a multiple in [0, 10], got {name!r}")
    return "realistic", scale


def _detector_levels(text: str) -> list[str]:
    levels = text.split(",")
    try:
        for level in levels:
            detector_setting(level)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None
    return levels


def _pointing_errors(text: str) -> list[float]:
    try:
        values = [float(value) for value in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected numbers separated by commas, got {text!r}"
        ) from None
    if not all(0 <= value <= 45 for value in values):
        raise argparse.ArgumentTypeError(f"expected each in [0, 45] deg, got {text!r}")
    return values


def configured(base: Scenario, detector: str, pointing_deg: float) -> Scenario:
    """The scenario with the detector level and the person's mean pointing error."""
    scenario = copy.deepcopy(base)
    preset, scale = detector_setting(detector)
    scenario.perception.detector.preset, scenario.perception.detector.scale = preset, scale
    scenario.person.imprecision.pointing_error_deg = pointing_deg
    return scenario


def run(args: argparse.Namespace) -> list[dict]:
    base = load_scenario(args.scenario)
    settings = [(d, p) for d in args.detectors for p in args.pointing]
    groups, specs = [], []
    for detector, pointing in settings:
        scenario = configured(base, detector, pointing)
        trials = make_trials(
            scenario, args.trials, args.distractors, args.seed, layouts=args.layouts
        )
        groups.append((detector, pointing, scenario, len(specs), len(trials)))
        specs += trials
    start = time.perf_counter()
    outcomes = run_trials(run_intent_trial, specs, args.workers, args.ray_address,
                          progress=TrialProgress())  # fmt: skip
    wall = time.perf_counter() - start
    print(f"{len(specs)} trials of {len(settings)} settings in {wall:.0f} s")
    rows = []
    for detector, pointing, scenario, first, count in groups:
        experiment = IntentExperiment(specs[first : first + count], outcomes[first : first + count],
                                      scenario, args.seed, wall, args.layouts)  # fmt: skip
        summary = summarise(experiment)
        rows.append(with_intervals({
            "detector": detector, "pointing_error_deg": pointing,
            "requests": summary["trials"], "success": summary["success_rate"],
            **{side: summary["by_position"][side] for side in POSITIONS},
            "distractors": summary["distractor_trials"],
            "distractors_run": summary["distractor_trials_run"],
            "false_triggers": summary["false_trigger_rate"],
            "latency_median_s": summary["latency_s"]["median"],
            "failed": summary["failed_trials"],
        }))  # fmt: skip
    return rows


def print_table(rows: list[dict]) -> None:
    sides = " ".join(f"{side:>7s}" for side in POSITIONS)
    print(f"{'detector':>10s} {'pointing':>8s} {'success (95 % CI)':>20s} {sides} "
          f"{'false (95 % CI)':>18s} {'latency':>8s} {'failed':>6s}")  # fmt: skip
    for row in rows:
        sides = " ".join(f"{100 * row[side]:6.1f}%" for side in POSITIONS)
        success = (
            f"{100 * row['success']:5.1f}% ({100 * row['success_low']:.0f}-"
            f"{100 * row['success_high']:.0f})"
        )
        false = (
            f"{100 * row['false_triggers']:5.1f}% ({100 * row['false_low']:.0f}-"
            f"{100 * row['false_high']:.0f})"
        )
        print(f"{row['detector']:>10s} {row['pointing_error_deg']:7.1f}° {success:>20s} "
              f"{sides} {false:>18s} {row['latency_median_s']:7.2f}s "
              f"{row['failed']:6d}")  # fmt: skip
    paper = " ".join(f"{100 * PAPER_BY_POSITION[side]:6.1f}%" for side in POSITIONS)
    success = f"{100 * PAPER_SUCCESS:5.1f}%"
    print(f"{'paper':>10s} {BREUER_POINTING_ERROR_DEG:7.1f}° {success:>20s} {paper}"
          "  (60 real trials with OpenPose; no false-trigger figure)")  # fmt: skip


def plot(rows: list[dict], path: Path) -> None:
    """Success and false triggers against the pointing error, one line per detector level with
    its 95 % intervals, the paper's success marked at Breuer's 7.3 deg."""
    figure, (success, false) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    for k, detector in enumerate(dict.fromkeys(row["detector"] for row in rows)):
        mine = [row for row in rows if row["detector"] == detector]
        x = [row["pointing_error_deg"] + 0.15 * k for row in mine]  # apart, so the bars show
        label = detector if detector in ("ideal", "realistic") else f"{detector} x realistic"
        for axes, key, name in (
            (success, "success", "success"),
            (false, "false_triggers", "false"),
        ):
            y = [100 * row[key] for row in mine]
            low = [y_ - 100 * row[f"{name}_low"] for y_, row in zip(y, mine, strict=True)]
            high = [100 * row[f"{name}_high"] - y_ for y_, row in zip(y, mine, strict=True)]
            axes.errorbar(x, y, yerr=[low, high], fmt="o-", capsize=3, label=label)
    success.plot([BREUER_POINTING_ERROR_DEG], [100 * PAPER_SUCCESS], "k*", markersize=12,
                 label="paper (real OpenPose)")  # fmt: skip
    success.set(xlabel="person's mean pointing error (deg)", ylabel="requests recognised (%)",
                ylim=(0, 102), title="Intent success")  # fmt: skip
    false.set(xlabel="person's mean pointing error (deg)", ylabel="distractors triggered (%)",
              ylim=(0, 100),
              title="False triggers")  # fmt: skip
    for axes in (success, false):
        axes.grid(alpha=0.3)
        axes.legend(fontsize=9)
    figure.savefig(path, dpi=150)
    plt.close(figure)


def _saved_rows(path: Path, parser: argparse.ArgumentParser) -> list[dict]:
    try:
        rows = [with_intervals(row) for row in json.loads(path.read_text())["settings"]]
    except (OSError, ValueError, KeyError, TypeError) as error:
        parser.error(f"--replot: expected a JSON file this script wrote, {path}: {error}")
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", type=Path, default=SCENARIO)
    parser.add_argument("--trials", type=int, default=16, help="requests per setting")
    parser.add_argument("--distractors", type=int, default=6, help="distractors per setting")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--workers", type=int)
    parser.add_argument("--ray-address", help="run the trials on this Ray cluster")
    parser.add_argument("--layouts", choices=("scenario", "generated"), default="generated")
    parser.add_argument("--detectors", type=_detector_levels, default="ideal,realistic,1.5,2")
    parser.add_argument("--pointing", type=_pointing_errors, default="5,7.3,11,15",
                        help="mean pointing errors (deg)")  # fmt: skip
    parser.add_argument("--json", type=Path)
    parser.add_argument("--csv", type=Path)
    parser.add_argument("--plot", type=Path)
    parser.add_argument("--replot", type=Path, help="print and plot a saved --json, run nothing")
    args = parser.parse_args()
    for flag in ("json", "csv", "plot"):
        path = getattr(args, flag)
        if path is not None and (path.is_dir() or not path.parent.is_dir()):
            parser.error(f"--{flag}: expected a file in an existing folder, got {path}")
    if args.replot is not None:
        rows = _saved_rows(args.replot, parser)
    else:
        rows = run(args)
    print_table(rows)
    if args.json:
        write_json({"settings": rows, "paper_by_position": PAPER_BY_POSITION,
                    "seed": args.seed, "layouts": args.layouts}, args.json)  # fmt: skip
    if args.csv:
        write_rows(rows, COLUMNS, args.csv)
    if args.plot:
        plot(rows, args.plot)


if __name__ == "__main__":
    main()

"""Write the intent experiment's results: a CSV row per trial, the JSON summary, a text table,
and a figure with the paper's figures beside ours."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only: no display on a robot's or CI's machine
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from hsr_handover.experiments.html_report import RateRow  # noqa: E402
from hsr_handover.experiments.intent.trial import POSITIONS  # noqa: E402
from hsr_handover.experiments.reporting import (  # noqa: E402
    bars_beside_paper,
    counted,
    format_value,
    save_figure,
    write_rows,
)
from hsr_handover.experiments.trial_classes import class_columns, class_lines  # noqa: E402

CSV_COLUMNS = (
    "index", "kind", "target", "arm", "recognised", "latency_s", "recognised_time_s",
    "confidence", "seed", "person_height_m", "person_x_m", "person_y_m", "person_yaw_rad",
    "person_moved_back_m", "watch_lift_m", "sim_s", "wall_s", "arm_nearest", "arm_error_deg",
    "cues_most_likely",
    "error",
)  # fmt: skip


TITLE = "The intent experiment (paper 4.2)"


def trial_columns(rows: list[dict]) -> tuple[str, ...]:
    """The per-trial table's columns: CSV_COLUMNS and the layout's classes."""
    return (*CSV_COLUMNS, *class_columns(rows))


def write_csv(rows: list[dict], path: Path) -> None:
    """One row per trial, failed trials included with their reason."""
    write_rows(rows, trial_columns(rows), path)


def rate_rows(summary: dict) -> list[RateRow]:
    """The summary's rates as counts, ours beside the paper's: by position, all requests (the
    paper's 85.6 % is 154 of its 180), and false triggers (the paper has none to compare)."""
    asked, paper_n = summary["requests_by_position"], summary["paper_trials_by_position"]
    rows = [
        RateRow(f"recognised, {side}", counted(summary["by_position"][side], asked[side]),
                counted(summary["paper_by_position"][side], paper_n))
        for side in POSITIONS
    ]  # fmt: skip
    paper_all = sum(counted(summary["paper_by_position"][side], paper_n)[0] for side in POSITIONS)
    rows.append(RateRow("recognised, all", counted(summary["success_rate"], summary["trials"]),
                        (paper_all, paper_n * len(POSITIONS))))  # fmt: skip
    limit = summary.get("cue_limit")
    if limit:
        rows.append(RateRow("arm and face most likely asked for the target",
                            counted(limit["success_rate"], summary["trials"])))  # fmt: skip
    runs = summary.get("distractor_trials_run", summary["distractor_trials"])
    rows.append(RateRow("false triggers", counted(summary["false_trigger_rate"], runs)))
    return rows


def summary_lines(summary: dict) -> list[str]:
    """The summary as text: success by position beside the paper's, then the rest."""
    percent = lambda value: format_value(100 * value, "5.1f", " %")  # noqa: E731
    lines = [f"{'position':8s} {'ours':>8s} {'paper':>8s}"]
    for side in POSITIONS:
        ours, paper = summary["by_position"][side], summary["paper_by_position"][side]
        lines.append(f"{side:8s} {percent(ours):>8s} {percent(paper):>8s}")
    latency = summary["latency_s"]
    lines += [
        f"success over {summary['trials']} requests: {percent(summary['success_rate'])}",
        f"false triggers over {summary['distractor_trials']} distractor trials: "
        + percent(summary["false_trigger_rate"]),
        f"latency from pointing onset: median {format_value(latency['median'], '.2f', ' s')}, "
        f"p95 {format_value(latency['p95'], '.2f', ' s')}",
        _arm_alone_line(summary["arm_alone"]),
        *_cue_limit_lines(summary["cue_limit"]),
        *_raised_lines(summary.get("watched_raised", 0)),
        *class_lines("requests", summary["by_class"]),
        *class_lines("distractors", summary["false_triggers_by_class"], "false triggers"),
        f"failed trials: {summary['failed_trials']}",
        *(f"  trial {f['index']}: {f['error']}" for f in summary["failures"]),
        f"wall time {summary['wall_s']:.0f} s",
    ]
    return lines


def _raised_lines(raised: int) -> list[str]:
    """How often the watch-only robot watched from a raised torso (nothing when never)."""
    if not raised:
        return []
    return [f"watched from a raised torso in {raised} trials (the objects would have hidden a "
            "pointing arm)"]  # fmt: skip


def _arm_alone_line(arm: dict) -> str:
    """How hard the gestures were: the arm alone, beside Breuer et al.'s forearm."""
    percent = lambda value: format_value(100 * value, ".1f", " %")  # noqa: E731
    degrees = lambda value: format_value(value, ".1f", " deg")  # noqa: E731
    breuer = arm["breuer"]
    return (
        f"the person's arm alone pointed nearest the target in "
        f"{percent(arm['nearest_target_rate'])} of requests, mean error "
        f"{degrees(arm['error_deg_mean'])} (Breuer et al.: {percent(breuer['targets_found'])}, "
        f"{degrees(breuer['error_deg_mean'])}); of the {arm['misaimed']} that pointed nearer "
        f"another object, {arm['misaimed_recognised']} were read right"
    )


def _cue_limit_lines(limit: dict) -> list[str]:
    """The most a recogniser of arm and face could read right, overall and by class."""
    rate = format_value(100 * limit["success_rate"], ".1f", " %")
    return [
        f"the person's arm and face together most likely asked for the target in {rate} of "
        f"requests (the most a recogniser reading both exactly could read right); of the "
        f"{limit['astray']} that asked for another object, {limit['astray_recognised']} were "
        "read right",
        *class_lines("  that limit", limit["by_class"], "target most likely"),
    ]


def plot(summary: dict, path: Path) -> None:
    """Left: success by position with 95 % intervals, ours beside the paper's. Right: the
    confusion matrix, each row (the object asked for) shaded by its share, counts printed."""
    figure, (bars, matrix) = plt.subplots(1, 2, figsize=(11, 4.4))
    asked = summary["requests_by_position"]
    ours = [counted(summary["by_position"][side], asked[side]) for side in POSITIONS]
    paper_n = summary["paper_trials_by_position"]
    paper = [counted(summary["paper_by_position"][side], paper_n) for side in POSITIONS]
    bars_beside_paper(bars, [f"{side}\n(person's view)" for side in POSITIONS], ours, paper)
    bars.set_ylabel("target recognised (% of requests)")
    false_rate = format_value(100 * summary["false_trigger_rate"], ".1f", " %")
    runs = summary.get("distractor_trials_run", summary["distractor_trials"])
    bars.set_title(f"Intent recognition, {summary['trials']} requests\n"
                   f"false triggers {false_rate} of {runs} distractor trials",
                   fontsize="medium")  # fmt: skip
    _confusion(matrix, summary["confusion"])
    figure.tight_layout()
    save_figure(figure, path)


def _confusion(axes, confusion: dict) -> None:
    """Rows: the object asked for; columns: the one recognised or none. Each cell shaded by
    its share of the row (rows may hold different counts) and labelled with its count."""
    names = list(confusion)
    columns = [*names, "none"]
    counts = np.array([[confusion[row][col] for col in columns] for row in names])
    totals = counts.sum(axis=1, keepdims=True)
    shares = np.divide(counts, totals, out=np.zeros(counts.shape), where=totals > 0)
    image = axes.imshow(shares, cmap="Blues", vmin=0.0, vmax=1.0)
    axes.set_xticks(range(len(columns)), columns, rotation=30, ha="right")
    axes.set_yticks(
        range(len(names)), [f"{n} ({t})" for n, t in zip(names, totals[:, 0], strict=True)]
    )
    axes.set_xlabel("recognised")
    axes.set_ylabel("asked for (requests)")
    axes.set_title("Confusion: share of each row, counts printed", fontsize="medium")
    for (row, col), count in np.ndenumerate(counts):
        axes.text(col, row, str(count), ha="center", va="center",
                  color="white" if shares[row, col] > 0.5 else "black")  # fmt: skip
    axes.figure.colorbar(image, ax=axes, fraction=0.046, pad=0.04, label="share of row")

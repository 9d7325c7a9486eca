"""Write the handover experiment's results: a CSV row per trial, the JSON summary, a text table,
and a figure with the paper's figures beside ours."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only: no display on a robot's or CI's machine
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402

from hsr_handover.experiments.handover.scoring import SPILL_TILT_DEG  # noqa: E402
from hsr_handover.experiments.html_report import RateRow  # noqa: E402
from hsr_handover.experiments.reporting import (  # noqa: E402
    bars_beside_paper,
    counted,
    format_value,
    save_figure,
    write_rows,
)
from hsr_handover.experiments.trial_classes import class_columns, class_lines  # noqa: E402

CSV_COLUMNS = (
    "index", "target", "arm", "takes", "reaction_s", "held_out", "recognised", "first_recognised",
    "corrected", "corrected_s", "repeated", "repeated_s", "retrieved",
    "handed_over", "graceful", "failure", "outcome", "robot_failure", "reason", "person_holds",
    "table_contact", "person_contact", "knocked", "person_knocked", "set_down_m", "table_contact_s",
    "person_contact_s", "dropped_s", "gripped_s", "released_s", "clearance_table_m",
    "clearance_person_m", "table_height_error_m", "held_tilt_deg", "spilled", "recognition_s",
    "planning_s", "execution_s",
    "watch_lift_m", "handed_to", "seed", "person_height_m", "person_x_m", "person_y_m",
    "person_yaw_rad", "person_moved_back_m", "sim_s", "wall_s", "arm_nearest", "arm_error_deg",
    "cues_most_likely",
    "error",
)  # fmt: skip


TITLE = "The handover experiment (paper 4.3)"


def trial_columns(rows: list[dict]) -> tuple[str, ...]:
    """The per-trial table's columns: CSV_COLUMNS and the layout's classes."""
    return (*CSV_COLUMNS, *class_columns(rows))


def write_csv(rows: list[dict], path: Path) -> None:
    """One row per trial, crashed trials included with their reason."""
    write_rows(rows, trial_columns(rows), path)


def rate_rows(summary: dict) -> list[RateRow]:
    """The summary's rates as counts, ours beside the paper's: retrieval and handover over the
    requests, the first object recognised being the one asked for, and refusals handled
    gracefully (the paper has none of the last two)."""
    trials, paper, paper_n = summary["trials"], summary["paper"], summary["paper"]["trials"]
    return [
        RateRow("retrieved", counted(summary["retrieval_rate"], trials),
                counted(paper["retrieval_rate"], paper_n)),
        RateRow("handed over", counted(summary["handover_rate"], trials),
                counted(paper["handover_rate"], paper_n)),
        RateRow("first object recognised the one asked for",
                counted(summary["first_choice_rate"], trials)),
        RateRow("refusals handled gracefully",
                counted(summary["graceful_refusal_rate"], summary["refusal_trials"])),
    ]  # fmt: skip


def _percent(value: float) -> str:
    return format_value(100 * value, "5.1f", " %")


def summary_lines(summary: dict) -> list[str]:
    """The summary as text: the two rates beside the paper's, then failures and the rest."""
    paper, times = summary["paper"], summary["times_s"]
    lines = [
        f"{'over ' + str(summary['trials']) + ' requests':22s} {'ours':>8s} {'paper':>8s}",
        f"{'retrieval':22s} {_percent(summary['retrieval_rate']):>8s} "
        f"{_percent(paper['retrieval_rate']):>8s}",
        f"{'handover':22s} {_percent(summary['handover_rate']):>8s} "
        f"{_percent(paper['handover_rate']):>8s}",
        f"the object first fetched was the one asked for in "
        f"{_percent(summary['first_choice_rate']).strip()}; the person corrected the robot in "
        f"{summary['corrected']} (it put the first back and fetched the other) and asked "
        f"again for want of a response in {summary['repeated']}",
        "failures: " + (", ".join(f"{name} {count}" for name, count in
                                  summary["failures"].items() if count) or "none"),
        f"trials with contact: table {summary['table_contacts']}, person "
        f"{summary['person_contacts']}; objects knocked in {summary['objects_knocked']} "
        f"(by the person, before the robot lifted them, in {summary['person_knocked']}); "
        f"objects lifted by mistake and not put back standing in {summary['objects_misplaced']}",
        f"cups tilted past spilling ({SPILL_TILT_DEG:.0f}°) while carried: "
        f"{summary['cups_spilled']}; the most an object asked for tilted: "
        f"{format_value(summary['most_held_tilt_deg'], '.0f', '°')}",
        f"medians over successful handovers: recognition "
        f"{format_value(times['recognition'], '.2f', ' s')}, planning "
        f"{format_value(times['planning'], '.2f', ' s')} (wall), execution "
        f"{format_value(times['execution'], '.1f', ' s')}",
        f"least clearance to the table or the person: "
        f"{format_value(100 * summary['min_clearance_m'], '.1f', ' cm')}",
        f"the perceived table top at most "
        f"{format_value(100 * summary['table_height_error_m'], '.1f', ' cm')} off its height",
    ]  # fmt: skip
    if summary["watched_raised"]:
        lines.append(f"watched from a raised torso in {summary['watched_raised']} trials "
                     "(the objects would have hidden a pointing arm)")  # fmt: skip
    if summary["handed_to_left"]:
        lines.append(f"handed to the left hand in {summary['handed_to_left']} trials "
                     "(no mutual area with the right)")  # fmt: skip
    if summary["refusal_trials"]:
        lines.append(f"refusals handled gracefully: {_percent(summary['graceful_refusal_rate'])} "
                     f"of {summary['refusal_trials']}")  # fmt: skip
    lines += class_lines("requests", summary["by_class"], "handed over")
    lines += [f"  trial {c['index']} crashed: {c['error']}" for c in summary["crashed"]]
    lines.append(f"wall time {summary['wall_s']:.0f} s")
    return lines


def plot(summary: dict, path: Path) -> None:
    """Left: retrieval and handover, ours beside the paper's, each bar labelled. Right:
    failures by class."""
    figure, (bars, failures) = plt.subplots(1, 2, figsize=(11, 4.6))
    keys = ("retrieval_rate", "handover_rate")
    trials, paper_trials = summary["trials"], summary["paper"]["trials"]
    ours = [counted(summary[key], trials) for key in keys]
    paper = [counted(summary["paper"][key], paper_trials) for key in keys]
    bars_beside_paper(bars, ["retrieval", "handover"], ours, paper)
    bars.set_ylabel("requests (%)")
    bars.set_title(f"Handover, {trials} requests (HandoverSim's success)", fontsize="medium")
    counts = {name: count for name, count in summary["failures"].items() if count}
    names = list(counts) or ["none"]
    drawn = failures.barh(names, [counts.get(name, 0) for name in names], color="tab:red",
                          height=0.5)  # fmt: skip
    failures.bar_label(drawn, padding=3, fontsize="small")
    failures.xaxis.set_major_locator(MaxNLocator(integer=True))  # whole trials
    failures.set_xlabel("trials")
    failures.set_title("Failures, first cause per trial", fontsize="medium")
    failures.invert_yaxis()
    wall = summary.get("wall_s")
    if wall:
        figure.suptitle(f"{summary['trials']} requests in {wall / 60:.0f} min", fontsize="small")
    figure.tight_layout()
    save_figure(figure, path)

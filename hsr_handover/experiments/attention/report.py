"""Write the attention experiment's results: CSV time series, JSON summary, the paper's figures
11 (node count and error over time) and 12 (node density per region)."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only: no display on a robot's or CI's machine
import matplotlib.pyplot as plt  # noqa: E402

from hsr_handover.experiments.attention.experiment import AttentionResult  # noqa: E402
from hsr_handover.experiments.reporting import format_value  # noqa: E402
from hsr_handover.experiments.reporting import write_json as write_summary  # noqa: E402


def summary_lines(result: AttentionResult) -> list[str]:
    """The summary as text: the headline figures, then one line per focus phase."""
    lines = [
        "density ratio (attended human region / rest): "
        + format_value(result.density_ratio, ".2f"),
        "node count settles after a shift (slowest):   "
        + format_value(result.settle_time_s, ".2f", " s"),
        "attended region settles (slowest):            "
        + format_value(result.region_settle_time_s, ".2f", " s"),
    ]
    for phase in result.phases:
        lines.append(
            f"  {phase.focus:6s} {phase.target:10s} from {phase.start:4.1f} s: "
            f"{phase.node_count:3d} nodes, "
            f"attended ratio {format_value(phase.attended_ratio, '5.2f')} "
            f"(gain {format_value(phase.attention_gain, '4.2f')}), "
            f"count settled in {format_value(phase.settle_time_s, '.2f', ' s')}, "
            f"region in {format_value(phase.region_settle_time_s, '.2f', ' s')}"
        )
    return lines


def write_json(result: AttentionResult, path: Path) -> None:
    """Summary with `density_ratio` and `settle_time_s` (null where undefined)."""
    write_summary(result.summary(), path)


def write_csv(result: AttentionResult, path: Path) -> None:
    """One row per camera frame: time, node count, mean node error, quantisation error."""
    with open(path, "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(["time_s", "node_count", "mean_node_error", "quantisation_error_m"])
        for row in zip(result.times, result.node_count, result.mean_node_error,
                       result.quantisation_error, strict=True):  # fmt: skip
            writer.writerow([f"{row[0]:.4f}", int(row[1]), f"{row[2]:.6g}", f"{row[3]:.6g}"])


def plot(result: AttentionResult, path: Path) -> None:
    """Fig. 11 (left: node count and mean error with the focus phases shaded) and fig. 12
    (right: node density ratio per region at the end of each phase)."""
    figure, (series, bars) = plt.subplots(1, 2, figsize=(12, 4.5))
    series.plot(result.times, result.node_count, color="tab:blue", label="nodes")
    series.set_xlabel("simulated time (s)")
    series.set_ylabel("node count", color="tab:blue")
    error_axis = series.twinx()
    error_axis.plot(result.times, result.mean_node_error, color="tab:red", label="mean error")
    error_axis.set_ylabel("mean node error", color="tab:red")
    for index, phase in enumerate(result.phases):
        series.axvspan(phase.start, phase.end, alpha=0.08 * (1 + index % 2), color="grey")
        label = phase.focus + (f" {phase.target}" if phase.target else "")
        series.text(phase.start, series.get_ylim()[1] * 0.97, label, fontsize=8, va="top")
    series.set_title("Scene GNG under shifting attention (paper fig. 11)")

    regions = sorted({name for phase in result.phases for name in phase.density_ratios})
    width = 0.8 / max(len(result.phases), 1)
    for index, phase in enumerate(result.phases):
        values = [phase.density_ratios.get(name, math.nan) for name in regions]
        offsets = [i + index * width for i in range(len(regions))]
        bars.bar(offsets, values, width, label=f"focus: {phase.focus} {phase.target}".strip())
    bars.axhline(1.0, color="black", linewidth=0.8)
    bars.set_xticks([i + 0.4 - width / 2 for i in range(len(regions))], regions, rotation=20)
    bars.set_ylabel("node density ratio (region / rest)")
    bars.set_title("Node density per region (paper fig. 12)")
    bars.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)

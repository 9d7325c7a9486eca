"""Write the attention experiment's results: CSV time series, JSON summary, the paper's figures
11 (node count and error over time) and 12 (node density per region)."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only: no display on a robot's or CI's machine
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from hsr_handover.experiments.attention.experiment import AttentionResult  # noqa: E402
from hsr_handover.experiments.reporting import format_value, save_figure  # noqa: E402
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


PAPER_DENSITY_RATIO = 4.0
"""The paper's figure for the attended human region: node density "fourfold" the rest (fig. 12)."""
SETTLING_S = 0.5  # s: the map starts empty; its first half second is left off the error's scale


def plot(result: AttentionResult, path: Path) -> None:
    """Fig. 11 (left: node count and the mean distance from a sample to its nearest node, the
    focus phases shaded) and fig. 12 (right: node density ratio per region at the end of each
    phase, the paper's fourfold marked)."""
    figure, (series, bars) = plt.subplots(1, 2, figsize=(12, 4.6))
    _node_series(series, result)
    _density_bars(bars, result)
    figure.tight_layout()
    save_figure(figure, path)


def _node_series(series, result: AttentionResult) -> None:
    series.plot(result.times, result.node_count, color="tab:blue")
    series.set_xlabel("simulated time (s)")
    series.set_ylabel("active nodes (fig. 11a)", color="tab:blue")
    error_axis = series.twinx()
    error_cm = 100 * np.asarray(result.quantisation_error, dtype=float)
    error_axis.plot(result.times, error_cm, color="tab:red")
    error_axis.set_ylabel("mean distance, sample to nearest node (cm, fig. 11b)", color="tab:red")
    settled = error_cm[(np.asarray(result.times) >= SETTLING_S) & np.isfinite(error_cm)]
    if settled.size:
        top = 1.5 * float(settled.max())
        error_axis.set_ylim(0.0, top)
        if np.nanmax(error_cm) > top:
            error_axis.text(SETTLING_S, 0.97 * top, "the map's first frames off scale",
                            fontsize="x-small", color="tab:red", va="top")  # fmt: skip
    top = 1.12 * max(float(np.max(result.node_count)), 1.0)
    series.set_ylim(0.0, top)
    for index, phase in enumerate(result.phases):
        series.axvspan(phase.start, phase.end, alpha=0.08 * (1 + index % 2), color="grey")
        label = phase.focus + (f"\n{phase.target}" if phase.target else "")
        series.text(phase.start + 0.05, top * 0.98, label, fontsize="x-small", va="top")
    series.set_title("Scene GNG under shifting attention (paper fig. 11)", fontsize="medium")


def _density_bars(bars, result: AttentionResult) -> None:
    regions = sorted({name for phase in result.phases for name in phase.density_ratios})
    width = 0.8 / max(len(result.phases), 1)
    for index, phase in enumerate(result.phases):
        values = [phase.density_ratios.get(name, math.nan) for name in regions]
        offsets = [i + index * width for i in range(len(regions))]
        bars.bar(offsets, values, width, label=f"focus: {phase.focus} {phase.target}".strip())
    bars.axhline(1.0, color="black", linewidth=0.8)
    bars.axhline(PAPER_DENSITY_RATIO, color="black", linestyle="--", linewidth=0.8,
                 label="paper: fourfold in the human area")  # fmt: skip
    bars.set_xticks([i + 0.4 - width / 2 for i in range(len(regions))], regions, rotation=20)
    bars.set_ylabel("node density, region over the rest (per m² observed)")
    bars.set_title("Node density per region at each phase's end (paper fig. 12)",
                   fontsize="medium")  # fmt: skip
    bars.legend(fontsize="small")

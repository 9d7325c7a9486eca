"""What every experiment's report shares: JSON with null where a figure is undefined, the text
summary's word for it, rates with their Wilson intervals, and figures saved by their suffix."""

from __future__ import annotations

import csv
import json
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

UNDEFINED = "n/a"  # the text summary's word for a value the JSON writes as null


def json_safe(value: Any) -> Any:
    """`value` with every NaN or infinite float replaced by None (JSON's null), recursively."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {key: json_safe(item) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [json_safe(item) for item in value]
    return value


def write_json(summary: dict, path: Path) -> None:
    """The summary as indented JSON, null where undefined."""
    Path(path).write_text(json.dumps(json_safe(summary), indent=2) + "\n")


def format_value(value: float, spec: str, unit: str = "") -> str:
    """`value` formatted with `spec` and followed by `unit`, or "n/a" (as wide, no unit) where it
    is undefined: NaN or infinite, which the JSON summary writes as null."""
    if math.isfinite(value):
        return f"{value:{spec}}{unit}"
    return UNDEFINED.rjust(len(f"{math.nan:{spec}}"))


def write_rows(rows: list[dict], columns: Sequence[str], path: Path) -> None:
    """One CSV row per trial in `columns` (failed trials included, blank where they have no
    value), floats to four significant digits."""
    with open(path, "w", newline="") as stream:
        writer = csv.DictWriter(stream, columns, extrasaction="ignore")
        writer.writeheader()
        for row in rows:
            writer.writerow({key: format_cell(row.get(key, "")) for key in columns})


def format_cell(value: Any) -> Any:
    """A per-trial value as the CSV and the report page show it: floats to four significant
    digits, the rest as it is."""
    return f"{value:.4g}" if isinstance(value, float) else value


FIGURE_SUFFIXES = (".png", ".svg", ".pdf")
"""What `--plot` writes, chosen by the path's suffix."""
PNG_DPI = 200  # readable at a column's width in print


def save_figure(figure, path: Path) -> None:
    """Write `figure` as PNG (PNG_DPI), SVG or PDF by `path`'s suffix, and close it."""
    import matplotlib.pyplot as plt

    suffix = Path(path).suffix.lower()
    if suffix not in FIGURE_SUFFIXES:
        raise ValueError(f"figure path: expected a suffix in {FIGURE_SUFFIXES}, got {str(path)!r}")
    figure.savefig(path, dpi=PNG_DPI if suffix == ".png" else "figure", format=suffix[1:])
    plt.close(figure)


def counted(rate: float, trials: int) -> tuple[int, int]:
    """(successes, trials) of a rate over `trials`; (0, 0) when it is undefined."""
    return (0, 0) if not trials or rate != rate else (round(rate * trials), trials)


def wilson_interval(successes: int, trials: int) -> tuple[float, float]:
    """The 95 % Wilson score interval of a rate (NaN, NaN without trials)."""
    from scipy.stats import binomtest  # here: the CLI imports this module to check its options

    if trials <= 0:
        return math.nan, math.nan
    interval = binomtest(int(successes), int(trials)).proportion_ci(0.95, method="wilson")
    return float(interval.low), float(interval.high)


def bars_beside_paper(
    axes,
    labels: Sequence[str],
    ours: Sequence[tuple[int, int]],
    paper: Sequence[tuple[int, int]],
) -> None:
    """Rates as percentages, ours (blue) beside the paper's real trials (grey), each given as
    (successes, trials): each bar labelled with its value and count and drawn with its 95 %
    Wilson interval, the legend above the bars."""
    x = range(len(labels))
    series = ((-0.2, ours, "ours (simulated)", "tab:blue"),
              (0.2, paper, "paper (real trials)", "tab:gray"))  # fmt: skip
    for offset, counts, label, colour in series:
        values = [100 * k / n if n else math.nan for k, n in counts]
        intervals = [wilson_interval(k, n) for k, n in counts]
        below = [v - 100 * low for v, (low, _) in zip(values, intervals, strict=True)]
        above = [100 * high - v for v, (_, high) in zip(values, intervals, strict=True)]
        drawn = axes.bar([k + offset for k in x], values, 0.4, label=label, color=colour,
                         yerr=[below, above], capsize=3, error_kw={"elinewidth": 0.8})  # fmt: skip
        for bar, value, (k, n), (_, high) in zip(drawn, values, counts, intervals, strict=True):
            _label_bar(axes, bar, f"{value:.1f} %\n{k}/{n}" if n else "n/a", 100 * high)
    axes.set_xticks(list(x), labels)
    axes.set_ylim(0, 118)
    axes.set_yticks(range(0, 101, 20))
    axes.legend(loc="upper center", ncols=2, fontsize="small")


def _label_bar(axes, bar, text: str, whisker_top: float) -> None:
    """`text` at the foot of a bar tall enough to hold it (white, below where an interval's
    whisker usually reaches), else above the whisker (black)."""
    height = bar.get_height()
    inside = height == height and height >= 25.0
    y = 3.0 if inside else (whisker_top if whisker_top == whisker_top else 0.0) + 2.0
    axes.text(bar.get_x() + bar.get_width() / 2, y, text, ha="center", va="bottom",
              fontsize="x-small", color="white" if inside else "black")  # fmt: skip

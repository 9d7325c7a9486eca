"""What every experiment's report shares: JSON with null where a figure is undefined, and the
text summary's word for it."""

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
            writer.writerow({key: _cell(row.get(key, "")) for key in columns})


def _cell(value: Any) -> Any:
    return f"{value:.4g}" if isinstance(value, float) else value


def bars_beside_paper(axes, labels: Sequence[str], ours: Sequence[float], paper: Sequence[float]):
    """Percentages, ours (blue) beside the paper's 60 real trials (grey), each bar labelled
    with its value, the legend above the bars."""
    x = range(len(labels))
    series = ((-0.2, ours, "ours (simulated)", "tab:blue"),
              (0.2, paper, "paper (60 real trials)", "tab:gray"))  # fmt: skip
    for offset, values, label, colour in series:
        drawn = axes.bar([k + offset for k in x], values, 0.4, label=label, color=colour)
        axes.bar_label(drawn, fmt="%.1f %%", padding=2, fontsize="small")
    axes.set_xticks(list(x), labels)
    axes.set_ylim(0, 118)
    axes.legend(loc="upper center", ncols=2, fontsize="small")

"""The classes a trial's layout falls in, so a weakness shows in the summary: the person's
posture, the table's height and the person's height, each in bins."""

from __future__ import annotations

import bisect
import math
from collections.abc import Callable, Sequence

from hsr_handover.scenario import Scenario

TABLE_HEIGHT_BINS = (0.68, 0.77)  # m: a low, middle and high table (generated: 0.60-0.85)
PERSON_HEIGHT_BINS = (1.65, 1.80)  # m: a short, middle and tall person (generated: 1.50-1.95)
CLASSES = ("posture", "table_height", "person_height")


def _binned(value: float, edges: Sequence[float]) -> str:
    """ "< a", "a-b" or ">= b" (m) for `value` between the `edges` (a, b)."""
    index = bisect.bisect_right(edges, value)
    if index == 0:
        return f"< {edges[0]:.2f} m"
    if index == len(edges):
        return f">= {edges[-1]:.2f} m"
    return f"{edges[index - 1]:.2f}-{edges[index]:.2f} m"


def _order(label: str) -> tuple[float, str]:
    """Bins from the lowest up (by the number in the label), names alphabetically."""
    numbers = [float(word) for word in label.replace("-", " ").split() if word[0].isdigit()]
    low = -math.inf if label.startswith("<") else (numbers[0] if numbers else 0.0)
    return low, label


def trial_classes(scenario: Scenario) -> dict[str, str]:
    """The trial's class in each of CLASSES, keyed `class_<name>` for its row."""
    return {
        "class_posture": scenario.person.posture,
        "class_table_height": _binned(scenario.table.height, TABLE_HEIGHT_BINS),
        "class_person_height": _binned(scenario.person.height, PERSON_HEIGHT_BINS),
    }


def by_class(rows: Sequence[dict], success: Callable[[dict], bool]) -> dict[str, dict]:
    """For each of CLASSES, each class seen: how many `rows` and the rate of `success` among
    them ({"trials": n, "rate": r})."""
    table: dict[str, dict] = {}
    for name in CLASSES:
        groups: dict[str, list[bool]] = {}
        for row in rows:
            groups.setdefault(row[f"class_{name}"], []).append(bool(success(row)))
        table[name] = {
            label: {"trials": len(hits), "rate": sum(hits) / len(hits)}
            for label, hits in sorted(groups.items(), key=lambda item: _order(item[0]))
        }
    return table


def class_lines(title: str, table: dict[str, dict], what: str = "success") -> list[str]:
    """The by-class table as text: one line per class with its trials and `what` rate."""
    lines = [f"{title} by class ({what}, trials):"]
    for name, classes in table.items():
        cells = [f"{label} {100 * c['rate']:.1f} % ({c['trials']})" for label, c in classes.items()]
        lines.append(f"  {name:<14} " + "; ".join(cells))
    return lines


def class_columns(rows: Sequence[dict]) -> tuple[str, ...]:
    """The CSV columns of the classes and of the generated layouts' parameters (`layout_*`,
    in the order the rows give them; none for the scenario's own layout)."""
    layout = dict.fromkeys(key for row in rows for key in row if key.startswith("layout_"))
    return (*(f"class_{name}" for name in CLASSES), *layout)

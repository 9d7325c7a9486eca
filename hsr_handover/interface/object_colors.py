"""The colours the robot's object detector knows, by name (linear RGB in [0, 1]).

Saturated and far apart in hue, so colour segmentation tells the objects from each other, the
person, the table and the robot. The simulated world paints its objects from this table.
"""

from __future__ import annotations

OBJECT_COLORS: dict[str, tuple[float, float, float]] = {
    "red": (0.85, 0.08, 0.08),
    "green": (0.10, 0.70, 0.15),
    "blue": (0.10, 0.20, 0.85),
    "yellow": (0.95, 0.85, 0.05),
    "purple": (0.50, 0.10, 0.70),
    "cyan": (0.05, 0.75, 0.80),
    "magenta": (0.90, 0.10, 0.65),
}

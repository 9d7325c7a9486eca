"""The robot's look round before it plans (docs/design.md §6: the table's extent from one view is a
lower bound): the head pans to each side in turn so the table's ends come into view, then back.
"""

from __future__ import annotations

LOOK_AROUND_PANS = (0.7, -0.7)  # rad of head pan: the table's ends, each side in turn
LOOK_DWELL_S = 0.9  # s at each: the pan's move (1 rad/s) and a few table fits (5 Hz)
LOOK_ROUND_TILT = -0.3
"""rad of head tilt while it looks round with an active gaze: from the head at its lowest
(0.97 m) the view spans 6 to 40 degrees below level, a table top 0.6-0.85 m high from its near
edge on (the ready posture's level head sees the near edge of a low table only from 0.9 m)."""
LOOK_ROUND_S = LOOK_DWELL_S * (len(LOOK_AROUND_PANS) + 1)  # s, back where it began included


def look_round_pan(time: float, start_pan: float) -> float:
    """The head pan (rad) to command `time` s into the look round that began at `start_pan`."""
    stop = int(time // LOOK_DWELL_S)
    return LOOK_AROUND_PANS[stop] if 0 <= stop < len(LOOK_AROUND_PANS) else start_pan

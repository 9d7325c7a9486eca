"""The robot's `watching` signals: `watching` (1 while its handover cycle watches for a
request, 0 while it acts) and `intent_watching` (1 also while it lifts and carries an object
the person may still correct): the perception that serves only the watch rests while the robot
acts, the intent estimator only once no correction can come.

The scene map feeds only the intent estimator (through the detections' cross-check), and the
supervisor reads the intent only until it has a target (and a correction); the planner works
from detections, the table and the skeleton, which it reads at its own ticks. Resting the two
leaves every decision as it was, and the camera renders only the frames something still
reads: while the robot acts, the supervisor's frames (one in three) and the table fit's (one in
six), against all of them. While the robot lifts and carries, the intent estimator alone
watches for a correction (it judges the objects where it last saw them): it needs the
skeleton and the detections at every frame, not the scene map.
"""

from __future__ import annotations

from pydrake.systems.framework import Context, InputPort, LeafSystem

WATCHING = "watching"
INTENT_WATCHING = "intent_watching"


def declare_watching_input(system: LeafSystem) -> InputPort:
    """An optional input `watching` (1 element): unconnected, the system always works."""
    return system.DeclareVectorInputPort(WATCHING, 1)


def is_watching(port: InputPort, context: Context) -> bool:
    return not port.HasValue(context) or port.Eval(context)[0] > 0.5

"""The robot's `watching` signal (1 while its handover cycle watches for a request, 0 while it
acts): the perception that serves only the watch rests while the robot acts.

The scene map feeds only the intent estimator (through the detections' cross-check), and the
supervisor reads the intent only until it has a target; the planner works from detections, the
table and the skeleton, which it reads at its own ticks. Resting the two leaves every decision
as it was, and the camera renders only the frames something still reads: while the robot acts,
the supervisor's frames (one in three) and the table fit's (one in six), against all of them.
A correction while the robot lifts and carries is watched for by the supervisor itself, on
its own frames (`HandoverSupervisor`): kept awake for it, the intent estimator had the camera
render every frame, and the reference run took half as long again.
"""

from __future__ import annotations

from pydrake.systems.framework import Context, InputPort, LeafSystem

WATCHING = "watching"


def declare_watching_input(system: LeafSystem) -> InputPort:
    """An optional input `watching` (1 element): unconnected, the system always works."""
    return system.DeclareVectorInputPort(WATCHING, 1)


def is_watching(port: InputPort, context: Context) -> bool:
    return not port.HasValue(context) or port.Eval(context)[0] > 0.5

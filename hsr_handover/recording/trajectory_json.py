"""The robot's planned motions written for `run --trajectories`: one JSON file a researcher can
check against, or send to, a real HSR's trajectory controllers (`interface.joint_trajectory`)."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

from hsr_handover.interface.joint_trajectory import CONTROLLERS, JointTrajectory

FORMAT = "hsr_handover.trajectories/1"


def trajectories_json(trajectories: Sequence[JointTrajectory], scenario: str) -> dict:
    """The motions in the order the robot started them, each with its start (s, the run's
    clock) and, per controller it drives, the HSR's joint names, times from its start (s),
    positions (m, rad) and velocities (m/s, rad/s) at those times; the base's in the odometry
    frame, which is the scenario's world frame."""
    return {
        "format": FORMAT,
        "scenario": scenario,
        "controllers": {topic: list(joints.values()) for topic, joints in CONTROLLERS.items()},
        "motions": [trajectory.as_json() for trajectory in trajectories],
    }


def write_trajectories(path: Path, trajectories: Sequence[JointTrajectory], scenario: str) -> None:
    """Write `trajectories_json` to `path` (whole, once the run is over)."""
    Path(path).write_text(json.dumps(trajectories_json(trajectories, scenario), indent=1) + "\n")

"""The robot's planned motions as the HSR's joint trajectory controllers take them
(trajectory_msgs/JointTrajectory): which controller drives which joints, by the HSR's own
names, and each motion's positions and velocities at the times it was timed at. A motion drives
the base and the arm; the head is aimed by the robot's gaze, point by point, not by the
plans."""

from __future__ import annotations

import dataclasses

import numpy as np

MODEL_JOINTS = (
    "base_x_joint", "base_y_joint", "base_yaw_joint",
    "arm_lift_joint", "arm_flex_joint", "arm_roll_joint", "wrist_flex_joint", "wrist_roll_joint",
)  # fmt: skip
"""The joints a motion drives, in this model's names and order (`hsr.COMMANDED_JOINTS` but the
head's)."""

ARM_CONTROLLER = "/hsrb/arm_trajectory_controller/command"
BASE_CONTROLLER = "/hsrb/omni_base_controller/command"
CONTROLLERS: dict[str, dict[str, str]] = {
    ARM_CONTROLLER: {name: name for name in MODEL_JOINTS[3:]},
    BASE_CONTROLLER: {"base_x_joint": "odom_x", "base_y_joint": "odom_y",
                      "base_yaw_joint": "odom_t"},
}  # fmt: skip
"""Each HSR controller's command topic: this model's joint -> the HSR's joint name. The omni
base takes its pose in the odometry frame, which is this simulation's world frame."""
STILL_RAD = 1e-6  # rad or m: a joint that moves less than this over a motion is not driven by it


@dataclasses.dataclass(frozen=True)
class JointTrajectory:
    """One motion the robot commanded: its `name` ("move", "carry", ...), when it `start`ed
    (s, the robot's clock), and at `times` (n,) s from then the `positions` and `velocities`
    (n, len(MODEL_JOINTS)) of MODEL_JOINTS, as the planner timed them."""

    name: str
    start: float
    times: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray

    def for_controllers(self) -> list[tuple[str, tuple[str, ...], np.ndarray, np.ndarray]]:
        """(topic, HSR joint names, positions, velocities) for each controller whose joints
        the motion moves (a motion of the arm alone sends the base nothing)."""
        if len(self.times) == 0:
            return []
        moving = np.ptp(self.positions, axis=0) > STILL_RAD
        commands = []
        for topic, joints in CONTROLLERS.items():
            rows = [MODEL_JOINTS.index(joint) for joint in joints]
            if np.any(moving[rows]):
                positions, velocities = self.positions[:, rows], self.velocities[:, rows]
                commands.append((topic, tuple(joints.values()), positions, velocities))
        return commands

    def as_json(self) -> dict:
        """The motion for `run --trajectories`: per controller, the HSR's joint names, times
        from the start and the positions and velocities at them."""
        return {
            "name": self.name,
            "start_s": self.start,
            "controllers": [
                {"topic": topic, "joint_names": list(names),
                 "time_from_start_s": self.times.tolist(),
                 "positions": positions.tolist(), "velocities": velocities.tolist()}
                for topic, names, positions, velocities in self.for_controllers()
            ],
        }  # fmt: skip

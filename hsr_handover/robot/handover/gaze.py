"""Where the robot looks while it acts: the head turned so the camera's optical axis meets a
point, by the HSR's own kinematics."""

from __future__ import annotations

import math

import numpy as np

from hsr_handover.hsr import CAMERA_FRAME
from hsr_handover.robot.perception.active_gaze import wrap
from hsr_handover.robot.planning.planning_scene import PlanningScene

ITERATIONS = 3  # pan and tilt corrected in turn; the camera sits off the joints' axes


def look_at(robot: PlanningScene, q: np.ndarray, target: np.ndarray) -> tuple[float, float]:
    """(head pan, head tilt) in rad, within their limits, that aim the camera of the HSR at
    `q` (plant positions) at `target` (m, world)."""
    plant, context = robot.plant, robot.plant_context
    pan_at, tilt_at = robot.index("head_pan_joint"), robot.index("head_tilt_joint")
    q = np.array(q, dtype=float)
    camera = plant.GetFrameByName(CAMERA_FRAME)
    for _ in range(ITERATIONS):
        plant.SetPositions(context, q)
        pose = camera.CalcPoseInWorld(context)
        to_target = np.asarray(target, dtype=float) - pose.translation()
        forward = pose.rotation().matrix()[:, 2]
        q[pan_at] += wrap(_heading(to_target) - _heading(forward))
        q[tilt_at] += _elevation(to_target) - _elevation(forward)
        q = np.clip(q, plant.GetPositionLowerLimits(), plant.GetPositionUpperLimits())
    return float(q[pan_at]), float(q[tilt_at])


def _heading(vector: np.ndarray) -> float:
    return math.atan2(vector[1], vector[0])


def _elevation(vector: np.ndarray) -> float:
    return math.atan2(vector[2], math.hypot(vector[0], vector[1]))

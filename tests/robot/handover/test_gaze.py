"""Where the robot looks: the head's pan and tilt that aim the camera at a point."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.hsr import CAMERA_FRAME
from hsr_handover.robot.handover.gaze import look_at
from hsr_handover.robot.planning.perceived_scene import PerceivedScene
from hsr_handover.robot.planning.planning_scene import PlanningScene


@pytest.fixture(scope="module")
def robot() -> PlanningScene:
    return PlanningScene(PerceivedScene(None))


def _miss_deg(robot: PlanningScene, q: np.ndarray, target: np.ndarray) -> float:
    plant, context = robot.plant, robot.plant_context
    plant.SetPositions(context, q)
    pose = plant.GetFrameByName(CAMERA_FRAME).CalcPoseInWorld(context)
    to_target = target - pose.translation()
    cosine = to_target @ pose.rotation().matrix()[:, 2] / np.linalg.norm(to_target)
    return float(np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))))


@pytest.mark.parametrize("target", [[1.5, 0.8, 1.0], [0.8, -0.3, 0.7], [1.2, 0.3, 1.4]])
def test_the_camera_looks_straight_at_the_point(robot, target):
    robot.set_positions({"base_yaw_joint": 0.5, "arm_lift_joint": 0.3})
    q = robot.positions()
    pan, tilt = look_at(robot, q, np.array(target))
    q[robot.index("head_pan_joint")], q[robot.index("head_tilt_joint")] = pan, tilt
    assert _miss_deg(robot, q, np.array(target)) < 0.5


def test_a_point_behind_the_head_is_aimed_at_as_far_as_the_pan_goes(robot):
    robot.set_positions({})
    pan, _ = look_at(robot, robot.positions(), np.array([-1.0, 1.0, 1.2]))
    upper = robot.plant.GetJointByName("head_pan_joint").position_upper_limits()[0]
    assert pan == pytest.approx(upper)

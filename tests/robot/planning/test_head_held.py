"""The head is aimed by gaze, never by a plan: a path holds it where it starts, and a goal
that carries another head (the end of an earlier plan, as a put back's is) is still reached
in everything else."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.hsr import BASE_JOINTS, HEAD_JOINTS
from hsr_handover.robot.planning.perceived_scene import PerceivedScene
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.trajectory import optimize_path


@pytest.fixture(scope="module")
def scene() -> PlanningScene:
    return PlanningScene(PerceivedScene(None, ()))


def test_a_goal_with_another_head_is_reached_with_the_head_held(scene):
    scene.set_positions({})
    start = scene.positions()
    head = [scene.index(joint) for joint in HEAD_JOINTS]
    start[head] = (0.3, -0.2)
    goal = start.copy()
    goal[scene.index(BASE_JOINTS[0])] += 0.3
    goal[scene.index("arm_lift_joint")] = 0.1
    goal[scene.index("torso_lift_joint")] = 0.05  # the torso rises half as far (coupled)
    goal[head] = (-0.4, 0.1)  # where the head looked when the goal was planned
    result = optimize_path(scene, start, goal)
    assert result.ok, result.reason
    path = result.path
    for t in np.linspace(path.start_time(), path.end_time(), 20):
        np.testing.assert_allclose(path.value(t).ravel()[head], start[head], atol=1e-6)
    end = path.value(path.end_time()).ravel()
    others = [i for i in range(len(start)) if i not in head]
    np.testing.assert_allclose(end[others], goal[others], atol=1e-6)

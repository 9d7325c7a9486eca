"""PerceivedPlanner.follow: the state-to-state move that holds the object out at the hand."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.effectivity.arm_map import load_or_build
from hsr_handover.handover.perceived_planner import PerceivedPlanner
from hsr_handover.hsr import BASE_JOINTS
from hsr_handover.planning.perceived_scene import PerceivedScene


@pytest.fixture(scope="module")
def planner():
    planner = PerceivedPlanner(load_or_build()[0])
    planner.perceive(PerceivedScene(None), None)
    return planner


def _arm_out(planner: PerceivedPlanner) -> np.ndarray:
    """The arm level and straight out in front, at the height of a seated person's hand."""
    robot = planner.robot
    q = robot.plant.GetDefaultPositions()
    for joint, value in {"arm_flex_joint": -1.57, "wrist_flex_joint": 0.0,
                         "arm_lift_joint": 0.2, "torso_lift_joint": 0.1}.items():  # fmt: skip
        q[robot.index(joint)] = value
    return q


def _base(planner: PerceivedPlanner, q: np.ndarray) -> np.ndarray:
    return np.array([q[planner.robot.index(joint)] for joint in BASE_JOINTS])


def test_a_hand_within_the_arms_reach_is_followed_by_the_arm_alone(planner):
    q = _arm_out(planner)
    goal = planner.palm(q) + [0.0, 0.0, 0.05]  # the arm lifted
    planned = planner.follow(q, np.zeros_like(q), goal, None)
    assert planned.ok, planned.reason
    end = planned.motions[-1][1].state(planned.motions[-1][1].duration)[0]
    np.testing.assert_allclose(planner.palm(end), goal, atol=0.02)
    np.testing.assert_allclose(_base(planner, end), _base(planner, q), atol=1e-6)


def test_a_hand_beyond_the_arms_reach_is_followed_with_a_step_of_the_base(planner):
    q = _arm_out(planner)
    goal = planner.palm(q) + [0.12, 0.0, 0.0]  # the arm is already straight out
    planned = planner.follow(q, np.zeros_like(q), goal, None)
    assert planned.ok, planned.reason
    end = planned.motions[-1][1].state(planned.motions[-1][1].duration)[0]
    np.testing.assert_allclose(planner.palm(end), goal, atol=0.02)
    assert np.linalg.norm(_base(planner, end)[:2] - _base(planner, q)[:2]) > 0.05

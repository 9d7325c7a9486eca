"""A path that closes the hand on an obstacle (a grasp's approach) may touch it only
as its goal does: ignored outright, an approach that the optimiser bent round a neighbour swept
a pad 3 cm into the box it was going to grasp and knocked it over (the standing layout's
trial 1, seed 2)."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.hsr import BASE_JOINTS
from hsr_handover.robot.perception.object_shapes import CYLINDER, ObjectShape
from hsr_handover.robot.planning.paths import find_path
from hsr_handover.robot.planning.perceived_scene import PerceivedScene
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.trajectory import (
    COLLISION_BOUND,
    ESCAPE_SLACK,
    Target,
    approached_target,
)
from hsr_handover.robot.planning.verification import DIP_ALLOWANCE
from tests.robot.planning.conftest import slid_until

TOUCHING = -0.01  # m: the goal is 1 cm inside the target
DENSE = 200


@pytest.fixture(scope="module")
def scene() -> PlanningScene:
    """One pillar, the target, half a metre ahead of the base."""
    pillar = ObjectShape("target", CYLINDER, np.array([0.5, 0.0]), np.array([0.1, 0.1]), 0.0,
                         0.0, 1.2)  # fmt: skip
    return PlanningScene(PerceivedScene(None, (pillar,)))


@pytest.fixture(scope="module")
def start(scene) -> np.ndarray:
    scene.set_positions({})
    return scene.positions()


@pytest.fixture(scope="module")
def goal(scene, start) -> np.ndarray:
    """The base beyond the pillar, backed onto it until TOUCHING: the straight way there runs
    through it."""
    return slid_until(scene, start, BASE_JOINTS[0], TOUCHING, (0.6, 1.2), "target")


def _least(scene, path) -> float:
    times = np.linspace(path.start_time(), path.end_time(), DENSE)
    return min(scene.clearances_at(path.value(t).ravel())["target"] for t in times)


def test_the_bound_is_the_goals_own_less_the_slack_and_at_most_the_collision_bound(
    scene, start, goal
):
    touched = approached_target(scene, goal, "target")
    assert touched == Target("target", pytest.approx(TOUCHING - ESCAPE_SLACK, abs=1e-4))
    assert approached_target(scene, start, "target").bound == COLLISION_BOUND


def test_a_path_closing_on_its_target_comes_no_nearer_than_its_goal(scene, start, goal):
    target = approached_target(scene, goal, "target")
    path, reason = find_path(scene, start, goal, ("target",), straight=True, target=target)
    assert path is not None, reason
    assert _least(scene, path) >= target.bound - DIP_ALLOWANCE


def test_ignored_outright_the_straight_way_runs_through_the_target(scene, start, goal):
    path, reason = find_path(scene, start, goal, ("target",), straight=True)
    assert path is not None, reason
    assert _least(scene, path) < -0.1

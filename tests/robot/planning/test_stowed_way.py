"""A carry's stowed way, shortened: from a cup held over the table's near side round its corner
to a goal at its side, clear and upright between its checks, faster than the stowed way it
started from, and refused, with its reason, where the stowed way is not clear."""

from __future__ import annotations

import numpy as np
import pytest
from pydrake.math import BsplineBasis
from pydrake.trajectories import BsplineTrajectory

from hsr_handover.robot.perception.table_fit import TableEstimate
from hsr_handover.robot.planning import stowed_way as way
from hsr_handover.robot.planning.perceived_scene import PerceivedScene
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.shortcut import resampled
from hsr_handover.robot.planning.timing import joint_limits, time_path
from hsr_handover.robot.planning.trajectory import start_contact
from hsr_handover.robot.planning.upright import keeps_upright
from hsr_handover.robot.planning.verification import DIP_ALLOWANCE, path_dips
from tests.robot.planning.conftest import cup_in_hand

TABLE = TableEstimate(0.72, np.array([0.845, 0.0]), np.array([0.6, 1.0]), 0.0, 6000)
HELD_OUT = {"arm_lift_joint": 0.6, "arm_flex_joint": -1.57, "wrist_flex_joint": 0.0}
"""The arm held out level, the hand 20 cm over the table's top when the base is at it."""


@pytest.fixture(scope="module")
def scene() -> PlanningScene:
    return PlanningScene(PerceivedScene(TABLE, (), ()))


def _at(scene: PlanningScene, **base: float) -> np.ndarray:
    scene.set_positions(HELD_OUT | {f"{joint}_joint": value for joint, value in base.items()})
    return scene.positions()


@pytest.fixture(scope="module")
def ends(scene) -> tuple[np.ndarray, np.ndarray]:
    """From the table's -x side (the hand over the table) to its -y side, facing it."""
    q_from = _at(scene, base_x=0.2)
    q_to = _at(scene, base_x=0.845, base_y=-0.97, base_yaw=np.pi / 2)
    return q_from, q_to


def test_the_way_round_the_corner_is_clear_upright_and_faster_than_the_stowed_way(scene, ends):
    q_from, q_to = ends
    limits = joint_limits(scene.plant)
    with scene.holding("red", q_from, cup_in_hand(scene, q_from)):
        path, reason = way.stowed_way(scene, q_from, q_to, ("red",))
        assert reason == "ok" and path is not None
        np.testing.assert_allclose(path.value(path.start_time()).ravel(), q_from, atol=1e-9)
        np.testing.assert_allclose(path.value(path.end_time()).ravel(), q_to, atol=1e-9)
        contact = start_contact(scene, q_from, ("red",))
        assert path_dips(scene, path, ("red",), contact, 400).max() <= DIP_ALLOWANCE
        times = np.linspace(path.start_time(), path.end_time(), 200)
        assert keeps_upright(scene, np.array([path.value(t).ravel() for t in times]))
        keys = next(way._ways(scene, q_from, q_to, ("red",)))  # the first: driven in
        stowed = resampled(keys, way._speeds(scene), way.WAY_POINTS)
        unshortened = BsplineTrajectory(BsplineBasis(4, way.WAY_POINTS), stowed.T.copy())
        duration = time_path(path, limits).duration
        assert duration < 0.75 * time_path(unshortened, limits).duration


def test_a_stowed_way_that_is_not_clear_is_refused_with_its_reason(scene, ends):
    q_from, _ = ends
    inside = _at(scene, base_x=0.845, base_y=-0.2)  # the base under the table's top
    with scene.holding("red", q_from, cup_in_hand(scene, q_from)):
        path, reason = way.stowed_way(scene, q_from, inside, ("red",))
    assert path is None and reason == "the stowed way is not clear"


def test_ends_that_are_not_finite_are_refused(scene, ends):
    q_from, q_to = ends
    broken = q_to.copy()
    broken[0] = np.nan
    path, reason = way.stowed_way(scene, q_from, broken, ())
    assert path is None and reason == "the way's ends are not finite"


def test_the_first_ways_unstow_standing_back_and_drive_in_over_the_goal(scene, ends):
    """Before the way that unstows at the goal's base, the base stands back along the goal's
    heading by each of DRIVE_INS, the arm unstows to the goal raised by OVER (within the lift's
    limit, the torso with it) there, the base drives in and the arm lowers onto the goal."""
    q_from, q_to = ends
    ways = list(way._ways(scene, q_from, q_to, ()))
    assert len(ways) == 1 + len(way.DRIVE_INS)
    x, y, yaw = (scene.index(joint) for joint in ("base_x_joint", "base_y_joint", "base_yaw_joint"))
    lift, torso = scene.index("arm_lift_joint"), scene.index("torso_lift_joint")
    heading = np.array([np.cos(q_to[yaw]), np.sin(q_to[yaw])])
    for back, keys in zip(way.DRIVE_INS, ways[:-1], strict=True):
        stood_back, unstowed, over, goal = keys[-4:]
        np.testing.assert_allclose(goal, q_to)
        np.testing.assert_allclose(stood_back[[x, y]], q_to[[x, y]] - back * heading, atol=1e-9)
        np.testing.assert_allclose(unstowed[[x, y]], stood_back[[x, y]])
        np.testing.assert_allclose(over[[x, y]], q_to[[x, y]])
        top = scene.plant.GetPositionUpperLimits()[lift]  # 0.69 m: the goal's 0.6 rises 9 cm
        assert over[lift] == pytest.approx(min(top, q_to[lift] + way.OVER))
        assert over[torso] == pytest.approx(q_to[torso] + (over[lift] - q_to[lift]) / 2)
        arm = [i for i in range(len(q_to)) if i not in (x, y, lift, torso)]
        np.testing.assert_allclose(unstowed[arm], q_to[arm])
    np.testing.assert_allclose(ways[-1][0], q_from)
    np.testing.assert_allclose(ways[-1][-2][[x, y]], q_to[[x, y]])  # unstowed at the goal


def test_the_head_stays_where_it_starts(scene, ends):
    """The gaze aims the head, not plans: a goal with the head elsewhere (kept from an earlier
    plan) is reached with the head as at the start, all along."""
    q_from, q_to = ends
    head = [scene.index(joint) for joint in ("head_pan_joint", "head_tilt_joint")]
    looking = q_to.copy()
    looking[head] = [0.4, -0.3]
    with scene.holding("red", q_from, cup_in_hand(scene, q_from)):
        path, _ = way.stowed_way(scene, q_from, looking, ("red",))
    times = np.linspace(path.start_time(), path.end_time(), 50)
    heads = np.array([path.value(t).ravel()[head] for t in times])
    np.testing.assert_allclose(heads, np.tile(q_from[head], (50, 1)), atol=1e-9)

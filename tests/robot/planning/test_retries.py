"""Retries and fallbacks, with a planner made to fail its first tries: a path whose first
guesses stop short is found by a fallback (and the plan says which, timed as "retry"); a path
no guess finds says whether SNOPT found them all infeasible or stopped short; a put back starts
the optimiser from the way it came; a handover pose whose IK fails from its first seeds is
found from the arm map's nodes round the point."""

from __future__ import annotations

import numpy as np
import pytest
from pydrake.math import BsplineBasis
from pydrake.trajectories import BsplineTrajectory

from hsr_handover.robot.effectivity.arm_map import load_or_build
from hsr_handover.robot.effectivity.person_map import HumanArm, PersonEffectivity
from hsr_handover.robot.perception.object_shapes import CYLINDER, ObjectShape
from hsr_handover.robot.perception.table_fit import TableEstimate
from hsr_handover.robot.planning import handover_pose, paths, planner
from hsr_handover.robot.planning.inverse_kinematics import IkResult, PalmGoal, solve_palm_ik
from hsr_handover.robot.planning.paths import RETRY
from hsr_handover.robot.planning.perceived_scene import Capsule, PerceivedScene
from hsr_handover.robot.planning.planner import Held, plan_posture, plan_put_back
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.solving import INFEASIBLE, SOLVER_TROUBLE, verdict
from hsr_handover.robot.planning.timing import JointLimits, joint_limits
from hsr_handover.robot.planning.trajectory import COLLISION_BOUND, PathResult, StartContact
from hsr_handover.robot.planning.verification import (
    DIP_ALLOWANCE,
    keeps_bounds,
    path_dips,
    timed_clearance,
)

TABLE_TOP = 0.72


@pytest.fixture(scope="module")
def scene() -> PlanningScene:
    table = TableEstimate(TABLE_TOP, np.array([0.845, 0.0]), np.array([0.6, 1.0]), 0.0, 6000)
    person = (Capsule(np.array([1.75, 0, 0.55]), np.array([1.75, 0, 1.05]), 0.2),
              Capsule(np.array([1.75, 0, 1.1]), np.array([1.7, 0, 1.25]), 0.15))  # fmt: skip
    cup = ObjectShape("red", CYLINDER, np.array([0.8, 0.0]), np.array([0.07, 0.07]), 0.0,
                      TABLE_TOP, 0.10)  # fmt: skip
    return PlanningScene(PerceivedScene(table, (cup,), person))


@pytest.fixture(scope="module")
def limits(scene) -> JointLimits:
    return joint_limits(scene.plant)


def _ready(scene: PlanningScene) -> np.ndarray:
    scene.set_positions({})
    return scene.positions()


def _raised(scene: PlanningScene, q: np.ndarray) -> np.ndarray:
    """`q` with the arm raised and the base 20 cm to the side (away from the table)."""
    goal = q.copy()
    goal[scene.index("base_y_joint")] += 0.2
    goal[scene.index("arm_lift_joint")] = 0.3
    goal[scene.index("torso_lift_joint")] = 0.15
    return goal


def _failing_first(monkeypatch, failures: int, code: str) -> list:
    """Make paths.optimize_path fail its first `failures` calls with SNOPT's `code` (stopping
    at the guess it was given); the guesses it is called with, in order."""
    real, guesses = paths.optimize_path, []

    def optimize(scene, q_start, q_goal, guess=None, *args, **kwargs):
        guesses.append(None if guess is None else np.array(guess))
        if len(guesses) <= failures:
            return PathResult(ok=False, reason=f"no path (SNOPT {code})", path=None, last=guess)
        return real(scene, q_start, q_goal, guess, *args, **kwargs)

    monkeypatch.setattr(paths, "optimize_path", optimize)
    monkeypatch.setattr(paths, "_line_clear", lambda *args: False)  # no shortcut past the solves
    return guesses


def test_a_path_whose_first_guesses_stop_short_is_found_going_on(scene, limits, monkeypatch):
    q = _ready(scene)
    guesses = _failing_first(monkeypatch, 2, "kIterationLimit")  # straight and round
    plan = plan_posture(scene, q, _raised(scene, q), limits)
    assert plan.ok, plan.reason
    assert plan.retried == ("posture: continued",)
    assert plan.seconds[RETRY] > 0.0
    assert len(guesses) == 3
    np.testing.assert_allclose(guesses[2], guesses[0])  # on from where the first stopped
    clearance = timed_clearance(scene, plan.motions[0])
    assert clearance >= COLLISION_BOUND - DIP_ALLOWANCE  # verified like any path


def test_a_plan_found_at_once_names_no_retry(scene, limits, monkeypatch):
    q = _ready(scene)
    _failing_first(monkeypatch, 0, "")
    plan = plan_posture(scene, q, _raised(scene, q), limits)
    assert plan.ok and plan.retried == () and plan.seconds[RETRY] == 0.0


@pytest.mark.parametrize(
    ("code", "verdict"),
    [("kInfeasibleConstraints", INFEASIBLE), ("kIterationLimit", SOLVER_TROUBLE)],
)
def test_a_path_no_guess_finds_says_infeasible_or_solver_trouble(
    scene, limits, monkeypatch, code, verdict
):
    q = _ready(scene)
    guesses = _failing_first(monkeypatch, 100, code)
    plan = plan_posture(scene, q, _raised(scene, q), limits)
    assert not plan.ok
    assert plan.reason.startswith(f"posture: {verdict}: "), plan.reason
    for fallback in ("base first", "arm first", "raised"):
        assert f"{fallback}: no path (SNOPT {code})" in plan.reason
    assert ("continued" in plan.reason) == (verdict == SOLVER_TROUBLE)
    assert len(guesses) == (6 if verdict == SOLVER_TROUBLE else 5)


def test_a_put_back_starts_the_optimiser_from_the_way_it_came(scene, limits, monkeypatch):
    """When the way it came, taken as it is, would dip inside its bounds between samples, the
    optimiser starts from it first, before the straight line and the round."""
    q_lifted = _raised(scene, _ready(scene))
    q_now = q_lifted.copy()
    q_now[scene.index("base_y_joint")] = 0.3
    came = list(np.linspace(q_lifted, q_now, 16))
    monkeypatch.setattr(planner, "verified", lambda *args, **kwargs: False)
    guesses = _failing_first(monkeypatch, 0, "")
    held = Held("red", _ready(scene))
    plan = plan_put_back(scene, q_now, held, q_lifted, limits, came)
    assert len(guesses) >= 1
    np.testing.assert_allclose(guesses[0][:, 0], q_now)
    np.testing.assert_allclose(guesses[0][:, 1], came[-2])  # the way it came, reversed
    assert plan.motions and plan.motions[0].name == planner.PUT_BACK


def test_a_handover_pose_whose_ik_fails_is_found_from_the_maps_nodes(scene, monkeypatch):
    shoulder = np.array([1.75, 0.19, 1.03])
    frame = np.column_stack([[-1.0, 0, 0], [0, -1.0, 0], [0, 0, 1.0]])  # facing the robot
    person = PersonEffectivity(HumanArm("r", shoulder, frame, 0.30, 0.25, 0.09))
    arm_map = load_or_build()[0]

    def fails(scene, arm_map, goal, seed, q_now, ignore):
        return IkResult(ok=False, q=seed, reason="no IK solution (SNOPT kIterationLimit)")

    monkeypatch.setattr(handover_pose, "_ik_at_point", fails)
    pose = handover_pose.plan_handover_pose(scene, arm_map, person, _ready(scene))
    assert pose.ok, pose.reason
    assert pose.found_by in ("map node 1", "map node 2", "map node 3", "arm as it is")
    monkeypatch.setattr(handover_pose, "other_seeds", lambda *args: [])
    pose = handover_pose.plan_handover_pose(scene, arm_map, person, _ready(scene))
    assert not pose.ok and "kIterationLimit" in pose.reason


def test_the_verdict_tells_infeasible_from_solver_trouble():
    assert verdict("a: no path (SNOPT kInfeasibleConstraints); b: no path (SNOPT "
                   "kInfeasibleConstraints)") == INFEASIBLE  # fmt: skip
    assert verdict("a: no path (SNOPT kInfeasibleConstraints); b: no path (SNOPT "
                   "kIterationLimit)") == SOLVER_TROUBLE  # fmt: skip
    assert verdict("a: dips 0.4 cm inside its bounds between 120 samples") == SOLVER_TROUBLE
    assert verdict("no IK solution (SNOPT kInfeasibleConstraints)") == INFEASIBLE


def test_an_ik_that_fails_says_whether_it_was_infeasible(scene):
    goal = PalmGoal(
        np.array([0.8, 0.0, TABLE_TOP - 0.05]), np.array([1.0, 0, 0]), np.array([0, 1.0, 0]), 0.08
    )  # fmt: skip  (inside the table)
    result = solve_palm_ik(scene, goal, _ready(scene))
    assert not result.ok
    assert result.reason.endswith(f", {verdict(result.reason)}")


@pytest.mark.parametrize("x", [0.6, -0.5])  # the base driven into the table, or away from it
def test_a_line_keeps_its_bounds_as_its_dips_say(scene, x):
    q = _ready(scene)
    goal = q.copy()
    goal[scene.index("base_x_joint")] = x
    line = BsplineTrajectory(BsplineBasis(4, 10), np.linspace(q, goal, 10).T)
    dips = path_dips(scene, line, (), StartContact(), 120)
    assert keeps_bounds(scene, line, (), StartContact(), 120) == (dips.max() <= 0)
    assert (dips.max() <= 0) == (x < 0)

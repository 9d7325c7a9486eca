"""PerceivedPlanner: one per percepts, and its follow, the state-to-state move that holds the
object out at the hand."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.hsr import BASE_JOINTS
from hsr_handover.robot.effectivity.arm_map import load_or_build
from hsr_handover.robot.effectivity.person_map import HumanArm
from hsr_handover.robot.handover.perceived_planner import PerceivedPlanner
from hsr_handover.robot.planning import follow
from hsr_handover.robot.planning.inverse_kinematics import IkResult
from hsr_handover.robot.planning.perceived_scene import Capsule, PerceivedScene


@pytest.fixture(scope="module")
def planner():
    return PerceivedPlanner(load_or_build()[0])


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
    end = planned.motions[-1].state(planned.motions[-1].duration)[0]
    np.testing.assert_allclose(planner.palm(end), goal, atol=0.02)
    np.testing.assert_allclose(_base(planner, end), _base(planner, q), atol=1e-6)


def test_a_hand_beyond_the_arms_reach_is_followed_with_a_step_of_the_base(planner):
    q = _arm_out(planner)
    goal = planner.palm(q) + [0.12, 0.0, 0.0]  # the arm is already straight out
    planned = planner.follow(q, np.zeros_like(q), goal, None)
    assert planned.ok, planned.reason
    end = planned.motions[-1].state(planned.motions[-1].duration)[0]
    np.testing.assert_allclose(planner.palm(end), goal, atol=0.02)
    assert np.linalg.norm(_base(planner, end)[:2] - _base(planner, q)[:2]) > 0.05


def test_a_hand_whose_forearm_covers_the_aim_gets_the_object_beside_it():
    """The aim in front of a held-out hand lies inside the perceived forearm's capsule: the
    object is held out beside it instead."""
    unseen = PerceivedPlanner(load_or_build()[0])
    q = _arm_out(unseen)
    # The wrist 32 cm beyond the object, its capsule running on 18 cm past it
    aim = unseen.palm(q) + [0.12, 0.0, 0.0]  # `CycleParams.offer` (20 cm) before it
    forearm = Capsule(aim + [0.46, 0.0, 0.0], aim + [0.02, 0.0, 0.0], 0.095)
    scene_planner = unseen.perceiving(PerceivedScene(None, person=(forearm,)), ())
    planned = scene_planner.follow(q, np.zeros_like(q), aim, None)
    assert planned.ok, planned.reason
    end = planned.motions[-1].state(planned.motions[-1].duration)[0]
    palm = scene_planner.palm(end)
    assert np.linalg.norm(palm - aim) < 0.2  # beside the hand, not into it
    assert forearm.distance(palm)[0] > 0.05


def test_the_carry_hands_to_the_other_arm_when_the_first_has_no_mutual_area():
    """A person whose right hand no robot pose reaches (here its shoulder 3 m up) is handed
    the object at the left; the plan says which arm it hands to."""
    facing = np.column_stack([[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]])
    right = HumanArm("r", np.array([1.6, 0.2, 3.0]), facing, 0.32, 0.25, 0.09)
    left = HumanArm("l", np.array([1.6, -0.2, 1.35]), facing, 0.32, 0.25, 0.09)
    unseen = PerceivedPlanner(load_or_build()[0])
    q = unseen.robot.plant.GetDefaultPositions()
    carrier = unseen.perceiving(PerceivedScene(None), (right, left))
    planned = carrier.carry(q, None)
    assert planned.ok, planned.reason
    assert planned.receiving == "l"
    end = planned.motions[-1].state(planned.motions[-1].duration)[0]
    palm = carrier.palm(end)
    assert np.linalg.norm(palm - left.shoulder) < left.reach
    refused = carrier.perceiving(PerceivedScene(None), (right,)).carry(q, None)
    assert not refused.ok and refused.reason.startswith("right arm: no mutual area")


def test_newer_percepts_give_a_new_planner_and_leave_the_old_one_planning_in_its_own(planner):
    """A planner is made for each tick's percepts: the same percepts give the same planner
    back, other ones a new planner that plans in them, while the old one (which a cloned Drake
    context may still hold) plans as before: nothing is shared but the robot's kinematics."""
    q = _arm_out(planner)
    aim = planner.palm(q) + [0.12, 0.0, 0.0]
    forearm = Capsule(aim + [0.46, 0.0, 0.0], aim + [0.02, 0.0, 0.0], 0.095)
    scene = PerceivedScene(None, person=(forearm,))
    seen = planner.perceiving(scene, ())
    assert seen is not planner and seen.perceiving(scene, ()) is seen
    beside = seen.follow(q, np.zeros_like(q), aim, None)
    at_aim = planner.follow(q, np.zeros_like(q), aim, None)
    assert beside.ok and at_aim.ok, (beside.reason, at_aim.reason)
    ends = [plan.motions[-1].state(plan.motions[-1].duration)[0] for plan in (beside, at_aim)]
    assert np.linalg.norm(planner.palm(ends[0]) - aim) > 0.05  # round the forearm
    np.testing.assert_allclose(planner.palm(ends[1]), aim, atol=0.02)  # nothing in the way


def test_a_follow_whose_first_ik_fails_starts_again_from_the_arm_map_before_stepping(
    planner, monkeypatch
):
    """The IK from the arm as it is made to fail: the retry starts from the effectivity map's
    nodes round the point with the base where it stands, and reaches the hand so."""
    solve = follow.solve_palm_ik
    calls = []

    def first_fails(scene, goal, seed, *args, **kwargs):
        calls.append((seed.copy(), kwargs.get("base_fixed", False)))
        if len(calls) == 1:
            return IkResult(ok=False, q=seed, reason="no IK solution (made to fail)")
        return solve(scene, goal, seed, *args, **kwargs)

    monkeypatch.setattr(follow, "solve_palm_ik", first_fails)
    q = _arm_out(planner)
    goal = planner.palm(q) + [0.0, 0.0, 0.05]
    planned = planner.follow(q, np.zeros_like(q), goal, None)
    assert planned.ok, planned.reason
    seed, base_fixed = calls[-1]
    assert len(calls) >= 2 and base_fixed
    assert not np.allclose(seed, q)  # an arm from the map, not the arm as it is
    np.testing.assert_allclose(_base(planner, seed), _base(planner, q))
    end = planned.motions[-1].state(planned.motions[-1].duration)[0]
    np.testing.assert_allclose(planner.palm(end), goal, atol=0.02)


def test_the_person_may_reach_for_a_point_within_either_arms_leaning_reach(planner):
    """An object stopped in front of one shoulder within the arm's full reach, leaning, may be
    reached for; one beyond it is not, nor anything with no person seen. An arm perceived short
    (one frame's elbow and wrist) still reaches as far as the body's proportions say."""
    facing = np.column_stack([[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]])
    right = HumanArm("r", np.array([1.6, 0.2, 1.3]), facing, 0.32, 0.25, 0.09)
    left = HumanArm("l", np.array([1.6, -0.2, 1.3]), facing, 0.22, 0.18, 0.09)  # short
    seeing = planner.perceiving(PerceivedScene(None), (right, left))
    ahead = np.array([-1.0, 0.0, 0.0])
    assert seeing.person_reaches(right.shoulder + (right.reach + 0.08) * ahead)
    assert not seeing.person_reaches(right.shoulder + (right.reach + 0.12) * ahead)
    assert left.reach < left.body_reach - 0.1
    assert seeing.person_reaches(left.shoulder + (left.body_reach + 0.08) * ahead)
    assert not planner.person_reaches(left.shoulder + 0.5 * left.reach * ahead)

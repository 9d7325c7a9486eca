"""Following the person's hand while presenting, in physical terms: how far off a hand is
followed, how long a nearer one waits, where the object is aimed, and a hand that comes for
the object."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.robot.handover.cycle_params import CycleParams
from hsr_handover.robot.handover.cycle_types import Percepts
from hsr_handover.robot.handover.hand_follower import PART_WAY, FollowStep, HandFollower

PALM = np.array([1.0, 0.0, 1.0])  # where the object is held out
AWAY = np.array([1.0, 0.0, 0.0])  # from the palm toward the person
TICK = 0.1  # s between decisions


def _percepts(time: float, hand: np.ndarray) -> Percepts:
    return Percepts(time, np.zeros(3), 0.06, hand=hand, palm=PALM)


def _steps(follower: HandFollower, hands, start: float = 0.0, following: bool = False):
    """The follower's step at each decision, the hand at each of `hands` in turn."""
    return [follower.step(_percepts(start + k * TICK, hand), following)
            for k, hand in enumerate(hands)]  # fmt: skip


def _still(hand: np.ndarray, seconds: float) -> list[np.ndarray]:
    return [hand] * round(seconds / TICK)


def test_a_hand_held_out_60_cm_off_is_followed_once_still_for_1_5_s_with_the_object_out():
    """Till then the person may yet reach for the object where it is; the hand's rest before
    the object was held out does not count."""
    held_out = PALM + 0.6 * AWAY
    follower = HandFollower(CycleParams(), since=2.0)
    follower.step(_percepts(0.0, held_out), following=False)  # at rest before it was held out
    steps = _steps(follower, _still(held_out, 1.6), start=2.0)
    assert FollowStep.FOLLOW not in steps[: round(1.5 / TICK)]
    assert steps[-1] is FollowStep.FOLLOW


def test_a_hand_60_cm_off_that_keeps_moving_is_never_followed():
    """It is reaching for the object (or not yet held out)."""
    reaching = [PALM + (0.9 - 0.05 * k) * AWAY for k in range(6)]
    reaching += [PALM + 0.6 * AWAY + [0.0, 0.05 * k, 0.0] for k in range(40)]
    assert FollowStep.FOLLOW not in _steps(HandFollower(CycleParams()), reaching)


def test_a_hand_30_cm_off_may_be_reaching_and_is_not_followed_at_once():
    assert _steps(HandFollower(CycleParams()), [PALM + 0.3 * AWAY]) == [FollowStep.STAY]


def test_the_object_is_aimed_20_cm_in_front_of_the_hand():
    """In front of the fingers, for the person to close them on: the wrist is inside the
    hand."""
    hand = PALM + [0.3, 0.4, 0.0]  # 50 cm off
    follower = HandFollower(CycleParams())
    assert _steps(follower, _still(hand, 1.6))[-1] is FollowStep.FOLLOW
    aims = follower.aims(_percepts(1.6, hand))
    np.testing.assert_allclose(aims, [hand + 0.2 * (PALM - hand) / 0.5])  # the aim alone:
    # held out this far, the person may yet reach for the object where it is.


def test_a_hand_that_waited_near_gets_the_object_part_way_where_the_arm_cannot_reach_it():
    """The person judged the object out of reach: where the arm cannot bring it in front of
    the hand, part way there from the palm, the nearer later, is nearer their reach."""
    hand = PALM + [0.3, 0.0, -0.1]
    follower = HandFollower(CycleParams())
    assert _steps(follower, _still(hand, 4.0))[-1] is FollowStep.FOLLOW
    aim, *part_way = follower.aims(_percepts(4.0, hand))
    shares = [np.linalg.norm(point - PALM) / np.linalg.norm(aim - PALM) for point in part_way]
    np.testing.assert_allclose(shares, PART_WAY)
    assert all(np.linalg.norm(np.cross(point - PALM, aim - PALM)) < 1e-12 for point in part_way)


def test_a_hand_still_32_cm_off_gets_the_object_brought_after_3_s():
    """The person judges the object out of reach: held out 32 cm off, they waited."""
    hand = PALM + [0.3, 0.0, -0.1]
    steps = _steps(HandFollower(CycleParams()), _still(hand, 4.0))
    assert FollowStep.FOLLOW not in steps[: round(2.0 / TICK)]  # still waiting at 2 s
    assert steps[-1] is FollowStep.FOLLOW  # brought by 4 s


def test_a_wrist_wandering_2_cm_is_still_waiting():
    """The skeleton's wrist wanders 1-2 cm."""
    hand = PALM + [0.3, 0.0, -0.1]
    wandering = [hand + [0.0, 0.02 * (k % 2), 0.0] for k in range(round(4.0 / TICK))]
    assert _steps(HandFollower(CycleParams()), wandering)[-1] is FollowStep.FOLLOW


def test_a_hand_that_moved_8_cm_waits_afresh_from_where_it_stopped():
    hand = PALM + [0.3, 0.0, -0.1]
    moved = _still(hand, 3.0) + _still(hand + [0.0, 0.08, 0.0], 1.0)
    assert FollowStep.FOLLOW not in _steps(HandFollower(CycleParams()), moved)


def test_a_hand_that_keeps_coming_is_never_followed():
    reaching = [PALM + [0.3 - 0.01 * k, 0.0, -0.1] for k in range(round(6.0 / TICK))]
    assert FollowStep.FOLLOW not in _steps(HandFollower(CycleParams()), reaching)


def test_a_hand_followed_is_followed_again_after_a_second_not_sooner():
    """A hand out of reach fails each try: it is tried once a second."""
    follower = HandFollower(CycleParams(), since=-2.0)
    hand = PALM + 0.6 * AWAY
    follower.step(_percepts(-2.0, hand), following=False)
    follower.aims(_percepts(0.0, hand))
    assert _steps(follower, [hand], start=0.5) == [FollowStep.STAY]
    assert _steps(follower, [hand], start=1.5) == [FollowStep.FOLLOW]


@pytest.mark.parametrize(("came", "stops"), [(0.01, False), (0.04, True)])
def test_a_followed_hand_that_comes_4_cm_for_the_object_stops_the_arm(came: float, stops: bool):
    """The wrist's keypoint wanders under 1 cm; a hand that comes 4 cm toward the object
    reaches for it where it was, and following on would bring the fingers into it."""
    follower = HandFollower(CycleParams())
    hand = PALM + 0.6 * AWAY
    follower.aims(_percepts(0.0, hand))
    step = follower.step(_percepts(TICK, hand - came * AWAY), following=True)
    assert (step is FollowStep.STOP) is stops


def test_a_hand_that_comes_while_the_arm_stands_still_stops_nothing():
    follower = HandFollower(CycleParams())
    hand = PALM + 0.6 * AWAY
    follower.aims(_percepts(0.0, hand))
    step = follower.step(_percepts(TICK, hand - 0.1 * AWAY), following=False)
    assert step is not FollowStep.STOP


def test_a_wrist_read_40_cm_off_for_one_decision_does_not_stop_a_follow():
    """The detector swaps the arms for a frame: the reading jumps to the other hand, nearer the
    object. The hand is the median of three decisions' readings: one such reading is not a
    hand that comes; two are."""
    follower = HandFollower(CycleParams())
    hand = PALM + 0.6 * AWAY
    other_hand = PALM + 0.2 * AWAY + [0.0, 0.3, 0.0]
    assert _steps(follower, _still(hand, 1.6), start=-1.6)[-1] is FollowStep.FOLLOW
    follower.aims(_percepts(TICK, hand))
    swapped = follower.step(_percepts(2 * TICK, other_hand), following=True)
    assert swapped is not FollowStep.STOP
    aim, *_ = follower.aims(_percepts(2 * TICK, other_hand))
    np.testing.assert_allclose(aim, hand - 0.2 * AWAY)  # the aim too is the hand's
    assert follower.step(_percepts(3 * TICK, other_hand), following=True) is FollowStep.STOP

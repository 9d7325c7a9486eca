"""The look round's memory of the person: the newest skeleton that shows both shoulders, its
arm's lengths voted over frames."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.effectivity.person_map import (
    FOREARM_PER_HEIGHT,
    LENGTH_VOTES,
    SHOULDER_DEPTH,
    SHOULDER_WIDTH_PER_HEIGHT,
    HumanArm,
    SteadyLengths,
    receiving_arm,
)
from hsr_handover.perception.coco18 import keypoint_index
from hsr_handover.perception.skeleton import Skeleton
from tests.intent.synthetic_person import keypoints


def _skeleton(shift: float = 0.0, without: tuple[str, ...] = ()) -> Skeleton:
    points, confidence = keypoints()
    confidence = confidence.copy()
    for name in without:
        confidence[keypoint_index(name)] = 0.0
    return Skeleton(np.zeros((18, 2)), points + [shift, 0.0, 0.0], confidence)


def test_the_newest_skeleton_with_both_shoulders_gives_the_arm():
    newest, older = _skeleton(0.0), _skeleton(0.3)
    arm = receiving_arm([newest, older])
    assert arm.side == "r"
    behind = newest.points[keypoint_index("r_shoulder")] - SHOULDER_DEPTH * arm.frame[:, 0]
    np.testing.assert_allclose(arm.shoulder, behind)


def test_a_skeleton_without_a_shoulder_falls_back_to_the_last_glimpse():
    out_of_view, glimpse = _skeleton(without=("l_shoulder",)), _skeleton(0.3)
    arm = receiving_arm([out_of_view, glimpse])
    behind = glimpse.points[keypoint_index("r_shoulder")] - SHOULDER_DEPTH * arm.frame[:, 0]
    np.testing.assert_allclose(arm.shoulder, behind)
    assert receiving_arm([out_of_view]) is None
    assert receiving_arm([]) is None


def test_an_unseen_forearm_takes_the_bodys_proportions():
    skeleton = _skeleton(without=("r_wrist",))
    shoulders = skeleton.points[[keypoint_index("r_shoulder"), keypoint_index("l_shoulder")]]
    height = np.linalg.norm(shoulders[0] - shoulders[1]) / SHOULDER_WIDTH_PER_HEIGHT
    unseen = receiving_arm([skeleton])
    assert unseen.upper == pytest.approx(receiving_arm([_skeleton()]).upper)
    assert unseen.forearm == pytest.approx(FOREARM_PER_HEIGHT * height)


def _arm(upper: float, forearm: float = 0.25, hand: float = 0.09) -> HumanArm:
    return HumanArm("r", np.zeros(3), np.eye(3), upper, forearm, hand)


def test_steady_lengths_are_each_the_median_of_the_votes():
    votes = SteadyLengths()
    for upper, forearm in ((0.30, 0.25), (0.36, 0.20), (0.31, 0.24)):  # one frame read long
        votes = votes.add(_arm(upper, forearm)).add(None)
    now = HumanArm("r", np.array([1.0, 2.0, 3.0]), np.eye(3)[[1, 0, 2]], 0.4, 0.3, 0.1)
    steady = votes.steady(now)
    assert (steady.upper, steady.forearm, steady.hand) == pytest.approx((0.31, 0.24, 0.09))
    np.testing.assert_array_equal(steady.shoulder, now.shoulder)  # where it is now
    np.testing.assert_array_equal(steady.frame, now.frame)
    assert SteadyLengths().steady(now) is now and votes.steady(None) is None


def test_steady_lengths_keep_the_last_votes_only():
    votes = SteadyLengths()
    for _ in range(LENGTH_VOTES):
        votes = votes.add(_arm(0.30))
    assert len(votes.votes) == LENGTH_VOTES
    for _ in range(LENGTH_VOTES // 2 + 1):
        votes = votes.add(_arm(0.40))
    assert len(votes.votes) == LENGTH_VOTES
    assert votes.steady(_arm(0.3)).upper == pytest.approx(0.40)

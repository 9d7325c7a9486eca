"""The look round's memory of the person: both arms from the newest skeleton that shows both
shoulders (one of them mirrored through the neck when hidden)."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.robot.effectivity.person_map import (
    FOREARM_PER_HEIGHT,
    SHOULDER_DEPTH,
    SHOULDER_WIDTH_PER_HEIGHT,
    receiving_arms,
)
from hsr_handover.robot.perception.skeleton import Skeleton
from tests.robot.intent.synthetic_person import keypoints


def _skeleton(shift: float = 0.0, without: tuple[str, ...] = ()) -> Skeleton:
    points, confidence = keypoints()
    points, confidence = points.copy(), confidence.copy()
    shoulders = [keypoint_index("r_shoulder"), keypoint_index("l_shoulder")]
    points[keypoint_index("neck")] = points[shoulders].mean(axis=0)  # OpenPose's: between them
    for name in without:
        confidence[keypoint_index(name)] = 0.0
    return Skeleton(np.zeros((18, 2)), points + [shift, 0.0, 0.0], confidence)


def test_the_newest_skeleton_with_both_shoulders_gives_both_arms_the_right_first():
    newest, older = _skeleton(0.0), _skeleton(0.3)
    right, left = receiving_arms([newest, older])
    assert (right.side, left.side) == ("r", "l")
    for arm, name in ((right, "r_shoulder"), (left, "l_shoulder")):
        behind = newest.points[keypoint_index(name)] - SHOULDER_DEPTH * arm.frame[:, 0]
        np.testing.assert_allclose(arm.shoulder, behind)


def test_a_skeleton_without_a_shoulder_or_neck_falls_back_to_the_last_glimpse():
    out_of_view, glimpse = _skeleton(without=("l_shoulder", "neck")), _skeleton(0.3)
    right, _ = receiving_arms([out_of_view, glimpse])
    behind = glimpse.points[keypoint_index("r_shoulder")] - SHOULDER_DEPTH * right.frame[:, 0]
    np.testing.assert_allclose(right.shoulder, behind)
    assert receiving_arms([out_of_view]) == ()
    assert receiving_arms([]) == ()


def test_a_hidden_shoulder_is_mirrored_through_the_neck():
    whole, hidden = _skeleton(), _skeleton(without=("r_shoulder",))
    for seen, mirrored in zip(receiving_arms([whole]), receiving_arms([hidden]), strict=True):
        np.testing.assert_allclose(mirrored.shoulder, seen.shoulder, atol=0.02)
        assert mirrored.upper == pytest.approx(seen.upper, rel=0.05)


def test_an_unseen_forearm_takes_the_bodys_proportions():
    skeleton = _skeleton(without=("r_wrist",))
    shoulders = skeleton.points[[keypoint_index("r_shoulder"), keypoint_index("l_shoulder")]]
    height = np.linalg.norm(shoulders[0] - shoulders[1]) / SHOULDER_WIDTH_PER_HEIGHT
    unseen = receiving_arms([skeleton])[0]
    assert unseen.upper == pytest.approx(receiving_arms([_skeleton()])[0].upper)
    assert unseen.forearm == pytest.approx(FOREARM_PER_HEIGHT * height)


def test_the_arms_size_is_the_median_over_the_views_not_the_newest_alone():
    """A pose detector's error persists over a held pose: one view's shoulders 6 cm narrower
    does not shrink the person when two others agree."""
    narrow = _skeleton()
    points = narrow.points.copy()
    for name in ("r_shoulder", "l_shoulder"):  # each 3 cm toward the midline
        i = keypoint_index(name)
        points[i, 1] -= 0.03 * np.sign(points[i, 1])
    narrow = Skeleton(narrow.pixels, points, narrow.confidence)
    alone = receiving_arms([narrow])[0]
    among = receiving_arms([narrow, _skeleton(0.3), _skeleton(0.2)])[0]
    whole = receiving_arms([_skeleton()])[0]
    assert alone.hand < 0.9 * whole.hand  # the hand is sized by the height alone
    assert among.hand == pytest.approx(whole.hand)
    np.testing.assert_allclose(among.shoulder, alone.shoulder)  # placed where last seen

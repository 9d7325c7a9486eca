"""The look round's memory of the person: the newest skeleton that shows both shoulders."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.effectivity.person_map import (
    FOREARM_PER_HEIGHT,
    SHOULDER_DEPTH,
    SHOULDER_WIDTH_PER_HEIGHT,
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

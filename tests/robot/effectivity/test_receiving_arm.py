"""The look round's memory of the person: both arms from the newest skeleton that shows both
shoulders (one of them mirrored through the neck when hidden), the shoulders steady over the
frames of about a second from it."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.robot.effectivity.person_map import (
    FOREARM_PER_HEIGHT,
    SHOULDER_DEPTH,
    SHOULDER_WIDTH_PER_HEIGHT,
    STEADY_FRAMES,
    receiving_arms,
    steady_shoulders,
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


def test_both_arms_the_right_first_lie_a_deltoids_depth_behind_the_shoulders():
    newest = _skeleton(0.0)
    right, left = receiving_arms([newest, newest])
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
    np.testing.assert_allclose(among.shoulder, whole.shoulder + [0.2, 0.0, 0.0])  # the median


def _lifted(skeleton: Skeleton, toward_robot: float, name: str = "r_shoulder") -> Skeleton:
    """`skeleton` with the keypoint `name` lifted `toward_robot` m nearer the robot (-x: the
    synthetic person faces it), as onto an object held up between the camera and the body."""
    points = skeleton.points.copy()
    points[keypoint_index(name), 0] -= toward_robot
    return Skeleton(skeleton.pixels, points, skeleton.confidence)


def _jittered(count: int, seed: int = 0) -> list[Skeleton]:
    """`count` frames of the seated person, each keypoint 1 cm off at random, as lifted."""
    rng = np.random.default_rng(seed)
    frames = []
    for _ in range(count):
        skeleton = _skeleton()
        points = skeleton.points + rng.normal(0.0, 0.01, skeleton.points.shape)
        frames.append(Skeleton(skeleton.pixels, points, skeleton.confidence))
    return frames


@pytest.mark.parametrize("at", [0, 4, STEADY_FRAMES - 1])
def test_one_frames_shoulder_lifted_onto_a_held_object_does_not_move_the_arm(at):
    """A pose detector can put a shoulder onto the cup the robot holds up in front of the
    camera, a quarter metre toward it: the arm the handover is planned for stays where the
    person's shoulder is, whichever of the last second's frames it is, the newest included."""
    frames = _jittered(STEADY_FRAMES)
    frames[at] = _lifted(frames[at], 0.26)
    right, left = receiving_arms(frames)
    true_right, true_left = receiving_arms([_skeleton()])
    assert np.linalg.norm(right.shoulder - true_right.shoulder) < 0.02
    assert np.linalg.norm(left.shoulder - true_left.shoulder) < 0.02
    assert right.frame[:, 0] @ true_right.frame[:, 0] > np.cos(np.radians(3.0))  # not turned


def test_a_person_who_moved_is_placed_where_the_latest_second_shows_them():
    """Views older than STEADY_FRAMES frames before the latest with both shoulders do not pull
    the arm back to where the person was; views without the shoulders start no window."""
    now = [_skeleton(without=("r_shoulder", "l_shoulder"))] + [_skeleton(0.0)] * STEADY_FRAMES
    before = [_skeleton(0.4)] * STEADY_FRAMES
    right = receiving_arms(now + before)[0]
    np.testing.assert_allclose(right.shoulder, receiving_arms([_skeleton(0.0)])[0].shoulder)


def test_each_shoulder_is_the_median_of_the_frames_that_show_it():
    right, left = np.array([1.8, -0.2, 1.0]), np.array([1.8, 0.2, 1.0])
    pairs = [(right, left), (right + [0.0, 0.0, 0.02], None), (right, left + [-0.26, 0, 0])]
    steady_right, steady_left = steady_shoulders(pairs)
    np.testing.assert_allclose(steady_right, right)
    np.testing.assert_allclose(steady_left, left + [-0.13, 0.0, 0.0])  # of two: their mean

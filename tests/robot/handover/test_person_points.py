"""The points of the person the cycle reads from the skeleton: the body and the face apart."""

from __future__ import annotations

import numpy as np

from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.robot.effectivity.person_map import SHOULDER_DEPTH, receiving_arms
from hsr_handover.robot.handover.person_points import face_point, person_point, wrist
from hsr_handover.robot.perception.skeleton import Skeleton
from tests.robot.intent.synthetic_person import keypoints


def test_a_person_with_one_shoulder_hidden_is_still_in_view():
    """Presenting to a standing person at their chest, the robot's arm hides one shoulder: the
    arms take it mirrored through the neck; with the neck hidden too the arms' frame is gone,
    but the person is not."""
    points = np.full((18, 3), np.nan)
    confidence = np.zeros(18)
    neck, shoulder = keypoint_index("neck"), keypoint_index("r_shoulder")
    points[[neck, shoulder]] = [[1.5, 0.2, 1.5], [1.5, 0.05, 1.5]]
    confidence[[neck, shoulder]] = 0.9
    skeleton = Skeleton(np.zeros((18, 2)), points, confidence)
    _, left = receiving_arms([skeleton])
    np.testing.assert_allclose(left.shoulder + SHOULDER_DEPTH * left.frame[:, 0], [1.5, 0.35, 1.5])
    confidence[neck] = 0.0
    skeleton = Skeleton(np.zeros((18, 2)), points, confidence)
    assert receiving_arms([skeleton]) == ()
    np.testing.assert_allclose(person_point(skeleton, None), points[shoulder])
    assert person_point(Skeleton.missing("no person"), None) is None


def test_the_steady_shoulder_is_a_point_on_the_person_only_while_they_are_seen():
    """The arm's shoulder is steady over the last second's frames: a person who left the view
    this frame is not seen now for it (presenting, the robot gives up on a person out of sight)."""
    points = np.full((18, 3), np.nan)
    confidence = np.zeros(18)
    neck = keypoint_index("neck")
    points[neck], confidence[neck] = [1.5, 0.2, 1.5], 0.9
    skeleton = Skeleton(np.zeros((18, 2)), points, confidence)
    whole = Skeleton(np.zeros((18, 2)), *keypoints())
    arm = receiving_arms([whole])[0]
    np.testing.assert_allclose(person_point(skeleton, arm), arm.shoulder)
    assert person_point(Skeleton.missing("no person"), arm) is None


def test_the_face_is_read_apart_from_the_body():
    """Eyes alone are a face seen, not a point of the body to hand toward."""
    points = np.full((18, 3), np.nan)
    confidence = np.zeros(18)
    eye = keypoint_index("l_eye")
    points[eye], confidence[eye] = [1.5, 0.25, 1.65], 0.8
    skeleton = Skeleton(np.zeros((18, 2)), points, confidence)
    np.testing.assert_allclose(face_point(skeleton), points[eye])
    assert person_point(skeleton, None) is None
    assert face_point(Skeleton.missing("no person")) is None


def test_the_receiving_wrist_is_the_sides_and_only_when_seen():
    points = np.full((18, 3), np.nan)
    confidence = np.zeros(18)
    right = keypoint_index("r_wrist")
    points[right], confidence[right] = [1.2, -0.2, 0.9], 0.7
    skeleton = Skeleton(np.zeros((18, 2)), points, confidence)
    np.testing.assert_allclose(wrist(skeleton, "r"), points[right])
    assert wrist(skeleton, "l") is None
    confidence[right] = 0.0  # located, but OpenPose gave it no confidence
    assert wrist(Skeleton(np.zeros((18, 2)), points, confidence), "r") is None

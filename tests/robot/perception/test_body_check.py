"""Lifted keypoints no body could hold are dropped (`body_check`), and the lifting drops them."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.robot.perception.body_check import LIFT_SLACK_M, REACH_BETWEEN, body_consistent
from hsr_handover.robot.perception.skeleton import lift_keypoints
from tests.synthetic_person_image import (
    CAMERA,
    KEYPOINTS,
    SURFACE_OFFSET,
    X_WC,
    synthetic_depth,
)

ALL = np.ones(18, dtype=bool)
L_SHOULDER, L_ELBOW, L_WRIST = (
    keypoint_index(f"l_{name}") for name in ("shoulder", "elbow", "wrist")
)


def test_a_body_of_human_proportions_is_kept_whole():
    np.testing.assert_array_equal(body_consistent(KEYPOINTS, ALL), ALL)
    some = ALL.copy()
    some[[0, 14, 15]] = False  # the face unseen: what is missing stays missing
    np.testing.assert_array_equal(body_consistent(KEYPOINTS, some), some)


def test_the_longest_reach_between_keypoints_runs_along_the_bones():
    neck, r_shoulder = keypoint_index("neck"), keypoint_index("r_shoulder")
    across = REACH_BETWEEN[r_shoulder, L_SHOULDER] - LIFT_SLACK_M
    assert across == pytest.approx(2 * (REACH_BETWEEN[neck, L_SHOULDER] - LIFT_SLACK_M))
    np.testing.assert_allclose(REACH_BETWEEN, REACH_BETWEEN.T)


def test_a_shoulder_lifted_onto_something_in_front_is_dropped_alone():
    points = KEYPOINTS.copy()
    points[L_SHOULDER] += [0.0, 0.0, -0.75]  # on the robot's arm, 75 cm nearer the camera
    kept = body_consistent(points, ALL)
    assert not kept[L_SHOULDER] and kept.sum() == 17


def test_two_keypoints_lifted_together_onto_an_occluder_are_dropped_together():
    points = KEYPOINTS.copy()
    points[[L_ELBOW, L_WRIST]] += [0.9, 0.0, -0.9]
    kept = body_consistent(points, ALL)
    assert not kept[L_ELBOW] and not kept[L_WRIST] and kept.sum() == 16


def _lifted_behind_occluder(columns: int, keypoint: int = L_SHOULDER):
    """The `keypoint`'s depth window with `columns` of its 5 columns on something 80 cm in
    front of the person, lifted."""
    depth = synthetic_depth()
    pixels, _ = CAMERA.project(KEYPOINTS, X_WC)
    u, v = np.round(pixels[keypoint]).astype(int)
    depth[v - 2 : v + 3, u - 2 : u - 2 + columns] = KEYPOINTS[keypoint, 2] - SURFACE_OFFSET - 0.8
    return pixels, lift_keypoints(pixels, np.full(18, 0.9), depth, CAMERA, X_WC)


def test_a_keypoint_on_an_occluding_edge_is_lifted_again_from_its_window_s_far_side():
    """Two columns of five on the occluder: the near quarter is the occluder's, the far quarter
    the shoulder's."""
    _, skeleton = _lifted_behind_occluder(2)
    assert skeleton.confidence[L_SHOULDER] > 0
    np.testing.assert_allclose(
        skeleton.points[L_SHOULDER], KEYPOINTS[L_SHOULDER], atol=SURFACE_OFFSET + 0.01
    )


def test_lifting_gives_no_point_for_a_keypoint_hidden_behind_an_occluder():
    """Four columns of five on the occluder: neither quarter is the elbow's."""
    pixels, skeleton = _lifted_behind_occluder(4, L_ELBOW)
    assert skeleton.confidence[L_ELBOW] == 0 and np.isnan(skeleton.points[L_ELBOW]).all()
    np.testing.assert_array_equal(skeleton.pixels[L_ELBOW], pixels[L_ELBOW])
    in_image = np.isfinite(skeleton.pixels).all(axis=1)
    assert (skeleton.confidence[in_image] > 0).sum() == in_image.sum() - 1


def test_a_shoulder_hidden_behind_an_occluder_takes_its_depth_from_the_torso():
    """Four columns of five on the occluder: the shoulder is put at the other shoulder's depth
    mirrored through the neck's, along its own pixel's ray."""
    pixels, skeleton = _lifted_behind_occluder(4)
    assert skeleton.confidence[L_SHOULDER] > 0
    np.testing.assert_array_equal(skeleton.pixels[L_SHOULDER], pixels[L_SHOULDER])
    np.testing.assert_allclose(
        skeleton.points[L_SHOULDER], KEYPOINTS[L_SHOULDER], atol=SURFACE_OFFSET + 0.01
    )

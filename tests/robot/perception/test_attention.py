"""Attention (layer 1): regions found in percepts, sampling weights, the focus schedule."""

from __future__ import annotations

import numpy as np

from hsr_handover.robot.perception.attention import (
    AttentionRegion,
    FocusChange,
    attended_regions,
    attention_weights,
    face_region,
    focus_at,
    hand_region,
)


def _skeleton() -> tuple[np.ndarray, np.ndarray]:
    points = np.full((18, 3), np.nan)
    confidence = np.zeros(18)
    for index, point in {
        0: (1.6, 0, 1.2),
        14: (1.62, 0.03, 1.23),
        15: (1.62, -0.03, 1.23),
        1: (1.75, 0, 1.03),
        4: (1.3, 0.1, 0.9),
        7: (1.7, -0.2, 0.75),
    }.items():
        points[index], confidence[index] = point, 0.9
    return points, confidence


def test_face_is_the_mean_of_visible_face_keypoints():
    points, confidence = _skeleton()
    region = face_region(points, confidence)
    np.testing.assert_allclose(region.center, points[[0, 14, 15]].mean(axis=0))
    confidence[[0, 14, 15]] = 0
    assert face_region(points, confidence) is None


def test_hand_is_the_wrist_held_out_farthest():
    points, confidence = _skeleton()
    # Right hand held out over the table; left forearm resting in front of the body, its
    # wrist lower and farther from the neck in 3-D, but nearer its shoulder horizontally.
    arms = {
        2: (1.75, 0.19, 1.03),
        3: (1.50, 0.16, 1.00),
        4: (1.20, 0.12, 0.95),
        5: (1.75, -0.19, 1.03),
        6: (1.72, -0.25, 0.55),
        7: (1.45, -0.35, 0.40),
    }
    for index, point in arms.items():
        points[index], confidence[index] = point, 0.9
    assert np.linalg.norm(points[7] - points[1]) > np.linalg.norm(points[4] - points[1])
    np.testing.assert_allclose(hand_region(points, confidence).center, points[4])
    confidence[2] = 0  # shoulder unseen: measured from the neck, still the held-out hand
    np.testing.assert_allclose(hand_region(points, confidence).center, points[4])
    confidence[4] = 0
    np.testing.assert_allclose(hand_region(points, confidence).center, points[7])
    confidence[7] = 0
    assert hand_region(points, confidence) is None


def test_weights_raise_only_points_inside_the_region():
    region = AttentionRegion("face", np.zeros(3), 0.5)
    points = np.array([[0.1, 0, 0], [1.0, 0, 0], [np.nan, 0, 0]])
    np.testing.assert_array_equal(attention_weights(points, [region], 16.0), [16.0, 1.0, 1.0])
    np.testing.assert_array_equal(attention_weights(points, [], 16.0), [1.0, 1.0, 1.0])


def test_focus_schedule_and_regions_from_percepts():
    schedule = [
        FocusChange(0.0, "none"),
        FocusChange(1.0, "face"),
        FocusChange(2.0, "object", "red"),
    ]
    assert focus_at(schedule, 0.5).focus == "none"
    assert focus_at(schedule, 1.5).focus == "face"
    assert focus_at(schedule, -1.0) is None
    points, confidence = _skeleton()
    detections = [("blue", np.array([0.8, 0.2, 0.77])), ("red", np.array([0.8, -0.2, 0.77]))]
    assert attended_regions(focus_at(schedule, 0.5), points, confidence, detections) == ()
    (face,) = attended_regions(focus_at(schedule, 1.5), points, confidence, detections)
    assert face.name == "face"
    (red,) = attended_regions(focus_at(schedule, 3.0), None, None, detections)
    np.testing.assert_allclose(red.center, detections[1][1])
    assert attended_regions(focus_at(schedule, 1.5), None, None, detections) == ()
    assert attended_regions(FocusChange(0, "object", "green"), points, confidence, detections) == ()

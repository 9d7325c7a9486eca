"""WristTrail: whether an arm has just risen into its pose (layer 1)."""

from __future__ import annotations

import numpy as np

from hsr_handover.interface.coco18 import NUM_KEYPOINTS
from hsr_handover.robot.intent.person_rays import ARMS
from hsr_handover.robot.intent.wrist_trail import WristTrail

RIGHT_WRIST, LEFT_WRIST = ARMS["right"][2], ARMS["left"][2]
TO_TABLE = np.array([-1.0, 0.0, 0.0])  # where the arms point: the table lies toward -x


def _frame(right, left=(1.0, 0.3, 0.8), seen=(True, True)):
    points = np.zeros((NUM_KEYPOINTS, 3))
    points[RIGHT_WRIST], points[LEFT_WRIST] = right, left
    confidence = np.full(NUM_KEYPOINTS, 0.8)
    confidence[RIGHT_WRIST], confidence[LEFT_WRIST] = (0.8 if s else 0.0 for s in seen)
    return points, confidence


def test_a_wrist_that_travelled_the_rise_within_the_window_rose():
    trail = WristTrail(rise_m=0.08, window_s=2.0)
    for k, x in enumerate(np.linspace(1.4, 1.2, 11)):  # 20 cm in 1 s, toward the table
        trail.add(0.1 * k, *_frame((x, -0.2, 1.0)))
    assert trail.rose("right", TO_TABLE)
    assert not trail.rose("left", TO_TABLE)  # still all along


def test_the_rise_is_forgotten_once_older_than_the_window():
    trail = WristTrail(rise_m=0.08, window_s=2.0)
    for time in (0.0, 0.1, 0.2):
        trail.add(time, *_frame((1.4, -0.2, 1.0)))
    trail.add(0.5, *_frame((1.2, -0.2, 1.0)))
    assert trail.rose("right", TO_TABLE)
    trail.add(2.4, *_frame((1.21, -0.2, 1.0)))  # held there since 0.5 s
    trail.add(2.6, *_frame((1.2, -0.2, 1.0)))
    assert not trail.rose("right", TO_TABLE)


def test_a_wander_below_the_rise_is_not_a_rise_and_unseen_wrists_do_not_count():
    trail = WristTrail(rise_m=0.08, window_s=2.0)
    rng = np.random.default_rng(0)
    for k in range(30):  # a held-out hand, its filtered wrist wandering 5 cm
        trail.add(0.05 * k, *_frame((1.3, 0.0, 1.0) + rng.uniform(-0.025, 0.025, 3)))
    assert not trail.rose("right", TO_TABLE)
    trail.add(1.6, *_frame((0.0, 0.0, 0.0), seen=(False, True)))  # unseen: not at the origin
    assert not trail.rose("right", TO_TABLE)
    assert not WristTrail(0.08, 2.0).rose("left", TO_TABLE)  # never seen


def test_one_frame_with_the_arms_swapped_is_not_a_rise():
    """The detector puts a resting right wrist on the left one for a frame, 40 cm across: the
    wrist has not moved; a rise takes frames."""
    trail = WristTrail(rise_m=0.08, window_s=2.0)
    left = (1.0, 0.3, 0.8)
    for k in range(20):
        right = left if k == 5 else (1.0, -0.1, 0.8)
        trail.add(0.05 * k, *_frame(right, left))
    assert not trail.rose("right", TO_TABLE)
    for k in range(20, 23):  # now it really rises, for three frames
        trail.add(0.05 * k, *_frame((0.8, -0.1, 0.9), left))
    assert trail.rose("right", TO_TABLE)


def test_a_wrist_slipping_back_from_where_the_arm_points_has_not_risen():
    """A resting wrist lifted from depth as the camera moves slips back onto the lap, 18 cm
    away from the table, over several frames: a travel, not toward where the arm points."""
    trail = WristTrail(rise_m=0.08, window_s=2.0)
    for k, x in enumerate([1.35] * 10 + [1.37, 1.45, 1.52, 1.53]):
        trail.add(0.1 * k, *_frame((x, -0.2, 0.8)))
    assert not trail.rose("right", TO_TABLE)
    assert trail.rose("right", -TO_TABLE)  # the same travel toward where it would point

"""A shoulder hidden behind its own arm takes its depth from the torso (`torso_depth`)."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.robot.perception.torso_depth import (
    SHOULDER_DEPTH_TOLERANCE_M,
    torso_shoulder_depths,
)

NECK, RIGHT, LEFT = (keypoint_index(name) for name in ("neck", "r_shoulder", "l_shoulder"))
DETECTED = np.ones(18, dtype=bool)


def _depths(neck: float, right: float, left: float) -> np.ndarray:
    depths = np.full(18, 2.5)
    depths[[NECK, RIGHT, LEFT]] = neck, right, left
    return depths


def test_a_shoulder_read_on_the_arm_in_front_of_it_is_put_at_the_torsos_depth():
    # The intent experiment's trial 4 at seed 1: the shoulder 24 cm in front of the neck.
    mended = torso_shoulder_depths(_depths(1.65, 1.41, 1.69), DETECTED)
    assert mended[RIGHT] == pytest.approx(1.61) and mended[LEFT] == 1.69
    np.testing.assert_array_equal(
        np.delete(mended, RIGHT), np.delete(_depths(1.65, 1.41, 1.69), RIGHT)
    )


def test_a_turned_torso_is_left_as_it_was_seen():
    """Turned 60 degrees, one shoulder is 17 cm nearer than the neck and the other as far
    behind: the mirror agrees with both."""
    seen = _depths(2.0, 1.83, 2.17)
    np.testing.assert_array_equal(torso_shoulder_depths(seen, DETECTED), seen)
    just_within = _depths(2.0, 2.0 - SHOULDER_DEPTH_TOLERANCE_M + 0.01, 2.0)
    np.testing.assert_array_equal(torso_shoulder_depths(just_within, DETECTED), just_within)


def test_a_detected_shoulder_without_depth_takes_the_mirror_an_undetected_one_nothing():
    seen = _depths(2.0, np.nan, 2.05)
    assert torso_shoulder_depths(seen, DETECTED)[RIGHT] == pytest.approx(1.95)
    undetected = DETECTED.copy()
    undetected[RIGHT] = False  # OpenPose found no pixel: nothing to put a depth on
    assert np.isnan(torso_shoulder_depths(seen, undetected)[RIGHT])


def test_without_the_neck_nothing_is_mended():
    seen = _depths(np.nan, 1.6, 2.0)
    np.testing.assert_array_equal(torso_shoulder_depths(seen, DETECTED), seen)


def test_a_shoulder_alone_cannot_be_checked_and_stays_as_seen():
    seen = _depths(2.0, 1.6, np.nan)
    seen_only = DETECTED.copy()
    seen_only[LEFT] = False
    np.testing.assert_array_equal(torso_shoulder_depths(seen, seen_only), seen)

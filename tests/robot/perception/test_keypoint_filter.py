"""The keypoint filter: smoothing, outliers, swapped arms and short misses."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.robot.perception.keypoint_filter import KeypointFilter, KeypointFilterParams

DT = 1.0 / 30.0
R_WRIST, L_WRIST = keypoint_index("r_wrist"), keypoint_index("l_wrist")
R_ARM = [keypoint_index(f"r_{j}") for j in ("shoulder", "elbow", "wrist")]
L_ARM = [keypoint_index(f"l_{j}") for j in ("shoulder", "elbow", "wrist")]
# A person at the table, arms apart (world frame, m).
BODY = np.column_stack([np.full(18, 1.6), np.linspace(-0.4, 0.4, 18), np.linspace(0.6, 1.4, 18)])
BODY[R_ARM] = [[1.6, -0.2, 1.3], [1.5, -0.35, 1.1], [1.35, -0.4, 0.95]]
BODY[L_ARM] = [[1.6, 0.2, 1.3], [1.5, 0.35, 1.1], [1.35, 0.4, 0.95]]
FULL = np.full(18, 0.9)


def _feed(keypoint_filter, frames, start=0):
    """Feed (points, confidence) frames from frame index `start`; the last output."""
    for k, (points, confidence) in enumerate(frames, start):
        out = keypoint_filter.update(k * DT, points, confidence)
    return out


def _noisy(rng, sd=0.01):
    return BODY + sd * rng.standard_normal(BODY.shape)


STEADY = KeypointFilterParams(acceleration_sd=2.0)  # a filter that smooths, for its mechanics


def test_smoothing_reduces_the_jitter_of_a_still_person():
    rng = np.random.default_rng(0)
    keypoint_filter, errors_in, errors_out = KeypointFilter(STEADY), [], []
    for k in range(300):
        frame = _noisy(rng, 0.02)
        points, _ = keypoint_filter.update(k * DT, frame, FULL)
        if k > 30:
            errors_in.append(frame - BODY)
            errors_out.append(points - BODY)
    assert np.std(errors_out) < 0.5 * np.std(errors_in)


def test_a_pointing_reach_is_followed_within_a_few_centimetres():
    """A minimum-jerk reach of 0.45 m in 0.6 s: peak speed 1.3 m/s, peak acceleration 7 m/s^2."""
    keypoint_filter, lags = KeypointFilter(STEADY), []
    _feed(keypoint_filter, [(BODY, FULL)] * 15)
    for k in range(15, 60):
        s = np.clip((k - 15) * DT / 0.6, 0.0, 1.0)
        frame = BODY.copy()
        frame[R_WRIST] += [-0.45 * (10 * s**3 - 15 * s**4 + 6 * s**5), 0.0, 0.0]
        points, confidence = keypoint_filter.update(k * DT, frame, FULL)
        lags.append(np.linalg.norm(points[R_WRIST] - frame[R_WRIST]))
    assert keypoint_filter.rejected == 0
    assert max(lags) < 0.08 and lags[-1] < 0.01


def test_an_outlier_for_two_frames_is_rejected_and_a_real_jump_taken_up():
    rng = np.random.default_rng(1)
    keypoint_filter = KeypointFilter(STEADY)
    _feed(keypoint_filter, [(_noisy(rng), FULL) for _ in range(30)])
    spurious = [_noisy(rng) for _ in range(2)]
    for frame in spurious:
        frame[R_WRIST] += [-0.2, 0.1, 0.0]  # on a cup beside the hand
    points, confidence = _feed(keypoint_filter, [(f, FULL) for f in spurious], start=30)
    assert np.linalg.norm(points[R_WRIST] - BODY[R_WRIST]) < 0.03
    assert confidence[R_WRIST] > 0  # held from its track
    assert keypoint_filter.rejected == 2
    moved = BODY.copy()
    moved[R_WRIST] += [-0.3, 0.0, 0.0]
    points, _ = _feed(keypoint_filter, [(moved, FULL)] * 3, start=32)
    np.testing.assert_allclose(points[R_WRIST], moved[R_WRIST], atol=0.01)


@pytest.mark.parametrize("jump, rejected", [(0.25, 0), (0.4, 1)])
def test_by_default_only_a_gross_jump_is_an_outlier(jump, rejected):
    """Lifted keypoints slip 5-15 cm in depth between a limb and what is behind it: the
    default gate lets a frame's jump of a hand's length through and stops one of 40 cm."""
    keypoint_filter = KeypointFilter()
    _feed(keypoint_filter, [(BODY, FULL)] * 30)
    frame = BODY.copy()
    frame[R_WRIST] += [jump, 0.0, 0.0]
    keypoint_filter.update(30 * DT, frame, FULL)
    assert keypoint_filter.rejected == rejected


def test_swapped_arms_are_exchanged_back():
    rng = np.random.default_rng(2)
    keypoint_filter = KeypointFilter()
    _feed(keypoint_filter, [(_noisy(rng), FULL) for _ in range(30)])
    swapped = _noisy(rng)
    swapped[R_ARM + L_ARM] = swapped[L_ARM + R_ARM]
    points, _ = keypoint_filter.update(30 * DT, swapped, FULL)
    np.testing.assert_allclose(points[R_ARM], BODY[R_ARM], atol=0.03)
    np.testing.assert_allclose(points[L_ARM], BODY[L_ARM], atol=0.03)
    assert keypoint_filter.swaps == 1
    # A lone arm reported under the other's name is given back its own.
    lone = _noisy(rng)
    lone[L_ARM] = lone[R_ARM]
    confidence = FULL.copy()
    confidence[R_ARM] = 0.0
    points, confidence = keypoint_filter.update(31 * DT, lone, confidence)
    np.testing.assert_allclose(points[R_ARM], BODY[R_ARM], atol=0.03)
    assert keypoint_filter.swaps == 2


def test_a_missed_keypoint_is_held_briefly_then_missing():
    rng = np.random.default_rng(3)
    keypoint_filter = KeypointFilter()
    _feed(keypoint_filter, [(_noisy(rng), FULL) for _ in range(30)])
    gone = FULL.copy()
    gone[R_WRIST] = 0.0
    points, confidence = keypoint_filter.update(30 * DT, _noisy(rng), gone)
    assert 0 < confidence[R_WRIST] < FULL[R_WRIST]
    assert np.linalg.norm(points[R_WRIST] - BODY[R_WRIST]) < 0.03
    hold = KeypointFilterParams().hold_s
    points, confidence = keypoint_filter.update(30 * DT + hold + 0.05, _noisy(rng), gone)
    assert confidence[R_WRIST] == 0 and np.isnan(points[R_WRIST]).all()
    assert confidence[L_WRIST] > 0


def test_a_low_confidence_measurement_moves_the_track_less():
    moves = []
    for confidence in (0.9, 0.2):
        keypoint_filter = KeypointFilter()
        _feed(keypoint_filter, [(BODY, FULL)] * 30)
        frame, weights = BODY.copy(), FULL.copy()
        frame[R_WRIST] += [0.0, 0.05, 0.0]
        weights[R_WRIST] = confidence
        points, _ = keypoint_filter.update(30 * DT, frame, weights)
        moves.append(np.linalg.norm(points[R_WRIST] - BODY[R_WRIST]))
    assert moves[1] < 0.3 * moves[0]


def test_a_copy_has_its_own_tracks():
    keypoint_filter = KeypointFilter()
    _feed(keypoint_filter, [(BODY, FULL)] * 5)
    clone = copy.deepcopy(keypoint_filter)
    clone.update(5 * DT, BODY + 0.5, FULL)
    points, _ = keypoint_filter.update(5 * DT, BODY, FULL)
    np.testing.assert_allclose(points, BODY, atol=1e-6)


@pytest.mark.parametrize("field, value", [("gate_sd", 0.0), ("reacquire_frames", 0),
                                          ("hold_s", -1.0), ("swap_ratio", 2.0)])  # fmt: skip
def test_a_parameter_out_of_range_names_itself(field, value):
    with pytest.raises(ValueError, match=f"^{field}"):
        KeypointFilterParams(**{field: value})

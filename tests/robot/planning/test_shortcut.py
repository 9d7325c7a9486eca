"""Partial shortcutting: a clear polyline made faster, stretch by stretch and joint group by
joint group, never through what the check forbids and never moving its ends."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.robot.planning.shortcut import resampled, seconds, shorten

SPEEDS = np.array([1.0, 1.0])
ALL, FIRST, SECOND = [0, 1], [0], [1]


def _always(stretch: np.ndarray, first: int) -> bool:
    return True


def test_seconds_take_each_segment_at_its_slowest_joint():
    points = np.array([[0.0, 0.0], [1.0, 0.5], [1.0, 2.5]])
    assert seconds(points, SPEEDS) == pytest.approx(1.0 + 2.0)
    assert seconds(points, np.array([0.5, 1.0])) == pytest.approx(2.0 + 2.0)
    assert seconds(points[:1], SPEEDS) == 0.0


def test_resampled_vertices_are_evenly_spaced_in_time_and_keep_the_ends():
    keys = np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 1.0]])
    points = resampled(keys, SPEEDS, 9)
    np.testing.assert_allclose(points[[0, -1]], keys[[0, -1]])
    steps = np.abs(np.diff(points, axis=0)).max(axis=1)
    np.testing.assert_allclose(steps, 0.5)


def test_one_joint_then_the_other_becomes_both_together():
    """The arm first, then the base: shortcuts in one joint let the two move at once, and
    the time falls from their sum towards the longer one."""
    keys = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    points = resampled(keys, SPEEDS, 21)
    shortened = shorten(points, SPEEDS, [FIRST, SECOND], _always, attempts=300)
    assert seconds(points, SPEEDS) == pytest.approx(2.0)
    assert seconds(shortened, SPEEDS) < 1.3
    np.testing.assert_allclose(shortened[[0, -1]], points[[0, -1]])


def test_a_stretch_the_check_refuses_is_never_taken():
    """A way round a square obstacle (|x - 1| < 0.5 and |y| < 0.5) keeps round it."""

    def outside(stretch: np.ndarray, first: int) -> bool:
        shares = np.linspace(0.0, 1.0, 200)[:, None, None]
        dense = (stretch[:-1] + shares * np.diff(stretch, axis=0)).reshape(-1, 2)
        inside = (np.abs(dense[:, 0] - 1.0) < 0.5) & (np.abs(dense[:, 1]) < 0.5)
        return not inside.any()

    keys = np.array([[0.0, 0.0], [0.0, 0.8], [2.0, 0.8], [2.0, 0.0]])
    points = resampled(keys, SPEEDS, 25)
    shortened = shorten(points, SPEEDS, [ALL, FIRST, SECOND], outside, attempts=300)
    assert outside(shortened, 0)
    assert seconds(shortened, SPEEDS) < seconds(points, SPEEDS)
    assert seconds(shortened, SPEEDS) >= 2.0  # at least the way along the obstacle's side


def test_the_same_seed_gives_the_same_path():
    keys = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 2.0]])
    points = resampled(keys, SPEEDS, 20)
    one = shorten(points, SPEEDS, [ALL, FIRST, SECOND], _always, attempts=40, seed=3)
    again = shorten(points, SPEEDS, [ALL, FIRST, SECOND], _always, attempts=40, seed=3)
    np.testing.assert_array_equal(one, again)
    assert seconds(one, SPEEDS) <= seconds(points, SPEEDS)

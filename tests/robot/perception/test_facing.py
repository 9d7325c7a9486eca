"""SteadyFacing: the torso's facing voted over frames (perception/facing.py)."""

from __future__ import annotations

import math

import numpy as np

from hsr_handover.robot.perception.facing import SteadyFacing, steady_facing


def _heading(deg: float) -> np.ndarray:
    return np.array([math.cos(math.radians(deg)), math.sin(math.radians(deg)), 0.0])


def test_the_steady_facing_is_the_mean_of_the_busiest_window_and_outvotes_the_rest():
    facing = SteadyFacing()
    assert facing.direction() is None
    for deg in (-3.0, 3.0, -3.0, 3.0, 91.0, 95.0, 179.0):  # two frames fitted on an arm
        facing = facing.add(_heading(deg))
    np.testing.assert_allclose(facing.direction(), [1.0, 0.0, 0.0], atol=1e-12)
    before = facing.direction()
    facing.add(_heading(90.0))  # adding makes a new facing; this one is unchanged
    np.testing.assert_array_equal(facing.direction(), before)
    across_the_seam = SteadyFacing().add(_heading(178.0)).add(_heading(-178.0))
    np.testing.assert_allclose(across_the_seam.direction(), [-1.0, 0.0, 0.0], atol=1e-12)


def test_a_facing_not_seen_adds_no_vote():
    seen = SteadyFacing().add(_heading(10.0))
    for unseen in (None, np.full(3, np.nan)):
        assert seen.add(unseen) is seen
    np.testing.assert_allclose(
        steady_facing([None, _heading(10.0), np.full(3, np.nan)]), _heading(10.0), atol=1e-12
    )
    assert steady_facing([None, np.full(3, np.nan)]) is None

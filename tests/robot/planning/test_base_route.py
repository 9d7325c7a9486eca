"""The base's way round the table, the optimiser's first guess when the line crosses it."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from hsr_handover.hsr import BASE_RADIUS
from hsr_handover.robot.perception.table_fit import TableEstimate
from hsr_handover.robot.planning.base_route import ROUTE_MARGIN, route_around, route_out

TABLE = TableEstimate(0.72, np.array([0.85, 0.0]), np.array([0.6, 1.0]), 0.0, 5000)


def _clear_of_table(route: np.ndarray) -> bool:
    """Every point along the route keeps the base's disc off the table's top."""
    half = TABLE.size / 2 + BASE_RADIUS
    for a, b in itertools.pairwise(route):
        for t in np.linspace(0, 1, 200):
            point = (1 - t) * a + t * b - TABLE.center
            if np.all(np.abs(point) < half):
                return False
    return True


def test_a_clear_line_is_kept():
    route = route_around(np.array([0.0, 0.0]), np.array([0.2, -0.6]), TABLE)
    np.testing.assert_allclose(route, [[0.0, 0.0], [0.2, -0.6]])


def test_the_way_to_the_far_side_goes_round_the_nearer_corners():
    start, goal = np.array([0.0, -0.2]), np.array([1.75, -0.3])
    route = route_around(start, goal, TABLE)
    assert len(route) == 4 and _clear_of_table(route)
    # Round the -y side (the nearer one), through the two corners on that side.
    corner_y = -(TABLE.size[1] / 2 + BASE_RADIUS + ROUTE_MARGIN)
    np.testing.assert_allclose(route[1:3, 1], corner_y)
    assert not _clear_of_table(np.array([start, goal]))


def test_without_a_table_the_line_is_the_way():
    route = route_around(np.array([0.0, 0.0]), np.array([2.0, 0.0]), None)
    assert len(route) == 2


def test_a_base_at_the_table_drives_straight_out_then_round_then_in():
    """A grasp's base stands nearer the table than the route's margin: `route_around` has
    nothing better than the straight line through the table; `route_out` backs out from the
    nearest side, goes round the corner and drives in to a goal that stands at the table too."""
    start = np.array([TABLE.center[0] - 0.3 - BASE_RADIUS - 0.04, 0.1])  # at the -x side
    goal = np.array([TABLE.center[0] + 0.1, -0.5 - BASE_RADIUS - 0.05])  # at the -y side
    assert len(route_around(start, goal, TABLE)) == 2
    route = route_out(start, goal, TABLE)
    half = TABLE.size / 2 + BASE_RADIUS + ROUTE_MARGIN
    out = route[1] - TABLE.center
    assert out[0] == pytest.approx(-half[0], abs=2e-3) and out[1] == pytest.approx(0.1)
    into = route[-2] - TABLE.center
    assert into[1] == pytest.approx(-half[1], abs=2e-3)
    assert len(route) == 5  # start, out, the corner, in, goal
    np.testing.assert_allclose(route[[0, -1]], [start, goal])
    assert _clear_of_table(route[1:-1])


def test_route_out_from_a_base_clear_of_the_margin_is_route_around():
    start, goal = np.array([0.0, -0.2]), np.array([1.75, -0.3])
    np.testing.assert_allclose(route_out(start, goal, TABLE), route_around(start, goal, TABLE))

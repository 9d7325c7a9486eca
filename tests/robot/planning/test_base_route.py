"""The base's way round the table, the optimiser's first guess when the line crosses it."""

from __future__ import annotations

import itertools

import numpy as np

from hsr_handover.hsr import BASE_RADIUS
from hsr_handover.robot.perception.table_fit import TableEstimate
from hsr_handover.robot.planning.base_route import ROUTE_MARGIN, route_around

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

"""Map quality metrics on cases small enough to check by hand."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.topology import metrics

NODES = np.array([[0.0, 0.0], [1.0, 0.0], [3.0, 0.0]])
EDGES = np.array([[0, 1]])


def test_quantisation_error_is_mean_euclidean_distance():
    points = np.array([[0.0, 0.5], [1.0, -2.0], [3.0, 0.0], [np.nan, 0.0]])
    assert metrics.quantisation_error(NODES, points) == pytest.approx((0.5 + 2.0 + 0.0) / 3)
    assert metrics.mean_squared_error(NODES, points) == pytest.approx((0.25 + 4.0) / 3)


def test_topographic_error_counts_unlinked_nearest_pairs():
    points = np.array([[0.4, 0.0], [2.2, 0.0], [2.9, 0.0], [0.6, 0.1]])
    # nearest pairs: (0,1) linked, (2,1) not, (2,1) not, (1,0) linked
    assert metrics.topographic_error(NODES, EDGES, points) == pytest.approx(0.5)


def test_node_density_per_measure():
    inside = np.array([True, True, False])
    assert metrics.node_density(NODES, inside, 0.5, 4.0) == (4.0, 0.25)
    with pytest.raises(ValueError, match="inside"):
        metrics.node_density(NODES, inside[:2], 1.0, 1.0)

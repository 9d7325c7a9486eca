"""Detections cross-checked against the scene map's nodes."""

from __future__ import annotations

import numpy as np

from hsr_handover.robot.perception.cloud_map import GraphSnapshot
from hsr_handover.robot.perception.cross_check import support_of


def test_detections_are_confirmed_only_where_the_map_has_nodes():
    nodes = np.array([[0.8, 0.0, 0.78], [0.82, 0.01, 0.76], [0.8, -0.02, 0.8], [1.5, 0, 1.2]])
    graph = GraphSnapshot(nodes, np.array([[0, 1], [1, 2]]), np.array([0, 0, 0, 1]))
    detections = [("yellow", np.array([0.8, 0.0, 0.78])), ("red", np.array([0.8, -0.3, 0.77])),
                  ("blue", np.full(3, np.nan))]  # fmt: skip
    yellow, red, blue = support_of(detections, graph)
    assert (yellow.nodes, yellow.cluster, yellow.confirmed) == (3, 0, True)
    assert (red.nodes, red.cluster, red.confirmed) == (0, -1, False)
    assert not blue.confirmed

"""The attention experiment's measurements on known inputs."""

from __future__ import annotations

import math

import numpy as np

from hsr_handover.experiments.attention import density_ratio, settle_time
from hsr_handover.perception.attention import AttentionRegion
from hsr_handover.perception.cloud_map import GraphSnapshot


def test_density_ratio_is_nodes_per_point_inside_over_outside():
    region = AttentionRegion("face", np.zeros(3), 1.0)
    points = np.vstack([np.zeros((100, 3)), np.full((300, 3), 5.0)])
    nodes = np.vstack([np.zeros((8, 3)), np.full((6, 3), 5.0)])
    graph = GraphSnapshot(nodes, np.zeros((0, 2), dtype=int), np.zeros(14, dtype=int))
    assert density_ratio(graph, points, region) == (8 / 100) / (6 / 300)
    assert math.isnan(density_ratio(graph, np.full((10, 3), 5.0), region))


def test_settle_time_is_when_the_count_stays_within_the_band():
    times = np.arange(0, 4, 0.1)
    counts = np.where(times < 1.5, 300, 200).astype(float)
    counts[times >= 2.3] = 202  # within 5% of the phase's final value
    assert settle_time(times, counts, 1.0, 4.0) == np.float64(times[times >= 1.5][0] - 1.0)
    assert settle_time(times, np.full(40, 5.0), 1.0, 4.0) == 0.0
    assert math.isnan(settle_time(times, counts, 10.0, 11.0))

"""The attention experiment's measurements on known inputs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hsr_handover.experiments.attention.experiment import (
    SMOOTHING_S,
    density_ratio,
    pixel_areas,
    settle_time,
)
from hsr_handover.robot.perception.attention import AttentionRegion
from hsr_handover.robot.perception.cloud_map import GraphSnapshot


def test_pixel_areas_measure_the_surface_and_skip_depth_jumps():
    # A 10 x 10 grid on a plane tilted 60 degrees, 1 cm spacing along u, 2 cm along v, and a
    # step of 0.5 m after column 6 (a silhouette edge).
    u, v = np.meshgrid(np.arange(10) * 0.01, np.arange(10) * 0.02)
    cloud = np.stack([u, v * np.cos(np.pi / 3), v * np.sin(np.pi / 3)], axis=2)
    cloud[:, 7:, 2] += 0.5
    areas = pixel_areas(cloud.reshape(-1, 3), 10, 10).reshape(10, 10)
    # Every pixel has a continuous neighbour along both axes (the edge ones step backwards).
    np.testing.assert_allclose(areas, 0.01 * 0.02)
    cloud[4, 3, 2] += 0.5  # a lone pixel in the air has no continuous neighbour
    areas = pixel_areas(cloud.reshape(-1, 3), 10, 10).reshape(10, 10)
    assert areas[4, 3] == 0 and np.count_nonzero(areas == 0) == 1


def test_density_ratio_is_nodes_per_area_inside_over_outside():
    region = AttentionRegion("face", np.zeros(3), 1.0)
    points = np.vstack([np.zeros((100, 3)), np.full((300, 3), 5.0)])
    areas = np.concatenate([np.full(100, 0.001), np.full(300, 0.002)])
    nodes = np.vstack([np.zeros((8, 3)), np.full((6, 3), 5.0)])
    graph = GraphSnapshot(nodes, np.zeros((0, 2), dtype=int), np.zeros(14, dtype=int))
    assert density_ratio(graph, points, areas, region) == pytest.approx((8 / 0.1) / (6 / 0.6))
    assert math.isnan(density_ratio(graph, np.full((10, 3), 5.0), np.ones(10), region))


def test_settle_time_is_the_90_percent_rise_time():
    times = np.arange(0, 4, 0.1)
    counts = np.where(times < 1.5, 300.0, 200.0)
    counts[times >= 2.3] = 202.0  # settles a little above the step's bottom
    # The step at 1.5 s is 0.5 s after the shift; the centred smoothing blurs it by half its
    # window at most.
    assert 0.5 <= settle_time(times, counts, 1.0, 4.0) <= 0.5 + SMOOTHING_S / 2 + 1e-9
    rising = np.clip((times - 1.0) * 100.0, 0.0, 50.0)  # 0 -> 50 over 0.5 s from the shift
    assert settle_time(times, rising, 1.0, 4.0) == pytest.approx(0.45, abs=0.1)
    noisy = 100 + np.random.default_rng(0).normal(0, 1.5, len(times))  # no step, just noise
    assert settle_time(times, noisy, 1.0, 4.0) == 0.0
    assert math.isnan(settle_time(times, counts, 10.0, 11.0))

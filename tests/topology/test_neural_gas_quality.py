"""Growing Neural Gas on surfaces: quality, adaptation to a new scene, attention."""

from __future__ import annotations

import numpy as np
import pytest

from hsr_handover.topology import GrowingNeuralGas, metrics
from hsr_handover.topology.synthetic import (
    THREE_BOX_CENTRES,
    THREE_BOX_SIZES,
    box_surface_area,
    box_surface_points,
)

BENCHMARK_PARAMS = dict(
    max_nodes=300, lam=100, mu1=0.05, mu2=0.006, a_max=50, alpha=0.5, beta=0.0005
)


@pytest.mark.parametrize("seed", [0, 1])
def test_quality_on_three_boxes(seed):
    rng = np.random.default_rng(100 + seed)
    train, held_out = box_surface_points(50_000, rng), box_surface_points(20_000, rng)
    gas = GrowingNeuralGas(**BENCHMARK_PARAMS, random_state=seed).fit(train)
    assert gas.n_nodes == 300
    assert metrics.quantisation_error(gas.nodes, held_out) == pytest.approx(0.047, rel=0.05)
    assert metrics.topographic_error(gas.nodes, gas.edges, held_out) < 0.02


def distance_to_box(points, centre, size):
    return np.linalg.norm(np.maximum(np.abs(points - centre) - size / 2, 0.0), axis=1)


def test_map_follows_the_scene_to_a_new_box():
    rng = np.random.default_rng(7)
    size = np.array([0.5, 0.5, 0.5])
    first, second = np.array([0.0, 0.0, 0.25]), np.array([2.0, 0.0, 0.25])
    held_out = box_surface_points(10_000, rng, second, size)
    params = dict(max_nodes=100, e_min=0.005)
    gas = GrowingNeuralGas(**params, random_state=0)
    gas.fit(box_surface_points(30_000, rng, first, size))
    gas.partial_fit(box_surface_points(20_000, rng, second, size))
    assert np.all(distance_to_box(gas.nodes, first, size) > 0.2)
    fresh = GrowingNeuralGas(**params, random_state=1)
    fresh.fit(box_surface_points(20_000, rng, second, size))
    adapted_error = metrics.quantisation_error(gas.nodes, held_out)
    assert adapted_error <= 1.05 * metrics.quantisation_error(fresh.nodes, held_out)


def attention_density_ratio(weight: float, seed: int, **params) -> float:
    """Node density on the small box (sampled with weight) over the density elsewhere."""
    rng = np.random.default_rng(seed)
    points = box_surface_points(50_000, rng)
    low = THREE_BOX_CENTRES[1] - THREE_BOX_SIZES[1] / 2 - 0.02
    high = THREE_BOX_CENTRES[1] + THREE_BOX_SIZES[1] / 2 + 0.02
    inside = np.all((points > low) & (points < high), axis=1)
    gas = GrowingNeuralGas(**params, random_state=seed)
    for _ in range(10):  # ten attention-weighted frames
        gas.partial_fit(points, n_signals=10_000, weights=np.where(inside, weight, 1.0))
    in_region = np.all((gas.nodes > low) & (gas.nodes < high), axis=1)
    areas = box_surface_area(THREE_BOX_SIZES)
    dense, sparse = metrics.node_density(gas.nodes, in_region, areas[1], areas.sum() - areas[1])
    return dense / sparse


def test_attention_raises_node_density_fourfold():
    # Adaptive GNG: long error memory (small beta) and deletion of nodes that stop winning.
    adaptive = dict(beta=5e-5, e_min=0.07)
    assert attention_density_ratio(16.0, seed=3, **adaptive) >= 4.0
    assert 0.7 < attention_density_ratio(1.0, seed=3, **adaptive) < 1.4

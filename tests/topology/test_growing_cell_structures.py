"""Growing Cell Structures: simplices, joint payloads on the HSR arm, paths, bad input."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import cKDTree

from hsr_handover.kinematics.hsr_arm import palm_position, sample_arm_joints
from hsr_handover.topology import GrowingCellStructures


def neighbour_sets(cells: GrowingCellStructures) -> list[set[int]]:
    sets = [set() for _ in range(cells.n_nodes)]
    for a, b in cells.edges.tolist():
        sets[a].add(b)
        sets[b].add(a)
    return sets


def is_connected(cells: GrowingCellStructures) -> bool:
    return cells.clusters().max() == 0


@pytest.fixture(scope="module")
def arm_samples():
    rng = np.random.default_rng(11)
    joints = sample_arm_joints(20_000, rng)
    return palm_position(joints), joints


@pytest.fixture(scope="module")
def arm_map(arm_samples):
    positions, joints = arm_samples
    cells = GrowingCellStructures(max_nodes=108, mu3=30.0, random_state=0)
    return cells.fit(positions, joints, n_signals=40_000)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_every_edge_lies_on_a_triangle_and_the_map_stays_connected(seed):
    rng = np.random.default_rng(seed)
    cells = GrowingCellStructures(k=2, max_nodes=80, lam=30, random_state=seed)
    cells.fit(rng.random((5000, 3)), n_signals=6000)
    assert cells.n_nodes == 80 and is_connected(cells)
    near = neighbour_sets(cells)
    assert all(near[a] & near[b] for a, b in cells.edges.tolist())


def test_every_edge_lies_on_a_tetrahedron_for_k3():
    rng = np.random.default_rng(3)
    cells = GrowingCellStructures(k=3, max_nodes=60, lam=30, random_state=0)
    cells.fit(rng.random((5000, 3)), n_signals=4000)
    near = neighbour_sets(cells)
    for a, b in cells.edges.tolist():
        common = near[a] & near[b]
        assert any(near[c] & common for c in common)
    assert is_connected(cells)


def test_payloads_are_training_rows_near_their_nodes(arm_samples, arm_map):
    positions, joints = arm_samples
    rows = {tuple(v) for v in joints.tolist()}
    assert all(tuple(v) in rows for v in arm_map.payload.tolist())  # copied, never averaged
    _, closest = cKDTree(positions).query(arm_map.nodes)
    np.testing.assert_array_equal(arm_map.payload, joints[closest])
    error = np.linalg.norm(palm_position(arm_map.payload) - arm_map.nodes, axis=1)
    assert error.mean() < 0.02 and np.percentile(error, 95) < 0.04


def test_streaming_payloads_follow_their_nodes(arm_samples):
    positions, joints = arm_samples
    cells = GrowingCellStructures(max_nodes=108, random_state=0)
    for chunk in np.array_split(np.arange(len(joints)), 4):
        cells.partial_fit(positions[chunk], joints[chunk])
    rows = {tuple(v) for v in joints.tolist()}
    assert all(tuple(v) in rows for v in cells.payload.tolist())
    error = np.linalg.norm(palm_position(cells.payload) - cells.nodes, axis=1)
    assert np.median(error) < 0.03


def test_interpolated_joints_reach_near_random_targets(arm_map):
    targets = palm_position(sample_arm_joints(2000, np.random.default_rng(12)))
    error = np.linalg.norm(palm_position(arm_map.payload_at(targets)) - targets, axis=1)
    assert error.mean() < 0.08 and np.percentile(error, 95) < 0.15


def test_eq11_weights_winner_and_neighbours():
    rng = np.random.default_rng(5)
    cells = GrowingCellStructures(max_nodes=20, lam=20, mu3=3.0, random_state=0)
    points = rng.random((2000, 2))
    cells.fit(points, points @ np.array([[1.0, 2.0, 0.0], [0.0, 1.0, 3.0]]))
    x = np.array([0.3, 0.6])
    s = int(cells.nearest(x[None])[0])
    near = sorted(neighbour_sets(cells)[s])
    xi = np.exp(-cells.mu3 * np.linalg.norm(cells.nodes[near] - x, axis=1))
    expected = (xi @ cells.payload[near] + cells.payload[s]) / (xi.sum() + 1)
    np.testing.assert_allclose(cells.payload_at(x[None])[0], expected)


def test_reachable_agrees_with_forward_kinematics(arm_map):
    rng = np.random.default_rng(13)
    dense = cKDTree(palm_position(sample_arm_joints(1_000_000, rng)))
    nodes = arm_map.nodes
    targets = rng.uniform(nodes.min(0) - 0.15, nodes.max(0) + 0.15, size=(2000, 3))
    truth = dense.query(targets)[0] < 0.01  # within 1 cm of a reachable palm position
    assert 0.15 < truth.mean() < 0.85
    accuracy = np.mean(arm_map.reachable(targets, tol=0.08) == truth)
    assert accuracy > 0.85


def test_path_walks_linked_nodes_to_the_goal(arm_samples, arm_map):
    positions, _ = arm_samples
    near = neighbour_sets(arm_map)
    for start, goal in [(positions[0], positions[1]), (positions[2], positions[3])]:
        path = arm_map.path(start, goal)
        labels = arm_map.nearest(path.positions)
        assert labels[0] == arm_map.nearest(start[None])[0]
        assert labels[-1] == arm_map.nearest(goal[None])[0]
        assert all(b in near[a] for a, b in zip(labels[:-1], labels[1:], strict=True))
        assert path.joints.shape == (len(labels), 5)
        np.testing.assert_allclose(path.joints, arm_map.payload_at(path.positions))


def test_save_load_keeps_payloads(tmp_path, arm_map):
    arm_map.save(tmp_path / "cells.npz")
    loaded = GrowingCellStructures.load(tmp_path / "cells.npz")
    np.testing.assert_array_equal(loaded.payload, arm_map.payload)
    np.testing.assert_array_equal(loaded.edges, arm_map.edges)


def test_bad_input_is_dropped_counted_or_refused():
    rng = np.random.default_rng(6)
    points, payload = rng.random((500, 3)), rng.random((500, 2))
    points[:5, 0] = np.nan
    payload[5:8, 1] = np.inf
    cells = GrowingCellStructures(max_nodes=10, lam=20, random_state=0).fit(points, payload)
    assert cells.n_dropped_ == 8 and np.all(np.isfinite(cells.payload))
    nodes = cells.nodes
    cells.partial_fit(np.empty((0, 3)), np.empty((0, 2)))
    np.testing.assert_array_equal(cells.nodes, nodes)
    with pytest.raises(ValueError, match=r"expected shape \(n, 3\)"):
        cells.partial_fit(np.zeros((4, 2)), np.zeros((4, 2)))
    with pytest.raises(ValueError, match="payload"):
        cells.partial_fit(np.zeros((4, 3)), np.zeros((3, 2)))
    with pytest.raises(ValueError, match="payload"):
        cells.partial_fit(np.zeros((4, 3)))
    assert not cells.reachable(np.array([[np.nan, 0.0, 0.0]]), tol=1.0)[0]
    with pytest.raises(ValueError, match="k"):
        GrowingCellStructures(k=4)
    with pytest.raises(ValueError, match="payload"):
        GrowingCellStructures(max_nodes=5).fit(rng.random((50, 3))).payload_at(np.zeros((1, 3)))

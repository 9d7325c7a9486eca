"""Growing Neural Gas: one-signal rules, invariants, persistence, bad input."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hsr_handover.topology import GrowingNeuralGas


def small_map(**params) -> GrowingNeuralGas:
    rng = np.random.default_rng(0)
    return GrowingNeuralGas(max_nodes=30, lam=20, random_state=1, **params).fit(
        rng.random((3000, 3))
    )


def neighbours_of(gas: GrowingNeuralGas, node: int) -> set[int]:
    edges = gas.edges
    return set(edges[edges[:, 0] == node, 1]) | set(edges[edges[:, 1] == node, 0])


def test_each_neighbour_moves_by_its_own_difference():
    gas = small_map(mu3=4.0)
    gas.lam, gas.a_max = 10**9, 10**9  # one signal: no insertion, no edge removal
    before = gas.nodes
    p = np.array([[0.5, 0.45, 0.55]])
    s1, s2 = np.argsort(np.linalg.norm(before - p, axis=1))[:2]
    gas.partial_fit(p)
    after = gas.nodes
    np.testing.assert_allclose(after[s1], before[s1] + gas.mu1 * (p[0] - before[s1]))
    neighbours = neighbours_of(gas, s1)
    assert s2 in neighbours and len(neighbours) >= 3
    for j in neighbours:
        xi = np.exp(-gas.mu3 * np.linalg.norm(p[0] - before[j]))
        np.testing.assert_allclose(after[j], before[j] + gas.mu2 * xi * (p[0] - before[j]))
    others = sorted(set(range(gas.n_nodes)) - neighbours - {s1})
    np.testing.assert_array_equal(after[others], before[others])


def test_winner_error_grows_by_squared_distance_then_decays():
    gas = small_map()
    gas.lam = 10**9
    p = np.array([[0.2, 0.9, 0.1]])
    distance = np.linalg.norm(gas.nodes - p, axis=1)
    s1 = int(np.argmin(distance))
    before = gas.errors
    gas.partial_fit(p)
    expected = before.copy()
    expected[s1] += distance[s1] ** 2
    np.testing.assert_allclose(gas.errors, expected * (1 - gas.beta))


def test_insertion_splits_the_edge_of_largest_errors():
    rng = np.random.default_rng(0)
    gas = GrowingNeuralGas(max_nodes=30, lam=20, random_state=1).fit(rng.random((300, 3)))
    assert gas.n_nodes < gas.max_nodes
    errors = gas.errors
    q = int(np.argmax(errors))
    f = max(neighbours_of(gas, q), key=lambda j: errors[j])
    winner = next(i for i in range(gas.n_nodes) if i not in {q, f})
    gas.lam = 1  # insert after the next signal, which sits on a node and adds no error
    gas.partial_fit(gas.nodes[winner][None])
    r = gas.n_nodes - 1
    assert r == len(errors)
    assert neighbours_of(gas, r) == {q, f}
    assert f not in neighbours_of(gas, q)
    np.testing.assert_allclose(gas.nodes[r], 0.5 * (gas.nodes[q] + gas.nodes[f]))
    decay = 1 - gas.beta
    e_q, e_f = (1 - gas.alpha) * errors[q], (1 - gas.alpha) * errors[f]
    np.testing.assert_allclose(gas.errors[[q, f, r]], decay * np.array([e_q, e_f, (e_q + e_f) / 2]))


def check_invariants(gas: GrowingNeuralGas) -> None:
    edges, ages = gas.edges, gas.edge_ages
    neighbours, degree, mirrored_ages = gas.adjacency
    n = gas.n_nodes
    assert 2 <= n <= gas.max_nodes
    assert np.all(edges[:, 0] < edges[:, 1])  # no self-loops; i < j listing
    assert len({tuple(e) for e in edges.tolist()}) == len(edges)  # no duplicates
    for i in range(n):  # symmetric: each list entry is mirrored with the same age
        for k in range(degree[i]):
            j = neighbours[i, k]
            back = list(neighbours[j, : degree[j]]).index(i)
            assert mirrored_ages[j, back] == mirrored_ages[i, k]
    assert set(np.unique(edges)) == set(range(n))  # no isolated node
    assert np.all(gas.errors >= 0)
    assert np.all((ages >= 0) & (ages <= gas.a_max))
    assert np.all(np.isfinite(gas.nodes))


@settings(max_examples=60, deadline=None)
@given(
    n_points=st.integers(1, 300),
    dim=st.integers(1, 4),
    max_nodes=st.integers(2, 40),
    lam=st.integers(1, 60),
    a_max=st.integers(1, 30),
    mu3=st.sampled_from([0.0, 2.0]),
    e_min=st.sampled_from([0.0, 1e-4, 1e-2]),
    n_signals=st.integers(1, 3000),
    seed=st.integers(0, 2**16),
)
def test_graph_invariants_hold(n_points, dim, max_nodes, lam, a_max, mu3, e_min, n_signals, seed):
    rng = np.random.default_rng(seed)
    gas = GrowingNeuralGas(
        max_nodes=max_nodes, lam=lam, a_max=a_max, mu3=mu3, e_min=e_min, random_state=seed
    )
    gas.partial_fit(rng.random((n_points, dim)), n_signals=n_signals)
    check_invariants(gas)
    gas.partial_fit(rng.random((n_points, dim)) + 3.0, n_signals=n_signals)
    check_invariants(gas)


def test_high_degree_lists_grow():
    rng = np.random.default_rng(3)
    gas = GrowingNeuralGas(max_nodes=200, lam=5, a_max=10**6, random_state=0)
    gas.fit(rng.normal(size=(20000, 12)))  # high dimension: many edges per node
    assert gas.adjacency[0].shape[1] > 16
    check_invariants(gas)


def test_same_seed_same_map_and_save_load_continues_identically(tmp_path):
    rng = np.random.default_rng(0)
    first, second = rng.random((4000, 3)), rng.random((4000, 3))
    a = GrowingNeuralGas(max_nodes=50, lam=30, e_min=1e-3, random_state=7).fit(first)
    b = GrowingNeuralGas(max_nodes=50, lam=30, e_min=1e-3, random_state=7).fit(first)
    np.testing.assert_array_equal(a.nodes, b.nodes)
    a.save(tmp_path / "gas.npz")
    c = GrowingNeuralGas.load(tmp_path / "gas.npz")
    assert c.get_params() == a.get_params()
    np.testing.assert_array_equal(c.nodes, a.nodes)
    np.testing.assert_array_equal(c.edge_ages, a.edge_ages)
    a.partial_fit(second)
    c.partial_fit(second)
    np.testing.assert_array_equal(c.nodes, a.nodes)
    np.testing.assert_array_equal(c.edges, a.edges)
    np.testing.assert_array_equal(c.errors, a.errors)


def test_nearest_matches_brute_force_in_each_dimension():
    rng = np.random.default_rng(2)
    for dim in (1, 2, 3, 5):
        gas = GrowingNeuralGas(max_nodes=60, lam=20, random_state=0).fit(rng.random((5000, dim)))
        queries = rng.normal(0.5, 0.6, size=(3000, dim))
        labels, distance = gas.nearest(queries, return_distance=True)
        brute = np.linalg.norm(queries[:, None] - gas.nodes[None], axis=2)
        np.testing.assert_allclose(distance, brute.min(axis=1), atol=1e-12)
        assert np.all(brute[np.arange(len(queries)), labels] <= brute.min(axis=1) + 1e-12)


def test_dead_nodes_vanish_and_clusters_are_connected_components():
    rng = np.random.default_rng(4)
    blobs = np.concatenate([rng.normal(0, 0.1, (3000, 2)), rng.normal(5, 0.1, (3000, 2))])
    # Early insertions leave a chain of nodes between the blobs that never win; Fritzke's GNG
    # keeps it (its inner edges never age), error-based deletion removes it.
    fritzke = GrowingNeuralGas(max_nodes=40, lam=50, random_state=0).fit(blobs, 30000)
    assert np.any(np.abs(fritzke.nodes[:, 0] - 2.5) < 1.5)
    gas = GrowingNeuralGas(max_nodes=40, lam=50, e_min=1e-3, random_state=0).fit(blobs, 30000)
    assert not np.any(np.abs(gas.nodes[:, 0] - 2.5) < 1.5)
    labels, edges = gas.clusters(), gas.edges
    assert labels.max() + 1 == 2
    assert np.all(labels[edges[:, 0]] == labels[edges[:, 1]])
    side = gas.nodes[:, 0] > 2.5
    assert not set(labels[side]) & set(labels[~side])
    for label in np.unique(labels):  # each label is one connected piece
        members = set(np.flatnonzero(labels == label))
        reached, frontier = set(), [min(members)]
        while frontier:
            node = frontier.pop()
            if node not in reached:
                reached.add(node)
                frontier += list(edges[edges[:, 0] == node, 1]) + list(
                    edges[edges[:, 1] == node, 0]
                )
        assert reached == members


def test_non_finite_points_are_dropped_and_counted():
    rng = np.random.default_rng(5)
    points = rng.random((1000, 3))
    points[::10, 1] = np.nan
    points[5::50, 2] = np.inf
    gas = GrowingNeuralGas(max_nodes=20, random_state=0).partial_fit(points)
    assert gas.n_dropped_ == 120
    assert gas.n_signals_ == 880
    assert np.all(np.isfinite(gas.nodes))
    weights = np.ones(1000)
    weights[:3] = np.nan
    gas.partial_fit(rng.random((1000, 3)), n_signals=100, weights=weights)
    assert gas.n_dropped_ == 123
    labels = gas.nearest(points[:20])
    assert labels[0] == -1 and labels[1] >= 0


def test_empty_input_changes_nothing():
    gas = GrowingNeuralGas(random_state=0).partial_fit(np.empty((0, 3)))
    assert gas.n_nodes == 0 and gas.dim is None
    gas = small_map()
    nodes = gas.nodes
    gas.partial_fit(np.empty((0, 3)))
    gas.partial_fit([])
    gas.partial_fit(np.full((4, 3), np.nan))
    np.testing.assert_array_equal(gas.nodes, nodes)


def test_wrong_dimension_raises_with_expected_shape():
    gas = small_map()
    with pytest.raises(ValueError, match=r"expected shape \(n, 3\)"):
        gas.partial_fit(np.zeros((10, 2)))
    with pytest.raises(ValueError, match=r"expected shape \(n, 3\)"):
        gas.nearest(np.zeros(3))
    with pytest.raises(ValueError, match="weights"):
        gas.partial_fit(np.zeros((10, 3)), weights=np.ones(9))
    with pytest.raises(ValueError, match="weights"):
        gas.partial_fit(np.zeros((10, 3)), weights=-np.ones(10))


@pytest.mark.parametrize(
    ("name", "value"),
    [("max_nodes", 1), ("lam", 0), ("mu1", 1.5), ("mu2", -0.1), ("mu3", np.nan), ("a_max", 0),
     ("alpha", 2.0), ("beta", 1.0), ("e_min", -1.0), ("max_nodes", 2.5)],
)  # fmt: skip
def test_bad_parameters_are_named(name, value):
    with pytest.raises(ValueError, match=name):
        GrowingNeuralGas(**{name: value})

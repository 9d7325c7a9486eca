"""Growing Cell Structures with joint-vector payloads (paper 3.1, Fritzke 1991;
docs/design.md §3.2)."""

from __future__ import annotations

from typing import NamedTuple, Self

import numpy as np
from scipy.sparse import coo_array
from scipy.sparse.csgraph import dijkstra
from scipy.spatial import cKDTree

from hsr_handover.topology._cell_structures_kernels import (
    interpolate_payload,
    train_cell_structures,
)
from hsr_handover.topology._graph_state import GraphState
from hsr_handover.topology._network import GrowingNetwork
from hsr_handover.topology._validation import as_points, check_real


class CellPath(NamedTuple):
    """Nodes visited from start to goal: positions (K, d) and eq.-11 joint vectors (K, m)."""

    positions: np.ndarray
    joints: np.ndarray


class GrowingCellStructures(GrowingNetwork):
    """A map made of k-simplices (triangles for k = 2) that can carry a payload per node.

    One signal p: winner s = nearest node (eq. 1, argmin), w_s += mu1 (p - w_s) (eq. 2), each
    neighbour j: w_j += mu2 xi_j (p - w_j), xi_j = exp(-mu3 ||p - w_j||) (eq. 3),
    E_s += ||p - w_s||^2 before the move (eq. 4); every lam signals a new node r at the
    midpoint of the node q of largest error and its neighbour f of largest error (eqs. 5-9),
    linked to q, f and every common neighbour of q and f so every simplex on edge q-f is split
    in two; then E_i -= beta E_i (eq. 10). No edge ageing and no deletion.

    Payloads (e.g. the joint vector v that put the gripper at x) are copied from training
    samples, never averaged: each node carries the payload of the closest sample it has won,
    and ``fit`` finally gives every node the payload of its closest training sample. Averaging
    across inverse-kinematics branches would give joints that reach nowhere.

    Parameters
    ----------
    k : simplex dimension, 2 (triangles) or 3 (tetrahedra).
    max_nodes : node limit (>= k + 1); the paper's arm map has 108.
    lam, mu1, mu2, mu3, alpha, beta, random_state : as in ``GrowingNeuralGas``. mu3 also sets
        the weights xi_j of eq. 11.
    """

    def __init__(
        self,
        k: int = 2,
        max_nodes: int = 108,
        lam: int = 100,
        mu1: float = 0.05,
        mu2: float = 0.006,
        mu3: float = 0.0,
        alpha: float = 0.5,
        beta: float = 0.0005,
        random_state: int | np.random.Generator | None = None,
    ) -> None:
        if k not in (2, 3):
            raise ValueError(f"k: expected 2 (triangles) or 3 (tetrahedra), got {k!r}")
        self.k = k
        self._set_learning_params(max_nodes, k + 1, lam, mu1, mu2, mu3, alpha, beta, random_state)

    @property
    def payload(self) -> np.ndarray | None:
        """Payload of each node, (n_nodes, m), or None when learnt without payload."""
        if self.dim is None or self._state.payload.shape[1] == 0:
            return None
        return self._state.payload[: self.n_nodes].copy()

    def fit(
        self, points: np.ndarray, payload: np.ndarray | None = None, n_signals: int | None = None
    ) -> Self:
        """Forget everything, learn as ``partial_fit``, then give each node the payload of its
        closest training sample."""
        self._reset()
        self.partial_fit(points, payload, n_signals)
        if payload is not None and self.n_nodes > 0:
            self._snap_payloads(points, payload)
        return self

    def partial_fit(
        self, points: np.ndarray, payload: np.ndarray | None = None, n_signals: int | None = None
    ) -> Self:
        """Learn from points (n, d) with optional payload rows (n, m); see ``GrowingNeuralGas``.

        Rows with NaN or inf in the point or its payload are dropped and counted.
        """
        payload = self._check_payload(points, payload)
        signals = self._signals(points, n_signals, payload=payload)
        if signals is None:
            return self
        array, payload, order = signals
        if payload is None:
            payload = np.empty((array.shape[0], 0))
        if self._state is None:
            self._state = GraphState.empty(array.shape[1], self.max_nodes, payload.shape[1])
            seeds = self._rng.choice(array.shape[0], size=self.k + 1, replace=False)
            self._state.seed_clique(array[seeds], payload[seeds])
        self._run(self._learn, order, array, payload)
        return self

    def _check_payload(self, points: object, payload: object) -> np.ndarray | None:
        known = None if self.dim is None else self._state.payload.shape[1]
        if payload is None:
            if known:
                raise ValueError(f"payload: expected shape (n, {known}), this map carries one")
            return None
        n = np.shape(points)[0] if np.ndim(points) > 0 else 0
        array = as_points(payload, known or None, "payload")
        if array.shape[0] != n:
            raise ValueError(f"payload: expected one row per point, ({n}, m), got {array.shape}")
        if known == 0:
            raise ValueError("payload: this map was learnt without payload")
        return array

    def _snap_payloads(self, points: np.ndarray, payload: np.ndarray) -> None:
        array = as_points(points, self.dim)
        values = np.asarray(payload, dtype=np.float64)
        keep = np.isfinite(array).all(axis=1) & np.isfinite(values).all(axis=1)
        array, values = array[keep], values[keep]
        _, closest = cKDTree(array).query(self.nodes)
        n = self.n_nodes
        self._state.payload[:n] = values[closest]
        self._state.payload_x[:n] = array[closest]

    def _learn(self, order, state, dist, scratch, array, payload) -> int:
        return train_cell_structures(
            array,
            payload,
            order,
            state.positions,
            state.errors,
            state.neighbours,
            state.ages,
            state.degree,
            state.counters,
            state.scale,
            state.payload,
            state.payload_x,
            dist,
            scratch,
            self.max_nodes,
            self.lam,
            self.mu1,
            self.mu2,
            self.mu3,
            self.alpha,
            self.beta,
        )

    def reachable(self, x: np.ndarray, tol: float) -> np.ndarray:
        """Whether each point (n, d) lies within tol of a node (False for NaN or inf rows)."""
        tol = check_real("tol", tol, 0.0)
        _, distance = self.nearest(x, return_distance=True)
        return np.nan_to_num(distance, nan=np.inf) <= tol

    def payload_at(self, x: np.ndarray) -> np.ndarray:
        """Payload interpolated at each point (n, d) by eq. 11 (NaN rows for NaN or inf input)."""
        if self.payload is None:
            raise ValueError("payload_at: the map was learnt without payload")
        array = np.ascontiguousarray(as_points(x, self.dim, "x"))
        labels = self.nearest(array)
        out = np.empty((array.shape[0], self._state.payload.shape[1]))
        state = self._state
        interpolate_payload(
            array, labels, state.positions, state.neighbours, state.degree, state.payload,
            self.mu3, out,
        )  # fmt: skip
        return out

    def path(self, x_start: np.ndarray, x_goal: np.ndarray) -> CellPath:
        """Walk node to node from the node nearest x_start toward x_goal (paper 3.1).

        Each step goes to the neighbour nearest the goal; if the walk stalls before the goal's
        node, it finishes along the shortest path in the graph. Joints are eq. 11 at each node.
        """
        ends = as_points(np.stack([np.ravel(x_start), np.ravel(x_goal)]), self.dim, "x_start")
        if not np.isfinite(ends).all():
            raise ValueError("x_start, x_goal: expected finite coordinates")
        start, goal = self.nearest(ends)
        nodes = self.nodes
        route = _greedy_walk(self._state, nodes, start, goal, ends[1])
        if route[-1] != goal:
            route += _shortest_path(nodes, self.edges, route[-1], goal)[1:]
        positions = nodes[route]
        joints = (
            self.payload_at(positions) if self.payload is not None else np.empty((len(route), 0))
        )
        return CellPath(positions, joints)


def _greedy_walk(state: GraphState, nodes: np.ndarray, start: int, goal: int, x: np.ndarray):
    route = [int(start)]
    current = start
    while current != goal:
        neighbours = state.neighbours[current, : state.degree[current]]
        gaps = np.linalg.norm(nodes[neighbours] - x, axis=1)
        best = neighbours[np.argmin(gaps)]
        if gaps.min() >= np.linalg.norm(nodes[current] - x):
            break
        route.append(int(best))
        current = best
    return route


def _shortest_path(nodes: np.ndarray, edges: np.ndarray, start: int, goal: int) -> list[int]:
    n = nodes.shape[0]
    lengths = np.linalg.norm(nodes[edges[:, 0]] - nodes[edges[:, 1]], axis=1)
    graph = coo_array((lengths, (edges[:, 0], edges[:, 1])), shape=(n, n))
    _, predecessors = dijkstra(graph, directed=False, indices=start, return_predecessors=True)
    route = [int(goal)]
    while route[-1] != start:
        route.append(int(predecessors[route[-1]]))
    return route[::-1]

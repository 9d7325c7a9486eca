"""What Growing Neural Gas and Growing Cell Structures share: state, queries, persistence."""

from __future__ import annotations

import inspect
import json
from pathlib import Path
from typing import Any, Self

import numpy as np
from scipy.sparse import coo_array
from scipy.sparse.csgraph import connected_components

from hsr_handover.topology._batch_search import nearest_nodes_3d, nearest_nodes_brute
from hsr_handover.topology._graph_state import GraphState
from hsr_handover.topology._validation import (
    as_points,
    as_weights,
    check_int,
    check_real,
    draw_order,
    finite_rows,
)


class GrowingNetwork:
    """Base of the growing networks. Subclasses define ``_learn_order``."""

    def _set_learning_params(
        self, max_nodes, min_nodes, lam, mu1, mu2, mu3, alpha, beta, random_state
    ) -> None:
        """Check and keep the parameters both networks share (eqs. 2-3, 5-10)."""
        self.max_nodes = check_int("max_nodes", max_nodes, min_nodes)
        self.lam = check_int("lam", lam, 1)
        self.mu1 = check_real("mu1", mu1, 0.0, 1.0)
        self.mu2 = check_real("mu2", mu2, 0.0, 1.0)
        self.mu3 = check_real("mu3", mu3, 0.0)
        self.alpha = check_real("alpha", alpha, 0.0, 1.0)
        self.beta = check_real("beta", beta, 0.0, 1.0, open_high=True)
        self.random_state = random_state

    def get_params(self) -> dict[str, Any]:
        names = inspect.signature(type(self).__init__).parameters
        return {name: getattr(self, name) for name in names if name != "self"}

    def _reset(self) -> None:
        self._state: GraphState | None = None
        seed = self.random_state
        self._rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
        self.n_dropped_ = 0

    def _ensure_started(self) -> None:
        if not hasattr(self, "_rng"):
            self._reset()

    def _signals(
        self,
        points: object,
        n_signals: int | None,
        weights: object = None,
        payload: np.ndarray | None = None,
    ) -> tuple[np.ndarray, np.ndarray | None, np.ndarray] | None:
        """Finite rows of points (and of payload), and the order to learn them in.

        Rows with NaN or inf in the point, its weight or its payload are dropped and counted in
        ``n_dropped_``. Returns None when nothing is left to learn.
        """
        self._ensure_started()
        array = as_points(points, self.dim)
        if n_signals is not None:
            n_signals = check_int("n_signals", n_signals, 0)
        weight_array = as_weights(weights, array.shape[0])
        valid = finite_rows(array, weight_array)
        if payload is not None:
            valid &= finite_rows(payload)
        self.n_dropped_ += int(array.shape[0] - valid.sum())
        if not valid.all():
            array = array[valid]
            weight_array = None if weight_array is None else weight_array[valid]
            payload = None if payload is None else payload[valid]
        if array.shape[0] == 0:
            return None
        order = draw_order(self._rng, array.shape[0], n_signals, weight_array)
        if order.shape[0] == 0:
            return None
        payload = None if payload is None else np.ascontiguousarray(payload)
        return np.ascontiguousarray(array), payload, order.astype(np.int64, copy=False)

    def _run(self, kernel, order: np.ndarray, *args) -> None:
        """Call a training kernel until all signals are learnt, growing neighbour lists."""
        state = self._state
        dist = np.empty(state.positions.shape[1])
        done = 0
        while done < order.shape[0]:
            scratch = np.empty(state.neighbours.shape[1] + 1, dtype=np.int64)
            done += kernel(order[done:], state, dist, scratch, *args)
            if done < order.shape[0]:
                state.grow_degree_capacity()

    @property
    def dim(self) -> int | None:
        """Dimension of the input space, known after the first data."""
        return None if getattr(self, "_state", None) is None else self._state.positions.shape[0]

    @property
    def n_nodes(self) -> int:
        return 0 if self.dim is None else self._state.n_nodes

    @property
    def n_signals_(self) -> int:
        """Signals learnt since the map was created."""
        return 0 if self.dim is None else self._state.n_signals

    @property
    def nodes(self) -> np.ndarray:
        """Node reference vectors w_i, (n_nodes, d)."""
        return np.empty((0, 0)) if self.dim is None else self._state.nodes()

    @property
    def errors(self) -> np.ndarray:
        """Accumulated errors E_i (eqs. 4, 7-10), (n_nodes,)."""
        return np.empty(0) if self.dim is None else self._state.true_errors()

    @property
    def edges(self) -> np.ndarray:
        """Edges as (M, 2) node indices, i < j, sorted; each edge listed once."""
        return np.empty((0, 2), np.int64) if self.dim is None else self._state.edge_list()[0]

    @property
    def edge_ages(self) -> np.ndarray:
        """Age a_ij of each edge in ``edges`` (eqs. 14-15)."""
        return np.empty(0, np.int64) if self.dim is None else self._state.edge_list()[1]

    @property
    def adjacency(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Each node's edges as the learning kernels keep them, copies: `neighbours` (n_nodes,
        width) and the `ages` of those edges, the first `degree[i]` of row i in use; every edge
        is listed at both its ends with the same age. The width grows with the highest
        degree."""
        if self.dim is None:
            empty = np.empty((0, 0), np.int64)
            return empty, np.empty(0, np.int64), empty
        n, state = self.n_nodes, self._state
        return state.neighbours[:n].copy(), state.degree[:n].copy(), state.ages[:n].copy()

    def nearest(
        self, points: np.ndarray, return_distance: bool = False
    ) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
        """Index of the nearest node for each point (n, d); -1 for rows with NaN or inf.

        With return_distance, also the Euclidean distances (NaN for those rows).
        """
        if self.n_nodes == 0:
            raise ValueError("nearest: the map has no nodes yet; call fit or partial_fit first")
        array = np.ascontiguousarray(as_points(points, self.dim))
        labels = np.full(array.shape[0], -1, dtype=np.int64)
        sq_dist = np.full(array.shape[0], np.nan)
        valid = finite_rows(array)
        if valid.any():
            self._label(array, valid, labels, sq_dist)
        return (labels, np.sqrt(sq_dist)) if return_distance else labels

    def _label(self, array, valid, labels, sq_dist) -> None:
        d, n = self.dim, self.n_nodes
        nodes_t = np.ascontiguousarray(self._state.positions[:, :n])
        edges = self.edges
        if d > 3 or len(edges) == 0:
            nearest_nodes_brute(array, valid, nodes_t, labels, sq_dist)
            return
        lengths = np.linalg.norm(nodes_t[:, edges[:, 0]] - nodes_t[:, edges[:, 1]], axis=0)
        # Cells of about an edge length balance building cell lists against scanning them.
        cell_size = max(0.8 * float(np.median(lengths)), 1e-12)
        if d < 3:
            array = np.pad(array, ((0, 0), (0, 3 - d)))
            nodes_t = np.pad(nodes_t, ((0, 3 - d), (0, 0)))
        nearest_nodes_3d(array, valid, nodes_t, cell_size, labels, sq_dist)

    def clusters(self) -> np.ndarray:
        """Connected component label of each node, (n_nodes,); GNG's clustering."""
        n = self.n_nodes
        edges = self.edges
        graph = coo_array((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
        return connected_components(graph, directed=False)[1]

    def save(self, path: str | Path) -> None:
        """Write parameters, learned state and random generator state to an .npz file."""
        params = self.get_params()
        if isinstance(params["random_state"], np.random.Generator):
            params["random_state"] = None
        self._ensure_started()
        arrays = {} if self._state is None else self._state.as_dict()
        meta = {
            "class": type(self).__name__,
            "params": params,
            "rng": self._rng.bit_generator.state,
            "n_dropped": self.n_dropped_,
        }
        np.savez(path, meta=np.array(json.dumps(meta)), **arrays)

    @classmethod
    def load(cls, path: str | Path) -> Self:
        """Rebuild a network written by ``save``; it continues learning exactly as the original."""
        with np.load(path) as archive:
            meta = json.loads(str(archive["meta"]))
            if meta["class"] != cls.__name__:
                raise ValueError(f"path: holds a {meta['class']}, expected a {cls.__name__}")
            network = cls(**meta["params"])
            network._reset()
            if "state_positions" in archive:
                network._state = GraphState.from_dict(dict(archive))
        network._rng.bit_generator.state = meta["rng"]
        network.n_dropped_ = meta["n_dropped"]
        return network

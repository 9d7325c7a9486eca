"""The flat arrays a growing network learns in, and their readable views."""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from hsr_handover.topology._graph_kernels import (
    MAX_DEGREE,
    MIN_NODE,
    N_COUNTERS,
    N_NODES,
    N_SIGNALS,
)


@dataclass
class GraphState:
    """Node capacity is fixed at creation; neighbour lists grow when the kernel asks."""

    positions: np.ndarray  # (d, capacity) float64
    errors: np.ndarray  # (capacity,) float64, true error = errors * scale[0]
    neighbours: np.ndarray  # (capacity, degree capacity) int64
    ages: np.ndarray  # (capacity, degree capacity) int64
    degree: np.ndarray  # (capacity,) int64
    counters: np.ndarray  # (N_COUNTERS,) int64
    scale: np.ndarray  # (1,) float64
    payload: np.ndarray  # (capacity, m) float64, m = 0 without payload
    payload_x: np.ndarray  # (capacity, d) float64, where each node's payload sample lies

    @classmethod
    def empty(
        cls, dim: int, capacity: int, payload_dim: int = 0, degree_capacity: int = 16
    ) -> GraphState:
        counters = np.zeros(N_COUNTERS, dtype=np.int64)
        counters[MIN_NODE] = -1
        return cls(
            positions=np.zeros((dim, capacity)),
            errors=np.zeros(capacity),
            neighbours=np.zeros((capacity, degree_capacity), dtype=np.int64),
            ages=np.zeros((capacity, degree_capacity), dtype=np.int64),
            degree=np.zeros(capacity, dtype=np.int64),
            counters=counters,
            scale=np.ones(1),
            payload=np.zeros((capacity, payload_dim)),
            payload_x=np.zeros((capacity, dim)),
        )

    def seed_clique(self, points: np.ndarray, payload: np.ndarray | None = None) -> None:
        """Start with the given points as nodes, all linked to each other (a simplex)."""
        n = points.shape[0]
        self.positions[:, :n] = points.T
        self.payload_x[:n] = points
        if payload is not None:
            self.payload[:n] = payload
        for i in range(n):
            self.neighbours[i, : n - 1] = [j for j in range(n) if j != i]
        self.degree[:n] = n - 1
        self.counters[N_NODES] = n
        self.counters[MAX_DEGREE] = n - 1

    def grow_degree_capacity(self) -> None:
        extra = self.neighbours.shape[1]
        pad = ((0, 0), (0, extra))
        self.neighbours = np.pad(self.neighbours, pad)
        self.ages = np.pad(self.ages, pad)

    @property
    def n_nodes(self) -> int:
        return int(self.counters[N_NODES])

    @property
    def n_signals(self) -> int:
        return int(self.counters[N_SIGNALS])

    def nodes(self) -> np.ndarray:
        return self.positions[:, : self.n_nodes].T.copy()

    def true_errors(self) -> np.ndarray:
        return self.errors[: self.n_nodes] * self.scale[0]

    def edge_list(self) -> tuple[np.ndarray, np.ndarray]:
        """Edges (M, 2) with i < j, sorted, and their ages (M,)."""
        n = self.n_nodes
        rows = np.repeat(np.arange(n), self.degree[:n])
        used = np.arange(self.neighbours.shape[1]) < self.degree[:n, None]
        cols = self.neighbours[:n][used]
        ages = self.ages[:n][used]
        keep = rows < cols
        edges = np.stack([rows[keep], cols[keep]], axis=1)
        order = np.lexsort((edges[:, 1], edges[:, 0]))
        return edges[order], ages[keep][order]

    def as_dict(self) -> dict[str, np.ndarray]:
        return {f"state_{f.name}": getattr(self, f.name) for f in fields(self)}

    @classmethod
    def from_dict(cls, arrays: dict[str, np.ndarray]) -> GraphState:
        return cls(**{f.name: np.array(arrays[f"state_{f.name}"]) for f in fields(cls)})

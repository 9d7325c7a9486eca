"""Quality of a topological map against data: how well nodes represent points and topology."""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree


def _finite(points: np.ndarray) -> np.ndarray:
    points = np.asarray(points, dtype=np.float64)
    if points.ndim != 2:
        raise ValueError(f"points: expected shape (n, d), got {points.shape}")
    return points[np.isfinite(points).all(axis=1)]


def quantisation_error(nodes: np.ndarray, points: np.ndarray) -> float:
    """Mean Euclidean (not squared) distance from each point to its nearest node."""
    distance, _ = cKDTree(nodes).query(_finite(points))
    return float(np.mean(distance))


def mean_squared_error(nodes: np.ndarray, points: np.ndarray) -> float:
    """Mean squared Euclidean distance from each point to its nearest node."""
    distance, _ = cKDTree(nodes).query(_finite(points))
    return float(np.mean(distance**2))


def topographic_error(nodes: np.ndarray, edges: np.ndarray, points: np.ndarray) -> float:
    """Share of points whose nearest and second-nearest nodes are not linked by an edge."""
    _, pair = cKDTree(nodes).query(_finite(points), k=2)
    n = len(nodes)
    linked = set((np.minimum(edges[:, 0], edges[:, 1]) * n + np.maximum(*edges.T)).tolist())
    keys = np.minimum(pair[:, 0], pair[:, 1]) * n + np.maximum(pair[:, 0], pair[:, 1])
    return float(np.mean([key not in linked for key in keys.tolist()]))


def node_density(
    nodes: np.ndarray, inside: np.ndarray, region_measure: float, rest_measure: float
) -> tuple[float, float]:
    """Nodes per unit measure (area or volume) inside a region and outside it.

    ``inside`` marks the nodes in the region; the measures are those of the data's support in
    the region and outside it (e.g. surface areas for a point cloud of surfaces).
    """
    inside = np.asarray(inside, dtype=bool)
    if inside.shape != (len(nodes),):
        raise ValueError(f"inside: expected shape ({len(nodes)},), got {inside.shape}")
    if region_measure <= 0 or rest_measure <= 0:
        raise ValueError("region_measure, rest_measure: expected positive measures")
    return float(inside.sum() / region_measure), float((~inside).sum() / rest_measure)

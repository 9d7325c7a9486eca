"""Exact nearest-node labels for many points at once (e.g. a 200 x 200 frame).

A grid of cubic cells of side h covers the query points. The first time a cell is met, it gets
the list of nodes that can be nearest to any point inside it: with c the cell centre, rho its
half-diagonal and D the distance from c to its nearest node b, the nearest node of a point x in
the cell lies within |x - c| + D + rho <= D + 2 rho of c; of those, only nodes nearer than b
to some point of the cell are kept. A query then scans only its cell's short list.

The grid kernels are written for three dimensions (the point-cloud case; 1-D and 2-D inputs
are padded with zeros). Other dimensions are searched by brute force.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from hsr_handover.topology._graph_kernels import FAST, squared_distances

MAX_CELLS = 1 << 17


@njit(cache=True)
def finite_rows(points):
    """Mask of rows without NaN or inf (a loop: numpy's all(axis=1) is slow on thin rows)."""
    mask = np.empty(points.shape[0], dtype=np.bool_)
    for i in range(points.shape[0]):
        ok = True
        for k in range(points.shape[1]):
            ok &= np.isfinite(points[i, k])
        mask[i] = ok
    return mask


@njit(cache=True)
def _grid(points, valid, cell_size):
    """Lower corner, cells per axis and cell side of a grid covering the valid points."""
    low = np.full(3, np.inf)
    high = np.full(3, -np.inf)
    for i in range(points.shape[0]):
        if valid[i]:
            for k in range(3):
                low[k] = min(low[k], points[i, k])
                high[k] = max(high[k], points[i, k])
    span = np.maximum(high - low, 0.0)
    total = np.prod(span / cell_size + 1.0)
    if total > MAX_CELLS:  # keep the cell table small whatever the spread of the points
        cell_size *= (total / MAX_CELLS) ** (1.0 / 3.0)
    shape = (span / cell_size).astype(np.int64) + 1
    return low, shape, cell_size


@njit(cache=True)
def _may_win(nodes_t, b, j, centre, half):
    """Whether node j is nearer than node b to some point of the cell (centre +- half).

    |x - w_j|^2 - |x - w_b|^2 is linear in x, so its minimum over the cell is at a corner.
    """
    gap = 0.0
    for k in range(3):
        towards_b = nodes_t[k, b] - nodes_t[k, j]
        x = centre[k] - half if towards_b > 0.0 else centre[k] + half
        gap += (nodes_t[k, j] - nodes_t[k, b]) * (nodes_t[k, j] + nodes_t[k, b] - 2.0 * x)
    return gap <= 1e-12 * (1.0 + abs(gap))


@njit(cache=True)
def _cell_candidates(nodes_t, centre, half, dist, storage, used):
    """Append the nodes that may be nearest within the cell to storage; returns the new end."""
    squared_distances(nodes_t, nodes_t.shape[1], centre, dist)
    b = np.argmin(dist)
    radius = (np.sqrt(dist[b]) + 2.0 * half * np.sqrt(3.0)) * (1.0 + 1e-9)
    limit = radius * radius
    for j in range(nodes_t.shape[1]):
        if dist[j] <= limit and (j == b or _may_win(nodes_t, b, j, centre, half)):
            storage[used] = j
            used += 1
    return used


@njit(cache=True, fastmath=FAST)
def _scan(nodes_t, storage, start, stop, px, py, pz):
    best, best_j = np.inf, -1
    for m in range(start, stop):
        j = storage[m]
        dx, dy, dz = nodes_t[0, j] - px, nodes_t[1, j] - py, nodes_t[2, j] - pz
        total = dx * dx + dy * dy + dz * dz
        if total < best:
            best, best_j = total, j
    return best_j, best


@njit(cache=True)
def _cell_of(points, i, low, inverse_h, shape):
    cell = 0
    for k in range(3):
        cell = cell * shape[k] + min(int((points[i, k] - low[k]) * inverse_h), shape[k] - 1)
    return cell


@njit(cache=True)
def _cell_centre(cell, low, h, shape, centre):
    for k in range(2, -1, -1):
        index = cell % shape[k]
        cell //= shape[k]
        centre[k] = low[k] + (index + 0.5) * h


@njit(cache=True)
def _label_points(points, valid, nodes_t, grid, tables, storage, start, labels, sq_dist):
    """Label points from start on; returns where it stopped (storage full) or len(points).

    Kept free of array reassignment, which costs reference counting per point; the caller
    grows storage and calls again.
    """
    low, shape, h = grid
    entry, bounds, counts, dist, centre = tables
    n = nodes_t.shape[1]
    inverse_h = 1.0 / h
    for i in range(start, points.shape[0]):
        if not valid[i]:
            continue
        cell = _cell_of(points, i, low, inverse_h, shape)
        e = entry[cell]
        if e < 0:
            if bounds[counts[0]] + n > storage.shape[0]:
                return i
            _cell_centre(cell, low, h, shape, centre)
            e = entry[cell] = counts[0]
            bounds[e + 1] = _cell_candidates(nodes_t, centre, 0.5 * h, dist, storage, bounds[e])
            counts[0] += 1
        labels[i], sq_dist[i] = _scan(
            nodes_t, storage, bounds[e], bounds[e + 1], points[i, 0], points[i, 1], points[i, 2]
        )
    return points.shape[0]


@njit(cache=True)
def nearest_nodes_3d(points, valid, nodes_t, cell_size, labels, sq_dist):
    """labels[i] = index of the node (column of nodes_t, 3 rows) nearest to valid points[i]."""
    low, shape, h = _grid(points, valid, cell_size)
    n = nodes_t.shape[1]
    tables = (
        np.full(np.prod(shape), -1, dtype=np.int64),  # cell -> entry in bounds
        np.zeros(points.shape[0] + 1, dtype=np.int64),  # entry e: storage[bounds[e]:bounds[e+1]]
        np.zeros(1, dtype=np.int64),  # entries used
        np.empty(n),
        np.empty(3),
    )
    storage = np.empty(16 * n, dtype=np.int64)
    done = 0
    while done < points.shape[0]:
        done = _label_points(
            points, valid, nodes_t, (low, shape, h), tables, storage, done, labels, sq_dist
        )
        if done < points.shape[0]:
            grown = np.empty(2 * storage.shape[0], dtype=np.int64)
            grown[: storage.shape[0]] = storage
            storage = grown


@njit(cache=True)
def nearest_nodes_brute(points, valid, nodes_t, labels, sq_dist):
    """The same labels by brute force, in any dimension."""
    dist = np.empty(nodes_t.shape[1])
    for i in range(points.shape[0]):
        if valid[i]:
            squared_distances(nodes_t, nodes_t.shape[1], points[i], dist)
            j = np.argmin(dist)
            labels[i], sq_dist[i] = j, dist[j]

"""Numba kernels shared by the growing networks: search, neighbour lists, moves, insertion.

State lives in flat preallocated arrays so the learners never allocate per signal:

- ``positions`` (d, capacity): node reference vectors, one column per node. Columns make the
  brute-force distance loop contiguous, so LLVM vectorises it.
- ``errors`` (capacity,): accumulated errors divided by ``scale[0]``. Decaying every error by
  ``(1 - beta)`` each signal (eq. 10) is then one multiplication of ``scale`` instead of a pass
  over all nodes (Fiser et al. 2013, the paper's ref. [7]).
- ``neighbours`` / ``ages`` (capacity, degree_capacity): neighbour list of each node and the
  age of each of those edges, stored in both directions so either end reads it directly.
- ``degree`` (capacity,): number of entries used in each neighbour list.
- ``counters`` (int64): see the ``N_NODES`` ... names below.

Nodes are kept compact (0 .. n-1): deleting a node moves the last node into its slot.
"""

from __future__ import annotations

import numpy as np
from numba import njit

N_NODES = 0  # nodes in use
SINCE_INSERT = 1  # signals since the last insertion step (eq. 5: every lambda signals)
MAX_DEGREE = 2  # upper bound of any node's degree, to know when the lists must grow
MIN_NODE = 3  # node with the smallest error, or -1 when it must be searched again
N_SIGNALS = 4  # signals learnt since the map was created
N_COUNTERS = 5

TINY_SCALE = 1e-100  # renormalise the lazy error scale long before it underflows
FAST = {"nsz", "arcp", "contract", "afn", "reassoc"}  # fastmath without assuming finite values


@njit(cache=True, fastmath=FAST)
def squared_distances(positions, n, p, out):
    """out[j] = ||p - w_j||^2 for the first n nodes (columns of positions)."""
    for j in range(n):
        out[j] = 0.0
    for k in range(positions.shape[0]):
        pk = p[k]
        for j in range(n):
            diff = positions[k, j] - pk
            out[j] += diff * diff


@njit(cache=True, fastmath=FAST)
def nearest_two(positions, n, p, dist):
    """Indices and squared distances of the nearest and second-nearest node to p.

    The paper's eqs. 1, 12, 13 print argmax; the winner is the argmin (docs/design.md §3.1).
    """
    if positions.shape[0] == 3:  # one fused pass for point clouds and gripper positions
        p0, p1, p2 = p[0], p[1], p[2]
        for j in range(n):
            a, b, c = positions[0, j] - p0, positions[1, j] - p1, positions[2, j] - p2
            dist[j] = a * a + b * b + c * c
    else:
        squared_distances(positions, n, p, dist)
    best1, best2 = np.inf, np.inf
    i1, i2 = 0, 0
    for j in range(n):
        dj = dist[j]
        if dj < best2:
            if dj < best1:
                best2, i2 = best1, i1
                best1, i1 = dj, j
            else:
                best2, i2 = dj, j
    return i1, best1, i2, best2


@njit(cache=True)
def squared_distance(positions, i, p):
    total = 0.0
    for k in range(positions.shape[0]):
        diff = positions[k, i] - p[k]
        total += diff * diff
    return total


@njit(cache=True)
def slot_of(neighbours, degree, i, j):
    """Position of j in i's neighbour list, or -1 when they are not linked."""
    for k in range(degree[i]):
        if neighbours[i, k] == j:
            return k
    return -1


@njit(cache=True)
def link(neighbours, ages, degree, counters, i, j, age):
    """Create edge i-j with the given age, or reset its age when it exists (eq. 14)."""
    k = slot_of(neighbours, degree, i, j)
    if k >= 0:
        ages[i, k] = age
        ages[j, slot_of(neighbours, degree, j, i)] = age
        return
    for a, b in ((i, j), (j, i)):
        neighbours[a, degree[a]] = b
        ages[a, degree[a]] = age
        degree[a] += 1
        if degree[a] > counters[MAX_DEGREE]:
            counters[MAX_DEGREE] = degree[a]


@njit(cache=True)
def _drop_slot(neighbours, ages, degree, i, k):
    last = degree[i] - 1
    neighbours[i, k] = neighbours[i, last]
    ages[i, k] = ages[i, last]
    degree[i] = last


@njit(cache=True)
def unlink(neighbours, ages, degree, i, j):
    """Remove edge i-j if it exists."""
    k = slot_of(neighbours, degree, i, j)
    if k < 0:
        return
    _drop_slot(neighbours, ages, degree, i, k)
    _drop_slot(neighbours, ages, degree, j, slot_of(neighbours, degree, j, i))


@njit(cache=True)
def adapt(positions, neighbours, degree, s, p, mu1, mu2, mu3):
    """Move the winner by eq. 2 and each neighbour j by eq. 3 with its own difference p - w_j.

    xi_j = exp(-mu3 ||p - w_j||) is evaluated before j moves.
    """
    d = positions.shape[0]
    for m in range(degree[s]):
        j = neighbours[s, m]
        step = mu2
        if mu3 != 0.0:
            step = mu2 * np.exp(-mu3 * np.sqrt(squared_distance(positions, j, p)))
        for k in range(d):
            positions[k, j] += step * (p[k] - positions[k, j])
    for k in range(d):
        positions[k, s] += mu1 * (p[k] - positions[k, s])


@njit(cache=True)
def renormalise(errors, n, scale):
    """Fold the lazy decay factor into the stored errors (keeps eq. 10 exact)."""
    for i in range(n):
        errors[i] *= scale[0]
    scale[0] = 1.0


@njit(cache=True)
def largest_error_pair(errors, neighbours, degree, n):
    """q = node of largest error (eq. 5) and f = its neighbour of largest error, or (-1, -1)."""
    q = 0
    for i in range(1, n):
        if errors[i] > errors[q]:
            q = i
    if degree[q] == 0:
        return -1, -1
    f = neighbours[q, 0]
    for m in range(1, degree[q]):
        j = neighbours[q, m]
        if errors[j] > errors[f]:
            f = j
    return q, f


@njit(cache=True)
def add_midpoint_node(positions, errors, degree, counters, q, f, alpha):
    """New node r at the midpoint of q and f (eq. 6) with errors by eqs. 7-9; returns r.

    Errors must be renormalised (scale 1) before the call.
    """
    r = counters[N_NODES]
    for k in range(positions.shape[0]):
        positions[k, r] = 0.5 * (positions[k, q] + positions[k, f])
    errors[q] -= alpha * errors[q]
    errors[f] -= alpha * errors[f]
    errors[r] = 0.5 * (errors[q] + errors[f])
    degree[r] = 0
    counters[N_NODES] = r + 1
    counters[MIN_NODE] = -1
    return r


@njit(cache=True)
def smallest_error_node(errors, n):
    best = 0
    for i in range(1, n):
        if errors[i] < errors[best]:
            best = i
    return best


@njit(cache=True)
def remove_isolated_node(positions, errors, neighbours, ages, degree, counters, i):
    """Delete node i, which must have no edges, by moving the last node into its slot."""
    last = counters[N_NODES] - 1
    counters[N_NODES] = last
    counters[MIN_NODE] = -1
    if i == last:
        return
    positions[:, i] = positions[:, last]
    errors[i] = errors[last]
    degree[i] = degree[last]
    for m in range(degree[last]):
        j = neighbours[last, m]
        neighbours[i, m] = j
        ages[i, m] = ages[last, m]
        neighbours[j, slot_of(neighbours, degree, j, last)] = i

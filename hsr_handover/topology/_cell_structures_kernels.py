"""Numba training loop of Growing Cell Structures (paper 3.1, docs/design.md §3.2).

Payloads (joint vectors) travel with nodes: ``payload[i]`` is the payload of the training
sample at ``payload_x[i]``, the closest sample node i has won so far. Payloads are copied,
never averaged, so a node never mixes two inverse-kinematics branches.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from hsr_handover.topology._graph_kernels import (
    MAX_DEGREE,
    N_NODES,
    N_SIGNALS,
    SINCE_INSERT,
    TINY_SCALE,
    adapt,
    add_midpoint_node,
    largest_error_pair,
    link,
    nearest_two,
    renormalise,
    slot_of,
    unlink,
)


@njit(cache=True)
def _sample_distance(positions, i, payload_x, sample):
    total = 0.0
    for k in range(positions.shape[0]):
        diff = positions[k, i] - payload_x[sample, k]
        total += diff * diff
    return total


@njit(cache=True)
def _keep_closer_payload(positions, payload, payload_x, node, p, v):
    """Give the node the sample (p, v) if it lies closer than the node's current sample."""
    new = 0.0
    for k in range(positions.shape[0]):
        diff = positions[k, node] - p[k]
        new += diff * diff
    if new < _sample_distance(positions, node, payload_x, node):
        payload_x[node, :] = p
        payload[node, :] = v


@njit(cache=True)
def _insert_in_simplices(positions, errors, neighbours, ages, degree, counters, alpha, common):
    """Steps 5 i-vi with r linked to q, f and every common neighbour of q and f.

    Splitting edge q-f this way splits every simplex on that edge in two, so the complex stays
    made of k-simplices (docs/design.md §3.2). Returns (q, f, r), or (-1, -1, -1) when q is
    isolated.
    """
    q, f = largest_error_pair(errors, neighbours, degree, counters[N_NODES])
    if q < 0:
        return -1, -1, -1
    count = 0
    for m in range(degree[q]):
        c = neighbours[q, m]
        if c != f and slot_of(neighbours, degree, f, c) >= 0:
            common[count] = c
            count += 1
    r = add_midpoint_node(positions, errors, degree, counters, q, f, alpha)
    unlink(neighbours, ages, degree, q, f)
    link(neighbours, ages, degree, counters, r, q, 0)
    link(neighbours, ages, degree, counters, r, f, 0)
    for m in range(count):
        link(neighbours, ages, degree, counters, r, common[m], 0)
    return q, f, r


@njit(cache=True)
def _inherit_payload(positions, payload, payload_x, q, f, r):
    """r takes the payload of q or f, whichever sample is closer to r (no averaging)."""
    source = q
    if _sample_distance(positions, r, payload_x, f) < _sample_distance(positions, r, payload_x, q):
        source = f
    payload_x[r, :] = payload_x[source, :]
    payload[r, :] = payload[source, :]


@njit(cache=True)
def train_cell_structures(
    points,
    sample_payload,
    order,
    positions,
    errors,
    neighbours,
    ages,
    degree,
    counters,
    scale,
    payload,
    payload_x,
    dist,
    scratch,
    max_nodes,
    lam,
    mu1,
    mu2,
    mu3,
    alpha,
    beta,
):
    """Learn the signals points[order[t]]; returns how many were learnt (see train_neural_gas).

    sample_payload has one row per point, possibly of width 0 (no payload).
    """
    decay = 1.0 - beta
    with_payload = payload.shape[1] > 0
    for t in range(order.shape[0]):
        if counters[MAX_DEGREE] + 2 > neighbours.shape[1]:
            return t
        p = points[order[t]]
        s, d1, _, _ = nearest_two(positions, counters[N_NODES], p, dist)
        errors[s] += d1 / scale[0]  # eq. 4
        adapt(positions, neighbours, degree, s, p, mu1, mu2, mu3)  # eqs. 2-3
        if with_payload:
            _keep_closer_payload(positions, payload, payload_x, s, p, sample_payload[order[t]])
        counters[SINCE_INSERT] += 1
        if counters[SINCE_INSERT] >= lam:
            counters[SINCE_INSERT] = 0
            renormalise(errors, counters[N_NODES], scale)
            if counters[N_NODES] < max_nodes:
                q, f, r = _insert_in_simplices(
                    positions, errors, neighbours, ages, degree, counters, alpha, scratch
                )
                if with_payload and r >= 0:
                    _inherit_payload(positions, payload, payload_x, q, f, r)
        scale[0] *= decay  # eq. 10
        if scale[0] < TINY_SCALE:
            renormalise(errors, counters[N_NODES], scale)
        counters[N_SIGNALS] += 1
    return order.shape[0]


@njit(cache=True)
def interpolate_payload(points, labels, positions, neighbours, degree, payload, mu3, out):
    """Eq. 11: V = (sum_j xi_j v_j + v_s) / (sum_j xi_j + 1) over the neighbours j of the
    winner s = labels[i], with xi_j = exp(-mu3 ||x - w_j||). Rows with label -1 become NaN.
    """
    for i in range(points.shape[0]):
        s = labels[i]
        if s < 0:
            out[i, :] = np.nan
            continue
        out[i, :] = payload[s, :]
        total = 1.0
        for m in range(degree[s]):
            j = neighbours[s, m]
            gap = 0.0
            for k in range(points.shape[1]):
                diff = points[i, k] - positions[k, j]
                gap += diff * diff
            xi = np.exp(-mu3 * np.sqrt(gap))
            out[i, :] += xi * payload[j, :]
            total += xi
        out[i, :] /= total

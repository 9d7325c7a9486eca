"""Numba training loop of the adaptive Growing Neural Gas (paper 3.1, docs/design.md §3.1)."""

from __future__ import annotations

from numba import njit

from hsr_handover.topology._graph_kernels import (
    MAX_DEGREE,
    MIN_NODE,
    N_NODES,
    N_SIGNALS,
    SINCE_INSERT,
    TINY_SCALE,
    adapt,
    add_midpoint_node,
    largest_error_pair,
    link,
    nearest_two,
    remove_isolated_node,
    renormalise,
    slot_of,
    smallest_error_node,
    unlink,
)


@njit(cache=True)
def _delete_isolated(positions, errors, neighbours, ages, degree, counters, candidates, count):
    """Delete those of the candidate nodes that have no edge left, highest index first.

    Highest first because deleting moves the last node into the freed slot; going down, that
    last node is never a candidate still waiting.
    """
    candidates[:count].sort()
    for m in range(count - 1, -1, -1):
        j = candidates[m]
        if degree[j] == 0:
            remove_isolated_node(positions, errors, neighbours, ages, degree, counters, j)


@njit(cache=True)
def _age_edges(positions, errors, neighbours, ages, degree, counters, s1, a_max, scratch):
    """Eq. 15: age the winner's edges; drop those older than a_max and nodes left alone."""
    for m in range(degree[s1]):
        j = neighbours[s1, m]
        ages[s1, m] += 1
        ages[j, slot_of(neighbours, degree, j, s1)] += 1
    count = 0
    m = 0
    while m < degree[s1]:
        if ages[s1, m] > a_max:
            j = neighbours[s1, m]
            unlink(neighbours, ages, degree, s1, j)
            scratch[count] = j
            count += 1
        else:
            m += 1
    if count > 0:
        _delete_isolated(positions, errors, neighbours, ages, degree, counters, scratch, count)


@njit(cache=True)
def _insert(positions, errors, neighbours, ages, degree, counters, alpha):
    """Steps 5 i-vi (eqs. 5-9): new node between q and f, edges q-r and r-f replace q-f."""
    q, f = largest_error_pair(errors, neighbours, degree, counters[N_NODES])
    if q < 0:
        return
    r = add_midpoint_node(positions, errors, degree, counters, q, f, alpha)
    unlink(neighbours, ages, degree, q, f)
    link(neighbours, ages, degree, counters, q, r, 0)
    link(neighbours, ages, degree, counters, r, f, 0)


@njit(cache=True)
def _delete_low_error(positions, errors, neighbours, ages, degree, counters, scale, e_min, scratch):
    """Step 6'-ii: delete nodes whose error fell below e_min, with neighbours left alone.

    Never leaves fewer than two nodes. Uniform decay keeps the order of the stored errors, so
    only the node of smallest error needs checking; it is searched again only when invalidated.
    """
    while True:
        n = counters[N_NODES]
        if counters[MIN_NODE] < 0:
            counters[MIN_NODE] = smallest_error_node(errors, n)
        i = counters[MIN_NODE]
        if errors[i] * scale[0] >= e_min:
            return
        count = 1
        scratch[0] = i
        for m in range(degree[i]):
            j = neighbours[i, m]
            if degree[j] == 1:
                scratch[count] = j
                count += 1
        if n - count < 2:
            return
        while degree[i] > 0:
            unlink(neighbours, ages, degree, i, neighbours[i, 0])
        _delete_isolated(positions, errors, neighbours, ages, degree, counters, scratch, count)


@njit(cache=True)
def train_neural_gas(
    points,
    order,
    positions,
    errors,
    neighbours,
    ages,
    degree,
    counters,
    scale,
    dist,
    scratch,
    max_nodes,
    lam,
    mu1,
    mu2,
    mu3,
    a_max,
    alpha,
    beta,
    e_min,
):
    """Learn the signals points[order[t]]; returns how many were learnt.

    Stops early (returns t < len(order)) when a neighbour list could overflow; the caller grows
    the lists and calls again with the remaining signals.
    """
    decay = 1.0 - beta
    for t in range(order.shape[0]):
        if counters[MAX_DEGREE] + 2 > neighbours.shape[1]:
            return t
        p = points[order[t]]
        s1, d1, s2, _ = nearest_two(positions, counters[N_NODES], p, dist)
        errors[s1] += d1 / scale[0]  # eq. 4 with the distance before the move, as Fritzke
        if s1 == counters[MIN_NODE]:
            counters[MIN_NODE] = -1
        link(neighbours, ages, degree, counters, s1, s2, 0)  # eq. 14
        adapt(positions, neighbours, degree, s1, p, mu1, mu2, mu3)  # eqs. 2-3
        _age_edges(positions, errors, neighbours, ages, degree, counters, s1, a_max, scratch)
        counters[SINCE_INSERT] += 1
        if counters[SINCE_INSERT] >= lam:
            counters[SINCE_INSERT] = 0
            renormalise(errors, counters[N_NODES], scale)
            if counters[N_NODES] < max_nodes:
                _insert(positions, errors, neighbours, ages, degree, counters, alpha)
        scale[0] *= decay  # eq. 10 for every node at once
        if scale[0] < TINY_SCALE:
            renormalise(errors, counters[N_NODES], scale)
        if e_min > 0.0:
            _delete_low_error(
                positions, errors, neighbours, ages, degree, counters, scale, e_min, scratch
            )
        counters[N_SIGNALS] += 1
    return order.shape[0]

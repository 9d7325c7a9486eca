"""A first guess for the base's way round the table: when the straight line
from where the base stands to where it must go crosses the table, the optimiser starting from
that line rarely finds its way out; it is given the shortest way round the table's corners
instead, and the arm folded over the base while the base drives. A base that stands at the
table (to grasp, to hand over across its corner) first drives straight out from it
(`route_out`).
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from hsr_handover.hsr import BASE_RADIUS
from hsr_handover.robot.perception.table_fit import TableEstimate

ROUTE_MARGIN = 0.12  # m kept between the base's disc and the table's edge on the way round


def _crosses(a: np.ndarray, b: np.ndarray, half: np.ndarray) -> bool:
    """Whether the segment a-b (in the rectangle's frame) enters the open box |x| < half."""
    low, high = 0.0, 1.0
    direction = b - a
    for axis in range(2):
        if abs(direction[axis]) < 1e-12:
            if abs(a[axis]) >= half[axis]:
                return False
            continue
        t1 = (-half[axis] - a[axis]) / direction[axis]
        t2 = (half[axis] - a[axis]) / direction[axis]
        low, high = max(low, min(t1, t2)), min(high, max(t1, t2))
        if low >= high:
            return False
    return True


def route_around(start: np.ndarray, goal: np.ndarray, table: TableEstimate | None) -> np.ndarray:
    """Base positions (k, 2) from `start` to `goal` (x, y, world): the straight line if it
    keeps clear of the table, else the shortest way through corners of the table's rectangle
    widened by the base's radius and a margin."""
    start, goal = np.asarray(start, float)[:2], np.asarray(goal, float)[:2]
    if table is None:
        return np.array([start, goal])
    half = table.size / 2 + BASE_RADIUS + ROUTE_MARGIN
    local = [table.to_local(point) for point in (start, goal)]
    if not _crosses(local[0], local[1], half - 1e-6):
        return np.array([start, goal])
    corners = [np.array([sx, sy]) * half for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1))]
    best, best_length = None, math.inf
    for count in (1, 2):
        for chosen in itertools.permutations(corners, count):
            path = [local[0], *chosen, local[1]]
            if any(_crosses(a, b, half - 1e-6) for a, b in itertools.pairwise(path)):
                continue
            length = sum(np.linalg.norm(b - a) for a, b in itertools.pairwise(path))
            if length < best_length:
                best, best_length = path, length
    if best is None:  # start or goal inside the widened table: nothing better than the line
        return np.array([start, goal])
    return table.to_world(np.array(best))


def _outside(point: np.ndarray, half: np.ndarray) -> np.ndarray | None:
    """The nearest point (rectangle frame) on the edge of the box |x| <= `half` straight out
    from `point` when it lies inside the box, else None."""
    depth = half - np.abs(point)
    if np.any(depth <= 0):
        return None
    axis = int(np.argmin(depth))
    out = point.copy()
    out[axis] = math.copysign(half[axis] + 1e-3, point[axis])
    return out


def route_out(start: np.ndarray, goal: np.ndarray, table: TableEstimate | None) -> np.ndarray:
    """`route_around` from a `start` and to a `goal` (x, y, world) that may stand nearer the
    table than the route's margin: straight out from the table's nearest side to the margin
    first, and straight in to the goal last (`route_around` itself, for a start within the
    margin, has nothing better than the straight line)."""
    start, goal = np.asarray(start, float)[:2], np.asarray(goal, float)[:2]
    if table is None:
        return np.array([start, goal])
    half = table.size / 2 + BASE_RADIUS + ROUTE_MARGIN
    ends = []
    for point in (start, goal):
        out = _outside(table.to_local(point), half)
        ends.append(point if out is None else table.to_world(out))
    way = [start, *route_around(ends[0], ends[1], table), goal]
    kept = [way[0]]
    for point in way[1:]:
        if np.linalg.norm(point - kept[-1]) > 1e-6:
            kept.append(point)
    return np.array(kept)

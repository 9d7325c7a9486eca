"""Partial shortcutting of a path in joint space (Geraerts and Overmars 2007, "Creating
high-quality paths for motion planning", IJRR 26(8)): a clear polyline made faster by replacing
a stretch of it, in every joint or in one group of them (the base, the arm, one joint), by the
straight line between the stretch's ends, whenever the new stretch is faster and clear. The
group's shortcut is what lets the arm fold while the base drives, where the first polyline
does one after the other.

The time of a polyline is taken at full speed, each segment as long as its slowest joint
takes (`seconds`): the joints move together, so a group that moves alongside another costs
nothing. The shortcuts tried come from a seeded generator: the same polyline gives the same
path.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

Clear = Callable[[np.ndarray, int], bool]
"""Whether a stretch of vertices (k, n) starting at the polyline's vertex `first` is clear,
between its vertices too."""


def seconds(points: np.ndarray, speeds: np.ndarray) -> float:
    """The time (s) along the polyline `points` (m, n) with every joint at most at its
    `speeds` (n,) and each segment as long as its slowest joint takes."""
    return float((np.abs(np.diff(points, axis=0)) / speeds).max(axis=1, initial=0.0).sum())


def resampled(keys: np.ndarray, speeds: np.ndarray, count: int) -> np.ndarray:
    """`count` vertices (count, n) along the polyline `keys` (m, n), evenly spaced in its time
    at full speed (`seconds`)."""
    keys = np.asarray(keys, dtype=float)
    steps = (np.abs(np.diff(keys, axis=0)) / speeds).max(axis=1)
    along = np.concatenate([[0.0], np.cumsum(steps)])
    spots = np.linspace(0.0, along[-1], count)
    return np.array([np.interp(spots, along, keys[:, i]) for i in range(keys.shape[1])]).T


def shorten(
    points: np.ndarray,
    speeds: np.ndarray,
    groups: Sequence[Sequence[int]],
    clear: Clear,
    attempts: int,
    seed: int = 0,
) -> np.ndarray:
    """The clear polyline `points` (m, n) shortened by up to `attempts` tries: two vertices
    and one of the joint `groups` drawn, the group's joints between them put on the straight
    line between their values there (every other joint as it was), kept when that saves time
    (`seconds` at `speeds`) and the changed stretch is `clear`. The ends never move."""
    points = np.array(points, dtype=float)
    count = len(points)
    generator = np.random.default_rng(seed)
    for _ in range(attempts):
        first, last = sorted(generator.choice(count, 2, replace=False))
        if last - first < 2:
            continue
        group = list(groups[generator.integers(len(groups))])
        stretch = points[first : last + 1].copy()
        stretch[:, group] = np.linspace(points[first, group], points[last, group], len(stretch))
        saved = seconds(points[first : last + 1], speeds) - seconds(stretch, speeds)
        if saved > 1e-3 and clear(stretch, first):
            points[first : last + 1] = stretch
    return points

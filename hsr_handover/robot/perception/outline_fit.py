"""Which outline a standing object's visible sides follow, seen from above: an arc of a circle
(a cup) or the sides of a rectangle (a box).

From the head camera the side of an object is seen over less than half its round: a cup shows
an arc, a box one face or two. Both fits are least-deviation fits of those side points alone,
so what the camera cannot see does not enter: the circle by algebraic least squares (Kasa
1976: linear in the centre and radius, exact on an arc of any length), the rectangle by the
orientation whose bounding sides the points lie closest to. Deviations are medians, the
rectangle's sides percentiles, and the circle is fitted again without the points far off it,
so a few stray points (an edge pixel, the table behind) do not move them.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

RECTANGLE_ANGLES = np.radians(np.arange(0.0, 90.0, 2.0))
"""Orientations tried for a rectangle: a rectangle repeats every 90 degrees, and 1 degree off
moves a 6 cm side's end 0.5 mm."""
SIDE_PERCENTILE = 3.0
"""% of the points a rectangle's side may leave outside it."""
OUTLIER_DEVIATIONS, OUTLIER_FLOOR = 3.0, 0.001  # -, m
REFITS = 2
MOST_POINTS = 200
"""Points fitted at most (an even stride through them): the fits' deviations settle well
before."""


@dataclasses.dataclass(frozen=True)
class CircleFit:
    """A circle's `center` (x, y) and `radius` (m), and the median distance of the points
    from it (`deviation`, m)."""

    center: np.ndarray
    radius: float
    deviation: float


@dataclasses.dataclass(frozen=True)
class RectangleFit:
    """The orientation (`yaw`, rad in [0, pi/2)) whose rectangle the points lie closest to,
    and their median distance from its nearest side (`deviation`, m)."""

    yaw: float
    deviation: float


def _thinned(xy: np.ndarray) -> np.ndarray:
    xy = np.asarray(xy, dtype=float)
    return xy[:: max(1, math.ceil(len(xy) / MOST_POINTS))]


def fit_circle(xy: np.ndarray) -> CircleFit:
    """The least-squares circle through the points `xy` (N, 2), N >= 3 (Kasa's fit: x^2 + y^2
    = 2 a x + 2 b y + c, linear in a, b and c), fitted again without the points further from
    it than OUTLIER_DEVIATIONS times their median (a least-squares circle follows a stray point
    far: three points 10 cm off a 3.5 cm arc of 300 nearly double its radius). The deviation
    is the median over all the points."""
    xy = _thinned(xy)
    kept = xy
    for refit in range(REFITS + 1):
        center, radius = _least_squares_circle(kept)
        deviation = np.abs(np.hypot(*(xy - center).T) - radius)
        median = float(np.median(deviation))
        near = deviation <= OUTLIER_DEVIATIONS * median + OUTLIER_FLOOR
        if refit == REFITS or near.all() or near.sum() < 3:
            return CircleFit(center, radius, median)
        kept = xy[near]


def _least_squares_circle(xy: np.ndarray) -> tuple[np.ndarray, float]:
    system = np.column_stack([2.0 * xy, np.ones(len(xy))])
    (a, b, c), *_ = np.linalg.lstsq(system, (xy**2).sum(axis=1), rcond=None)
    return np.array([a, b]), math.sqrt(max(c + a * a + b * b, 0.0))


def fit_rectangle(xy: np.ndarray) -> RectangleFit:
    """The rectangle whose sides the points `xy` (N, 2) lie on most closely, over
    RECTANGLE_ANGLES: at each, its sides are the points' SIDE_PERCENTILE bounds along and
    across."""
    xy = _thinned(xy)
    xy = xy - xy.mean(axis=0)
    along = xy @ np.array([np.cos(RECTANGLE_ANGLES), np.sin(RECTANGLE_ANGLES)])  # (N, angles)
    across = xy @ np.array([-np.sin(RECTANGLE_ANGLES), np.cos(RECTANGLE_ANGLES)])
    deviations = []
    for u in (along, across):
        low, high = np.percentile(u, [SIDE_PERCENTILE, 100.0 - SIDE_PERCENTILE], axis=0)
        deviations += [np.abs(u - low), np.abs(high - u)]
    median = np.median(np.minimum.reduce(deviations), axis=0)
    best = int(np.argmin(median))
    return RectangleFit(float(RECTANGLE_ANGLES[best]), float(median[best]))

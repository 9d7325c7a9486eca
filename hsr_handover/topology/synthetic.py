"""Synthetic point clouds for testing and benchmarking the maps: box surfaces."""

from __future__ import annotations

import numpy as np

# The benchmark scene: three boxes on a floor, centres and sizes in metres.
THREE_BOX_CENTRES = np.array([(0.0, 0.0, 0.25), (1.2, 0.3, 0.15), (-0.8, -0.5, 0.4)])
THREE_BOX_SIZES = np.array([(1.0, 0.6, 0.5), (0.3, 0.3, 0.3), (0.2, 0.4, 0.8)])


def box_surface_area(sizes: np.ndarray) -> np.ndarray:
    """Surface area of each box (n, 3) -> (n,)."""
    sizes = np.atleast_2d(sizes)
    a, b, c = sizes.T
    return 2.0 * (a * b + b * c + a * c)


def box_surface_points(
    n: int,
    rng: np.random.Generator,
    centres: np.ndarray = THREE_BOX_CENTRES,
    sizes: np.ndarray = THREE_BOX_SIZES,
) -> np.ndarray:
    """n points uniform by area on the surfaces of axis-aligned boxes, (n, 3)."""
    centres, sizes = np.atleast_2d(centres), np.atleast_2d(sizes)
    box = np.repeat(np.arange(len(sizes)), 6)
    axis = np.tile(np.repeat(np.arange(3), 2), len(sizes))
    sign = np.tile([-1.0, 1.0], 3 * len(sizes))
    face_area = np.prod(sizes[box], axis=1) / sizes[box, axis]
    face = rng.choice(len(box), size=n, p=face_area / face_area.sum())
    points = centres[box[face]] + (rng.random((n, 3)) - 0.5) * sizes[box[face]]
    normal = axis[face]
    rows = np.arange(n)
    points[rows, normal] = centres[box[face], normal] + 0.5 * sign[face] * sizes[box[face], normal]
    return points

"""The depth at a keypoint's pixel: a percentile of the valid depths in a small window round it,
so that a pixel slipping off a limb's edge or onto a depth hole still reads the body."""

from __future__ import annotations

import numpy as np

from hsr_handover.interface.pinhole import valid_depth

# Half-size of the depth window a keypoint is lifted from: the window survives a pixel
# that slips off a limb's edge onto the background or a depth hole.
DEPTH_WINDOW_HALF = 2


def _pixel_indices(pixels: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Column and row of the pixel nearest each (u, v); callers pass in-image pixels."""
    return np.rint(pixels[:, 0]).astype(int), np.rint(pixels[:, 1]).astype(int)


def window_depths(depth: np.ndarray, pixels: np.ndarray, percentile: float) -> np.ndarray:
    """The `percentile` of the valid depths in the 5 x 5 window around each in-image pixel
    (N, 2); NaN where the window holds no valid depth."""
    u, v = _pixel_indices(pixels)
    result = np.full(len(pixels), np.nan)
    h = DEPTH_WINDOW_HALF
    for i, (col, row) in enumerate(zip(u, v, strict=True)):
        window = depth[max(row - h, 0) : row + h + 1, max(col - h, 0) : col + h + 1]
        values = window[valid_depth(window)]
        if values.size:
            result[i] = np.percentile(values, percentile)
    return result

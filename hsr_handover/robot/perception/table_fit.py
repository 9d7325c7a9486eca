"""The table as the robot sees it: a horizontal top fitted to head-camera point clouds.

A table top is the largest horizontal surface at a table's height in the workspace, so each
frame's heights are histogrammed and the fullest bin (refined by the median of the points near
it) is that frame's height; the top's is their median weighted by the area each frame saw at
its height (`TableMap.height`). The points on that plane are marked on a grid over the
workspace, frame after frame, so a head that looks around adds what one view misses; the
table's extent is the smallest rectangle around the grid's largest connected patch
(`cv2.minAreaRect`). Objects standing on the table and a person's arm resting on it hide parts
of the top but not its outline, and they are not at its height.
"""

from __future__ import annotations

import dataclasses
import math

import cv2
import numpy as np

from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.robot.perception.cloud_map import Workspace

EDGE_PROBE_M = 0.05  # m past an edge's middle where the camera must have looked and seen no top
NO_POINTS = "no points at a table's height"
NO_TABLE = "no table top seen"


@dataclasses.dataclass(frozen=True)
class TableFitParams:
    """heights: where a table's top may be (m, low and high). bin_m: the height histogram's
    bin (m). band_m: how near the top's height (m) a point must be to lie on it. cell_m: the
    grid's cell (m). gap_m: gaps between seen cells up to this wide (m) are bridged (a far,
    grazing view samples the top a few cm apart). min_area_m2: the least area of top seen
    before it counts as a table."""

    heights: tuple[float, float] = (0.4, 1.2)
    bin_m: float = 0.005
    band_m: float = 0.01
    cell_m: float = 0.01
    gap_m: float = 0.05
    min_area_m2: float = 0.05

    def __post_init__(self) -> None:
        low, high = self.heights
        if not 0.0 <= low < high:
            raise ValueError(f"heights: expected 0 <= low < high (m), got {self.heights}")
        for name in ("bin_m", "band_m", "cell_m", "gap_m", "min_area_m2"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name}: expected a positive value, got {getattr(self, name)}")


@dataclasses.dataclass(frozen=True)
class TableEstimate:
    """A table top: its height (m), the centre (x, y) of its rectangle, the rectangle's size
    (m) along its own x (the longer side) and y, its yaw (rad, in [-pi/2, pi/2)) and the
    number of grid cells seen on it."""

    height: float
    center: np.ndarray
    size: np.ndarray
    yaw: float
    cells: int
    open_edges: tuple[bool, ...] = (False, False, False, False)
    """Per edge (+x, -x, +y, -y along the rectangle's own axes): whether the top may run on past
    it, the camera never having had the strip just beyond it in view."""

    @property
    def rotation(self) -> np.ndarray:
        """The rectangle's axes in the world (2, 2): local (x, y) to world directions."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return np.array([[c, -s], [s, c]])

    def to_world(self, local: np.ndarray) -> np.ndarray:
        """Points (..., 2) in the rectangle's own frame to the world's (x, y)."""
        return self.center + np.asarray(local, dtype=float) @ self.rotation.T

    def to_local(self, xy: np.ndarray) -> np.ndarray:
        """World (x, y) points (..., 2) to the rectangle's own frame."""
        return (np.asarray(xy, dtype=float)[..., :2] - self.center) @ self.rotation

    def corners(self) -> np.ndarray:
        """The top's four corners (4, 2) in the world, counter-clockwise."""
        return self.to_world(np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * self.size / 2)


@dataclasses.dataclass(frozen=True)
class TableReport:
    """What the robot knows of the table: the estimate (None until a top has been seen), how
    many frames have shown it, and "ok" or why there is no estimate."""

    estimate: TableEstimate | None
    frames: int
    status: str


def top_height(heights: np.ndarray, params: TableFitParams) -> float | None:
    """The height (m) of the largest horizontal surface among points' heights (N,): the
    fullest histogram bin, refined to the median of the heights within `band_m` of it."""
    low, high = params.heights
    heights = heights[(heights >= low) & (heights <= high)]
    if heights.size == 0:
        return None
    bins = max(int(math.ceil((high - low) / params.bin_m)), 1)
    counts, edges = np.histogram(heights, bins=bins, range=(low, high))
    peak = (edges[np.argmax(counts)] + edges[np.argmax(counts) + 1]) / 2
    return float(np.median(heights[np.abs(heights - peak) <= params.band_m]))


class TableMap:
    """Table-top evidence gathered over frames (`add`), and the table it shows (`estimate`).

    The top's height is the frames' heights' median weighted by the area each saw there
    (`height`); a grid over the workspace's floor plan counts, per cell, the frames' points
    found on the top.
    """

    def __init__(self, workspace: Workspace, params: TableFitParams | None = None):
        self.workspace, self.params = workspace, params or TableFitParams()
        params = self.params
        self._origin = np.asarray(workspace.lower[:2], dtype=float)
        span = np.asarray(workspace.upper[:2], dtype=float) - self._origin
        shape = np.maximum(np.ceil(span / params.cell_m).astype(int), 1)
        self.counts_ = np.zeros((shape[1], shape[0]), dtype=np.int32)  # rows are y, columns x
        self.viewed_ = np.zeros((shape[1], shape[0]), dtype=bool)  # in a camera's view at the top
        self.heights_: list[float] = []
        self.areas_: list[int] = []  # grid cells each frame saw at its own height

    def add(self, points: np.ndarray, view: tuple[PinholeCamera, np.ndarray] | None = None) -> str:
        """Add one frame's world points (N, 3; NaN rows are skipped), with the `view` (camera
        intrinsics and X_WC) they were seen with, which marks the cells the camera had in view
        at the top's height; returns "ok" or why the frame showed no table top."""
        points = self.workspace.crop(np.asarray(points, dtype=float).reshape(-1, 3))
        height = top_height(points[:, 2], self.params)
        if height is None:
            return NO_POINTS
        self.heights_.append(height)
        self.areas_.append(max(self._area(self._level(points, height)), 1))
        top = self.height  # the frames' so far, this one's included
        np.add.at(self.counts_, self._cells(self._level(points, top)), 1)
        if view is not None:
            self._mark_viewed(*view, top)
        return "ok"

    def _level(self, points: np.ndarray, height: float) -> np.ndarray:
        """The floor-plan positions (N, 2) of the points (N, 3) within `band_m` of `height`."""
        return points[np.abs(points[:, 2] - height) <= self.params.band_m, :2]

    def _mark_viewed(self, camera: PinholeCamera, X_WC: np.ndarray, top: float) -> None:
        rows, cols = self.counts_.shape
        y, x = np.mgrid[0:rows, 0:cols]
        centres = (
            self._origin + (np.column_stack([x.ravel(), y.ravel()]) + 0.5) * self.params.cell_m
        )
        at_top = np.column_stack([centres, np.full(len(centres), top)])
        self.viewed_ |= camera.project_in_view(at_top, X_WC)[2].reshape(rows, cols)

    def _area(self, xy: np.ndarray) -> int:
        """The number of grid cells under the points (N, 2)."""
        seen = np.zeros(self.counts_.shape, dtype=bool)
        seen[self._cells(xy)] = True
        return int(np.count_nonzero(seen))

    def _cells(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(rows, columns) of the grid cells under the points (N, 2) that fall on the grid."""
        cells = np.floor((xy - self._origin) / self.params.cell_m).astype(int)
        rows, cols = self.counts_.shape
        inside = (
            (cells[:, 0] >= 0) & (cells[:, 0] < cols) & (cells[:, 1] >= 0) & (cells[:, 1] < rows)
        )
        return cells[inside, 1], cells[inside, 0]

    def open_edges(self, estimate: TableEstimate) -> tuple[bool, ...]:
        """Per edge of `estimate` (+x, -x, +y, -y): False when the camera has had the point
        EDGE_PROBE_M past the edge's middle in view and saw no top there (a rectangular top
        that ends there ends along the whole edge; the middle, not a corner, because a view
        cut diagonally by the image's border leaves a corner's strip unseen); True (the top may
        run on) otherwise."""
        result = []
        for axis in (0, 1):
            for sign in (1.0, -1.0):
                local = np.zeros(2)
                local[axis] = sign * (estimate.size[axis] / 2 + EDGE_PROBE_M)
                rows, cols = self._cells(estimate.to_world(local)[None])
                ends = len(rows) == 1 and self.viewed_[rows[0], cols[0]]
                ends = ends and self.counts_[rows[0], cols[0]] == 0
                result.append(not ends)
        return tuple(result)

    @property
    def height(self) -> float:
        """The top's height (m): the median of the frames' heights weighted by the area (grid
        cells) each saw at its height; NaN before any frame showed one. Unweighted, frames in
        which the camera looked up at a standing person, the top out of view, each gave the
        fullest level of the person (0.9 to 1.2 m), and over a long trial they outnumbered
        the frames of the table: the top rose 9 cm by 29 s and the planner drove the base
        into the table's leg. A frame of the table
        sees 1,000 to 3,700 cells at its height, one of a person 50 to 250."""
        if not self.heights_:
            return math.nan
        weighted = np.quantile(self.heights_, 0.5, weights=self.areas_, method="inverted_cdf")
        return float(weighted)

    def report(self) -> TableReport:
        """The table seen so far (`estimate`), with the number of frames that showed a top."""
        estimate = self.estimate()
        status = "ok" if estimate else NO_TABLE if self.heights_ else NO_POINTS
        return TableReport(estimate, len(self.heights_), status)

    def estimate(self) -> TableEstimate | None:
        """The table: the smallest rectangle around the largest connected patch of cells seen
        on the top, or None until a patch of `min_area_m2` has been seen."""
        occupied = (self.counts_ > 0).astype(np.uint8)
        # Far off, a grazing view samples the top more sparsely than the grid: close the gaps
        # (up to `gap_m`) so that the top is one patch. Then open it: an upright surface (a
        # person's front, a chair's back) crosses the top's height in a thin line, not a patch.
        # Of the patch, keep the cells actually seen.
        gap = 2 * max(int(round(self.params.gap_m / self.params.cell_m / 2)), 0) + 1
        kernel = cv2.getStructuringElement(cv2.MORPH_RECT, (gap, gap))
        closed = cv2.morphologyEx(occupied, cv2.MORPH_CLOSE, kernel)
        opened = cv2.morphologyEx(closed, cv2.MORPH_OPEN, kernel)
        count, labels, stats, _ = cv2.connectedComponentsWithStats(opened, connectivity=8)
        if count < 2:
            return None
        largest = 1 + int(np.argmax(stats[1:, cv2.CC_STAT_AREA]))
        rows, cols = np.nonzero((labels == largest) & (occupied > 0))
        cells = len(rows)
        if cells * self.params.cell_m**2 < self.params.min_area_m2:
            return None
        # Cell centres: the top's true edge lies anywhere in its outermost cells, on average
        # at their centres, so the rectangle through them is unbiased.
        centres = np.column_stack([cols, rows]).astype(np.float32) + 0.5
        (cx, cy), (length, width), angle = cv2.minAreaRect(centres)
        yaw = math.radians(angle)
        if length < width:  # the rectangle's own x along its longer side
            length, width, yaw = width, length, yaw + math.pi / 2
        yaw = (yaw + math.pi / 2) % math.pi - math.pi / 2
        center = self._origin + np.array([cx, cy]) * self.params.cell_m
        size = np.array([length, width]) * self.params.cell_m
        estimate = TableEstimate(self.height, center, size, yaw, cells)
        return dataclasses.replace(estimate, open_edges=self.open_edges(estimate))

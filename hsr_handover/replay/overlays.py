"""What a replay draws over the recorded run, each under one root in Meshcat's tree, OVERLAYS:
its path, its colour and the legend's words for it.

Every overlay is a parent path the viewer's controls switch on and off, and what is drawn sits
in children below it (`<overlay>/mark` for a mark that moves, numbered snapshots for a thing
that changes shape, `meshcat_recording.Snapshots`). The recording animates only the children,
so a user's untick of the parent holds however the replay plays or is scrubbed.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from pydrake.geometry import Meshcat, Rgba
from pydrake.perception import BaseField, Fields, PointCloud

OVERLAYS = "/overlays"
MARK = "mark"  # the child drawn under an overlay that moves rather than changes shape
POINT_SIZE = 0.02  # m, a map's node
HANDOVER_POINT_RADIUS = 0.03  # m
EDGE_WIDTH = 1.0  # px, a map's edge (WebGL draws 1 px whatever is asked)

# Cluster colours (matplotlib's tab10), cycled over the scene map's cluster labels.
CLUSTER_PALETTE = np.array(
    [
        [31, 119, 180], [255, 127, 14], [44, 160, 44], [214, 39, 40], [148, 103, 189],
        [140, 86, 75], [227, 119, 194], [127, 127, 127], [188, 189, 34], [23, 190, 207],
    ],
    dtype=np.uint8,
)  # fmt: skip


@dataclasses.dataclass(frozen=True)
class Overlay:
    """One overlay: its `name` under OVERLAYS, its colour and what the legend says of it;
    `swatch` is the legend's CSS background when one colour does not say it."""

    name: str
    rgba: Rgba
    label: str
    swatch: str = ""

    @property
    def path(self) -> str:
        return f"{OVERLAYS}/{self.name}"

    @property
    def mark(self) -> str:
        """The child that is drawn, moved and shown (the user keeps `path`)."""
        return f"{self.path}/{MARK}"


def _css(rgb: np.ndarray) -> str:
    return f"rgb({int(rgb[0])}, {int(rgb[1])}, {int(rgb[2])})"


RESTING_RGBA = Rgba(0.62, 0.62, 0.62, 1.0)  # the scene map while it rests
_CLUSTERS = ", ".join(_css(rgb) for rgb in CLUSTER_PALETTE[:4])

SCENE_MAP = Overlay(
    "scene_map", RESTING_RGBA, "scene map (GNG), one colour a cluster; grey while it rests",
    swatch=f"linear-gradient(90deg, {_CLUSTERS}, rgb(158, 158, 158))",
)  # fmt: skip
POINTING_RAY = Overlay(
    "pointing_ray", Rgba(0.95, 0.5, 0.0, 1.0), "pointing ray, while the robot watches"
)
GAZE_RAY = Overlay("gaze_ray", Rgba(0.1, 0.7, 0.9, 1.0), "gaze ray, while the robot watches")
TARGET = Overlay(
    "target", Rgba(1.0, 0.9, 0.0, 0.35), "recognised target: where seen, or in the hand"
)
PALM_PATH = Overlay("palm_path", Rgba(0.6, 0.1, 0.8, 1.0), "palm's planned path")
ARM_MAP = Overlay(
    "arm_map", Rgba(0.2, 0.6, 0.2, 1.0), "arm's reachable range at the handover base (fig. 8)"
)
PERSON_RANGE = Overlay("person_range", Rgba(0.2, 0.4, 0.9, 0.6), "person's reachable range")
MUTUAL_AREA = Overlay(
    "mutual_area", Rgba(0.9, 0.1, 0.1, 1.0), "mutual area: both reach it (fig. 14)"
)
HANDOVER_POINT = Overlay("handover_point", Rgba(1.0, 0.8, 0.0, 1.0), "handover point")
PLANNED_ROBOT = Overlay(
    "planned_robot", Rgba(0.55, 0.6, 0.75, 0.45), "the robot at its planned handover pose"
)
CATALOGUE = (SCENE_MAP, POINTING_RAY, GAZE_RAY, TARGET, PALM_PATH, ARM_MAP, PERSON_RANGE,
             MUTUAL_AREA, HANDOVER_POINT, PLANNED_ROBOT)  # fmt: skip
"""Every overlay a replay may draw, in the legend's order."""


def drawn_overlays(meshcat: Meshcat) -> list[Overlay]:
    """The overlays of CATALOGUE that `meshcat` holds, in the legend's order."""
    return [overlay for overlay in CATALOGUE if meshcat.HasPath(overlay.path)]


def swatch_css(overlay: Overlay) -> str:
    """The legend's CSS background for `overlay` (a translucent colour shown at least 60 %
    opaque, so the swatch can be seen)."""
    if overlay.swatch:
        return overlay.swatch
    rgba = overlay.rgba
    red, green, blue = (round(255 * value) for value in (rgba.r(), rgba.g(), rgba.b()))
    return f"rgba({red}, {green}, {blue}, {max(rgba.a(), 0.6):.2f})"


def draw_points(meshcat: Meshcat, path: str, points: np.ndarray, rgba: Rgba) -> None:
    """Points (n, 3, world) drawn at `path`, POINT_SIZE each, in one colour."""
    cloud = PointCloud(len(points), Fields(BaseField.kXYZs))
    cloud.mutable_xyzs()[:] = np.asarray(points, dtype=float).reshape(-1, 3).T
    meshcat.SetObject(path, cloud, POINT_SIZE, rgba)


def draw_edges(
    meshcat: Meshcat, path: str, nodes: np.ndarray, edges: np.ndarray, rgba: Rgba
) -> None:
    """A map's edges (m, 2 node indices) between its `nodes` (n, 3, world) as line segments."""
    ends = np.asarray(nodes, dtype=float)[np.asarray(edges, dtype=int).reshape(-1, 2)]
    meshcat.SetLineSegments(
        path, np.asfortranarray(ends[:, 0].T), np.asfortranarray(ends[:, 1].T), EDGE_WIDTH, rgba
    )

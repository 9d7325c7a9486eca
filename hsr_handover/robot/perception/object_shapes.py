"""How big a detected object is, from depth: a cylinder or a box standing on the table.

The object's sides name its shape: the points under its top follow an arc for a cup and one or
two straight faces for a box (`outline_fit`). The footprint alone cannot: the head camera,
often only a little above the objects, sees less than half of a cup's round and a sliver of its
rim, and the smallest rectangle around such an arc is tighter than its circle (a cup read as a
box is grasped from above and may be carried on its side). With too few side points the
footprint decides: the smallest enclosing circle and rectangle (`cv2.minEnclosingCircle`,
`cv2.minAreaRect`), the tighter one. A cup's circle is its side's fit; a box is turned as its
faces are and spans all its points, the lid's included (the smallest rectangle around two
faces seen corner on lies along their diagonal: a 6.5 by 6.9 cm box read as 4.1 by 8.4 cm,
turned 34 degrees, and the gripper closed on its corner); one that shows a single face, its
lid unseen, is taken as deep as it is wide (ONE_FACE). The height runs from the table's top to
the highest point.
"""

from __future__ import annotations

import dataclasses
import math

import cv2
import numpy as np

from hsr_handover.interface.pinhole import PinholeCamera, checked_depth
from hsr_handover.robot.perception.object_detection import Detection
from hsr_handover.robot.perception.outline_fit import fit_circle, fit_rectangle

CYLINDER, BOX = "cylinder", "box"
MAX_OBJECT_RADIUS = 0.15
"""m: the farthest a point may lie (horizontally) from the detection's centre and belong to it:
a tabletop object a hand can grasp."""
ABOVE_TABLE = 0.005
"""m: points lower than this above the table's top are the table."""
MIN_POINTS = 10
SIDE_BELOW_TOP = 0.015
"""m: points this far under an object's highest are its side (nearer, the rim's or lid's edge)."""
MIN_SIDE_POINTS = 30
"""Side points that name a shape: fewer, and the footprint does."""
ONE_FACE = 0.015
"""m: a box read thinner than this across shows one face only, its lid unseen (a camera level
with the lid). Its depth is hidden behind that face: it is taken as deep as the face is wide,
behind it as the camera sees it. Read from its points alone, a 5.7 by 6.4 cm box was 1 mm
deep, its centre on its front face 3.7 cm from the true one, and the gripper, closing across
that millimetre, pushed the box out."""


@dataclasses.dataclass(frozen=True)
class ObjectShape:
    """A detected object as a solid standing on the table: `kind` CYLINDER or BOX, the
    footprint's centre (x, y), its size (m: the cylinder's diameter twice, or the box's sides
    along its yaw and across), the yaw (rad, 0 for a cylinder), the bottom (the table's top)
    and the height (m) above it."""

    label: str
    kind: str
    center: np.ndarray
    size: np.ndarray
    yaw: float
    bottom: float
    height: float

    @property
    def radius(self) -> float:
        """The radius (m) of the footprint's enclosing circle."""
        return float(np.hypot(*self.size) / 2) if self.kind == BOX else float(self.size[0] / 2)

    @property
    def centroid(self) -> np.ndarray:
        """The middle of the solid (x, y, z)."""
        return np.array([*self.center, self.bottom + self.height / 2])


def object_points(
    detection: Detection, depth: np.ndarray, camera: PinholeCamera, X_WC: np.ndarray,
    table_height: float,
) -> np.ndarray:  # fmt: skip
    """The world points (N, 3) of the detection's own pixels (its blob; its whole box when the
    blob is not known) in the depth image (H, W) (m) of the same capture that stand above the
    table's top and near the detection's centre. Only the object's own colour: over the whole
    box, a hand in front of a cup and beside it joins its footprint (a 7 cm cup read as a 16 cm
    box, and the gripper closes on nothing)."""
    depth = checked_depth(depth, camera)
    u0, v0, u1, v1 = detection.box
    window = depth[v0 : v1 + 1, u0 : u1 + 1]
    own = np.isfinite(window) & (window > 0)
    if detection.blob is not None:
        own &= detection.blob
    v, u = np.nonzero(own)
    pixels = np.column_stack([u + u0, v + v0]).astype(float)
    points = camera.deproject(pixels, window[v, u], X_WC)
    near = np.hypot(*(points[:, :2] - detection.center[:2]).T) <= MAX_OBJECT_RADIUS
    return points[near & (points[:, 2] > table_height + ABOVE_TABLE)]


def fit_shape(
    label: str, points: np.ndarray, table_height: float, viewpoint: np.ndarray | None = None
) -> ObjectShape | None:
    """The cylinder or box standing on a table whose top is at `table_height` that the points
    (N, 3) of one object show, seen by a camera at `viewpoint` (x, y; None: a box is only as
    deep as its points, see ONE_FACE); None with fewer than MIN_POINTS points."""
    if len(points) < MIN_POINTS:
        return None
    top = float(points[:, 2].max())
    height = top - table_height
    xy = points[:, :2].astype(np.float32)
    side = points[points[:, 2] < top - SIDE_BELOW_TOP, :2]
    if len(side) < MIN_SIDE_POINTS:
        shape = _tighter_footprint(label, xy, table_height, height)
    else:
        circle, rectangle = fit_circle(side), fit_rectangle(side)
        # a flat face is an arc of a huge circle: a round side is no wider than a graspable object
        if circle.radius <= MAX_OBJECT_RADIUS and circle.deviation < rectangle.deviation:
            return _cylinder(label, circle.center, circle.radius, table_height, height)
        shape = _box_along(label, xy, rectangle.yaw, table_height, height)
    if shape.kind != BOX or viewpoint is None:
        return shape
    return _deepened(shape, np.asarray(viewpoint, dtype=float))


def _tighter_footprint(
    label: str, xy: np.ndarray, table_height: float, height: float
) -> ObjectShape:
    center, radius = cv2.minEnclosingCircle(xy)
    _, sides, angle = cv2.minAreaRect(xy)
    if math.pi * radius**2 > np.prod(sides):
        return _box_along(label, xy, math.radians(angle), table_height, height)
    return _cylinder(label, np.array(center), radius, table_height, height)


def _cylinder(label: str, center, radius: float, table_height: float, height: float) -> ObjectShape:
    return ObjectShape(label, CYLINDER, np.asarray(center, dtype=float), np.full(2, 2 * radius),
                       0.0, table_height, height)  # fmt: skip


def _box_along(
    label: str, xy: np.ndarray, yaw: float, table_height: float, height: float
) -> ObjectShape:
    """The box turned `yaw` (its faces' orientation) around the points `xy` (N, 2): the
    smallest rectangle around two faces seen corner on lies along their diagonal."""
    axes = np.array([[math.cos(yaw), math.sin(yaw)], [-math.sin(yaw), math.cos(yaw)]])
    local = np.asarray(xy, dtype=float) @ axes.T
    low, high = local.min(axis=0), local.max(axis=0)
    return ObjectShape(label, BOX, (low + high) / 2 @ axes, high - low, yaw, table_height,
                       height)  # fmt: skip


def _deepened(shape: ObjectShape, viewpoint: np.ndarray) -> ObjectShape:
    """`shape`, a box; if it is thinner than ONE_FACE across, as deep as it is wide, the depth
    added on the far side of the face from `viewpoint` (x, y)."""
    thin = int(shape.size[1] < shape.size[0])
    if shape.size[thin] >= ONE_FACE:
        return shape
    across = np.array([math.cos(shape.yaw), math.sin(shape.yaw)])
    across = across if thin == 0 else np.array([-across[1], across[0]])
    away = across if across @ (shape.center - viewpoint) >= 0 else -across
    size = shape.size.copy()
    size[thin] = size[1 - thin]
    center = shape.center + away * (size[thin] - shape.size[thin]) / 2
    return dataclasses.replace(shape, center=center, size=size)


def measure_objects(
    detections, depth: np.ndarray, camera: PinholeCamera, X_WC: np.ndarray, table_height: float
) -> list[ObjectShape]:
    """The shape of each detection with a 3-D centre and enough depth on it; the others are
    left out (the planning scene cannot place them)."""
    shapes = []
    for detection in detections:
        if not np.all(np.isfinite(detection.center)):
            continue
        points = object_points(detection, depth, camera, X_WC, table_height)
        shape = fit_shape(detection.label, points, table_height, X_WC[:2, 3])
        if shape is not None:
            shapes.append(shape)
    return shapes

"""Grasp candidates for a perceived object: where the finger pads' centre
goes, along which direction the hand approaches, and across which axis the fingers close.

Cups are taken from the side, the fingers closing horizontally across the cup; boxes from the
top (fingers across the shorter side), from the side (fingers across a horizontal side that
fits), or, last, from above leaning away from the robot (`leaning`), which reaches a box a few
centimetres deeper in a high table than straight down does. Side approaches face away from the
robot, within +-60 degrees of the direction from the robot to the object, so the arm never
reaches round the object.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from hsr_handover.hsr import GRIPPER_MAX_OPENING
from hsr_handover.robot.perception.object_shapes import CYLINDER, ObjectShape

PAD_OFFSET = 0.05  # m, the finger pads' centre beyond the palm frame along its z (the SDF)
PREGRASP_STANDOFF = 0.10  # m the hand stands back along the approach before closing in
LIFT_HEIGHT = 0.10  # m the object is lifted straight up once held, before it is carried
GRIP_CLEARANCE = 0.03  # m of opening beyond the object's width, for the approach
SIDE_ANGLES_DEG = (0.0, -30.0, 30.0, -60.0, 60.0, -90.0, 90.0, -135.0, 135.0, 180.0)
GRIP_HEIGHT = 0.5  # of the object's height: where side grasps hold it, unless too low:
MIN_GRIP_HEIGHT = 0.07
"""m above the table: in a side grasp the hand reaches 3.2 cm below the pads' centre, the
planner keeps 2 cm from the table, and the pre-grasp needs room to spare."""
PAD_HALF_LENGTH = 0.015  # m: a side grasp's pads stay this far below an object's top
TOP_GRIP_DEPTH = 0.03  # m the pads reach below a box's lid
LEAN_DEG = (30.0, 45.0)
"""Tilts from straight down of the leaning grasps, about the closing axis. Straight down, the
arm reaches 4-6 cm short of a box 30 cm in from the near edge of a table 0.81 m high; leaning
30-45 degrees away it reaches it. Further over, the palm sinks to the lid (`_lid_depth`)."""


@dataclasses.dataclass(frozen=True)
class Grasp:
    """A grasp of `label`: the pads' centre `point` (world, m), the unit `approach` (the palm's
    z), the unit `closing` axis (the palm's y, along which the fingers close), the `opening`
    (m between the fingertips) for the approach, the object's `width` across the fingers, and
    how far back along the approach the hand waits before closing in (`standoff`, m)."""

    label: str
    kind: str
    point: np.ndarray
    approach: np.ndarray
    closing: np.ndarray
    opening: float
    width: float
    standoff: float = PREGRASP_STANDOFF

    @property
    def pregrasp_point(self) -> np.ndarray:
        """Where the pads' centre waits before closing in (m, world)."""
        return self.point - self.standoff * self.approach

    @property
    def lifted_point(self) -> np.ndarray:
        """Where the pads' centre holds the object once lifted off the table (m, world)."""
        return self.point + np.array([0.0, 0.0, LIFT_HEIGHT])


def _horizontal(angle: float) -> np.ndarray:
    return np.array([math.cos(angle), math.sin(angle), 0.0])


def _grasp(
    shape: ObjectShape, kind: str, point, approach, closing, width: float,
    standoff: float = PREGRASP_STANDOFF,
) -> Grasp:  # fmt: skip
    opening = min(width + GRIP_CLEARANCE, GRIPPER_MAX_OPENING)
    return Grasp(shape.label, kind, np.asarray(point, float), approach, closing, opening, width,
                 standoff)  # fmt: skip


def grasp_candidates(shape: ObjectShape, robot_xy: np.ndarray) -> list[Grasp]:
    """The grasps of `shape` that the gripper's opening allows, best first, for a robot
    standing at `robot_xy` (m, world)."""
    center = np.asarray(shape.center, dtype=float)
    heading = math.atan2(*(center - np.asarray(robot_xy, dtype=float))[::-1])
    grip = max(GRIP_HEIGHT * shape.height, MIN_GRIP_HEIGHT)
    grip_z = shape.bottom + min(grip, shape.height - PAD_HALF_LENGTH)
    side_point = np.array([*center, grip_z])
    up = np.array([0.0, 0.0, 1.0])
    if shape.kind == CYLINDER:
        return [
            _grasp(shape, "side", side_point, _horizontal(heading + math.radians(a)),
                   np.cross(up, _horizontal(heading + math.radians(a))), shape.size[0])
            for a in SIDE_ANGLES_DEG
        ]  # fmt: skip
    return _box_grasps(shape, heading, side_point)


def _box_grasps(shape: ObjectShape, heading: float, side_point: np.ndarray) -> list[Grasp]:
    """A top grasp across the shorter side, then side grasps on the faces, nearest the robot's
    heading first, the fingers across the horizontal side that fits."""
    axes = (_horizontal(shape.yaw), _horizontal(shape.yaw + math.pi / 2))
    short = int(shape.size[1] < shape.size[0])
    grasps = []
    if shape.size[short] + GRIP_CLEARANCE <= GRIPPER_MAX_OPENING:
        top = np.array([*shape.center, shape.bottom + shape.height - TOP_GRIP_DEPTH])
        grasps.append(_grasp(shape, "top", top, np.array([0.0, 0, -1]), axes[short],
                             shape.size[short]))  # fmt: skip
    faces = []
    for i, axis in enumerate(axes):
        for sign in (1.0, -1.0):
            approach = sign * axis
            turn = math.acos(np.clip(approach[:2] @ _horizontal(heading)[:2], -1, 1))
            width = shape.size[1 - i]
            if width + GRIP_CLEARANCE <= GRIPPER_MAX_OPENING:
                faces.append((turn, approach, axes[1 - i], width))
    for _, approach, closing, width in sorted(faces, key=lambda face: face[0]):
        grasps.append(_grasp(shape, "side", side_point, approach, closing, width))
    return grasps + _leaning_grasps(shape, heading, axes)


def _leaning_grasps(shape: ObjectShape, heading: float, axes) -> list[Grasp]:
    """Grasps from above leaning LEAN_DEG away from the robot about the closing axis, which
    stays horizontal, so the pads still meet two upright faces square on: across the shorter
    side first, the least lean first."""
    away = _horizontal(heading)
    grasps = []
    for i in sorted(range(2), key=lambda i: shape.size[i]):
        width = shape.size[i]
        if width + GRIP_CLEARANCE > GRIPPER_MAX_OPENING:
            continue
        lean = axes[1 - i] * (1.0 if axes[1 - i] @ away >= 0 else -1.0)
        for tilt in np.radians(LEAN_DEG):
            approach = math.sin(tilt) * lean - math.cos(tilt) * np.array([0.0, 0, 1])
            point = np.array([*shape.center, shape.bottom + shape.height - _lid_depth(tilt)])
            # Backed off along the lean, the tilted pads' lower corners clear the lid by less.
            standoff = PREGRASP_STANDOFF / math.cos(tilt)
            grasps.append(_grasp(shape, "leaning", point, approach, axes[i], width, standoff))
    return grasps


def _lid_depth(tilt: float) -> float:
    """m the pads' centre goes below the lid with the hand tilted `tilt` (rad) from straight
    down: the palm stays as high over the lid as in the top grasp (the target is ignored by the
    planner, so nothing else keeps the palm off it)."""
    return PAD_OFFSET * math.cos(tilt) - (PAD_OFFSET - TOP_GRIP_DEPTH)

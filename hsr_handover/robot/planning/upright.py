"""A held object keeps its top up. A cup is carried, held out and followed with the hand no more
than CUP_TILT from how it stood; a box may lie on its side (a box grasped from above is held out
with the hand level: 90 degrees) but is never turned over. Without this the hand's closing axis,
free in sign, let inverse kinematics hold a cup out upside down, and a carry between two upright
ends could swing it over on the way."""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING

import numpy as np

from hsr_handover.robot.perception.object_shapes import CYLINDER, ObjectShape

if TYPE_CHECKING:
    from hsr_handover.robot.planning.planning_scene import PlanningScene

WRIST_ROLL = "wrist_roll_joint"  # turns the hand about its approach
CUP_TILT = math.radians(20.0)
"""The most a held cup tilts: a 10 cm cup filled to 1.5 cm under its rim spills past about 23
degrees."""
BOX_TILT = math.radians(100.0)
"""The most a held box tilts: on its side, with the 5 degrees the hand's axes may be off."""
SLACK = math.radians(2.0)
"""How far a path may tilt past a bound that its own start or goal already reaches."""


@dataclasses.dataclass(frozen=True)
class Upright:
    """A held object's up axis in the hand body's frame (`up_in_hand`, unit) and the most it
    may tilt from the world's vertical (`most`, rad)."""

    up_in_hand: np.ndarray
    most: float


def upright_for(shape: ObjectShape, R_WH: np.ndarray) -> Upright:
    """The `Upright` of the object `shape`, standing when grasped by a hand body turned
    `R_WH` (3x3) in the world."""
    up = np.asarray(R_WH, dtype=float).T @ np.array([0.0, 0.0, 1.0])
    return Upright(up, CUP_TILT if shape.kind == CYLINDER else BOX_TILT)


def tilt_from(R_WH: np.ndarray, up_in_hand: np.ndarray) -> float:
    """The tilt (rad) from the world's vertical of the axis `up_in_hand` of a hand body turned
    `R_WH` (3x3) in the world."""
    up = np.asarray(R_WH, dtype=float) @ up_in_hand
    return math.acos(float(np.clip(up[2], -1.0, 1.0)))


def tilt(scene: PlanningScene, q: np.ndarray) -> float:
    """The held object's tilt (rad) from upright with the HSR at `q`; 0 when nothing is held."""
    if scene.upright is None:
        return 0.0
    return tilt_from(scene.hand_pose(q).rotation().matrix(), scene.upright.up_in_hand)


def path_bound(scene: PlanningScene, q_from: np.ndarray, q_to: np.ndarray) -> float:
    """The most (rad) a path from `q_from` to `q_to` may tilt the held object: its `most`, or,
    when an end already tilts it further (a goal not made to keep it up, as the stowed arm),
    that end's tilt and SLACK."""
    if scene.upright is None:
        return math.pi
    ends = max(tilt(scene, q_from), tilt(scene, q_to))
    return scene.upright.most if ends <= scene.upright.most else ends + SLACK


def turned_up(scene: PlanningScene, seed: np.ndarray) -> np.ndarray:
    """`seed` with the wrist rolled by a half turn either way (within its limits) when that
    holds the object less tilted: a seed on the hand's other turn, whose closing axis is as
    good, left SNOPT no way to the object kept up."""
    if scene.upright is None:
        return seed
    roll = scene.index(WRIST_ROLL)
    low = scene.plant.GetPositionLowerLimits()[roll]
    high = scene.plant.GetPositionUpperLimits()[roll]
    turns = []
    for half in (0.0, math.pi, -math.pi):
        turned = seed.copy()
        turned[roll] += half
        if low <= turned[roll] <= high:
            turns.append(turned)
    return min(turns, key=lambda q: tilt(scene, q))


def keeps_upright(scene: PlanningScene, positions, slack: float = 0.0) -> bool:
    """Whether the held object tilts no more than its `path_bound` (and `slack`, rad) at each
    of a path's `positions` (n, nq; its ends first and last)."""
    if scene.upright is None:
        return True
    bound = path_bound(scene, positions[0], positions[-1]) + slack
    return all(tilt(scene, q) <= bound for q in positions)


def path_keeps_upright(scene: PlanningScene, path, samples: int, slack: float = 0.0) -> bool:
    """`keeps_upright` at `samples` evenly spaced times along a path (`value(t)`,
    `start_time()`, `end_time()`), sampled only when an object is held."""
    if scene.upright is None:
        return True
    times = np.linspace(path.start_time(), path.end_time(), samples)
    return keeps_upright(scene, [path.value(t).ravel() for t in times], slack)

"""A pointing arm held clear of the objects: a person points at a thing within reach from above
it, they do not lay their hand on it, and they draw the hand back before lowering the arm when
lowering it straight would sweep the hand through one.

A 1.81 m person's straight arm aimed at a box's middle 0.8 m away ends on its top edge: the
hand pushes it over during the gesture and rests beside it, and the robot cannot grasp it. An
arm that points clear of the objects can still sweep its hand through one on its way back to
rest (the hand's axis 0.5 cm from it)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from hsr_handover.world.person.aiming import arm_move_points, pointing_arm_angles
from hsr_handover.world.person.body import HAND_WIDTH, BodyDimensions

POINT_CLEAR = HAND_WIDTH / 2 + 0.02
"""m from the pointing hand's axis to any object: half the hand's width and 2 cm."""
RAISE_STEP = math.radians(1.0)  # rad the arm is raised by at a time
MAX_RAISE = math.radians(30.0)  # rad: no higher; an arm that still does not clear stays aimed
_HAND_SAMPLES = 11  # points along the hand, wrist to fingertips
_LOWER_SAMPLES = 21  # arm poses checked along the move back to rest


@dataclasses.dataclass(frozen=True)
class Upright:
    """An object standing on the table as the vertical cylinder round it: its axis at `xy`
    (m, in the frame the arm is aimed in), `radius` (m), from `bottom` to `top` (m)."""

    xy: np.ndarray
    radius: float
    bottom: float
    top: float

    def distance(self, points: np.ndarray) -> np.ndarray:
        """Distance (m) from each point (N, 3) to the cylinder (0 inside)."""
        sideways = np.maximum(np.linalg.norm(points[:, :2] - self.xy, axis=1) - self.radius, 0)
        up = np.maximum(np.maximum(points[:, 2] - self.top, self.bottom - points[:, 2]), 0)
        return np.hypot(sideways, up)


def hand_clearance(
    body: BodyDimensions, shoulder: np.ndarray, direction: np.ndarray, objects: list[Upright]
) -> float:
    """The least distance (m) from the axis of a straight arm's hand, the arm along the unit
    `direction` from `shoulder`, to the `objects` (inf without any)."""
    along = body.upper_arm + body.forearm + np.linspace(0.0, body.hand, _HAND_SAMPLES)
    hand = shoulder + along[:, None] * direction
    return _least_distance(hand, objects)


def clear_aim(
    body: BodyDimensions, side: str, aim: np.ndarray, objects: list[Upright]
) -> np.ndarray:
    """Where the straight arm on `side` points instead of `aim` (person frame) so that its hand
    clears the `objects` by POINT_CLEAR: the same point raised about the shoulder, RAISE_STEP
    at a time, up to MAX_RAISE; `aim` itself when it clears already or nothing does."""
    aim = np.asarray(aim, dtype=float)
    shoulder = body.shoulder(side)
    offset = aim - shoulder
    reach = float(np.linalg.norm(offset))
    heading = math.atan2(offset[1], offset[0])
    elevation = math.asin(float(np.clip(offset[2] / max(reach, 1e-9), -1.0, 1.0)))
    for step in range(round(MAX_RAISE / RAISE_STEP) + 1):
        up = elevation + step * RAISE_STEP
        direction = np.array([math.cos(up) * math.cos(heading),
                              math.cos(up) * math.sin(heading), math.sin(up)])  # fmt: skip
        if hand_clearance(body, shoulder, direction, objects) >= POINT_CLEAR:
            return aim if step == 0 else shoulder + reach * direction
    return aim


def lowering_clearance(
    body: BodyDimensions, side: str, aim: np.ndarray, rest: np.ndarray, objects: list[Upright]
) -> float:
    """The least distance (m) from the hand's axis to the `objects` (inf without any) as the
    straight arm on `side` aimed at `aim` goes back to the `rest` arm angles: a straight line
    in joint space, as the actor moves."""
    start = pointing_arm_angles(np.asarray(aim, dtype=float) - body.shoulder(side))
    poses = arm_move_points(body, side, start, rest, _LOWER_SAMPLES)
    hands = [np.linspace(joints["wrist"], joints["tips"], _HAND_SAMPLES) for joints in poses]
    return _least_distance(np.concatenate(hands), objects)


def _least_distance(points: np.ndarray, objects: list[Upright]) -> float:
    return min((float(obj.distance(points).min()) for obj in objects), default=math.inf)

"""Where robot and person both reach (paper 3.3, fig. 14's red nodes) and the handover point in
it.

The rule for the handover point: in front of the receiver (Koay et al. 2007: seated people
prefer being approached and handed things from the front), in reach without stretching: the
point straight ahead of the receiving shoulder, COMFORT_PITCH_DEG below level, at COMFORT_REACH
of the arm's full reach, the elbow bent as in a relaxed reach (Cakmak et al. 2011: receivers
prefer the poses they would choose themselves; the 70 % and 20 degrees are this project's
choice within that). The point handed over at is the mutual-area node nearest that ideal, at
least ABOVE_TABLE over the table's top, AWAY_FROM_BODY from the body's capsules and within
MOST_REACH of the arm's full reach (a person does not take things at full stretch). Where the
robot cannot stand to hand over in front (a person standing behind a table), the same point
turned toward the receiving arm's side by SIDE_TURNS_DEG is the next aim: handed from the side,
as people hand things to someone beside them.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from hsr_handover.robot.effectivity.person_map import HumanArm, PersonEffectivity

COMFORT_REACH = 0.7  # of the arm's full reach
COMFORT_PITCH_DEG = -20.0  # below the shoulder's level
ABOVE_TABLE = 0.15  # m over the table's top: an object held and the hands around it
AWAY_FROM_BODY = 0.10  # m from the body's capsules' surface
MOST_REACH = 0.9
"""of the arm's full reach: the farthest from the shoulder a handover point may be. The range's
edge is the arm at full stretch, and the perceived arm's lengths and shoulder are a few cm off
(a cup held at 0.89 of the perceived reach can end 8 mm beyond the person's)."""
SIDE_TURNS_DEG = (0.0, 30.0, 60.0)  # the aims, turned from straight ahead toward the arm's side


def ideal_handover_point(arm: HumanArm, side_turn_deg: float = 0.0) -> np.ndarray:
    """The rule's ideal point (world, m) for the receiving arm, turned about the shoulder by
    `side_turn_deg` toward the arm's own side (the right arm's right)."""
    pitch = math.radians(COMFORT_PITCH_DEG)
    turn = math.radians(side_turn_deg) * (-1.0 if arm.side == "r" else 1.0)
    local = [math.cos(pitch) * math.cos(turn), math.cos(pitch) * math.sin(turn), math.sin(pitch)]
    return arm.shoulder + COMFORT_REACH * arm.reach * (arm.frame @ np.array(local))


def within_reach(arm: HumanArm, points: np.ndarray, reach: float | None = None) -> np.ndarray:
    """Whether each point (n, 3, world) is within `reach` (m; default MOST_REACH of the arm's
    full reach: near enough to be handed over at) of the arm's shoulder."""
    reach = MOST_REACH * arm.reach if reach is None else reach
    return np.linalg.norm(np.reshape(points, (-1, 3)) - arm.shoulder, axis=1) <= reach


def handover_aims(arm: HumanArm) -> list[np.ndarray]:
    """The ideal point straight ahead, then turned toward the arm's side by SIDE_TURNS_DEG."""
    return [ideal_handover_point(arm, turn) for turn in SIDE_TURNS_DEG]


def mutual_mask(robot_nodes: np.ndarray, person: PersonEffectivity) -> np.ndarray:
    """Which robot nodes (n, 3, world) the person reaches too: the mutual area."""
    return person.reachable(robot_nodes)


def handover_point(
    robot_nodes: np.ndarray,
    person: PersonEffectivity,
    table_height: float | None,
    body: Sequence = (),
    aim: np.ndarray | None = None,
) -> tuple[np.ndarray | None, np.ndarray]:
    """The handover point (world, m; None when the areas do not meet or no node suits): the
    suitable mutual node nearest `aim` (the ideal point when None); and the mutual mask over
    `robot_nodes` (n, 3, world). `body` holds capsules with `distance(points)`."""
    mutual = mutual_mask(robot_nodes, person)
    arm = person.arm
    suitable = mutual & within_reach(arm, robot_nodes)
    if table_height is not None:
        suitable &= robot_nodes[:, 2] >= table_height + ABOVE_TABLE
    for capsule in body:
        suitable &= capsule.distance(robot_nodes) >= AWAY_FROM_BODY
    if not suitable.any():
        return None, mutual
    aim = ideal_handover_point(arm) if aim is None else aim
    candidates = np.flatnonzero(suitable)
    best = candidates[np.argmin(np.linalg.norm(robot_nodes[candidates] - aim, axis=1))]
    return robot_nodes[best].copy(), mutual

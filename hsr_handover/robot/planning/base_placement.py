"""Where the base stands for a grasp, and the arm's first guess there.

The arm reaches forward in the vertical plane y = 0.078 m of the base frame (its flex joint's
offset), so for a hand pointing along the approach the base faces the approach and stands a
reach `d` behind the palm. Each reach the arm's effectivity map holds at the palm's height is
a candidate; those whose base (arm folded up) stays clear of the table, the objects and the
person are tried, the reach nearest PREFERRED_REACH first. A vertical approach leaves the
base's heading free: it faces the object from where the robot stands, or, `turned`, stands
round it (ROUND_TURNS_DEG), which reaches an object deep in a table from the table's nearer
side (a box 35 cm in from the near edge and 8 cm from the side is out of reach from the near
side). The arm's seed is eq. 11's walk on
the map for the palm's position; the map knows positions only, so the hand's orientation is
then the grasp's: no roll, the wrist flexed to the approach's pitch, the wrist rolled to the
closing axis.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from hsr_handover.hsr import ARM_JOINTS, BASE_JOINTS, BASE_RADIUS, TORSO_JOINT
from hsr_handover.kinematics import hsr_arm
from hsr_handover.kinematics.hsr_arm import ARM_FLEX_ORIGIN
from hsr_handover.robot.effectivity.arm_map import ArmEffectivity
from hsr_handover.robot.planning.grasps import PAD_OFFSET
from hsr_handover.robot.planning.planning_scene import TABLE, TABLE_MARGIN, PlanningScene

REACHES = np.arange(0.30, 0.66, 0.025)  # m, palm ahead of the base centre, the candidates
PREFERRED_REACH = 0.47  # m: the arm about level, far from its limits
BASE_CLEARANCE = 0.04  # m the folded-up robot keeps from every obstacle where it stands
MAX_CANDIDATES = 4
BASE_DISC_RADIUS = BASE_RADIUS - 0.003
"""m: a hair inside the HSR's base disc (it is below any table the fit accepts). A base whose
centre is nearer the perceived table's block (floor to top) than this plus BASE_CLEARANCE
cannot keep BASE_CLEARANCE from it (`_in_table`)."""
ROUND_TURNS_DEG = (90.0, -90.0, 45.0, -45.0, 135.0, -135.0, 180.0)
"""Headings a turned base tries for a vertical approach, from facing the object as it does
from where the robot stands: square to that first (beside a table the robot faces), then
halfway, then from beyond the object."""
VERTICAL = 0.75
"""An approach whose horizontal part is shorter than this (within 48 degrees of straight down:
the top and leaning grasps) leaves the base's heading free."""


@dataclasses.dataclass(frozen=True)
class BasePlacement:
    """A full configuration `q` (plant positions) with the base at a candidate pose and the arm
    at its seed; `reach` (m) of the palm ahead of the base."""

    q: np.ndarray
    reach: float


def base_yaws(approach: np.ndarray, toward: np.ndarray, turned: bool = False) -> list[float]:
    """The base faces a horizontal approach; for a vertical one, the object from `toward`
    (the vector from the robot to the object), or, `turned`, from round it. A turned base for
    a horizontal approach has no heading to try."""
    vertical = np.hypot(*approach[:2]) <= VERTICAL
    horizontal = toward[:2] if vertical else approach[:2]
    yaw = math.atan2(horizontal[1], horizontal[0])
    if not turned:
        return [yaw]
    return [yaw + math.radians(turn) for turn in ROUND_TURNS_DEG] if vertical else []


def base_pose(palm: np.ndarray, yaw: float, reach: float) -> np.ndarray:
    """(x, y) of the base that puts the arm's plane through `palm` at `reach` ahead."""
    c, s = math.cos(yaw), math.sin(yaw)
    offset = np.array([reach, ARM_FLEX_ORIGIN[1]])
    return palm[:2] - np.array([[c, -s], [s, c]]) @ offset


def hand_posture(arm: np.ndarray, approach_local: np.ndarray, closing_local: np.ndarray):
    """The arm seed (5,) with the hand's orientation set: arm roll 0, the wrist flexed so the
    palm's z points along `approach_local` (base frame), the wrist rolled so its y lies along
    `closing_local` (either sign)."""
    arm = arm.copy()
    pitch = math.atan2(np.hypot(*approach_local[:2]), approach_local[2])  # from straight up
    arm[2] = 0.0
    arm[3] = -pitch - arm[1]
    # With no roll the palm's y is the base's -y; rolling the wrist turns it in the hand's plane.
    roll = math.atan2(-closing_local[0], -closing_local[1]) if pitch > 3 * math.pi / 4 else 0.0
    arm[4] = (roll + math.pi / 2) % math.pi - math.pi / 2
    return np.clip(arm, hsr_arm.ARM_LOWER, hsr_arm.ARM_UPPER)


def place_base(
    scene: PlanningScene,
    arm_map: ArmEffectivity | None,
    point: np.ndarray,
    approach: np.ndarray,
    closing: np.ndarray,
    q_now: np.ndarray,
    ignore: tuple[str, ...] = (),
    most: int = MAX_CANDIDATES,
    turned: bool = False,
) -> list[BasePlacement]:
    """At most `most` base poses and arm seeds for putting the pads' centre at `point` along
    `approach`, best first, clear of all but `ignore` (an object held); `turned`, those round
    the object a vertical approach allows (`base_yaws`), none for a horizontal one. With no
    map (the unseeded baseline) there is one candidate per heading at PREFERRED_REACH with the
    arm as it is now."""
    palm = np.asarray(point, float) - PAD_OFFSET * np.asarray(approach, float)
    robot_xy = q_now[[scene.index(BASE_JOINTS[0]), scene.index(BASE_JOINTS[1])]]
    reaches, palms = _mapped_reaches(arm_map, palm[2])
    placements = []
    for yaw in base_yaws(approach, palm - np.array([*robot_xy, palm[2]]), turned):
        to_base = np.array([[math.cos(yaw), math.sin(yaw), 0],
                            [-math.sin(yaw), math.cos(yaw), 0], [0, 0, 1]])  # fmt: skip
        for reach, local in zip(reaches, palms, strict=True):
            q = _at_base(scene, q_now, base_pose(palm, yaw, reach), yaw)
            if not _folded_clear(scene, q, ignore):
                continue
            if arm_map is not None:
                seed = arm_map.seed(local[None])[0]
                _set_arm(scene, q, hand_posture(seed, to_base @ approach, to_base @ closing))
            placements.append(BasePlacement(q, float(reach)))
            if len(placements) == most:
                return placements
    return placements


def _mapped_reaches(arm_map: ArmEffectivity | None, height: float):
    """The candidate reaches (m) nearest PREFERRED_REACH first, those the map holds at the
    palm's `height`, and the palm at each in the base frame (n, 3): the map asked once for
    them all, as one at a time it cost more than the clearance queries. Without a map,
    PREFERRED_REACH alone."""
    reaches = np.array([PREFERRED_REACH] if arm_map is None else sorted(
        REACHES, key=lambda reach: abs(reach - PREFERRED_REACH)))  # fmt: skip
    palms = np.column_stack([reaches, np.full(len(reaches), ARM_FLEX_ORIGIN[1]),
                             np.full(len(reaches), height)])  # fmt: skip
    if arm_map is None:
        return reaches, palms
    mapped = arm_map.reachable(palms)
    return reaches[mapped], palms[mapped]


def _at_base(scene: PlanningScene, q_now: np.ndarray, xy: np.ndarray, yaw: float) -> np.ndarray:
    q = q_now.copy()
    for joint, value in zip(BASE_JOINTS, (*xy, yaw), strict=True):
        q[scene.index(joint)] = value
    return q


def with_arm(scene: PlanningScene, q: np.ndarray, arm: np.ndarray) -> np.ndarray:
    """A copy of `q` with the arm's joints (ARM_JOINTS order) at `arm`, the torso coupled."""
    q = q.copy()
    _set_arm(scene, q, arm)
    return q


def _set_arm(scene: PlanningScene, q: np.ndarray, arm: np.ndarray) -> None:
    for joint, value in zip(ARM_JOINTS, arm, strict=True):
        q[scene.index(joint)] = value
    q[scene.index(TORSO_JOINT)] = 0.5 * arm[0]


def _folded_clear(scene: PlanningScene, q: np.ndarray, ignore: tuple[str, ...]) -> bool:
    """Whether the robot at q's base with the arm folded keeps BASE_CLEARANCE from everything:
    asked only within that distance, as most candidates are not clear (a handover pose
    tries about 150) and a query of all within NEAR cost several times as much."""
    if _in_table(scene, q, ignore):
        return False
    folded = _folded(scene, q)
    return scene.clearance_at(folded, ignore, within=BASE_CLEARANCE) >= BASE_CLEARANCE


def _in_table(scene: PlanningScene, q: np.ndarray, ignore: tuple[str, ...]) -> bool:
    """Whether the base disc at q's x, y comes within BASE_CLEARANCE of the table's block (the
    block rising above the disc, the table not ignored): then no distance query is needed to
    rule it out. Most of a handover pose's candidates stand in the table behind the seated
    person, and a query that finds the robot inside the table costs the most."""
    table = scene.scene.table
    if table is None or TABLE in ignore:
        return False
    xy = q[[scene.index(BASE_JOINTS[0]), scene.index(BASE_JOINTS[1])]]
    outside = np.maximum(np.abs(table.to_local(xy)) - (table.size / 2 + TABLE_MARGIN), 0.0)
    return float(np.hypot(*outside)) < BASE_DISC_RADIUS + BASE_CLEARANCE


def _folded(scene: PlanningScene, q: np.ndarray) -> np.ndarray:
    folded = q.copy()
    _set_arm(scene, folded, np.zeros(len(ARM_JOINTS)))
    return folded

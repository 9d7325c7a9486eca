"""What the robot plans around, as it perceives it: the table's top, the objects on it, and
the person as capsules around the lifted skeleton's bones.

A lifted keypoint lies on the body's surface that faces the camera, so each bone's axis is put
a limb's radius behind its keypoints, along the camera's line of sight; every capsule is then
widened by a margin for the skeleton's error. COCO-18 has no hands: each forearm's capsule runs
on past the wrist so that its surface, before the margin, ends at the fingertips. What the
camera cannot see (the back, the seat, the legs under the table) is a column from the floor to
the neck. An elbow hidden while its shoulder and wrist are seen is put where an arm of the
body's proportions would have it (`hidden_elbow`): without it the arm would be missing from
the scene.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.robot.effectivity.person_map import perceived_arm
from hsr_handover.robot.perception.depth_view import DepthView
from hsr_handover.robot.perception.object_shapes import ObjectShape
from hsr_handover.robot.perception.table_fit import TableEstimate

HAND_LENGTH = 0.2
"""m, wrist to fingertips: a large adult hand (a man's averages 19 cm)."""
PERSON_MARGIN = 0.05
"""m added to every capsule: the lifted skeleton is off by a few cm."""
UNSEEN_EXTENSION = 0.5  # m a table's top may run on past the edge of the camera's view
ROBOT_KEEP = 0.45  # m: an unseen table is never assumed nearer than this to the camera
OVER_TABLE_EDGE = 0.03
"""m past the table's outline, and below its top, that a lifted point still counts as on it: a
keypoint's pixel on the top's far edge is lifted onto the edge's face (the lifting takes the
nearest quarter of its window), and the depth there errs by a centimetre or two."""
BODY_COLUMN_RADIUS = 0.3
"""m: a person's body and seat seen from above (a chair's seat is about 45 cm square, the
trunk about 35 cm deep); the column also stands for legs and back the camera does not see."""

# Bone radii (m), adult anthropometry rounded up (upper arm and forearm girths of about 30 and
# 26 cm, thigh 55 cm, calf 37 cm; the head's breadth about 15 cm; the chest's depth about 24 cm).
_BONES = {
    ("neck", "r_shoulder"): 0.06, ("neck", "l_shoulder"): 0.06,
    ("r_shoulder", "r_elbow"): 0.05, ("l_shoulder", "l_elbow"): 0.05,
    ("r_elbow", "r_wrist"): 0.045, ("l_elbow", "l_wrist"): 0.045,
    ("neck", "r_hip"): 0.12, ("neck", "l_hip"): 0.12,
    ("r_hip", "r_knee"): 0.09, ("l_hip", "l_knee"): 0.09,
    ("r_knee", "r_ankle"): 0.06, ("l_knee", "l_ankle"): 0.06,
    ("neck", "nose"): 0.1,
}  # fmt: skip
BONES = {(keypoint_index(a), keypoint_index(b)): radius for (a, b), radius in _BONES.items()}
_BONE_NAMES = {(keypoint_index(a), keypoint_index(b)): f"{a}-{b}" for a, b in _BONES}
BODY_PART = "body"  # the column for what the camera does not see of the person
_ELBOWS = {keypoint_index("r_elbow"), keypoint_index("l_elbow")}
ARM_PARTS = frozenset(name for bone, name in _BONE_NAMES.items() if _ELBOWS & set(bone))
"""The upper arms and forearms: the parts of a seated person that move."""
_WRISTS = (keypoint_index("r_wrist"), keypoint_index("l_wrist"))
LOWER_BODY = tuple(
    keypoint_index(f"{side}_{joint}") for side in "rl" for joint in ("hip", "knee", "ankle")
)
_ARM = ("shoulder", "elbow", "wrist")


@dataclasses.dataclass(frozen=True)
class Capsule:
    """A segment from `start` to `end` (m, world) swept by a sphere of `radius` (m), around
    the `part` of the person it stands for (a bone, "neck-r_shoulder", or BODY_PART), as seen
    at time `seen_at` (s; NaN when not said)."""

    start: np.ndarray
    end: np.ndarray
    radius: float
    part: str = ""
    seen_at: float = math.nan

    @property
    def length(self) -> float:
        return float(np.linalg.norm(self.end - self.start))

    def distance(self, points: np.ndarray) -> np.ndarray:
        """Distance (m) from each point (N, 3) to the capsule's surface (negative inside)."""
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        axis = self.end - self.start
        t = np.clip((points - self.start) @ axis / max(float(axis @ axis), 1e-12), 0.0, 1.0)
        nearest = self.start + t[:, None] * axis
        return np.linalg.norm(points - nearest, axis=1) - self.radius


def person_capsules(
    points: np.ndarray,
    confidence: np.ndarray,
    camera_position: np.ndarray,
    margin: float = PERSON_MARGIN,
    seen_at: float = math.nan,
    table: TableEstimate | None = None,
) -> tuple[Capsule, ...]:
    """Capsules around the bones of a lifted COCO-18 skeleton (18 x 3 points, 18 confidences)
    whose two keypoints were seen, seen from `camera_position` (3,) at time `seen_at` (s);
    with the perceived `table`, a lower-body keypoint lifted over its top is not seen."""
    points = np.array(points, dtype=float)
    seen = (np.asarray(confidence) > 0) & np.isfinite(points).all(axis=1)
    if table is not None:
        lower = np.array(LOWER_BODY)
        seen[lower] &= ~over_table(points[lower], table)
    for side in ("r", "l"):
        shoulder, elbow, wrist = (keypoint_index(f"{side}_{joint}") for joint in _ARM)
        if not (seen[shoulder] and seen[wrist]) or seen[elbow]:
            continue
        arm = perceived_arm(points, confidence, side)  # None without both shoulders
        if arm is not None:
            points[elbow] = hidden_elbow(points[shoulder], points[wrist], arm.upper, arm.forearm)
            seen[elbow] = True
    capsules = []
    for (a, b), radius in BONES.items():
        if not (seen[a] and seen[b]):
            continue
        start, end = (behind(points[i], camera_position, radius) for i in (a, b))
        if b in _WRISTS:  # the axis ends a radius short: the capsule's round end is the hand's
            forearm = end - start
            end = end + (HAND_LENGTH - radius) * forearm / max(np.linalg.norm(forearm), 1e-9)
        capsules.append(Capsule(start, end, radius + margin, _BONE_NAMES[a, b], seen_at))
    column = _body_column(points, seen, camera_position, margin, seen_at)
    return tuple(capsules) + column


def over_table(points: np.ndarray, table: TableEstimate) -> np.ndarray:
    """(N,) bool: which points (N, 3; m, world) lie over the `table`'s top, its outline
    widened by OVER_TABLE_EDGE and its top lowered by as much. A seated person's hips are
    below the top and a standing person's stand clear of its edge; a hip lifted over it is
    the top's far edge or an object seen in front of the body at the hip's pixel (a seated
    person's hip just visible over the table's edge, its pixel a few off), and would draw a
    torso across the table that no grasp may pass."""
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    local = np.abs(table.to_local(points[:, :2]))
    inside = np.all(local <= table.size / 2 + OVER_TABLE_EDGE, axis=1)
    return inside & (points[:, 2] >= table.height - OVER_TABLE_EDGE)


def hidden_elbow(
    shoulder: np.ndarray, wrist: np.ndarray, upper: float, forearm: float
) -> np.ndarray:
    """Where the elbow of an arm with segments `upper` and `forearm` (m) is, given its
    `shoulder` and `wrist` (m, world): on the circle of elbows that join the two, at its lowest
    point (an arm hangs from the shoulder); on the line between them, in proportion, if the
    two lie as far apart as the arm is long or farther.

    Without it an arm whose elbow the robot's own arm hides would drop out of the live view and
    be planned around where it was last seen whole (`remember`), though it has moved since.
    """
    axis = wrist - shoulder
    span = float(np.linalg.norm(axis))
    if span >= upper + forearm or span < 1e-9:
        return shoulder + upper / (upper + forearm) * axis
    along = np.clip((upper**2 - forearm**2 + span**2) / (2 * span), -upper, upper)
    axis /= span
    down = np.array([0.0, 0.0, -1.0])
    down -= (down @ axis) * axis
    if np.linalg.norm(down) < 1e-9:  # a vertical arm: its elbow on the line
        return shoulder + along * axis
    return shoulder + along * axis + np.sqrt(upper**2 - along**2) * down / np.linalg.norm(down)


def _body_column(
    points, seen, camera_position, margin: float, seen_at: float
) -> tuple[Capsule, ...]:
    """What the camera cannot see of a person, down to the floor: the back, a seat, legs
    under the table. A vertical capsule BODY_COLUMN_RADIUS round the neck, set back by the
    radius, from the floor to the neck."""
    neck = keypoint_index("neck")
    if not seen[neck]:
        return ()
    sight = (points[neck] - camera_position) * np.array([1.0, 1.0, 0.0])  # set back level
    center = points[neck] + BODY_COLUMN_RADIUS * sight / max(np.linalg.norm(sight), 1e-9)
    radius = BODY_COLUMN_RADIUS + margin
    bottom = np.array([center[0], center[1], radius])
    top = np.array([center[0], center[1], max(points[neck][2], 2 * radius)])
    return (Capsule(bottom, top, radius, BODY_PART, seen_at),)


def extend_past_view(table: TableEstimate, camera_xy: np.ndarray) -> TableEstimate:
    """The table with each of its `open_edges` (the camera never had the strip beyond in view:
    the top may run on) pushed out by UNSEEN_EXTENSION, what the robot has not seen it must not
    drive into; but never nearer than ROBOT_KEEP to the camera at `camera_xy` (on the robot):
    the near edge of a table seen with the head raised is not pushed under the robot."""
    camera_local = table.to_local(camera_xy)
    low, high = -table.size / 2, table.size / 2
    edges = ((0, 1.0, high), (0, -1.0, low), (1, 1.0, high), (1, -1.0, low))
    for is_open, (axis, sign, edge) in zip(table.open_edges, edges, strict=True):
        if not is_open:
            continue
        outward = sign * (camera_local[axis] - edge[axis])  # > 0: the camera is that way
        room = outward - ROBOT_KEEP if outward > 0 else UNSEEN_EXTENSION
        edge[axis] += sign * float(np.clip(room, 0.0, UNSEEN_EXTENSION))
    center = table.to_world((low + high) / 2)
    return dataclasses.replace(table, center=center, size=high - low)


def behind(surface: np.ndarray, camera_position: np.ndarray, depth: float) -> np.ndarray:
    """The point `depth` m behind a point on a `surface` seen from `camera_position`, along
    the line of sight (m, world): a limb's axis behind its lifted keypoint."""
    sight = surface - camera_position
    return surface + depth * sight / max(np.linalg.norm(sight), 1e-9)


@dataclasses.dataclass(frozen=True)
class PerceivedScene:
    """Everything the planner avoids, from the percepts only: the table (None if unseen), the
    detected objects' shapes and the person's capsules; with the depth `view` they were seen
    in (None if not kept), which tells what the camera now sees through."""

    table: TableEstimate | None
    objects: tuple[ObjectShape, ...] = ()
    person: tuple[Capsule, ...] = ()
    view: DepthView | None = dataclasses.field(default=None, compare=False, repr=False)

    def object_named(self, label: str) -> ObjectShape | None:
        return next((shape for shape in self.objects if shape.label == label), None)

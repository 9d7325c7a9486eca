"""Where the robot watches from (active perception): high enough that the objects on the table
do not hide the arm a person points with.

A seated person's pointing arm runs down from the shoulder toward the object, and near a high
table the wrist comes level with the objects' tops: seen from the HSR's head at its lowest
(the camera 0.97 m up), the objects between hide it, and the request is never recognised (a
table 0.80 m high, a person 1.58 m tall). Before the person points, the robot knows where the
shoulders and the objects are; it works out where an arm pointing at each object would have its
elbow and wrist, and how much higher the camera must be for every sight line to them to pass
over every object. The torso rises that much,
the arm folded down out of the camera's view; the head keeps its tilt (a higher camera at
the same tilt still frames the table's near edge, the objects and the person's head).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from typing import NamedTuple

import numpy as np
from pydrake.math import RigidTransform

from hsr_handover.hsr import CAMERA_FRAME, TORSO_JOINT
from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.robot.perception.active_gaze import FACE_ABOVE
from hsr_handover.robot.perception.object_shapes import ObjectShape
from hsr_handover.robot.perception.torso_depth import seen_shoulders
from hsr_handover.robot.planning.perceived_scene import BONES, behind
from hsr_handover.robot.planning.plan import Motion
from hsr_handover.robot.planning.planning_scene import PlanningScene

LIFT = "arm_lift_joint"
FLEX = "arm_flex_joint"
SHOULDER_DEPTH = BONES[(keypoint_index("neck"), keypoint_index("r_shoulder"))]
"""m from a lifted shoulder keypoint, on the body's surface facing the camera, back to the
joint the arm turns about. Taken at the keypoints, seated people's shoulders came 8-12 cm
nearer the robot than they are, and over twelve handovers the nearest sight line passed 0.6 cm
short of asking for a rise; from the joints, 5 cm."""
POINTING_REACH = 0.5
"""m from the shoulder to the wrist of an arm pointing at an object on the table (the
simulated 1.58 m person's reads 0.51 m; most adults' are longer, so their wrists are
nearer the object and higher above the table)."""
SIGHT_POINTS = (0.55, 1.0)
"""Where along the pointing reach the camera must see: the elbow and the wrist, the keypoints
the pointing ray is drawn through."""
OVER_TOP = 0.03
"""m a sight line must pass above an object's top: the keypoints are joint centres inside the
limb, and the objects' tops are perceived a cm or two off."""
BESIDE = 0.02
"""m beyond an object's footprint that a sight line passing it still counts as over it."""
SHOULDER_SPAN = (0.2, 0.55)
"""m: the least and most two lifted shoulder keypoints of one person lie apart (the joints are
0.22 of the height apart, 0.32-0.45 m from 1.45 m to 2.05 m tall, and each keypoint is up to
a few cm off its joint). A pointing arm in front of the chest can have a shoulder lifted onto it:
one of the handover reference's people had a shoulder read 66 cm from the other, 60 cm before
the body, and the view asked for a rise of 6 m."""
SHOULDER_TILT = 0.15  # m: two shoulders' heights differ by less, leaning to point included
EYES_OVER_SHOULDERS = FACE_ABOVE[keypoint_index("r_shoulder")]
"""m from the lifted shoulders up to the eyes (the active gaze's estimate). The
camera rises no higher than the person's eyes: from above, the face of a seated person
looking down at the table shows the top of the head, and the nose and eyes are lost for the
whole gesture (a 1.65 m person at a 0.84 m table, watched from the lift's top, 0.69 m: the
request never recognised)."""
LEAST_RISE = 0.02
"""m: a view that asks for less than this is clear enough; no move for it (the perceived
shoulders and objects wander by a cm or so from frame to frame)."""


def reach_points(shoulders: Sequence[np.ndarray], objects: Sequence[ObjectShape]) -> np.ndarray:
    """(n, 3) points (m, world) where the elbow and wrist of an arm from each shoulder pointing
    at each object would be: on the line to where the object stands (the simulated person's
    wrist ends 4 cm below the line to the object's middle, 2 cm below this one)."""
    points = []
    for shoulder in shoulders:
        for shape in objects:
            toward = np.array([*shape.center, shape.bottom]) - shoulder
            length = float(np.linalg.norm(toward))
            if length < 1e-6:
                continue
            points += [shoulder + toward * min(1.0, f * POINTING_REACH / length)
                       for f in SIGHT_POINTS]  # fmt: skip
    return np.array(points).reshape(-1, 3)


def camera_rise(
    camera: np.ndarray, shoulders: Sequence[np.ndarray], objects: Sequence[ObjectShape]
) -> float:
    """How much higher (m, >= 0) the camera at `camera` (m, world) must be for its sight lines
    to every `reach_points` to pass OVER_TOP above every object they cross."""
    rise = 0.0
    for point in reach_points(shoulders, objects):
        for shape in objects:
            needed = _height_to_clear(camera, point, shape)
            rise = max(rise, needed - camera[2])
    return rise


def _height_to_clear(camera: np.ndarray, point: np.ndarray, shape: ObjectShape) -> float:
    """The camera height (m) at which the line from it to `point` passes OVER_TOP above
    `shape`'s top where it crosses the footprint (-inf if it does not cross it, or crosses it
    beyond the point). The camera rises straight up, so the line's horizontal course stays."""
    start, end = camera[:2], point[:2]
    span = end - start
    length_sq = float(span @ span)
    if length_sq < 1e-12:
        return -math.inf
    offset = shape.center - start
    along = float(offset @ span) / length_sq  # 0 at the camera, 1 at the point
    across = abs(float(span[0] * offset[1] - span[1] * offset[0])) / math.sqrt(length_sq)
    if not 0.0 < along < 1.0 or across > shape.radius + BESIDE:
        return -math.inf
    top = shape.bottom + shape.height + OVER_TOP
    # The line's height over the object is camera_z + along * (point_z - camera_z).
    return (top - along * point[2]) / (1.0 - along)


def watch_posture(
    robot: PlanningScene,
    q: np.ndarray,
    shoulders: Sequence[np.ndarray],
    objects: Sequence[ObjectShape],
) -> np.ndarray | None:
    """The HSR's posture (plant positions) to watch from: `q` with the torso raised by the
    `camera_rise` the person's two `shoulders` (the lifted keypoints, SHOULDER_DEPTH before the
    joints) and the `objects` (m, world) ask for, as far as the lift goes and no higher than
    the person's eyes (EYES_OVER_SHOULDERS), and the arm folded down. None when the view from
    `q` asks for less than LEAST_RISE, the lift is at its top, or the shoulders could not be
    one person's.

    The lift raises the arm twice as fast as the head: raised 0.34 m with the arm upright, its
    wrist stands 11 cm below the camera and 19 cm before it, in the view's lower half, and
    hides the objects on that side (two of the staggered layout's four). Folded down to its
    limit, the upper arm points down and forward, the tucked hand below it, out of view."""
    if not objects or not plausible_shoulders(shoulders):
        return None
    camera = _camera(robot, q).translation()
    joints = [behind(shoulder, camera, SHOULDER_DEPTH) for shoulder in shoulders]
    eyes = float(np.mean([shoulder[2] for shoulder in shoulders])) + EYES_OVER_SHOULDERS
    rise = min(camera_rise(camera, joints, objects), eyes - camera[2])
    lift_at, torso_at, flex_at = robot.index(LIFT), robot.index(TORSO_JOINT), robot.index(FLEX)
    lower, upper = robot.plant.GetPositionLowerLimits(), robot.plant.GetPositionUpperLimits()
    if not rise >= LEAST_RISE or q[lift_at] >= upper[lift_at] - 2.0 * LEAST_RISE:
        return None
    raised = np.array(q, dtype=float)
    # The torso, which carries the head, rises half as fast as the arm lift.
    raised[lift_at] = min(upper[lift_at], q[lift_at] + 2.0 * rise)
    raised[torso_at] = 0.5 * raised[lift_at]
    raised[flex_at] = lower[flex_at]
    return raised


def plausible_shoulders(shoulders: Sequence[np.ndarray]) -> bool:
    """Whether two lifted shoulders could be one person's (SHOULDER_SPAN, SHOULDER_TILT)."""
    if len(shoulders) != 2:
        return False
    apart = shoulders[0] - shoulders[1]
    span = float(np.linalg.norm(apart))
    return bool(SHOULDER_SPAN[0] <= span <= SHOULDER_SPAN[1] and abs(apart[2]) <= SHOULDER_TILT)


class Weighed(NamedTuple):
    """What the view was last weighed with: the shoulders as first seen, the objects' labels."""

    shoulders: list[np.ndarray]
    labels: frozenset[str]


def weigh_now(
    weighed: Weighed | None, points: np.ndarray, confidence: np.ndarray, objects: Sequence
) -> Weighed | None:
    """What to weigh the view with now (`watch_posture`), else None: first when both shoulders
    (`points`, `confidence`: the lifted skeleton) and an object are seen, then again whenever
    an object is seen for the first time, with the shoulders as first seen (the person at rest:
    pointing, they lean in and their arm can take a shoulder's keypoint)."""
    labels = frozenset(shape.label for shape in objects)
    if not objects or (weighed is not None and labels <= weighed.labels):
        return None
    if weighed is not None:
        return Weighed(weighed.shoulders, labels)
    shoulders = [point for point in seen_shoulders(points, confidence) if point is not None]
    return Weighed(shoulders, labels) if plausible_shoulders(shoulders) else None


@dataclasses.dataclass(frozen=True)
class Raise:
    """The move to the posture the robot watches from: the `motion` (plant positions over
    time), begun at `start` s, and the arm `lift` (m) it ends at."""

    start: float
    motion: Motion
    lift: float
    arrived: tuple[np.ndarray, np.ndarray] = dataclasses.field(init=False, repr=False)

    def __post_init__(self) -> None:
        # Held once it is over: the command is read at every plant step.
        object.__setattr__(self, "arrived", self.motion.state(self.motion.duration))

    @property
    def end(self) -> float:
        return self.start + self.motion.duration

    def state(self, time: float) -> tuple[np.ndarray, np.ndarray]:
        """Positions and velocities (plant order) at `time` s."""
        return self.arrived if time >= self.end else self.motion.state(time - self.start)

    def __deepcopy__(self, memo: dict) -> Raise:
        return self  # never changed once made


@dataclasses.dataclass
class WatchView:
    """Where the robot watches from, carried between its ticks: what the view was last weighed
    with, the raise made (None: it watches from where it stands) and whether a raise found no
    way (then it watches from where it is, for good)."""

    weighed: Weighed | None = None
    raised: Raise | None = None
    blocked: bool = False

    def settled(self, time: float) -> bool:
        """Whether it may weigh the view at `time` s: no raise blocked, none under way."""
        return not self.blocked and (self.raised is None or time >= self.raised.end)

    def weigh(
        self,
        time: float,
        robot: PlanningScene,
        q: np.ndarray,
        points: np.ndarray,
        confidence: np.ndarray,
        objects: Sequence[ObjectShape],
        plan: Callable[[np.ndarray, np.ndarray], Motion | None],
    ) -> Raise | None:
        """The raise begun at `time` s when `weigh_now` has something to weigh, the view from
        `q` (the HSR's measured positions, plant order) asks for one (`watch_posture`) and
        `plan(q, posture)` finds a motion to it (None: none, and it stays where it is); else
        None."""
        if not self.settled(time):
            return None
        weighed = weigh_now(self.weighed, points, confidence, objects)
        if weighed is None:
            return None
        self.weighed = weighed
        posture = watch_posture(robot, q, weighed.shoulders, objects)
        if posture is None:
            return None
        motion = plan(q, posture)
        self.blocked = motion is None
        if motion is None:
            return None
        self.raised = Raise(time, motion, float(posture[robot.index(LIFT)]))
        return self.raised


def _camera(robot: PlanningScene, q: np.ndarray) -> RigidTransform:
    robot.plant.SetPositions(robot.plant_context, q)
    return robot.plant.GetFrameByName(CAMERA_FRAME).CalcPoseInWorld(robot.plant_context)

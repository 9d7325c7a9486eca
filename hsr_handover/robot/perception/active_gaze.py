"""Active gaze: where the robot turns its head while it watches. Looking is an action (the
paper's perceiving-acting cycle, section 2 and fig. 2b): what the camera's field of view holds
is all the robot can perceive, so attention must move the head.

Two modes, decided from the lifted skeleton alone:

- **Searching**: no person seen. The head visits `GazeParams.search` (pan, tilt) in turn, each
  long enough for the move and a few frames, and begins again.
- **Framing**: a person seen. The head aims the camera so its field of view holds, in this
  order, what attention selects (the face, the hand or an object: paper 3.2; fixated, the
  axis as near it as the rest allows), the person's face, where an arm held out points on the
  table (`pointed_at`: the robot looks where a straight arm points, so an object outside its view
  is seen once asked for), their hands and the objects on the table (where last seen: they
  stay put while the camera looks away). Each wants the optical axis within an interval of
  heading and elevation; the intervals are intersected in that order, one that would leave
  nothing is dropped, and the axis goes to the middle of what is left (`fit`). A standing
  person's face and the table in front of them span more than the camera's 47 degrees
  vertically, so the objects are then dropped and remembered. A face not seen yet is taken to
  stand above the highest body keypoint seen (`face_estimate`): the first frames of a standing
  person show the torso, and the head moves up until it shows the face.

The person lost for `lost_s`, it searches again. Angles are the camera's own (heading about
the world's z, elevation from level) and become joint targets by the difference from the
measured pan and tilt: the camera sits a few cm off the joints' axes, an error each frame's
re-aim takes out.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np

from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.robot.intent.rays import elbow_angle_deg
from hsr_handover.robot.perception.attention import FACE, LEFT_ARM, RIGHT_ARM

SEARCH_FIXATIONS = ((0.0, 0.2), (0.6, 0.2), (-0.6, 0.2), (1.2, 0.1), (-1.2, 0.1), (0.0, -0.3))
"""(pan, tilt) rad the head visits while it finds no one: ahead first, then each side; tilted
up 0.2 rad the camera (0.97 m up) sees from 12 degrees below level to 35 above, so both a
seated person's face (5-10 degrees up at 1.5-2 m) and a standing one's (25-35 up) are in view
at the first fixation that faces them."""

WRISTS = (keypoint_index("r_wrist"), keypoint_index("l_wrist"))
HELD_OUT = 0.3
"""m a wrist is held out from its shoulder, horizontally, for its arm to count as pointing (a
seated person's resting forearms hold it 0.2-0.3 m out; a pointing arm, 0.4-0.6)."""
POINTING_ELBOW_DEG = 135.0
"""deg (eq. 16's elbow angle) from which an arm held out counts as pointing: a forearm resting
on the table, held 0.3-0.5 m out, bends 80-105 degrees; a pointing arm reads 140-180 through
the detector's error. An arm whose elbow is not seen does not count: the camera is not turned
on a guess."""
POINTED_AHEAD = 0.6
"""m beyond the wrist the object pointed at is taken to be: objects on the table between the
person and the robot lie 0.3-0.9 m beyond a pointing wrist, and the camera's width takes in
the rest."""
FACE_ABOVE = {
    keypoint_index("neck"): 0.22,
    keypoint_index("r_shoulder"): 0.27,
    keypoint_index("l_shoulder"): 0.27,
    keypoint_index("r_hip"): 0.75,
    keypoint_index("l_hip"): 0.75,
    keypoint_index("r_knee"): 1.2,
    keypoint_index("l_knee"): 1.2,
}
"""m from a body keypoint up to the eyes of an upright adult (about 0.13, 0.15, 0.42 and 0.67
of a 1.8 m person's height, seated or standing: a seated person's knees are as high as their
hips, so their face is overestimated; the head then moves up and down once)."""
MIN_KEYPOINTS = 3
"""A person is seen when at least this many keypoints are (one or two may be a spurious
detection on a coloured object)."""

SEARCH, FRAMING = "search", "framing"


@dataclasses.dataclass(frozen=True)
class GazeParams:
    """How the head moves while it watches.

    search: (pan, tilt) fixations (rad) visited while no person is seen. dwell_s: s held at each
    once there (the skeleton of a person in view is detected in the first frame; a few frames
    let the moved head settle). margin_deg: how far inside the field of view's edge a framed
    point is kept. lost_s: s without a person seen before searching again. deadband_deg: a new
    aim within this of the one under way is not taken (keypoints wander by a cm or two).
    speed: rad/s of each head joint (the HSR's limit is 1.0 rad/s).

    Ranges: search non-empty, each pan and tilt in [-pi, pi] rad; dwell_s in [0, 10] s;
    margin_deg in [0, 20] deg; lost_s in (0, 60] s; deadband_deg in [0, 10] deg; speed in
    (0, 1] rad/s."""

    search: tuple[tuple[float, float], ...] = SEARCH_FIXATIONS
    dwell_s: float = 0.4
    margin_deg: float = 5.0
    lost_s: float = 1.5
    deadband_deg: float = 2.0
    speed: float = 0.8

    def __post_init__(self) -> None:
        fixations_ok = bool(self.search) and all(
            len(f) == 2 and all(abs(a) <= math.pi for a in f) for f in self.search
        )
        checks = {
            "search": (fixations_ok, "a non-empty list of (pan, tilt) each in [-pi, pi] rad"),
            "dwell_s": (0 <= self.dwell_s <= 10, "[0, 10] s"),
            "margin_deg": (0 <= self.margin_deg <= 20, "[0, 20] deg"),
            "lost_s": (0 < self.lost_s <= 60, "(0, 60] s"),
            "deadband_deg": (0 <= self.deadband_deg <= 10, "[0, 10] deg"),
            "speed": (0 < self.speed <= 1, "(0, 1] rad/s"),
        }
        for name, (ok, expected) in checks.items():
            if not ok:
                raise ValueError(f"{name}: expected {expected}, got {getattr(self, name)}")


@dataclasses.dataclass(frozen=True)
class FieldOfView:
    """The camera's half-extent (rad) about its optical axis, across and up."""

    half_width: float
    half_height: float

    @classmethod
    def of(cls, camera: PinholeCamera) -> FieldOfView:
        return cls(
            math.atan(camera.width / 2.0 / camera.fx), math.atan(camera.height / 2.0 / camera.fy)
        )


@dataclasses.dataclass(frozen=True)
class GazeState:
    """Where the gaze stands: `mode` (SEARCH or FRAMING), the head's goal (pan, tilt) rad,
    when the person was last seen and first found (s; -inf and NaN before), the search's
    fixation under way and until when it holds, and the objects (label, centre) where last
    seen."""

    mode: str = SEARCH
    goal: tuple[float, float] | None = None
    seen_at: float = -math.inf
    found_at: float = math.nan
    fixation: int = -1
    fixation_until: float = -math.inf
    objects: tuple[tuple[str, np.ndarray], ...] = ()


def angles(origin: np.ndarray, point: np.ndarray) -> tuple[float, float]:
    """(heading about z, elevation from level) rad of `point` seen from `origin` (m, world)."""
    d = np.asarray(point, dtype=float) - np.asarray(origin, dtype=float)
    return math.atan2(d[1], d[0]), math.atan2(d[2], math.hypot(d[0], d[1]))


def wrap(angle: float) -> float:
    """`angle` (rad) in [-pi, pi)."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def _seen(points: np.ndarray, confidence: np.ndarray, index: int) -> bool:
    return bool(confidence[index] > 0 and np.all(np.isfinite(points[index])))


def person_seen(points: np.ndarray, confidence: np.ndarray) -> bool:
    """Whether the lifted skeleton shows a person (MIN_KEYPOINTS or more keypoints)."""
    return sum(_seen(points, confidence, i) for i in range(len(confidence))) >= MIN_KEYPOINTS


def face_estimate(points: np.ndarray, confidence: np.ndarray) -> np.ndarray | None:
    """The face (m, world): the mean of the face keypoints seen, else the highest the body
    keypoints seen put it (each FACE_ABOVE below the eyes); None when neither is."""
    face = [points[i] for i in FACE if _seen(points, confidence, i)]
    if face:
        return np.mean(face, axis=0)
    body = [(points[i][2] + above, i) for i, above in FACE_ABOVE.items()
            if _seen(points, confidence, i)]  # fmt: skip
    if not body:
        return None
    top, index = max(body)
    return np.array([points[index][0], points[index][1], top])


def pointed_at(points: np.ndarray, confidence: np.ndarray, level: float) -> np.ndarray | None:
    """Where on the table the straight arm (POINTING_ELBOW_DEG) held out farthest (HELD_OUT or
    more) points: POINTED_AHEAD beyond its wrist along the shoulder-to-wrist heading, at the
    objects' `level` (m, world); None when no straight arm is held out over it. The heading
    alone is taken: lifted, the wrist lands on the hand's surface a few cm low, and the line
    through it dips to the table 30 cm short of the object pointed at."""
    best, best_reach = None, HELD_OUT
    for shoulder, elbow, wrist in (RIGHT_ARM, LEFT_ARM):
        if not all(_seen(points, confidence, i) for i in (shoulder, elbow, wrist)):
            continue
        if not elbow_angle_deg(*points[[shoulder, elbow, wrist]]) >= POINTING_ELBOW_DEG:
            continue
        along = (points[wrist] - points[shoulder])[:2]
        reach = float(np.hypot(*along))
        if reach >= best_reach and points[wrist][2] > level:
            ahead = points[wrist][:2] + POINTED_AHEAD * along / reach
            best, best_reach = np.array([*ahead, level]), reach
    return best


def fit(wanted: Sequence[float], half: float, toward: float | None = None) -> float | None:
    """Of the angles that keep the most of `wanted` (angles, in their order of priority) within
    `half` of the axis (each narrows the interval left, and one that would leave nothing is
    dropped), the middle, or the nearest to `toward` when given (a fixation). None when
    nothing is wanted."""
    low, high = -math.inf, math.inf
    for value in wanted:
        new_low, new_high = max(low, value - half), min(high, value + half)
        if new_low <= new_high:
            low, high = new_low, new_high
    if not math.isfinite(low):
        return None
    return 0.5 * (low + high) if toward is None else float(np.clip(toward, low, high))


class ActiveGaze:
    """Decides the head's goal from what the camera shows (see the module's docstring)."""

    def __init__(
        self,
        view: FieldOfView,
        limits: tuple[tuple[float, float], tuple[float, float]],
        params: GazeParams | None = None,
    ):
        """`view`: the camera's field of view; `limits`: the pan's and the tilt's (lower,
        upper) rad, which every goal keeps within."""
        self.params = GazeParams() if params is None else params
        self.view = view
        self.limits = limits
        self.state_ = GazeState()

    def update(
        self,
        time: float,
        camera_rotation: np.ndarray,
        camera_position: np.ndarray,
        head: tuple[float, float],
        points: np.ndarray,
        confidence: np.ndarray,
        detections: Sequence[tuple[str, np.ndarray]] = (),
        attended: Sequence[np.ndarray] = (),
    ) -> GazeState:
        """One frame: the camera's pose (3 x 3 rotation, z the optical axis; position, m) at its
        capture, the head's measured (pan, tilt), the lifted skeleton (18 x 3 points, 18
        confidences), the objects detected (label, centre) and the centres of the regions
        attention selects (m, world; framed before all else). Returns the new state."""
        state = self.state_
        seen = {label: np.asarray(c, dtype=float) for label, c in state.objects}
        seen |= {label: np.asarray(c, dtype=float) for label, c in detections
                 if np.all(np.isfinite(c))}  # fmt: skip
        state = dataclasses.replace(state, objects=tuple(seen.items()))
        face = face_estimate(points, confidence) if person_seen(points, confidence) else None
        if face is not None:
            aim = self._frame(camera_position, face, points, confidence, state.objects, attended)
            goal = self._within_limits(_to_joints(aim, camera_rotation, head))
            found = time if math.isnan(state.found_at) else state.found_at
            state = dataclasses.replace(state, mode=FRAMING, seen_at=time, found_at=found,
                                        goal=self._settled(state.goal, goal))  # fmt: skip
        elif state.mode == FRAMING and time - state.seen_at < self.params.lost_s:
            pass  # a blink of the detector: hold the aim
        else:
            state = self._search(time, state, head)
        self.state_ = state
        return state

    def _frame(
        self,
        camera: np.ndarray,
        face: np.ndarray,
        points: np.ndarray,
        confidence: np.ndarray,
        objects: Sequence[tuple[str, np.ndarray]],
        attended: Sequence[np.ndarray] = (),
    ) -> tuple[float, float]:
        """The optical axis's (heading, elevation) that frames what attention selects, then the
        face, then where an arm points on the table (the object asked for may not have been
        seen yet), then the hands, then the objects (nearest the face's heading first)."""
        margin = math.radians(self.params.margin_deg)
        targets = [angles(camera, center) for center in attended] + [angles(camera, face)]
        if objects:
            level = float(np.mean([center[2] for _, center in objects]))
            pointed = pointed_at(points, confidence, level)
            targets += [] if pointed is None else [angles(camera, pointed)]
        targets += [angles(camera, points[i]) for i in WRISTS if _seen(points, confidence, i)]
        face_heading = targets[len(attended)][0]
        by_heading = sorted((angles(camera, c) for _, c in objects),
                            key=lambda a: abs(wrap(a[0] - face_heading)))  # fmt: skip
        targets += by_heading
        # Headings are unwrapped about the face's, so the interval arithmetic is on a line.
        headings = [targets[0][0] + wrap(h - targets[0][0]) for h, _ in targets]
        elevations = [e for _, e in targets]
        # What attention selects is fixated: the axis as near it as the rest allows.
        fixation = (headings[0], elevations[0]) if attended else (None, None)
        heading = fit(headings, max(self.view.half_width - margin, 0.0), fixation[0])
        elevation = fit(elevations, max(self.view.half_height - margin, 0.0), fixation[1])
        return float(heading), float(elevation)

    def _settled(
        self, current: tuple[float, float] | None, goal: tuple[float, float]
    ) -> tuple[float, float]:
        """`goal`, or the goal under way when it is within the deadband of it."""
        band = math.radians(self.params.deadband_deg)
        if current is not None and max(abs(goal[0] - current[0]), abs(goal[1] - current[1])) < band:
            return current
        return goal

    def _within_limits(self, goal: tuple[float, float]) -> tuple[float, float]:
        (pan_low, pan_high), (tilt_low, tilt_high) = self.limits
        return float(np.clip(goal[0], pan_low, pan_high)), float(
            np.clip(goal[1], tilt_low, tilt_high)
        )

    def _search(self, time: float, state: GazeState, head: tuple[float, float]) -> GazeState:
        """The next fixation once the one under way has been held its time."""
        if state.mode == SEARCH and time < state.fixation_until:
            return state
        fixations = self.params.search
        index = (state.fixation + 1) % len(fixations) if state.mode == SEARCH else 0
        goal = self._within_limits(fixations[index])
        travel = max(abs(goal[0] - head[0]), abs(goal[1] - head[1])) / self.params.speed
        until = time + travel + self.params.dwell_s
        return dataclasses.replace(state, mode=SEARCH, goal=goal, fixation=index,
                                   fixation_until=until)  # fmt: skip


def _to_joints(
    aim: tuple[float, float], camera_rotation: np.ndarray, head: tuple[float, float]
) -> tuple[float, float]:
    """The (pan, tilt) that turn the optical axis (the rotation's z column) to `aim`'s heading
    and elevation, from the measured `head`: pan turns the heading, tilt the elevation."""
    axis = np.asarray(camera_rotation, dtype=float)[:, 2]
    heading, elevation = angles(np.zeros(3), axis)
    return head[0] + wrap(aim[0] - heading), head[1] + (aim[1] - elevation)


TAKEN_OVER = 0.1
"""rad between the head's commanded and measured angles beyond which something else commands
the head (the PD-driven head lags a moving command by under 0.01 rad)."""


@dataclasses.dataclass(frozen=True)
class HeadMove:
    """The head's command from (pan, tilt) `start` at `start_time` (s) to `goal` along a
    straight line in joint space, the farther joint at `speed` (rad/s); held at the goal."""

    start_time: float
    start: tuple[float, float]
    goal: tuple[float, float]
    speed: float

    def at(self, time: float) -> tuple[np.ndarray, np.ndarray]:
        """(pan, tilt) positions (rad) and velocities (rad/s) at `time` s."""
        start, goal = np.asarray(self.start, dtype=float), np.asarray(self.goal, dtype=float)
        span = goal - start
        duration = float(np.max(np.abs(span))) / self.speed
        elapsed = time - self.start_time
        if elapsed >= duration or duration == 0.0:
            return goal, np.zeros(2)
        elapsed = max(elapsed, 0.0)
        return start + span * (elapsed / duration), span / duration

    def toward(
        self, time: float, goal: tuple[float, float], measured: tuple[float, float] | None = None
    ) -> HeadMove:
        """A move to `goal` from where this one commands the head at `time`, or from where the
        head is `measured` when that is more than TAKEN_OVER rad off it (something else
        commanded the head meanwhile: the handover supervisor's look round or its look at an
        object), so the head is not stepped back to a command it never followed."""
        here = self.at(time)[0]
        if measured is not None and np.max(np.abs(here - np.asarray(measured))) > TAKEN_OVER:
            here = np.asarray(measured, dtype=float)
        elif tuple(goal) == tuple(self.goal):
            return self
        return HeadMove(time, (float(here[0]), float(here[1])), goal, self.speed)

"""The person's scripted behaviour as a timeline of joint targets with human-like moves.

Each action sets a whole-body target posture (PERSON_JOINTS order); the body moves between
targets along minimum-jerk profiles whose duration follows from a peak joint speed, so motions
look like a person's (smooth, bell-shaped speed) rather than a servo's.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from hsr_handover.world.person.aiming import (
    arm_points,
    head_angles,
    pointing_arm_angles,
    reaching_arm_angles,
    rot_y,
    rot_z,
)
from hsr_handover.world.person.body import (
    HAND_THICKNESS,
    PERSON_JOINTS,
    BodyDimensions,
    arm_joint_indices,
    side_sign,
)

ACTIONS = ("rest", "look_at", "point_at", "reach_to", "touch", "gesture")
REACHES = ("reach_to", "touch")  # the hand goes to a point; "touch" without looking at it
GESTURE_BEAT_S = 0.6  # s between the arm's turns while gesturing (one minimum move)
PEAK_JOINT_SPEED = 1.5  # rad/s: brisk but human
MAX_STRETCHES = 100  # a move is stretched by 5 % at most this often (x131) to keep under the peak
MIN_MOVE_TIME = 0.6  # s
# A person lifts a hand from rest before stretching the arm out: the arm first swings to its
# goal's shoulder angles with the elbow bent this much (rad), and the elbow opens once the
# swing is LIFT_SHARE done. Swinging out a straight arm from a forearm resting at table height
# sweeps the hand into the table's edge when the person sits or stands close to it.
LIFT_ELBOW = -0.8
LIFT_SHARE = 0.5
OVER_TABLE = 0.02
"""m a seated person's resting hands keep over the table's top. Forearms resting level sit at
0.70-0.76 m, under the top of a high table (0.80 m): a hand whose tip rested a few cm from the
table's edge met the edge as the arm swung out, and stayed there for the whole gesture: the
person never pointed. At such a table the forearms rest tilted up, the elbows bent further,
as people hold their hands over a table's edge; and where the elbow would still be under the
top, the upper arm comes forward until it is over it (the forearms rest on the table): a
1.55 m person seated at a 0.77 m table, elbow under the top and hand over it, jammed the
forearm against the edge from below as the arm swung up to point (700 N; generated layouts)."""
RAISE_STEP = 0.1  # rad: the elbow (or the shoulder) turns by steps of this
WITHDRAW_ELBOW = -1.6
"""rad: a pointing hand held over an object is drawn back by bending the elbow this far (the
forearm about square to the upper arm) before the arm lowers: lowered straight from the point
to rest, it sweeps through the object it pointed over and knocks it down."""
_MIN_JERK_PEAK = 1.875  # peak of d/dtau of the minimum-jerk profile

_INDEX = {name: i for i, name in enumerate(PERSON_JOINTS)}
_LIMITS = {
    "neck_yaw": (-1.4, 1.4), "neck_pitch": (-0.8, 1.0),
    "shoulder_pitch": (-3.1, 1.0), "shoulder_roll": (-1.6, 1.6), "shoulder_yaw": (-1.6, 1.6),
    "elbow": (-2.6, 0.0), "wrist": (-1.2, 1.2),
}  # fmt: skip


def joint_limits(name: str) -> tuple[float, float]:
    """Position limits (rad) of a person joint, by its name in PERSON_JOINTS."""
    return _LIMITS[name.removeprefix("r_").removeprefix("l_")]


@dataclasses.dataclass(frozen=True)
class Action:
    """A scripted action with its target already in the person frame.

    kind: one of ACTIONS. end: None lasts until the next action. point: the object or point
    looked at or reached for (person frame), None for rest and gesture. arm: "right" or "left".
    head_fraction: the share of the turn toward `point` the head makes (the eyes do the rest).
    arm_point: where a pointing arm aims when it misses `point` (the person's pointing error);
    None aims at `point`. The eyes stay on `point`: the arm errs, the gaze does not follow it.
    withdraw: a pointing hand held over an object is drawn back (the elbow bent to
    WITHDRAW_ELBOW) before the arm lowers to rest, not swept down through the object.
    """

    kind: str
    start: float
    end: float | None = None
    point: np.ndarray | None = None
    arm: str = "right"
    head_fraction: float = 1.0
    arm_point: np.ndarray | None = None
    withdraw: bool = False


def rest_posture(body: BodyDimensions, table_top: float | None = None) -> np.ndarray:
    """Head level and a little down; standing, arms hang. Seated, the forearms rest level in
    front of the body (as on armrests), above table height: every joint-space move from there
    to a pointing or reaching arm then keeps the hand above the table top rather than sweeping
    it under the table's edge. At a table whose top (`table_top`, m, person frame; None: no
    table) is higher than that, the seated person's hands rest OVER_TABLE over it, and so do a
    standing person's whose hanging hands are below it: swung out from hanging, a 1.50 m
    person's hand met the edge of a 0.85 m table from below and stayed jammed under it for the
    whole gesture (130 N; generated layouts), as no one's does."""
    q = np.zeros(len(PERSON_JOINTS))
    q[_INDEX["neck_pitch"]] = 0.2
    for prefix, sign in (("r_", -1.0), ("l_", 1.0)):
        q[_INDEX[prefix + "shoulder_roll"]] = 0.08 * sign
        q[_INDEX[prefix + "shoulder_pitch"]] = -0.25 if body.seated else 0.0
        q[_INDEX[prefix + "elbow"]] = -1.5 if body.seated else -0.15
    if table_top is not None and (body.seated or _hands_under(body, q, table_top)):
        for arm in ("right", "left"):
            _raise_hand_over(body, arm, q, table_top + OVER_TABLE)
    return q


def _hands_under(body: BodyDimensions, q: np.ndarray, table_top: float) -> bool:
    """Whether the hands hang, in posture `q`, below the table's top (m, person frame)."""
    tips = (
        arm_points(body, arm, q[arm_joint_indices(arm)])["tips"][2] for arm in ("right", "left")
    )
    return min(tips) < table_top


def _raise_hand_over(body: BodyDimensions, arm: str, q: np.ndarray, height: float) -> None:
    """Bring the `arm`'s upper arm forward in `q` until its elbow is over `height`, then bend
    its elbow until the hand's lowest point (its axis, wrist to tips, less half its thickness)
    is over it: by RAISE_STEP at a time, within the joints' limits."""
    joints = arm_joint_indices(arm)
    pitch, elbow = joints[0], joints[3]
    forward_most = joint_limits(PERSON_JOINTS[pitch])[0]
    if _hand_low(body, arm, q) >= height:
        return  # the hand rests over the table as it is: the arm stays as it is
    while (
        arm_points(body, arm, q[joints])["elbow"][2] < height
        and q[pitch] - RAISE_STEP >= forward_most
    ):
        q[pitch] -= RAISE_STEP
    lowest = joint_limits(PERSON_JOINTS[elbow])[0]
    while q[elbow] - RAISE_STEP >= lowest:
        if _hand_low(body, arm, q) >= height:
            return
        q[elbow] -= RAISE_STEP


def _hand_low(body: BodyDimensions, arm: str, q: np.ndarray) -> float:
    """The height (m) of the lowest point of the `arm`'s hand's axis, less half its thickness."""
    points = arm_points(body, arm, q[arm_joint_indices(arm)])
    return min(points["wrist"][2], points["tips"][2]) - HAND_THICKNESS / 2


def aim_head(body: BodyDimensions, point: np.ndarray) -> np.ndarray:
    """Neck (yaw, pitch) that put the target on the line of sight from between the eyes.

    The eyes sit above and ahead of the neck pivot, so aiming from the pivot misses by several
    degrees at arm's length; a few fixed-point steps from the eyes' actual position fix that.
    """
    pivot = body.neck_pivot()
    face = body.face_points()
    eyes = (face["r_eye"] + face["l_eye"]) / 2
    angles = head_angles(point - pivot)
    # Contracts by about (eye offset / distance) per step: 12 steps suffice down to 0.2 m.
    for _ in range(12):
        eye_position = pivot + head_rotation(*angles) @ eyes
        angles = head_angles(point - eye_position)
    return angles


def head_rotation(yaw: float, pitch: float) -> np.ndarray:
    """Rotation of the head in the person frame for neck yaw (about z), then pitch (about y)."""
    return rot_z(yaw) @ rot_y(pitch)


def target_posture(
    body: BodyDimensions, action: Action, rest: np.ndarray | None = None
) -> np.ndarray:
    """The whole-body joint target for one action (PERSON_JOINTS order), within joint limits:
    the `rest` posture (`rest_posture(body)` if None) with the head and the acting arm aimed."""
    q = rest_posture(body) if rest is None else rest.copy()
    neck = [_INDEX["neck_yaw"], _INDEX["neck_pitch"]]
    if action.point is not None and action.kind != "touch":
        level = q[neck].copy()
        q[neck] = level + action.head_fraction * (aim_head(body, action.point) - level)
    if action.kind in ("point_at", *REACHES):
        aimed = action.point if action.arm_point is None else action.arm_point
        to_target = aimed - body.shoulder(action.arm)
        if action.kind == "point_at":
            arm = pointing_arm_angles(to_target)
        else:
            arm = reaching_arm_angles(to_target, body)
        q[arm_joint_indices(action.arm)] = arm
    lower, upper = np.array([joint_limits(name) for name in PERSON_JOINTS]).T
    return np.clip(q, lower, upper)


def posture_changes(
    body: BodyDimensions, actions: Sequence[Action], table_top: float | None = None
) -> list[tuple[float, np.ndarray]]:
    """(time, target posture) pairs, in time order: each action's start, and a return to rest
    where an action ends before the next begins. `table_top` as for `rest_posture`."""
    ordered = sorted(actions, key=lambda a: a.start)
    rest = rest_posture(body, table_top)
    changes = [(0.0, rest)]
    for index, action in enumerate(ordered):
        next_start = ordered[index + 1].start if index + 1 < len(ordered) else np.inf
        end = next_start if action.end is None else min(action.end, next_start)
        if action.kind == "gesture":
            changes += _gesture_beats(body, action, end, rest)
        elif action.kind in ("point_at", *REACHES):
            goal = target_posture(body, action, rest)
            changes += _lift_then_stretch(action, end, changes[-1][1], goal)
        else:
            changes.append((action.start, target_posture(body, action, rest)))
        if action.end is not None and action.end < next_start:
            if action.withdraw:
                changes += _withdraw_then_rest(action, next_start, changes[-1][1], rest)
            else:
                changes.append((action.end, rest))
    return changes


def move_duration(origin: np.ndarray, goal: np.ndarray) -> float:
    """How long (s) a minimum-jerk move from `origin` to `goal` takes at PEAK_JOINT_SPEED."""
    span = float(np.max(np.abs(np.asarray(goal) - np.asarray(origin))))
    return max(MIN_MOVE_TIME, _MIN_JERK_PEAK * span / PEAK_JOINT_SPEED)


def _lift_then_stretch(action: Action, end: float, before: np.ndarray, goal: np.ndarray):
    """A pointing or reaching arm's move in two overlapping parts: swing the arm to its goal's
    shoulder angles with the elbow bent (LIFT_ELBOW), which raises the hand, then open the
    elbow (by `end` at the latest). `before` is the posture the move starts from (or is
    heading to)."""
    lifted = _elbow_bent(goal, action.arm, LIFT_ELBOW)
    stretch = min(action.start + LIFT_SHARE * move_duration(before, lifted), end)
    return [(action.start, lifted), (stretch, goal)]


def _elbow_bent(posture: np.ndarray, arm: str, elbow: float) -> np.ndarray:
    """`posture` with the `arm`'s elbow bent at least to `elbow` (rad) and its wrist straight."""
    prefix = "r_" if arm == "right" else "l_"
    bent = posture.copy()
    bent[_INDEX[prefix + "elbow"]] = min(posture[_INDEX[prefix + "elbow"]], elbow)
    bent[_INDEX[prefix + "wrist"]] = 0.0
    return bent


def _withdraw_then_rest(action: Action, end: float, before: np.ndarray, rest: np.ndarray):
    """A pointing arm's return in two overlapping parts, `_lift_then_stretch` backwards: bend
    the elbow to WITHDRAW_ELBOW, the shoulder held, which draws the hand back and up; then, once
    that is LIFT_SHARE done (by `end` at the latest), go to `rest`. `before` is the pointing
    posture."""
    withdrawn = _elbow_bent(before, action.arm, WITHDRAW_ELBOW)
    lower = min(action.end + LIFT_SHARE * move_duration(before, withdrawn), end)
    return [(action.end, withdrawn), (lower, rest)]


def _gesture_beats(body: BodyDimensions, action: Action, end: float, rest: np.ndarray):
    """Talking with the hands: the forearm swings up and out and back every GESTURE_BEAT_S,
    the elbow bent (never a straight, pointing arm), until `end` (at most a minute of beats);
    the rest of the body as in `rest`."""
    sign = side_sign(action.arm)
    joints = arm_joint_indices(action.arm)
    beats = []
    for beat in range(int(min(end - action.start, 60.0) / GESTURE_BEAT_S) + 1):
        q = rest.copy()
        lifted = beat % 2 == 0
        q[joints] = [-0.9 if lifted else -0.5, sign * (0.35 if lifted else 0.15), 0.0,
                     -1.1 if lifted else -1.6, 0.3 if lifted else -0.2]  # fmt: skip
        beats.append((action.start + beat * GESTURE_BEAT_S, q))
    return beats


def _profiles(tau: np.ndarray) -> tuple[np.ndarray, ...]:
    """The quintic that carries a move from rest at 0 to rest at 1 (s, ds/dtau) and the one
    that carries an initial velocity away to nothing (h, dh/dtau): h(0) = 0, h'(0) = 1, and
    h, h', h'' vanish at 1 (h'' also at 0), so a move entered mid-motion stays smooth."""
    s = tau**3 * (10 - 15 * tau + 6 * tau**2)
    ds = 30 * tau**2 * (1 - tau) ** 2
    h = tau - 6 * tau**3 + 8 * tau**4 - 3 * tau**5
    dh = 1 - 18 * tau**2 + 32 * tau**3 - 15 * tau**4
    return s, ds, h, dh


_TAU = np.linspace(0.0, 1.0, 101)
_TAU_PROFILES = _profiles(_TAU)


@dataclasses.dataclass(frozen=True)
class _Move:
    start: float
    duration: float
    origin: np.ndarray
    goal: np.ndarray
    velocity: np.ndarray  # at the start: a change mid-move carries the body's motion on

    @classmethod
    def starting(cls, start: float, origin, velocity, goal) -> _Move:
        """The move from `origin` at `velocity` to rest at `goal`, as slow as it must be for
        no joint to pass PEAK_JOINT_SPEED (at least the move from rest would take)."""
        origin, velocity, goal = (np.asarray(v, dtype=float) for v in (origin, velocity, goal))
        duration = move_duration(origin, goal)
        _, ds, _, dh = _TAU_PROFILES
        # Stretching the move slows only its own part: the motion carried on from before is
        # the body's already, so a body moving at the peak (or a hair above it) stays there.
        peak = max(PEAK_JOINT_SPEED, float(np.abs(velocity).max(initial=0.0))) + 1e-9
        for _ in range(MAX_STRETCHES):
            speeds = np.abs(np.outer(ds / duration, goal - origin) + np.outer(dh, velocity))
            if speeds.max() <= peak:
                break
            duration *= 1.05
        return cls(start, duration, origin, goal, velocity)

    def at(self, time: float) -> tuple[np.ndarray, np.ndarray]:
        if self.duration <= 0.0 or time >= self.start + self.duration:
            return self.goal.copy(), np.zeros_like(self.goal)
        tau = max(time - self.start, 0.0) / self.duration
        s, ds, h, dh = _profiles(tau)
        delta = self.goal - self.origin
        position = self.origin + s * delta + self.duration * h * self.velocity
        return position, ds / self.duration * delta + dh * self.velocity


class PostureTimeline:
    """Joint positions and velocities over time for a list of (time, target) changes.

    A move starts at each change from wherever the body is then, moving as it is (mid-move
    included), and ends at rest at its target; it lasts at least
    `max(MIN_MOVE_TIME, 1.875 |dq|_max / PEAK_JOINT_SPEED)`, and longer where the motion it
    takes over needs it, so that no joint exceeds the peak speed.
    """

    def __init__(self, changes: Sequence[tuple[float, np.ndarray]]):
        if not changes:
            raise ValueError("changes: expected at least the starting posture")
        first_time, first = changes[0]
        self._moves = [_Move.starting(first_time, first, np.zeros(len(first)), first)]
        self._starts = np.array([first_time])
        for time, goal in changes[1:]:
            origin, velocity = self.evaluate(time)
            self._moves.append(_Move.starting(time, origin, velocity, goal))
            self._starts = np.append(self._starts, time)

    def interrupted(self, time: float, goal: np.ndarray) -> PostureTimeline:
        """This timeline until `time`, then a move from wherever the body is to `goal`, the
        rest of the script dropped (a person who reacts to the world)."""
        origin, velocity = self.evaluate(time)
        kept = self._starts < time
        clone = PostureTimeline.__new__(PostureTimeline)
        clone._moves = [m for m, keep in zip(self._moves, kept, strict=True) if keep]
        clone._moves.append(_Move.starting(time, origin, velocity, goal))
        clone._starts = np.append(self._starts[kept], time)
        return clone

    def evaluate(self, time: float) -> tuple[np.ndarray, np.ndarray]:
        """Positions and velocities at `time`."""
        index = max(int(np.searchsorted(self._starts, time, side="right")) - 1, 0)
        return self._moves[index].at(time)

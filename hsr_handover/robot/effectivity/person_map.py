"""The person's reachable range: the same Growing Cell Structures as the
robot's arm (paper 3.1), learnt over a human arm whose lengths come from the perceived skeleton,
with the body held still, each node carrying the arm's joint angles.

The arm: a shoulder of three angles (flexion forward from hanging, abduction out to the side,
rotation of the upper arm about its own axis) and an elbow that bends the forearm forward, in
the body frame (x forward, y left, z up, origin at the shoulder). The hand's reach point is the
palm's centre, PALM_SHARE of a hand's length past the wrist. Ranges of motion are adult active
ranges, rounded inward (AAOS: shoulder flexion 180, extension 60, abduction 180, elbow flexion
150 degrees).

Lengths: the lifted skeleton's upper arm and forearm, unless one is implausible (a keypoint
lifted onto an occluding surface can be 20 cm off, see tests/test_perception_station.py); then
the segment-length ratios of Drillis and Contini (1966) from the shoulders' width.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable

import numpy as np

from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.robot.perception.skeleton import Skeleton
from hsr_handover.robot.perception.torso_depth import seen_shoulders
from hsr_handover.topology import GrowingCellStructures

SHOULDER_WIDTH_PER_HEIGHT = 0.259  # Drillis and Contini 1966: biacromial width / height
UPPER_ARM_PER_HEIGHT = 0.186
FOREARM_PER_HEIGHT = 0.146
HAND_PER_HEIGHT = 0.108
PALM_SHARE = 0.5  # of the hand's length past the wrist: where an object is held
SHOULDER_DEPTH = 0.06
"""m the shoulder joint's centre lies behind its keypoint: a lifted keypoint is the front of
the body (`robot.perception.skeleton`), and the joint is about a deltoid's depth behind it (the
perceived scene's shoulder capsule has the same radius). Taken at the keypoint, a shoulder can
sit 11 cm toward the robot, and an object held out at the reach then ends beyond it."""
LEAN = 0.1
"""m a person reaches past the arm's length by leaning the trunk toward what they reach for: a
modest share of what a seated person's forward lean adds (functional reach tests measure tens
of centimetres)."""
PLAUSIBLE = (0.7, 1.4)  # a perceived segment within these shares of the ratio's length is kept
RANGES_DEG = np.array([[-40.0, 170.0],  # flexion, 0 hanging, 90 forward level
                       [-30.0, 150.0],  # abduction, 0 hanging, 90 out to the side
                       [-70.0, 90.0],  # upper-arm rotation
                       [0.0, 145.0]])  # elbow flexion  # fmt: skip
SAMPLES, SIGNALS, MAX_NODES, MU3 = 20_000, 60_000, 250, 30.0
"""The map's samples, training signals, size (the robot arm's has 200) and eq. 11's mu3."""


@dataclasses.dataclass(frozen=True)
class HumanArm:
    """A perceived arm: its `side` ("r" or "l"), the shoulder joint in the world (m), the body
    frame's rotation (3 x 3, columns forward, left, up) and the segment lengths (m): `upper`
    (shoulder to elbow), `forearm` (elbow to wrist), `hand` (wrist to the palm's centre)."""

    side: str
    shoulder: np.ndarray
    frame: np.ndarray
    upper: float
    forearm: float
    hand: float

    @property
    def reach(self) -> float:
        """The longest reach (m) from the shoulder: the arm straight."""
        return self.upper + self.forearm + self.hand

    @property
    def body_reach(self) -> float:
        """The longest reach (m) the body's proportions give (Drillis and Contini 1966), for
        the height the hand's length was taken from (`perceived_arm`): one frame's elbow and
        wrist, lifted onto what lies in front of them, can make the perceived arm a quarter or
        a third shorter than it is (a forearm held toward the camera)."""
        height = self.hand / (PALM_SHARE * HAND_PER_HEIGHT)
        return (UPPER_ARM_PER_HEIGHT + FOREARM_PER_HEIGHT) * height + self.hand

    @property
    def leaning_reach(self) -> float:
        """The farthest (m) from the shoulder the person may reach for something held out
        to them: the longer of `reach` and `body_reach`, leaning (LEAN)."""
        return max(self.reach, self.body_reach) + LEAN


def _rot(axis: int, angle: np.ndarray) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    matrix = np.zeros((*np.shape(angle), 3, 3))
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    matrix[..., axis, axis] = 1.0
    matrix[..., i, i], matrix[..., j, j] = c, c
    matrix[..., i, j], matrix[..., j, i] = -s, s
    return matrix


def hand_points(arm: HumanArm, angles: np.ndarray) -> np.ndarray:
    """The palm's centre (n, 3) in the body frame (origin at the shoulder) for joint angles
    (n, 4) in radians: flexion, abduction, rotation, elbow flexion."""
    flexion, abduction, rotation, elbow = np.moveaxis(np.asarray(angles, dtype=float), -1, 0)
    outward = -1.0 if arm.side == "r" else 1.0
    shoulder = _rot(0, outward * abduction) @ _rot(1, -flexion) @ _rot(2, rotation)
    down = np.array([0.0, 0.0, -1.0])
    upper = shoulder @ down
    forearm_local = _rot(1, -elbow) @ down  # the forearm in the upper arm's frame
    forearm = np.einsum("...ij,...j->...i", shoulder, forearm_local)
    return arm.upper * upper + (arm.forearm + arm.hand) * forearm


def sample_angles(count: int, rng: np.random.Generator) -> np.ndarray:
    """Joint angles (count, 4) drawn uniformly within RANGES_DEG, in radians."""
    low, high = np.radians(RANGES_DEG).T
    return rng.uniform(low, high, size=(count, 4))


class PersonEffectivity:
    """The person's range as a map in the body frame; queries take world points."""

    def __init__(self, arm: HumanArm, seed: int = 0):
        self.arm = arm
        rng = np.random.default_rng(seed)
        angles = sample_angles(SAMPLES, rng)
        self.cells = GrowingCellStructures(max_nodes=MAX_NODES, mu3=MU3, random_state=seed)
        self.cells.fit(hand_points(arm, angles), angles, n_signals=SIGNALS)
        edges = self.cells.edges
        gaps = np.linalg.norm(self.cells.nodes[edges[:, 0]] - self.cells.nodes[edges[:, 1]], axis=1)
        self.resolution = float(np.median(gaps))

    def to_world(self, local: np.ndarray) -> np.ndarray:
        return np.asarray(local) @ self.arm.frame.T + self.arm.shoulder

    def to_body(self, world: np.ndarray) -> np.ndarray:
        return (np.asarray(world, dtype=float).reshape(-1, 3) - self.arm.shoulder) @ self.arm.frame

    @property
    def nodes(self) -> np.ndarray:
        """Node positions (n, 3) in the world (m)."""
        return self.to_world(self.cells.nodes)

    def reachable(self, points: np.ndarray) -> np.ndarray:
        """Whether the person reaches each world point (n, 3) without moving the body: within
        the arm's length of the shoulder and within the map's resolution of a node. (The range
        is a volume, and a volume's nodes lie a resolution apart: half of it, the robot arm's
        test, misses one reachable point in ten.)"""
        local = self.to_body(points)
        within = np.linalg.norm(local, axis=1) <= self.arm.reach
        return within & self.cells.reachable(local, self.resolution)


def _height(right: np.ndarray, left: np.ndarray) -> float:
    """The height (m) of a person whose shoulders are at `right` and `left`."""
    return float(np.linalg.norm(right - left)) / SHOULDER_WIDTH_PER_HEIGHT


def perceived_arm(
    points: np.ndarray,
    confidence: np.ndarray,
    side: str,
    forward: np.ndarray | None = None,
    height: float | None = None,
    shoulders: tuple[np.ndarray, np.ndarray] | None = None,
) -> HumanArm | None:
    """The arm on `side` ("r" or "l") from a lifted COCO-18 skeleton (18 x 3, 18), or None
    without both shoulders (one hidden is mirrored through the neck, `seen_shoulders`).
    `forward`: the way the torso faces (world; the chest's facing voted over frames,
    `perception.facing`), when known. `height` (m): the person's, when known from more than
    this frame; else from this frame's shoulder width. `shoulders`: the (right, left) shoulder
    keypoints, when known from more than this frame; else this frame's."""
    seen = (np.asarray(confidence) > 0) & np.isfinite(points).all(axis=1)

    def at(name: str) -> np.ndarray | None:
        index = keypoint_index(name)
        return points[index] if seen[index] else None

    right, left = seen_shoulders(points, confidence) if shoulders is None else shoulders
    if right is None or left is None:
        return None
    if height is None:
        height = _height(right, left)
    shoulder = right if side == "r" else left
    elbow, wrist = at(f"{side}_elbow"), at(f"{side}_wrist")
    upper = _plausible(shoulder, elbow, UPPER_ARM_PER_HEIGHT * height)
    forearm = _plausible(elbow, wrist, FOREARM_PER_HEIGHT * height)
    frame = _body_frame(right, left, at("nose"), forward)
    joint = shoulder - SHOULDER_DEPTH * frame[:, 0]
    return HumanArm(side, joint, frame, upper, forearm, PALM_SHARE * HAND_PER_HEIGHT * height)


def _plausible(a: np.ndarray | None, b: np.ndarray | None, expected: float) -> float:
    if a is None or b is None:
        return expected
    length = float(np.linalg.norm(b - a))
    low, high = PLAUSIBLE
    return length if low * expected <= length <= high * expected else expected


def _body_frame(
    right: np.ndarray, left: np.ndarray, nose: np.ndarray | None, facing: np.ndarray | None
) -> np.ndarray:
    """Columns forward, left, up: forward the torso's `facing` (levelled) when known; else
    square to the shoulders' line, on the nose's side (the face is in front of the shoulders).
    The lifted shoulders turn only a fifth as far as the person (`perception.chest_plane`): a
    person turned 20 degrees from the camera gets a frame 16 degrees off."""
    up = np.array([0.0, 0.0, 1.0])
    level = None if facing is None else np.asarray(facing, dtype=float) * [1.0, 1.0, 0.0]
    if level is not None and np.isfinite(level).all() and np.linalg.norm(level) > 1e-9:
        forward = level / np.linalg.norm(level)
        return np.column_stack([forward, np.cross(up, forward), up])
    across = (left - right) * np.array([1.0, 1.0, 0.0])
    across /= max(np.linalg.norm(across), 1e-9)
    forward = np.cross(across, up)
    middle = (left + right) / 2
    if nose is not None and (nose - middle) @ forward < 0:
        forward = -forward
        across = -across
    return np.column_stack([forward, across, up]) if math.isfinite(forward[0]) else np.eye(3)


RECEIVING_SIDES = ("r", "l")
"""The arms the robot may hand to, the one tried first first: most people are right-handed,
and a person takes with the other hand what only that hand reaches (a person seated off the
table's axis, the robot able to stand only on their left). An arm whose elbow or wrist is not
seen gets the body's proportions (`perceived_arm`)."""
STEADY_FRAMES = 10
"""How many frames the arms' shoulders are the median over (`receiving_arms`): the latest that
shows both shoulders and those before it, a second at the supervisor's 10 Hz. A person
seated or standing at the table barely moves the shoulders in a second, while a pose detector
can put one frame's shoulder onto an object held up in front of the camera, a quarter metre
toward it: the median of ten is moved by none of up to four such frames, and lags a person
who moves by half a second."""


def receiving_arms(
    skeletons: Iterable[Skeleton], forward: np.ndarray | None = None
) -> tuple[HumanArm, ...]:
    """The person's arms, in RECEIVING_SIDES order, from `skeletons` (newest first): the
    elbows and wrists of the first that shows both shoulders, the shoulders steady over it and
    the older ones, STEADY_FRAMES in all (`steady_shoulders`), their body frame facing
    `forward` when known (see `perceived_arm`), their size from the median height over all of
    them that show both shoulders (one frame's shoulders err by 2 cm and more: a pose
    detector's error persists over a held pose); empty if none shows both."""
    skeletons = list(skeletons)
    shoulders = [seen_shoulders(s.points, s.confidence) for s in skeletons]
    both = [i for i, (right, left) in enumerate(shoulders) if not (right is None or left is None)]
    if not both:
        return ()
    height = float(np.median([_height(*shoulders[i]) for i in both]))
    steady = steady_shoulders(shoulders[both[0] : both[0] + STEADY_FRAMES])
    newest = skeletons[both[0]]
    return tuple(perceived_arm(newest.points, newest.confidence, side, forward, height, steady)
                 for side in RECEIVING_SIDES)  # fmt: skip


def steady_shoulders(
    shoulders: Iterable[tuple[np.ndarray | None, np.ndarray | None]],
) -> tuple[np.ndarray, np.ndarray]:
    """The (right, left) shoulders, each the per-coordinate median over the frames' (right,
    left) pairs that show it (None where one does not; at least one must show each): a frame
    whose keypoint was lifted onto something in front of the shoulder moves no coordinate
    while most frames agree."""
    pairs = list(shoulders)
    return tuple(np.median([pair[k] for pair in pairs if pair[k] is not None], axis=0)
                 for k in (0, 1))  # fmt: skip

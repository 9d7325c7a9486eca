"""Attention: regions of the scene the robot attends to, and the sampling weights they give.

The paper (§3.1, end; figs. 9-12) lets the robot's attention move from the person's face to the
hand to an object; points inside the attended region are sampled more often, so the Growing
Neural Gas puts more nodes there. Regions are built from what the robot perceives (skeleton
keypoints, object detections), never from the simulator's state.

Node density on a surface grows roughly with the square root of sampling density, so a
sampling weight of 16 gives about 4x the nodes on a plain surface; in the bundled scene, per m^2
of observed surface, the paper's ~4x over the rest takes a weight of about 36 (docs/design.md §3.1).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from hsr_handover.interface.coco18 import FACE_KEYPOINTS, keypoint_index

FACE = tuple(keypoint_index(name) for name in FACE_KEYPOINTS)
NECK = keypoint_index("neck")
RIGHT_ARM, LEFT_ARM = (
    tuple(keypoint_index(f"{side}_{joint}") for joint in ("shoulder", "elbow", "wrist"))
    for side in "rl"
)
FACE_RADIUS = 0.15
HAND_RADIUS = 0.15
OBJECT_RADIUS = 0.10
DEFAULT_ATTENTION_WEIGHT = 36.0
"""How many times more often points in an attended region are sampled than the rest."""


@dataclasses.dataclass(frozen=True)
class AttentionRegion:
    """A ball in the world: `name` is "face", "hand" or "object:<label>"."""

    name: str
    center: np.ndarray
    radius: float

    def contains(self, points: np.ndarray) -> np.ndarray:
        """Which points (N, 3) lie inside; NaN points never do."""
        offsets = np.asarray(points, dtype=float) - self.center
        with np.errstate(invalid="ignore"):
            return np.einsum("ij,ij->i", offsets, offsets) <= self.radius**2


def face_region(points: np.ndarray, confidence: np.ndarray) -> AttentionRegion | None:
    """The face from the visible face keypoints (18 x 3 lifted skeleton), or None."""
    face = [i for i in FACE if confidence[i] > 0 and np.isfinite(points[i]).all()]
    if not face:
        return None
    return AttentionRegion("face", points[face].mean(axis=0), FACE_RADIUS)


def hand_region(points: np.ndarray, confidence: np.ndarray) -> AttentionRegion | None:
    """The active hand: of the visible wrists, the one held out farthest from its shoulder in
    the horizontal plane (a hand reaching or pointing across the table, not one resting in
    front of the body). Horizontal reach survives what lifting does to keypoints: each lifted
    point is the nearest body surface, which for a foreshortened arm puts the elbow on the
    forearm and corrupts angles. Without the shoulder, the neck stands in; None when no wrist
    is visible."""

    def seen(index: int) -> bool:
        return confidence[index] > 0 and np.isfinite(points[index]).all()

    def reach(shoulder: int, wrist: int) -> float:
        base = shoulder if seen(shoulder) else NECK
        return float(np.hypot(*(points[wrist] - points[base])[:2])) if seen(base) else 0.0

    arms = [(shoulder, wrist) for shoulder, _, wrist in (RIGHT_ARM, LEFT_ARM) if seen(wrist)]
    if not arms:
        return None
    _, wrist = max(arms, key=lambda arm: reach(*arm))
    return AttentionRegion("hand", points[wrist], HAND_RADIUS)


def object_region(label: str, center: np.ndarray) -> AttentionRegion | None:
    """An object from a detection's 3-D centre, or None when the centre is unknown."""
    if not np.isfinite(center).all():
        return None
    return AttentionRegion(f"object:{label}", np.asarray(center, dtype=float), OBJECT_RADIUS)


def attention_weights(
    points: np.ndarray,
    regions: Sequence[AttentionRegion],
    weight: float = DEFAULT_ATTENTION_WEIGHT,
) -> np.ndarray:
    """Sampling weight per point (N,): `weight` inside any attended region, 1 elsewhere."""
    weights = np.ones(len(points))
    for region in regions:
        weights[region.contains(points)] = weight
    return weights


FOCUS_KINDS = ("none", "face", "hand", "object")


@dataclasses.dataclass(frozen=True)
class FocusChange:
    """From `start` (s) on, attend to `focus` (one of FOCUS_KINDS); for "object", `target` is
    the detection label (the object's colour) to attend to."""

    start: float
    focus: str
    target: str = ""


def focus_at(schedule: Sequence[FocusChange], time: float) -> FocusChange | None:
    """The focus in force at `time` (the latest change that has started), or None."""
    current = None
    for change in schedule:
        if change.start <= time:
            current = change
    return current


def attended_regions(
    focus: FocusChange | None,
    skeleton_points: np.ndarray | None,
    skeleton_confidence: np.ndarray | None,
    detections: Sequence[tuple[str, np.ndarray]],
) -> tuple[AttentionRegion, ...]:
    """The region the focus names, found in what the robot perceives right now: the face or the
    hand from the lifted skeleton (18 x 3 points, 18 confidences; None when there is no
    skeleton), an object from the detections as (label, centre) pairs. Empty when the focus is
    "none" or its region is not perceived (e.g. the face turned away)."""
    if focus is None or focus.focus == "none":
        return ()
    if focus.focus in ("face", "hand") and skeleton_points is None:
        return ()
    if focus.focus == "face":
        region = face_region(skeleton_points, skeleton_confidence)
    elif focus.focus == "hand":
        region = hand_region(skeleton_points, skeleton_confidence)
    else:
        centers = [center for label, center in detections if label == focus.target]
        region = object_region(focus.target, centers[0]) if centers else None
    return () if region is None else (region,)

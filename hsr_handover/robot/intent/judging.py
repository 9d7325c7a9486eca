"""One frame judged: what the person's rays show (`observe`) and the object they ask for among
the candidates (`judge`), or why none."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np

from hsr_handover.robot.intent.params import IntentParams
from hsr_handover.robot.intent.person_rays import (
    bearing_errors_deg,
    bearing_tolerance_deg,
    face_ray,
    gaze_ray,
    pitch_errors_deg,
    pitch_tolerance_deg,
    pointing_rays,
    torso_forward,
)
from hsr_handover.robot.intent.rays import Ray, ray_distances

NO_SKELETON = "no skeleton"
NO_CANDIDATES = "no objects detected"
NO_POINTING = "no straight arm"
ARM_MOVING = "arm still moving"
NOTHING_POINTED_AT = "pointing at nothing"
NO_FACE = "unsure: face not seen"
GAZE_ELSEWHERE = "looking elsewhere"
ARM_NOT_RAISED = "arm not raised to point"  # an arm that has not just moved: `WristTrail`
ASKS_FOR_TARGET = "asking for the object fetched"  # a reach for it, not a correction
POINTING = "pointing"
RECOGNISED = "recognised"


@dataclasses.dataclass(frozen=True)
class Observation:
    """What a frame shows of the person: the pointing arm (None if no arm is straight), its
    elbow angle and ray, the face's ray (None without the face) and the torso's forward
    direction (None without shoulders or hips); how fast (deg/s) the pointing ray turns, as
    `RaySmoother` measures it (infinite until enough frames show it; 0 for a lone frame); and
    whether the pointing ray passes within `d_min` of an object (`at_object`)."""

    arm: str | None = None
    elbow_angle_deg: float = math.nan
    pointing: Ray | None = None
    face: Ray | None = None
    forward: np.ndarray | None = None
    sweep_deg_s: float = 0.0
    face_for_pitch: Ray | None = None
    at_object: bool = False


def observe(
    points: np.ndarray,
    confidence: np.ndarray,
    centers: np.ndarray,
    params: IntentParams,
    face_forward: np.ndarray | None = None,
) -> Observation:
    """The rays of one lifted COCO-18 skeleton (18 x 3 points, 18 confidences; `face_forward`
    the face's direction from the head's shape, see `face_ray`). Of two straight arms, the
    one whose ray passes nearer an object (`centers`, N x 3) points."""
    face = face_ray(points, confidence, params, face_forward)
    arms = pointing_rays(points, confidence, params)
    if not arms or len(centers) == 0:
        return Observation(face=face, forward=torso_forward(points, confidence))
    nearest = [ray_distances(ray, centers).min() for _, _, ray in arms]
    best = int(np.argmin(nearest))
    arm, angle, ray = arms[best]
    return Observation(arm, angle, ray, face, torso_forward(points, confidence, arm),
                       at_object=bool(nearest[best] <= params.d_min))  # fmt: skip


@dataclasses.dataclass(frozen=True)
class FrameJudgement:
    """What one frame shows: the object asked for (None if none), how clearly (1 - best score
    over the runner-up's), a status saying why not, the arm, its elbow angle, the pointing
    ray and the estimated gaze ray."""

    candidate: str | None
    clarity: float
    status: str
    arm: str | None = None
    elbow_angle_deg: float = math.nan
    pointing: Ray | None = None
    gaze: Ray | None = None

    @property
    def face_seen(self) -> bool:
        return self.gaze is not None


def _clarity(scores: np.ndarray, best: int) -> float:
    """1 - best / runner-up: 0 for a tie, near 1 when one object stands out."""
    if len(scores) < 2:
        return 1.0
    runner_up = float(np.min(np.delete(scores, best)))
    return float(np.clip(1.0 - scores[best] / max(runner_up, 1e-9), 0.0, 1.0))


def judge(
    observation: Observation,
    candidates: Sequence[tuple[str, np.ndarray]],
    params: IntentParams,
) -> FrameJudgement:
    """The object the observed rays ask for among the (label, centre) candidates: the one with
    the least (d / d_min)^2 + gaze_weight (gaze error / gaze_tolerance_deg)^2, if both are
    within bounds (the gaze's: `bearing_tolerance_deg` beside it, `pitch_tolerance_deg` above
    it). (A centre object can be the right answer when the arm errs toward one neighbour and
    the eyes toward the other.)"""
    labels = [label for label, _ in candidates]
    centers = np.array([center for _, center in candidates], dtype=float).reshape(-1, 3)
    face, ray = observation.face, observation.pointing
    gaze = None if face is None else gaze_ray(face, observation.forward, params)
    seen = dict(arm=observation.arm, elbow_angle_deg=observation.elbow_angle_deg, pointing=ray,
                gaze=gaze)  # fmt: skip
    if ray is None:
        return FrameJudgement(None, 0.0, NO_POINTING, **seen)
    if not observation.sweep_deg_s <= params.steady_deg_s:
        return FrameJudgement(None, 0.0, ARM_MOVING, **seen)
    pointing = ray_distances(ray, centers) / params.d_min
    if gaze is None:
        best = int(np.argmin(pointing))
        pointed = labels[best] if pointing[best] <= 1.0 else None
        status = NO_FACE if pointed else NOTHING_POINTED_AT
        return FrameJudgement(pointed, _clarity(pointing, best), status, **seen)
    beside = bearing_errors_deg(gaze, centers)  # the eyes beside each object (deg)
    looking = beside / params.gaze_tolerance_deg
    scores = pointing**2 + params.gaze_weight * looking**2
    best = int(np.argmin(scores))
    if pointing[best] > 1.0:
        return FrameJudgement(None, 0.0, NOTHING_POINTED_AT, **seen)
    level = gaze  # the eyes' pitch, from the face over the longer window when there is one
    if observation.face_for_pitch is not None:
        level = gaze_ray(observation.face_for_pitch, observation.forward, params)
    above = pitch_errors_deg(level, centers[best : best + 1])[0]  # the eyes over the object
    astray = beside[best] > bearing_tolerance_deg(gaze.origin, observation.forward,
                                                  centers[best], params)  # fmt: skip
    if astray or above > pitch_tolerance_deg(level.origin, centers[best], params):
        return FrameJudgement(None, 0.0, GAZE_ELSEWHERE, **seen)
    return FrameJudgement(labels[best], _clarity(scores, best), POINTING, **seen)


def nothing_to_judge(confidence: np.ndarray, candidates: Sequence) -> FrameJudgement | None:
    if not np.any(np.asarray(confidence) > 0):
        return FrameJudgement(None, 0.0, NO_SKELETON)
    if not candidates:
        return FrameJudgement(None, 0.0, NO_CANDIDATES)
    return None


def judge_frame(
    points: np.ndarray,
    confidence: np.ndarray,
    candidates: Sequence[tuple[str, np.ndarray]],
    params: IntentParams,
) -> FrameJudgement:
    """One frame on its own, unsmoothed: `observe`, then `judge`."""
    empty = nothing_to_judge(confidence, candidates)
    if empty is not None:
        return empty
    centers = np.array([center for _, center in candidates], dtype=float)
    return judge(observe(points, confidence, centers, params), candidates, params)

"""Recognising the object a person asks for (paper 3.2): a straight arm (eq. 16) whose pointing
ray passes within `d_min` of an object, a face (eq. 17) turned toward the same object, and both
held for `t_max` seconds.

Each frame is judged on its own (`judge_frame`); `IntentTracker` adds the dwell. A frame that
lacks the face neither starts nor completes a recognition (missing keypoints never make a
guess), but it does not break a dwell that the arm keeps pointing through: OpenPose drops a
face point in about a quarter of frames, and a request is not withdrawn by a blink.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np

from hsr_handover.intent.rays import Ray, elbow_angle_deg, face_normal, ray_distances, tilt_down
from hsr_handover.perception.coco18 import keypoint_index

POINTING_RAYS = ("shoulder_wrist", "elbow_wrist", "eye_wrist")
"""Where the pointing ray starts (it always runs through the wrist): the shoulder, the elbow
(eq. 16's forearm) or the midpoint of the eyes (people align eye, finger and target)."""

ARMS = {
    side: tuple(keypoint_index(f"{side[0]}_{joint}") for joint in ("shoulder", "elbow", "wrist"))
    for side in ("right", "left")
}
NOSE, R_EYE, L_EYE = (keypoint_index(name) for name in ("nose", "r_eye", "l_eye"))

NO_SKELETON = "no skeleton"
NO_CANDIDATES = "no objects detected"
NO_POINTING = "no straight arm"
NOTHING_POINTED_AT = "pointing at nothing"
NO_FACE = "unsure: face not seen"
GAZE_ELSEWHERE = "looking elsewhere"
POINTING = "pointing"
RECOGNISED = "recognised"


@dataclasses.dataclass(frozen=True)
class IntentParams:
    """The recogniser's thresholds (paper 3.2); defaults measured in the intent experiment.

    straight_arm_deg: eq. 16's elbow angle above which an arm counts as pointing, in (90, 180].
    d_min: how near (m) the pointing ray must pass an object's centre.
    gaze_d_min: how near (m) the gaze ray must pass the same object (the head turns only part
    of the way, the eyes do the rest, so the face's ray misses by more than the arm's).
    t_max: how long (s) the same object must be asked for.
    pointing_ray: one of POINTING_RAYS.
    face_tilt_deg: the nose-eyes plane of eq. 17 faces upward by this much when the head faces
    straight ahead (the nose tip is below and a little ahead of the eyes); the gaze ray is its
    normal turned down by this angle.
    gaze_weight: with both rays, the object chosen minimises d_pointing + gaze_weight d_gaze.
    smoothing_s: the rays are averaged over the frames of the last `smoothing_s` seconds.
    """

    straight_arm_deg: float = 150.0
    d_min: float = 0.12
    gaze_d_min: float = 0.25
    t_max: float = 0.5
    pointing_ray: str = "shoulder_wrist"
    face_tilt_deg: float = 23.0
    gaze_weight: float = 0.5
    smoothing_s: float = 0.4

    def __post_init__(self) -> None:
        if not 90.0 < self.straight_arm_deg <= 180.0:
            raise ValueError(f"straight_arm_deg: expected (90, 180], got {self.straight_arm_deg}")
        for name in ("d_min", "gaze_d_min"):
            if not 0.0 < getattr(self, name) < 2.0:
                raise ValueError(
                    f"{name}: expected a distance in (0, 2) m, got {getattr(self, name)}"
                )
        if not 0.0 <= self.t_max <= 10.0:
            raise ValueError(f"t_max: expected a dwell in [0, 10] s, got {self.t_max}")
        if self.pointing_ray not in POINTING_RAYS:
            raise ValueError(f"pointing_ray: expected one of {POINTING_RAYS}")
        if not 0.0 <= self.face_tilt_deg < 90.0:
            raise ValueError(f"face_tilt_deg: expected [0, 90) deg, got {self.face_tilt_deg}")
        if not 0.0 <= self.smoothing_s <= 10.0:
            raise ValueError(f"smoothing_s: expected [0, 10] s, got {self.smoothing_s}")
        if not 0.0 <= self.gaze_weight <= 10.0:
            raise ValueError(f"gaze_weight: expected [0, 10], got {self.gaze_weight}")


@dataclasses.dataclass(frozen=True)
class FrameJudgement:
    """What one frame shows: the object asked for (None if none), how clearly (1 - best score
    over the runner-up's), the arm, its elbow angle, the rays, and a status saying why not."""

    candidate: str | None
    clarity: float
    status: str
    arm: str | None = None
    elbow_angle_deg: float = math.nan
    pointing: Ray | None = None
    gaze: Ray | None = None
    face_seen: bool = False


def _seen(points: np.ndarray, confidence: np.ndarray, indices: Sequence[int]) -> bool:
    return all(confidence[i] > 0 and np.isfinite(points[i]).all() for i in indices)


def gaze_ray(points: np.ndarray, confidence: np.ndarray, params: IntentParams) -> Ray | None:
    """The face's ray (eq. 17) from the eyes' midpoint, or None without nose and both eyes."""
    if not _seen(points, confidence, (NOSE, R_EYE, L_EYE)):
        return None
    normal = face_normal(points[NOSE], points[R_EYE], points[L_EYE])
    if normal is None:
        return None
    eyes = (points[R_EYE] + points[L_EYE]) / 2
    return Ray(eyes, tilt_down(normal, params.face_tilt_deg))


def pointing_rays(
    points: np.ndarray, confidence: np.ndarray, params: IntentParams
) -> list[tuple[str, float, Ray]]:
    """(arm, elbow angle, ray) for each arm seen straight enough to point (eq. 16)."""
    rays = []
    for arm, (shoulder, elbow, wrist) in ARMS.items():
        if not _seen(points, confidence, (shoulder, elbow, wrist)):
            continue
        angle = elbow_angle_deg(points[shoulder], points[elbow], points[wrist])
        if not angle >= params.straight_arm_deg:
            continue
        start = {"shoulder_wrist": shoulder, "elbow_wrist": elbow}.get(params.pointing_ray)
        if start is not None:
            origin = points[start]
        elif _seen(points, confidence, (R_EYE, L_EYE)):
            origin = (points[R_EYE] + points[L_EYE]) / 2
        else:
            continue
        ray = Ray.through(origin, points[wrist])
        if ray is not None:
            rays.append((arm, angle, ray))
    return rays


def _clarity(scores: np.ndarray, best: int) -> float:
    """1 - best / runner-up: 0 for a tie, near 1 when one object stands out."""
    if len(scores) < 2:
        return 1.0
    runner_up = float(np.min(np.delete(scores, best)))
    return float(np.clip(1.0 - scores[best] / max(runner_up, 1e-9), 0.0, 1.0))


@dataclasses.dataclass(frozen=True)
class Observation:
    """What a frame shows of the person: the pointing arm (None if no arm is straight), its
    elbow angle, its ray, and the gaze ray (None without the face)."""

    arm: str | None = None
    elbow_angle_deg: float = math.nan
    pointing: Ray | None = None
    gaze: Ray | None = None


def observe(
    points: np.ndarray, confidence: np.ndarray, centers: np.ndarray, params: IntentParams
) -> Observation:
    """The rays of one lifted COCO-18 skeleton (18 x 3 points, 18 confidences). Of two
    straight arms, the one whose ray passes nearer an object (`centers`, N x 3) points."""
    gaze = gaze_ray(points, confidence, params)
    arms = pointing_rays(points, confidence, params)
    if not arms or len(centers) == 0:
        return Observation(gaze=gaze)
    arm, angle, ray = min(arms, key=lambda item: ray_distances(item[2], centers).min())
    return Observation(arm, angle, ray, gaze)


def judge(
    observation: Observation,
    candidates: Sequence[tuple[str, np.ndarray]],
    params: IntentParams,
) -> FrameJudgement:
    """The object the observed rays ask for among the (label, centre) candidates."""
    labels = [label for label, _ in candidates]
    centers = np.array([center for _, center in candidates], dtype=float).reshape(-1, 3)
    gaze, ray = observation.gaze, observation.pointing
    seen = dict(
        arm=observation.arm, elbow_angle_deg=observation.elbow_angle_deg, pointing=ray,
        gaze=gaze, face_seen=gaze is not None,
    )  # fmt: skip
    if ray is None:
        return FrameJudgement(None, 0.0, NO_POINTING, **seen)
    distances = ray_distances(ray, centers)
    if gaze is None:
        best = int(np.argmin(distances))
        pointed = labels[best] if distances[best] <= params.d_min else None
        status = NO_FACE if pointed else NOTHING_POINTED_AT
        return FrameJudgement(pointed, _clarity(distances, best), status, **seen)
    gaze_distances = ray_distances(gaze, centers)
    scores = distances + params.gaze_weight * gaze_distances
    best = int(np.argmin(scores))
    if distances[best] > params.d_min:
        return FrameJudgement(None, 0.0, NOTHING_POINTED_AT, **seen)
    if gaze_distances[best] > params.gaze_d_min:
        return FrameJudgement(None, 0.0, GAZE_ELSEWHERE, **seen)
    return FrameJudgement(labels[best], _clarity(scores, best), POINTING, **seen)


def judge_frame(
    points: np.ndarray,
    confidence: np.ndarray,
    candidates: Sequence[tuple[str, np.ndarray]],
    params: IntentParams,
) -> FrameJudgement:
    """One frame on its own, unsmoothed: `observe`, then `judge`."""
    empty = _nothing_to_judge(confidence, candidates)
    if empty is not None:
        return empty
    centers = np.array([center for _, center in candidates], dtype=float)
    return judge(observe(points, confidence, centers, params), candidates, params)


def _nothing_to_judge(confidence: np.ndarray, candidates: Sequence) -> FrameJudgement | None:
    if not np.any(np.asarray(confidence) > 0):
        return FrameJudgement(None, 0.0, NO_SKELETON)
    if not candidates:
        return FrameJudgement(None, 0.0, NO_CANDIDATES)
    return None


class RaySmoother:
    """The mean of the rays seen over the last `window` seconds: the face's ray from three
    points a few cm apart swings by 10-30 degrees from frame to frame, while the head holds
    still for the length of a request. A pointing ray's history restarts when the arm changes
    or stops pointing; a frame without a face adds nothing to the gaze's."""

    def __init__(self, window: float):
        self.window = window
        self._pointing: list[tuple[float, Ray]] = []
        self._gaze: list[tuple[float, Ray]] = []
        self._arm: str | None = None

    def smooth(self, time: float, observation: Observation) -> Observation:
        if observation.pointing is None or observation.arm != self._arm:
            self._pointing = []
        self._arm = observation.arm
        pointing = self._add(self._pointing, time, observation.pointing)
        gaze = self._add(self._gaze, time, observation.gaze)
        return dataclasses.replace(observation, pointing=pointing, gaze=gaze)

    def _add(self, history: list, time: float, ray: Ray | None) -> Ray | None:
        if ray is None:
            return None
        history.append((time, ray))
        history[:] = [(t, r) for t, r in history if t > time - self.window - 1e-9]
        origin = np.mean([r.origin for _, r in history], axis=0)
        direction = np.sum([r.direction for _, r in history], axis=0)
        return Ray(origin, direction / np.linalg.norm(direction))


@dataclasses.dataclass(frozen=True)
class IntentState:
    """The recogniser's state after a frame: the recognised `target` (None until one is) with
    its `confidence` and `recognised_time` (s; NaN until then); the object the person is
    asking for now (`candidate`, since `candidate_since`); and the frame's judgement."""

    target: str | None = None
    confidence: float = 0.0
    recognised_time: float = math.nan
    candidate: str | None = None
    candidate_since: float = math.nan
    frame: FrameJudgement = FrameJudgement(None, 0.0, NO_SKELETON)

    @property
    def status(self) -> str:
        return RECOGNISED if self.target is not None else self.frame.status


class IntentTracker:
    """The dwell over frames: the first object asked for, with the face confirming it at the
    start and at the end, for `t_max` seconds, is the recognised target (latched)."""

    def __init__(self, params: IntentParams | None = None):
        self.params = IntentParams() if params is None else params
        self.state_ = IntentState()
        self._smoother = RaySmoother(self.params.smoothing_s)

    def update(
        self,
        time: float,
        points: np.ndarray,
        confidence: np.ndarray,
        candidates: Sequence[tuple[str, np.ndarray]],
    ) -> IntentState:
        """Judge the frame captured at `time` (s), its rays smoothed over the recent frames,
        and advance the dwell."""
        frame = _nothing_to_judge(confidence, candidates)
        if frame is None:
            centers = np.array([center for _, center in candidates], dtype=float)
            seen = observe(points, confidence, centers, self.params)
            frame = judge(self._smoother.smooth(time, seen), candidates, self.params)
        state = self.state_
        if state.target is not None:
            self.state_ = dataclasses.replace(state, frame=frame)
            return self.state_
        if frame.candidate is None or (frame.candidate != state.candidate and not frame.face_seen):
            candidate, since = None, math.nan  # nothing asked for: any dwell is broken
        elif frame.candidate == state.candidate:
            candidate, since = state.candidate, state.candidate_since
        else:
            candidate, since = frame.candidate, time  # a new request starts, face confirmed
        target, recognised = None, math.nan
        done = candidate is not None and time - since >= self.params.t_max - 1e-9
        if done and frame.face_seen:
            target, recognised = candidate, time
        self.state_ = IntentState(
            target, frame.clarity if target else 0.0, recognised, candidate, since, frame
        )
        return self.state_
